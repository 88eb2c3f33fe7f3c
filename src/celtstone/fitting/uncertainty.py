"""Standard errors and correlations from the Jacobian at the optimum.

Linearised least squares: Cov = s² (JᵀJ)⁻¹ with s² = 2 cost / (m − p) = Σ r² / (m − p)
the residual variance (in units of the weights σ_s), computed by SVD of J with its
columns scaled to the parameters' sizes. A singular value below ``RANK_TOLERANCE`` of
the largest marks a direction the data do not determine: the parameters along it get
an infinite standard error, and the rank is reported.

Where the residuals are not white (``fitting.diagnostics``), s² (JᵀJ)⁻¹ is too tight:
:func:`autocorrelation_consistent` gives the Newey-West covariance (Bartlett weights over
the residuals' correlation length), and the fit reports the larger of the two errors.

Each number's 95 % interval holds its truth in 95 % of records; k of them hold theirs
together less often (about 90 % for two). :class:`JointRegion` is the region that holds
all k together in 95 % of records: the ellipsoid of the covariance at χ²_k's 95 %
quantile, and its shadow on each axis (simultaneous intervals).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = [
    "CORRELATION_LIMIT",
    "JOINT_LEVEL",
    "RANK_TOLERANCE",
    "JointRegion",
    "Uncertainty",
    "autocorrelation_consistent",
    "uncertainty",
]

CORRELATION_LIMIT = 0.99  # |correlation| above this: not separately identifiable
RANK_TOLERANCE = 1e-8  # singular value of the scaled J, relative to the largest
_NULL_COMPONENT = 1e-3  # a parameter's share of a null direction that makes it undetermined
JOINT_LEVEL = 0.95  # the probability that the joint region holds all its truths together


@dataclass(frozen=True)
class Uncertainty:
    """What the data say about the fitted numbers.

    Parameters
    ----------
    covariance : [unit_i unit_j], shape (p, p); inf where undetermined
    standard_errors : [unit of each parameter], shape (p,); inf where undetermined
    correlation : [1], shape (p, p); NaN where undetermined
    residual_variance : s² [1], in units of the weights
    rank : rank of J (p when every direction is determined)
    condition_number : largest over smallest singular value of the scaled J
    strongly_correlated : (name, name, correlation) of the pairs above the limit
    widened_by_profile : each standard error's factor that makes the 95 % interval hold
        the other minima the data cannot reject (``fitting.solve``), empty when none
    joint_covariance : the covariance whose ellipsoid is the joint 95 % region
        [unit_i unit_j], shape (p, p): widened to hold the profiles' crossings of the
        joint level and the minima below it (``fitting.solve``); None: ``covariance``
    """

    covariance: np.ndarray
    standard_errors: np.ndarray
    correlation: np.ndarray
    residual_variance: float
    rank: int
    condition_number: float
    strongly_correlated: tuple[tuple[str, str, float], ...]
    widened_by_profile: tuple[float, ...] = ()
    joint_covariance: np.ndarray | None = None

    def warnings(self, names: Sequence[str]) -> list[str]:
        """One sentence per identifiability problem (for ``IdentifiabilityWarning``)."""
        texts = [
            f"{a} and {b} are not separately identifiable from these data (correlation "
            f"{c:+.4f}): fix one with --set, or measure a series that tells them apart"
            for a, b, c in self.strongly_correlated
        ]
        undetermined = [n for n, e in zip(names, self.standard_errors, strict=True) if np.isinf(e)]
        if undetermined:
            texts.append(
                f"the Jacobian has rank {self.rank} < {len(names)}: "
                f"{', '.join(undetermined)} are not determined by these data"
            )
        return texts


def _inverse_normal(scaled: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(JᵀJ)⁻¹ of the scaled J on its determined directions, the singular values and rows."""
    _, singular, rows = np.linalg.svd(scaled, full_matrices=False)
    largest = singular[0] if singular.size and singular[0] > 0.0 else 1.0
    kept = singular > RANK_TOLERANCE * largest
    vectors = rows[kept].T
    return (vectors / singular[kept] ** 2) @ vectors.T, singular, rows


def autocorrelation_consistent(
    jacobian: np.ndarray,
    residuals: np.ndarray,
    blocks: Sequence[slice],
    lags: Sequence[int],
    scale: np.ndarray,
    degrees_of_freedom: int,
) -> np.ndarray:
    """Newey-West covariance of the fitted numbers [unit_i unit_j], shape (p, p).

    Parameters
    ----------
    jacobian : ∂r/∂x of the weighted residuals [1/unit_j], shape (m, p)
    residuals : the weighted residuals [1], shape (m,)
    blocks : the rows of each series (correlated within a series only)
    lags : each series' correlation length L [samples] (Bartlett weights 1 − l/(L + 1))
    scale : the parameters' sizes [unit_j], shape (p,)
    degrees_of_freedom : m − p, for the small-sample factor m / (m − p)

    Notes
    -----
    Cov = A S A with A = (JᵀJ)⁻¹ and S = Σ_l w_l Σ_t (g_t g_{t−l}ᵀ + g_{t−l} g_tᵀ),
    g_t = J_t r_t (Newey & West 1987, doi:10.2307/1913610); for white residuals it is
    s² (JᵀJ)⁻¹ up to sampling noise.
    """
    scaled = jacobian * scale
    inverse, _, _ = _inverse_normal(scaled)
    meat = np.zeros((scaled.shape[1], scaled.shape[1]))
    for rows, lag in zip(blocks, lags, strict=True):
        g = scaled[rows] * residuals[rows, None]
        meat += g.T @ g
        for step in range(1, min(lag, g.shape[0] - 1) + 1):
            weight = 1.0 - step / (lag + 1.0)
            cross = g[step:].T @ g[:-step]
            meat += weight * (cross + cross.T)
    correction = residuals.size / max(degrees_of_freedom, 1)
    return correction * scale[:, None] * (inverse @ meat @ inverse) * scale


def uncertainty(
    jacobian: np.ndarray,
    cost: float,
    degrees_of_freedom: int,
    scale: np.ndarray,
    names: Sequence[str],
    widened: np.ndarray | None = None,
) -> Uncertainty:
    """Covariance, standard errors and correlation of the fit.

    Parameters
    ----------
    jacobian : ∂r/∂x of the weighted residuals at the optimum [1/unit_j], shape (m, p)
    cost : ½ Σ r² at the optimum [1]
    degrees_of_freedom : m − p (less any offsets removed from the residuals), > 0
    scale : the parameters' sizes [unit_j], shape (p,), to condition J
    names : the parameters' names, shape (p,)
    widened : a covariance for residuals that are not white
        (:func:`autocorrelation_consistent`): each standard error is the larger of the two
    """
    variance = 2.0 * cost / degrees_of_freedom
    scaled = jacobian * scale
    inverse, singular, rows = _inverse_normal(scaled)
    largest = singular[0] if singular.size and singular[0] > 0.0 else 1.0
    kept = singular > RANK_TOLERANCE * largest
    rank = int(np.count_nonzero(kept))
    covariance = variance * scale[:, None] * inverse * scale
    if widened is not None:  # the larger of the two variances, correlations kept
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = np.sqrt(np.maximum(np.diag(widened) / np.diag(covariance), 1.0))
        ratio = np.where(np.isfinite(ratio), ratio, 1.0)
        covariance = covariance * np.outer(ratio, ratio)
    null = rows[~kept]
    undetermined = (
        np.any(np.abs(null) > _NULL_COMPONENT, axis=0) if null.size else np.zeros(len(names), bool)
    )
    covariance[undetermined, :] = np.inf
    covariance[:, undetermined] = np.inf
    with np.errstate(invalid="ignore"):
        errors = np.sqrt(np.diag(covariance))
        correlation = covariance / np.outer(errors, errors)
    correlation[undetermined, :] = np.nan
    correlation[:, undetermined] = np.nan
    np.fill_diagonal(correlation, np.where(undetermined, np.nan, 1.0))
    pairs = tuple(
        (names[i], names[j], float(correlation[i, j]))
        for i in range(len(names))
        for j in range(i + 1, len(names))
        if abs(correlation[i, j]) > CORRELATION_LIMIT
    )
    smallest = singular[-1] if singular.size else 0.0
    condition = float(largest / smallest) if smallest > 0.0 else float("inf")
    return Uncertainty(covariance, errors, correlation, variance, rank, condition, pairs)


@dataclass(frozen=True)
class JointRegion:
    """The joint 95 % confidence region of several fitted numbers.

    Parameters
    ----------
    names : the numbers' names, shape (k,)
    values : their fitted values [their units], shape (k,)
    covariance : their reported covariance [unit_i unit_j], shape (k, k)

    Notes
    -----
    The ellipsoid q(θ) = (θ − θ̂)ᵀ C⁻¹ (θ − θ̂) ≤ χ²_k(0.95) holds all k true values
    together with probability 0.95 where θ̂ is normal with covariance C (Seber & Wild,
    Nonlinear Regression, 1989, ch. 5, doi:10.1002/0471725315). Its shadow on axis j,
    θ̂_j ± sqrt(χ²_k(0.95)) σ_j, is a simultaneous interval (Scheffé's projection): all of
    them hold their truths whenever the ellipsoid does, at the price of being wider than
    the marginal θ̂_j ± 1.96 σ_j (2.45 σ_j for two numbers).
    """

    names: tuple[str, ...]
    values: np.ndarray
    covariance: np.ndarray

    @property
    def quantile(self) -> float:
        """χ²_k(0.95) [1], k = len(names)."""
        from scipy.stats import chi2

        return float(chi2.ppf(JOINT_LEVEL, len(self.names)))

    @property
    def is_determined(self) -> bool:
        """Whether every number has a finite, positive variance and C is invertible."""
        finite = bool(np.all(np.isfinite(self.covariance)))
        return finite and bool(np.all(np.linalg.eigvalsh(self.covariance) > 0.0))

    def statistic(self, point: np.ndarray) -> float:
        """q(``point``) [1]: inside the region where at most :attr:`quantile`.

        ``point`` [units of the numbers], shape (k,). inf where the region is not
        determined.
        """
        if not self.is_determined:
            return math.inf
        difference = np.asarray(point, dtype=float) - self.values
        return float(difference @ np.linalg.solve(self.covariance, difference))

    def simultaneous_intervals(self) -> dict[str, tuple[float, float]]:
        """Name -> the region's shadow on its axis [its unit] (``Notes``)."""
        half = math.sqrt(self.quantile) * np.sqrt(np.diag(self.covariance))
        return {
            name: (float(value - h), float(value + h))
            for name, value, h in zip(self.names, self.values, half, strict=True)
        }

    def summary(self) -> dict[str, object]:
        """The region as ``summary.json`` writes it (``joint_region_95``)."""
        determined = self.is_determined
        return {
            "parameters": list(self.names),
            "level": JOINT_LEVEL,
            "chi_square_quantile": self.quantile,
            "simultaneous_intervals_95": {
                name: list(ends) if determined else None
                for name, ends in self.simultaneous_intervals().items()
            },
        }
