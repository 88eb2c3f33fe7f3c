"""Profile-likelihood intervals of ``fitting.intervals``, against costs whose 95 %
region is known: a linear model (the profile interval is θ̂ ± 1.96 σ exactly) and
double wells (the region where 2 Δcost stays below 3.84, found on a fine grid), also
through the fit's own checks (``solve._checked``)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from types import SimpleNamespace

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


# --- the fit's own checks (``solve._checked``) on a cost with a neighbouring minimum ---------

WELL_DEPTH = 0.3  # δ of the well: minima at θ = 1 (cost 0) and θ ≈ 0.092 (cost ≈ 0.275)
NOISE_ROWS = 60  # residuals that no parameter moves
ROWS = NOISE_ROWS + 3  # and the well's two, and φ's


def _well_residuals(theta: float) -> list[float]:
    """2 sqrt(2) θ (θ − 1) and sqrt(2 δ) (θ − 1): cost ½ Σ r² = 4 θ² (θ − 1)² + δ (θ − 1)²,
    with minima at 1 and at (8 − sqrt(64 − 128 δ)) / 32 and the maximum between them below
    3.84."""
    return [2.0 * np.sqrt(2.0) * theta * (theta - 1.0), np.sqrt(2.0 * WELL_DEPTH) * (theta - 1.0)]


def _well_cost(theta: np.ndarray) -> np.ndarray:
    return 4.0 * theta**2 * (theta - 1.0) ** 2 + WELL_DEPTH * (theta - 1.0) ** 2


@dataclass
class _WellProblem:
    """What ``solve._checked`` asks of a ``Problem``: two physical numbers θ and φ, one
    series (a spin-only record's shape of problem)."""

    names: tuple[str, ...] = ("theta", "phi")
    free: tuple[str, ...] = ("theta", "phi")
    lower: np.ndarray = field(default_factory=lambda: np.array([-5.0, -5.0]))
    upper: np.ndarray = field(default_factory=lambda: np.array([5.0, 5.0]))
    scale: np.ndarray = field(default_factory=lambda: np.ones(2))
    physical_columns: tuple[int, ...] = (0, 1)
    degrees_of_freedom: int = ROWS - 2
    series_rows: dict[str, slice] = field(default_factory=lambda: {"spin": slice(0, ROWS)})
    record: SimpleNamespace = field(default_factory=lambda: SimpleNamespace(series={"spin": 0}))


class _WellRuns:
    """Residuals (fixed white noise scaled to Σ e² = m − p, so that s² = 1 at θ = 1; the
    well in θ; and (φ − θ / 2) / 0.1, so that φ is refitted along a profile of θ) and
    their exact Jacobian, as ``fitting.runs.Runs`` gives them."""

    def __init__(self) -> None:
        noise = np.random.default_rng(3).normal(size=NOISE_ROWS)
        self.noise = noise * np.sqrt((ROWS - 2) / (noise @ noise))
        self.problem = _WellProblem()

    def residuals(self, x: np.ndarray, columns: Sequence[int] | None = None) -> np.ndarray:
        theta, phi = x
        return np.concatenate([self.noise, _well_residuals(theta), [(phi - theta / 2) / 0.1]])

    def jacobian(self, x: np.ndarray, columns: Sequence[int] | None = None) -> np.ndarray:
        theta = float(x[0])
        full = np.zeros((ROWS, 2))
        full[NOISE_ROWS, 0] = 2.0 * np.sqrt(2.0) * (2.0 * theta - 1.0)
        full[NOISE_ROWS + 1, 0] = np.sqrt(2.0 * WELL_DEPTH)
        full[NOISE_ROWS + 2] = [-5.0, 10.0]
        return full[:, list(range(2)) if columns is None else list(columns)]


def _grid_ends(level: float) -> tuple[float, float]:
    """The ends of the region where 2 Δcost / s² < ``level`` about θ = 1 on a fine grid
    (s² = 1: the noise rows' Σ e² / (m − p); φ refitted exactly, so the profile of θ is
    the well's cost)."""
    grid = np.linspace(-3.0, 4.0, 70001)
    inside = 2.0 * _well_cost(grid) < level
    edges = np.flatnonzero(np.diff(inside.astype(int)))
    return float(grid[edges[0] + 1]), float(grid[edges[-1]])


def test_a_fit_in_the_neighbouring_minimum_moves_and_its_interval_holds_both() -> None:
    """A fit that ends in the higher of two minima of a record of one series: the
    profile's walk meets the lower minimum, the optimum moves there (and says so), and
    from there the walk reaches over the neighbouring minimum: the 95 % interval and the
    joint region's shadow are the fine grid's crossings of 3.84 and of χ²₂(0.95) = 5.99,
    much wider than the curvature's ± 1.96 σ."""
    from celtstone.fitting.solve import _checked, _minimise, _Optimum

    runs = _WellRuns()
    x, cost, converged, _, jacobian, residuals = _minimise(runs, np.array([0.05, 0.0]), [0, 1])
    assert x[0] == pytest.approx(0.0919, abs=1e-3)  # the fit sits in the higher minimum
    optimum = _Optimum(x, cost, converged, jacobian, residuals)
    checked = _checked(runs, optimum, [])  # type: ignore[arg-type]
    assert checked.optimum.values[0] == pytest.approx(1.0, abs=1e-5)
    assert checked.moved_from == [pytest.approx(cost)]
    curvature_error = 1.0 / np.sqrt(2.0 * (4.0 + WELL_DEPTH))  # s = 1, JᵀJ = 2 (4 + δ)
    theta = checked.intervals[0]
    assert [i.name for i in checked.intervals] == ["theta", "phi"]  # one series: both walked
    low, high = _grid_ends(CHI2_95)
    assert theta.lower == pytest.approx(low, abs=0.03)
    assert theta.upper == pytest.approx(high, abs=0.03)
    assert theta.lower < 1.0 - 1.5 * Z_95 * curvature_error
    joint_low, joint_high = _grid_ends(5.991464547107979)
    assert theta.joint_lower == pytest.approx(joint_low, abs=0.03)
    assert theta.joint_upper == pytest.approx(joint_high, abs=0.03)
    error = checked.spread.standard_errors[0]
    assert Z_95 * error == pytest.approx(1.0 - low, abs=0.03)
    joint_error = np.sqrt(checked.spread.joint_covariance[0, 0])
    assert np.sqrt(5.991464547107979) * joint_error == pytest.approx(1.0 - joint_low, abs=0.03)
