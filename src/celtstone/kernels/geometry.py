"""Contact point r(n) of a convex surface and its rate of change.

``r`` is the vector from the centre of mass G to the contact point A (the
paper's r_CA = -r_AC), in body axes, for the surface point whose outward
normal is -n. ``r_rate`` is dr/dt = (dr/dn) dn/dt, the paper's V_A^* (eq. 4).
"""

from __future__ import annotations

import math

from celtstone.kernels._jit import kernel
from celtstone.kernels.implicit import implicit_contact
from celtstone.kernels.layout import RHS_NON_CONVEX, RHS_OFF_SHAPE, RHS_OK, ShapeCode
from celtstone.kernels.vector import NAN3, Vec


@kernel
def ellipsoid_contact(
    n: Vec, n_rate: Vec, a: float, b: float, c: float, h: float
) -> tuple[Vec, Vec]:
    """Contact point and its rate for an ellipsoid, G a distance h below its centre.

    Parameters
    ----------
    n, n_rate : upward vertical in body axes [1] and its time derivative [1/s]
    a, b, c : semi-axes along body axes 1, 2, 3 [m]
    h : distance of G below the centre along axis 3 [m]

    Notes
    -----
    With Q = diag(a², b², c²) and s = sqrt(nᵀ Q n): r = -Q n / s + h e3, so
    dr/dt = -Q ṅ / s + Q n (nᵀ Q ṅ) / s³. r is homogeneous of degree 0 in n.
    """
    qa, qb, qc = a * a, b * b, c * c
    s2 = qa * n[0] * n[0] + qb * n[1] * n[1] + qc * n[2] * n[2]
    s = math.sqrt(s2)
    r = (-qa * n[0] / s, -qb * n[1] / s, -qc * n[2] / s + h)
    projection = (qa * n[0] * n_rate[0] + qb * n[1] * n_rate[1] + qc * n[2] * n_rate[2]) / (s2 * s)
    r_rate = (
        -qa * n_rate[0] / s + qa * n[0] * projection,
        -qb * n_rate[1] / s + qb * n[1] * projection,
        -qc * n_rate[2] / s + qc * n[2] * projection,
    )
    return r, r_rate


@kernel
def paraboloid_contact(
    n: Vec, n_rate: Vec, rho1: float, rho2: float, height: float
) -> tuple[Vec, Vec]:
    """Contact point and its rate for the paraboloid cap z = x²/(2ρ1) + y²/(2ρ2).

    Parameters
    ----------
    n, n_rate : upward vertical in body axes [1] and its time derivative [1/s]
    rho1, rho2 : radii of curvature at the rest contact along body axes 1, 2 [m]
    height : height l of G above the rest contact point [m]

    Notes
    -----
    The outward normal (x/ρ1, y/ρ2, -1) is parallel to -n, so x = -ρ1 n1/n3,
    y = -ρ2 n2/n3; valid while n3 > 0.
    """
    x = -rho1 * n[0] / n[2]
    y = -rho2 * n[1] / n[2]
    z = 0.5 * x * x / rho1 + 0.5 * y * y / rho2
    x_rate = -rho1 * (n_rate[0] * n[2] - n[0] * n_rate[2]) / (n[2] * n[2])
    y_rate = -rho2 * (n_rate[1] * n[2] - n[1] * n_rate[2]) / (n[2] * n[2])
    z_rate = x * x_rate / rho1 + y * y_rate / rho2
    return (x, y, z - height), (x_rate, y_rate, z_rate)


@kernel
def _signed_power(value: float, exponent: float) -> float:
    """sign(value) |value|^exponent."""
    magnitude = abs(value) ** exponent
    return magnitude if value >= 0.0 else -magnitude


@kernel
def _power_rate(value: float, rate: float, exponent: float) -> float:
    """d(sign(value) |value|^exponent)/dt = exponent |value|^(exponent-1) rate, taken as 0
    where rate = 0 (|value|^(exponent-1) is unbounded at value = 0 for exponent < 1)."""
    if rate == 0.0:
        return 0.0
    return exponent * abs(value) ** (exponent - 1.0) * rate


@kernel
def superellipsoid_contact(
    n: Vec, n_rate: Vec, a: float, b: float, c: float, h: float, exponent: float
) -> tuple[Vec, Vec]:
    """Contact point and its rate for |x/a|^p + |y/b|^p + |z/c|^p = 1, G h below the centre.

    Parameters
    ----------
    n, n_rate, a, b, c, h : as :func:`ellipsoid_contact` (the vertical and its rate [1],
        [1/s]; the semi-axes and G's offset [m])
    exponent : p >= 2 [1]; p = 2 is the ellipsoid

    Notes
    -----
    The surface point with outward normal u = -n maximises u · x on the body, whose
    support function is the dual norm: with w_i = a_i u_i, e = 1/(p - 1) and
    S = Σ |w_i|^(1+e), x_i = a_i sign(w_i) |w_i|^e / S^(1/p) (p = 2 gives the
    ellipsoid's -Q n / sqrt(nᵀQn)). Closed form, so no iteration can fail.
    With P_i = sign(w_i)|w_i|^e and ẇ_i = -a_i ṅ_i,
    dx_i/dt = a_i e (|w_i|^(e-1) ẇ_i - P_i Σ_j P_j ẇ_j / S) / S^(1/p).
    For p > 2 the normal curvature vanishes on the three coordinate-plane curves of
    the surface (∂²F/∂x_i² ∝ |x_i|^(p-2)), the six axis points (rest contact) among
    them: |w_i|^(e-1) is unbounded as w_i -> 0, so dr/dt is unbounded (integrably,
    ~ |t|^((2-p)/(p-1))) whenever n_i crosses zero; a term with ẇ_i = 0 is taken as 0.
    """
    e = 1.0 / (exponent - 1.0)
    axes = (a, b, c)
    w = (-a * n[0], -b * n[1], -c * n[2])
    w_rate = (-a * n_rate[0], -b * n_rate[1], -c * n_rate[2])
    total = abs(w[0]) ** (1.0 + e) + abs(w[1]) ** (1.0 + e) + abs(w[2]) ** (1.0 + e)
    norm = total ** (1.0 / exponent)
    powered = (_signed_power(w[0], e), _signed_power(w[1], e), _signed_power(w[2], e))
    # d|w|^e sign(w)/dt = e |w|^(e-1) ẇ; S^(-1/p) rate = -(e / S) Σ powered_j ẇ_j / S^(1/p)
    slopes = (
        _power_rate(w[0], w_rate[0], e),
        _power_rate(w[1], w_rate[1], e),
        _power_rate(w[2], w_rate[2], e),
    )
    weighted = powered[0] * w_rate[0] + powered[1] * w_rate[1] + powered[2] * w_rate[2]
    shrink = e * weighted / total
    r = (
        axes[0] * powered[0] / norm,
        axes[1] * powered[1] / norm,
        axes[2] * powered[2] / norm + h,
    )
    r_rate = (
        axes[0] * (slopes[0] - powered[0] * shrink) / norm,
        axes[1] * (slopes[1] - powered[1] * shrink) / norm,
        axes[2] * (slopes[2] - powered[2] * shrink) / norm,
    )
    return r, r_rate


@kernel
def superellipsoid_gaussian_curvature(
    n: Vec, a: float, b: float, c: float, exponent: float
) -> float:
    """Gaussian curvature K [1/m²] of |x/a|^p + |y/b|^p + |z/c|^p = 1 at the point of
    outward normal -n.

    For an implicit surface F = 1 with diagonal Hessian H and gradient g,
    K = Σ_i g_i² Π_(j≠i) H_jj / |g|⁴; here g_i = p sign(x_i)|x_i/a_i|^(p-1)/a_i and
    H_ii = p(p-1)|x_i/a_i|^(p-2)/a_i². K = 0 on the flat curves of p > 2 (any x_i = 0).
    """
    zero = (0.0, 0.0, 0.0)
    r, _ = superellipsoid_contact(n, zero, a, b, c, 0.0, exponent)
    axes = (a, b, c)
    ratios = (abs(r[0]) / a, abs(r[1]) / b, abs(r[2]) / c)
    gradient = (
        exponent * ratios[0] ** (exponent - 1.0) / axes[0],
        exponent * ratios[1] ** (exponent - 1.0) / axes[1],
        exponent * ratios[2] ** (exponent - 1.0) / axes[2],
    )
    bend = exponent * (exponent - 1.0)
    hessian = (
        bend * ratios[0] ** (exponent - 2.0) / axes[0] ** 2,
        bend * ratios[1] ** (exponent - 2.0) / axes[1] ** 2,
        bend * ratios[2] ** (exponent - 2.0) / axes[2] ** 2,
    )
    squared = gradient[0] ** 2 + gradient[1] ** 2 + gradient[2] ** 2
    numerator = (
        gradient[0] ** 2 * hessian[1] * hessian[2]
        + gradient[1] ** 2 * hessian[0] * hessian[2]
        + gradient[2] ** 2 * hessian[0] * hessian[1]
    )
    return numerator / (squared * squared)


@kernel
def contact(n: Vec, n_rate: Vec, params) -> tuple[Vec, Vec]:
    """Contact point r [m] and its rate dr/dt [m/s] for the shape coded in ``params``.

    ``params`` is a record of ``layout.PARAMETERS``; an unknown shape code gives NaN
    (``system.code_status`` reports it).
    """
    shape = params.shape_code
    axes = params.semi_axes
    if shape == ShapeCode.ELLIPSOID:
        return ellipsoid_contact(n, n_rate, axes[0], axes[1], axes[2], params.com_offset)
    if shape == ShapeCode.PARABOLOID:
        radii = params.radii_of_curvature
        return paraboloid_contact(n, n_rate, radii[0], radii[1], params.com_height)
    if shape == ShapeCode.SUPERELLIPSOID:
        return superellipsoid_contact(
            n, n_rate, axes[0], axes[1], axes[2], params.com_offset, params.exponent
        )
    if shape == ShapeCode.IMPLICIT:
        return implicit_contact(n, n_rate, params)
    return NAN3, NAN3


@kernel
def contact_status(n: Vec, r: Vec, params) -> int:
    """RHS status of the contact point r = contact(n, ...)[0] for n.

    ``RHS_OFF_SHAPE`` when n leaves the paraboloid cap's domain (n3 <= 1e-3);
    ``RHS_NON_CONVEX`` when the implicit shape's Newton solve found no strictly
    convex contact point (r is NaN); else ``RHS_OK``.
    """
    if params.shape_code == ShapeCode.PARABOLOID and not n[2] > 1e-3:
        return RHS_OFF_SHAPE
    if params.shape_code == ShapeCode.IMPLICIT and not math.isfinite(r[0]):
        return RHS_NON_CONVEX
    return RHS_OK
