"""Every figure the package makes fits its canvas: no text is cut off (issue 16, item 5).

Animation frames included: the figures of ``celtstone animate`` and of the
reproduction's video.

The Figure 3 analogue's title of ``make run`` (``fig3_kane_levinson_1982+realistic.png``)
was cut off at both edges. Each figure of ``tests/figure_registry.py`` is drawn with the
longest title it is given in practice, and every visible text artist's extent must lie
inside the figure. An animation frame's text must also be 8 pt or more (11 px at the
frames' 100 dpi; its legend was 5 pt, about 7 px).
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.text import Text
from matplotlib.transforms import Bbox

from tests.figure_checks import small_texts
from tests.figure_registry import CASES, LONG_KEY, FigureCase
from tests.figure_registry import runs as registry_runs


@pytest.fixture(scope="module")
def runs() -> list[xr.Dataset]:
    return list(registry_runs())


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


@pytest.mark.parametrize("case", CASES, ids=[case.name for case in CASES])
def test_no_text_is_cut_off(case: FigureCase) -> None:
    assert _outside(case.build()) == []


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
    panel's title, legend and read-out fit the frame at its first, middle and last time,
    none under 8 pt.

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
                panel.show(panel.sample(float(time)), plan.speed)
            cut[float(time)] = _outside(figure) + small_texts(figure)
        path.write_bytes(b"")

    monkeypatch.setattr(animation, "_write", check_frames)
    labels = ["rolling without sliding", f"rolling with sliding, f = 0.35 ({LONG_KEY})"]
    animate_comparison(
        [runs[i] for i in which], [labels[i] for i in which], tmp_path / f"run{suffix}", speed=0.2
    )
    assert len(cut) == 3
    assert {time: texts for time, texts in cut.items() if texts} == {}
