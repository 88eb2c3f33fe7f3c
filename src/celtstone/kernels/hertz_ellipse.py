"""The elliptic Hertz contact at the current contact point: principal radii and semi-axes.

:func:`principal_radii` gives the two principal radii of curvature R1 >= R2 of the body's
surface at the contact point of the vertical n and the direction of R1 (along which the
contact ellipse's major axis lies), for every shape code, from the contact kernel's own
rate dr/dn. :func:`hertz_ellipse_axes` gives the semi-axes A >= B of the Hertz ellipse
(Johnson, *Contact Mechanics*, 1985, §4.2) with the complete elliptic integrals in
Carlson's form, R_D(0, p, 1) and R_D(0, 1, p), evaluated by the AGM (:func:`complete_rd`,
about 0.1 µs for both) rather than by Carlson's duplication (:func:`carlson_rd`, the
general R_D, about 0.17 µs each, six per solve). ``contact.ellipse.hertz_ellipse`` is
the NumPy/SciPy reference both are tested against (``tests/test_hertz_ellipse_kernel.py``).
"""

from __future__ import annotations

import math

from celtstone.kernels._jit import kernel
from celtstone.kernels.geometry import contact, contact_status
from celtstone.kernels.layout import RHS_OK
from celtstone.kernels.vector import NAN3, Vec, dot, tangent_basis

# relative truncation error r of Carlson's R_D series (1995, eq. 2.29): 2^-53
RD_TOLERANCE = 2.0**-53
# (r/4)^(-1/6): the duplication stops once 4^-m Q < |A_m| (Carlson 1995, section 2)
_RD_SCALE = (0.25 * RD_TOLERANCE) ** (-1.0 / 6.0)
# Newton on log p stops after a step below this; the error left is ~0.1 × step² (tested)
NEWTON_STEP_TOLERANCE = 1e-7
MAX_NEWTON_STEPS = 60  # 1 to 3 are used for R1/R2 from 1 + 1e-6 to 1e9; then NaN
# R1/R2 − 1 below this: p from the series of R1/R2 in m = 1 − p, error ~(R1/R2 − 1)³
SERIES_RATIO = 1e-6
# R1 − R2 below this × (R1 + R2) is a round point to rounding: d = t1 of tangent_basis
ROUND_POINT = 16.0 * 2.0**-52
# R_D(0, 1, 1) = 3π/4: the circle's a³ = N R R_D/(π E*) = 3 N R/(4 E*) (Johnson eq. 4.22)
_CIRCLE_RD = 0.75 * math.pi


@kernel
def carlson_rd(x: float, y: float, z: float) -> float:
    """Carlson's R_D(x, y, z) = (3/2) ∫₀^∞ dt / ((t + z) sqrt((t + x)(t + y)(t + z))) [1].

    Parameters
    ----------
    x, y : >= 0, at most one of them 0 [1]
    z : > 0 [1]

    Notes
    -----
    Duplication algorithm of Carlson (1995), section 2 (eqs. 2.25–2.29): with
    λ = √x√y + √x√z + √y√z, each step adds 4^-m / (√z (z + λ)) to a sum Σ and maps
    each argument v to (v + λ)/4, until 4^-m Q < |A_m|, with A₀ = (x + y + 3z)/5,
    A_(m+1) = (A_m + λ)/4 and Q = (r/4)^(-1/6) max |A₀ − v₀|. Then
    X = (A₀ − x₀)/(4^m A_m), Y = (A₀ − y₀)/(4^m A_m), Z = −(X + Y)/3 and
    R_D = 4^-m A_m^(-3/2) (1 − 3E₂/14 + E₃/6 + 9E₂²/88 − 3E₄/22 − 9E₂E₃/52 + 3E₅/26) + 3Σ,
    E₂ = XY − 6Z², E₃ = (3XY − 8Z²)Z, E₄ = 3(XY − Z²)Z², E₅ = XYZ³. The relative
    truncation error is below r = ``RD_TOLERANCE``; arguments outside the domain give
    NaN. 5–9 steps of three square roots for the arguments of the Hertz ellipse.

    References
    ----------
    B. C. Carlson, "Numerical computation of real or complex elliptic integrals",
    Numerical Algorithms 10 (1995) 13–26, doi:10.1007/BF02198293.
    """
    mean0 = (x + y + 3.0 * z) / 5.0
    bound = _RD_SCALE * max(abs(mean0 - x), max(abs(mean0 - y), abs(mean0 - z)))
    x0, y0 = x, y
    mean = mean0
    power = 1.0  # 4^-m
    total = 0.0
    while power * bound >= abs(mean):
        sx, sy, sz = math.sqrt(x), math.sqrt(y), math.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        total += power / (sz * (z + lam))
        power *= 0.25
        x = 0.25 * (x + lam)
        y = 0.25 * (y + lam)
        z = 0.25 * (z + lam)
        mean = 0.25 * (mean + lam)
    big_x = power * (mean0 - x0) / mean
    big_y = power * (mean0 - y0) / mean
    big_z = -(big_x + big_y) / 3.0
    xy = big_x * big_y
    z2 = big_z * big_z
    e2 = xy - 6.0 * z2
    e3 = (3.0 * xy - 8.0 * z2) * big_z
    e4 = 3.0 * (xy - z2) * z2
    e5 = xy * z2 * big_z
    series = (
        1.0
        - 3.0 * e2 / 14.0
        + e3 / 6.0
        + 9.0 * e2 * e2 / 88.0
        - 3.0 * e4 / 22.0
        - 9.0 * e2 * e3 / 52.0
        + 3.0 * e5 / 26.0
    )
    return power * series / (mean * math.sqrt(mean)) + 3.0 * total


@kernel
def radius_of_curvature_tensor(
    n: Vec, params
) -> tuple[Vec, Vec, tuple[float, float, float, float], int]:
    """The radius-of-curvature tensor at the contact point of n on the tangent plane [m].

    Returns (t1, t2, (R11, R12, R21, R22), status): R_ij = −t_i · (dr/dn) t_j on the basis
    of :func:`tangent_basis`, and the RHS status of the contact point (``contact_status``).

    Notes
    -----
    r(n) is the surface point of outward normal ν = −n/|n| measured from G, and is
    homogeneous of degree 0 in n for every shape, so dr/dn n = 0 and, at unit n,
    dr/dn = −dx/dν: the inverse of the shape operator (the Weingarten map), whose
    eigenvalues are the principal radii of curvature, positive on a convex surface.
    dr/dn t_j is the contact kernel's rate for ṅ = t_j at u = n/|n|. The tensor is
    symmetric (the Weingarten map is self-adjoint); R12 and R21 are returned apart so
    that the symmetry can be checked.
    """
    u, t1, t2 = tangent_basis(n)
    r, rate1 = contact(u, t1, params)
    _, rate2 = contact(u, t2, params)
    status = contact_status(u, r, params)
    tensor = (-dot(t1, rate1), -dot(t1, rate2), -dot(t2, rate1), -dot(t2, rate2))
    return t1, t2, tensor, status


@kernel
def principal_radii(n: Vec, params) -> tuple[float, float, Vec]:
    """(R1, R2, d): principal radii of curvature R1 >= R2 [m] at the contact point of the
    vertical n, and the unit direction d of R1 in body axes [1].

    Parameters
    ----------
    n : upward vertical in body axes [1], need not be unit
    params : parameter record (``layout.PARAMETERS``), any shape code

    Returns
    -------
    R1, R2 : larger and smaller principal radius of curvature [m], 0 < R2 <= R1 < ∞
    d : unit vector ⊥ n along the principal direction of R1 [1], the major axis of the
        Hertz contact ellipse; of the two signs, the one whose component of largest
        magnitude is positive (the first on a tie)

    Notes
    -----
    The eigen-decomposition of the symmetric part of :func:`radius_of_curvature_tensor`,
    [[P, S], [S, T]]: R1 = (P + T)/2 + sqrt(((P − T)/2)² + S²), R2 = (PT − S²)/R1, and
    the eigenvector (P − T)/2 + root, S (when P >= T) or S, root − (P − T)/2, which
    cancels nowhere. At a round point (R1 − R2 <= ``ROUND_POINT`` (R1 + R2), where the
    eigenvector is rounding noise) d is t1 of :func:`tangent_basis`. R1, R2 and d are
    NaN when the contact point is bad: off the paraboloid cap, no convex implicit
    contact point, an unknown shape code, a radius that is not finite or not > 0 (a
    flat point of a superellipsoid with p > 2, a saddle), or n = 0. Cost: two calls of
    ``geometry.contact`` (two Newton solves for an implicit shape).
    """
    if not dot(n, n) > 0.0:
        return math.nan, math.nan, NAN3
    t1, t2, tensor, status = radius_of_curvature_tensor(n, params)
    p11, p12, p21, p22 = tensor
    shear = 0.5 * (p12 + p21)
    mean = 0.5 * (p11 + p22)
    half_difference = 0.5 * (p11 - p22)
    root = math.hypot(half_difference, shear)
    larger = mean + root
    smaller = min((p11 * p22 - shear * shear) / larger, larger)  # rounding near a round point
    if not (status == RHS_OK and smaller > 0.0 and larger < math.inf):
        return math.nan, math.nan, NAN3
    if root <= ROUND_POINT * mean:
        v1, v2 = 1.0, 0.0
    elif half_difference >= 0.0:
        v1, v2 = half_difference + root, shear
    else:
        v1, v2 = shear, root - half_difference
    d = (v1 * t1[0] + v2 * t2[0], v1 * t1[1] + v2 * t2[1], v1 * t1[2] + v2 * t2[2])
    length = math.sqrt(dot(d, d))
    k = 0
    if abs(d[1]) > abs(d[k]):
        k = 1
    if abs(d[2]) > abs(d[k]):
        k = 2
    if d[k] < 0.0:
        length = -length
    return larger, smaller, (d[0] / length, d[1] / length, d[2] / length)


@kernel
def _agm_sums(p: float, m: float) -> tuple[float, float]:
    """(3K, T) at p = 1 − m in (0, 1): K = K(m) and T = Σ_(n>=1) 2^(n−1) c_n²/m of the AGM.

    a₀ = 1, b₀ = √p, c₀² = m, a_(n+1) = (a_n + b_n)/2, b_(n+1) = sqrt(a_n b_n),
    c_(n+1) = c_n²/(4 a_(n+1)); K = π/(2 a_∞) (DLMF 19.8.1). Stops once
    2^(n−1) c_n² <= 2^-53 m/2: 3–6 steps of one square root for p from 0.9 to 1e-8.
    """
    a, b = 1.0, math.sqrt(p)
    c2 = m
    weight = 0.5
    total = 0.0
    floor = 0.5 * RD_TOLERANCE * m
    while True:
        a_next = 0.5 * (a + b)
        b = math.sqrt(a * b)
        c2 = c2 * c2 / (16.0 * a_next * a_next)
        a = a_next
        weight *= 2.0
        term = weight * c2
        total += term
        if not term > floor:
            break
    return 1.5 * math.pi / a, total / m


@kernel
def complete_rd(log_p: float) -> tuple[float, float]:
    """(R_D(0, p, 1), R_D(0, 1, p)) at p = exp(log_p) in (0, 1) [1], by the AGM.

    Notes
    -----
    K − E = K Σ_(n>=0) 2^(n−1) c_n² (DLMF 19.8.6; Abramowitz & Stegun 17.6.3–4) with the
    AGM of :func:`_agm_sums`, c₀² = m = 1 − p, so with T = Σ_(n>=1) 2^(n−1) c_n²/m (all
    terms positive): R_D(0, p, 1) = 3(K − E)/m = 3K(1/2 + T) and
    R_D(0, 1, p) = 3(E − pK)/(m p) = 3K(1/2 − T)/p; nothing cancels as m → 0
    (T = m/16 + O(m²)). Agrees with :func:`carlson_rd` to ~1e-15 (tested) at about a
    third of the cost of two of its calls, which need 5–9 duplication steps of three
    square roots each at these arguments.

    References
    ----------
    NIST Digital Library of Mathematical Functions, §19.8(i), https://dlmf.nist.gov/19.8.
    """
    p = math.exp(log_p)
    three_k, excess = _agm_sums(p, -math.expm1(log_p))
    return three_k * (0.5 + excess), three_k * (0.5 - excess) / p


@kernel
def curvature_ratio(log_p: float) -> tuple[float, float, float]:
    """(R1/R2 − 1, d log(R1/R2)/d log p, R_D(0, p, 1)) at p = B²/A² = exp(log_p) in (0, 1).

    Notes
    -----
    R1/R2 = ρ = R_D(0, 1, p)/R_D(0, p, 1) (Johnson eq. 4.36 in Carlson's form, as
    ``contact.ellipse._curvature_ratio``), so with T of :func:`complete_rd`
    δ = ρ − 1 = (m/2 − T(1 + p))/(p(1/2 + T)), exact as m → 0. With D1 = R_D(0, p, 1)
    = 3(K − E)/m, D2 = R_D(0, 1, p) = 3(E − pK)/(m p), dK/dm = (E − pK)/(2mp),
    dE/dm = (E − K)/(2m) and K = (D1 + p D2)/3: d log ρ/d log p = −(1/ρ + 2m − pρ)/(2m)
    = −(m(1 + δ)(3 + δ) − δ(2 + δ))/(2mρ): −3/4 at p → 1, → −1 as p → 0.
    """
    p = math.exp(log_p)
    m = -math.expm1(log_p)
    three_k, excess = _agm_sums(p, m)
    major = three_k * (0.5 + excess)
    delta = (0.5 * m - excess * (1.0 + p)) / (p * (0.5 + excess))
    ratio = 1.0 + delta
    slope = -(m * ratio * (3.0 + delta) - delta * (2.0 + delta)) / (2.0 * m * ratio)
    return delta, slope, major


@kernel
def axis_ratio_squared(curvature_ratio_value: float) -> tuple[float, float]:
    """(p, R_D(0, p, 1)): p = B²/A² = 1 − e² of the Hertz ellipse for ρ = R1/R2 >= 1 [1].

    Notes
    -----
    Solves log ρ(p) = log(R1/R2) for L = log p by Newton's method with the exact slope
    of :func:`curvature_ratio` (log ρ is smooth, decreasing and nearly linear in L),
    kept inside the bracket [lower, upper] of L met so far (a bisection where a step
    would leave it). Start: for log ρ <= 2, Hamrock & Brewe's B/A ≈ (R2/R1)^(2/π)
    (1983), L0 = −(4/π) log ρ (off by < 0.08 in L); above, the asymptote
    ρ ≈ 1/(p(K − 1)), K ≈ log(4/√p) as p → 0, iterated twice,
    L0 ← −log ρ − log(log 4 − 1 − L0/2) from L0 = −log ρ (off by < 0.06). The loop
    stops at a step below ``NEWTON_STEP_TOLERANCE``, takes it, and moves R_D(0, p, 1)
    along it by d log R_D(0, p, 1)/d log p = −pδ/(2m) (dR_D/dm = (D2 − D1)/(2m)):
    both are then exact to rounding (the error left is ~0.1 × step²). One to three
    evaluations of :func:`curvature_ratio` (one AGM each) for R1/R2 from 1 + 1e-6 to 1e9.
    For δ = ρ − 1 < ``SERIES_RATIO``: ρ = 1 + 3m/4 + 21m²/32 + O(m³) (the AGM's
    T = m/16 + m²/32 + O(m³)) inverted, m = 4δ/3 − 14δ²/9; ρ = 1 is the circle, p = 1,
    R_D(0, 1, 1) = 3π/4. NaN for ρ < 1 or NaN.

    References
    ----------
    B. J. Hamrock and D. E. Brewe, "Simplified solution for stresses and deformations",
    J. Lubrication Technology 105 (1983) 171–177, doi:10.1115/1.3254558.
    """
    if not curvature_ratio_value >= 1.0:
        return math.nan, math.nan
    excess = curvature_ratio_value - 1.0
    if excess == 0.0:
        return 1.0, _CIRCLE_RD
    if excess < SERIES_RATIO:
        m = excess * (4.0 / 3.0 - 14.0 / 9.0 * excess)
        return 1.0 - m, complete_rd(math.log1p(-m))[0]
    target = math.log(curvature_ratio_value)
    if target <= 2.0:
        log_p = -4.0 / math.pi * target
    else:
        log_p = -target
        for _ in range(2):
            log_p = -target - math.log(math.log(4.0) - 1.0 - 0.5 * log_p)
    lower, upper = -math.inf, 0.0
    for _ in range(MAX_NEWTON_STEPS):
        delta, slope, major = curvature_ratio(log_p)
        mismatch = math.log1p(delta) - target
        if mismatch > 0.0:  # ρ too large: p too small (ρ falls as p grows)
            lower = log_p
        else:
            upper = log_p
        step = -mismatch / slope
        if abs(step) < NEWTON_STEP_TOLERANCE:
            rate = 0.5 * math.exp(log_p) * delta / math.expm1(log_p)  # −pδ/(2m)
            return math.exp(log_p + step), major * (1.0 + rate * step)
        log_p += step
        if not (lower < log_p < upper):
            log_p = 0.5 * (lower + upper)
    return math.nan, math.nan


@kernel
def hertz_ellipse_axes(
    radius_major: float, radius_minor: float, normal_force: float, effective_modulus: float
) -> tuple[float, float]:
    """Semi-axes A >= B [m] of the Hertz contact ellipse of a convex body on a plane.

    Parameters
    ----------
    radius_major, radius_minor : principal radii of curvature R1 >= R2 > 0 at the
        contact [m] (the plane's are infinite); A lies along the direction of R1
    normal_force : N [N], > 0
    effective_modulus : E*, 1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2 [Pa], > 0

    Notes
    -----
    Johnson (1985) §4.2 in Carlson's form (as ``contact.ellipse.hertz_ellipse``):
    p = B²/A² = 1 − e² solves R1/R2 = R_D(0, 1, p)/R_D(0, p, 1) (:func:`axis_ratio_squared`),
    A³ = N R1 R_D(0, p, 1)/(π E*), B = A √p. R1 = R2 gives the circle
    A = B = (3 N R/(4 E*))^(1/3) (eq. 4.22). Symbols: R', R'' → radius_major,
    radius_minor; N → normal_force; E* → effective_modulus. NaN for R1 < R2, R2 <= 0.
    doi:10.1017/CBO9781139171731.
    """
    if not radius_minor > 0.0:
        return math.nan, math.nan
    p, major = axis_ratio_squared(radius_major / radius_minor)
    semi_major = (normal_force * radius_major * major / (math.pi * effective_modulus)) ** (
        1.0 / 3.0
    )
    return semi_major, semi_major * math.sqrt(p)
