"""The explorer's page on the Python side (no browser): a notebook renders it, a slider
change redraws from the newest run, a refused input keeps the last plot, a pinned run is
overlaid, and the NetCDF download is a run ``celtstone plot`` reads."""

from __future__ import annotations

import json
import shlex
import threading
import time
from collections.abc import Callable
from importlib import resources
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pytest

import celtstone as cs
from celtstone.cli.main import main

pn = pytest.importorskip("panel")

from celtstone.explorer import Inputs, Runner, app, command_line  # noqa: E402
from celtstone.explorer.app import Explorer  # noqa: E402
from celtstone.explorer.inputs import KINDS  # noqa: E402
from celtstone.simulation.models import SETTINGS, settings_of  # noqa: E402

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
    # what the command line warns of after this run (the paper's static friction load
    # beyond Coulomb's bound), up to the fix it names in its own words
    assert main(["run", "--model", "sliding", "--t-end", "4", "--json"]) == 0
    cli_warning = capsys.readouterr().err.strip().removeprefix("celtstone: warning: ")
    assert cli_warning.startswith("the friction force reached")
    assert cli_warning.split("; use ")[0] in explorer.status.object
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
    path.write_bytes(explorer._dataset_bytes("run.nc").getvalue())
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
        assert not _has_figures(explorer.layout)
        pn.state._on_load(document)  # the browser has shown the page
        assert explorer.runner.generation == 1
        assert _has_figures(explorer.layout)
    if explorer._callback is not None:
        explorer._callback.stop()
    _settle(explorer)
    assert explorer.outcome is not None and explorer.outcome.trajectory is not None


def _has_figures(layout: object) -> bool:
    """Whether ``layout``'s rendered objects hold the stone and the three plots."""
    return len(layout.select(pn.pane.Bokeh)) == 4  # type: ignore[attr-defined]


@pytest.mark.parametrize("kind", list(KINDS))
def test_each_model_shows_its_own_settings_with_their_declared_words(kind: str) -> None:
    """The contact card shows exactly the settings of the chosen model (read from the
    models' declarations, so a new setting gets a control), each with the words of its
    declaration as the CLI's --help gives them."""
    explorer = Explorer(Inputs(kind=kind), run_first=False)
    shown = {name for name, widget in explorer.settings.items() if widget.visible}
    assert shown == set(settings_of(kind))
    for name, widget in explorer.settings.items():
        words = SETTINGS[name].help()
        if "description" in widget.param:
            assert widget.description == words
        else:  # a slider: the note is an icon beside it
            icons = explorer._settings_shown[name].select(pn.widgets.TooltipIcon)
            assert [icon.value for icon in icons] == [words]
    if kind == "sliding":  # the contact the issue names, each a control of this model
        assert shown >= {
            "friction_coefficient",
            "contact_radius",
            "elastic_modulus",
            "poisson_ratio",
            "friction_law",
            "contact_shape",
            "friction_load",
            "rolling_resistance",
        }


def test_the_stone_card_shows_the_published_inertia_and_radii_of_curvature() -> None:
    """Kane & Levinson's ellipsoid (semi-axes 0.20, 0.03, 0.02 m; I11 = 2e-4, I22 = 1.6e-3,
    I33 = 1.7e-3, I12 = -2e-5 kg m², their paper as in ../shared/references.md): the rest
    contact's radii of curvature of an ellipsoid are a²/c = 2 m and b²/c = 0.045 m."""
    explorer = Explorer(Inputs(), run_first=False)
    explorer._changed()
    words = explorer.body_numbers.object
    assert "mass 1 kg" in words
    assert "I11, I22, I33, I12 = 0.0002, 0.0016, 0.0017, -2e-05 kg m²" in words
    assert "a²/c = 2 m" in words and "b²/c = 0.045 m" in words
    explorer.runner.stop()


def test_a_design_slider_rebuilds_the_stone() -> None:
    """The design form's mass slider: the stone shown and run is the design's (inertia
    scales with mass at fixed dimensions, so I11 doubles when the mass does)."""
    explorer = Explorer(Inputs(body_source="design", t_end=1.0))
    _settle(explorer)
    before = explorer.outcome
    assert before is not None and before.trajectory is not None
    mass = explorer.design["mass"].value
    explorer.design["mass"].value = 2 * mass
    _settle(explorer)
    after = explorer.outcome
    assert after is not None and after.trajectory is not None
    inertia = [json.loads(o.trajectory.dataset.attrs["body_inertia"]) for o in (before, after)]
    assert after.trajectory.dataset.attrs["body_mass"] == pytest.approx(2 * mass)
    assert inertia[1][0][0] == pytest.approx(2 * inertia[0][0][0], rel=1e-12)


def test_an_uploaded_body_file_is_refused_with_the_command_lines_message(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The page's upload goes through ``celtstone run --body FILE``'s checks: a broken
    file gets the CLI's one line (naming the user's file), the last good run stays; a
    good file is run."""
    broken = tmp_path / "mine.toml"
    broken.write_text("[body]\nmass = -1.0\n")
    assert main(["run", "--body", str(broken)]) == 2
    cli = capsys.readouterr().err.strip().removeprefix("celtstone: error: ")
    explorer = Explorer(Inputs(t_end=1.0))
    _settle(explorer)
    shown = explorer.outcome
    explorer.body_file.filename = "mine.toml"
    explorer.body_file.value = broken.read_bytes()
    explorer.body_source.value = "file"
    assert explorer.message.visible
    assert cli.replace(str(broken), "mine.toml") in explorer.message.object
    assert explorer.outcome is shown
    good = tmp_path / "kane_levinson_1982.toml"
    good.write_bytes(
        resources.files("celtstone.bodies").joinpath("data/kane_levinson_1982.toml").read_bytes()
    )
    explorer.body_file.filename = good.name
    explorer.body_file.value = good.read_bytes()
    _settle(explorer)
    assert not explorer.message.visible
    assert explorer.outcome is not shown and explorer.outcome.trajectory is not None
    assert (
        explorer.outcome.trajectory.summary()["reversal_times"]
        == (shown.trajectory.summary()["reversal_times"])
    )


def test_the_downloads_are_the_command_lines_files_and_leave_nothing_behind(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """NetCDF and CSV hold the run that ``celtstone run --out`` writes for the same
    inputs; the figure is a whole PNG and an SVG document; no file is left on disk."""
    import pandas as pd
    import xarray as xr

    explorer = Explorer(Inputs(t_end=2.0))
    _settle(explorer)
    scratch = tmp_path / "scratch"
    scratch.mkdir()
    monkeypatch.setattr("tempfile.tempdir", str(scratch))
    offered = {  # what the page's download buttons give
        button.filename: button.callback().getvalue()
        for button in explorer.downloads.select(pn.widgets.FileDownload)  # type: ignore[attr-defined]
    }
    assert set(offered) == {"run.nc", "run.csv", "run.png", "run.svg"}
    netcdf, csv, png, svg = (offered[f"run.{kind}"] for kind in ("nc", "csv", "png", "svg"))
    assert list(scratch.iterdir()) == []
    words = shlex.split(command_line(explorer.outcome.inputs) or "")
    for suffix, content in ((".nc", netcdf), (".csv", csv)):
        written = tmp_path / f"cli{suffix}"
        assert main([*words[1:], "--out", str(written)]) == 0
        downloaded = tmp_path / f"page{suffix}"
        downloaded.write_bytes(content)
        if suffix == ".nc":
            with xr.open_dataset(written) as cli, xr.open_dataset(downloaded) as page:
                assert set(page.data_vars) == set(cli.data_vars)
                for name in ("time", "spin", "energy", "tilt"):
                    np.testing.assert_array_equal(page[name].values, cli[name].values)
        else:
            cli_rows = pd.read_csv(written, comment="#")
            page_rows = pd.read_csv(downloaded, comment="#")
            assert list(page_rows.columns) == list(cli_rows.columns)
            for name in ("time", "spin", "energy"):
                np.testing.assert_array_equal(page_rows[name], cli_rows[name])
    capsys.readouterr()
    assert png.startswith(b"\x89PNG\r\n\x1a\n") and png.endswith(b"IEND\xaeB`\x82")
    assert ElementTree.fromstring(svg).tag == "{http://www.w3.org/2000/svg}svg"


def test_the_play_button_moves_the_stone_through_the_run() -> None:
    explorer = Explorer(Inputs(t_end=4.0))
    _settle(explorer)
    explorer.player.value = 0
    start = list(explorer.stone_source.data["xs"])
    explorer.player.value = app.PLAYER_FRAMES // 2
    assert explorer.time_cursor.value == pytest.approx(2.0)
    assert explorer.stone_source.data["xs"] != start
    explorer.player.value = app.PLAYER_FRAMES
    assert explorer.time_cursor.value == pytest.approx(explorer.time_cursor.end)


def test_a_run_whose_loop_has_not_started_says_it_may_be_compiling(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Before the compiled loop reports progress, the run is loading or compiling its
    model: the page says so, then shows t / t_end once the loop runs."""
    monkeypatch.setattr(app, "SLOW_RUN", 0.0)
    looping = threading.Event()
    release = threading.Event()

    def slow(prepared: object, progress: Callable[[float], None]) -> cs.Trajectory:
        looping.wait(WAIT)  # as the compile before the loop: no progress reported
        while not release.is_set():
            progress(0.125)
            time.sleep(0.005)
        raise cs.ParameterError("t_end", 0.5, "a test's stand-in run, released")

    explorer = Explorer(Inputs(t_end=1.0), run_first=False)
    explorer.runner = Runner(slow)
    explorer.t_end.value = 0.5
    explorer.poll()
    assert "compiled" in explorer.status.object and "celtstone compile" in explorer.status.object
    looping.set()
    deadline = time.monotonic() + WAIT
    while "0.125 of 0.5 s" not in explorer.status.object:
        assert time.monotonic() < deadline
        explorer.poll()
        time.sleep(0.01)
    release.set()
    explorer.runner.wait(explorer.runner.generation, WAIT)


def test_explore_renders_in_a_jupyter_notebook() -> None:
    """``celtstone.explore()`` as a notebook cell's value, run by a Jupyter kernel: the
    cell's output is the page (HTML with Panel's mime data), with no error."""
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    notebook = nbformat.v4.new_notebook()
    notebook.cells = [
        nbformat.v4.new_code_cell("import celtstone as cs\ncs.explore(t_end=1.0)"),
    ]
    nbclient.NotebookClient(notebook, timeout=int(WAIT), kernel_name="python3").execute()
    outputs = notebook.cells[0].outputs
    assert [output.output_type for output in outputs if output.output_type == "error"] == []
    shown = [output for output in outputs if output.output_type == "execute_result"]
    assert len(shown) == 1
    # Panel's output: the page's HTML, and the id by which Jupyter's Panel extension
    # links it to the kernel's live objects
    assert {"text/html", "application/vnd.holoviews_exec.v0+json"} <= set(shown[0].data)
    assert "spin it the wrong way" in shown[0].data["text/html"]  # the page's own controls
