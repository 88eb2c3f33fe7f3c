"""Axis labels with units, and the words that name a run in titles and legends."""

from __future__ import annotations

from typing import TYPE_CHECKING

from celtstone.schema import VARIABLES, current_attributes

if TYPE_CHECKING:
    import xarray as xr


__all__ = ["axis_label", "run_label", "run_title"]


def axis_label(name: str) -> str:
    """``"spin ω·n [rad/s]"`` for a variable name (``schema.VARIABLES``)."""
    return VARIABLES[name].axis_label()


def run_label(dataset: xr.Dataset) -> str:
    """Short legend entry: ``rolling`` or ``sliding f = 0.35, N = m g``."""
    attrs = current_attributes(dataset.attrs)  # a file written before the rename too
    if attrs["model"] != "sliding":
        return str(attrs["model"])
    normal = "N = m g" if attrs["friction_load"] == "static" else "dynamic N"
    return f"sliding f = {float(attrs['friction_coefficient']):g}, {normal}"


def run_title(dataset: xr.Dataset) -> str:
    """Title naming the body, the model and the start."""
    attrs = dataset.attrs
    return f"{attrs['body']}: {run_label(dataset)}; ω0 = {attrs['initial_omega']} rad/s"
