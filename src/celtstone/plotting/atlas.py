"""Maps of the atlas: each finding's verdict over a two-parameter slice of the family."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from celtstone.plotting.labels import wrapped_title
from celtstone.plotting.legible import make_legible

if TYPE_CHECKING:
    from matplotlib.figure import Figure


__all__ = ["VERDICT_COLOURS", "plot_verdict_maps"]

VERDICT_COLOURS = {"no": "#d7301f", "partly": "#fdae61", "yes": "#1a9850"}
"""A verdict's colour (red, orange, green; ColorBrewer RdYlGn), the same in every panel."""


def plot_verdict_maps(
    x_values: Sequence[float],
    y_values: Sequence[float],
    verdicts: Mapping[str, Sequence[str]],
    x_label: str,
    y_label: str,
    title: str,
) -> Figure:
    """Draw a panel per entry of ``verdicts``: each design's verdict as its cell's colour.

    The verdict ("yes", "partly", "no") is also written as a letter in the cell.

    Parameters
    ----------
    x_values : sequence of float
        The slice's values of its first parameter.
    y_values : sequence of float
        The slice's values of its second parameter.
    verdicts : Mapping
        Finding (or "all five") -> one verdict per design, x fastest
        (``len(x) * len(y)`` each).
    x_label : str
        The first parameter in words, with its unit.
    y_label : str
        The second parameter in words, with its unit.
    title : str
        The figure's title (wrapped to the figure's width).

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    order = list(VERDICT_COLOURS)
    colours = ListedColormap([VERDICT_COLOURS[v] for v in order])
    columns = min(3, len(verdicts))
    rows = math.ceil(len(verdicts) / columns)
    figure = Figure(figsize=(3.4 * columns, 2.9 * rows + 1.0), layout="constrained")
    grid = figure.subplots(rows, columns, squeeze=False)
    shape = (len(y_values), len(x_values))
    for axes, (name, values) in zip(grid.flat, verdicts.items(), strict=False):
        codes = np.array([order.index(v) for v in values], dtype=float).reshape(shape)
        axes.pcolormesh(codes, cmap=colours, vmin=-0.5, vmax=len(order) - 0.5, edgecolors="w")
        for (j, i), code in np.ndenumerate(codes):
            axes.text(i + 0.5, j + 0.5, order[int(code)][0].upper(), ha="center", va="center")
        axes.set_xticks(np.arange(len(x_values)) + 0.5, [f"{v:g}" for v in x_values])
        axes.set_yticks(np.arange(len(y_values)) + 0.5, [f"{v:g}" for v in y_values])
        axes.set_xlabel(x_label)
        axes.set_ylabel(y_label)
        axes.set_title(name.replace("_", " "))
    for axes in list(grid.flat)[len(verdicts) :]:
        axes.set_visible(False)
    figure.legend(
        handles=[Patch(color=VERDICT_COLOURS[v], label=v) for v in order],
        loc="outside lower center",
        ncols=len(order),
    )
    figure.suptitle(wrapped_title(title, figure.get_figwidth()))
    return make_legible(figure)
