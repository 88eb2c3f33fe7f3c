"""The explorer's page on the Python side (no browser): a notebook renders it, a slider
change redraws from the newest run, a refused input keeps the last plot, a pinned run is
overlaid, and the NetCDF download is a run ``celtstone plot`` reads."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from pathlib import Path

import pytest

import celtstone as cs
from celtstone.cli.main import main

pn = pytest.importorskip("panel")

from celtstone.explorer import Inputs  # noqa: E402
from celtstone.explorer.app import Explorer  # noqa: E402

WAIT = 120.0  # s; a bound on waiting, not a speed requirement


def _settle(explorer: Explorer) -> None:
    """Poll as the page's periodic callback does until the newest inputs' run is shown."""
    deadline = time.monotonic() + WAIT
    while time.monotonic() < deadline:
        explorer.poll()
        shown = explorer.outcome
        if shown is not None and shown.generation == explorer.runner.generation:
            return
        time.sleep(0.01)
    raise AssertionError("no result")


def test_notebook_renders_the_explorer() -> None:
    explorer = cs.explore(t_end=1.0)
    bundle = explorer._repr_mimebundle_()
    data = bundle[0] if isinstance(bundle, tuple) else bundle
    assert any("html" in kind or "holoviews" in kind for kind in data)
    root = explorer.layout.get_root()
    assert root is not None
    if explorer._callback is not None:
        explorer._callback.stop()


def test_friction_slider_redraws_with_the_cli_reversal(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    explorer = Explorer(Inputs(kind="sliding", t_end=4.0))
    _settle(explorer)
    explorer._pin()
    explorer.settings["friction_coefficient"].value = 0.15
    _settle(explorer)
    reference = cs.simulate(
        cs.SlidingModel(friction_coefficient=0.15),
        cs.load_body("kane_levinson_1982"),
        cs.InitialState(),
        4.0,
    ).summary()["reversal_times"]
    assert explorer.outcome is not None and explorer.outcome.trajectory is not None
    assert explorer.outcome.trajectory.summary()["reversal_times"] == reference
    assert list(explorer.reversal_source.data["time"]) == reference
    # the pinned f = 0.35 run and this one: two different curves on the spin plot
    pinned = explorer.sources["pinned_spin"].data["value"]
    current = explorer.sources["spin"].data["value"]
    assert len(pinned) == len(current) > 0 and any(pinned != current)

    shown = explorer.outcome
    explorer.settings["friction_coefficient"].value = -1.0
    explorer.poll()
    assert explorer.message.visible
    assert "friction_coefficient = -1.0 is not allowed: expected a number >= 0" in (
        explorer.message.object
    )
    assert explorer.outcome is shown and len(explorer.sources["spin"].data["time"]) > 0

    path = tmp_path / "run.nc"
    path.write_bytes(explorer._dataset_bytes(".nc").getvalue())
    assert main(["plot", str(path), "--out", str(tmp_path / "run.png")]) == 0
    assert (tmp_path / "run.png").stat().st_size > 0
    capsys.readouterr()


def test_wrong_and_right_way_buttons_pick_the_senses_that_do_and_do_not_reverse() -> None:
    """Kane & Levinson's stone reverses spun at ω3 = -5 rad/s and not at +5 (their paper,
    ../shared/references.md); the buttons read the sense from linear stability."""
    explorer = Explorer(Inputs(t_end=5.0))
    _settle(explorer)
    explorer.omega[2].value = 3.0
    explorer._spin_sense(wrong=True)
    assert explorer.omega[2].value == -3.0
    _settle(explorer)
    assert explorer.outcome is not None and explorer.outcome.trajectory is not None
    assert explorer.outcome.trajectory.summary()["reversal_times"]
    explorer._spin_sense(wrong=False)
    assert explorer.omega[2].value == 3.0
    _settle(explorer)
    assert not explorer.outcome.trajectory.summary()["reversal_times"]


def test_the_time_cursor_moves_the_stone() -> None:
    explorer = Explorer(Inputs(t_end=3.0))
    _settle(explorer)
    explorer.time_cursor.value = 0.0
    start = list(explorer.stone_source.data["xs"])
    explorer.time_cursor.value = 2.5
    assert start and explorer.stone_source.data["xs"] != start
    assert "t = 2.5 s" in explorer.cursor_words.object


def test_a_slow_run_shows_its_progress_and_stops(monkeypatch: pytest.MonkeyPatch) -> None:
    from celtstone.explorer import Runner, app

    monkeypatch.setattr(app, "SLOW_RUN", 0.0)  # any run counts as slow here
    release = threading.Event()
    stopped: list[bool] = []

    def slow(prepared: object, progress: Callable[[float], None]) -> cs.Trajectory:
        try:
            while not release.is_set():
                progress(0.25)
                time.sleep(0.005)
        except BaseException:
            stopped.append(True)
            raise
        raise AssertionError("released: not expected")

    explorer = Explorer(Inputs(t_end=1.0), run_first=False)
    explorer.runner = Runner(slow)
    explorer.t_end.value = 0.5
    deadline = time.monotonic() + WAIT
    while not (explorer.progress.visible and explorer.progress.value == 50):
        assert time.monotonic() < deadline
        explorer.poll()
        time.sleep(0.01)
    assert explorer.stop_button.visible and "0.25 of 0.5 s" in explorer.status.object
    explorer._stop()
    while not stopped:
        assert time.monotonic() < deadline
        time.sleep(0.01)
    explorer.poll()
    assert explorer.outcome is None and not explorer.progress.visible
    release.set()


def test_a_served_page_runs_once_shown_and_sends_its_figures_then() -> None:
    """In a served session the first run and the figures wait for the page to be shown,
    so that its controls answer first; once shown, the run starts and the figures come."""
    from unittest.mock import MagicMock

    from bokeh.document import Document
    from panel.io.state import set_curdoc

    document = Document()
    document._session_context = lambda: MagicMock()  # what a served page's document has
    with set_curdoc(document):
        explorer = Explorer(Inputs(t_end=1.0))
        explorer.layout.get_root(document)
        assert explorer.runner.generation == 0 and explorer.outcome is None
        assert "computing the first run" in explorer.status.object
        assert not _has_figure(explorer.layout, explorer.spin_figure)
        pn.state._on_load(document)  # the browser has shown the page
        assert explorer.runner.generation == 1
        assert _has_figure(explorer.layout, explorer.spin_figure)
    if explorer._callback is not None:
        explorer._callback.stop()
    _settle(explorer)
    assert explorer.outcome is not None and explorer.outcome.trajectory is not None


def _has_figure(layout: object, figure: object) -> bool:
    """Whether ``figure`` is in ``layout``'s rendered objects."""
    return any(shown is figure for shown in layout.select(type(figure)))  # type: ignore[attr-defined]
