"""Reading a run file back for drawing, with a clear error for anything else."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from celtstone.errors import ParameterError
from celtstone.export import MIN_SAMPLES, read_run

if TYPE_CHECKING:
    import xarray as xr


__all__ = ["REQUIRED_VARIABLES", "check_run", "default_label", "load_run"]

# what the scene and the plots read (schema.VARIABLES names)
REQUIRED_VARIABLES = (
    "spin",
    "tilt",
    "energy",
    "slip_speed",
    "n",
    "quaternion",
    "com_position",
    "com_height",
    "contact_position",
)
_ALLOWED = "a NetCDF file written by `celtstone run --out RUN.nc`"


def check_run(dataset: xr.Dataset, name: str = "run") -> xr.Dataset:
    """``dataset`` if it holds a run's variables and body attributes, else ParameterError."""
    missing = [v for v in REQUIRED_VARIABLES if v not in dataset.variables]
    missing += [a for a in ("body_shape", "body_shape_parameters") if a not in dataset.attrs]
    if missing:
        raise ParameterError(
            name, dataset.attrs.get("title", "dataset"), _ALLOWED, f"it lacks {', '.join(missing)}"
        )
    if dataset.sizes.get("time", 0) < MIN_SAMPLES:
        raise ParameterError(
            name,
            dataset.attrs.get("title", "dataset"),
            f"a run with at least {MIN_SAMPLES} samples",
        )
    return dataset


def load_run(path: str | Path) -> xr.Dataset:
    """Load the run saved at ``path`` (NetCDF) and check it holds what drawing needs.

    Parameters
    ----------
    path : str or pathlib.Path
        The NetCDF file (``celtstone run --out RUN.nc``).

    Returns
    -------
    xarray.Dataset
        The run, loaded into memory (:func:`celtstone.export.read_run`).
    """
    return check_run(read_run(path))


def default_label(dataset: xr.Dataset) -> str:
    """A title from the run's attributes.

    E.g. ``"sliding — kane_levinson_1982, f = 0.35, ε = 1 mm"``.
    """
    attrs = dataset.attrs
    label = f"{attrs.get('model', 'run')} — {attrs.get('body', '')}"
    if attrs.get("model") == "sliding":
        label += (
            f", f = {float(attrs['friction_coefficient']):g},"
            f" ε = {1e3 * float(attrs['contact_radius']):g} mm"
        )
    return label
