"""A fit at a glance: each measured series with the fitted model against time, and the
residuals beneath it."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from celtstone.plotting.labels import axis_label, wrapped_title

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["FitPanel", "plot_fit"]


@dataclass(frozen=True)
class FitPanel:
    """One series of a fit, as drawn.

    Parameters
    ----------
    label : str
        The series' name with its plotted unit.
    measured : numpy.ndarray
        Measured values in that unit, shape (m,).
    fitted : numpy.ndarray
        Fitted model's values in that unit, shape (m,).
    """

    label: str
    measured: np.ndarray
    fitted: np.ndarray


def plot_fit(times: np.ndarray, panels: Sequence[FitPanel], title: str = "") -> Figure:
    """Draw data (dots) and fitted model (line) against time, residuals beneath each series.

    Parameters
    ----------
    times : numpy.ndarray
        Sample times [s], shape (m,).
    panels : sequence of FitPanel
        The series, one panel each; residuals are model − data.
    title : str, optional
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(10.0, 1.0 + 3.6 * len(panels)), layout="constrained")
    ratios = [3, 1] * len(panels)
    grid = figure.subplots(2 * len(panels), 1, sharex=True, height_ratios=ratios, squeeze=False)
    for index, panel in enumerate(panels):
        values, residual = grid[2 * index, 0], grid[2 * index + 1, 0]
        values.plot(times, panel.measured, ".", markersize=2.0, color="0.5", label="data")
        values.plot(times, panel.fitted, color="tab:blue", linewidth=1.2, label="fitted model")
        values.set_ylabel(panel.label)
        values.legend(loc="upper right", fontsize="small")
        residual.plot(times, panel.fitted - panel.measured, ".", markersize=2.0, color="tab:red")
        residual.axhline(0.0, color="black", linewidth=0.5)
        residual.set_ylabel("model − data")
        for axes in (values, residual):
            axes.grid(alpha=0.3)
    grid[-1, 0].set_xlabel(axis_label("time"))
    if title:
        figure.suptitle(wrapped_title(title, figure.get_figwidth()))
    return figure
