"""Waits that say what they are, work that stops when asked, and files whole or absent
(issue 37, "Interruptions" and "Hangs without a word")."""

from __future__ import annotations

import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import celtstone as cs
from celtstone import ParameterError, stability
from celtstone._threads import map_in_threads
from celtstone.cli import animate as animate_cli
from celtstone.cli import stability as stability_cli
from celtstone.cli.main import main
from celtstone.fitting.runs import Runs
from celtstone.visual import animate, load_run
from celtstone.visual.animation import _count_frames
from tests.processes import catches_sigterm

CELTSTONE = Path(sys.executable).with_name("celtstone")
WAIT = 300  # s: only stops a hung test


# ---- a fit's runs stop at once ------------------------------------------------------------


class _BlockingProblem:
    """Stands in for ``fitting.Problem``: each run waits until released (a run of minutes)."""

    def __init__(self) -> None:
        self.started = threading.Semaphore(0)
        self.release = threading.Event()
        self.finished = 0

    def run(self, x: np.ndarray) -> SimpleNamespace:
        self.started.release()
        self.release.wait(WAIT)
        self.finished += 1
        return SimpleNamespace(ok=True)

    def residuals(self, trajectory: object, x: np.ndarray | None = None) -> np.ndarray:
        return np.zeros(1)


def _interrupt_once_running(problem: _BlockingProblem, runs: int) -> None:
    def send() -> None:
        for _ in range(runs):
            problem.started.acquire(timeout=WAIT)
        signal.raise_signal(signal.SIGINT)  # taken by the main thread

    threading.Thread(target=send, daemon=True).start()


def test_ctrl_c_leaves_a_fits_runs_in_flight_behind() -> None:
    """Ctrl-C while two runs are under way: the fit stops without waiting for them
    (before, the pool's shutdown joined them: minutes)."""
    problem = _BlockingProblem()
    _interrupt_once_running(problem, 2)
    with pytest.raises(KeyboardInterrupt), Runs(problem, workers=2) as runs:  # type: ignore[arg-type]
        runs.evaluate_many([np.zeros(1), np.ones(1)])
    assert problem.finished == 0  # both runs were still going when the fit had stopped
    problem.release.set()


def test_the_threads_take_no_queued_run_after_ctrl_c() -> None:
    problem = _BlockingProblem()
    _interrupt_once_running(problem, 2)
    started = []

    def run(item: int) -> int:
        started.append(item)
        problem.run(np.zeros(1))
        return item

    with pytest.raises(KeyboardInterrupt):
        list(map_in_threads(run, range(10), workers=2))
    problem.release.set()
    time.sleep(0.2)  # the released threads look for the next run, and find the stop
    assert len(started) == 2


# ---- stability: linear in the spin count, with progress, quiet on a closed pipe ----------


def test_the_stability_table_computes_each_column_once(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """The text table read every column once per row: k² work for k spins. The number
    of column computations must not grow with k."""
    calls = []
    original = stability._max_growth

    def counted(eigenvalues: np.ndarray) -> np.ndarray:
        calls.append(len(eigenvalues))
        return original(eigenvalues)

    monkeypatch.setattr(stability, "_max_growth", counted)
    counts = []
    for count in (5, 50):
        calls.clear()
        assert main(["stability", "--spin", f"-1:1:{count}"]) == 0
        assert len(capsys.readouterr().out.splitlines()) == 4 + count  # 4 header lines
        counts.append(len(calls))
    assert counts[0] == counts[1]


def test_spin_stability_reports_its_progress() -> None:
    seen: list[tuple[int, int]] = []
    count = 2 * stability.PROGRESS_EVERY + 7
    body = cs.load_body("kane_levinson_1982")
    cs.spin_stability(body, np.linspace(-2, 2, count), progress=lambda *a: seen.append(a))
    every = stability.PROGRESS_EVERY
    assert seen == [(every, count), (2 * every, count), (count, count)]


def test_a_long_stability_grid_says_what_it_does_when_not_at_a_terminal(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr(stability_cli, "ANNOUNCED_SPIN_COUNT", 20)
    assert main(["stability", "--spin", "-1:1:20", "--json"]) == 0
    error = capsys.readouterr().err
    assert error == (
        "celtstone: linearising the rolling model at 20 spin rates and their mirror images\n"
    )
    assert main(["stability", "--spin", "-1:1:19", "--json"]) == 0
    assert capsys.readouterr().err == ""


# ---- animate: progress, and whole or absent at any moment -----------------------------


@pytest.fixture(scope="module")
def run_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("runs") / "run.nc"
    assert main(["run", "--t-end", "3", "--out", str(path)]) == 0
    return path


def test_animate_reports_every_frame(run_file: Path, tmp_path: Path) -> None:
    seen: list[tuple[int, int]] = []
    info = animate(
        load_run(run_file), tmp_path / "a.gif", fps=5, progress=lambda *a: seen.append(a)
    )
    assert seen == [(done, info.frames) for done in range(info.frames + 1)]


def test_animate_says_what_it_draws_when_not_at_a_terminal(
    run_file: Path,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(animate_cli, "ANNOUNCED_FRAME_COUNT", 16)
    out = tmp_path / "a.gif"
    assert main(["animate", str(run_file), "--out", str(out), "--fps", "5"]) == 0
    captured = capsys.readouterr()
    assert captured.err == f"celtstone: drawing 16 frames into {out}\n"
    assert main(["animate", str(run_file), "--out", str(out), "--overwrite", "--fps", "5",
                 "--no-progress"]) == 0  # fmt: skip
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(animate_cli, "ANNOUNCED_FRAME_COUNT", 17)
    assert main(["animate", str(run_file), "--out", str(out), "--overwrite", "--fps", "5"]) == 0
    assert capsys.readouterr().err == ""  # a short animation: no line


def _wait_until(process: subprocess.Popen[str], reached: Callable[[], bool]) -> None:
    """Poll until ``reached()`` or the process has ended."""
    while not reached() and process.poll() is None:
        time.sleep(0.001)


#: the moments of a write at which the signal comes: as the command starts (its first
#: line has run), once the encoder has written the temporary's first bytes (the frames
#: being drawn), once the video is in place (the command finishing)
MOMENTS = ["starting", "encoding", "in place"]


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads /proc")
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM, signal.SIGKILL])
@pytest.mark.parametrize("moment", MOMENTS)
def test_an_interrupted_animation_leaves_the_whole_video_or_none(
    signum: int, moment: str, run_file: Path, tmp_path: Path
) -> None:
    """Each moment is watched for (the process's handlers, the temporary's first bytes,
    the video), not waited for: the same moments on a fast machine and a loaded one."""
    target = tmp_path / "a.mp4"

    def temporary_written() -> bool:
        for path in tmp_path.iterdir():
            try:
                if path.name != target.name and path.stat().st_size > 0:
                    return True
            except FileNotFoundError:  # moved into place since it was listed
                return True
        return False

    with subprocess.Popen(
        [str(CELTSTONE), "animate", str(run_file), "--out", str(target), "--fps", "10"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    ) as process:
        _wait_until(process, lambda: catches_sigterm(process.pid))
        if moment == "encoding":
            _wait_until(process, temporary_written)
        elif moment == "in place":
            _wait_until(process, target.exists)
        process.send_signal(signum)
        _, error = process.communicate(timeout=WAIT)
    assert "Traceback" not in error, error
    if target.exists():  # the signal came after the video was in place
        assert _count_frames(target) == 31  # 3 s at 10 fps, the first and last included
    if signum == signal.SIGKILL:
        return  # nothing can clean up; the next write removes a temporary left behind
    # 0: the signal came after the command ended; 128 + signum: it stopped the command;
    # -signum: it came while Python itself was exiting, after the command's work and its
    # handlers (a shell reports that as 128 + signum too)
    assert process.returncode in (0, 128 + signum, -signum), error
    leftovers = [p.name for p in tmp_path.iterdir() if p.name != "a.mp4"]
    assert leftovers == []
    if moment == "starting":  # stopped before it drew: nothing was written
        assert not target.exists() and process.returncode == 128 + signum, error


# ---- sweep: a million points say what happens before the first run ------------------------


def test_a_sweep_of_a_million_points_says_what_it_does_before_it_starts(
    tmp_path: Path,
) -> None:
    arguments = [
        "sweep", "--vary", "friction_coefficient=0.1:0.5:1000",
        "--vary", "contact_radius=0.0005:0.002:1000", "--t-end", "1", "--no-maps",
        "--out", str(tmp_path / "s.zarr"),
    ]  # fmt: skip
    with subprocess.Popen(
        [str(CELTSTONE), *arguments], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    ) as process:
        assert process.stderr is not None
        said = process.stderr.read(1)  # blocks until the command says something
        process.send_signal(signal.SIGINT)
        said += process.stderr.read()
        process.wait(WAIT)
    text = said.decode(errors="replace")
    assert "validating" in text or "sweep of 1000000 points" in text, text
    assert process.returncode == 130, text
    assert "Traceback" not in text


def test_a_million_points_over_a_body_and_a_model_validate_each_body_once(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A 1000 x 1000 grid of masses by friction coefficients: each body and each model
    is built once, and each body is checked once with the one contact the models share
    (the friction coefficient is not part of it), not a million times."""
    from celtstone.sweep import runner, spec

    calls = {"body": 0, "runnable": 0}
    build_body, require_runnable = spec.build_body, spec.plausibility.require_runnable

    def count_body(*args, **kwargs):  # type: ignore[no-untyped-def]
        calls["body"] += 1
        return build_body(*args, **kwargs)

    def count_runnable(*args, **kwargs):  # type: ignore[no-untyped-def]
        calls["runnable"] += 1
        return require_runnable(*args, **kwargs)

    monkeypatch.setattr(spec, "build_body", count_body)
    monkeypatch.setattr(spec.plausibility, "require_runnable", count_runnable)
    reports: list[tuple[int, int]] = []
    sweep = runner.Sweep(
        {"mass": np.linspace(0.5, 2.0, 1000), "friction_coefficient": np.linspace(0.1, 0.5, 1000)},
        t_end=1.0,
        force=True,
        progress=lambda built, total: reports.append((built, total)),
    )
    assert sweep.size == 1_000_000
    assert calls["body"] <= 1000 + 10  # a few for the sweep's description aside
    assert 1000 <= calls["runnable"] <= 1000 + 10
    assert reports[-1][0] == reports[-1][1]  # the progress ends at its total


def test_the_first_unrunnable_pair_is_named_as_point_by_point() -> None:
    """The oracle: each point built and checked on its own (``kernel_parameters``); the
    deduplicated validation names the same first point with the same message."""
    from celtstone.bodies import load_body
    from celtstone.simulation.models import kernel_parameters, model_from_name
    from celtstone.sweep import spec

    base = load_body("kane_levinson_1982")
    rho_min = min(base.shape.radii_of_curvature)
    masses = np.array([1.0, 1.5, 2.0])
    radii = np.array([0.1 * rho_min, 0.5 * rho_min, 2.0 * rho_min])  # the last: too large
    mass, radius = (a.ravel() for a in np.meshgrid(masses, radii, indexing="ij"))
    expected = None
    for index in range(mass.size):  # point by point
        body = spec.build_body(base, {"mass": float(mass[index])})
        model = model_from_name("sliding", contact_radius=float(radius[index]))
        try:
            kernel_parameters(model, body)
        except ParameterError as error:
            expected = (index, error)
            break
    assert expected is not None and expected[0] == 2
    with pytest.raises(ParameterError) as caught:
        spec.PointBuilder(base, "sliding", {}, {"mass": mass, "contact_radius": radius})
    error, oracle = caught.value, expected[1]
    assert error.name == oracle.name == "contact_radius"
    assert (error.value, error.allowed) == (oracle.value, oracle.allowed)
    assert error.hint == f"{oracle.hint}; at sweep point 2 (mass=1, contact_radius={radii[2]:g})"


# ---- fit: a long record says what happens --------------------------------------------------


def test_a_fit_of_a_million_samples_says_what_it_does(tmp_path: Path) -> None:
    """A record of 10^6 rows (23 MB): the command says that it reads it, then that it
    fits it, and stops at SIGTERM (not a hang without a word)."""
    time_s = np.linspace(0.0, 20.0, 1_000_000)
    spin = -5.0 * np.exp(-0.1 * time_s) + 0.01 * np.sin(37.0 * time_s)
    data = tmp_path / "long.csv"
    np.savetxt(data, np.column_stack([time_s, spin]), delimiter=",", header="time,spin",
               comments="", fmt="%.9g")  # fmt: skip
    command = [
        str(CELTSTONE), "fit", str(data), "--body", "kane_levinson_1982",
        "--column", "omega3=spin", "--free", "friction_coefficient", "--set", "omega3=-5",
    ]  # fmt: skip
    with subprocess.Popen(
        command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    ) as process:
        assert process.stderr is not None
        said = [process.stderr.readline(), process.stderr.readline()]  # blocks until said
        process.send_signal(signal.SIGTERM)
        rest = process.stderr.read()
        process.wait(WAIT)
    assert said[0].startswith(f"celtstone: reading {data} (23 MB)"), said
    assert said[1] == "celtstone: fitting the sliding model to 1000000 samples ...\n", said
    assert process.returncode == 143, rest
    assert "Traceback" not in rest
