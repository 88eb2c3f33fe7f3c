"""Reading a measured record: column mapping with units, phyphox's gyroscope export with
the sensor's rotation, and bad data refused in one line with exit 2 before any run."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import celtstone as cs
from celtstone.cli.main import main
from celtstone.fitting.noise import noise_scale
from celtstone.fitting.sensor import parse_sensor_rotation
from celtstone.fitting.series import yaw_angle

PHYPHOX_HEADER = (
    '"Time (s)","Gyroscope x (rad/s)","Gyroscope y (rad/s)","Gyroscope z (rad/s)",'
    '"Absolute (rad/s)"'
)


def _phyphox_file(path: Path, times: np.ndarray, sensor: np.ndarray) -> Path:
    """A small file in phyphox's gyroscope export format (written here, not downloaded)."""
    lines = [PHYPHOX_HEADER]
    for t, (x, y, z) in zip(times, sensor, strict=True):
        lines.append(f"{t:.9E},{x:.9E},{y:.9E},{z:.9E},{math.sqrt(x * x + y * y + z * z):.9E}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def test_phyphox_gyroscope_is_read_in_body_axes(tmp_path: Path) -> None:
    times = 3.25 + 0.01 * np.arange(50)  # phyphox's clock starts when the recording does
    phase = 2.0 * np.pi * 3.0 * (times - times[0])
    body_rates = np.column_stack([np.sin(phase), np.cos(phase), -5.0 + 0.1 * phase])
    # sensor x along body x, sensor y along -body z, sensor z along body y: the columns of R
    rotation = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
    sensor = body_rates @ rotation  # omega_sensor = R^T omega_body, row by row
    path = _phyphox_file(tmp_path / "gyro.csv", times, sensor)
    record = cs.read_record(path, sensor_rotation="x,-z,y")
    assert list(record.series) == ["omega1", "omega2", "omega3"]
    assert record.start_time == pytest.approx(3.25)
    assert record.times[0] == 0.0 and record.times[-1] == pytest.approx(0.49)
    for k in range(3):
        np.testing.assert_allclose(record.series[f"omega{k + 1}"], body_rates[:, k], atol=1e-8)


def test_columns_with_units(tmp_path: Path) -> None:
    path = tmp_path / "video.csv"
    times = np.linspace(0.0, 1.0, 21)
    tilt_deg = 2.0 + np.sin(times)
    yaw = np.mod(8.0 * times + np.pi, 2.0 * np.pi) - np.pi  # wrapped, as a tracker gives it
    rate_deg = np.degrees(-5.0 + times)
    rows = "\n".join(
        f"{t},{a},{y},{r}" for t, a, y, r in zip(times, tilt_deg, yaw, rate_deg, strict=True)
    )
    path.write_text(
        "t;ignored\n" if False else f"t [s],Tilt (deg),psi,w\n{rows}\n", encoding="utf-8"
    )
    record = cs.read_record(path, ["time=t [s]", "tilt=Tilt (deg)", "yaw=psi", "spin[deg/s]=w"])
    np.testing.assert_allclose(record.series["tilt"], np.radians(tilt_deg))
    np.testing.assert_allclose(record.series["yaw"], 8.0 * times, atol=1e-12)
    np.testing.assert_allclose(record.series["spin"], -5.0 + times)
    with pytest.raises(cs.ParameterError, match="tilt unit"):
        cs.read_record(path, ["tilt[rad]=Tilt (deg)"])  # the header says deg


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (None, np.eye(3)),
        ("x,-z,y", [[1, 0, 0], [0, 0, 1], [0, -1, 0]]),
        ("2,3,1", [[0, 0, 1], [1, 0, 0], [0, 1, 0]]),
        ("0,-1,0,1,0,0,0,0,1", [[0, -1, 0], [1, 0, 0], [0, 0, 1]]),
    ],
)
def test_sensor_rotation(text: str | None, expected: object) -> None:
    np.testing.assert_array_equal(parse_sensor_rotation(text), np.array(expected, dtype=float))


@pytest.mark.parametrize("text", ["x,y", "x,x,z", "x,z,y", "1,0,0,0,1,0,0,0,2", "a,b,c"])
def test_sensor_rotation_refused(text: str) -> None:
    with pytest.raises(cs.ParameterError, match="sensor_rotation"):
        parse_sensor_rotation(text)


def test_yaw_of_a_turn_about_the_vertical() -> None:
    heading = np.linspace(0.0, 7.0, 50)  # more than a turn: unwrapped
    quaternion = np.column_stack(
        [np.cos(heading / 2), np.zeros(50), np.zeros(50), np.sin(heading / 2)]
    )
    np.testing.assert_allclose(yaw_angle(quaternion), heading, atol=1e-12)


@pytest.mark.parametrize("uniform", [True, False])
def test_noise_scale_of_white_noise_on_a_smooth_series(uniform: bool) -> None:
    rng = np.random.default_rng(3)
    steps = np.full(4000, 0.01) if uniform else rng.uniform(0.005, 0.015, 4000)
    times = np.concatenate([[0.0], np.cumsum(steps)])
    values = np.sin(0.5 * times) + rng.normal(0.0, 0.05, times.size)
    assert noise_scale(times, values) == pytest.approx(0.05, rel=0.1)


def test_noise_scale_of_white_noise_at_jittered_times_is_calibrated() -> None:
    """40 records of 300 samples of white noise at jittered 100 Hz times (a phone's short
    record): the estimates average the noise they were made with within 5 % (their
    spread is 9 %, so the mean's is 1.5 %; the least of several orders reads low by
    about 2.5 % on so few samples) and none is off by more than 30 %."""
    rng = np.random.default_rng(40)
    ratios = []
    for _ in range(40):
        times = np.arange(300) / 100.0 + rng.uniform(-1e-3, 1e-3, 300)
        ratios.append(noise_scale(times, rng.normal(0.0, 0.02, 300)) / 0.02)
    assert abs(np.mean(ratios) - 1.0) <= 0.05, ratios
    assert max(abs(r - 1.0) for r in ratios) <= 0.3, ratios


def test_a_polynomial_below_the_least_order_leaves_the_noise_estimate_alone() -> None:
    """A polynomial of degree 5 (below the least order of the divided differences, 6)
    adds nothing to any of them: the estimate is that of the noise alone."""
    rng = np.random.default_rng(5)
    times = np.arange(300) / 100.0 + rng.uniform(-1e-3, 1e-3, 300)
    noise = rng.normal(0.0, 0.02, times.size)
    polynomial = np.polynomial.Polynomial([-5.0, 3.0, -2.0, 1.0, -0.5, 0.2])(times)
    assert noise_scale(times, polynomial + noise) == pytest.approx(
        noise_scale(times, noise), rel=1e-6
    )


def _write(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8")
    return path


GOOD = "t,w\n" + "".join(f"{0.01 * i},{-5 + 0.1 * math.sin(i)}\n" for i in range(20))

# (file text, extra arguments, what the one line names): issue 14, item 5
BAD_DATA = {
    "missing column": (GOOD, ["--column", "spin=omega_z"], "spin column = 'omega_z'"),
    "non-numeric": (GOOD.replace("-5", "abc", 1), ["--column", "spin=w"], "row 1"),
    "NaN": (GOOD.replace("0.03,", "0.03,nan\n0.035,"), ["--column", "spin=w"], "NaN"),
    "times not increasing": (GOOD.replace("0.05,", "0.02,"), ["--column", "spin=w"], "time ="),
    "too few points": (
        "t,w\n0,-5\n0.01,-4.9\n",
        ["--column", "spin=w", "--free", "friction_coefficient,contact_radius,damping"],
        "more values than the 6 free",  # 3, the spin's bias and the initial slip's 2
    ),
    "no variation": (
        "t,w\n" + "".join(f"{0.01 * i},-5\n" for i in range(20)),
        ["--column", "spin=w"],
        "spin = 'constant -5'",
    ),
    "bounds LO >= HI": (
        GOOD,
        ["--column", "spin=w", "--bounds", "friction_coefficient=0.5:0.1"],
        "bounds of friction_coefficient",
    ),
    "bounds outside the range": (
        GOOD,
        ["--column", "spin=w", "--free", "contact_radius", "--bounds", "contact_radius=0:1e-3"],
        "bounds of contact_radius",
    ),
    "unknown free parameter": (
        GOOD,
        ["--column", "spin=w", "--free", "friction_coeficient"],
        "did you mean 'friction_coefficient'",
    ),
    "unknown series": (GOOD, ["--column", "spinn=w"], "did you mean 'spin'"),
    "sensor rotation without gyroscope": (
        GOOD,
        ["--column", "spin=w", "--sensor-rotation", "x,y,z"],
        "sensor_rotation",
    ),
    "start outside the bounds": (
        GOOD,
        ["--column", "spin=w", "--start", "friction_coefficient=3"],
        "start of friction_coefficient",
    ),
    "starts": (GOOD, ["--column", "spin=w", "--starts", "0"], "starts"),
    # issue 37: each of these gave a traceback
    "empty file": ("", [], "data ="),
    "only newlines": ("\n\n\n", [], "data ="),
    "one column named time": ("time\n0\n1\n2\n", [], "NAME=HEADER for a series"),
    "tiny sigma": (GOOD, ["--column", "spin=w", "--sigma", "spin=1e-300"], "sigma of spin"),
    "huge starts": (GOOD, ["--column", "spin=w", "--starts", "1e12"], "<= 1000"),
    "workers 0": (GOOD, ["--column", "spin=w", "--workers", "0"], "workers"),
    "unknown bias": (GOOD, ["--column", "spin=w", "--set", "bias_omega1=0.1"], "bias_spin"),
}


@pytest.mark.parametrize("case", list(BAD_DATA))
def test_bad_data_is_one_line_and_exit_2(
    case: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text, arguments, named = BAD_DATA[case]
    path = _write(tmp_path / "record.csv", text)
    if "--free" not in arguments:
        arguments = [*arguments, "--free", "friction_coefficient"]
    status = main(["fit", str(path), "--body", "kane_levinson_1982", "--no-progress", *arguments])
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert status == 2, captured.err
    assert len(lines) == 1 and lines[0].startswith("celtstone: error: "), captured.err
    assert named in lines[0]
    assert "Traceback" not in captured.err and captured.out == ""


def test_fit_workers_and_starts_checked_from_python() -> None:
    """The API refuses what the CLI refuses, with the same one-line error (issue 37)."""
    record = cs.make_record([0.0, 0.01, 0.02, 0.03], {"spin": [-5.0, -4.9, -4.8, -4.75]})
    for keyword, value in (("workers", 0), ("workers", 2.5), ("starts", 0), ("starts", 10**12)):
        with pytest.raises(cs.ParameterError, match=keyword):
            cs.fit(record, "kane_levinson_1982", free=["friction_coefficient"], **{keyword: value})


def test_columns_named_like_series_need_no_mapping(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "r.csv",
        "time (s),spin (rad/s),omega1 (deg/s)\n0,-5,1\n0.01,-4.9,2\n0.02,-4.8,4\n",
    )
    record = cs.read_record(path)
    assert set(record.series) == {"spin", "omega1"}
    np.testing.assert_allclose(record.series["omega1"], np.radians([1.0, 2.0, 4.0]))
    assert record.columns["time"] == "time (s)"


def test_phyphox_semicolon_decimal_comma(tmp_path: Path) -> None:
    """phyphox's own "semicolon, decimal comma" export reads as its comma export does."""
    times = 0.01 * np.arange(20)
    sensor = np.column_stack([np.sin(times), np.cos(times), -5.0 + times])
    comma = _phyphox_file(tmp_path / "comma.csv", times, sensor)
    text = comma.read_text(encoding="utf-8").replace(",", ";")
    text = "\n".join(
        line if i == 0 else line.replace(".", ",") for i, line in enumerate(text.splitlines())
    )
    semicolon = _write(tmp_path / "semicolon.csv", text + "\n")
    a, b = cs.read_record(comma), cs.read_record(semicolon)
    np.testing.assert_array_equal(a.times, b.times)
    for name in ("omega1", "omega2", "omega3"):
        np.testing.assert_array_equal(a.series[name], b.series[name])


def test_sensor_rotation_with_a_leading_minus_is_a_value() -> None:
    """``--sensor-rotation -y,x,z`` is read as written, not as an unknown option."""
    from celtstone.cli.main import build_parser

    args = build_parser().parse_args(
        ["fit", "r.csv", "--body", "b", "--free", "f", "--sensor-rotation", "-y,x,z"]
    )
    assert args.sensor_rotation == "-y,x,z"
