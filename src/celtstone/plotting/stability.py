"""Growth rates of the pitch and roll modes against steady spin (linear stability).

The figure is returned; ``plotting.save_figure`` writes it whole or not at all.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from celtstone.plotting.labels import wrapped_title
from celtstone.plotting.legible import make_legible
from celtstone.stability import SpinStability

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["growth_rate_figure"]


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
    title = (
        f"Linear stability of steady spin: {result.body.name}\n"
        f"rolling model, damping σ = {result.model.damping:g} N m s; "
        f"preferred sense: {direction}"
    )
    axes.set_title(wrapped_title(title, 0.9 * figure.get_figwidth(), "large"))
    axes.legend()
    axes.grid(True, linewidth=0.4, alpha=0.5)
    return make_legible(figure)
