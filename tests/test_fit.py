"""Fitting a measured motion: synthetic recovery with honest standard errors, parameters
that the data cannot tell apart, failed runs, the parallel and speculative Jacobian, the
profile likelihood, and ``celtstone fit``'s output directory.

The oracle is a run with known parameters plus Gaussian noise of a known level: the fit
must find the parameters within its own standard errors and the noise level it was given.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

import celtstone as cs
from celtstone.cli.main import main
from celtstone.errors import CeltstoneError
from celtstone.files.export import read_run
from celtstone.fitting.problem import FAILED_RESIDUAL, Problem, Settings, make_problem
from celtstone.fitting.runs import Runs
from celtstone.fitting.series import yaw_angle

KL_STATE = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))  # Kane & Levinson's start
TRUTH = {"friction_coefficient": 0.3, "contact_radius": 1e-3}
NOISE = 0.05  # rad/s, of the spin
SEEDS = range(5)  # the recovery's noise draws; the fast tier fits the first two
FAST_SEEDS = range(2)
DURATION = 2.5  # s, at 100 samples per second
# records shorter than the first reversal: the fit says so (tested in test_fit_trust.py)
NO_REVERSAL = pytest.mark.filterwarnings("ignore:the fitted spin does not reverse")


def _truth_run(body: cs.Body, state: cs.InitialState, duration: float) -> cs.Trajectory:
    """The 'measured' motion: the sliding model with ``TRUTH``, at the default (tight)
    tolerances, sampled at 100 Hz."""
    times = np.round(np.arange(0.0, duration + 1e-9, 0.01), 10)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cs.FrictionBoundWarning)
        return cs.simulate(cs.SlidingModel(**TRUTH), body, state, duration, sample_times=times)


def _noisy_spin_record(
    body: cs.Body, state: cs.InitialState, duration: float, noise: float
) -> cs.Record:
    """The spin of the truth run with Gaussian noise of ``noise`` [rad/s] (seed 0)."""
    run = _truth_run(body, state, duration)
    spin = run.samples.values("spin")
    noisy = spin + np.random.default_rng(0).normal(0.0, noise, spin.size)
    return cs.make_record(run.samples.values("time"), {"spin": noisy})


@pytest.fixture(scope="module")
def kl_spin(kane_levinson: cs.Body) -> tuple[np.ndarray, np.ndarray]:
    run = _truth_run(kane_levinson, KL_STATE, DURATION)
    return run.samples.values("time"), run.samples.values("spin")


@pytest.mark.parametrize(
    "seeds",
    [
        pytest.param(FAST_SEEDS, id="two-draws"),
        pytest.param(SEEDS, id="five-draws", marks=pytest.mark.slow),
    ],
)
def test_synthetic_recovery_within_the_standard_errors(
    kane_levinson: cs.Body, kl_spin: tuple[np.ndarray, np.ndarray], seeds: range
) -> None:
    """f, ε and the initial spin from a noisy spin record, started 33 % and 40 % away:
    the truth within 3 standard errors in every repeat and 2 in all but one at most; the
    noise level found within 20 % of the one added. Each fit walks three profiles (a
    record of one series), so the fast tier fits two noise draws and the slow one five;
    the errors' calibration over many draws is ``test_fit_trust``'s slow
    ``test_standard_errors_match_the_spread_over_fresh_noise``."""
    times, spin = kl_spin
    truth = {**TRUTH, "initial_spin": float(np.dot(KL_STATE.omega, KL_STATE.vertical))}
    start = {"friction_coefficient": 0.2, "contact_radius": 1.4e-3}
    within_two = 0
    for seed in seeds:
        noisy = spin + np.random.default_rng(seed).normal(0.0, NOISE, spin.size)
        record = cs.make_record(times, {"spin": noisy})
        result = cs.fit(  # a record from the release: its contact starts without slip
            record,
            kane_levinson,
            "sliding",
            [*truth],
            start=start,
            sensor_bias=False,
            initial_slip=False,
            starts=1,
        )
        errors = result.standard_errors
        deviations = np.abs(result.values - np.array(list(truth.values()))) / errors
        assert np.all(np.isfinite(errors)) and np.all(deviations < 3.0), (seed, deviations)
        within_two += bool(np.all(deviations < 2.0))
        assert result.noise_estimates()["spin"] == pytest.approx(NOISE, rel=0.2)
        assert result.starts[0].converged and result.failed_runs == 0
        assert result.summary()["starts_reaching_best"] == 1
    assert within_two >= len(seeds) - 1


def test_friction_and_contact_size_from_spin_alone_are_correlated() -> None:
    """The toy stone spun the stable way: its spin decays by the pivoting moment, whose
    size is f ε N (paper eq. 10), so f and ε are not separately determined."""
    body = cs.load_body("toy_rattleback_10cm")
    record = _noisy_spin_record(body, cs.InitialState((0.0, 0.0, 5.0), (0.5, 0.5)), 2.0, 0.02)
    with pytest.warns(cs.IdentifiabilityWarning, match="friction_coefficient and contact_radius"):
        result = cs.fit(
            record,
            body,
            "sliding",
            ["friction_coefficient", "contact_radius"],
            fixed={"omega3": 5.0},
            sensor_bias=False,
            starts=1,
        )
    assert abs(result.correlation[0, 1]) > 0.99
    pair = result.summary()["strongly_correlated"][0]
    assert pair["parameters"] == ["friction_coefficient", "contact_radius"]
    assert abs(pair["correlation"]) > 0.99


@NO_REVERSAL
def test_pure_pivoting_leaves_only_the_product(kane_levinson: cs.Body) -> None:
    """Spin about the upright axis 3 without tilt: the only torque is the pivoting moment
    ∝ f ε, so the Jacobian has rank 1 and neither is determined alone."""
    upright = cs.InitialState((0.0, 0.0, -5.0), (0.0, 0.0))
    record = _noisy_spin_record(kane_levinson, upright, 1.0, 0.01)
    with pytest.warns(cs.IdentifiabilityWarning, match="rank 1 < 2"):
        result = cs.fit(
            record,
            kane_levinson,
            "sliding",
            ["friction_coefficient", "contact_radius"],
            fixed={"euler_alpha": 0.0, "euler_beta": 0.0, "omega3": -5.0},
            sensor_bias=False,
            starts=1,
        )
    summary = result.summary()
    assert summary["jacobian_rank"] == 1
    assert [p["standard_error"] for p in summary["parameters"].values()] == [None, None]
    product = result.values[0] * result.values[1]
    assert product == pytest.approx(
        TRUTH["friction_coefficient"] * TRUTH["contact_radius"], rel=0.02
    )


# the short runs' friction-bound warnings (the fit silences them in its trial runs)
QUIET = pytest.mark.filterwarnings("ignore::celtstone.errors.FrictionBoundWarning")


def _problem(kane_levinson: cs.Body, kl_spin: tuple[np.ndarray, np.ndarray]) -> Problem:
    times, spin = kl_spin
    record = cs.make_record(times[:101], {"spin": spin[:101]})
    return make_problem(
        record,
        kane_levinson,
        "sliding",
        ["friction_coefficient", "contact_radius"],
        Settings(fixed={"omega3": -5.0}, sensor_bias=False, rtol=1e-8, atol=1e-10),
    )


def test_a_failed_run_gives_large_finite_residuals_and_is_counted(
    kane_levinson: cs.Body,
    kl_spin: tuple[np.ndarray, np.ndarray],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    problem = _problem(kane_levinson, kl_spin)

    def refuse(self: Problem, x: np.ndarray) -> cs.Trajectory:
        raise CeltstoneError("the run raised")

    monkeypatch.setattr(Problem, "run", refuse)
    with Runs(problem, workers=1) as runs:
        residuals = runs.residuals(problem.start)
    assert np.all(residuals == FAILED_RESIDUAL) and residuals.size == problem.n_residuals
    assert (runs.count, runs.failed) == (1, 1)


@QUIET
def test_parallel_jacobian_equals_the_serial_one(
    kane_levinson: cs.Body, kl_spin: tuple[np.ndarray, np.ndarray]
) -> None:
    problem = _problem(kane_levinson, kl_spin)
    with Runs(problem, workers=1) as serial, Runs(problem, workers=2) as parallel:
        np.testing.assert_array_equal(
            serial.jacobian(problem.start), parallel.jacobian(problem.start)
        )
        assert serial.count == parallel.count == 3


def _jacobian_runs(runs: Runs, x: np.ndarray) -> tuple[np.ndarray, int]:
    """The Jacobian at ``x`` and the runs it took."""
    before = runs.count
    return runs.jacobian(x), runs.count - before


@QUIET
@pytest.mark.parametrize("workers", [2, 3])
def test_speculative_columns_are_taken_at_the_same_point_only(
    kane_levinson: cs.Body, kl_spin: tuple[np.ndarray, np.ndarray], workers: int
) -> None:
    """Residuals at x run beside workers − 1 of the Jacobian's columns there; the Jacobian
    at x takes them (a hit) and equals the serial one bit for bit; at another point they
    are not used (a miss), and counted as wasted once a new point replaces them."""
    problem = _problem(kane_levinson, kl_spin)
    x, other = problem.start, problem.start * np.array([1.1, 0.9])
    ahead = min(workers - 1, 2)  # columns run beside a residual
    with Runs(problem, workers=1) as serial, Runs(problem, workers=workers) as runs:
        expected = serial.jacobian(x)
        residuals = runs.residuals(x, columns=[0, 1])
        np.testing.assert_array_equal(residuals, serial.residuals(x))
        assert (runs.count, runs.wasted) == (1 + ahead, ahead)  # not asked for yet
        hit, hit_runs = _jacobian_runs(runs, x.copy())  # the same bytes, another array
        np.testing.assert_array_equal(hit, expected)
        assert (hit_runs, runs.wasted) == (2 - ahead, 0)
        # a rejected step: residuals at `other`, then the next residuals elsewhere
        runs.residuals(other, columns=[0, 1])
        runs.residuals(x, columns=[1])  # column 1 alone ahead
        assert runs.wasted == ahead + 1  # `other`'s, and x's until the Jacobian asks
        _, miss_runs = _jacobian_runs(runs, x + 1e-12)  # not the same bytes
        assert miss_runs == 3 and runs.wasted == ahead + 1
        again, again_runs = _jacobian_runs(runs, x)
        np.testing.assert_array_equal(again, expected)
        assert (again_runs, runs.wasted) == (1, ahead)  # column 0 run now
        runs.use(problem)  # a new problem: nothing kept
        assert runs.wasted == ahead
        # x and its columns ahead, the rest; `other` and x again; a miss; column 0
        assert runs.count == (1 + ahead) + (2 - ahead) + (1 + ahead) + 2 + 3 + 1


@QUIET
def test_not_speculating_runs_only_the_residual(
    kane_levinson: cs.Body, kl_spin: tuple[np.ndarray, np.ndarray]
) -> None:
    problem = _problem(kane_levinson, kl_spin)
    with Runs(problem, workers=2, speculate=False) as runs:
        runs.residuals(problem.start, columns=[0, 1])
        assert (runs.count, runs.wasted) == (1, 0)
        assert _jacobian_runs(runs, problem.start)[1] == 2


@NO_REVERSAL
def test_a_speculative_fit_takes_the_serial_fits_path(
    kane_levinson: cs.Body, kl_spin: tuple[np.ndarray, np.ndarray]
) -> None:
    """Speculation changes no number of a fit: the same optimum bit for bit, and the
    serial fit's runs plus the wasted ones."""
    times, spin = kl_spin
    noisy = spin + np.random.default_rng(3).normal(0.0, NOISE, spin.size)
    record = cs.make_record(times[:101], {"spin": noisy[:101]})
    free = ["friction_coefficient", "contact_radius"]
    wasted = 0
    # starts far from the truth (f 0.3, eps 1 mm), so that the optimiser rejects trial
    # points and the speculation under test wastes runs (5 and 2 when measured; a start
    # near the truth rejects none, and which one does moves with the last bits of a run)
    for start in (
        {"friction_coefficient": 2.0, "contact_radius": 5e-4},
        {"friction_coefficient": 1.5, "contact_radius": 5e-4},
    ):
        serial, speculative = (
            cs.fit(
                record,
                kane_levinson,
                "sliding",
                free,
                start=start,
                fixed={"omega3": -5.0},
                workers=workers,
                sensor_bias=False,
                starts=1,
            )
            for workers in (1, 2)
        )
        np.testing.assert_array_equal(speculative.values, serial.values)
        assert serial.speculative_runs_wasted == 0
        assert speculative.runs == serial.runs + speculative.speculative_runs_wasted
        wasted += speculative.summary()["speculative_runs_wasted"]
    assert wasted > 0  # a trial point was rejected


@NO_REVERSAL
def test_profile_interval_of_a_near_linear_parameter(
    kane_levinson: cs.Body, kl_spin: tuple[np.ndarray, np.ndarray]
) -> None:
    """One free parameter: the 95 % profile interval holds the truth, and for this nearly
    quadratic cost it is close to ± 1.96 standard errors."""
    times, spin = kl_spin
    noisy = spin + np.random.default_rng(7).normal(0.0, NOISE, spin.size)
    record = cs.make_record(times[:151], {"spin": noisy[:151]})
    reports: list[tuple[int, float]] = []
    result = cs.fit(
        record,
        kane_levinson,
        "sliding",
        ["friction_coefficient"],
        fixed={"omega3": -5.0},
        profile="friction_coefficient",
        progress=lambda runs, cost: reports.append((runs, cost)),
        sensor_bias=False,
        starts=1,
    )
    runs = [count for count, _ in reports]
    # all but the final run and its check at tighter tolerances
    assert runs == sorted(runs) and runs[-1] == result.runs - 2
    assert min(cost for _, cost in reports) == pytest.approx(result.cost)
    assert result.profile is not None
    low, high = result.profile.interval
    assert low is not None and high is not None
    assert low < TRUTH["friction_coefficient"] < high
    half_width = 1.959964 * result.standard_errors[0]
    assert (high - low) / 2.0 == pytest.approx(half_width, rel=0.2)


@NO_REVERSAL
def test_yaw_and_tilt_from_video(kane_levinson: cs.Body, tmp_path: Path) -> None:
    """A video record: yaw [rad] with an arbitrary zero and tilt [deg] in a CSV file."""
    run = _truth_run(kane_levinson, KL_STATE, 1.5)
    samples = run.samples
    yaw = yaw_angle(samples.values("quaternion")) + 1.0  # camera's zero
    tilt = np.degrees(samples.values("tilt"))
    rng = np.random.default_rng(2)
    rows = zip(
        samples.values("time"),
        yaw + rng.normal(0.0, 0.002, yaw.size),
        tilt + rng.normal(0.0, 0.005, tilt.size),
        strict=True,
    )
    path = tmp_path / "video.csv"
    path.write_text("time,heading,tilt\n" + "".join(f"{t},{a},{b}\n" for t, a, b in rows))
    record = cs.read_record(path, ["yaw=heading", "tilt[deg]=tilt"])
    result = cs.fit(
        record,
        kane_levinson,
        "sliding",
        ["friction_coefficient"],
        start={"friction_coefficient": 0.2},
        fixed={"omega3": -5.0},
    )
    deviation = abs(result.values[0] - TRUTH["friction_coefficient"]) / result.standard_errors[0]
    assert deviation < 3.0
    assert result.problem.degrees_of_freedom == 2 * len(samples.values("time")) - 2
    # two series: weighted again by their first fit's residuals, which find the noise added
    assert set(result.problem.sigma_source.values()) == {"residuals of a first fit"}
    noise = result.noise_estimates()
    assert noise["yaw"] == pytest.approx(0.002, rel=0.2)
    assert noise["tilt"] == pytest.approx(np.radians(0.005), rel=0.2)


def _phyphox_record(path: Path, body: cs.Body) -> Path:
    run = _truth_run(body, KL_STATE, 1.0)
    rates = run.samples.values("omega") + np.random.default_rng(1).normal(0.0, 0.01, (101, 3))
    header = '"Time (s)","Gyroscope x (rad/s)","Gyroscope y (rad/s)","Gyroscope z (rad/s)"'
    rows = "".join(
        f"{t + 100.0},{x},{y},{z}\n"
        for t, (x, y, z) in zip(run.samples.values("time"), rates, strict=True)
    )
    path.write_text(header + "\n" + rows, encoding="utf-8")
    return path


@NO_REVERSAL
def test_cli_writes_the_fit_directory_whole(
    kane_levinson: cs.Body, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    data = _phyphox_record(tmp_path / "gyro.csv", kane_levinson)
    out = tmp_path / "fit"
    arguments = [
        "fit", str(data), "--body", "kane_levinson_1982", "--free", "friction_coefficient",
        "--start", "friction_coefficient=0.25", "--no-progress", "--json", "--out", str(out),
    ]  # fmt: skip
    assert main(arguments) == 0
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    assert "the initial state omega1 = " in captured.err  # held at the noisy first sample
    names = ["fit.png", "fit.svg", "run.nc", "summary.json"]  # and the manifest that owns them
    assert sorted(p.name for p in out.iterdir()) == [".celtstone-output.json", *names]
    assert json.loads((out / "summary.json").read_text()) == summary
    assert summary["parameters"]["friction_coefficient"]["value"] == pytest.approx(0.3, rel=0.01)
    assert summary["runs"] > 0 and summary["failed_runs"] == 0 and summary["wall_time"] > 0
    assert set(summary["series"]) == {"omega1", "omega2", "omega3"}
    fitted = read_run(out / "run.nc")  # what `plot`, `view`, `animate` open
    assert (
        float(fitted.attrs["friction_coefficient"])
        == summary["parameters"]["friction_coefficient"]["value"]
    )
    # an existing directory: refused; with --overwrite replaced only if it is a fit's
    assert main(arguments) == 2
    assert "add --overwrite" in capsys.readouterr().err
    assert main([*arguments, "--overwrite"]) == 0
    capsys.readouterr()
    thesis = tmp_path / "thesis"
    thesis.mkdir()
    (thesis / "chapter.tex").write_text("keep me")
    arguments[arguments.index(str(out))] = str(thesis)
    assert main([*arguments, "--overwrite"]) == 2
    assert "replaces only what celtstone wrote itself" in capsys.readouterr().err
    assert sorted(p.name for p in thesis.iterdir()) == ["chapter.tex"]
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".part")]
