"""``fit``: weighted least squares of a record by the simulator, from several starts.

SciPy's ``least_squares`` (trust-region reflective, bounded) minimises ½ Σ r² over the
free numbers; the forward-difference Jacobian's runs go in parallel on threads, as many
as there are idle threads started beside each residual (``fitting.runs``); a bias's
column is exact and takes no run. By default the starts come from a global search
(``fitting.search``); with ``starts=N`` they are the user's and N − 1 drawn by Latin
hypercube within the bounds, seeded. Each physical number's interval is checked for a
cost that is not quadratic, and then taken from its profile likelihood
(``fitting.intervals``). The finished fit is checked (``fitting.assess``):
residual whiteness (the errors widened where it fails), goodness against the noise
measured without the model, bounds, convergence, the runs' integration error.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from types import MappingProxyType
from typing import Any, NamedTuple

import numpy as np

from celtstone.bodies import Body, load_body
from celtstone.errors import (
    CeltstoneError,
    FitQualityWarning,
    FrictionBoundWarning,
    IdentifiabilityWarning,
    ParameterError,
    PlausibilityWarning,
    require_choice,
)
from celtstone.fitting.assess import assess
from celtstone.fitting.diagnostics import Whiteness, correlation_length, whiteness
from celtstone.fitting.intervals import (
    PROFILE_COST_TOLERANCE,
    QUADRATIC_TOLERANCE,
    LowerMinimum,
    ProfiledInterval,
    profiled_intervals,
    quadratic_misfits,
)
from celtstone.fitting.problem import (
    FIT_ATOL,
    FIT_RTOL,
    Problem,
    Settings,
    make_problem,
)
from celtstone.fitting.profile import profile_likelihood
from celtstone.fitting.record import Record
from celtstone.fitting.result import FitResult, StartOutcome
from celtstone.fitting.runs import Runs, run_device
from celtstone.fitting.search import draw_starts, screened_starts
from celtstone.fitting.uncertainty import (
    JOINT_LEVEL,
    Uncertainty,
    autocorrelation_consistent,
    uncertainty,
)
from celtstone.simulation.trajectory import Trajectory
from celtstone.sweep.devices import DEVICES

__all__ = [
    "FIT_ATOL",
    "FIT_RTOL",
    "MAX_ITERATIONS",
    "fit",
    "reweighted",
]

MAX_ITERATIONS = 50  # residual evaluations of one start (least_squares' max_nfev)
MAX_STARTS = 1000  # starts one may ask for
MAX_WORKERS = 1024  # threads one may ask for
# fits again from a lower minimum a profile's walk found, at most
MAX_REFITS = 3
Z_95 = 1.959963984540054

# relative changes of cost and of x below which a start has converged
COST_TOLERANCE = 1e-8
STEP_TOLERANCE = 1e-6


def _minimise(
    runs: Runs, x0: np.ndarray, columns: list[int], cost_tolerance: float = COST_TOLERANCE
) -> tuple[np.ndarray, float, bool, str, np.ndarray, np.ndarray]:
    """least_squares over ``columns`` of the parameter vector from ``x0`` (the others
    held), stopping at a relative change of the cost below ``cost_tolerance``: (optimum,
    cost, converged, message, Jacobian of the columns there, residuals there)."""
    from scipy.optimize import least_squares

    problem = runs.problem
    held = x0.copy()

    def full(sub: np.ndarray) -> np.ndarray:
        x = held.copy()
        x[columns] = sub
        return x

    result = least_squares(
        lambda sub: runs.residuals(full(sub), columns),
        np.clip(x0[columns], problem.lower[columns], problem.upper[columns]),
        jac=lambda sub: runs.jacobian(full(sub), columns),
        bounds=(problem.lower[columns], problem.upper[columns]),
        x_scale=problem.scale[columns],
        method="trf",
        ftol=cost_tolerance,
        xtol=STEP_TOLERANCE,
        gtol=cost_tolerance,
        max_nfev=MAX_ITERATIONS,
    )
    converged = result.status > 0
    return full(result.x), float(result.cost), converged, result.message, result.jac, result.fun


def _from_starts(
    runs: Runs, starting: list[np.ndarray]
) -> tuple[list[StartOutcome], tuple[np.ndarray, float, np.ndarray, np.ndarray]]:
    """Each start's outcome, and the best one's (values, cost, Jacobian, residuals). A start
    reached the best when its cost is within half the residual variance of the best's (the
    same minimum, as far as the data tell)."""
    problem = runs.problem
    columns = list(range(len(problem.free)))
    ends = []
    for x0 in starting:
        before = runs.count
        ends.append((x0, *_minimise(runs, x0, columns), runs.count - before))
    best = min(ends, key=lambda end: end[2])
    variance = 2.0 * best[2] / problem.degrees_of_freedom
    outcomes = [
        StartOutcome(x0, x, cost, converged, message, used, cost - best[2] <= 0.5 * variance)
        for x0, x, cost, converged, message, _, _, used in ends
    ]
    return outcomes, (best[1], best[2], best[5], best[6])


def _costed(runs: Runs, points: list[np.ndarray]) -> list[tuple[np.ndarray, np.ndarray]]:
    """Each of ``points`` with its residuals under ``runs``' problem (one run each)."""
    return list(zip(points, runs.evaluate_many(points), strict=True)) if points else []


def reweighted(problem: Problem, residuals: np.ndarray) -> Problem:
    """``problem`` with each estimated σ_s replaced by the noise level of its series'
    ``residuals`` (weighted by the old σ_s): RMS · sqrt(m / (m − p)) [unit of the series].

    The data's own estimate (``noise_scale``) is an upper bound where a series oscillates
    within a few samples (a rocking rate at 100 Hz); the residuals of a first fit are not,
    so a record of several series is fitted again from the optimum with these weights.
    """
    ratio = problem.n_residuals / problem.degrees_of_freedom
    sigma, sources, start = dict(problem.sigma), dict(problem.sigma_source), 0
    for name, measured in problem.record.series.items():
        part = residuals[start : start + measured.size] * sigma[name]
        start += measured.size
        if sources[name] != "given":
            sigma[name] = float(np.sqrt(np.mean(part**2) * ratio)) or sigma[name]
            sources[name] = "residuals of a first fit"
    return replace(problem, sigma=MappingProxyType(sigma), sigma_source=MappingProxyType(sources))


def _body(body: Body | str | Path) -> Body:
    return body if isinstance(body, Body) else load_body(body)


def _check_count(name: str, value: object, lowest: int, highest: int | None = None) -> int:
    """``value`` as a whole number in [lowest, highest], or ParameterError naming ``name``."""
    allowed = f"a whole number >= {lowest}" + (f" and <= {highest}" if highest else "")
    if not isinstance(value, (int, np.integer)) or isinstance(value, bool):
        raise ParameterError(name, value, allowed)
    if value < lowest or (highest is not None and value > highest):
        raise ParameterError(name, value, allowed)
    return int(value)


def fit(
    record: Record,
    body: Body | str | Path,
    model: str = "sliding",
    free: Sequence[str] = ("friction_coefficient", "contact_radius"),
    *,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    start: Mapping[str, float] | None = None,
    fixed: Mapping[str, float | str] | None = None,
    sigma: Mapping[str, float] | None = None,
    sensor_bias: bool = True,
    initial_slip: bool = True,
    starts: int | None = None,
    seed: int | None = 0,
    profile: str | None = None,
    rtol: float = FIT_RTOL,
    atol: float = FIT_ATOL,
    method: str | None = None,
    workers: int | None = None,
    device: str = "cpu",
    progress: Callable[[int, float], None] | None = None,
) -> FitResult:
    """Fit the free numbers of a model of ``body`` to ``record`` by weighted least squares.

    Parameters
    ----------
    record : Record
        The measured motion (:func:`read_record`, :func:`make_record`).
    body : Body or str or pathlib.Path
        A body, a shipped body's name or a body file.
    model : str
        "rolling" or "sliding".
    free : sequence of str
        Names to fit: model settings (``friction_coefficient`` f [1], ``contact_radius``
        ε [m], ``rolling_resistance`` λ [m], ``damping`` σ [N m s], ...), the initial
        state (``omega1..3`` [rad/s], ``initial_spin`` [rad/s], ``euler_alpha``,
        ``euler_beta`` [deg], ``slip_velocity1..2`` [m/s]), body numbers (``celtstone
        sweep`` names) or the record's own numbers (``fitting.nuisance``:
        ``release_offset`` [s], the time from the release state to the first sample;
        ``bias_<series>`` [rad/s], a gyroscope's bias; ``scale_<series>`` [1], its scale
        error: the sensor reads (1 + scale) × rate + bias).
    bounds : mapping of str to (float, float), optional
        Name -> (LO, HI) [its unit]; defaults in ``fitting.problem.DEFAULT_BOUNDS`` and
        ``fitting.nuisance.NUISANCES``.
    start : mapping of str to float, optional
        Name -> first start [its unit]; default the fixed or the model's default value,
        for the initial rates the record's first sample.
    fixed : mapping of str to float or str, optional
        Name -> value of the numbers and options held (``celtstone sweep --set`` names,
        ``bias_<series>`` and ``scale_<series>``); the initial state defaults to the
        record's first sample of omega1..3 or spin, or with ``release_offset`` to the
        model's default state.
    sigma : mapping of str to float, optional
        Series name -> noise scale σ_s weighting it [its SI unit]; default estimated
        from the record's high-frequency part (``fitting.noise.noise_scale``).
    sensor_bias : bool
        Free a constant bias on every gyroscope rate series (spin, omega1..3) not held
        by ``fixed``.
    initial_slip : bool
        Free the contact's initial sliding velocity (``slip_velocity1``, ``slip_velocity2``
        [m/s], body axes 1 and 2) where the run starts mid-motion: at the record's first
        sample with the initial rates read from it or free (not at a release, nor a state
        given in ``fixed``); a sliding model only. Held at 0 otherwise.
    starts : int or None
        Local fits from this many starts, the first being ``start``, the others drawn
        (1 to 1000); None: the global search, a screening of the bounds (``start``
        among its points) whose best points start local fits (``screened_starts``).
    seed : int or None
        Seed of the drawn starts.
    profile : str or None
        A free name whose profile likelihood interval to compute.
    rtol : float
        Relative tolerance of the runs.
    atol : float
        Absolute tolerance of the runs.
    method : str or None
        Integrator, default the model's.
    workers : int or None
        Threads for the runs on the CPU (default: one per core), >= 1.
    device : str
        Where the runs go: "cpu" (threads), "cuda" (a CUDA GPU: each batch of runs the
        fit makes, a residual with the Jacobian's columns, the screening's points, an
        interval's checks, as one launch, a thread per run; refused where there is no
        GPU, before any run) or "auto" (the GPU where there is one, else the CPU).
    progress : callable or None
        Called after each residual evaluation with (runs so far, cost).

    Returns
    -------
    FitResult
        The best of the starts, with standard errors and correlations, the checks of
        ``fitting.diagnostics`` and ``converged``; each warning is also issued (an
        :class:`IdentifiabilityWarning` for correlations and rank, a
        :class:`FitQualityWarning` for the rest).
    """
    began = time.perf_counter()
    _check_counts(starts, workers, seed)
    require_choice("device", device, DEVICES)
    settings = Settings(
        bounds=bounds or {},
        start=start or {},
        fixed=fixed or {},
        sigma=sigma or {},
        sensor_bias=sensor_bias,
        initial_slip=initial_slip,
        rtol=rtol,
        atol=atol,
        method=method,
    )
    problem, device = _checked_problem(record, _body(body), model, free, settings, profile, device)
    noise = dict(problem.sigma)  # the model-free noise estimates (or the given σ_s)
    with warnings.catch_warnings(), Runs(problem, workers, progress, device=device) as runs:
        # trial runs warn about nothing; the fitted run below warns once
        warnings.simplefilter("ignore", FrictionBoundWarning)
        warnings.simplefilter("ignore", PlausibilityWarning)
        starting = (
            screened_starts(runs, seed) if starts is None else draw_starts(problem, starts, seed)
        )
        stages = {"screening": runs.count}
        problem, outcomes, ends, optimum = _best_of_starts(runs, problem, starting, stages)
        optimum, spread, whiteness, intervals, moved_from = _checked(runs, optimum, ends)
        values, best_converged = optimum.values, optimum.converged
        stages["interval checks and profiles"] = runs.count - sum(stages.values())
        profiled = None if profile is None else _profile(runs, values, spread, profile)
        if profiled is not None:
            stages["--profile"] = runs.count - sum(stages.values())
        count, failed, wasted = runs.count, runs.failed, runs.wasted
    stages["fitted run and its integration check"] = 2
    trajectory, residuals, assessment = _fitted_run(
        problem, values, spread, whiteness, noise, outcomes, best_converged, profiled
    )
    for text in spread.warnings(problem.names):
        warnings.warn(text, IdentifiabilityWarning, stacklevel=2)
    for text in assessment.warnings:
        warnings.warn(text, FitQualityWarning, stacklevel=2)
    return FitResult(
        problem=problem,
        values=values,
        cost=0.5 * float(residuals @ residuals),
        residuals=residuals,
        uncertainty=spread,
        starts=tuple(outcomes),
        runs=count + 2,
        runs_by_stage=MappingProxyType(stages),
        failed_runs=failed + (not trajectory.ok),
        speculative_runs_wasted=wasted,
        wall_time=time.perf_counter() - began,
        trajectory=trajectory,
        profile=profiled,
        intervals=tuple(intervals),
        moved_by_profile=tuple(moved_from),
        warnings=(*spread.warnings(problem.names), *assessment.warnings),
        assessment=assessment,
        device=_device_name(device),
    )


def _checked_problem(
    record: Record,
    body: Body,
    model: str,
    free: Sequence[str],
    settings: Settings,
    profile: str | None,
    device: str,
) -> tuple[Problem, str]:
    """The fit's :class:`Problem` and the device of its runs ("cpu" or "cuda"), every
    refusal before the problem's warnings: a missing GPU is one line."""
    with warnings.catch_warnings(record=True) as held:
        warnings.simplefilter("always")
        problem = make_problem(record, body, model, free, settings)
    if profile is not None and profile not in problem.names:
        raise ParameterError("profile", profile, "a free parameter: " + ", ".join(problem.names))
    resolved = run_device(device, problem)
    for warning in held:  # as make_problem warned them, at the caller of fit
        warnings.warn(warning.message, warning.category, stacklevel=3)
    return problem, resolved


def _device_name(device: str) -> str:
    """Where a fit's runs went, as its summary says it: "cpu", or the GPU's name."""
    if device == "cpu":
        return "cpu"
    from celtstone.sweep.devices import describe_gpu

    return describe_gpu()


class _Optimum(NamedTuple):
    """A local fit's end: values, cost, whether converged, Jacobian and residuals there."""

    values: np.ndarray
    cost: float
    converged: bool
    jacobian: np.ndarray
    residuals: np.ndarray


class _Checked(NamedTuple):
    """What :func:`_checked` found: the optimum, its uncertainty, the residuals'
    whiteness, the profiled intervals and the costs of the optima the profiles moved
    away from (lower minima found beside them)."""

    optimum: _Optimum
    spread: Uncertainty
    whiteness: dict[str, Whiteness]
    intervals: list[ProfiledInterval]
    moved_from: list[float]


def _checked(runs: Runs, optimum: _Optimum, ends: list[tuple[np.ndarray, float]]) -> _Checked:
    """The optimum, its uncertainty (each physical number's error widened to hold its
    profile's 95 % interval and the other minima the data cannot reject, ``ends``; the
    joint region's covariance widened to hold the profile's crossing of the joint level
    and the minima below it, ``fitting.intervals``), the residuals' whiteness and the
    profiled intervals. A profile that finds a lower cost moves the optimum there (fitted
    again, at most ``MAX_REFITS`` times; the costs it left are returned).

    The profiles are walked where the cost is not quadratic, where other minima the
    data cannot reject were found, and on every record of one series: there (a spin
    record, f and the bias trading against each other) the cost's shape can change
    within the interval, at a few noise draws so much that the optimum's f–ε correlation
    has the other sign from the truth's, and the check at ± 2 σ need not see it.
    """
    problem = runs.problem
    columns = list(range(len(problem.free)))
    # the initial slip decays within milliseconds: like the sensor's numbers, its interval
    # is the curvature's (profiles of two more numbers would double a fit's runs)
    physical = problem.physical_columns
    level = joint_level(len(physical))
    always = len(problem.record.series) == 1
    spread, white = _spread(problem, optimum.jacobian, optimum.residuals, optimum.cost)
    intervals: list[ProfiledInterval] = []
    moved_from: list[float] = []

    def loose_refit(x: np.ndarray, others: list[int]) -> tuple[np.ndarray, float]:
        optimum, cost = _minimise(runs, x, others, PROFILE_COST_TOLERANCE)[:2]
        return optimum, cost

    for _ in range(MAX_REFITS):
        values, cost = optimum.values, optimum.cost
        if always:
            chosen = list(physical)
        else:
            misfits = quadratic_misfits(runs, values, cost, spread, physical)
            others = _other_minima(spread, values, cost, ends, physical, level)
            chosen = [j for j in physical if others or misfits.get(j, 0.0) > QUADRATIC_TOLERANCE]
        walked = profiled_intervals(runs, loose_refit, values, cost, spread, chosen, level)
        if not isinstance(walked, LowerMinimum):
            intervals = walked
            break
        # a lower cost beside the optimum: fitted from there, it is the optimum
        ends.append((values, cost))
        moved_from.append(cost)
        x, cost, converged, _, jacobian, residuals = _minimise(runs, walked.values, columns)
        optimum = _Optimum(x, cost, converged, jacobian, residuals)
        spread, white = _spread(problem, jacobian, residuals, cost)
    values, cost = optimum.values, optimum.cost
    # a start's end within half an error of the optimum is the optimum's own minimum
    # (another start that reached it), not another one
    apart = _apart(spread, values, ends, physical)
    marginal = {i.column: (i.lower, i.upper) for i in intervals}
    factors = np.maximum(
        _minima_factors(spread, values, cost, apart, walked=marginal),
        _profile_factors(spread, values, intervals),
    )
    shadows = {i.column: (i.joint_lower, i.joint_upper) for i in intervals}
    joint = np.maximum.reduce(
        [
            factors * Z_95 / math.sqrt(level),  # the shadow holds each 95 % interval
            _minima_factors(spread, values, cost, apart, level, shadows),
            _profile_factors(spread, values, intervals, joint=True),
        ]
    )
    widened = _widened(spread, factors)
    widened = replace(widened, joint_covariance=spread.covariance * np.outer(joint, joint))
    return _Checked(optimum, widened, white, intervals, moved_from)


def joint_level(count: int) -> float:
    """χ²_k(0.95) [1] of ``count`` = k numbers (``CHI2_95`` for one or none)."""
    from scipy.stats import chi2

    from celtstone.fitting.profile import CHI2_95

    return float(chi2.ppf(JOINT_LEVEL, count)) if count > 1 else CHI2_95


def _spread(
    problem: Problem, jacobian: np.ndarray, residuals: np.ndarray, cost: float
) -> tuple[Uncertainty, dict[str, Whiteness]]:
    """The uncertainty, widened by the Newey-West covariance where a series' residuals
    are not white, and each series' whiteness."""
    blocks = problem.series_rows
    white = {name: whiteness(residuals[rows]) for name, rows in blocks.items()}
    widened = None
    if not all(w.is_white for w in white.values()):
        widened = autocorrelation_consistent(
            jacobian,
            residuals,
            list(blocks.values()),
            [correlation_length(residuals[rows]) for rows in blocks.values()],
            problem.scale,
            problem.degrees_of_freedom,
        )
    spread = uncertainty(
        jacobian, cost, problem.degrees_of_freedom, problem.scale, problem.names, widened
    )
    return spread, white


def _other_minima(
    spread: Uncertainty,
    values: np.ndarray,
    cost: float,
    minima: Sequence[tuple[np.ndarray, float]],
    columns: Sequence[int],
    level: float,
) -> list[tuple[np.ndarray, float]]:
    """The ``minima`` the joint region cannot reject (2 Δcost / s² below ``level``) that
    lie apart from the optimum (:func:`_apart`)."""
    variance = spread.residual_variance
    return [
        (x, other)
        for x, other in _apart(spread, values, minima, columns)
        if 2.0 * (other - cost) / variance < level
    ]


def _apart(
    spread: Uncertainty,
    values: np.ndarray,
    minima: Sequence[tuple[np.ndarray, float]],
    columns: Sequence[int],
) -> list[tuple[np.ndarray, float]]:
    """The ``minima`` that lie apart from the optimum ``values``: by half a standard
    error or more in one of ``columns``."""
    errors = spread.standard_errors[list(columns)]
    return [
        (x, other)
        for x, other in minima
        if np.any(np.abs(x - values)[list(columns)] > 0.5 * errors)
    ]


def _minima_factors(
    spread: Uncertainty,
    values: np.ndarray,
    cost: float,
    minima: Sequence[tuple[np.ndarray, float]],
    level: float | None = None,
    walked: Mapping[int, tuple[float, float]] | None = None,
) -> np.ndarray:
    """Each standard error's factor [1] that makes the region of 2 Δcost / s² below
    ``level`` (default ``CHI2_95``: the 95 % interval) hold every other minimum the data
    cannot reject at that level, with the part of its own region below it; a number
    whose profile was walked over the minimum (``walked``: column -> the ends of its
    profile's region at that level) has the profile's region there instead.

    Notes
    -----
    The region of 2 Δcost / s² < L is the union of the optimum's ± sqrt(L) errors and,
    about a minimum at statistic q and distance Δ_j, ± sqrt(L − q) errors: its half-width
    about the optimum is max(sqrt(L) σ_j, |Δ_j| + sqrt(L − q) σ_j), reported as
    sqrt(L) σ'_j (1.96 σ'_j for L = 3.84).
    """
    from celtstone.fitting.profile import CHI2_95

    level = CHI2_95 if level is None else level
    errors = spread.standard_errors
    factors = np.ones(errors.size)
    for x, other in minima:
        statistic = 2.0 * (other - cost) / spread.residual_variance
        if not statistic < level:
            continue
        reach = np.abs(x - values) + np.sqrt(level - max(statistic, 0.0)) * errors
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = np.where(
                np.isfinite(errors) & (errors > 0), reach / (math.sqrt(level) * errors), 1.0
            )
        for j, (low, high) in (walked or {}).items():
            if low <= x[j] <= high:
                ratio[j] = 1.0
        factors = np.maximum(factors, ratio)
    return factors


def _profile_factors(
    spread: Uncertainty,
    values: np.ndarray,
    intervals: Sequence[ProfiledInterval],
    joint: bool = False,
) -> np.ndarray:
    """Each standard error's factor [1] that makes ± 1.96 errors hold the profile's 95 %
    interval of ``intervals`` (its farther end from the optimum), or with ``joint`` that
    makes ± sqrt(L) errors hold its crossing of the joint level L; 1 for a number not
    profiled. ``intervals`` are of ``values``' columns, in order (``column``)."""
    factors = np.ones(values.size)
    for interval in intervals:
        j, error = interval.column, spread.standard_errors[interval.column]
        if np.isfinite(error) and error > 0.0:
            if joint:
                low, high = interval.joint_lower, interval.joint_upper
                half = math.sqrt(interval.joint_level) * error
            else:
                low, high, half = interval.lower, interval.upper, Z_95 * error
            factors[j] = max(1.0, max(values[j] - low, high - values[j]) / half)
    return factors


def _widened(spread: Uncertainty, factors: np.ndarray) -> Uncertainty:
    """``spread`` with each standard error multiplied by its factor (correlations kept)."""
    if np.all(factors <= 1.0 + 1e-9):
        return spread
    return replace(
        spread,
        covariance=spread.covariance * np.outer(factors, factors),
        standard_errors=spread.standard_errors * factors,
        widened_by_profile=tuple(float(f) for f in factors),
    )


def _widened_by_minima(
    spread: Uncertainty,
    values: np.ndarray,
    cost: float,
    minima: Sequence[tuple[np.ndarray, float]],
) -> Uncertainty:
    """``spread`` widened so that the 95 % interval holds every other minimum the data
    cannot reject (:func:`_minima_factors`)."""
    return _widened(spread, _minima_factors(spread, values, cost, minima))


def _integration_error(problem: Problem, values: np.ndarray, trajectory: Trajectory) -> float:
    """Largest |Δ model| / σ_s between the fitted run and one at 1/100 of its tolerances
    [1]: far below 1 when the runs' error is far below the noise; inf if it fails."""
    tighter = replace(problem, rtol=problem.rtol / 100.0, atol=problem.atol / 100.0)
    try:
        reference = tighter.run(values)
    except CeltstoneError:
        return math.inf
    if not (reference.ok and trajectory.ok):
        return math.inf
    difference = tighter.residuals(reference, values) - problem.residuals(trajectory, values)
    return float(np.max(np.abs(difference)))


def _profile(runs: Runs, values: np.ndarray, spread: Any, name: str) -> Any:
    """The profile likelihood of the free number ``name`` about ``values`` (``--profile``)."""
    index = runs.problem.names.index(name)

    def refit(x: np.ndarray, others: list[int]) -> tuple[np.ndarray, float]:
        optimum, cost = _minimise(runs, x, others)[:2]
        return optimum, cost

    return profile_likelihood(
        runs, refit, values, index, spread.standard_errors[index], spread.residual_variance
    )


def _best_of_starts(
    runs: Runs, problem: Any, starting: Any, stages: dict[str, int]
) -> tuple[Any, list[Any], list[tuple[np.ndarray, float]], _Optimum]:
    """The local fits from ``starting``, then, for several series without a given
    noise, the refit with each series weighted by its residuals' noise; the runs each
    stage took are added to ``stages``. Returns (problem, the starts' outcomes, the
    converged ends with their costs, the optimum)."""
    outcomes, (values, cost, jacobian, residuals) = _from_starts(runs, starting)
    stages["local fits"] = runs.count - sum(stages.values())
    best_converged = min(outcomes, key=lambda s: s.cost).converged
    ends = [(s.end, s.cost) for s in outcomes if s.converged]
    if len(problem.record.series) > 1 and "given" not in problem.sigma_source.values():
        # the refit moves the best's own minimum (by up to two errors where the weights
        # change much): the ends within half an error of the best, under the weights
        # they were found with, are that minimum, not others beside the refitted one
        first = uncertainty(
            jacobian, cost, problem.degrees_of_freedom, problem.scale, problem.names
        )
        ends = _apart(first, values, ends, problem.physical_columns)
        problem, ends, (values, cost, best_converged, _, jacobian, residuals) = _reweighted(
            runs, problem, values, residuals, ends
        )
        stages["refit with the residuals' noise"] = runs.count - sum(stages.values())
    return problem, outcomes, ends, _Optimum(values, cost, best_converged, jacobian, residuals)


def _reweighted(
    runs: Runs,
    problem: Any,
    values: np.ndarray,
    residuals: np.ndarray,
    ends: list[tuple[np.ndarray, float]],
) -> tuple[Any, list[tuple[np.ndarray, float]], Any]:
    """Each series weighted by its residuals' noise, the optimum refitted, and the starts'
    ends costed again with these weights (comparable with the optimum's)."""
    problem = reweighted(problem, residuals)
    runs.use(problem)
    minimum = _minimise(runs, values, list(range(len(problem.free))))
    ends = [(x, 0.5 * float(r @ r)) for x, r in _costed(runs, [x for x, _ in ends])]
    return problem, ends, minimum


def _fitted_run(
    problem: Any,
    values: np.ndarray,
    spread: Any,
    whiteness: Any,
    noise: dict[str, float],
    outcomes: list[Any],
    converged: bool,
    profiled: Any,
) -> tuple[Any, np.ndarray, Any]:
    """The run at the fitted values, its residuals, and the fit's assessment (with the
    run's integration error checked at tighter tolerances)."""
    trajectory = problem.run(values)
    residuals = problem.residuals(trajectory, values)
    integration_error = _integration_error(problem, values, trajectory)
    assessment = assess(
        problem, values, trajectory, residuals, spread, whiteness, noise, outcomes,
        converged, profiled, integration_error,
    )  # fmt: skip
    return trajectory, residuals, assessment


def _check_counts(starts: int | None, workers: int | None, seed: int | None) -> None:
    """The counts among :func:`fit`'s arguments, each checked where given."""
    if starts is not None:
        _check_count("starts", starts, 1, MAX_STARTS)
    if workers is not None:
        _check_count("workers", workers, 1, MAX_WORKERS)
    if seed is not None:
        _check_count("seed", seed, 0)
