"""Maps of a sweep's result fields: a heat map over two varied parameters, a line over
one, a scatter over a list of points."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from celtstone.plotting.labels import wrapped_title
from celtstone.schema import VARIABLES

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure


__all__ = ["plot_field_map"]


def _label(variable: xr.DataArray, name: object) -> str:
    """A parameter's axis label from its ``units`` attribute: ``"spin [rad/s]"``."""
    unit = variable.attrs.get("units", "")
    return f"{name} [{unit}]" if unit else str(name)


def plot_field_map(dataset: xr.Dataset, name: str) -> Figure:
    """Figure of the sweep field ``name`` over the sweep's dimensions (beyond two, the
    first value of each further dimension); ``status`` as categories.

    The field is labelled, and drawn in its plot unit, as its ``schema.VARIABLES`` row
    says; the varied parameters by their ``units`` attribute.
    """
    from matplotlib.figure import Figure

    declared = VARIABLES[name]
    variable = dataset[name]
    title = name
    ticks: list[str] | None = None
    if name == "status":
        labels = [str(v) for v in np.ravel(variable.values)]
        ticks = sorted(set(labels))
        codes = np.array([ticks.index(v) for v in labels], dtype=float)
        variable = variable.copy(data=codes.reshape(variable.shape))
    else:
        variable = variable.astype(float) * declared.plot_scale
    figure = Figure(figsize=(6.4, 4.8), layout="constrained")
    axes = figure.add_subplot()
    dims = [str(d) for d in variable.dims]
    mesh: Any = None
    if dims == ["point"]:
        names = [str(c) for c in dataset.coords if c != "point"]
        x = dataset[names[0]].values
        y = dataset[names[1]].values if len(names) > 1 else np.zeros_like(x)
        mesh = axes.scatter(x, y, c=variable.values, cmap="viridis")
        axes.set_xlabel(_label(dataset[names[0]], names[0]))
        if len(names) > 1:
            axes.set_ylabel(_label(dataset[names[1]], names[1]))
    elif len(dims) == 1:
        axes.plot(dataset[dims[0]].values, variable.values, marker=".")
        axes.set_xlabel(_label(dataset[dims[0]], dims[0]))
        axes.set_ylabel(declared.axis_label())
    else:
        if len(dims) > 2:
            rest = {d: 0 for d in dims[2:]}
            variable = variable.isel(rest)
            title += " at " + ", ".join(f"{d} = {dataset[d].values[0]:g}" for d in dims[2:])
        mesh = axes.pcolormesh(
            dataset[dims[1]].values,
            dataset[dims[0]].values,
            variable.values,
            shading="nearest",
            cmap="viridis",
        )
        axes.set_xlabel(_label(dataset[dims[1]], dims[1]))
        axes.set_ylabel(_label(dataset[dims[0]], dims[0]))
    if mesh is not None:
        colorbar = figure.colorbar(mesh, ax=axes, label=declared.axis_label())
        if ticks is not None:
            colorbar.set_ticks(range(len(ticks)), labels=ticks)
    axes.set_title(wrapped_title(title, 0.8 * figure.get_figwidth(), "large"))
    return figure
