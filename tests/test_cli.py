"""``celtstone`` in-process through ``main([...])``: outputs, exit statuses, files.

Expected values come from the command line given (the initial state), from the
Kane & Levinson numbers of ../shared/references.md worked by hand, or from
invariants (energy balance, |n| = 1); never from an earlier run of the code.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import signal
import subprocess
import sys
from importlib import metadata
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from celtstone.cli.main import main
from celtstone.simulation.outcome import OUTCOMES

KL_NAME = "kane_levinson_1982"
KL_SOURCE_TITLE = "Realistic mathematical modeling of the rattleback"
# what every run's --json holds: each outcome not of the stick–slip contact only, and the
# settings every run records (``simulation.outcome``, the one declaration)
SUMMARY_KEYS = {name for name, outcome in OUTCOMES.items() if not outcome.contact} | {
    "model",
    "contact",
    "body",
    "t_end",
    "method",
    "rtol",
    "atol",
    "reversal_band",
    "reversal_window",
    "statistics",
    "units",
}
# Kane & Levinson body at rest upright, spinning at w3 about axis 3 (references.md):
# G is l = c - h = 0.01 m above the contact and does not move, so
# E = ½ C w3² + m g l with C = 1.7e-3 kg m², m = 1 kg, g = 9.81 m/s²; and N = m g.
C_MOMENT, MASS, GRAVITY, REST_HEIGHT = 1.7e-3, 1.0, 9.81, 0.01


class Result:
    """Exit status and the two output streams of one ``main`` call."""

    def __init__(self, argv: list[str]) -> None:
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            self.status = main(argv)
        self.out = out.getvalue()
        self.err = err.getvalue()

    def json(self) -> dict:
        """The one JSON object of standard output (and nothing else there)."""
        assert self.out.endswith("\n")
        assert self.out.count("\n") == 1, self.out
        value = json.loads(self.out)
        assert isinstance(value, dict)
        return value


@pytest.fixture(scope="module")
def upright() -> Result:
    """Steady spin at -5 rad/s, exactly upright: a relative equilibrium."""
    return Result(["run", "--omega", "0,0,-5", "--euler-angles", "0,0", "--t-end", "1", "--json"])


@pytest.fixture(scope="module")
def reversing() -> Result:
    """Kane & Levinson's start w3 = -5 rad/s, α = β = 0.5°: rolling, reverses within 3 s."""
    return Result(
        ["run", "--omega", "0,0,-5", "--euler-angles", "0.5,0.5", "--t-end", "3", "--json"]
    )


@pytest.fixture(scope="module")
def sliding(tmp_path_factory: pytest.TempPathFactory) -> tuple[Result, Path]:
    """A sliding run with non-default options, saved as NetCDF."""
    target = tmp_path_factory.mktemp("sliding") / "run.nc"
    result = Result(
        [
            "run",
            "--model",
            "sliding",
            "--friction-coefficient",
            "0.25",
            "--contact-radius",
            "0.002",
            "--friction-load",
            "dynamic",
            "--omega",
            "0,0,-5",
            "--euler-angles",
            "0.5,0.5",
            "--t-end",
            "2",
            "--rtol",
            "1e-8",
            "--atol",
            "1e-11",
            "--json",
            "--out",
            str(target),
        ]
    )
    return result, target


def test_json_has_every_key(upright: Result, reversing: Result) -> None:
    for result in (upright, reversing):
        assert result.status == 0, result.err
        assert result.err == ""
        assert set(result.json()) >= SUMMARY_KEYS


def test_first_reversal_is_the_held_reversal(tmp_path: Path) -> None:
    """``first_reversal_time`` is the reversal of sweeps and the report: the last zero of
    the spin's running mean over the body's rocking period before that mean leaves the
    band ±4 % of |spin(0)| on the side opposite to the start, checked here on the saved
    samples with a running mean written in the test, not by the code's own function."""
    target = tmp_path / "run.nc"
    result = Result(["run", "--t-end", "20", "--samples", "20001", "--json", "--out", str(target)])
    summary = result.json()
    with xr.open_dataset(target) as dataset:
        spin, time = dataset["spin"].values, dataset["time"].values
        window = dataset.attrs["reversal_window"]
    band = 0.04 * abs(summary["spin_initial"])
    assert summary["reversal_band"] == pytest.approx(band, rel=1e-15)
    # K&L rolls at 2 pi sqrt((A11 + m l^2) / (m g (b^2/c - l))) = 0.186 s, its slower rocking
    roll = 2 * np.pi * np.sqrt((2e-4 + 1e-4) / (9.81 * (0.03**2 / 0.02 - 0.01)))
    assert summary["reversal_window"] == window == pytest.approx(roll, rel=1e-12)
    # the running mean over [t - w/2, t + w/2], cut to the run, by a cumulative integral
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (spin[1:] + spin[:-1]) * np.diff(time))])
    low = np.clip(time - window / 2, time[0], time[-1])
    high = np.clip(time + window / 2, time[0], time[-1])
    mean = (np.interp(high, time, integral) - np.interp(low, time, integral)) / (high - low)
    # the start is negative: the mean's first sample above +band comes after the reversal
    leaves = int(np.argmax(mean > band))
    before = np.flatnonzero(np.sign(mean[:leaves]) != np.sign(mean[1 : leaves + 1]))[-1]
    zero = time[before] - mean[before] * (time[before + 1] - time[before]) / (
        mean[before + 1] - mean[before]
    )
    first = summary["first_reversal_time"]
    assert first == pytest.approx(zero, abs=1e-5)  # the code integrates the interpolant exactly
    assert summary["reversal_times"][0] == first
    # the raw spin changes sign earlier and more often around the reversal
    assert summary["first_spin_crossing_time"] < first
    assert len(summary["reversal_times"]) < len(summary["spin_crossings"])


def test_upright_steady_spin(upright: Result) -> None:
    summary = upright.json()
    assert summary["model"] == "rolling"
    assert summary["body"] == KL_NAME
    assert summary["t_end"] == 1.0
    assert summary["status"] == "success"
    assert isinstance(summary["message"], str) and summary["message"]
    # spin = ω · n with n = (0, 0, 1): exactly the given w3
    assert summary["spin_initial"] == -5.0
    assert summary["spin_final"] == pytest.approx(-5.0, abs=1e-6)
    assert summary["first_reversal_time"] is None
    assert summary["first_spin_crossing_time"] is None
    assert summary["spin_crossings"] == []
    energy = 0.5 * C_MOMENT * 25.0 + MASS * GRAVITY * REST_HEIGHT  # 0.11935 J
    assert summary["energy_initial"] == pytest.approx(energy, rel=1e-12)
    assert summary["energy_final"] == pytest.approx(energy, rel=1e-8)
    assert summary["max_tilt"] == pytest.approx(0.0, abs=1e-8)  # rad
    assert summary["min_normal_force"] == pytest.approx(MASS * GRAVITY, rel=1e-6)
    assert summary["max_slip_speed"] == 0.0  # rolling: no slip, ever
    assert summary["dissipated_work"] == 0.0
    assert 0.0 <= summary["max_relative_energy_drift"] < 1e-8


def test_reversal_is_the_first_zero_crossing(reversing: Result) -> None:
    summary = reversing.json()
    crossings = summary["spin_crossings"]
    assert crossings, "Kane & Levinson's -5 rad/s start reverses within 3 s"
    assert summary["first_spin_crossing_time"] == crossings[0]
    assert crossings == sorted(crossings)
    assert 0.0 < crossings[0] < 3.0
    # spin_initial: ω0 · n0 with n0 = (-cos α sin β, sin α, cos α cos β), ω0 = (0, 0, -5)
    alpha = beta = math.radians(0.5)
    assert summary["spin_initial"] == pytest.approx(-5.0 * math.cos(alpha) * math.cos(beta))
    # an odd number of sign changes leaves the spin positive, an even one negative
    assert (summary["spin_final"] > 0) == (len(crossings) % 2 == 1)
    assert summary["max_slip_speed"] == 0.0
    assert summary["dissipated_work"] == 0.0
    assert summary["max_relative_energy_drift"] < 1e-8
    assert summary["energy_final"] == pytest.approx(summary["energy_initial"], rel=1e-8)
    assert math.degrees(summary["max_tilt"]) > 0.5  # it rattles


def test_text_output(reversing: Result) -> None:
    text = Result(["run", "--omega", "0,0,-5", "--euler-angles", "0.5,0.5", "--t-end", "3"])
    summary = reversing.json()
    assert text.status == 0
    assert text.err == ""
    with pytest.raises(json.JSONDecodeError):
        json.loads(text.out)
    lines = text.out.splitlines()
    assert lines[0].startswith(f"rolling run of {KL_NAME}")
    assert "success" in lines[0]
    assert f"first reversal at {summary['first_reversal_time']:.6g} s" in text.out
    assert f"spin zero crossings: {len(summary['spin_crossings'])}" in text.out
    assert "energy" in text.out and "J" in text.out
    assert "max tilt" in text.out


def test_text_output_without_reversal(upright: Result) -> None:
    text = Result(["run", "--omega", "0,0,-5", "--euler-angles", "0,0", "--t-end", "1"])
    assert text.status == 0
    assert "no reversal" in text.out
    assert "spin zero crossings: 0" in text.out


def test_sliding_json(sliding: tuple[Result, Path]) -> None:
    result, _ = sliding
    assert result.status == 0, result.err
    summary = result.json()
    assert set(summary) >= SUMMARY_KEYS
    assert summary["model"] == "sliding"
    assert summary["status"] == "success"
    assert summary["t_end"] == 2.0
    assert summary["max_slip_speed"] > 0.0
    assert summary["dissipated_work"] > 0.0
    lost = summary["energy_initial"] - summary["energy_final"]
    assert lost > 0.0
    # energy balance E(0) - E(t) = W(t), to the solver's accuracy (rtol 1e-8)
    assert summary["dissipated_work"] == pytest.approx(lost, abs=1e-5 * summary["energy_initial"])
    if summary["spin_crossings"]:
        assert summary["first_spin_crossing_time"] == summary["spin_crossings"][0]
    else:
        assert summary["first_spin_crossing_time"] is None
    # only the rolling model without damping conserves energy: no drift to report
    assert summary["max_relative_energy_drift"] is None


def test_netcdf_output(sliding: tuple[Result, Path]) -> None:
    result, target = sliding
    summary = result.json()
    assert [p.name for p in target.parent.iterdir()] == ["run.nc"]
    with xr.open_dataset(target, engine="netcdf4") as stored:
        ds = stored.load()
    units = {
        "spin": "rad/s",
        "tilt": "rad",
        "energy": "J",
        "normal_force": "N",
        "slip_speed": "m/s",
        "omega": "rad/s",
        "n": "1",
    }
    for name, unit in units.items():
        assert ds[name].dims[0] == "time", name
        assert ds[name].attrs["units"] == unit, name
    assert ds["time"].attrs["units"] == "s"
    assert ds["omega"].shape == (ds.sizes["time"], 3)
    assert ds["time"].values[0] == 0.0
    assert ds["time"].values[-1] == pytest.approx(2.0)
    # the file holds the run the summary describes
    assert ds["spin"].values[0] == summary["spin_initial"]
    assert ds["spin"].values[-1] == summary["spin_final"]
    assert ds["energy"].values[0] == summary["energy_initial"]
    assert np.max(ds["slip_speed"].values) == summary["max_slip_speed"]
    np.testing.assert_allclose(np.linalg.norm(ds["n"].values, axis=1), 1.0, atol=1e-6)
    # provenance
    attrs = ds.attrs
    assert KL_SOURCE_TITLE in attrs["body_source"]
    assert attrs["body"] == KL_NAME
    assert attrs["model"] == "sliding"
    assert attrs["friction_law"]
    assert attrs["friction_load"] == "dynamic"
    assert attrs["friction_coefficient"] == 0.25
    assert attrs["contact_radius"] == 0.002
    assert attrs["rtol"] == 1e-8
    assert attrs["atol"] == 1e-11
    assert attrs["celtstone_version"] == metadata.version("celtstone")


def test_csv_output(tmp_path: Path) -> None:
    target = tmp_path / "run.csv"
    result = Result(["run", "--t-end", "1", "--samples", "11", "--json", "--out", str(target)])
    assert result.status == 0, result.err
    summary = result.json()
    lines = target.read_text(encoding="utf-8").splitlines()
    comments = [line for line in lines if line.startswith("#")]
    table = [line for line in lines if not line.startswith("#")]
    assert lines[0].startswith("#")
    assert any("spin [rad/s]" in line for line in comments)
    header = table[0].split(",")
    for column in ("time", "spin", "tilt", "energy", "normal_force", "omega_1", "n_3"):
        assert column in header
    rows = np.array([row.split(",") for row in table[1:]], dtype=float)
    assert rows.shape == (11, len(header))
    time = rows[:, header.index("time")]
    np.testing.assert_allclose(time, np.linspace(0.0, 1.0, 11), rtol=0, atol=1e-15)
    assert rows[0, header.index("spin")] == summary["spin_initial"]
    assert rows[-1, header.index("spin")] == summary["spin_final"]


def test_lift_off_exits_3_and_keeps_the_output(tmp_path: Path) -> None:
    """Fast rolling about the short horizontal axis throws the body off the plane."""
    target = tmp_path / "lift.nc"
    result = Result(
        [
            "run",
            "--omega",
            "0,60,0",
            "--euler-angles",
            "0,0",
            "--t-end",
            "1",
            "--json",
            "--out",
            str(target),
        ]
    )
    assert result.status == 3
    summary = result.json()
    assert summary["status"] == "lift_off"
    assert 0.0 < summary["t_stop"] < 1.0
    stderr = result.err.splitlines()
    assert len(stderr) == 1
    assert "Traceback" not in result.err
    assert summary["message"] in stderr[0]
    assert "lift" in stderr[0].lower()
    with xr.open_dataset(target, engine="netcdf4") as stored:
        ds = stored.load()
    assert ds.attrs["status"] == "lift_off"
    assert 0.0 < ds["time"].values[-1] <= summary["t_stop"]
    # the values at t_end are null: the run did not get there (its file has the spin up
    # to the stop); the values over the run reach the stop
    assert summary["spin_final"] is None and summary["energy_final"] is None
    assert summary["dissipated_work"] == ds["dissipated_work"].values[-1]


def test_lift_off_run_reports_a_vanishing_minimum_normal_force() -> None:
    """A run stopped by lift-off ends where N crosses zero: its minimum is about 0, not m g."""
    result = Result(["run", "--omega", "0,60,0", "--euler-angles", "0,0", "--t-end", "1", "--json"])
    summary = result.json()
    assert summary["status"] == "lift_off"
    assert summary["min_normal_force"] < 1e-3 * MASS * GRAVITY


def test_bodies_lists_the_shipped_bodies_with_sources() -> None:
    result = Result(["bodies"])
    assert result.status == 0
    lines = result.out.splitlines()
    index = next(k for k, line in enumerate(lines) if line.startswith(f"{KL_NAME}:"))
    assert "ellipsoid" in lines[index]
    source = lines[index + 1]
    assert "source" in source
    assert "Kane" in source and "1982" in source and KL_SOURCE_TITLE in source
    assert any(line.startswith(f"{KL_NAME}_paraboloid:") for line in lines)


def test_bodies_json() -> None:
    result = Result(["bodies", "--json"])
    assert result.status == 0
    entries = json.loads(result.out)
    entry = entries[KL_NAME]
    assert entry["shape"] == "ellipsoid"
    assert entry["mass"] == 1.0
    assert KL_SOURCE_TITLE in entry["source"]
    assert entries[f"{KL_NAME}_paraboloid"]["shape"] == "paraboloid"


def test_version() -> None:
    result = Result(["--version"])
    assert result.status == 0
    assert result.out.strip() == f"celtstone {metadata.version('celtstone')}"


def test_run_help_names_units_and_ranges() -> None:
    result = Result(["run", "--help"])
    assert result.status == 0
    for fragment in ("--friction-coefficient", "--contact-radius", "[m]", "--omega", "rad/s"):
        assert fragment in result.out


def test_python_dash_m_help() -> None:
    completed = subprocess.run(
        [sys.executable, "-m", "celtstone", "--help"],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert completed.returncode == 0, completed.stderr
    assert "usage: celtstone" in completed.stdout
    assert "run" in completed.stdout and "bodies" in completed.stdout


def test_text_output_when_a_summary_value_is_null(monkeypatch: pytest.MonkeyPatch) -> None:
    """The JSON summary allows null for the minimum normal force; the text must cope."""
    from celtstone.simulation.trajectory import Trajectory

    original = Trajectory.summary

    def summary_without_normal_force(self: Trajectory) -> dict:
        return {**original(self), "min_normal_force": None}

    monkeypatch.setattr(Trajectory, "summary", summary_without_normal_force)
    result = Result(["run", "--omega", "0,0,-5", "--euler-angles", "0,0", "--t-end", "1"])
    assert result.status == 0, result.err
    assert "min normal force unknown" in result.out


ABANDONED_WRITE = """
import gc, sys
from celtstone.cli import bodies, main as cli

async def write_block():  # as zarr's writes: a coroutine run by a sync wrapper
    pass

abandoned = []

def interrupted(args):
    abandoned.append(write_block())  # created as Ctrl-C arrived, never awaited
    print("celtstone: interrupted: run the same command with --resume", file=sys.stderr)
    return cli.EXIT_INTERRUPTED

bodies.handle = interrupted
status = cli.main(["bodies"])
abandoned.clear()
gc.collect()  # the coroutine is collected, as at exit
sys.exit(status)
"""


ABANDONED_WHILE_UNWINDING = """
import gc, os, signal, sys
from celtstone.cli import bodies, main as cli

async def write_block():  # as zarr's writes: a coroutine run by a sync wrapper
    pass

def interrupted(args):
    try:
        pending = write_block()  # a block's write under way as the signal arrives
        os.kill(os.getpid(), signal.SIGNUM)
    except KeyboardInterrupt:  # as the sweep catches it for its resume message
        del pending
        gc.collect()  # collected while the command unwinds, inside its warnings' context
        print("celtstone: stopped: run the same command with --resume", file=sys.stderr)
        return cli.EXIT_INTERRUPTED
    return 0

bodies.handle = interrupted
sys.exit(cli.main(["bodies"]))
"""


@pytest.mark.parametrize("name", ["SIGINT", "SIGTERM"])
def test_a_write_abandoned_while_the_command_unwinds_adds_no_line(name: str) -> None:
    """A store write's coroutine that the signal left unawaited and that is collected
    before the command returns (the sweep catching the interrupt) is not warned of:
    the resume message stays the only line, for Ctrl-C and SIGTERM alike."""
    script = ABANDONED_WHILE_UNWINDING.replace("SIGNUM", name)
    completed = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120
    )
    assert completed.returncode == 128 + getattr(signal, name)
    assert completed.stderr.splitlines() == [
        "celtstone: stopped: run the same command with --resume"
    ]


def test_an_interrupt_says_one_line_even_with_a_write_left_unawaited() -> None:
    """The stopped sweep's message stays the only line when a store write's coroutine
    created as the signal arrived is collected afterwards (Python would warn that it
    was never awaited)."""
    completed = subprocess.run(
        [sys.executable, "-c", ABANDONED_WRITE], capture_output=True, text=True, timeout=120
    )
    assert completed.returncode == 130
    assert completed.stderr.splitlines() == [
        "celtstone: interrupted: run the same command with --resume"
    ]
