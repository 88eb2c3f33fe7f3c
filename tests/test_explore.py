"""The live explorer without a browser: validation through the CLI's checks, the run /
cancel / stale-result logic, the recipes it hands out, and the page's Python side."""

from __future__ import annotations

import json
import shlex
import threading
import time
from collections.abc import Callable
from importlib import resources
from pathlib import Path

import pytest

import celtstone as cs
from celtstone.cli.main import main
from celtstone.explorer import Inputs, Runner, command_line, prepare, python_snippet
from celtstone.explorer.inputs import DESIGN_BODY, Prepared, body_from_file, design_defaults

WAIT = 120.0  # s; a generous bound on waiting for a result, not a speed requirement


def _cli_error(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    assert main(argv) == 2
    return capsys.readouterr().err.strip().removeprefix("celtstone: error: ")


@pytest.mark.parametrize(
    ("inputs", "argv"),
    [
        (
            Inputs(kind="sliding", settings={"friction_coefficient": -1.0}),
            ["run", "--model", "sliding", "--friction-coefficient", "-1"],
        ),
        (Inputs(t_end=-2.0), ["run", "--t-end", "-2"]),
        (
            Inputs(kind="sliding", settings={"rolling_resistance": 0.5}),
            ["run", "--model", "sliding", "--rolling-resistance", "0.5"],
        ),
        (Inputs(body="no_such_stone"), ["run", "--body", "no_such_stone"]),
    ],
)
def test_refused_with_the_command_lines_message(
    inputs: Inputs, argv: list[str], capsys: pytest.CaptureFixture[str]
) -> None:
    """One validation path: the page's refusal is the CLI's one line, word for word."""
    with pytest.raises(cs.ParameterError) as refused:
        prepare(inputs)
    assert str(refused.value) == _cli_error(capsys, argv)


def test_settings_the_model_does_not_have_are_not_sent() -> None:
    """The rolling model is given none of the sliding settings the page still holds."""
    inputs = Inputs(kind="rolling", settings={"friction_coefficient": 0.15})
    assert isinstance(prepare(inputs).model, cs.RollingModel)
    assert "--friction-coefficient" not in (command_line(inputs) or "")


def test_design_form_starts_at_the_shipped_design() -> None:
    design = cs.bodies.load_design(DESIGN_BODY)
    body = prepare(Inputs(body_source="design")).body
    assert body.mass == pytest.approx(design.mass)
    assert design_defaults()["misalignment"] == design.misalignment


def test_uploaded_body_file_goes_through_the_loader(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A shipped file uploaded gives the shipped body; a broken one the loader's message
    naming the user's file; the temporary copy is gone afterwards."""
    monkeypatch.setattr("tempfile.tempdir", str(tmp_path))
    text = resources.files("celtstone.bodies").joinpath("data/kane_levinson_1982.toml")
    body = body_from_file(text.read_bytes(), "kane_levinson_1982.toml")
    shipped = cs.load_body("kane_levinson_1982")
    assert body.inertia == shipped.inertia and body.mass == shipped.mass
    with pytest.raises(cs.ParameterError, match=r"mine\.toml") as refused:
        body_from_file(b"mass = 'heavy'\n", "mine.toml")
    assert "\n" not in str(refused.value)
    assert list(tmp_path.iterdir()) == []


def _slow_run(
    started: list[float], cancelled: list[float], release: threading.Event
) -> Callable[[Prepared, Callable[[float], None]], cs.Trajectory]:
    """A stand-in for ``simulate``: reports progress until released, then runs for real."""

    def run(prepared: Prepared, progress: Callable[[float], None]) -> cs.Trajectory:
        started.append(prepared.t_end)  # the run's name in these tests
        try:
            while not release.is_set():
                progress(0.0)
                time.sleep(0.005)
        except BaseException:
            cancelled.append(prepared.t_end)
            raise
        return cs.simulate(prepared.model, prepared.body, prepared.initial_state, prepared.t_end)

    return run


def test_a_change_cancels_the_run_in_flight_and_only_the_newest_is_shown() -> None:
    started: list[float] = []
    cancelled: list[float] = []
    release = threading.Event()
    runner = Runner(_slow_run(started, cancelled, release))
    first = runner.submit(Inputs(t_end=1.0))
    second = runner.submit(Inputs(t_end=2.0))
    deadline = time.monotonic() + WAIT
    while cancelled != [1.0] and time.monotonic() < deadline:
        time.sleep(0.005)
    assert cancelled == [1.0]  # the superseded run was stopped through its progress callback
    release.set()
    outcome = runner.wait(second, WAIT)
    assert outcome is not None and outcome.generation == second > first
    assert outcome.inputs.t_end == 2.0
    assert float(outcome.trajectory.dataset["time"][-1]) == pytest.approx(2.0)
    assert runner.take() is None


def test_a_stale_result_is_dropped() -> None:
    """A run that finishes after newer inputs came is never handed out."""
    gate = threading.Event()

    def run(prepared: Prepared, progress: Callable[[float], None]) -> cs.Trajectory:
        if prepared.t_end == 1.0:
            gate.wait(WAIT)  # ignores the cancel: finishes late, as a compiled loop would
        return cs.simulate(prepared.model, prepared.body, prepared.initial_state, prepared.t_end)

    runner = Runner(run)
    runner.submit(Inputs(t_end=1.0))
    newest = runner.submit(Inputs(t_end=0.5))
    outcome = runner.wait(newest, WAIT)
    assert outcome is not None and outcome.inputs.t_end == 0.5
    gate.set()
    deadline = time.monotonic() + WAIT
    while runner.dropped == 0 and time.monotonic() < deadline:
        time.sleep(0.005)
    assert runner.dropped == 1
    assert runner.take() is None


def test_refused_input_starts_nothing_and_keeps_the_run_in_flight() -> None:
    started: list[float] = []
    cancelled: list[float] = []
    release = threading.Event()
    runner = Runner(_slow_run(started, cancelled, release))
    good = runner.submit(Inputs(t_end=0.5))
    with pytest.raises(cs.ParameterError):
        runner.submit(Inputs(t_end=0.0))
    assert runner.generation == good
    release.set()
    outcome = runner.wait(good, WAIT)
    assert outcome is not None and cancelled == []


def test_stop_ends_the_run_and_hands_out_nothing() -> None:
    started: list[float] = []
    cancelled: list[float] = []
    runner = Runner(_slow_run(started, cancelled, threading.Event()))
    runner.submit(Inputs())
    while not started:
        time.sleep(0.005)
    assert runner.stop()
    deadline = time.monotonic() + WAIT
    while not cancelled and time.monotonic() < deadline:
        time.sleep(0.005)
    assert cancelled == [10.0] and runner.running() is None and runner.take() is None


@pytest.mark.parametrize("kind", ["rolling", "sliding"])
def test_command_line_and_snippet_reproduce_the_run(
    kind: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """The handed-out command and Python give the explorer's first reversal time."""
    settings = {"friction_coefficient": 0.15} if kind == "sliding" else {}
    inputs = Inputs(kind=kind, t_end=4.0, settings=settings)
    runner = Runner()
    outcome = runner.wait(runner.submit(inputs), WAIT)
    assert outcome is not None and outcome.trajectory is not None
    shown = outcome.trajectory.summary()["reversal_times"]
    words = shlex.split(command_line(inputs) or "")
    assert words[:2] == ["celtstone", "run"]
    assert main([*words[1:], "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["reversal_times"] == shown
    scope: dict[str, object] = {}
    exec(python_snippet(inputs).replace("print(", "found = ("), scope)
    assert scope["found"] == shown


def test_serve_without_panel_names_the_extra(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "panel" else real(name, *a)
    )
    assert main(["serve", "--no-browser"]) == 2
    error = capsys.readouterr().err.strip()
    assert "celtstone[explore]" in error and "\n" not in error


def test_serve_binds_localhost_and_says_when_widened(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    panel = pytest.importorskip("panel")
    served: list[dict[str, object]] = []
    monkeypatch.setattr(panel, "serve", lambda pages, **options: served.append(options))
    assert main(["serve", "--no-browser", "--port", "5123"]) == 0
    assert served[-1]["address"] == "127.0.0.1" and served[-1]["show"] is False
    assert "other machines" not in capsys.readouterr().err
    assert main(["serve", "--no-browser", "--host", "0.0.0.0"]) == 0
    assert served[-1]["address"] == "0.0.0.0"
    assert "other machines" in capsys.readouterr().err


LONG_RUN = 1.0e6  # s of rolling: ~3.6e8 steps of K&L's stone, many minutes of computing


def _long_run(prepared: Prepared, progress: Callable[[float], None]) -> cs.Trajectory:
    """The page's run with few samples (its output fits in memory) and no step limit
    (the default ends a rolling run after ~3e4 s: 1e7 steps)."""
    return cs.simulate(
        prepared.model,
        prepared.body,
        prepared.initial_state,
        prepared.t_end,
        n_samples=1001,
        max_steps=10**12,
        progress=progress,
    )


def _start_long_run(runner: Runner) -> list[threading.Thread]:
    """Submit a long run and wait for its compiled loop; the threads it started."""
    before = set(threading.enumerate())
    long = runner.submit(Inputs(t_end=LONG_RUN))
    deadline = time.monotonic() + WAIT
    while (progress := runner.running()) is None or not progress.looping:
        assert time.monotonic() < deadline, "the long run's loop never started"
        time.sleep(0.01)
    started = [thread for thread in threading.enumerate() if thread not in before]
    assert f"celtstone-explore-{long}" in {thread.name for thread in started}
    assert len(started) >= 2  # the run's worker and its compiled loop's thread
    return started


def _wait_ended(threads: list[threading.Thread]) -> None:
    deadline = time.monotonic() + WAIT  # the loop alone would need many times this
    while any(thread.is_alive() for thread in threads):
        assert time.monotonic() < deadline, "the stopped run's compiled loop runs on"
        time.sleep(0.05)


def test_a_superseded_run_stops_inside_its_compiled_loop() -> None:
    """A change ends the run in flight inside its compiled loop, not only on the page:
    the superseded run's worker thread and the loop's own thread both end, long before
    the loop could have reached its t_end, and nothing of that run is handed out."""
    runner = Runner(_long_run)
    threads = _start_long_run(runner)
    newest = runner.submit(Inputs(t_end=0.5))
    outcome = runner.wait(newest, WAIT)
    assert outcome is not None and outcome.inputs.t_end == 0.5
    _wait_ended(threads)
    assert runner.take() is None and runner.dropped == 0  # stopped, not finished and dropped


def test_the_stop_button_ends_the_compiled_loop() -> None:
    runner = Runner(_long_run)
    threads = _start_long_run(runner)
    assert runner.stop()
    _wait_ended(threads)
    assert runner.running() is None and runner.take() is None and runner.dropped == 0
