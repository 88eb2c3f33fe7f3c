"""Hertz contact radius from the normal force and the curvature at the contact point.

The elliptic Hertz contact of two principal radii R1, R2 is reduced to a circular
one of the equivalent radius R_eq = sqrt(R1 R2) (Johnson, *Contact Mechanics*,
1985, ch. 4, without the correction factor for the ellipticity); see ``docs/equations.md``.
"""

from __future__ import annotations

import math

from celtstone.kernels._jit import kernel
from celtstone.kernels.geometry import superellipsoid_gaussian_curvature
from celtstone.kernels.implicit import implicit_gaussian_curvature
from celtstone.kernels.layout import ShapeCode
from celtstone.kernels.vector import Vec


@kernel
def equivalent_radius(n: Vec, params) -> float:
    """R_eq = sqrt(R1 R2) = 1/sqrt(K), K the Gaussian curvature at the contact point [m].

    Notes
    -----
    Ellipsoid with Q = diag(a², b², c²): K = (nᵀQn)² / (a²b²c²) at the point of
    normal -n, so R_eq = abc / (nᵀQn). Paraboloid z = x²/(2ρ1) + y²/(2ρ2):
    K = n3⁴ / (ρ1 ρ2), so R_eq = sqrt(ρ1 ρ2) / n3². n need not be exactly unit.
    At rest (n = e3) both give sqrt(ρ1 ρ2), with ρ1 = a²/c, ρ2 = b²/c for the ellipsoid.
    Superellipsoid: K from ``geometry.superellipsoid_gaussian_curvature`` (0, so R_eq
    infinite, on its flat curves: models refuse a Hertz radius for p > 2). Implicit
    polynomial: K from ``implicit.implicit_gaussian_curvature`` (Newton solve).
    An unknown shape code gives NaN.
    """
    norm2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2]
    shape = params.shape_code
    axes = params.semi_axes
    if shape == ShapeCode.ELLIPSOID:
        a, b, c = axes[0], axes[1], axes[2]
        quadratic = (a * a * n[0] * n[0] + b * b * n[1] * n[1] + c * c * n[2] * n[2]) / norm2
        return a * b * c / quadratic
    if shape == ShapeCode.PARABOLOID:
        radii = params.radii_of_curvature
        return math.sqrt(radii[0] * radii[1]) * norm2 / (n[2] * n[2])
    if shape == ShapeCode.SUPERELLIPSOID:
        curvature = superellipsoid_gaussian_curvature(n, axes[0], axes[1], axes[2], params.exponent)
        return 1.0 / math.sqrt(curvature) if curvature > 0.0 else math.inf
    if shape == ShapeCode.IMPLICIT:
        return 1.0 / math.sqrt(implicit_gaussian_curvature(n, params))
    return math.nan


@kernel
def hertz_contact_radius(
    normal_force: float, equivalent_radius: float, effective_modulus: float
) -> float:
    """ε = (3 N R_eq / (4 E*))^(1/3), the Hertz contact radius [m].

    Parameters
    ----------
    normal_force : N [N], > 0
    equivalent_radius : R_eq [m]
    effective_modulus : E*, 1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2 [Pa]

    Notes
    -----
    Johnson (1985), ch. 4, circular contact; doi:10.1017/CBO9781139171731.
    """
    return (0.75 * normal_force * equivalent_radius / effective_modulus) ** (1.0 / 3.0)
