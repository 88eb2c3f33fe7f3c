"""Profile-likelihood intervals of ``fitting.intervals``, against costs whose 95 %
region is known: a linear model (the profile interval is θ̂ ± 1.96 σ exactly) and a
double well (the region where 2 Δcost stays below 3.84, found on a fine grid)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import pytest

from celtstone.fitting.intervals import (
    QUADRATIC_TOLERANCE,
    LowerMinimum,
    profiled_intervals,
    quadratic_misfits,
)
from celtstone.fitting.profile import CHI2_95
from celtstone.fitting.uncertainty import Uncertainty, uncertainty

Z_95 = 1.959963984540054


@dataclass
class _Problem:
    lower: np.ndarray
    upper: np.ndarray
    names: tuple[str, ...]


class _Runs:
    """What the intervals ask of ``fitting.runs.Runs``: residuals of parameter vectors."""

    def __init__(self, residuals: Callable[[np.ndarray], np.ndarray], problem: _Problem):
        self.function, self.problem = residuals, problem

    def residuals(self, x: np.ndarray) -> np.ndarray:
        return self.function(np.asarray(x, dtype=float))

    def evaluate_many(self, vectors: Sequence[np.ndarray]) -> list[np.ndarray]:
        return [self.residuals(x) for x in vectors]


def _cost(runs: _Runs, x: np.ndarray) -> float:
    r = runs.residuals(x)
    return 0.5 * float(r @ r)


def test_a_linear_model_s_profile_interval_is_the_curvature_s() -> None:
    """r = A x − y, two numbers: the profile of each, the other refitted (exactly, by
    least squares), crosses 3.84 at θ̂ ± 1.96 σ with σ² = s² [(AᵀA)⁻¹]_jj."""
    rng = np.random.default_rng(0)
    t = np.linspace(0.0, 1.0, 50)
    design = np.column_stack([np.ones_like(t), t])
    data = design @ np.array([1.0, 2.0]) + rng.normal(0.0, 0.1, t.size)
    problem = _Problem(np.array([-10.0, -10.0]), np.array([10.0, 10.0]), ("a", "b"))
    runs = _Runs(lambda x: design @ x - data, problem)
    best = np.linalg.lstsq(design, data, rcond=None)[0]
    cost = _cost(runs, best)
    spread = uncertainty(design, cost, t.size - 2, np.ones(2), ["a", "b"])

    def refit(x: np.ndarray, others: list[int]) -> tuple[np.ndarray, float]:
        held = [j for j in range(2) if j not in others]
        rest = np.linalg.lstsq(design[:, others], data - design[:, held] @ x[held], rcond=None)
        fitted = x.copy()
        fitted[others] = rest[0]
        return fitted, _cost(runs, fitted)

    intervals = profiled_intervals(runs, refit, best, cost, spread, [0, 1])
    assert not isinstance(intervals, LowerMinimum)
    for interval in intervals:
        j, error = interval.column, spread.standard_errors[interval.column]
        assert interval.lower == pytest.approx(best[j] - Z_95 * error, rel=1e-9)
        assert interval.upper == pytest.approx(best[j] + Z_95 * error, rel=1e-9)
        assert not (interval.lower_open or interval.upper_open)
    misfits = quadratic_misfits(runs, best, cost, spread, [0, 1])
    assert max(misfits.values()) < 1e-9


def _double_well(x: np.ndarray) -> np.ndarray:
    """One residual whose cost ½ r² = 4 θ² (θ − 1)² + ½ (θ − 1)²: minima at 1 (cost 0)
    and near 0 (cost ≈ 0.5), the barrier between them below the 95 % threshold."""
    theta = x[0]
    return np.array(
        [np.sqrt(2.0 * (4.0 * theta**2 * (theta - 1.0) ** 2 + 0.5 * (theta - 1.0) ** 2))]
    )


def _spread(variance: float) -> Uncertainty:
    """One number's uncertainty of ``variance``, residual variance 1."""
    return Uncertainty(
        np.array([[variance]]), np.array([np.sqrt(variance)]), np.ones((1, 1)), 1.0, 1, 1.0, ()
    )


def test_a_double_well_s_interval_reaches_over_the_second_minimum() -> None:
    """The 95 % region about θ̂ = 1 (statistic 2 Δcost, s² = 1) spans the second well:
    its ends found on a fine grid; the curvature's ± 1.96 σ reaches only 1 ± 0.65; the
    quadratic check flags it."""
    problem = _Problem(np.array([-5.0]), np.array([5.0]), ("theta",))
    runs = _Runs(_double_well, problem)
    best = np.array([1.0])
    curvature = 2.0 * 4.0 + 1.0  # d²cost/dθ² at 1
    spread = _spread(1.0 / curvature)
    coarse = np.linspace(-2.0, 3.0, 5001)
    statistic = np.array([_double_well(np.array([g]))[0] ** 2 for g in coarse])  # 2 cost
    inside = statistic < CHI2_95
    start = int(np.argmin(np.abs(coarse - 1.0)))
    low = start
    while inside[low - 1]:
        low -= 1
    high = start
    while inside[high + 1]:
        high += 1
    (interval,) = profiled_intervals(runs, lambda x, o: (x, 0.0), best, 0.0, spread, [0])
    assert interval.lower == pytest.approx(coarse[low], abs=0.05)
    assert interval.upper == pytest.approx(coarse[high], abs=0.05)
    assert interval.lower < 1.0 - 1.5 * Z_95 * spread.standard_errors[0]
    misfits = quadratic_misfits(runs, best, 0.0, spread, [0])
    assert misfits[0] > QUADRATIC_TOLERANCE


def test_a_walk_that_finds_a_lower_cost_says_so() -> None:
    """Started at the higher well (near 0), the walk towards 1 meets a lower cost."""
    problem = _Problem(np.array([-5.0]), np.array([5.0]), ("theta",))
    runs = _Runs(_double_well, problem)
    best = np.array([0.1])  # near the upper well's minimum
    cost = _cost(runs, best)
    spread = _spread(0.04)
    found = profiled_intervals(runs, lambda x, o: (x, 0.0), best, cost, spread, [0])
    assert isinstance(found, LowerMinimum) and found.cost < cost
