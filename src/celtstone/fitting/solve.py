"""``fit``: weighted least squares of a record by the simulator, from several starts.

SciPy's ``least_squares`` (trust-region reflective, bounded) minimises ½ Σ r² over the
free numbers; the forward-difference Jacobian's runs go in parallel on threads, as many
as there are idle threads started beside each residual (``fitting.runs``); starts besides
the user's are drawn by Latin hypercube within the bounds (log-uniform where the bounds
span a decade or more), seeded.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from types import MappingProxyType

import numpy as np

from celtstone.bodies import Body, load_body
from celtstone.errors import (
    FrictionBoundWarning,
    IdentifiabilityWarning,
    ParameterError,
    PlausibilityWarning,
)
from celtstone.fitting.problem import Problem, make_problem
from celtstone.fitting.profile import profile_likelihood
from celtstone.fitting.record import Record
from celtstone.fitting.result import FitResult, StartOutcome
from celtstone.fitting.runs import Runs
from celtstone.fitting.uncertainty import uncertainty

__all__ = ["FIT_ATOL", "FIT_RTOL", "MAX_ITERATIONS", "draw_starts", "fit", "reweighted"]

# the runs' tolerances: rtol 1e-8 changes the spin of a 3 s K&L sliding run by 2.5e-9
# rad/s from rtol 1e-10, at half the time (docs/decisions.md §31)
FIT_RTOL = 1e-8
FIT_ATOL = 1e-10
MAX_ITERATIONS = 50  # residual evaluations of one start (least_squares' max_nfev)
# relative changes of cost and of x below which a start has converged
COST_TOLERANCE = 1e-8
STEP_TOLERANCE = 1e-6


def draw_starts(problem: Problem, count: int, seed: int | None) -> list[np.ndarray]:
    """The problem's start and ``count − 1`` more from a seeded Latin hypercube in the
    bounds, log-uniform for a parameter whose positive bounds span a decade or more."""
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
        starts.append(start)
    return starts


def _minimise(
    runs: Runs, x0: np.ndarray, columns: list[int]
) -> tuple[np.ndarray, float, bool, str, np.ndarray, np.ndarray]:
    """least_squares over ``columns`` of the parameter vector from ``x0`` (the others
    held): (optimum, cost, converged, message, Jacobian of the columns there, residuals
    there)."""
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
        ftol=COST_TOLERANCE,
        xtol=STEP_TOLERANCE,
        gtol=COST_TOLERANCE,
        max_nfev=MAX_ITERATIONS,
    )
    converged = result.status > 0
    return full(result.x), float(result.cost), converged, result.message, result.jac, result.fun


def _from_starts(
    runs: Runs, count: int, seed: int | None
) -> tuple[list[StartOutcome], tuple[np.ndarray, float, np.ndarray, np.ndarray]]:
    """Each start's outcome, and the best one's (values, cost, Jacobian, residuals). A start
    reached the best when its cost is within half the residual variance of the best's (the
    same minimum, as far as the data tell)."""
    problem = runs.problem
    columns = list(range(len(problem.free)))
    ends = []
    for x0 in draw_starts(problem, count, seed):
        before = runs.count
        ends.append((x0, *_minimise(runs, x0, columns), runs.count - before))
    best = min(ends, key=lambda end: end[2])
    variance = 2.0 * best[2] / problem.degrees_of_freedom
    outcomes = [
        StartOutcome(x0, x, cost, converged, message, used, cost - best[2] <= 0.5 * variance)
        for x0, x, cost, converged, message, _, _, used in ends
    ]
    return outcomes, (best[1], best[2], best[5], best[6])


def reweighted(problem: Problem, residuals: np.ndarray) -> Problem:
    """``problem`` with each estimated σ_s replaced by the noise level of its series'
    ``residuals`` (weighted by the old σ_s): RMS · sqrt(m / (m − p)) [unit of the series].

    The data's own estimate (``noise_scale``) is biased up where a series curves within a
    few samples (a rocking rate at 100 Hz); the residuals of a first fit are not, so a
    record of several series is fitted again from the optimum with these weights.
    """
    ratio = problem.n_residuals / problem.degrees_of_freedom
    sigma, sources, start = dict(problem.sigma), dict(problem.sigma_source), 0
    for name, measured in problem.record.series.items():
        part = residuals[start : start + measured.size] * sigma[name]
        start += measured.size
        if sources[name] == "estimated":
            sigma[name] = float(np.sqrt(np.mean(part**2) * ratio)) or sigma[name]
            sources[name] = "residuals of a first fit"
    return replace(problem, sigma=MappingProxyType(sigma), sigma_source=MappingProxyType(sources))


def _body(body: Body | str | Path) -> Body:
    return body if isinstance(body, Body) else load_body(body)


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
    starts: int = 1,
    seed: int | None = 0,
    profile: str | None = None,
    rtol: float = FIT_RTOL,
    atol: float = FIT_ATOL,
    method: str | None = None,
    workers: int | None = None,
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
        ``euler_beta`` [deg]) or body numbers (``celtstone sweep`` names).
    bounds : mapping of str to (float, float), optional
        Name -> (LO, HI) [its unit]; defaults in ``fitting.problem.DEFAULT_BOUNDS``.
    start : mapping of str to float, optional
        Name -> first start [its unit]; default the fixed or the model's default value,
        for the initial rates the record's first sample.
    fixed : mapping of str to float or str, optional
        Name -> value of the numbers and options held (``celtstone sweep --set`` names);
        the initial state defaults to the record's first sample of omega1..3 or spin.
    sigma : mapping of str to float, optional
        Series name -> noise scale σ_s weighting it [its SI unit]; default estimated
        from the data (``fitting.problem.noise_scale``).
    starts : int
        Number of starts, the first being ``start`` (>= 1).
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
        Threads for the runs (default: one per core): the Jacobian's columns, and
        beside each residual as many of them as there are threads besides it.
    progress : callable or None
        Called after each residual evaluation with (runs so far, cost).

    Returns
    -------
    FitResult
        The best of the starts, with standard errors and correlations (and an
        :class:`IdentifiabilityWarning` for each pair with |correlation| > 0.99 or a
        rank-deficient Jacobian).
    """
    began = time.perf_counter()
    if not isinstance(starts, int) or isinstance(starts, bool) or starts < 1:
        raise ParameterError("starts", starts, "a whole number >= 1")
    problem = make_problem(
        record,
        _body(body),
        model,
        free,
        bounds=bounds,
        start=start,
        fixed=fixed,
        sigma=sigma,
        rtol=rtol,
        atol=atol,
        method=method,
    )
    if profile is not None and profile not in problem.names:
        raise ParameterError("profile", profile, "a free parameter: " + ", ".join(problem.names))
    columns = list(range(len(problem.free)))
    with warnings.catch_warnings(), Runs(problem, workers, progress) as runs:
        # trial runs warn about nothing; the fitted run below warns once
        warnings.simplefilter("ignore", FrictionBoundWarning)
        warnings.simplefilter("ignore", PlausibilityWarning)
        outcomes, (values, cost, jacobian, residuals) = _from_starts(runs, starts, seed)
        if len(problem.record.series) > 1 and "estimated" in problem.sigma_source.values():
            problem = reweighted(problem, residuals)
            runs.use(problem)
            values, cost, _, _, jacobian, residuals = _minimise(runs, values, columns)
        spread = uncertainty(
            jacobian, cost, problem.degrees_of_freedom, problem.scale, problem.names
        )
        profiled = None
        if profile is not None:
            index = problem.names.index(profile)

            def refit(x: np.ndarray, others: list[int]) -> tuple[np.ndarray, float]:
                optimum, cost = _minimise(runs, x, others)[:2]
                return optimum, cost

            profiled = profile_likelihood(
                runs,
                refit,
                values,
                index,
                spread.standard_errors[index],
                spread.residual_variance,
            )
        count, failed, wasted = runs.count, runs.failed, runs.wasted
    trajectory = problem.run(values)
    residuals = problem.residuals(trajectory)
    texts = tuple(spread.warnings(problem.names))
    for text in texts:
        warnings.warn(text, IdentifiabilityWarning, stacklevel=2)
    return FitResult(
        problem=problem,
        values=values,
        cost=0.5 * float(residuals @ residuals),
        residuals=residuals,
        uncertainty=spread,
        starts=tuple(outcomes),
        runs=count + 1,
        failed_runs=failed + (not trajectory.ok),
        speculative_runs_wasted=wasted,
        wall_time=time.perf_counter() - began,
        trajectory=trajectory,
        profile=profiled,
        warnings=texts,
    )
