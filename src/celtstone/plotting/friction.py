"""The friction laws of the contact disk (``contact.LAWS``) against the slip ratio u."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from celtstone.contact import LAWS, friction_functions
from celtstone.plotting.legible import make_legible

if TYPE_CHECKING:
    from matplotlib.figure import Figure

LINE_STYLES = ("--", "-", ":", "-.")  # one per law, in the order of ``contact.LAWS``


def friction_law_figure(pressure: str = "hertz") -> Figure:
    """Every registered law's F/(fN) and M/(fNε) against u on a logarithmic axis.

    Parameters
    ----------
    pressure : "hertz" (paper eq. 2) or "uniform"

    The functions are those a run evaluates (``contact.friction_functions``), at 601
    slip ratios u = |V1| / (ε |Ω_n|) from 1e-3 to 1e3.
    """
    from matplotlib.figure import Figure

    u = np.logspace(-3, 3, 601)
    figure = Figure(figsize=(9.0, 3.8), layout="constrained")
    force_axes, moment_axes = figure.subplots(1, 2, sharex=True)
    for index, entry in enumerate(LAWS.values()):
        force, moment = friction_functions(u, entry.name, pressure)
        style = LINE_STYLES[index % len(LINE_STYLES)]
        force_axes.plot(u, force, style, label=entry.label)
        moment_axes.plot(u, moment, style, label=entry.label)
    force_axes.set_ylabel("friction force F / (f N)")
    moment_axes.set_ylabel("pivoting moment M / (f N ε)")
    for axes in (force_axes, moment_axes):
        axes.set_xscale("log")
        axes.set_xlabel("slip ratio u = |V1| / (ε |Ω_n|)")
        axes.grid(True, which="both", alpha=0.3)
        axes.legend()
    figure.suptitle(f"Coulomb–Contensou friction on a disk, {pressure} pressure")
    return make_legible(figure)
