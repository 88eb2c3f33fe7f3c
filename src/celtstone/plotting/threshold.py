"""The friction threshold: reversal time and final energy against f."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from celtstone.plotting.labels import axis_label, wrapped_title
from celtstone.plotting.legible import make_legible

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure


__all__ = ["plot_threshold"]


def plot_threshold(table: pd.DataFrame, title: str, boundaries: Sequence[float] = ()) -> Figure:
    """Draw two panels against ``friction_coefficient``: first reversal time, final energy.

    Parameters
    ----------
    table : pandas.DataFrame
        Needs the columns ``friction_coefficient`` [1], ``first_reversal_time`` [s]
        (NaN: no reversal), ``energy_final`` [J] and ``energy_rest`` [J].
    title : str
        The figure's title.
    boundaries : sequence of float, optional
        The bisected f where reversal appears or disappears [1], drawn as vertical lines.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(11.0, 4.4), layout="constrained")
    time_axes, energy_axes = figure.subplots(1, 2, sharex=True)
    f = table["friction_coefficient"].to_numpy(dtype=float)
    reversal = table["first_reversal_time"].to_numpy(dtype=float)
    reverses = np.isfinite(reversal)
    time_axes.plot(f[reverses], reversal[reverses], "o-", label="first reversal")
    time_axes.plot(
        f[~reverses],
        np.zeros(int(np.count_nonzero(~reverses))),
        "x",
        color="tab:red",
        label="no reversal in the run",
    )
    time_axes.set_ylabel("first reversal time [s]")
    energy_axes.plot(f, table["energy_final"].to_numpy(dtype=float), "o-", label="end of run")
    energy_axes.axhline(
        float(table["energy_rest"].iloc[0]),
        color="black",
        linestyle="--",
        linewidth=0.8,
        label="at rest, m g l",
    )
    energy_axes.set_ylabel(axis_label("energy"))
    for axes in (time_axes, energy_axes):
        for index, value in enumerate(boundaries):
            axes.axvline(
                value,
                color="tab:purple",
                linestyle=":",
                label="threshold (bisection)" if index == 0 else "_nolegend_",
            )
        axes.set_xlabel(axis_label("friction_coefficient"))
        axes.grid(alpha=0.3)
        axes.legend(fontsize="small")
    figure.suptitle(wrapped_title(title, figure.get_figwidth()))
    return make_legible(figure)
