"""Profile likelihood of one fitted parameter: the cost with that parameter held at each
value of a grid and the others refitted.

With Gaussian noise, 2 (cost(θ) − cost_min) / s² follows χ² with one degree of freedom;
the 95 % interval is where it stays below ``CHI2_95`` (3.841). Unlike θ ± 1.96 SE it
follows a cost that is not quadratic (a bound, a curved valley).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from celtstone.fitting.runs import Runs

__all__ = ["CHI2_95", "Profile", "profile_likelihood"]

CHI2_95 = 3.841458820694124  # 95 % quantile of χ² with 1 degree of freedom
PROFILE_POINTS = 11
PROFILE_SPAN = 4.0  # the grid reaches this many standard errors either side


@dataclass(frozen=True)
class Profile:
    """The profile of ``name``: ``values`` [its unit], ``costs`` [1] and ``statistic``
    2 Δcost / s² [1]; ``interval`` the 95 % interval [its unit], an end None where the
    statistic stays below ``CHI2_95`` up to the grid's end (open there)."""

    name: str
    values: np.ndarray
    costs: np.ndarray
    statistic: np.ndarray
    interval: tuple[float | None, float | None]

    def summary(self) -> dict[str, Any]:
        return {
            "parameter": self.name,
            "values": self.values.tolist(),
            "costs": self.costs.tolist(),
            "statistic": self.statistic.tolist(),
            "interval_95": list(self.interval),
            "threshold": CHI2_95,
        }


def _crossing(values: np.ndarray, statistic: np.ndarray, indices: range) -> float | None:
    """Where ``statistic`` first rises through CHI2_95 walking ``indices`` from the optimum."""
    previous = None
    for i in indices:
        if previous is not None and statistic[i] >= CHI2_95 > statistic[previous]:
            share = (CHI2_95 - statistic[previous]) / (statistic[i] - statistic[previous])
            return float(values[previous] + share * (values[i] - values[previous]))
        previous = i
    return None


def profile_likelihood(
    runs: Runs,
    refit: Callable[[np.ndarray, list[int]], tuple[np.ndarray, float]],
    best: np.ndarray,
    index: int,
    standard_error: float,
    variance: float,
    points: int = PROFILE_POINTS,
) -> Profile:
    """Profile parameter ``index`` about the optimum ``best``.

    ``refit(x, free_columns)`` minimises over ``free_columns`` from ``x`` and returns the
    optimum and its cost; the grid spans ``PROFILE_SPAN`` standard errors (the bounds
    where the error is infinite), cut to the bounds, with the optimum in it.
    """
    problem = runs.problem
    lower, upper = problem.lower[index], problem.upper[index]
    centre = best[index]
    if np.isfinite(standard_error) and standard_error > 0.0:
        span = PROFILE_SPAN * standard_error
        grid = np.linspace(max(lower, centre - span), min(upper, centre + span), points)
    else:
        grid = np.linspace(lower, upper, points)
    grid = np.unique(np.append(grid, centre))
    others = [j for j in range(best.size) if j != index]
    start = int(np.searchsorted(grid, centre))
    costs = np.empty(grid.size)
    # walk outwards from the optimum, each point starting from its neighbour's optimum
    for order in (range(start, grid.size), range(start, -1, -1)):
        x = best.copy()
        for i in order:
            x[index] = grid[i]
            if others:
                x, costs[i] = refit(x, others)
            else:
                residuals = runs.residuals(x)
                costs[i] = 0.5 * float(residuals @ residuals)
    statistic = 2.0 * (costs - costs.min()) / variance
    interval = (
        _crossing(grid, statistic, range(start, -1, -1)),
        _crossing(grid, statistic, range(start, grid.size)),
    )
    return Profile(problem.names[index], grid, costs, statistic, interval)
