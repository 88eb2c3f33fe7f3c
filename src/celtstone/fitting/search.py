"""Where the local fits start: the user's start, points drawn in the bounds, and the global
search that screens the bounds first.

The global search (``fit(starts=None)``) runs each of a seeded Latin hypercube of points
once, sets each bias to its best value there (the residuals are linear in a bias), and
starts local fits from the best few (the user's start screened among them). A free
``release_offset`` makes the cost oscillate with the rocking period (tens of ms) over its
bounds (2 s): no affordable grid of starts finds its basin, so each screened point is one
run from the release sampled every ``SCAN_STEP``, and the record is slid along it to the
best offset.
"""

from __future__ import annotations

import numpy as np

from celtstone.fitting.nuisance import RELEASE_OFFSET, bias_name, sensor_reading
from celtstone.fitting.problem import SLIP_NAMES, Problem
from celtstone.fitting.runs import Runs
from celtstone.fitting.series import SERIES
from celtstone.simulation.trajectory import Trajectory

__all__ = [
    "SCAN_STEP",
    "SCREEN_KEPT",
    "SCREEN_MINIMUM",
    "SCREEN_PER_PARAMETER",
    "draw_starts",
    "screened_starts",
]

# screened points per free number other than a bias or the release offset, at least
# SCREEN_MINIMUM; the best SCREEN_KEPT of them start local fits
SCREEN_PER_PARAMETER = 12
SCREEN_MINIMUM = 16
SCREEN_KEPT = 2
# a screened point whose cost is above this multiple of the best's starts no local fit
SCREEN_COST_RATIO = 4.0
# refined starts of a released record closer than this share of each number's bounds
# (log-scaled where drawn so) are one start: the refinement's own scatter is far smaller
SAME_START_SHARE = 0.01
# Nelder-Mead runs per number refining the best screened point of a released record
REFINE_PER_PARAMETER = 15
# sampling of the release run that the record is slid along [s]: the linear
# interpolation's error is A (2π ν h)² / 8, 2.5e-3 rad/s for a 2 rad/s rocking at 16 Hz
SCAN_STEP = 1e-3


def _kept_at_start(problem: Problem) -> list[int]:
    """Columns every drawn start takes from the problem's start: the initial slip (it
    decays within milliseconds; a drawn one of metres per second is no start)."""
    return [j for j, name in enumerate(problem.names) if name in SLIP_NAMES]


def draw_starts(problem: Problem, count: int, seed: int | None) -> list[np.ndarray]:
    """The problem's start and ``count − 1`` more from a seeded Latin hypercube in the
    bounds, log-uniform for a parameter whose positive bounds span a decade or more; the
    initial slip at the problem's start (``_kept_at_start``)."""
    starts = [problem.start]
    if count <= 1:
        return starts
    from scipy.stats import qmc

    unit = qmc.LatinHypercube(d=len(problem.free), rng=np.random.default_rng(seed)).random(
        count - 1
    )
    for row in unit:
        start = np.empty(len(problem.free))
        for j, p in enumerate(problem.free):
            if p.is_log_spaced:
                start[j] = p.lower * (p.upper / p.lower) ** row[j]
            else:
                start[j] = p.lower + (p.upper - p.lower) * row[j]
        kept = _kept_at_start(problem)
        start[kept] = problem.start[kept]
        starts.append(start)
    return starts


def _best_biases(problem: Problem, point: np.ndarray, residuals: np.ndarray) -> float:
    """Set ``point``'s biases to their best values in their bounds for ``residuals`` (those
    at ``point``, shifted in place); the cost there [1]."""
    for j, rows in problem.bias_columns.items():
        slope = float(problem.bias_jacobian(j)[rows][0])
        value = float(
            np.clip(point[j] - np.mean(residuals[rows]) / slope, problem.lower[j], problem.upper[j])
        )
        residuals[rows] += (value - point[j]) * slope
        point[j] = value
    return 0.5 * float(residuals @ residuals)


def _release_runs(problem: Problem, points: list[np.ndarray], runs: Runs) -> list[np.ndarray]:
    """For each screened point: the model's series sampled every ``SCAN_STEP`` from the
    release to the latest offset's end (one run each, in parallel or as one batch)."""
    j = problem.names.index(RELEASE_OFFSET)
    end = problem.upper[j] + float(problem.record.times[-1]) + SCAN_STEP
    grid = np.arange(0.0, end, SCAN_STEP)

    def dense(trajectory: Trajectory | None) -> np.ndarray:
        if trajectory is None:  # a refused configuration: this point is not a start
            return np.full((len(problem.record.series), 0), np.nan)
        return np.array([SERIES[name].model(trajectory.samples) for name in problem.record.series])

    return runs.run_many(dense, points, sample_times=grid)


def _moving(values: np.ndarray, window: int) -> np.ndarray:
    """Moving mean and moving standard deviation over ``window`` samples along the last
    axis, concatenated: the slow motion and the rocking's envelope."""
    if window <= 1:
        return values
    total = np.cumsum(np.insert(values, 0, 0.0, axis=-1), axis=-1)
    squares = np.cumsum(np.insert(values**2, 0, 0.0, axis=-1), axis=-1)
    mean = (total[..., window:] - total[..., :-window]) / window
    power = (squares[..., window:] - squares[..., :-window]) / window
    spread = np.sqrt(np.maximum(power - mean**2, 0.0))
    return np.concatenate([mean, spread], axis=-1)


def smoothing_window(problem: Problem) -> int:
    """Samples in the body's longer rocking period: the screening compares the motion
    averaged over it, whose cost varies slowly with the numbers (the samples themselves
    swing with the rocking's phase, and their cost has a minimum every period)."""
    step = float(np.median(np.diff(problem.record.times)))
    return max(1, round(problem.body.rocking_period / step))


def _scan_offset(
    problem: Problem, point: np.ndarray, modelled: np.ndarray, window: int = 1
) -> float:
    """Set ``point``'s release offset to the best on the grid of ``SCAN_STEP`` for the
    model's series ``modelled`` (rows: series, every SCAN_STEP from the release), each
    bias at its best; with ``window`` > 1, model and record compared averaged over that
    many samples (``_moving``). The cost there [1], inf if the run fell short."""
    j = problem.names.index(RELEASE_OFFSET)
    offsets = np.arange(problem.lower[j], problem.upper[j] + 0.5 * SCAN_STEP, SCAN_STEP)
    times = problem.record.times
    positions = (offsets[:, None] + times[None, :]) / SCAN_STEP
    below = np.floor(positions).astype(int)
    if modelled.shape[1] < int(below.max()) + 2:
        return np.inf
    share = positions - below
    costs = np.zeros(offsets.size)
    for row, (name, measured) in enumerate(problem.record.series.items()):
        # as the sensor reads it at ``point`` (its bias, free or held, and scale)
        values = sensor_reading(name, modelled[row], problem.values(point))
        shifted = values[below] * (1.0 - share) + values[below + 1] * share
        residual = _moving(shifted, window) - _moving(measured, window)
        residual *= np.sqrt(window) / problem.sigma[name]  # an average of `window` samples
        half = residual.shape[1] // 2 if window > 1 else residual.shape[1]
        mean = residual[:, :half].mean(axis=1, keepdims=True)  # a shift moves the mean only
        if SERIES[name].is_angle_offset_free:
            residual[:, :half] -= mean
        elif bias_name(name) in problem.names:  # the best bias within its bounds
            k = problem.names.index(bias_name(name))
            scale = np.sqrt(window) / problem.sigma[name]
            bias = np.clip(
                point[k] * scale - mean, problem.lower[k] * scale, problem.upper[k] * scale
            )
            residual[:, :half] += bias - point[k] * scale
        costs += 0.5 * np.sum(residual**2, axis=1)
    best = int(np.argmin(costs))
    point[j] = offsets[best]
    return float(costs[best])


def _refined(
    problem: Problem, point: np.ndarray, others: list[int], runs: Runs, window: int = 1
) -> np.ndarray:
    """``point`` improved by Nelder-Mead over ``others`` (log-scaled where their bounds
    span decades), the release offset slid to its best at each point: at most
    ``REFINE_PER_PARAMETER`` runs per number."""
    from scipy.optimize import minimize

    if not others:
        return point
    logs = [problem.free[j].is_log_spaced for j in others]
    lower, upper = problem.lower[others], problem.upper[others]

    def to_unit(x: np.ndarray) -> np.ndarray:
        return np.array([np.log(v) if lg else v for v, lg in zip(x, logs, strict=True)])

    def from_unit(u: np.ndarray) -> np.ndarray:
        x = np.array([np.exp(v) if lg else v for v, lg in zip(u, logs, strict=True)])
        return np.clip(x, lower, upper)

    best_cost, best_point = [np.inf], [point.copy()]

    def cost(u: np.ndarray) -> float:
        trial = point.copy()
        trial[others] = from_unit(u)
        modelled = _release_runs(problem, [trial], runs)[0]
        value = _scan_offset(problem, trial, modelled, window) if modelled.size else np.inf
        if value < best_cost[0]:
            best_cost[0], best_point[0] = value, trial
        return value if np.isfinite(value) else 1e300

    minimize(
        cost,
        to_unit(point[others]),
        method="Nelder-Mead",
        bounds=list(zip(to_unit(lower), to_unit(upper), strict=True)),
        options={"maxfev": REFINE_PER_PARAMETER * len(others), "xatol": 1e-3, "fatol": 1e-2},
    )
    return best_point[0]


def _in_unit(problem: Problem, point: np.ndarray, columns: list[int]) -> np.ndarray:
    """``point``'s ``columns`` as shares of their bounds [1], log-scaled where the starts
    are drawn so (``FreeParameter.is_log_spaced``)."""
    shares = []
    for j in columns:
        p = problem.free[j]
        if p.is_log_spaced:
            shares.append(np.log(point[j] / p.lower) / np.log(p.upper / p.lower))
        else:
            shares.append((point[j] - p.lower) / (p.upper - p.lower))
    return np.array(shares)


def _distinct(problem: Problem, points: list[np.ndarray], columns: list[int]) -> list[np.ndarray]:
    """``points`` less each one within ``SAME_START_SHARE`` of an earlier one in every
    number of ``columns`` (``_in_unit``): starts that lead to the same place."""
    kept: list[np.ndarray] = []
    for point in points:
        unit = _in_unit(problem, point, columns)
        if all(
            np.any(np.abs(unit - _in_unit(problem, k, columns)) > SAME_START_SHARE) for k in kept
        ):
            kept.append(point)
    return kept


def screened_starts(runs: Runs, seed: int | None) -> list[np.ndarray]:
    """The global search's starts: the best ``SCREEN_KEPT`` of the problem's start and a
    seeded Latin hypercube of ``SCREEN_PER_PARAMETER`` points per free number (one run
    each, in parallel), ranked with each bias at its best value there (a start keeps the
    problem's: a bias fitted to a wrong motion leads to a wrong minimum), the release
    offset slid to its best, the kept ones within ``SCREEN_COST_RATIO`` of the best cost
    and apart by a tenth of the bounds in some free number. The problem's start is
    screened as the rest and fitted from only if it is among them: a start screened
    below the best few leads a local fit into another minimum, at the cost of a whole
    fit's runs (``starts=1`` fits from it alone).

    With a free release offset the best ones are refined (``_refined``) whether apart or
    not, and judged apart afterwards (``_distinct``): two screened points closer than a
    tenth of the bounds can lead to different minima (the averaged motion's cost has several
    within that distance in f and ε), and the one screened second to the lower."""
    problem = runs.problem
    linear = problem.linear_columns  # a bias or a scale: held at its start, not drawn
    slid = RELEASE_OFFSET in problem.names
    kept_at_start = _kept_at_start(problem)
    drawn = [j for j in range(len(problem.free)) if j not in linear and j not in kept_at_start]
    others = [j for j in drawn if problem.names[j] != RELEASE_OFFSET]
    if not drawn:
        return [problem.start]
    count = max(SCREEN_MINIMUM, SCREEN_PER_PARAMETER * max(len(others), 1))
    # the user's start among them: its offset and biases screened too
    points = draw_starts(problem, count + 1, seed)
    for point in points:
        point[list(linear)] = problem.start[list(linear)]
    ranked = []
    window = smoothing_window(problem)
    if slid:
        models = _release_runs(problem, points, runs)
        for point, modelled in zip(points, models, strict=True):
            if modelled.size:
                ranked.append((_scan_offset(problem, point, modelled, window), point))
    else:
        for point, residuals in zip(points, runs.evaluate_many(points), strict=True):
            ranked.append((_best_biases(problem, point.copy(), residuals), point))
    ranked.sort(key=lambda pair: pair[0])
    width = (problem.upper - problem.lower)[drawn]
    kept: list[np.ndarray] = []
    for cost, point in ranked:
        if cost > SCREEN_COST_RATIO * ranked[0][0]:
            break
        if slid or all(np.any(np.abs(point[drawn] - k[drawn]) > 0.1 * width) for k in kept):
            kept.append(point)
        if len(kept) == SCREEN_KEPT:
            break
    if slid:  # each kept point refined over the others, the offset slid each time: on
        # the averaged motion, then on the samples (the rocking's phase)
        kept = [_refined(problem, point, others, runs, window) for point in kept]
        kept = [_refined(problem, point, others, runs) for point in kept]
        kept = _distinct(problem, kept, drawn)
    return kept or [problem.start]
