"""The explorer's page: Panel controls built from the models' declarations, Bokeh plots.

Panel and Bokeh are imported here only, when an explorer is made (``celtstone serve``,
:func:`celtstone.explorer`). Every control change makes an :class:`~.inputs.Inputs` and
hands it to a :class:`~.runner.Runner`; a periodic callback of the page's own session
takes finished runs and draws them (Bokeh documents may only change on their session's
thread), so a figure always shows the newest inputs' run. A served page is sent
without its figures and before its first run: both follow once the browser shows it, so
that its controls answer first.
"""

from __future__ import annotations

import io
import math
import tempfile
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
import panel as pn
from bokeh.models import ColumnDataSource, Span  # type: ignore[attr-defined]

from celtstone.bodies import Ellipsoid, list_bodies
from celtstone.errors import CeltstoneError, ParameterError
from celtstone.explorer.controls import (
    DESIGN_LABELS,
    DESIGN_TRAVEL,
    noted,
    parameter_label,
    setting_widget,
)
from celtstone.explorer.inputs import (
    DESIGN_FIELDS,
    KINDS,
    Inputs,
    command_line,
    design_defaults,
    prepare,
    python_snippet,
)
from celtstone.explorer.notes import NOTES
from celtstone.explorer.runner import FinishedRun, Progress, Runner
from celtstone.simulation import schema
from celtstone.simulation.models import SETTINGS, settings_of

__all__ = ["POLL_MS", "Explorer", "verdict"]

POLL_MS = 50  # ms between looks for a finished run: well under the targets' 0.5 s
SLOW_RUN = 1.0  # s; a run still going after this shows its progress bar and why
PLAYER_FRAMES = 200  # frames the play button steps the time cursor through
PLAYER_INTERVAL_MS = 100  # ms between them: a run plays in 20 s, whatever its t_end


def verdict(outcome: FinishedRun) -> str:
    """The run in one line: "reverses at 2.86 s; 3 reversals in 20 s"."""
    if outcome.trajectory is None:
        return f"the run failed: {outcome.error}"
    trajectory = outcome.trajectory
    summary = trajectory.summary()
    times = summary["reversal_times"]
    t_stop = summary["t_stop"]
    if times:
        count = len(times)
        plural = "s" if count != 1 else ""
        text = f"reverses at {times[0]:.3g} s; {count} reversal{plural} in {t_stop:g} s"
    else:
        last = float(trajectory.samples.values("spin")[-1])  # at the stop (spin_final: t_end)
        spins = f"{summary['spin_initial']:.3g} -> {last:.3g} rad/s"
        text = f"no reversal in {t_stop:g} s (spin {spins})"
    if not trajectory.ok:
        text += f"; stopped early: {trajectory.message}"
    return text


class Explorer:
    """The live explorer: controls, plots, verdict, compare and downloads.

    Parameters
    ----------
    inputs : Inputs, optional
        The first state of the controls (default: K&L's stone spun the wrong way, rolling).
    run_first : bool
        Start a run of the first inputs: at once, or in a served page once the browser
        shows it (the controls answer before the first verdict).
    """

    def __init__(self, inputs: Inputs | None = None, run_first: bool = True) -> None:
        self.runner = Runner()
        self.outcome: FinishedRun | None = None
        self.pinned: FinishedRun | None = None
        first = inputs or Inputs()
        self._build_controls(first)
        self._build_plots()
        self._build_outputs()
        figures: Any
        if _served():  # most of the page's Bokeh models: sent once the page is shown
            figures = pn.param.ParamFunction(
                lambda: self._figures(), defer_load=True, sizing_mode="stretch_width"
            )
        else:
            figures = self._figures()
        self.layout = pn.Row(
            pn.Column(*self._control_cards, width=400, scroll=True, sizing_mode="stretch_height"),
            pn.Column(
                self.message,
                self.verdict,
                pn.Row(self.progress, self.stop_button, self.pin_button, self.unpin_button),
                self.status,
                pn.Row(self.player, self.time_cursor, sizing_mode="stretch_width"),
                self.cursor_words,
                figures,
                pn.pane.Markdown(NOTES["plots"], styles={"font-size": "0.9em"}),
                self.downloads,
                sizing_mode="stretch_width",
            ),
            sizing_mode="stretch_both",
        )
        self._callback: Any = None
        for widget in self._watched:
            widget.param.watch(self._changed, "value")
        if run_first:
            if _served():  # the page first, usable at once; the first run once it is shown
                self.status.object = "computing the first run …"
                pn.state.onload(self._changed)
            else:
                self._changed()

    # -- controls ---------------------------------------------------------------------
    def _build_controls(self, first: Inputs) -> None:
        bodies = list(list_bodies())
        self.body_source = pn.widgets.RadioButtonGroup(
            label="stone", options=["shipped", "file", "design"], value=first.body_source
        )
        self.body = pn.widgets.Select(label="shipped body", options=bodies, value=first.body)
        self.body_file = pn.widgets.FileInput(accept=".toml", multiple=False)
        defaults = {**design_defaults(), **first.design}
        self.design = {
            name: pn.widgets.EditableFloatSlider(
                label=DESIGN_LABELS[name],
                start=DESIGN_TRAVEL[name][0],
                end=DESIGN_TRAVEL[name][1],
                step=DESIGN_TRAVEL[name][2],
                value=defaults[name],
                format="0[.]0000",
                css_classes=[f"cs-design-{name}"],
            )
            for name in DESIGN_FIELDS
        }
        self.body_numbers = pn.pane.Markdown("", styles={"font-size": "0.85em"})
        self.omega = _component_inputs("omega", ("ω1", "ω2", "ω3"), "rad/s", first.omega)
        self.angles = _component_inputs("euler_angles", ("α", "β"), "deg", first.euler_angles)
        self.t_end = pn.widgets.FloatInput(
            label=parameter_label("t_end"),
            value=first.t_end,
            description=schema.PARAMETERS["t_end"].help(),
            css_classes=["cs-t_end"],
        )
        self.wrong_way = pn.widgets.Button(label="spin it the wrong way", color="warning")
        self.right_way = pn.widgets.Button(label="spin it the right way", color="success")
        self.wrong_way.on_click(lambda event: self._spin_sense(wrong=True))
        self.right_way.on_click(lambda event: self._spin_sense(wrong=False))
        self.kind = pn.widgets.RadioButtonGroup(
            label="model", options=list(KINDS), value=first.kind
        )
        self.settings = {name: setting_widget(name) for name in SETTINGS}
        for name, value in first.settings.items():
            self.settings[name].value = value
        self._settings_shown = {
            name: noted(widget, SETTINGS[name].help()) for name, widget in self.settings.items()
        }
        main = (
            "friction_coefficient",
            "contact_radius",
            "friction_law",
            "contact_shape",
            "friction_load",
            "rolling_resistance",
            "elastic_modulus",
            "poisson_ratio",
        )
        more = [name for name in SETTINGS if name not in main]
        self.kind.param.watch(lambda event: self._show_settings(), "value")
        self._control_cards = [
            pn.Card(
                self.body_source,
                self.body,
                self.body_file,
                *self.design.values(),
                self.body_numbers,
                pn.pane.Markdown(NOTES["stone"]),
                title="The stone",
            ),
            pn.Card(
                pn.Row(*self.omega),
                pn.Row(*self.angles),
                pn.Row(self.wrong_way, self.right_way),
                self.t_end,
                pn.pane.Markdown(NOTES["start"]),
                title="The start",
            ),
            pn.Card(
                self.kind,
                *(self._settings_shown[name] for name in main),
                pn.Card(
                    *(self._settings_shown[name] for name in more),
                    title="more settings",
                    collapsed=True,
                ),
                pn.pane.Markdown(NOTES["contact"]),
                title="The contact",
            ),
        ]
        self._watched = [
            self.body_source,
            self.body,
            self.body_file,
            *self.design.values(),
            *self.omega,
            *self.angles,
            self.t_end,
            self.kind,
            *self.settings.values(),
        ]
        self._show_settings()

    def _show_settings(self) -> None:
        """Show only the settings the chosen model has (``models.settings_of``)."""
        own = set(settings_of(self.kind.value))
        for name, widget in self.settings.items():
            widget.visible = self._settings_shown[name].visible = name in own
        source = self.body_source.value
        self.body.visible = source == "shipped"
        self.body_file.visible = source == "file"
        for widget in self.design.values():
            widget.visible = source == "design"

    def inputs(self) -> Inputs:
        """The controls' values now, unvalidated (numbers as floats, as the command line
        parses them, so that a refusal reads the same; an emptied box is None)."""
        own = set(settings_of(self.kind.value))
        return Inputs(
            body_source=self.body_source.value,
            body=self.body.value,
            body_file=self.body_file.value,
            body_file_name=self.body_file.filename or "body.toml",
            design={name: _real(widget.value) for name, widget in self.design.items()},
            kind=self.kind.value,
            omega=tuple(_real(w.value) for w in self.omega),
            euler_angles=tuple(_real(w.value) for w in self.angles),
            t_end=_real(self.t_end.value),
            settings={name: _real(w.value) for name, w in self.settings.items() if name in own},
        )

    def _spin_sense(self, wrong: bool) -> None:
        """Set ω so that ω·n0 has the sense whose steady spin is unstable (wrong) or stable
        (right), read from the rolling model's linear stability (``spin_stability``)."""
        from celtstone.stability import spin_stability

        try:
            body = prepare(self.inputs()).body
            spin = abs(self.omega[2].value or 0.0) or 5.0
            stability = spin_stability(body, [spin, -spin])
        except CeltstoneError as error:
            self._refused(str(error))
            return
        growth = np.maximum(stability.growth_rate_pitch, stability.growth_rate_roll)
        unstable = spin if growth[0] >= growth[1] else -spin
        self.omega[0].value = 0.0
        self.omega[1].value = 0.0
        self.omega[2].value = unstable if wrong else -unstable

    # -- running ----------------------------------------------------------------------
    def _changed(self, *events: Any) -> None:
        self._show_settings()
        try:
            inputs = self.inputs()
            prepared = prepare(inputs)
            self.body_numbers.object = _body_words(prepared.body)
            generation = self.runner.submit(inputs)
        except ParameterError as error:
            self._refused(str(error))
            return
        self.message.object = ""
        self.message.visible = False
        self.status.object = f"running (inputs #{generation}) …"
        self._ensure_polling()

    def _refused(self, text: str) -> None:
        self.message.object = f"**refused:** {text}. The plots show the last good run."
        self.message.visible = True

    def _ensure_polling(self, anywhere: bool = False) -> None:
        """Look for finished runs every ``POLL_MS`` in a served page's session (or, with
        ``anywhere``, in a notebook's event loop); tests call :meth:`poll` themselves."""
        if self._callback is not None:
            return
        if anywhere or _served():
            self._callback = pn.state.add_periodic_callback(self.poll, period=POLL_MS)

    def poll(self) -> None:
        """Draw a finished run, or show the progress of a slow one (session thread)."""
        running = self.runner.running()
        if running is not None and running.seconds > SLOW_RUN:
            self.progress.visible = True
            self.stop_button.visible = True
            self.progress.value = int(100 * min(1.0, running.time_reached / running.t_end))
            self.status.object = _progress_words(running)
        elif running is None:
            self.progress.visible = False
            self.stop_button.visible = False
        outcome = self.runner.take()
        if outcome is not None:
            self.show(outcome)

    def _stop(self, event: Any = None) -> None:
        if self.runner.stop():
            self.status.object = "stopped; the plots show the last finished run"
            self.progress.visible = False
            self.stop_button.visible = False

    # -- plots ------------------------------------------------------------------------
    def _build_plots(self) -> None:
        """The plots' data and the time cursor; the figures that show them are made by
        :meth:`_figures` (in a served page once it is shown: Bokeh's plotting interface
        takes a while to import)."""
        empty: dict[str, list[float]] = {"time": [], "value": []}
        self.sources = {
            key: ColumnDataSource(data=dict(empty))
            for key in ("spin", "pinned_spin", "energy", "work", "total", "tilt", "pinned_tilt")
        }
        self.reversal_source = ColumnDataSource(data={"time": [], "low": [], "high": []})
        self.stone_source = ColumnDataSource(data={"xs": [], "ys": [], "color": []})
        self.track_source = ColumnDataSource(data={"x": [], "y": []})
        self.cursor_spans = [
            Span(location=0.0, dimension="height", line_color="black", line_alpha=0.5)
            for _ in range(3)
        ]
        self._stone_scene: Any = None
        self._figure_column: Any = None
        self.time_cursor = pn.widgets.FloatSlider(
            label="time cursor [s]",
            start=0.0,
            end=1.0,
            step=0.01,
            value=0.0,
            sizing_mode="stretch_width",
        )
        self.time_cursor.param.watch(self._move_cursor, "value")
        # plays the run: steps the time cursor through PLAYER_FRAMES equal steps of it
        self.player = pn.widgets.Player(
            label="play the run",
            start=0,
            end=PLAYER_FRAMES,
            value=0,
            interval=PLAYER_INTERVAL_MS,
            loop_policy="once",
            show_loop_controls=False,
            show_value=False,
            visible_buttons=["first", "pause", "play"],
            width=220,
            css_classes=["cs-player"],
        )
        self.player.param.watch(self._play, "value")

    def _figures(self) -> Any:
        """The stone and the three plots, made on the first call."""
        if self._figure_column is None:
            from celtstone.explorer.figures import run_figures

            shown = run_figures(
                self.sources, self.reversal_source, self.stone_source, self.track_source
            )
            for plot, span in zip(shown[1:], self.cursor_spans, strict=True):
                plot.add_layout(span)
            self._figure_column = pn.Column(
                *(pn.pane.Bokeh(plot, sizing_mode="stretch_width") for plot in shown),
                sizing_mode="stretch_width",
            )
        return self._figure_column

    def _play(self, event: Any = None) -> None:
        """The player's frame as the time cursor's time (the stone moves with it)."""
        self.time_cursor.value = self.time_cursor.end * self.player.value / PLAYER_FRAMES

    def _move_cursor(self, event: Any = None) -> None:
        for span in self.cursor_spans:
            span.location = self.time_cursor.value
        if self.outcome is None or self.outcome.trajectory is None:
            return
        ds = self.outcome.trajectory.dataset
        if self._stone_scene is not None:
            view = self._stone_scene.at(self.time_cursor.value)
            self.stone_source.data = {
                "xs": view.xs,
                "ys": view.ys,
                "color": [_stone_colour(shade) for shade in view.shade],
            }
            self.track_source.data = {"x": view.track_x, "y": view.track_y}
        at = ds.sel(time=self.time_cursor.value, method="nearest")
        self.cursor_words.object = (
            f"at t = {float(at.time):.3g} s: spin {float(at.spin):.4g} rad/s, "
            f"tilt {math.degrees(float(at.tilt)):.3g} deg, energy {float(at.energy):.6g} J"
        )

    def show(self, outcome: FinishedRun) -> None:
        """Draw ``outcome`` (the newest inputs' run) and its verdict."""
        self.outcome = outcome
        self.status.object = f"run of inputs #{outcome.generation} done in {outcome.seconds:.2f} s"
        if outcome.concerns or outcome.cautions:
            self.status.object += "; " + "; ".join((*outcome.concerns, *outcome.cautions))
        self.verdict.object = f"**{verdict(outcome)}**"
        if outcome.trajectory is None:
            return
        ds = outcome.trajectory.dataset
        time = ds["time"].values
        spin = ds["spin"].values
        self.sources["spin"].data = {"time": time, "value": spin}
        energy = ds["energy"].values
        work = ds["dissipated_work"].values
        self.sources["energy"].data = {"time": time, "value": energy}
        self.sources["work"].data = {"time": time, "value": work}
        self.sources["total"].data = {"time": time, "value": energy + work}
        self.sources["tilt"].data = {"time": time, "value": np.degrees(ds["tilt"].values)}
        reversals = list(outcome.trajectory.summary()["reversal_times"])
        high = float(np.max(np.abs(spin))) if len(spin) else 1.0
        self.reversal_source.data = {
            "time": reversals,
            "low": [-high] * len(reversals),
            "high": [high] * len(reversals),
        }
        self._stone_scene = _scene_or_none(ds)
        self.time_cursor.end = float(time[-1]) if len(time) > 1 else 1.0
        self.time_cursor.value = min(self.time_cursor.value, self.time_cursor.end)
        self._move_cursor()
        self._write_recipes(outcome.inputs)

    def _pin(self, event: Any = None) -> None:
        """Keep the shown run as a grey overlay under the next ones."""
        if self.outcome is None or self.outcome.trajectory is None:
            return
        self.pinned = self.outcome
        ds = self.outcome.trajectory.dataset
        self.sources["pinned_spin"].data = {"time": ds["time"].values, "value": ds["spin"].values}
        self.sources["pinned_tilt"].data = {
            "time": ds["time"].values,
            "value": np.degrees(ds["tilt"].values),
        }
        self.pinned_words.object = f"pinned: {verdict(self.outcome)}"

    def _unpin(self, event: Any = None) -> None:
        self.pinned = None
        for key in ("pinned_spin", "pinned_tilt"):
            self.sources[key].data = {"time": [], "value": []}
        self.pinned_words.object = ""

    # -- outputs ----------------------------------------------------------------------
    def _build_outputs(self) -> None:
        self.message = pn.pane.Alert(
            "", alert_type="danger", visible=False, css_classes=["cs-message"]
        )
        self.verdict = pn.pane.Markdown(
            "", styles={"font-size": "1.3em"}, css_classes=["cs-verdict"]
        )
        self.status = pn.pane.Markdown("", styles={"font-size": "0.85em"})
        self.cursor_words = pn.pane.Markdown("", styles={"font-size": "0.85em"})
        self.pinned_words = pn.pane.Markdown("", styles={"font-size": "0.85em"})
        self.progress = pn.indicators.Progress(value=0, max=100, visible=False, width=200)
        self.stop_button = pn.widgets.Button(label="stop", color="danger", visible=False)
        self.stop_button.on_click(self._stop)
        self.pin_button = pn.widgets.Button(label="pin this run", color="primary")
        self.pin_button.on_click(self._pin)
        self.unpin_button = pn.widgets.Button(label="unpin")
        self.unpin_button.on_click(self._unpin)
        self.command = pn.pane.Markdown("")
        self.snippet = pn.pane.Markdown("")
        downloads = (  # file name, label, what makes its bytes from the file name
            ("run.nc", "run (NetCDF)", self._dataset_bytes),
            ("run.csv", "run (CSV)", self._dataset_bytes),
            ("run.png", "figure (PNG)", self._figure_bytes),
            ("run.svg", "figure (SVG)", self._figure_bytes),
        )
        files = [
            pn.widgets.FileDownload(
                callback=partial(make, name), filename=name, label=label, embed=False
            )
            for name, label, make in downloads
        ]
        self.downloads = pn.Card(
            pn.Row(*files),
            self.command,
            self.snippet,
            self.pinned_words,
            title="Keep it",
        )

    def _write_recipes(self, inputs: Inputs) -> None:
        line = command_line(inputs)
        self.command.object = (
            f"```bash\n{line}\n```"
            if line is not None
            else "The design form has no `celtstone run` spelling; the Python below rebuilds it."
        )
        self.snippet.object = f"```python\n{python_snippet(inputs)}\n```"

    def _dataset_bytes(self, name: str) -> io.BytesIO:
        """The shown run as the file ``name`` (its suffix the format), written by
        ``celtstone.files.export`` into a private temporary directory and read back;
        nothing is left on disk."""
        from celtstone.files.export import write

        if self.outcome is None or self.outcome.trajectory is None:
            return io.BytesIO(b"")
        with tempfile.TemporaryDirectory(prefix="celtstone-explore-") as folder:
            path = write(self.outcome.trajectory.dataset, Path(folder) / name)
            return io.BytesIO(path.read_bytes())

    def _figure_bytes(self, name: str) -> io.BytesIO:
        """The shown run drawn by ``celtstone plot``'s figure, as PNG or SVG by the suffix
        of the file ``name``."""
        from celtstone.plotting.run import plot_run

        if self.outcome is None or self.outcome.trajectory is None:
            return io.BytesIO(b"")
        import matplotlib.pyplot as plt

        drawn = plot_run(self.outcome.trajectory.dataset)
        buffer = io.BytesIO()
        drawn.savefig(buffer, format=Path(name).suffix[1:])
        plt.close(drawn)
        buffer.seek(0)
        return buffer

    # -- showing ----------------------------------------------------------------------
    def servable(self) -> Any:
        """The page, served by ``panel serve`` / ``celtstone serve``."""
        return self.layout.servable(title="celtstone explorer")

    def _repr_mimebundle_(self, include: Any = None, exclude: Any = None) -> Any:
        """Shown inline in a notebook (Jupyter calls this)."""
        self._ensure_polling(anywhere=True)
        return self.layout._repr_mimebundle_(include, exclude)


def _component_inputs(
    parameter: str, symbols: tuple[str, ...], unit: str, values: tuple[float, ...]
) -> list[Any]:
    """One number input per component of the vector ``parameter`` (``schema.PARAMETERS``)."""
    return [
        pn.widgets.FloatInput(
            label=f"{symbol} [{unit}]",
            value=value,
            width=110,
            description=schema.PARAMETERS[parameter].help(),
        )
        for symbol, value in zip(symbols, values, strict=True)
    ]


def _progress_words(running: Progress) -> str:
    """The status line of a slow run: t / t_end, or why its loop has not started."""
    if not running.looping:
        return (
            f"inputs #{running.generation}: preparing the model's compiled code "
            f"({running.seconds:.0f} s): a model not yet in numba's cache is compiled on "
            "its first run, up to a minute (`celtstone compile` does it once for all)"
        )
    return (
        f"running (inputs #{running.generation}): {running.time_reached:.3g} of {running.t_end:g} s"
    )


def _served() -> bool:
    """Whether this runs in a served page's session (not a notebook, not a test)."""
    document = pn.state.curdoc
    return document is not None and document.session_context is not None


def _real(value: Any) -> Any:
    """A box's number as a float (a browser sends -1 for -1.0); other values unchanged."""
    if isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    return value


def _stone_colour(shade: float) -> str:
    """A sandstone colour at brightness ``shade`` in [0, 1], as #rrggbb."""
    red, green, blue = (round(channel * (0.2 + 0.8 * shade)) for channel in (214, 180, 120))
    return f"#{red:02x}{green:02x}{blue:02x}"


def _scene_or_none(dataset: Any) -> Any:
    """The run's 3-D scene, or None for a body the viewer cannot draw."""
    from celtstone.explorer.stone import StoneScene

    try:
        return StoneScene(dataset)
    except CeltstoneError:
        return None


def _body_words(body: Any) -> str:
    inertia = np.array(body.inertia)
    numbers = ", ".join(
        f"{v:.3g}" for v in (inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1])
    )
    # the rest contact's radii of curvature, a²/c and b²/c, hold for the ellipsoid only
    radii = body.shape.semi_axes if isinstance(body.shape, Ellipsoid) else None
    text = f"mass {body.mass:.4g} kg; I11, I22, I33, I12 = {numbers} kg m²"
    if radii is not None:
        a, b, c = radii
        text += f"; radii of curvature at rest a²/c = {a * a / c:.3g} m, b²/c = {b * b / c:.3g} m"
    return text
