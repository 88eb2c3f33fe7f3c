"""One map per result field of a finished sweep, as PNG files (matplotlib, Agg).

Two grid axes give a heat map (first axis vertical, second horizontal); one axis a
curve; more axes a heat map over the first two at the first value of the others (the
title says which). A list of points gives a scatter over its first two parameters.
``status`` is drawn as categories; ``message`` is text and is not drawn.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from celtstone.export import atomic_path

__all__ = ["MAPPED_FIELDS", "write_maps"]

MAPPED_FIELDS = (
    "first_reversal_time",
    "n_reversals",
    "final_spin",
    "energy_lost",
    "max_tilt",
    "min_normal_force",
    "t_stop",
    "status",
)


def _label(variable: xr.DataArray, name: object) -> str:
    unit = variable.attrs.get("units", "")
    return f"{name} [{unit}]" if unit else str(name)


def write_maps(dataset: xr.Dataset, directory: str | Path) -> list[Path]:
    """Write ``<field>.png`` for each of ``MAPPED_FIELDS`` into ``directory``; return the paths."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    target = Path(directory)
    target.mkdir(parents=True, exist_ok=True)
    written = []
    for name in MAPPED_FIELDS:
        variable = dataset[name]
        title = name
        ticks: list[str] | None = None
        if name == "status":
            labels = [str(v) for v in np.ravel(variable.values)]
            ticks = sorted(set(labels))
            codes = np.array([ticks.index(v) for v in labels], dtype=float)
            variable = variable.copy(data=codes.reshape(variable.shape))
        else:
            variable = variable.astype(float)
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
            axes.set_ylabel(_label(dataset[name], name))
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
            colorbar = figure.colorbar(mesh, ax=axes, label=_label(dataset[name], name))
            if ticks is not None:
                colorbar.set_ticks(range(len(ticks)), labels=ticks)
        axes.set_title(title)
        path = target / f"{name}.png"
        with atomic_path(path) as temporary:
            figure.savefig(temporary, format="png", dpi=100)
        written.append(path)
    return written
