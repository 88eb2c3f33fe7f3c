"""Whether to believe a fit: residual whiteness, goodness of fit against the noise measured
without the model, parameters at their bounds, information criteria.

Each check is a plain function of arrays; ``fitting.solve`` turns their findings into the
summary's ``warnings`` (and ``converged``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = [
    "AT_BOUND_FRACTION",
    "GOODNESS_LIMIT",
    "RUNS_Z_LIMIT",
    "Whiteness",
    "at_bound",
    "information_criteria",
    "whiteness",
]

# |z| of the Wald-Wolfowitz runs test beyond which residuals are not white (p ≈ 0.003)
RUNS_Z_LIMIT = 3.0
# lag-1 autocorrelation beyond this many 1/sqrt(n): not white (4σ of white noise's)
AUTOCORRELATION_SIGMAS = 4.0
# residual RMS over the model-free noise estimate above which the model does not explain
# the record: that estimate is an upper bound (a fast motion adds to it), so this is
# conservative; white noise alone gives 1 ± 1/sqrt(2 n)
GOODNESS_LIMIT = 1.5
# a parameter closer to a bound than this fraction of the bounds' width is at the bound
AT_BOUND_FRACTION = 1e-4


@dataclass(frozen=True)
class Whiteness:
    """The residuals of one series: lag-1 autocorrelation ρ₁ [1], the runs test's z [1]
    (negative: fewer sign changes than white noise), and whether they look white."""

    autocorrelation: float
    runs_z: float
    samples: int

    @property
    def is_white(self) -> bool:
        limit = AUTOCORRELATION_SIGMAS / math.sqrt(max(self.samples, 1))
        return abs(self.runs_z) <= RUNS_Z_LIMIT and abs(self.autocorrelation) <= limit

    def summary(self) -> dict[str, Any]:
        return {
            "lag1_autocorrelation": self.autocorrelation,
            "runs_test_z": self.runs_z,
            "is_white": self.is_white,
        }


def autocorrelation(residuals: np.ndarray, lag: int) -> float:
    """ρ_lag of ``residuals`` about their mean [1]."""
    centred = residuals - residuals.mean()
    power = float(centred @ centred)
    if lag >= centred.size or power == 0.0:
        return 0.0
    return float(centred[lag:] @ centred[:-lag]) / power


def whiteness(residuals: np.ndarray) -> Whiteness:
    """Lag-1 autocorrelation and the Wald-Wolfowitz runs test of one series' residuals.

    Notes
    -----
    With n₊ residuals above their mean and n₋ below, white noise has
    μ = 2 n₊ n₋ / n + 1 runs of one sign, variance (μ − 1)(μ − 2)/(n − 1);
    z = (runs − μ) / sqrt(variance) (Wald & Wolfowitz 1940, doi:10.1214/aoms/1177731909).
    """
    signs = residuals > residuals.mean()
    above, n = int(np.count_nonzero(signs)), signs.size
    below = n - above
    if above == 0 or below == 0 or n < 3:
        z = -math.inf if n >= 3 else 0.0
    else:
        runs = 1 + int(np.count_nonzero(signs[1:] != signs[:-1]))
        mean = 2.0 * above * below / n + 1.0
        variance = (mean - 1.0) * (mean - 2.0) / (n - 1.0)
        z = (runs - mean) / math.sqrt(variance) if variance > 0.0 else 0.0
    return Whiteness(autocorrelation(residuals, 1), z, n)


def correlation_length(residuals: np.ndarray) -> int:
    """Lags [samples] over which the residuals stay correlated: the first lag whose
    autocorrelation is below 2/sqrt(n) (white noise's 2σ), at least 1."""
    limit = 2.0 / math.sqrt(max(residuals.size, 1))
    centred = residuals - residuals.mean()
    power = float(centred @ centred)
    if power == 0.0:
        return 1
    for lag in range(1, residuals.size // 3):
        if abs(float(centred[lag:] @ centred[:-lag]) / power) < limit:
            return lag
    return max(1, residuals.size // 3)


def at_bound(values: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """Whether each value is at its lower or upper bound (within ``AT_BOUND_FRACTION``
    of the bounds' width), shape (p,)."""
    margin = AT_BOUND_FRACTION * (upper - lower)
    return (values - lower <= margin) | (upper - values <= margin)


def information_criteria(chi_square: float, samples: int, parameters: int) -> dict[str, float]:
    """AIC and BIC of a least-squares fit, lmfit's convention.

    Notes
    -----
    −2 ln L = n ln(χ²/n) (Gaussian noise of unknown level); AIC = −2 ln L + 2 k,
    BIC = −2 ln L + k ln n, with k free parameters and n residuals: lower is better;
    only differences between fits of the same record mean anything.
    """
    n = max(samples, 1)
    neg2_log_likelihood = n * math.log(max(chi_square, 1e-300) / n)
    return {
        "aic": neg2_log_likelihood + 2.0 * parameters,
        "bic": neg2_log_likelihood + math.log(n) * parameters,
    }
