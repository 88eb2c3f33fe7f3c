"""Standard errors and correlations from the Jacobian at the optimum.

Linearised least squares: Cov = s² (JᵀJ)⁻¹ with s² = 2 cost / (m − p) = Σ r² / (m − p)
the residual variance (in units of the weights σ_s), computed by SVD of J with its
columns scaled to the parameters' sizes. A singular value below ``RANK_TOLERANCE`` of
the largest marks a direction the data do not determine: the parameters along it get
an infinite standard error, and the rank is reported.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["CORRELATION_LIMIT", "RANK_TOLERANCE", "Uncertainty", "uncertainty"]

CORRELATION_LIMIT = 0.99  # |correlation| above this: not separately identifiable
RANK_TOLERANCE = 1e-8  # singular value of the scaled J, relative to the largest
_NULL_COMPONENT = 1e-3  # a parameter's share of a null direction that makes it undetermined


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
    """

    covariance: np.ndarray
    standard_errors: np.ndarray
    correlation: np.ndarray
    residual_variance: float
    rank: int
    condition_number: float
    strongly_correlated: tuple[tuple[str, str, float], ...]

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


def uncertainty(
    jacobian: np.ndarray,
    cost: float,
    degrees_of_freedom: int,
    scale: np.ndarray,
    names: Sequence[str],
) -> Uncertainty:
    """Covariance, standard errors and correlation of the fit.

    Parameters
    ----------
    jacobian : ∂r/∂x of the weighted residuals at the optimum [1/unit_j], shape (m, p)
    cost : ½ Σ r² at the optimum [1]
    degrees_of_freedom : m − p (less any offsets removed from the residuals), > 0
    scale : the parameters' sizes [unit_j], shape (p,), to condition J
    names : the parameters' names, shape (p,)
    """
    variance = 2.0 * cost / degrees_of_freedom
    scaled = jacobian * scale
    _, singular, rows = np.linalg.svd(scaled, full_matrices=False)
    largest = singular[0] if singular.size and singular[0] > 0.0 else 1.0
    kept = singular > RANK_TOLERANCE * largest
    rank = int(np.count_nonzero(kept))
    vectors = rows[kept].T
    covariance = variance * scale[:, None] * ((vectors / singular[kept] ** 2) @ vectors.T) * scale
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
