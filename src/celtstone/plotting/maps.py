"""Maps of a sweep's result fields: a heat map over two varied parameters, a line over
one, a scatter over a list of points.

Each field is named, and drawn in its plot unit, as its ``schema.VARIABLES`` row says;
each varied parameter by its declaration (its ``VARIABLES`` row, else the ``long_name``
and ``units`` the sweep stored with it). A field that takes both signs (the final spin)
is drawn in a diverging colour map centred on zero, so that the line where it changes
sign shows; a count in whole steps; cells without a value are hatched grey and named
in the legend (``Variable.missing``, or "stopped early").
"""

from __future__ import annotations

import re
import textwrap
from typing import TYPE_CHECKING, Any

import numpy as np

from celtstone.plotting.labels import wrapped_title
from celtstone.plotting.legible import make_legible
from celtstone.simulation.outcome import variable as declaration
from celtstone.simulation.schema import VARIABLES

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


__all__ = ["parameter_label", "plot_field_map"]

_SEQUENTIAL = "viridis"
_DIVERGING = "RdBu_r"  # negative blue, positive red, white at zero
_MISSING: dict[str, Any] = {
    "facecolor": "0.85",
    "edgecolor": "0.55",
    "hatch": "///",
    "linewidth": 0.0,
}
_MISSING_MARK = "0.4"  # on a line: an x at zero
_STOPPED = "stopped early (see the status)"
_LABEL_CHARACTERS = 48  # an axis label longer than this is broken between words


def _parameter_words(dataset: xr.Dataset, name: str) -> tuple[str, str]:
    """A varied parameter in words and its unit: its ``VARIABLES`` row if it has one, else
    the ``long_name`` (without its closing remark in parentheses) and ``units`` stored
    with it."""
    if name in VARIABLES:
        declared = VARIABLES[name]
        return declared.label or declared.long_name, declared.plot_unit or declared.unit
    attrs = dataset[name].attrs
    words = str(attrs.get("long_name", name)).split("; ")[0]
    return re.sub(r"\s*\([^()]*\)$", "", words) or name, str(attrs.get("units", ""))


def parameter_label(dataset: xr.Dataset, name: str) -> str:
    """The axis label of the varied parameter ``name``: ``"initial spin omega0 . n0
    [rad/s]"`` (:func:`_parameter_words`), broken between words if long."""
    words, unit = _parameter_words(dataset, name)
    text = f"{words} [{unit}]" if unit not in ("", "1") else words
    return textwrap.fill(text, _LABEL_CHARACTERS)


def _at(dataset: xr.Dataset, names: list[str]) -> str:
    """`` at initial Euler angle alpha = 0.5 deg``: the first value of each of ``names``."""
    said = []
    for name in names:
        words, unit = _parameter_words(dataset, name)
        unit = f" {unit}" if unit not in ("", "1") else ""
        said.append(f"{words} = {float(dataset[name].values[0]):g}{unit}")
    return " at " + ", ".join(said)


def _title(dataset: xr.Dataset, name: str, at: str) -> str:
    label = declaration(name).label or declaration(name).long_name
    attrs = dataset.attrs
    context = [f"{attrs['model']} model" if "model" in attrs else ""]
    context.append(str(attrs.get("body", "")))
    if "t_end" in attrs:
        context.append(f"runs of {float(attrs['t_end']):g} s")
    words = ", ".join(c for c in context if c)
    return label[:1].upper() + label[1:] + (f" ({words})" if words else "") + at


def _colours(values: np.ndarray, name: str) -> dict[str, Any]:
    """``cmap`` and ``norm`` of a field: a diverging map centred on zero where the values
    take both signs, whole steps where they are counts, else viridis."""
    from matplotlib import colormaps
    from matplotlib.colors import BoundaryNorm, CenteredNorm

    finite = values[np.isfinite(values)]
    if finite.size and finite.min() < 0.0 < finite.max():
        return {"cmap": _DIVERGING, "norm": CenteredNorm(vcenter=0.0)}
    if name == "status" or (finite.size and np.all(finite == np.round(finite))):
        low, high = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
        edges = np.arange(low - 0.5, high + 1.0, 1.0)
        base = colormaps["tab10" if name == "status" else _SEQUENTIAL]
        cmap = base.resampled(max(len(edges) - 1, 1))
        return {"cmap": cmap, "norm": BoundaryNorm(edges, cmap.N)}
    return {"cmap": _SEQUENTIAL}


def _missing_kinds(
    status: np.ndarray | None, name: str, values: np.ndarray
) -> dict[str, np.ndarray]:
    """Legend label -> where a cell has no value: the run stopped early (``status``), or
    the field's declared meaning of a missing value."""
    missing = ~np.isfinite(values)
    if not missing.any():
        return {}
    stopped = np.zeros_like(missing) if status is None else (status != "success")
    kinds = {_STOPPED: missing & stopped}
    kinds[declaration(name).missing or "no value"] = missing & ~stopped
    return {label: cells for label, cells in kinds.items() if cells.any()}


def _draw_missing(axes: Axes, x: np.ndarray, y: np.ndarray, cells: np.ndarray) -> None:
    """Hatched grey patches on the cells without a value (``cells`` shaped y by x)."""
    mask = np.ma.masked_where(~cells, np.ones(cells.shape))
    axes.pcolor(x, y, mask, shading="nearest", cmap="Greys", vmin=0.0, vmax=4.0, **_MISSING)


def plot_field_map(dataset: xr.Dataset, name: str) -> Figure:
    """Figure of the sweep field ``name`` over the sweep's dimensions (beyond two, the
    first value of each further dimension); ``status`` as categories.

    Parameters
    ----------
    dataset : xarray.Dataset
        A sweep's results (``Sweep.run``, ``open_sweep``).
    name : str
        A result field (``outcome.OUTCOMES``).

    Returns
    -------
    matplotlib.figure.Figure
        The figure: the field's values in colour (a line over a single parameter), cells
        without a value hatched and named in the legend.
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    declared = declaration(name)
    variable = dataset[name]
    at = ""
    ticks: list[str] | None = None
    if name == "status":
        labels = [str(v) for v in np.ravel(variable.values)]
        ticks = sorted(set(labels))
        codes = np.array([ticks.index(v) for v in labels], dtype=float)
        variable = variable.copy(data=codes.reshape(variable.shape))
    else:
        variable = variable.astype(float) * declared.plot_scale
    dims = [str(d) for d in variable.dims]
    rest = {d: 0 for d in dims[2:]}
    if rest:
        variable = variable.isel(rest)
        at = _at(dataset, list(rest))
        dims = dims[:2]
    values = np.asarray(variable.values, dtype=float)
    status = np.asarray(dataset["status"].isel(rest).values) if "status" in dataset else None
    figure = Figure(figsize=(6.4, 4.8), layout="constrained")
    axes = figure.add_subplot()
    mesh: Any = None
    missing = _missing_kinds(status, name, values)
    colours = _colours(values, name)
    if dims == ["point"]:
        names = [str(c) for c in dataset.coords if c != "point"]
        x = dataset[names[0]].values
        y = dataset[names[1]].values if len(names) > 1 else np.zeros_like(x)
        for cells in missing.values():
            axes.scatter(x[cells], y[cells], marker="X", color=_MISSING["edgecolor"])
        mesh = axes.scatter(x, y, c=values, **colours)
        axes.set_xlabel(parameter_label(dataset, names[0]))
        if len(names) > 1:
            axes.set_ylabel(parameter_label(dataset, names[1]))
    elif len(dims) == 1:
        x = dataset[dims[0]].values
        axes.plot(x, values, marker=".")
        for cells in missing.values():
            axes.plot(x[cells], np.zeros(int(cells.sum())), "x", color=_MISSING_MARK)
        axes.set_xlabel(parameter_label(dataset, dims[0]))
        axes.set_ylabel(declared.axis_label())
    else:
        x, y = dataset[dims[1]].values, dataset[dims[0]].values
        for cells in missing.values():
            _draw_missing(axes, x, y, cells)
        mesh = axes.pcolormesh(x, y, values, shading="nearest", **colours)
        axes.set_xlabel(parameter_label(dataset, dims[1]))
        axes.set_ylabel(parameter_label(dataset, dims[0]))
    if mesh is not None:
        colorbar = figure.colorbar(mesh, ax=axes, label=declared.axis_label())
        if ticks is not None:
            colorbar.set_ticks(range(len(ticks)), labels=ticks)
        elif "norm" in colours and hasattr(colours["norm"], "boundaries"):
            bounds = colours["norm"].boundaries
            colorbar.set_ticks(list(_whole_ticks(bounds[:-1] + 0.5)))
    if missing:
        handles = [
            Patch(label=label, **_MISSING) if len(dims) == 2 else _marker(label, len(dims))
            for label in missing
        ]
        figure.legend(handles=handles, loc="outside lower center", ncols=len(handles))
    title = _title(dataset, name, at)
    axes.set_title(wrapped_title(title, 0.8 * figure.get_figwidth(), "large"))
    return make_legible(figure)


def _marker(label: str, dimensions: int) -> Any:
    """The legend entry of points without a value: on a line (one dimension) or among
    a list of points."""
    from matplotlib.lines import Line2D

    marker, colour = ("x", _MISSING_MARK) if dimensions == 1 else ("X", _MISSING["edgecolor"])
    return Line2D([], [], linestyle="none", marker=marker, color=colour, label=label)


def _whole_ticks(levels: np.ndarray, most: int = 8) -> np.ndarray:
    """At most ``most`` of the whole-number ``levels``, evenly picked."""
    step = max(1, int(np.ceil(len(levels) / most)))
    return levels[::step]
