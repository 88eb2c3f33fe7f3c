"""Figures of runs, comparisons and sweeps, drawn with matplotlib's object API.

No pyplot and no global backend: every function returns a
:class:`matplotlib.figure.Figure`; :func:`save_figure` writes it (PNG or SVG)
whole or not at all.
"""

from celtstone.plotting.atlas import plot_verdict_maps as plot_verdict_maps
from celtstone.plotting.compare import plot_energy_budget as plot_energy_budget
from celtstone.plotting.compare import plot_spin_comparison as plot_spin_comparison
from celtstone.plotting.fit import FitPanel as FitPanel
from celtstone.plotting.fit import FittedValue as FittedValue
from celtstone.plotting.fit import plot_fit as plot_fit
from celtstone.plotting.run import plot_run as plot_run
from celtstone.plotting.save import FIGURE_FORMATS as FIGURE_FORMATS
from celtstone.plotting.save import save_figure as save_figure
from celtstone.plotting.save import save_figure_formats as save_figure_formats
from celtstone.plotting.threshold import plot_threshold as plot_threshold

__all__ = [
    "FIGURE_FORMATS",
    "FitPanel",
    "FittedValue",
    "plot_energy_budget",
    "plot_fit",
    "plot_run",
    "plot_spin_comparison",
    "plot_threshold",
    "plot_verdict_maps",
    "save_figure",
    "save_figure_formats",
]
