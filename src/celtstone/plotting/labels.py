"""Axis labels with units, and the words that name a run in titles and legends."""

from __future__ import annotations

import xarray as xr

from celtstone.schema import VARIABLES

__all__ = ["axis_label", "run_label", "run_title"]


def axis_label(name: str) -> str:
    """``"spin ω·n [rad/s]"`` for a variable name (``schema.VARIABLES``)."""
    return VARIABLES[name].axis_label()


def run_label(dataset: xr.Dataset) -> str:
    """Short legend entry: ``rolling`` or ``sliding f = 0.35, N = m g``."""
    attrs = dataset.attrs
    if attrs["model"] != "sliding":
        return str(attrs["model"])
    normal = "N = m g" if attrs["normal_force_option"] == "static" else "dynamic N"
    return f"sliding f = {float(attrs['friction_coefficient']):g}, {normal}"


def run_title(dataset: xr.Dataset) -> str:
    """Title naming the body, the model and the start."""
    attrs = dataset.attrs
    return f"{attrs['body']}: {run_label(dataset)}; ω0 = {attrs['initial_omega']} rad/s"
