"""What every figure of the package does last: tick labels written whole, legends off the data.

A reader should not have to add an offset printed above an axis (``1e−12+1.2388e−1``)
to every tick, nor look for a curve under a legend. :func:`make_legible` is called by
each figure function on the finished figure:

- every linear axis (colour bars included) gets :func:`plain_tick_formatter`, which
  writes each tick's value in full (``0.25``, ``2×10⁻⁵``) and never an offset or a
  common factor apart from the ticks;
- every legend inside an axes is moved to the first place, of the corners and edge
  centres, where it covers no data (lines, markers, meshes, text) and no other legend;
  where there is none it goes above the axes (right of it when the axes has a title).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.backend_bases import RendererBase
    from matplotlib.figure import Figure
    from matplotlib.legend import Legend
    from matplotlib.transforms import Bbox


__all__ = [
    "LEGEND_PLACES",
    "make_legible",
    "place_legends",
    "plain_tick_formatter",
    "tick_labels",
]

LEGEND_PLACES: tuple[Any, ...] = (
    "upper right",
    "upper left",
    "lower left",
    "lower right",
    "center right",
    "center left",
    "upper center",
    "lower center",
)
"""Where a legend may sit inside its axes, in the order they are tried."""

# fixed notation for tick values of this size [units of the axis]; beyond it, or when
# the ticks need more decimals than _MAX_DECIMALS, each tick is written m×10ⁿ
_FIXED_RANGE = (1e-3, 1e5)
_MAX_DECIMALS = 6
_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")
_MINUS = "\N{MINUS SIGN}"


def tick_labels(values: Sequence[float]) -> list[str]:
    """Labels of ticks at ``values``, each carrying its whole value: no offset, no common
    ×10ⁿ apart from the ticks.

    Values of size 1e-3 to 1e5 are written in fixed notation with as many decimals as
    the spacing of the ticks needs; others as ``m×10ⁿ`` on each tick.
    """
    finite = np.unique(np.asarray([v for v in values if math.isfinite(v)], dtype=float))
    largest = float(np.max(np.abs(finite))) if finite.size else 0.0
    steps = np.diff(finite)
    step = float(np.min(steps)) if steps.size else largest
    if step <= 0.0 or not math.isfinite(step):
        step = 1.0
    exponent = math.floor(math.log10(step))
    leading = step / 10.0**exponent
    if not math.isclose(leading, round(leading), rel_tol=1e-6):
        exponent -= 1  # a step of 2.5×10ⁿ needs one more digit
    decimals = max(0, -exponent)
    fixed = largest == 0.0 or (
        _FIXED_RANGE[0] <= largest < _FIXED_RANGE[1] and decimals <= _MAX_DECIMALS
    )
    # a tick at floating-point noise from zero (−1.4e-17) is zero
    return [
        _tick_label(0.0 if abs(v) < 1e-9 * step else float(v), fixed, decimals, exponent)
        for v in values
    ]


def _tick_label(value: float, fixed: bool, decimals: int, step_exponent: int) -> str:
    if not math.isfinite(value):
        return str(value)
    if fixed:
        text = f"{value:.{decimals}f}"
    elif value == 0.0:
        text = "0"
    else:
        power = math.floor(math.log10(abs(value)))
        digits = max(0, power - step_exponent)
        mantissa = f"{value / 10.0**power:.{digits}f}"
        if abs(float(mantissa)) >= 10.0:  # rounding carried into the next power
            power += 1
            mantissa = f"{value / 10.0**power:.{digits}f}"
        text = f"{mantissa}×10{str(power).translate(_SUPERSCRIPT)}"
    return text.replace("-", _MINUS)


@functools.cache
def _formatter_class() -> type:
    """:class:`matplotlib.ticker.Formatter` of :func:`tick_labels` (made on first use:
    importing this module does not import matplotlib)."""
    from matplotlib.ticker import Formatter

    class PlainTickFormatter(Formatter):
        """Tick labels of :func:`tick_labels`."""

        def format_ticks(self, values: Sequence[float]) -> list[str]:
            return tick_labels(values)

        def __call__(self, x: float, pos: int | None = None) -> str:
            return tick_labels([x])[0]

    return PlainTickFormatter


def plain_tick_formatter() -> Any:
    """A matplotlib tick formatter writing :func:`tick_labels`."""
    return _formatter_class()()


def make_legible(figure: Figure) -> Figure:
    """Give ``figure``'s linear axes plain tick labels and move its legends off the data.

    Returns
    -------
    matplotlib.figure.Figure
        ``figure`` itself.
    """
    from matplotlib.ticker import ScalarFormatter

    for axes in figure.axes:
        colorbar = getattr(axes, "_colorbar", None)
        for axis in (axes.xaxis, axes.yaxis):
            if isinstance(axis.get_major_formatter(), ScalarFormatter):
                if colorbar is not None and axis is colorbar.long_axis:
                    colorbar.formatter = plain_tick_formatter()
                else:
                    axis.set_major_formatter(plain_tick_formatter())
    place_legends(figure)
    return figure


def place_legends(figure: Figure) -> None:
    """Move each legend drawn inside an axes to where it covers no data and no other
    legend (the first free place of :data:`LEGEND_PLACES`), else outside the axes.

    A legend moved outside changes the layout, so the others are placed again after it.
    """
    outside: set[int] = set()
    for _ in range(len(figure.axes) + 1):
        legends: list[Legend] = [
            legend
            for axes in figure.axes
            if axes.get_visible() and (legend := axes.get_legend()) is not None
        ]
        if not legends:
            return
        renderer = _draw(figure)
        placed = [legend.get_window_extent(renderer) for legend in figure.legends]
        placed += [g.get_window_extent(renderer) for g in legends if id(g) in outside]
        for legend in (g for g in legends if id(g) not in outside):
            box = _free_place(legend, placed, renderer)
            if box is None:
                outside.add(id(_outside(legend, renderer)))
                break
            placed.append(box)
        else:
            return


def _free_place(legend: Legend, placed: Sequence[Bbox], renderer: RendererBase) -> Bbox | None:
    """Put ``legend`` at the first place of :data:`LEGEND_PLACES` where it covers nothing
    (``_covers``); its box there, or None (left at the last place tried)."""
    for place in LEGEND_PLACES:
        legend.set_loc(place)
        box = legend.get_window_extent(renderer)
        if not _covers(box, legend.axes, placed, renderer):
            return box
    return None


def _draw(figure: Figure) -> RendererBase:
    """Lay ``figure`` out and draw it once; its renderer (an Agg canvas if it has none)."""
    canvas: Any = figure.canvas
    if not hasattr(canvas, "get_renderer"):
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        canvas = FigureCanvasAgg(figure)
    canvas.draw()
    return canvas.get_renderer()


def _outside(legend: Legend, renderer: RendererBase) -> Legend:
    """``legend`` drawn again above its axes, in as many columns as the axes' width holds
    (right of the axes if it has a title, which sits above it)."""
    axes = legend.axes
    handles: list[Any] = list(legend.legend_handles)
    labels = [text.get_text() for text in legend.get_texts()]
    size = legend.get_texts()[0].get_fontsize() if labels else None
    if axes.get_title():
        return axes.legend(
            handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=size
        )
    width = axes.get_window_extent(renderer).width
    for columns in range(len(labels), 0, -1):
        above = axes.legend(
            handles,
            labels,
            loc="lower center",
            bbox_to_anchor=(0.5, 1.01),
            ncols=columns,
            fontsize=size,
            borderaxespad=0.0,
        )
        if above.get_window_extent(renderer).width <= width:
            break
    return above


def _covers(box: Bbox, axes: Axes, legends: Sequence[Bbox], renderer: RendererBase) -> bool:
    """Whether ``box`` (a legend of ``axes``) leaves the axes or covers a legend, or a
    data artist of ``axes`` or of an axes over it (a twin)."""
    frame = axes.get_window_extent(renderer)
    if box.x0 < frame.x0 - 1 or box.x1 > frame.x1 + 1 or box.y0 < frame.y0 - 1:
        return True
    if box.y1 > frame.y1 + 1 or any(box.overlaps(other) for other in legends):
        return True
    stacked = [a for a in axes.figure.axes if a.get_visible() and a.bbox.overlaps(axes.bbox)]
    return any(_hits(artist, box, renderer) for a in stacked for artist in _data_artists(a))


def _data_artists(axes: Axes) -> Iterator[Any]:
    yield from (line for line in axes.lines if line.get_visible())
    yield from (c for c in axes.collections if c.get_visible())
    yield from (image for image in axes.images if image.get_visible())
    yield from (t for t in axes.texts if t.get_visible() and t.get_text().strip())


def _hits(artist: Any, box: Bbox, renderer: Any) -> bool:
    """Whether ``artist`` draws anything inside ``box`` (display coordinates)."""
    from matplotlib.collections import Collection
    from matplotlib.lines import Line2D

    if isinstance(artist, Line2D):
        path = artist.get_transform().transform_path(artist.get_path())
        vertices = np.asarray(path.vertices, dtype=float)
        if vertices.size == 0:
            return False
        if artist.get_linestyle() not in ("None", "", " ") and path.intersects_bbox(
            box, filled=False
        ):
            return True
        if artist.get_marker() in (None, "None", "", " "):
            return False
        reach = artist.get_markersize() * renderer.points_to_pixels(1.0) / 2.0
        return bool(_inside(vertices, box.padded(reach)).any())
    offsets = (
        np.asarray(artist.get_offsets(), dtype=float) if isinstance(artist, Collection) else ()
    )
    if len(offsets) > 1:  # a scatter: its markers' centres
        points = artist.get_offset_transform().transform(offsets)
        return bool(_inside(points, box).any())
    extent = artist.get_window_extent(renderer)
    return bool(extent.width > 0 and extent.height > 0 and extent.overlaps(box))


def _inside(points: np.ndarray, box: Bbox) -> np.ndarray:
    x, y = points[:, 0], points[:, 1]
    return (x >= box.x0) & (x <= box.x1) & (y >= box.y0) & (y <= box.y1)
