"""Each physical number's 95 % interval from its profile likelihood where the cost is not
quadratic about the optimum, or where the record cannot be trusted to make it so.

The curvature's interval θ̂ ± 1.96 σ holds for a quadratic cost. A spin-only record's
cost can change shape within the interval (f and the gyroscope's bias trade against
each other along a curved valley): there the curvature at the optimum can understate
it. So each physical number's cost is
checked at ± ``CHECK_STEPS`` σ along its linearised profile (the number moved, the others
to their linearised conditional optimum; one run each, all in parallel): where the
statistic 2 Δcost / s² there is off the quadratic's ``CHECK_STEPS``² by more than
``QUADRATIC_TOLERANCE`` of it, or where the caller asks (other minima were found, or a
record of one series), the profile is walked out from the optimum in steps of
``WALK_STEP`` σ, the others refitted at each, until the statistic crosses the joint
region's level χ²_k(0.95) (k the physical numbers; ``CHI2_95`` for one), or a bound is
met (the end there). Each crossing is interpolated linearly in the statistic's square
root, which is linear in θ for a quadratic cost. The crossing of ``CHI2_95`` is the
number's 95 % interval; that of χ²_k(0.95) is the shadow on its axis of the joint 95 %
likelihood region of the k numbers (the profile's minimum over the others is the
region's projection). A walk that finds a cost below the optimum's stops: the optimum
was not the minimum, and the caller fits again from there.

With Gaussian noise the region where the statistic stays below ``CHI2_95`` is the
likelihood-ratio 95 % interval (Wilks' theorem; Venzon & Moolgavkar 1988,
doi:10.2307/2347496, for the profile's walk).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from celtstone.fitting.profile import CHI2_95
from celtstone.fitting.runs import Runs
from celtstone.fitting.uncertainty import Uncertainty

__all__ = [
    "CHECK_STEPS",
    "QUADRATIC_TOLERANCE",
    "WALK_STEP",
    "LowerMinimum",
    "ProfiledInterval",
    "profiled_intervals",
    "quadratic_misfits",
]

CHECK_STEPS = 2.0  # standard errors from the optimum where the cost is checked
# |statistic / CHECK_STEPS² − 1| above this: the cost is not quadratic out to ~2 σ (a
# quadratic cost's own sampling noise in the statistic is far smaller: the runs are exact)
QUADRATIC_TOLERANCE = 0.1
WALK_STEP = 0.75  # standard errors per step of a profile's walk
MAX_WALK_STEPS = 8  # steps per side at most: the walk reaches 6 standard errors
# a refitted cost this many residual variances below the optimum's is a lower minimum
LOWER_BY = 0.1
# a profile's refits stop at this relative change of the cost: 1e-6 of a cost of ~m/2
# is far below the 0.5 s² that one unit of the statistic is
PROFILE_COST_TOLERANCE = 1e-6

Refit = Callable[[np.ndarray, list[int]], tuple[np.ndarray, float]]


@dataclass(frozen=True)
class ProfiledInterval:
    """The 95 % profile-likelihood interval of one number.

    Parameters
    ----------
    name : the number's name
    column : its column in the parameter vector
    lower, upper : the interval's ends [its unit]
    lower_open, upper_open : whether that end is a bound or the walk's last point, not a
        crossing of ``CHI2_95`` (the interval may reach further)
    joint_lower, joint_upper : the ends of the crossing of the joint level χ²_k(0.95)
        [its unit] (equal to ``lower``, ``upper`` for k = 1; a bound or the walk's last
        point where it was not crossed)
    values : the profile's points, the optimum included [its unit]
    statistic : 2 Δcost / s² at each [1]
    """

    name: str
    column: int
    lower: float
    upper: float
    lower_open: bool
    upper_open: bool
    values: tuple[float, ...]
    statistic: tuple[float, ...]
    joint_lower: float
    joint_upper: float
    joint_level: float = CHI2_95

    def summary(self) -> dict[str, Any]:
        return {
            "interval_95": [self.lower, self.upper],
            "open": [self.lower_open, self.upper_open],
            "joint_region_shadow_95": [self.joint_lower, self.joint_upper],
            "values": list(self.values),
            "statistic": list(self.statistic),
            "threshold": CHI2_95,
            "joint_threshold": self.joint_level,
        }


@dataclass(frozen=True)
class LowerMinimum:
    """A point a profile's refit reached with a cost below the optimum's [1]."""

    values: np.ndarray
    cost: float


def _directions(spread: Uncertainty, j: int) -> np.ndarray:
    """d x / d θ_j along the linearised profile of number j (1 in column j)."""
    return spread.covariance[:, j] / spread.covariance[j, j]


def quadratic_misfits(
    runs: Runs, values: np.ndarray, cost: float, spread: Uncertainty, columns: Sequence[int]
) -> dict[int, float]:
    """For each of ``columns``: |statistic / CHECK_STEPS² − 1| at ± ``CHECK_STEPS`` σ along
    its linearised profile, the larger side; inf where that point is outside the bounds.
    One run per point, in parallel."""
    problem = runs.problem
    points, owners = [], []
    misfits: dict[int, float] = {}
    for j in columns:
        error = spread.standard_errors[j]
        if not (np.isfinite(error) and error > 0.0):
            continue
        for side in (-1.0, 1.0):
            point = values + side * CHECK_STEPS * error * _directions(spread, j)
            if np.any(point < problem.lower) or np.any(point > problem.upper):
                misfits[j] = math.inf
            points.append(np.clip(point, problem.lower, problem.upper))
            owners.append(j)
    expected = CHECK_STEPS**2
    for j, residuals in zip(owners, runs.evaluate_many(points), strict=True):
        statistic = (float(residuals @ residuals) - 2.0 * cost) / spread.residual_variance
        misfits[j] = max(misfits.get(j, 0.0), abs(statistic / expected - 1.0))
    return misfits


def _crossing(
    inside: tuple[float, float], outside: tuple[float, float], level: float = CHI2_95
) -> float:
    """θ where the statistic reaches ``level`` between a point below it and one above:
    linear in the statistic's square root (exact for a quadratic cost)."""
    (a, qa), (b, qb) = inside, outside
    ra, rb = math.sqrt(max(qa, 0.0)), math.sqrt(qb)
    share = (math.sqrt(level) - ra) / (rb - ra)
    return a + share * (b - a)


class _End(NamedTuple):
    """One side of a profile: the crossings of ``CHI2_95`` and of the joint level [unit of
    the number] (a bound or the walk's last point where not crossed), whether the first
    is open, and the points walked (θ, statistic)."""

    marginal: float
    marginal_open: bool
    joint: float
    walked: list[tuple[float, float]]


def _walk(
    runs: Runs,
    refit: Refit,
    values: np.ndarray,
    cost: float,
    spread: Uncertainty,
    j: int,
    side: float,
    joint_level: float,
) -> _End | LowerMinimum:
    """One side of number j's profile, walked until the statistic crosses ``joint_level``
    (>= ``CHI2_95``); or the lower minimum a refit found."""
    problem = runs.problem
    variance = spread.residual_variance
    others = [k for k in range(values.size) if k != j]
    bound = float(problem.upper[j] if side > 0 else problem.lower[j])
    step = WALK_STEP * float(spread.standard_errors[j])
    slope = _directions(spread, j)
    x = values.copy()
    previous = (float(values[j]), 0.0)
    walked: list[tuple[float, float]] = []
    marginal: tuple[float, bool] | None = None
    for k in range(1, MAX_WALK_STEPS + 1):
        target = float(values[j]) + side * k * step
        at_bound = side * (target - bound) >= 0.0
        if at_bound:
            target = bound
        # the others from the last refit, moved along the linearised profile
        trial = np.clip(x + (target - x[j]) * slope, problem.lower, problem.upper)
        trial[j] = target
        x, refitted = refit(trial, others) if others else (trial, _cost(runs, trial))
        statistic = 2.0 * (refitted - cost) / variance
        walked.append((target, statistic))
        if refitted < cost - 0.5 * LOWER_BY * variance:
            return LowerMinimum(x.copy(), refitted)
        if marginal is None and statistic >= CHI2_95:
            marginal = (_crossing(previous, (target, statistic)), False)
        if statistic >= joint_level:
            assert marginal is not None  # joint_level >= CHI2_95
            joint = _crossing(previous, (target, statistic), joint_level)
            return _End(*marginal, joint, walked)
        if at_bound:
            break
        previous = (target, statistic)
    end = walked[-1][0]
    return _End(*(marginal or (end, True)), end, walked)


def _cost(runs: Runs, x: np.ndarray) -> float:
    residuals = runs.residuals(x)
    return 0.5 * float(residuals @ residuals)


def profiled_intervals(
    runs: Runs,
    refit: Refit,
    values: np.ndarray,
    cost: float,
    spread: Uncertainty,
    columns: Sequence[int],
    joint_level: float = CHI2_95,
) -> list[ProfiledInterval] | LowerMinimum:
    """The profile-likelihood 95 % interval of each of ``columns`` about the optimum
    ``values`` (cost ``cost``), walked out both ways until the statistic crosses
    ``joint_level`` (at least ``CHI2_95``; see the module); or the first lower minimum a
    refit finds.

    ``refit(x, free_columns)`` minimises over ``free_columns`` from ``x`` and returns the
    optimum and its cost.
    """
    joint_level = max(joint_level, CHI2_95)
    problem = runs.problem
    found = []
    for j in columns:
        if not np.isfinite(spread.standard_errors[j]) or spread.standard_errors[j] <= 0.0:
            continue
        ends = []
        points = [(float(values[j]), 0.0)]
        for side in (-1.0, 1.0):
            end = _walk(runs, refit, values, cost, spread, j, side, joint_level)
            if isinstance(end, LowerMinimum):
                return end
            ends.append(end)
            points.extend(end.walked)
        points.sort()
        low, high = ends
        found.append(
            ProfiledInterval(
                problem.names[j],
                j,
                low.marginal,
                high.marginal,
                low.marginal_open,
                high.marginal_open,
                tuple(p[0] for p in points),
                tuple(p[1] for p in points),
                low.joint,
                high.joint,
                joint_level,
            )
        )
    return found
