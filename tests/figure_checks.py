"""What a reader must never meet in a figure, found from the drawn artists.

Written apart from ``celtstone.plotting.legible`` (which places legends by testing
paths against boxes): here every drawn line is sampled point by point in display
coordinates, so the two do not share a mistake.
"""

from __future__ import annotations

import itertools

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backend_bases import RendererBase
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import Collection, QuadMesh
from matplotlib.figure import Figure
from matplotlib.legend import Legend
from matplotlib.text import Text
from matplotlib.transforms import Bbox

MINIMUM_FONT_POINTS = 8.0
_SAMPLE_PIXELS = 1.0  # spacing of the points sampled along a drawn line [px]


def draw(figure: Figure) -> RendererBase:
    """Draw ``figure`` on an Agg canvas; its renderer."""
    canvas = FigureCanvasAgg(figure)
    canvas.draw()
    return canvas.get_renderer()


def offset_texts(figure: Figure) -> list[str]:
    """The offsets and common factors written apart from an axis's ticks (``1e−12+1.2e−1``)."""
    draw(figure)
    found = []
    for axes in figure.axes:
        if not axes.get_visible():
            continue
        for axis in (axes.xaxis, axes.yaxis):
            text = axis.get_offset_text()
            if axis.get_visible() and text.get_visible() and text.get_text().strip():
                found.append(f"{axes.get_label() or axes}: {text.get_text()!r}")
    return found


def small_texts(figure: Figure, minimum: float = MINIMUM_FONT_POINTS) -> list[str]:
    """Every drawn text smaller than ``minimum`` [pt], tick labels included."""
    draw(figure)
    return [
        f"{text.get_text()!r} at {text.get_fontsize():.3g} pt"
        for text in figure.findobj(Text)
        if text.get_visible() and text.get_text().strip() and text.get_fontsize() < minimum
    ]


def legend_overlaps(figure: Figure) -> list[str]:
    """Legends drawn over data (a sampled point of a line, a marker, a mesh, a text of
    an axes) or over another legend. Three-dimensional axes are left out: their
    plane fills the whole panel."""
    renderer = draw(figure)
    legends: list[Legend] = [a.get_legend() for a in figure.axes if a.get_legend() is not None]
    legends += figure.legends
    legends = [legend for legend in legends if legend.get_visible()]
    boxes = [legend.get_window_extent(renderer) for legend in legends]
    found = []
    for legend, box in zip(legends, boxes, strict=True):
        inner = box.padded(-1.0)
        for axes in figure.axes:
            if not axes.get_visible() or axes.name == "3d":
                continue
            frame = axes.get_window_extent(renderer)
            for artist, points in _data_points(axes, renderer):
                points = points[_inside(points, frame)]
                if _inside(points, inner).any():
                    found.append(f"legend {_words(legend)} over {artist}")
    for i, box in enumerate(boxes):
        for j in range(i + 1, len(boxes)):
            if box.padded(-1.0).overlaps(boxes[j]):
                found.append(f"legends {_words(legends[i])} and {_words(legends[j])} overlap")
    return found


def _words(legend: Legend) -> str:
    return repr([text.get_text() for text in legend.get_texts()])


def _data_points(axes: Axes, renderer: RendererBase):  # type: ignore[no-untyped-def]
    """(artist, display points) of each data artist of ``axes``: lines sampled every
    pixel along their segments, markers with their size, collections by their paths."""
    for line in axes.lines:
        if not line.get_visible():
            continue
        xy = line.get_transform().transform(np.column_stack(line.get_data()).astype(float))
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        if xy.shape[0] == 0:
            continue
        if line.get_linestyle() not in ("None", "", " "):
            yield line, _sampled(xy)
        if line.get_marker() not in (None, "None", "", " "):
            reach = line.get_markersize() * renderer.points_to_pixels(1.0) / 2.0
            yield line, _marker_points(xy, reach)
    for collection in axes.collections:
        if collection.get_visible():
            yield collection, _collection_points(collection)
    for text in axes.texts:
        if text.get_visible() and text.get_text().strip():
            box = text.get_window_extent(renderer)
            yield text, _box_points(box)


def _sampled(xy: np.ndarray) -> np.ndarray:
    """Points every ``_SAMPLE_PIXELS`` along the polyline ``xy`` (display coordinates)."""
    points = [xy]
    for start, end in itertools.pairwise(xy):
        count = int(np.hypot(*(end - start)) / _SAMPLE_PIXELS)
        if count > 1:
            t = np.linspace(0.0, 1.0, count)[:, None]
            points.append(start + t * (end - start))
    return np.concatenate(points)


def _marker_points(xy: np.ndarray, reach: float) -> np.ndarray:
    offsets = np.array([[0, 0], [reach, 0], [-reach, 0], [0, reach], [0, -reach]])
    return (xy[:, None, :] + offsets[None, :, :]).reshape(-1, 2)


def _collection_points(collection: Collection) -> np.ndarray:
    if isinstance(collection, QuadMesh):
        corners = collection.get_coordinates().reshape(-1, 2)
        centres = 0.5 * (corners[:-1] + corners[1:])
        return collection.get_transform().transform(np.concatenate([corners, centres]))
    offsets = collection.get_offsets()
    if len(offsets) and len(collection.get_paths()) <= 1:  # a scatter: one marker, offsets
        return collection.get_offset_transform().transform(np.asarray(offsets, dtype=float))
    transform = collection.get_transform()
    paths = [transform.transform(path.vertices) for path in collection.get_paths()]
    paths = [path[np.all(np.isfinite(path), axis=1)] for path in paths]
    sampled = [_sampled(path) for path in paths if path.shape[0]]
    return np.concatenate(sampled) if sampled else np.empty((0, 2))


def _box_points(box: Bbox) -> np.ndarray:
    x = np.linspace(box.x0, box.x1, 9)
    y = np.linspace(box.y0, box.y1, 9)
    return np.array([(a, b) for a in x for b in y])


def _inside(points: np.ndarray, box: Bbox) -> np.ndarray:
    if points.size == 0:
        return np.zeros(0, dtype=bool)
    x, y = points[:, 0], points[:, 1]
    return (x > box.x0) & (x < box.x1) & (y > box.y0) & (y < box.y1)


def defects(figure: Figure) -> list[str]:
    """Every offset text, small text and legend over data of ``figure``."""
    return [
        *(f"offset: {t}" for t in offset_texts(figure)),
        *(f"small: {t}" for t in small_texts(figure)),
        *(f"overlap: {t}" for t in legend_overlaps(figure)),
    ]
