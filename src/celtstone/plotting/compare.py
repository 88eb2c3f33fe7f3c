"""Several runs side by side: spin against time (Figures 2 and 3), energy budget."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from celtstone.plotting.labels import axis_label, run_label, wrapped_title
from celtstone.plotting.legible import make_legible
from celtstone.simulation.reversals import dataset_reversal_times

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure


__all__ = ["plot_energy_budget", "plot_spin_comparison"]

_STYLES = ("-", "--", ":", "-.")


def plot_spin_comparison(
    panels: Sequence[Sequence[xr.Dataset]],
    title: str,
    threshold: float | None = None,
    columns: int = 2,
) -> Figure:
    """Draw spin against time, one panel per group of runs overlaid; reversals marked.

    Parameters
    ----------
    panels : sequence of sequence of xarray.Dataset
        ``panels[i]`` holds the runs drawn in panel i (e.g. one friction coefficient
        with N = m g and with the dynamic normal force).
    title : str
        The figure's title.
    threshold : float, optional
        Band of the reversals [rad/s], dotted lines in each run's colour; default from
        each run's initial spin.
    columns : int, optional
        Panels per row.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.figure import Figure

    rows = -(-len(panels) // columns)
    figure = Figure(figsize=(5.5 * columns, 3.2 * rows + 0.6), layout="constrained")
    grid = np.atleast_1d(figure.subplots(rows, columns, sharey=True, squeeze=False)).ravel()
    for axes, runs in zip(grid, panels, strict=False):
        marked = False  # one legend entry for the reversals: dotted, in their run's colour
        for index, dataset in enumerate(runs):
            (line,) = axes.plot(
                dataset["time"].values,
                dataset["spin"].values,
                linestyle=_STYLES[index % len(_STYLES)],
                linewidth=1.0,
                label=run_label(dataset),
            )
            for time in dataset_reversal_times(dataset, threshold):
                axes.axvline(
                    float(time),
                    color=line.get_color(),
                    linestyle=":",
                    linewidth=1.0,
                    label="_nolegend_" if marked else "reversal (dotted, in its run's colour)",
                )
                marked = True
        axes.axhline(0.0, color="black", linewidth=0.5)
        axes.set_xlabel(axis_label("time"))
        axes.set_ylabel(axis_label("spin"))
        axes.grid(alpha=0.3)
        axes.legend(fontsize="small")
    for axes in grid[len(panels) :]:
        axes.set_visible(False)
    figure.suptitle(wrapped_title(title, figure.get_figwidth()))
    return make_legible(figure)


def plot_energy_budget(runs: Sequence[xr.Dataset], title: str) -> Figure:
    """Draw energy against time; energy lost beside the friction work; their difference.

    The third panel is the budget's residual |E(0) − E(t) − W(t)| [J] on a log
    scale: it shows the integrator's error, not physics.

    Parameters
    ----------
    runs : sequence of xarray.Dataset
        Sliding runs (they carry the friction work).
    title : str
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(15.0, 4.2), layout="constrained")
    energy_axes, budget_axes, residual_axes = figure.subplots(1, 3)
    for dataset in runs:
        time = dataset["time"].values
        energy = dataset["energy"].values
        work = dataset["dissipated_work"].values
        label = run_label(dataset)
        (line,) = energy_axes.plot(time, energy, linewidth=1.0, label=label)
        budget_axes.plot(time, energy[0] - energy, color=line.get_color(), label=f"lost: {label}")
        budget_axes.plot(time, work, color="black", linestyle=":", linewidth=1.0)
        residual = np.abs(energy[0] - energy - work)
        residual_axes.semilogy(
            time, np.maximum(residual, 1e-18), color=line.get_color(), linewidth=0.8, label=label
        )
    budget_axes.plot([], [], color="black", linestyle=":", label="friction work (each run)")
    energy_axes.set_ylabel(axis_label("energy"))
    budget_axes.set_ylabel("energy lost $E(0)-E(t)$, friction work $W$ [J]")
    residual_axes.set_ylabel("budget residual $|E(0)-E-W|$ [J]")
    for axes in (energy_axes, budget_axes, residual_axes):
        axes.set_xlabel(axis_label("time"))
        axes.grid(alpha=0.3)
        axes.legend(fontsize="small")
    figure.suptitle(wrapped_title(title, figure.get_figwidth()))
    return make_legible(figure)
