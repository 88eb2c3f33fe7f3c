"""Growth rates of the pitch and roll modes against steady spin (linear stability).

Figures are returned, not written: callers save them whole with ``export.atomic_path``
(``celtstone stability --plot`` does), since plotting and export are sibling layers.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from celtstone.analysis.stability import SpinStability
from celtstone.errors import ParameterError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["PLOT_FORMATS", "check_plot_target", "growth_rate_figure"]

PLOT_FORMATS = (".png", ".svg")


def check_plot_target(path: str | Path) -> Path:
    """``path`` as a :class:`Path` if a figure can be written there (.png or .svg, existing dir).

    Raises
    ------
    ParameterError
        for another suffix or a directory that does not exist.
    """
    target = Path(path)
    if target.suffix.lower() not in PLOT_FORMATS:
        allowed = "a file name ending in " + " or ".join(PLOT_FORMATS)
        raise ParameterError("plot", str(path), allowed)
    directory = target.parent if str(target.parent) else Path(".")
    if not directory.is_dir():
        raise ParameterError("plot", str(path), "a file in an existing directory")
    return target


def growth_rate_figure(result: SpinStability) -> Figure:
    """Figure of the growth rates Re λ [1/s] of the pitch and roll modes against spin [rad/s].

    A positive growth rate means the steady spin is unstable in that mode.
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(7.0, 4.5), layout="constrained")
    axes = figure.add_subplot()
    axes.axhline(0.0, color="0.6", linewidth=0.8, label="_neutral")
    axes.plot(result.spin, result.growth_rate_pitch, color="C0", label="pitch mode")
    axes.plot(result.spin, result.growth_rate_roll, color="C1", label="roll mode")
    axes.set_xlabel("spin ω·n [rad/s]")
    axes.set_ylabel("growth rate Re λ [1/s]")
    direction = {1: "positive", -1: "negative", 0: "neither"}[result.preferred_direction]
    axes.set_title(
        f"Linear stability of steady spin: {result.body.name}\n"
        f"rolling model, damping σ = {result.model.damping:g} N m s; "
        f"preferred sense: {direction}"
    )
    axes.legend()
    axes.grid(True, linewidth=0.4, alpha=0.5)
    return figure
