"""Coulomb–Contensou friction over an elliptic Hertz contact, and the Hertz ellipse.

A rigid plane slides with velocity V (2-vector in the contact plane) and spins
with Ω_n about its normal e_z over an elliptic contact of semi-axes A >= B (major
axis along x), loaded by the Hertz pressure

    p(x, y) = 3N / (2πAB) · sqrt(1 − x²/A² − y²/B²).

The local slip is v(x, y) = V + Ω_n e_z × (x, y), and Coulomb's law at every
point gives (issue 13; paper section 2 for the disk)

    F = −f ∫ p v/|v| dA,        M = −f ∫ p ((x, y) × v/|v|)·e_z dA.

The results depend on u = |V|/(A|Ω_n|), the slip direction α from the major axis,
the aspect B/A and the sign of Ω_n only: F = f N F̂, M = f N A M̂.

Method (``docs/equations.md``, "Elliptic Hertz contact"). The local slip
vanishes at the instantaneous centre of sliding ρ* = e_z × V / Ω_n, where v/|v|
jumps. Map the ellipse to the unit disk, σ = (x/A, y/B), and take polar
coordinates about σ* = (ρ*_x/A, ρ*_y/B): σ = σ* + r (cos χ, sin χ), so
(x, y) = ρ* + r (A cos χ, B sin χ). Along each such ray the slip direction is
constant, d(χ) = (−B sin χ, A cos χ)/L(χ) with L = sqrt(A² cos²χ + B² sin²χ),
and the pressure is the disk's, so the radial integrals are elementary (arcsin
and square roots) and only the angle χ is integrated numerically, by adaptive
Gauss–Legendre panels split where the integrand turns fast (the minor-axis
directions and, with ρ* inside, the rays tangent to the circle through σ*).
Where ρ* is inside the contact every ray counts; where it is outside, only the
rays that cross the ellipse, each over its whole chord.

:func:`hertz_ellipse` gives the semi-axes of the Hertz contact of a convex body
with principal radii of curvature R1, R2 on a plane (Johnson, *Contact
Mechanics*, 1985, §4.2, doi:10.1017/CBO9781139171731), with the complete
elliptic integrals written in Carlson's form so that nothing cancels.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from typing import NamedTuple

import numpy as np
from scipy import optimize, special

from celtstone.errors import CeltstoneWarning, ParameterError

__all__ = [
    "HertzEllipse",
    "elliptic_friction",
    "elliptic_friction_functions",
    "hertz_ellipse",
    "zero_slip_moment",
]

# Gauss–Legendre nodes per panel of the angular quadrature
_GAUSS_ORDER = 20
_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(_GAUSS_ORDER)
# most panels the angular quadrature refines at once (a few dozen are usual)
_MAX_PANELS = 4096
# relative tolerance of the angular quadrature; the floor is rounding on ∫|integrand|
_DEFAULT_RTOL = 1e-12
_ROUNDING_FLOOR = 16.0 * np.finfo(float).eps
# 3/(2π): the Hertz pressure per unit N on the unit disk, at its centre
_HERTZ_PEAK = 1.5 / math.pi
# u from which the expansion in 1/u (:func:`_fast_slip`) replaces the quadrature: its
# error, about 0.1/u² (1e-15 here, absolute and relative), is below the quadrature's,
# whose moment of order 1/u comes out of cancelling terms (1e-9 relative at u = 1e7,
# all of it lost by u = 1e16, and the rays no longer resolved beyond)
FAST_SLIP_RATIO = 1e7


def zero_slip_moment(aspect: float) -> float:
    """M0/(f N A) = (3/8) E(e), the pivoting moment at V = 0 [1].

    Parameters
    ----------
    aspect : B/A [1], in (0, 1]

    Notes
    -----
    With x = A s cos θ, y = B s sin θ the moment arm is s sqrt(A² cos²θ + B² sin²θ);
    ∫₀¹ s² sqrt(1 − s²) ds = π/16 and ∫₀^{2π} sqrt(A² cos²θ + B² sin²θ) dθ = 4 A E(e),
    e² = 1 − B²/A² (SciPy's ``ellipe`` takes the parameter m = e²). For B = A,
    E(0) = π/2 gives the disk's 3π/16 (paper eq. 10).
    """
    return 0.375 * float(special.ellipe(1.0 - aspect * aspect))


def _ray_integrands(
    angle: np.ndarray,
    centre_distance: float,
    centre_direction: tuple[float, float],
    aspect: float,
    inside: bool,
) -> np.ndarray:
    """The three χ-integrands (force x, force y, moment) at the rays ψ = χ − θ*.

    σ* = s (cos θ*, sin θ*), s = ``centre_distance``, (cos θ*, sin θ*) = ``centre_direction``.

    ``angle`` is ψ where σ* is inside the disk, β = ψ − π outside (so that the
    narrow fan of rays at large u keeps its relative precision).

    Units: A = 1, A|Ω_n| = 1, Ω_n > 0. With s = |σ*| and the ray σ = σ* + r ê(χ),
    1 − |σ|² = h² − (r − m)², m = −s cos ψ, h² = 1 − s² sin²ψ. With t = r − m the
    radial integrals are ∫ sqrt(h² − t²) tᵏ dt = [G_k], k = 0, 1, 2, from t₀ to h;
    t₀ = −h (whole chord) when σ* is outside the disk and t₀ = −m (from σ*) inside.
    The force weight is ∫ p r dr ∝ m[G0] + [G1]; the moment arm about the centre is
    c + t L, c = ρ_mid × d the arm of the chord's midpoint (kept O(1) so that the
    moment does not cancel at large u), and its weight m c [G0] + (c + m L)[G1] + L[G2].
    Returns shape (3, n) for ``angle`` of shape (n,).
    """
    if inside:
        cos_psi, sin_psi = np.cos(angle), np.sin(angle)
    else:
        cos_psi, sin_psi = -np.cos(angle), -np.sin(angle)
    # χ = θ* + ψ by the addition theorem, so that no component loses digits to
    # rounding of χ where the fan of rays is narrow
    cos_centre, sin_centre = centre_direction
    cos_chi = cos_centre * cos_psi - sin_centre * sin_psi
    sin_chi = sin_centre * cos_psi + cos_centre * sin_psi
    arm = np.hypot(cos_chi, aspect * sin_chi)  # L(χ)
    slip_x = -aspect * sin_chi / arm  # d(χ), the slip direction along the ray
    slip_y = cos_chi / arm
    offset = -centre_distance * cos_psi  # m
    across = -centre_distance * sin_psi  # σ*·(−sin χ, cos χ)
    if inside:
        # h² = (1 − s²) + m², exact near the rim where both terms are small
        edge2 = (1.0 - centre_distance) * (1.0 + centre_distance)  # h² − m², > 0
        edge = math.sqrt(edge2)
        half_chord2 = edge2 + offset * offset
        opening = np.arctan2(offset, edge)  # asin(m/h)
        g0 = 0.25 * math.pi * half_chord2 + 0.5 * (offset * edge + half_chord2 * opening)
        g1 = np.full_like(angle, edge2 * edge / 3.0)
        g2 = 0.0625 * math.pi * half_chord2 * half_chord2 + 0.125 * (
            offset * (2.0 * offset * offset - half_chord2) * edge
            + half_chord2 * half_chord2 * opening
        )
    else:
        half_chord2 = np.maximum(1.0 - across * across, 0.0)  # h²
        g0 = 0.5 * math.pi * half_chord2
        g1 = np.zeros_like(angle)
        g2 = 0.125 * math.pi * half_chord2 * half_chord2
    # arm of the chord midpoint ρ_mid = a (−sin χ, B cos χ), a = σ*·(−sin χ, cos χ):
    # ρ_mid × d = −a (1 − B²) sin χ cos χ / L, written without cancellation
    lever = -across * ((1.0 - aspect) * (1.0 + aspect)) * sin_chi * cos_chi / arm
    force_weight = offset * g0 + g1
    moment_weight = offset * lever * g0 + (lever + offset * arm) * g1 + arm * g2
    return np.stack([slip_x * force_weight, slip_y * force_weight, moment_weight])


def _gauss_panels(
    integrand: Callable[[np.ndarray], np.ndarray], lower: np.ndarray, upper: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre sums of each row of ``integrand`` over each panel, and of |row|."""
    half = 0.5 * (upper - lower)
    nodes = (0.5 * (upper + lower))[:, None] + half[:, None] * _GAUSS_NODES
    values = integrand(nodes.ravel()).reshape(-1, *nodes.shape)
    weights = half[:, None] * _GAUSS_WEIGHTS
    return (values * weights).sum(axis=-1), (np.abs(values) * weights).sum(axis=-1)


def _adaptive_gauss(
    integrand: Callable[[np.ndarray], np.ndarray], breaks: np.ndarray, rtol: float
) -> np.ndarray:
    """∫ of each row of ``integrand`` over [breaks[0], breaks[-1]], panels halved as needed.

    A panel is accepted when its halves' sum differs from its own sum by less than
    its share (by width) of max(rtol |∫ row|, rounding on ∫ |row|), or than the
    rounding on its own ∫ |row|; the halves' sum is kept. All panels of one level
    are evaluated in one vectorised call.
    """
    lower, upper = breaks[:-1], breaks[1:]
    coarse, magnitude = _gauss_panels(integrand, lower, upper)
    tolerance = np.maximum(
        rtol * np.abs(coarse.sum(axis=1)), _ROUNDING_FLOOR * magnitude.sum(axis=1)
    ) / (breaks[-1] - breaks[0])
    total = np.zeros(coarse.shape[0])
    while True:
        middle = 0.5 * (lower + upper)
        halves, sizes = _gauss_panels(
            integrand, np.concatenate([lower, middle]), np.concatenate([middle, upper])
        )
        left, right = halves[:, : lower.size], halves[:, lower.size :]
        fine = left + right
        error = np.abs(fine - coarse)
        allowed = np.maximum(
            tolerance[:, None] * (upper - lower),
            _ROUNDING_FLOOR * (sizes[:, : lower.size] + sizes[:, lower.size :]),
        )
        done = np.all(error <= allowed, axis=0)
        total += fine[:, done].sum(axis=1)
        if done.all():
            return total
        keep = ~done
        if 2 * np.count_nonzero(keep) > _MAX_PANELS:
            break
        lower, upper = (
            np.concatenate([lower[keep], middle[keep]]),
            np.concatenate([middle[keep], upper[keep]]),
        )
        coarse = np.concatenate([left[:, keep], right[:, keep]], axis=1)
    warnings.warn(
        f"elliptic friction: the angular quadrature stopped at {_MAX_PANELS} panels short "
        f"of rtol = {rtol:g} (error estimate {error[:, keep].sum(axis=1).max():.1e})",
        CeltstoneWarning,
        stacklevel=4,
    )
    return total + fine[:, keep].sum(axis=1)


def _breaks(start: float, stop: float, fixed: list[float], origin: float) -> np.ndarray:
    """Panel ends: [start, stop], ``fixed`` and the minor-axis rays origin + angle = π/2 + kπ."""
    points = {start, stop, *fixed}
    first = 0.5 * math.pi - origin
    k = math.ceil((start - first) / math.pi)
    while first + k * math.pi < stop:
        points.add(first + k * math.pi)
        k += 1
    inner = sorted(p for p in points if start <= p <= stop)
    return np.array(inner)


def _friction_quadrature(
    u: float, direction: float, aspect: float, rtol: float
) -> tuple[np.ndarray, float]:
    """F/(fN) (shape (2,)) and M/(fNA) for 0 < u < ∞, Ω_n > 0, by quadrature over χ."""
    # ρ* = e_z × V / Ω_n in units of A; σ* = (ρ*_x, ρ*_y / (B/A))
    centre_x = -u * math.sin(direction)
    centre_y = u * math.cos(direction) / aspect
    centre_distance = math.hypot(centre_x, centre_y)
    if centre_distance == 0.0:  # u below the smallest float times B/A: pure spin
        return np.zeros(2), -zero_slip_moment(aspect)
    centre_angle = math.atan2(centre_y, centre_x)
    inside = centre_distance < 1.0
    if inside:  # every ray from σ*; ψ = ±π/2 are tangent to the circle |σ| = s
        breaks = _breaks(-0.5 * math.pi, 1.5 * math.pi, [0.5 * math.pi], centre_angle)
    else:  # the rays that cross the disk: ψ = π + β, |β| <= asin(1/s)
        width = math.asin(1.0 / centre_distance)
        breaks = _breaks(-width, width, [0.0], centre_angle + math.pi)

    centre_direction = (centre_x / centre_distance, centre_y / centre_distance)

    def integrand(angle: np.ndarray) -> np.ndarray:
        return _ray_integrands(angle, centre_distance, centre_direction, aspect, inside)

    force_x, force_y, moment = -_HERTZ_PEAK * _adaptive_gauss(integrand, breaks, rtol)
    return np.array([force_x, force_y]), float(moment)


def _fast_slip(u: float, direction: float, aspect: float) -> tuple[np.ndarray, float]:
    """F/(fN) and M/(fNA) for u >> 1, to first order in 1/u.

    The local slip direction is ŝ + (Ω_n/|V|) (r·ŝ) ŝ⊥ + O(1/u²), ŝ = (cos α, sin α),
    ŝ⊥ = e_z × ŝ: F = −ŝ, and M = −(Ω_n/|V|) ∫ p (r·ŝ)² dA / N
    = −(cos²α + k² sin²α) / (5u) with ∫ p x² dA = N A²/5, ∫ p y² dA = N B²/5.
    Both neglected terms are O(1/u²) relative.
    """
    cos_a, sin_a = math.cos(direction), math.sin(direction)
    lever = cos_a * cos_a + aspect * aspect * sin_a * sin_a
    return -np.array([cos_a, sin_a]), -lever / (5.0 * u)


def _check_aspect(aspect: float) -> float:
    value = float(aspect)
    if not (0.0 < value <= 1.0):
        raise ParameterError("aspect", aspect, "B/A in (0, 1]", "A is the semi-major axis")
    return value


def elliptic_friction_functions(
    u: float, direction: float = 0.0, aspect: float = 1.0, *, rtol: float = _DEFAULT_RTOL
) -> tuple[np.ndarray, float]:
    """F/(f N) and M/(f N A) over a Hertz ellipse, for a spin Ω_n > 0.

    Parameters
    ----------
    u : slip ratio |V| / (A Ω_n) [1], >= 0; ``math.inf`` for pure slip (Ω_n = 0)
    direction : α, angle of the slip V from the major axis [rad]
    aspect : B/A, ratio of the semi-minor to the semi-major axis [1], in (0, 1]
    rtol : relative tolerance of the angular quadrature [1]

    Returns
    -------
    force : F / (f N) [1], shape (2,), components along the major and minor axes
    moment : M / (f N A) [1], the pivoting moment about e_z (negative: it opposes Ω_n > 0)

    Notes
    -----
    V = u A Ω_n (cos α, sin α). For Ω_n < 0 mirror y: use −α and negate F_y and M.
    u = 0 (pure spin) gives F = 0 and M = −(3/8) E(e) exactly (:func:`zero_slip_moment`);
    u = ∞ gives F = −(cos α, sin α), M = 0 (the pressure's centroid is the centre).
    Accuracy: within 1e-14 absolute of independent quadratures and of the disk's
    closed forms for A = B (``tests/test_friction_ellipse.py``, ``docs/equations.md``).
    From u = ``FAST_SLIP_RATIO`` on, the first terms in 1/u replace the quadrature
    (:func:`_fast_slip`, about 1e-15 there), so every finite u has an answer.
    """
    ratio = float(u)
    slip_angle = float(direction)
    if math.isnan(ratio) or ratio < 0.0:
        raise ParameterError("slip_ratio", u, "a number >= 0 (inf for pure slip)")
    if not math.isfinite(slip_angle):
        raise ParameterError("direction", direction, "a finite angle [rad]")
    shape = _check_aspect(aspect)
    if ratio == 0.0:
        return np.zeros(2), -zero_slip_moment(shape)
    if math.isinf(ratio):
        return -np.array([math.cos(slip_angle), math.sin(slip_angle)]), 0.0
    if ratio >= FAST_SLIP_RATIO:
        return _fast_slip(ratio, slip_angle, shape)
    return _friction_quadrature(ratio, slip_angle, shape, rtol)


def elliptic_friction(
    sliding_velocity: np.ndarray | tuple[float, float],
    spin_rate: float,
    semi_major_axis: float,
    semi_minor_axis: float,
    normal_force: float = 1.0,
    friction_coefficient: float = 1.0,
    *,
    rtol: float = _DEFAULT_RTOL,
) -> tuple[np.ndarray, float]:
    """Coulomb–Contensou force [N] and pivoting moment [N m] over a Hertz ellipse.

    Parameters
    ----------
    sliding_velocity : V [m/s], shape (2,), in the contact's axes (major axis = x)
    spin_rate : Ω_n, spin about the plane's normal e_z [rad/s]
    semi_major_axis : A [m], >= ``semi_minor_axis``
    semi_minor_axis : B [m], > 0
    normal_force : N [N]
    friction_coefficient : f [1]
    rtol : relative tolerance of the angular quadrature [1]

    Returns
    -------
    force : F [N], shape (2,)
    moment : M·e_z [N m]

    Notes
    -----
    V = 0 and Ω_n = 0 together is the singular state of paper eq. (11), where the law
    is set-valued: refused.
    """
    velocity = np.asarray(sliding_velocity, dtype=float).reshape(2)
    if not (0.0 < semi_minor_axis <= semi_major_axis < math.inf):
        raise ParameterError(
            "ellipse", (semi_major_axis, semi_minor_axis), "semi-axes A >= B > 0 [m]"
        )
    speed = math.hypot(velocity[0], velocity[1])
    if speed == 0.0 and spin_rate == 0.0:
        raise ParameterError(
            "sliding_velocity", (0.0, 0.0), "a slip or a spin that is not zero",
            "the Coulomb–Contensou law is set-valued at rest (paper eq. 11)",
        )  # fmt: skip
    direction = math.atan2(velocity[1], velocity[0])
    is_spin_negative = spin_rate < 0.0
    if is_spin_negative:  # the mirror image y -> −y spins the other way
        direction = -direction
    u = math.inf if spin_rate == 0.0 else speed / (semi_major_axis * abs(spin_rate))
    force, moment = elliptic_friction_functions(
        u, direction, semi_minor_axis / semi_major_axis, rtol=rtol
    )
    if is_spin_negative:
        force[1], moment = -force[1], -moment
    load = friction_coefficient * normal_force
    return load * force, load * semi_major_axis * moment


class HertzEllipse(NamedTuple):
    """The contact ellipse of a convex body on a plane (Johnson 1985, §4.2)."""

    semi_major_axis: float
    """a [m]"""
    semi_minor_axis: float
    """b [m]"""
    major_axis_angle: float
    """angle of the major axis from the first principal direction [rad]: 0 or π/2"""
    eccentricity: float
    """e = sqrt(1 − b²/a²) [1]"""


def _curvature_ratio(axis_ratio2: float) -> float:
    """R1/R2 >= 1 of the body whose contact has b²/a² = ``axis_ratio2`` (Johnson eq. 4.36).

    R1/R2 = [E/(1 − e²) − K]/(K − E); with K − E = (e²/3) R_D(0, 1 − e², 1) and
    E − (1 − e²) K = (e²(1 − e²)/3) R_D(0, 1, 1 − e²) this is
    R_D(0, 1, p)/R_D(0, p, 1), p = 1 − e², with no cancellation near e = 0.
    """
    return float(special.elliprd(0.0, 1.0, axis_ratio2) / special.elliprd(0.0, axis_ratio2, 1.0))


def hertz_ellipse(
    radii_of_curvature: tuple[float, float], normal_force: float, effective_modulus: float
) -> HertzEllipse:
    """Semi-axes a >= b [m] of the Hertz contact of a convex body on a plane.

    Parameters
    ----------
    radii_of_curvature : principal radii R1, R2 of the body at the contact [m], > 0
        (the plane's curvature is zero, so they are the relative radii)
    normal_force : N [N], > 0
    effective_modulus : E*, 1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2 [Pa], > 0

    Returns
    -------
    HertzEllipse : a along the direction of the larger radius, b, that direction, e

    Notes
    -----
    Johnson (1985) §4.2, with A' = 1/(2R'), B' = 1/(2R''), R' >= R'': the eccentricity
    solves R'/R'' = [E(e)/(1 − e²) − K(e)]/[K(e) − E(e)] and
    a³ = 3 N (K − E) R' / (π E* e²) = N R' R_D(0, 1 − e², 1) / (π E*), b = a sqrt(1 − e²).
    Equal radii give the circle a = b = (3 N R / (4 E*))^(1/3) (R_D(0, 1, 1) = 3π/4).
    Symbols: R', R'' → radii_of_curvature, N → normal_force, E* → effective_modulus.
    """
    radii = tuple(float(r) for r in radii_of_curvature)
    if len(radii) != 2 or not all(0.0 < r < math.inf for r in radii):
        raise ParameterError("radii_of_curvature", radii_of_curvature, "two numbers > 0 [m]")
    if not (0.0 < normal_force < math.inf):
        raise ParameterError("normal_force", normal_force, "> 0 [N]")
    if not (0.0 < effective_modulus < math.inf):
        raise ParameterError("effective_modulus", effective_modulus, "> 0 [Pa]")
    larger, smaller = max(radii), min(radii)
    ratio = larger / smaller
    if ratio == 1.0:
        axis_ratio2 = 1.0
    else:  # solve in log(b²/a²): R1/R2 grows without bound as b/a -> 0

        def mismatch(log_p: float) -> float:
            return math.log(_curvature_ratio(math.exp(log_p))) - math.log(ratio)

        lower = -1.0
        while mismatch(lower) < 0.0:
            lower *= 2.0
        axis_ratio2 = math.exp(optimize.brentq(mismatch, lower, 0.0, xtol=1e-15, rtol=1e-15))
    semi_major = (
        normal_force * larger * float(special.elliprd(0.0, axis_ratio2, 1.0))
        / (math.pi * effective_modulus)
    ) ** (1.0 / 3.0)  # fmt: skip
    return HertzEllipse(
        semi_major_axis=semi_major,
        semi_minor_axis=semi_major * math.sqrt(axis_ratio2),
        major_axis_angle=0.0 if radii[0] >= radii[1] else 0.5 * math.pi,
        eccentricity=math.sqrt(1.0 - axis_ratio2),
    )
