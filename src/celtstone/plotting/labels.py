"""Axis labels with units, and the words that name a run in titles and legends."""

from __future__ import annotations

import xarray as xr

__all__ = ["axis_label", "run_label", "run_title"]

_SYMBOLS = {
    "time": ("time $t$", "s"),
    "spin": (r"spin $\omega\cdot n$", "rad/s"),
    "tilt": ("tilt of body axis 3", "deg"),
    "energy": ("energy $E$", "J"),
    "slip_speed": ("slip speed $|V_1|$", "m/s"),
    "normal_force": ("normal force $N$", "N"),
    "dissipated_work": ("friction work", "J"),
    "friction_coefficient": ("friction coefficient $f$", "1"),
    "contact_x": ("contact point $x$", "m"),
    "contact_y": ("contact point $y$", "m"),
}


def axis_label(name: str) -> str:
    """``"spin ω·n [rad/s]"`` for a variable name."""
    text, unit = _SYMBOLS[name]
    return f"{text} [{unit}]" if unit != "1" else text


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
