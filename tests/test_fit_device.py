"""A fit's and the atlas's runs on a device (``fit(device=...)``, ``celtstone fit
--device``, ``compute_atlas(device=...)``, ``celtstone reproduce --device``).

No GPU is needed. On a GPU each batch of runs goes as one ``simulate_many`` call; here
that batch path runs on the CPU (``simulate_many(device="cpu")``, forced by ``batch``),
and its oracle is the thread path, ``Problem.run`` on threads, which it must give to the
last bit: residuals, Jacobian, run counts, a whole fit, an atlas's long runs. Asking for
a GPU where there is none, or for a device that does not exist, is one line (exit 2 from
the CLI) before any run. ``tests/test_fit_cuda.py`` compares both devices in numba's CUDA
simulator.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import io
import json
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import celtstone as cs
from celtstone.atlas import StoneDesign, compute_atlas, fields
from celtstone.atlas.fields import ATLAS_STUDY, _long_run, _long_runs
from celtstone.atlas.search import SearchPoint, search_long_runs
from celtstone.cli.main import main
from celtstone.errors import (
    CeltstoneError,
    FitQualityWarning,
    IdentifiabilityWarning,
    ParameterError,
)
from celtstone.fitting import solve
from celtstone.fitting.problem import FAILED_RESIDUAL, Problem, Settings, make_problem
from celtstone.fitting.runs import Runs, run_device
from celtstone.fitting.search import _release_runs
from test_fit_trust import Truth, phone_record

# the short runs' friction-bound warnings (the fit silences them in its trial runs)
QUIET = pytest.mark.filterwarnings("ignore::celtstone.errors.FrictionBoundWarning")
TRUTH = Truth(0.3, 1e-3, 0.2, ("spin",))  # f, ε [m], release offset [s], series
FREE = ["friction_coefficient", "contact_radius"]
# two designs of the atlas family (tests/test_atlas_search.py's), runs of 2 s
DESIGNS = [StoneDesign(0.1, 0.25, 0.15, 4.0, 0.5), StoneDesign(0.2, 0.3, 0.15, 3.0, 0.5)]
SHORT = dataclasses.replace(ATLAS_STUDY, fig3_t_end=2.0)


def _gpu_here() -> bool:
    """Whether this process sees a CUDA GPU (or the simulator): then the refusals below
    do not happen."""
    from celtstone.solvers.batch_cuda import cuda_unavailable_reason

    return cuda_unavailable_reason() is None


@pytest.fixture(scope="module")
def record(kane_levinson: cs.Body) -> cs.Record:
    """A spin record of 0.5 s that starts 0.2 s after Kane & Levinson's release."""
    return phone_record(kane_levinson, TRUTH, 0.5, seed=0)


def _problem(body: cs.Body, record: cs.Record, released: bool) -> Problem:
    """f and ε free (with the spin's bias), from the record's first sample; ``released``:
    from the release, its offset free too (each run then ends at its own time)."""
    free = [*FREE, "release_offset"] if released else FREE
    fixed = {} if released else {"omega3": -5.0}
    return make_problem(record, body, "sliding", free, Settings(fixed=fixed, initial_slip=False))


class _NoRuns:
    """Stands in for every way a fit or an atlas runs the simulator: a run is a failure."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch) -> None:
        def refuse(*args: Any, **kwargs: Any) -> None:
            raise AssertionError("a run started")

        for module in ("celtstone.fitting.problem", "celtstone.atlas.fields"):
            monkeypatch.setattr(f"{module}.simulate", refuse)
        for module in ("celtstone.simulation.integrate", "celtstone.atlas.fields"):
            monkeypatch.setattr(f"{module}.simulate_many", refuse)


@QUIET
@pytest.mark.parametrize("released", [False, True], ids=["first sample", "release"])
def test_the_batch_path_gives_the_thread_paths_runs(
    kane_levinson: cs.Body, record: cs.Record, released: bool
) -> None:
    """Residuals with the Jacobian's columns ahead, the Jacobian, screened points (one
    of them a configuration the model refuses), the release runs: the same numbers and
    the same counts, whether each batch is ``Problem.run`` on threads or one
    ``simulate_many`` (grouped by end time where the release offset differs)."""
    problem = _problem(kane_levinson, record, released)
    x = problem.start
    columns = list(range(x.size))
    refused = x.copy()
    refused[problem.names.index("contact_radius")] = -1.0  # no model has ε < 0
    shifted = x * 1.01
    outcomes = []
    for batch in (False, True):
        with Runs(problem, workers=2, batch=batch) as runs:
            got = [
                runs.residuals(x, columns),
                runs.jacobian(x),
                *runs.evaluate_many([shifted, refused, x]),
            ]
            if released:
                got += _release_runs(problem, [x, refused, shifted], runs)
            outcomes.append((got, runs.count, runs.failed, runs.wasted))
    (threads, *counts), (batched, *batch_counts) = outcomes
    assert batch_counts == counts
    assert counts[1] == 1  # the refused point's residuals (its release run: no start)
    assert len(batched) == len(threads)
    for expected, got in zip(threads, batched, strict=True):
        np.testing.assert_array_equal(got, expected, strict=True)
    assert np.all(threads[3] == FAILED_RESIDUAL)  # the refused configuration
    if released:
        assert threads[-2].size == 0  # no release run of it
        assert threads[-1].size > 0 and np.all(np.isfinite(threads[-1]))


@QUIET
def test_a_fit_through_the_batch_path_is_the_thread_paths_fit(
    kane_levinson: cs.Body, record: cs.Record, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A whole fit (its local fit, the checks and profiles of its intervals) with every
    batch through ``simulate_many``: the thread path's values, errors, cost and runs."""

    def fitted() -> cs.FitResult:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", IdentifiabilityWarning)
            warnings.simplefilter("ignore", FitQualityWarning)
            return cs.fit(
                record, kane_levinson, "sliding", FREE, fixed={"omega3": -5.0}, starts=1,
                initial_slip=False, workers=2,
            )  # fmt: skip

    threads = fitted()
    monkeypatch.setattr(solve, "Runs", functools.partial(Runs, batch=True))
    batched = fitted()
    np.testing.assert_array_equal(batched.values, threads.values, strict=True)
    np.testing.assert_array_equal(batched.standard_errors, threads.standard_errors, strict=True)
    assert batched.cost == threads.cost
    assert dict(batched.runs_by_stage) == dict(threads.runs_by_stage)
    assert (batched.runs, batched.failed_runs) == (threads.runs, threads.failed_runs)
    assert threads.runs > 20  # the profiles were walked: many batches
    assert batched.device == threads.device == threads.summary()["device"] == "cpu"


def test_a_bad_device_is_refused_before_any_run(
    kane_levinson: cs.Body, record: cs.Record, monkeypatch: pytest.MonkeyPatch
) -> None:
    _NoRuns(monkeypatch)
    with pytest.raises(ParameterError, match=r"device = 'gpu' is not allowed: expected one of"):
        cs.fit(record, kane_levinson, "sliding", FREE, device="gpu")
    problem = _problem(kane_levinson, record, released=False)
    with pytest.raises(ParameterError, match="expected one of: cpu, cuda, auto"):
        run_device("gpu", problem)
    with pytest.raises(ParameterError, match="device = 'gpu' is not allowed"):
        compute_atlas(DESIGNS, SHORT, device="gpu")
    with pytest.raises(ParameterError, match="device = 'gpu' is not allowed"):
        search_long_runs([SearchPoint(DESIGNS[0], "eps_1mm")], SHORT, device="gpu")


def _write_record(record: cs.Record, path: Path) -> Path:
    rows = ["time,spin"] + [
        f"{float(t)!r},{float(s)!r}"
        for t, s in zip(record.times, record.series["spin"], strict=True)
    ]
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


def _cli(*argv: str) -> tuple[int, list[str]]:
    """``celtstone ARGV``'s exit status and the lines of its standard error."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        status = main(list(argv))
    return status, err.getvalue().strip().splitlines()


@pytest.mark.parametrize("device", ["gpu", "cuda"])
def test_the_cli_refuses_a_device_in_one_line_before_any_run(
    record: cs.Record, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, device: str
) -> None:
    """``--device gpu`` everywhere; ``--device cuda`` where there is no GPU: exit 2, one
    line naming the device, no run, no output."""
    if device == "cuda" and _gpu_here():
        pytest.skip("a CUDA GPU is here: the fit would run on it")
    _NoRuns(monkeypatch)
    data = _write_record(record, tmp_path / "spin.csv")
    out = tmp_path / "fit"
    fit = ["fit", str(data), "--body", "kane_levinson_1982", "--free", ",".join(FREE)]
    reproduce = ["reproduce", "atlas", "--out", str(tmp_path / "results"), "--no-progress"]
    for argv in (
        [*fit, "--device", device, "--out", str(out), "--no-progress"],
        [*reproduce, "--device", device],
    ):
        status, lines = _cli(*argv)
        assert status == 2 and len(lines) == 1, lines
        assert f"device = '{device}' is not allowed" in lines[0]
        if device == "cuda":
            assert "numba" in lines[0]  # why: no CUDA GPU, or no CUDA target
    assert not out.exists() and not (tmp_path / "results").exists()


def test_a_device_without_the_atlas_target_is_refused(tmp_path: Path) -> None:
    status, lines = _cli("reproduce", "figure2", "--device", "auto", "--out", str(tmp_path / "r"))
    assert status == 2 and len(lines) == 1, lines
    assert "device = 'auto' is not allowed: expected cpu without the target atlas" in lines[0]


def test_cuda_without_a_gpu_is_refused_in_python_before_any_run(
    kane_levinson: cs.Body, record: cs.Record, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """And "auto" takes the CPU there."""
    if _gpu_here():
        pytest.skip("a CUDA GPU is here: the runs would go to it")
    _NoRuns(monkeypatch)
    problem = _problem(kane_levinson, record, released=False)
    assert run_device("auto", problem) == "cpu"
    refusal = r"device = 'cuda' is not allowed: expected cpu, or auto"
    with pytest.raises(ParameterError, match=refusal):
        cs.fit(record, kane_levinson, "sliding", FREE, device="cuda")
    with pytest.raises(ParameterError, match=refusal):
        compute_atlas(DESIGNS, SHORT, tmp_path / "atlas", device="cuda")
    assert not (tmp_path / "atlas").exists()
    with pytest.raises(ParameterError, match=refusal):
        search_long_runs([SearchPoint(DESIGNS[0], "eps_1mm")], SHORT, device="cuda")


@QUIET
def test_the_atlas_long_runs_together_are_each_designs_own(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The long runs of every design as two ``simulate_many`` calls (one per model kind,
    the GPU's path, here on the CPU): each design's numbers are those of its own runs
    (``_long_run``, the thread path's), each stored as it is computed; resumed, only the
    designs not stored run."""
    bodies = [design.body() for design in DESIGNS]
    expected = [_long_run(SHORT, body) for body in bodies]
    assert any(case["reversal_times"] for n in expected for case in n["cases"])  # one reverses
    calls: list[int] = []
    real = fields.simulate_many

    def counted(runs: Any, *args: Any, **kwargs: Any) -> Any:
        calls.append(len(runs))
        return real(runs, *args, **kwargs)

    monkeypatch.setattr(fields, "simulate_many", counted)
    together = _long_runs(SHORT, DESIGNS, bodies, tmp_path, None, False, "cpu", batch=True)
    assert together == expected
    assert calls == [2, 2]  # rolling, then sliding: every design in each
    stored = sorted((tmp_path / "long_run").iterdir())
    assert [p.name for p in stored] == ["design_00000.json", "design_00001.json"]
    assert json.loads(stored[1].read_text())["numbers"] == expected[1]
    stored[0].unlink()
    resumed = _long_runs(SHORT, DESIGNS, bodies, tmp_path, None, False, "cpu", batch=True)
    assert resumed == expected and calls[2:] == [1, 1]  # the unstored design alone


def test_a_run_a_batch_cannot_make_keeps_its_error(
    kane_levinson: cs.Body, record: cs.Record
) -> None:
    """``Problem.run_many``: a vector the model refuses has its error in its place."""
    problem = _problem(kane_levinson, record, released=False)
    refused = problem.start.copy()
    refused[1] = -1.0
    made = problem.run_many([refused, problem.start], "cpu", workers=1)
    assert isinstance(made[0], CeltstoneError) and not isinstance(made[1], CeltstoneError)
    np.testing.assert_array_equal(
        problem.residuals(made[1], problem.start),
        problem.residuals(problem.run(problem.start), problem.start),
        strict=True,
    )
