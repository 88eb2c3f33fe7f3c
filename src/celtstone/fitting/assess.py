"""Whether to believe a finished fit: each check of ``fitting.diagnostics`` turned into a
sentence that names the fix, and ``converged``, the flag a script tests.

``converged`` is false when the best start stopped at its evaluation limit, a parameter
sits at a bound, the fitted run stopped early, or the profile found a lower cost than the
optimum: the reported numbers are not a minimum of the cost. The other checks (residuals
above the noise or not white, integration error near the noise, no spin reversal) leave
it true and only warn; starts that ended in other minima are counted, not warned about
(the best is reported).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from celtstone.fitting.diagnostics import (
    GOODNESS_LIMIT,
    Whiteness,
    at_bound,
    information_criteria,
)
from celtstone.fitting.problem import Problem
from celtstone.fitting.profile import Profile
from celtstone.fitting.result import StartOutcome
from celtstone.fitting.uncertainty import Uncertainty
from celtstone.simulation.trajectory import Trajectory

__all__ = ["INTEGRATION_ERROR_LIMIT", "Assessment", "assess"]

# the runs' error (fitted run against one at 1/100 of its tolerances), in noise σ_s:
# above this it is not "far below the noise"
INTEGRATION_ERROR_LIMIT = 0.01


@dataclass(frozen=True)
class Assessment:
    """The checks of a fit.

    Parameters
    ----------
    converged : whether the optimum is a minimum inside the bounds (see the module)
    at_bound : free names at a bound
    goodness : series -> residual RMS over the noise measured without the model [1]
    noise : series -> that noise σ [unit of the series] and where it came from
    whiteness : series -> its residuals' whiteness
    chi_square : Σ ((model − data) / σ_noise)² over every series, with the model-free σ [1]
    information : "aic" and "bic" of the fit as weighted [1]
    starts_reaching_best, distinct_minima : how many starts agreed; minima found
    integration_error : largest change of the fitted model at 1/100 of the tolerances,
        in σ_s [1]
    has_reversal : whether the fitted spin changes sign within the record
    warnings : one sentence per finding
    """

    converged: bool
    at_bound: tuple[str, ...]
    goodness: Mapping[str, float]
    noise: Mapping[str, tuple[float, str]]
    whiteness: Mapping[str, Whiteness]
    chi_square: float
    degrees_of_freedom: int
    information: Mapping[str, float]
    starts_reaching_best: int
    distinct_minima: int
    integration_error: float
    has_reversal: bool
    warnings: tuple[str, ...] = field(default=())

    def summary(self) -> dict[str, Any]:
        dof = max(self.degrees_of_freedom, 1)
        return {
            "converged": self.converged,
            "at_bound": list(self.at_bound),
            "chi_square": self.chi_square,
            "reduced_chi_square": self.chi_square / dof,
            **self.information,
            "goodness_of_fit": {
                name: {
                    "residual_rms_over_noise": ratio,
                    "noise": self.noise[name][0],
                    "noise_source": self.noise[name][1],
                    **self.whiteness[name].summary(),
                }
                for name, ratio in self.goodness.items()
            },
            "distinct_minima": self.distinct_minima,
            "integration_error_over_noise": _finite(self.integration_error),
            "has_reversal": self.has_reversal,
        }


def _finite(value: float) -> float | None:
    return float(value) if math.isfinite(value) else None


def _spin_reverses(trajectory: Trajectory) -> bool:
    spin = trajectory.samples.values("spin")
    signs = np.sign(spin[np.abs(spin) > 0.0])
    return bool(signs.size and np.any(signs != signs[0]))


def assess(
    problem: Problem,
    values: np.ndarray,
    trajectory: Trajectory,
    residuals: np.ndarray,
    spread: Uncertainty,
    whiteness: Mapping[str, Whiteness],
    noise: Mapping[str, float],
    outcomes: Sequence[StartOutcome],
    best_converged: bool,
    profile: Profile | None,
    integration_error: float,
) -> Assessment:
    """Check a fit (see the module); ``noise`` is each series' σ measured without the model
    (or given), ``residuals`` those of the fitted run with ``problem``'s weights."""
    texts: list[str] = []
    pinned = at_bound(values, problem.lower, problem.upper)
    names = problem.names
    for name, value, p, is_pinned in zip(names, values, problem.free, pinned, strict=True):
        if is_pinned:
            side = "lower" if value - p.lower < p.upper - value else "upper"
            texts.append(
                f"{name} = {value:.6g} is at its {side} bound ({p.lower:g}:{p.upper:g}): the "
                f"data push it out of the bounds and its standard error means nothing; widen "
                f"them (--bounds {name}=LO:HI) or fix it if it is known"
            )
    if not best_converged:
        texts.append(
            "the optimiser stopped at its evaluation limit before converging: the values "
            "are not a minimum; start nearer (--start) or check the model"
        )
    goodness, chi_square, start = {}, 0.0, 0
    for name, measured in problem.record.series.items():
        part = residuals[start : start + measured.size] * problem.sigma[name]
        start += measured.size
        ratio = float(np.sqrt(np.mean(part**2))) / noise[name]
        goodness[name] = ratio
        chi_square += float(np.sum((part / noise[name]) ** 2))
        if ratio > GOODNESS_LIMIT:
            texts.append(
                f"the {name} residuals are {ratio:.3g} times the noise measured in the "
                f"record ({noise[name]:.3g}): the model does not explain the record; try "
                "--compare-models, free more numbers, or check the column mapping"
            )
        if not whiteness[name].is_white:
            w = whiteness[name]
            texts.append(
                f"the {name} residuals are not white (lag-1 autocorrelation "
                f"{w.autocorrelation:+.2f}, runs test z {w.runs_z:+.1f}): the model misses "
                "a systematic part; the standard errors are widened (Newey-West) but the "
                "values may be biased"
            )
    best = min(s.cost for s in outcomes)
    variance = spread.residual_variance
    reaching = sum(s.reached_best for s in outcomes)
    minima = _distinct(outcomes, variance)  # reported, not a warning: the best is kept
    lower_profile = profile is not None and float(np.min(profile.costs)) < best - 0.5 * variance
    if lower_profile:
        texts.append(
            "the profile found a lower cost than the optimum: the optimum is not the "
            "minimum; fit again from the profile's best point or with more --starts"
        )
    if integration_error > INTEGRATION_ERROR_LIMIT:
        texts.append(
            f"the runs' integration error reaches {integration_error:.3g} of the noise: "
            "tighten --rtol and --atol"
        )
    reverses = _spin_reverses(trajectory)
    if not reverses:
        texts.append(
            "the fitted spin does not reverse within the record: f and the contact size are "
            "set by the spin's decay alone and may be poorly determined; record until the "
            "stone reverses"
        )
    if not trajectory.ok:
        texts.append(f"the fitted run stopped early: {trajectory.message}")
    converged = best_converged and not pinned.any() and trajectory.ok and not lower_profile
    return Assessment(
        converged=bool(converged),
        at_bound=tuple(n for n, p in zip(names, pinned, strict=True) if p),
        goodness=goodness,
        noise={
            name: (
                noise[name],
                "given"
                if problem.sigma_source.get(name) == "given"
                else "estimated from the record's high-frequency part",
            )
            for name in problem.record.series
        },
        whiteness=dict(whiteness),
        chi_square=chi_square,
        degrees_of_freedom=problem.degrees_of_freedom,
        information=information_criteria(
            float(residuals @ residuals), problem.n_residuals, len(problem.free)
        ),
        starts_reaching_best=reaching,
        distinct_minima=minima,
        integration_error=integration_error,
        has_reversal=reverses,
        warnings=tuple(texts),
    )


def _distinct(outcomes: Sequence[StartOutcome], variance: float) -> int:
    """Minima found by the converged starts (all, if none converged): their costs grouped
    within half the residual variance ``variance`` [1] of each other."""
    ended = [s.cost for s in outcomes if s.converged] or [s.cost for s in outcomes]
    groups, previous = 0, -math.inf
    for cost in sorted(ended):
        if cost - previous > 0.5 * variance:
            groups += 1
            previous = cost
    return groups
