"""One run at a glance: spin, tilt, energy, slip speed, normal force, contact track."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from celtstone.plotting.labels import axis_label, run_title, wrapped_title
from celtstone.plotting.legible import make_legible
from celtstone.simulation.reversals import dataset_reversal_times

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


__all__ = ["mark_reversals", "plot_run"]

_TIME_PANELS = ("spin", "tilt", "energy", "slip_speed", "normal_force")
# below this spread relative to |E(0)| the energy is constant to the eye, and its ticks
# would need more digits than a reader can compare: the panel shows the relative drift
_CONSTANT_ENERGY = 1e-4


def mark_reversals(axes: Axes, times: Sequence[float] | np.ndarray, color: str = "0.4") -> None:
    """Dashed vertical lines at the reversal times [s], labelled once in the legend."""
    for index, time in enumerate(times):
        axes.axvline(
            float(time),
            color=color,
            linestyle="--",
            linewidth=0.8,
            label="reversal" if index == 0 else "_nolegend_",
        )


def _values(dataset: xr.Dataset, name: str) -> tuple[np.ndarray, str]:
    """The values of panel ``name`` as drawn, and their axis label."""
    values = np.asarray(dataset[name].values, dtype=float)
    if name == "tilt":
        return np.degrees(values), axis_label(name)
    if name == "energy" and _is_constant(values):
        return (values - values[0]) / abs(values[0]), "relative energy drift $(E-E_0)/E_0$"
    return values, axis_label(name)


def _is_constant(energy: np.ndarray) -> bool:
    """Whether ``energy`` [J] spreads less than ``_CONSTANT_ENERGY`` of its start."""
    spread = float(np.ptp(energy))
    return energy[0] != 0.0 and spread < _CONSTANT_ENERGY * abs(float(energy[0]))


def plot_run(dataset: xr.Dataset, threshold: float | None = None) -> Figure:
    """Draw six panels of a run; reversals marked.

    Panels: spin, tilt, energy (with the energy lost beside the friction work in
    sliding), slip speed and normal force against time, and the contact point's
    track on the plane. An energy constant to 1e-4 of its start (rolling) is drawn
    as its relative drift (E − E0)/E0, the integrator's error.

    Parameters
    ----------
    dataset : xarray.Dataset
        A run (``Trajectory.dataset`` or :func:`celtstone.files.export.read_run`).
    threshold : float, optional
        Hysteresis band of the reversals [rad/s]; default from the initial spin.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(11.0, 10.0), layout="constrained")
    grid = figure.subplots(3, 2)
    time = dataset["time"].values
    reversals = dataset_reversal_times(dataset, threshold)
    for axes, name in zip(grid.flat, _TIME_PANELS, strict=False):
        values, label = _values(dataset, name)
        axes.plot(time, values, linewidth=1.0, label=name.replace("_", " "))
        if name == "spin":
            axes.axhline(0.0, color="black", linewidth=0.5)
            mark_reversals(axes, reversals)
        axes.set_xlabel(axis_label("time"))
        axes.set_ylabel(label)
        axes.grid(alpha=0.3)
    energy_axes = grid.flat[2]
    lost = dataset["energy"].values[0] - dataset["energy"].values
    if np.any(dataset["dissipated_work"].values != 0.0):
        twin = energy_axes.twinx()
        twin.plot(time, lost, color="tab:red", linewidth=1.0, label="energy lost")
        twin.plot(
            time,
            dataset["dissipated_work"].values,
            color="black",
            linestyle=":",
            linewidth=1.2,
            label="friction work",
        )
        twin.set_ylabel("energy lost, friction work [J]")
        twin.legend(fontsize="small")
    track = grid.flat[5]
    contact = dataset["contact_position"].values
    track.plot(contact[:, 0], contact[:, 1], linewidth=0.8, label="contact point")
    track.plot(contact[:1, 0], contact[:1, 1], "o", color="tab:green", label="start")
    track.plot(contact[-1:, 0], contact[-1:, 1], "s", color="tab:red", label="end")
    track.set_aspect("equal", adjustable="datalim")
    track.set_xlabel(axis_label("contact_x"))
    track.set_ylabel(axis_label("contact_y"))
    track.grid(alpha=0.3)
    for axes in grid.flat:
        if len(axes.get_legend_handles_labels()[0]) > 1:  # one curve: its axis label says it
            axes.legend(fontsize="small")
    figure.suptitle(wrapped_title(run_title(dataset), figure.get_figwidth()))
    return make_legible(figure)
