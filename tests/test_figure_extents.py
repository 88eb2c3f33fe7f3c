"""Every figure the package makes fits its canvas: no text is cut off (issue 16, item 5).

Animation frames included: the figures of ``celtstone animate`` and of the
reproduction's video.

The Figure 3 analogue's title of ``make run`` (``fig3_kane_levinson_1982+realistic.png``)
was cut off at both edges. Each figure function is drawn here with the longest title it
is given in practice, and every visible text artist's extent must lie inside the figure.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.text import Text
from matplotlib.transforms import Bbox

import celtstone as cs
from celtstone.atlas.target import FINE_ATLAS
from celtstone.plotting import (
    plot_energy_budget,
    plot_run,
    plot_spin_comparison,
    plot_threshold,
    plot_verdict_maps,
)
from celtstone.plotting.fit import FitPanel, plot_fit
from celtstone.plotting.friction import friction_law_figure
from celtstone.plotting.maps import plot_field_map
from celtstone.plotting.stability import growth_rate_figure
from celtstone.sweep import Sweep

LONG_KEY = "kane_levinson_1982+realistic"  # the longest study key of the reproduction
LONG_CONTACT = "Hertz ellipse, E = 3e+09 Pa, ν = 0.35, exact law, λ = 1e-05 m, stick–slip"


@pytest.fixture(scope="module")
def runs(kane_levinson: cs.Body) -> list[xr.Dataset]:
    state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
    sliding = cs.SlidingModel(friction_coefficient=0.35, contact_radius=1e-3)
    return [
        cs.simulate(cs.RollingModel(), kane_levinson, state, 3.0).dataset,
        cs.simulate(sliding, kane_levinson, state, 3.0, rtol=1e-8, atol=1e-10).dataset,
    ]


def _outside(figure: Figure) -> list[str]:
    """What is drawn outside the figure (1 pixel of slack): the figure's tight box (every
    drawn artist, tick labels of the ticks in view included) against its frame, and by
    name the titles, labels and legend texts that leave it."""
    canvas = FigureCanvasAgg(figure)
    canvas.draw()
    renderer = canvas.get_renderer()
    frame = figure.bbox
    tick_labels = {
        id(label)
        for axes in figure.axes
        for axis in (axes.xaxis, axes.yaxis)
        for label in axis.get_ticklabels(minor=False) + axis.get_ticklabels(minor=True)
    }
    cut = []
    for text in figure.findobj(Text):
        if id(text) in tick_labels or not text.get_visible() or not text.get_text().strip():
            continue
        box = text.get_window_extent(renderer)
        if not _inside(box, frame):
            cut.append(f"{text.get_text()!r} at {box.bounds}")
    tight = figure.get_tightbbox(renderer).transformed(figure.dpi_scale_trans)
    if not cut and not _inside(tight, frame):
        cut.append(f"the drawn artists span {tight.bounds} beyond {frame.bounds}")
    return cut


def _inside(box: Bbox, frame: Bbox) -> bool:
    return (
        box.x0 >= frame.x0 - 1
        and box.y0 >= frame.y0 - 1
        and box.x1 <= frame.x1 + 1
        and box.y1 <= frame.y1 + 1
    )


def _figures(runs: list[xr.Dataset]) -> dict[str, Figure]:
    table = pd.DataFrame(
        {
            "friction_coefficient": [0.1, 0.2, 0.3],
            "first_reversal_time": [np.nan, 3.0, 2.0],
            "energy_final": [0.099, 0.0985, 0.098],
            "energy_rest": [0.0981] * 3,
        }
    )
    sweep = Sweep(
        {"friction_coefficient": [0.2, 0.35], "initial_spin": [-5.0, 5.0]},
        model="sliding",
        t_end=0.2,
    ).run()
    long_slice = max(FINE_ATLAS.slices, key=lambda s: len(s.words()))
    verdicts = ["yes", "partly", "no"] * (len(long_slice.x_values) * len(long_slice.y_values))
    cells = len(long_slice.x_values) * len(long_slice.y_values)
    findings = ("period", "energy_order", "energy_decrease", "threshold", "long_run", "all five")
    stability = cs.spin_stability(cs.load_body("kane_levinson_1982"), np.linspace(-10, 10, 21))
    return {
        "fig2": plot_spin_comparison(
            [[runs[0]], [runs[1], runs[1]]],
            f"Figure 2 analogue, {LONG_KEY}: spin against time ({LONG_CONTACT})",
        ),
        "fig3": plot_spin_comparison(
            [[runs[0]], [runs[1]]],
            f"Figure 3 analogue, {LONG_KEY}: long run, rolling and sliding f = 0.35",
            columns=1,
        ),
        "energy": plot_energy_budget(
            runs, f"{LONG_KEY}: energy and energy budget, sliding with N = m g"
        ),
        "threshold": plot_threshold(
            table,
            f"Threshold, {LONG_KEY}: sliding, {LONG_CONTACT}, N = m g, runs of 20 s",
            [0.15],
        ),
        "run": plot_run(runs[1]),
        "map": plot_field_map(sweep, "first_reversal_time"),
        "stability": growth_rate_figure(stability),
        "fit": plot_fit(
            runs[1]["time"].values,
            [FitPanel("spin ω·n [rad/s]", runs[1]["spin"].values, runs[1]["spin"].values)],
            f"celtstone fit of {LONG_KEY}: friction_coefficient, contact_radius, "
            "rolling_resistance, damping, omega3 free, sliding model, 3 starts",
        ),
        "friction": friction_law_figure(),
        "atlas": plot_verdict_maps(
            list(long_slice.x_values),
            list(long_slice.y_values),
            {name: verdicts[:cells] for name in findings},
            "b/a",
            "c/a",
            f"Atlas (fine grid), {long_slice.words()}: each finding's verdict",
        ),
    }


def test_no_text_is_cut_off(runs: list[xr.Dataset]) -> None:
    for name, figure in _figures(runs).items():
        assert _outside(figure) == [], name


def test_the_check_finds_a_cut_title() -> None:
    """The check itself: a title wider than its figure is found."""
    figure = Figure(figsize=(4.0, 3.0), layout="constrained")
    figure.add_subplot()
    figure.suptitle("a title far too long for a figure four inches wide, " * 2)
    assert len(_outside(figure)) == 1


@pytest.mark.parametrize(
    ("suffix", "which"),
    [(".gif", (1,)), (".mp4", (1,)), (".gif", (0, 1)), (".mp4", (0, 1))],
    ids=["gif", "mp4", "gif-side-by-side", "mp4-side-by-side"],
)
def test_no_text_is_cut_off_in_an_animation_frame(
    runs: list[xr.Dataset],
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    suffix: str,
    which: tuple[int, ...],
) -> None:
    """The frames of ``celtstone animate`` and of the reproduction's rolling-beside-sliding
    video (``visual.animation``), at their default sizes (a gif panel is the smallest, 400
    px wide side by side), in slow motion so that the read-out is at its longest: each
    panel's title, legend and read-out fit the frame at its first, middle and last time.

    The encoder is replaced by one that draws the first frame and then shows the frames
    to check on the figure the animation built (its arguments, read before it runs)."""
    from celtstone.visual import animate_comparison, animation

    cut: dict[float, list[str]] = {}

    def check_frames(
        path: Path, suffix: str, frames: Iterator[np.ndarray], *args: object, **kwargs: object
    ) -> None:
        arguments = frames.gi_frame.f_locals  # type: ignore[attr-defined]
        figure, panels, plan = arguments["figure"], arguments["panels"], arguments["plan"]
        next(frames)
        for time in (plan.times[0], plan.times[len(plan.times) // 2], plan.times[-1]):
            for panel in panels:
                panel.show(float(time), plan.speed)
            cut[float(time)] = _outside(figure)
        path.write_bytes(b"")

    monkeypatch.setattr(animation, "_write", check_frames)
    labels = ["rolling without sliding", f"rolling with sliding, f = 0.35 ({LONG_KEY})"]
    animate_comparison(
        [runs[i] for i in which], [labels[i] for i in which], tmp_path / f"run{suffix}", speed=0.2
    )
    assert len(cut) == 3
    assert {time: texts for time, texts in cut.items() if texts} == {}
