"""Exact rational Taylor coefficients of the exact friction functions for u > 1.

For u = |V1|/(ε|Ω_n|) > 1 the instantaneous centre of rotation lies outside the
contact disk, and with k = 1/u the friction functions become one-dimensional
integrals over β ∈ [0, π/2] (``docs/equations.md``, "Exact Coulomb–Contensou
friction"):

- Hertz force      F = (3/2)   ∫ cos³β (1 − k² sin²β)^(1/2) dβ
- Hertz moment     M = (3k/8)  ∫ cos⁵β (1 − k² sin²β)^(−1/2) dβ
- uniform force    F = (4/π)   ∫ cos²β (1 − k² sin²β)^(1/2) dβ   (also u ≤ 1 with k = u, F/u)
- uniform moment   M = (4k/3π) ∫ cos⁴β (1 − k² sin²β)^(−1/2) dβ

Their closed forms lose digits by cancellation for small k, so the kernel uses
these power series in k² there. The coefficients are exact rationals
(binomial series times Wallis integrals); ``kernels/friction_exact.py`` holds
them as floats and a test checks that they equal :func:`coefficients`.
"""

from __future__ import annotations

from fractions import Fraction

__all__ = ["SERIES", "coefficients"]

# name: (prefactor without π, exponent of Δ = (1 − k² sin²β)^(1/2), power of cos β)
SERIES: dict[str, tuple[Fraction, Fraction, int]] = {
    "hertz_force": (Fraction(3, 2), Fraction(1, 2), 3),
    "hertz_moment": (Fraction(3, 8), Fraction(-1, 2), 5),
    "uniform_force": (Fraction(4), Fraction(1, 2), 2),  # 4/π times a Wallis integral with π/2
    "uniform_moment": (Fraction(4, 3), Fraction(-1, 2), 4),
}


def _binomial(alpha: Fraction, n: int) -> Fraction:
    value = Fraction(1)
    for j in range(n):
        value = value * (alpha - j) / (j + 1)
    return value


def _wallis(cos_power: int, sin_power: int) -> Fraction:
    """∫_0^{π/2} cos^a β sin^b β dβ, b even; for even a without its factor π."""
    if cos_power % 2 == 0:
        value = Fraction(1, 2)  # ∫ dβ = π/2, π dropped
        for j in range(2, cos_power + 1, 2):
            value = value * (j - 1) / j
    else:
        value = Fraction(1)
        for j in range(3, cos_power + 1, 2):
            value = value * (j - 1) / j
    for j in range(2, sin_power + 1, 2):
        value = value * (j - 1) / (cos_power + j)
    return value


def coefficients(name: str, terms: int) -> list[Fraction]:
    """c_n, n < ``terms``, of the series Σ c_n k^(2n) of F, or of M/k, named ``name``."""
    prefactor, exponent, cos_power = SERIES[name]
    return [
        prefactor * _binomial(exponent, n) * (-1) ** n * _wallis(cos_power, 2 * n)
        for n in range(terms)
    ]
