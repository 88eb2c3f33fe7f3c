"""Contact point of a body bounded by an implicit polynomial, by a damped Newton solve.

The body is {F(x) <= 1} about an origin O with
F(x) = Σ_k c_k x^i_k y^j_k z^l_k (the record fields ``term_*`` of ``params``, see
``kernels.layout``), or a user's compiled function (``level_function``), and
G = (0, 0, -h). The contact point x* for the upward
vertical n (body axes) is the lowest point of the body: the surface point whose
outward normal ∇F is parallel to -n,

    ∇F(x) + λ n = 0,   F(x) = 1,   λ > 0                     (docs/equations.md)

solved by Newton's method on the bordered system [[H, n], [∇Fᵀ, 0]] (H the
Hessian of F). Its rate follows from differentiating the same conditions:
[[H, n], [∇Fᵀ, 0]] [ẋ; λ̇] = [-λ ṅ; 0]. A failed solve, λ <= 0 or a tangent Hessian
that is not positive definite (the surface not strictly convex there) returns NaN,
which the right-hand side reports as ``RHS_NON_CONVEX``.
"""

from __future__ import annotations

import math

from celtstone.kernels._jit import call_level_function, kernel
from celtstone.kernels.vector import NAN3, Mat, Vec, dot, matvec, solve3, tangent_basis

MAX_ITERATIONS = 50  # Newton iterations before the solve counts as failed
MAX_HALVINGS = 12  # backtracking halvings of one Newton step
STEP_TOLERANCE = 1e-12  # converged when |Δx| <= this × L (quadratic: error ~1e-24 L)
RESIDUAL_FLOOR = 1e-13  # scaled residual at which round-off stops further decrease
SINGULAR_RATIO = 1e-13  # |det| / (product of row norms) of the reduced 3x3 system
MIN_CURVATURE = 1e-8  # smallest principal curvature × L accepted as strictly convex


@kernel
def _powers(v: float, m: int) -> tuple[float, float, float]:
    """(v^m, m v^(m-1), m(m-1) v^(m-2)) for an integer m >= 0; terms with m < 1, 2 are 0."""
    if m == 0:
        return 1.0, 0.0, 0.0
    low = 1.0  # v^(m-2), or 1 for m == 1
    for _ in range(m - 2):
        low *= v
    if m == 1:
        return v, 1.0, 0.0
    return low * v * v, m * low * v, m * (m - 1) * low


@kernel
def polynomial(x: Vec, params) -> tuple[float, Vec, Mat]:
    """F(x) [1], ∇F(x) [1/m] and the Hessian H(x) [1/m²] (row-major 9-tuple).

    x is measured from the origin O of the polynomial [m].
    """
    coefficients = params.term_coefficients
    exponents = params.term_exponents
    count = min(params.term_count, coefficients.shape[0])
    value = 0.0
    g0 = g1 = g2 = 0.0
    hxx = hyy = hzz = hxy = hxz = hyz = 0.0
    for k in range(count):
        c = coefficients[k]
        px, dx, ddx = _powers(x[0], exponents[k, 0])
        py, dy, ddy = _powers(x[1], exponents[k, 1])
        pz, dz, ddz = _powers(x[2], exponents[k, 2])
        value += c * px * py * pz
        g0 += c * dx * py * pz
        g1 += c * px * dy * pz
        g2 += c * px * py * dz
        hxx += c * ddx * py * pz
        hyy += c * px * ddy * pz
        hzz += c * px * py * ddz
        hxy += c * dx * dy * pz
        hxz += c * dx * py * dz
        hyz += c * px * dy * dz
    return value, (g0, g1, g2), (hxx, hxy, hxz, hxy, hyy, hyz, hxz, hyz, hzz)


@kernel
def level_function(x: Vec, params) -> tuple[float, Vec, Mat]:
    """F(x) [1], ∇F(x) [1/m], H(x) [1/m²]: the polynomial of the record's terms, or,
    when ``params.level_function`` is not 0, the user's compiled function at that C
    address (``bodies.function.ImplicitFunction``)."""
    address = params.level_function
    if address == 0:
        return polynomial(x, params)
    out: tuple[float, ...] = call_level_function(address, x[0], x[1], x[2])  # type: ignore[call-arg]
    return (
        out[0],
        (out[1], out[2], out[3]),
        (
            out[4],
            out[5],
            out[6],
            out[7],
            out[8],
            out[9],
            out[10],
            out[11],
            out[12],
        ),
    )


@kernel
def bordered_solve(
    hessian: Mat, n: Vec, gradient: Vec, a: Vec, b: float
) -> tuple[Vec, float, float]:
    """Solve [[H, n], [gᵀ, 0]] [Δx; Δλ] = [a; b]; returns (Δx, Δλ, conditioning ratio).

    Notes
    -----
    Gaussian elimination pivoting on the largest |n_k| of the last column: Δλ is
    eliminated with row k, the other two rows and gᵀ form a 3x3 system solved by
    ``solve3``. The ratio |det| / (product of its row norms) is 0 for a singular
    bordered matrix (tangent Hessian singular: a flat point) and ~1 when well posed.
    """
    k = 0
    if abs(n[1]) > abs(n[k]):
        k = 1
    if abs(n[2]) > abs(n[k]):
        k = 2
    i1 = (k + 1) % 3
    i2 = (k + 2) % 3
    m1 = n[i1] / n[k]
    m2 = n[i2] / n[k]
    r10 = hessian[3 * i1] - m1 * hessian[3 * k]
    r11 = hessian[3 * i1 + 1] - m1 * hessian[3 * k + 1]
    r12 = hessian[3 * i1 + 2] - m1 * hessian[3 * k + 2]
    r20 = hessian[3 * i2] - m2 * hessian[3 * k]
    r21 = hessian[3 * i2 + 1] - m2 * hessian[3 * k + 1]
    r22 = hessian[3 * i2 + 2] - m2 * hessian[3 * k + 2]
    reduced = (r10, r11, r12, r20, r21, r22, gradient[0], gradient[1], gradient[2])
    rhs = (a[i1] - m1 * a[k], a[i2] - m2 * a[k], b)
    step, det = solve3(reduced, rhs)
    scale = (
        math.sqrt(r10 * r10 + r11 * r11 + r12 * r12)
        * math.sqrt(r20 * r20 + r21 * r21 + r22 * r22)
        * math.sqrt(dot(gradient, gradient))
    )
    ratio = abs(det) / scale if scale > 0.0 else 0.0
    if not ratio > SINGULAR_RATIO:
        return (0.0, 0.0, 0.0), 0.0, ratio
    h_step = matvec(hessian, step)
    return step, (a[k] - h_step[k]) / n[k], ratio


@kernel
def tangent_hessian(hessian: Mat, n: Vec) -> tuple[float, float, float]:
    """(T11, T12, T22), H projected on an orthonormal basis t1, t2 of the plane ⊥ n [1/m²]."""
    _, t1, t2 = tangent_basis(n)
    h1 = matvec(hessian, t1)
    h2 = matvec(hessian, t2)
    return dot(t1, h1), dot(t1, h2), dot(t2, h2)


@kernel
def _residual(value: float, gradient: Vec, lam: float, n: Vec, length: float) -> float:
    """sqrt(L² |∇F + λ n|² + (F - 1)²), dimensionless."""
    e0 = gradient[0] + lam * n[0]
    e1 = gradient[1] + lam * n[1]
    e2 = gradient[2] + lam * n[2]
    f = value - 1.0
    return math.sqrt(length * length * (e0 * e0 + e1 * e1 + e2 * e2) + f * f)


@kernel
def implicit_point(n: Vec, params) -> tuple[Vec, float, Vec, Mat, bool]:
    """Lowest surface point x* about O [m] for the vertical n; (x*, λ [1/m], ∇F, H, ok).

    Notes
    -----
    Start: the contact point of the start ellipsoid (centre and semi-axes stored
    in ``params`` by ``bodies.shapes.ImplicitPolynomial``), λ0 = -∇F · n / |n|².
    Each Newton step is halved until the scaled residual falls (Armijo factor
    1 - 1e-4 t); converged when |Δx| <= ``STEP_TOLERANCE`` L (L the largest
    semi-axis), or when the residual sits at round-off. ``ok`` is False when
    the solve fails, λ <= 0 (a highest, not lowest, point), or a principal
    curvature is below ``MIN_CURVATURE`` / L (not strictly convex at x*).
    """
    axes = params.start_semi_axes
    centre = params.start_centre
    qa = axes[0] * axes[0]
    qb = axes[1] * axes[1]
    qc = axes[2] * axes[2]
    length = max(axes[0], max(axes[1], axes[2]))
    s = math.sqrt(qa * n[0] * n[0] + qb * n[1] * n[1] + qc * n[2] * n[2])
    x = (
        centre[0] - qa * n[0] / s,
        centre[1] - qb * n[1] / s,
        centre[2] - qc * n[2] / s,
    )
    value, gradient, hessian = level_function(x, params)
    lam = -dot(gradient, n) / dot(n, n)
    residual = _residual(value, gradient, lam, n, length)
    converged = False
    for _ in range(MAX_ITERATIONS):
        a = (
            -(gradient[0] + lam * n[0]),
            -(gradient[1] + lam * n[1]),
            -(gradient[2] + lam * n[2]),
        )
        step, lam_step, ratio = bordered_solve(hessian, n, gradient, a, 1.0 - value)
        if not ratio > SINGULAR_RATIO:
            break
        if math.sqrt(dot(step, step)) <= STEP_TOLERANCE * length:
            x = (x[0] + step[0], x[1] + step[1], x[2] + step[2])
            lam += lam_step
            value, gradient, hessian = level_function(x, params)
            converged = True
            break
        t = 1.0
        accepted = False
        trial, trial_lam, trial_residual = x, lam, residual
        trial_value, trial_gradient, trial_hessian = value, gradient, hessian
        for _ in range(MAX_HALVINGS):
            trial = (x[0] + t * step[0], x[1] + t * step[1], x[2] + t * step[2])
            trial_lam = lam + t * lam_step
            trial_value, trial_gradient, trial_hessian = level_function(trial, params)
            trial_residual = _residual(trial_value, trial_gradient, trial_lam, n, length)
            if trial_residual <= (1.0 - 1e-4 * t) * residual:
                accepted = True
                break
            t *= 0.5
        if not accepted:
            converged = residual <= RESIDUAL_FLOOR
            break
        x, lam, residual = trial, trial_lam, trial_residual
        value, gradient, hessian = trial_value, trial_gradient, trial_hessian
    ok = converged and lam > 0.0
    if ok:
        t11, t12, t22 = tangent_hessian(hessian, n)
        half_trace = 0.5 * (t11 + t22)
        lowest = half_trace - math.sqrt(0.25 * (t11 - t22) * (t11 - t22) + t12 * t12)
        ok = lowest > MIN_CURVATURE * math.sqrt(dot(gradient, gradient)) / length
    return x, lam, gradient, hessian, ok


@kernel
def implicit_contact(n: Vec, n_rate: Vec, params) -> tuple[Vec, Vec]:
    """Contact point r = x* - G [m] and its rate dr/dt [m/s]; NaN where ``ok`` fails.

    Parameters
    ----------
    n, n_rate : upward vertical in body axes [1] and its time derivative [1/s]
    params : parameter record (``layout.PARAMETERS``) of an implicit shape; h = com_offset [m]

    Notes
    -----
    ẋ solves [[H, n], [∇Fᵀ, 0]] [ẋ; λ̇] = [-λ ṅ; 0] at x* (the derivative of
    ∇F + λ n = 0, F = 1 along n(t)). r is homogeneous of degree 0 in n.
    """
    x, lam, gradient, hessian, ok = implicit_point(n, params)
    if not ok:
        return NAN3, NAN3
    a = (-lam * n_rate[0], -lam * n_rate[1], -lam * n_rate[2])
    rate, _, ratio = bordered_solve(hessian, n, gradient, a, 0.0)
    if not ratio > SINGULAR_RATIO:
        return NAN3, NAN3
    return (x[0], x[1], x[2] + params.com_offset), rate


@kernel
def implicit_gaussian_curvature(n: Vec, params) -> float:
    """Gaussian curvature K = det(T) / |∇F|² at the contact point for n [1/m²]; NaN if none.

    T is the Hessian of F on an orthonormal basis of the tangent plane: the shape
    operator of the level surface is T / |∇F| there.
    """
    _, _, gradient, hessian, ok = implicit_point(n, params)
    if not ok:
        return math.nan
    t11, t12, t22 = tangent_hessian(hessian, n)
    return (t11 * t22 - t12 * t12) / dot(gradient, gradient)
