"""The Coulomb–Contensou integrals of paper section 2 by direct numerical quadrature.

F/(fN) and M/(fNε) for a sliding-and-pivoting disk with an axisymmetric
pressure, as functions of u = |V1| / (ε|Ω_n|) alone (references.md). This is
the reference the closed forms of ``kernels/friction_exact.py`` are tested
against; it is slow (milliseconds) and used only outside the integrator.

Method: in units of ε and ε|Ω_n| the local slip at ρ is v = u e1 + e3 × ρ,
which vanishes at the instantaneous centre of rotation (ICR) ρ* = u e2 — inside
the disk for u < 1, where v/|v| is discontinuous. In polar coordinates (q, φ)
centred on the ICR, ρ = ρ* + q (cos φ, sin φ), the slip direction is
(−sin φ, cos φ) along a whole ray, so both integrands are smooth:

    F = ∫ dφ ∫ p(ρ) (−sin φ) q dq,     M = ∫ dφ ∫ p(ρ) (q + u sin φ) q dq

(F along −V1, M about −n·sign Ω_n; p is the pressure per unit N in units of
1/ε²). A ray meets the unit circle at q = c ∓ h, c = −u sin φ,
h² = 1 − u² cos² φ; the substitution q = c + h sin t absorbs the square-root
end behaviour of the Hertz pressure. The outer integral runs over the whole
circle for u <= 1 and over the rays that meet the disk for u > 1.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from celtstone.errors import ParameterError, require_choice
from celtstone.simulation.schema import real_number

__all__ = ["MAX_QUADRATURE_SLIP_RATIO", "PRESSURE_DENSITIES", "friction_integrals"]

# largest u the quadrature answers: beyond it the rays that meet the disk span an angle
# of 2/u around φ = 3π/2, and the error grows from about 1e-12 at u = 1e4 to 1e-9 at
# 1e6 and a zero force at 1e155 (the closed forms, ``friction_functions``, have none)
MAX_QUADRATURE_SLIP_RATIO = 1e4


def _hertz(rho2: float) -> float:
    """Hertz pressure per unit N, paper eq. (2) with ε = 1: 3/(2π) sqrt(1 − ρ²)."""
    return 1.5 / math.pi * math.sqrt(max(0.0, 1.0 - rho2))


def _uniform(rho2: float) -> float:
    """Uniform pressure per unit N with ε = 1: 1/π."""
    return 1.0 / math.pi


# pressure per unit normal force on the unit disk, as a function of ρ²
PRESSURE_DENSITIES: dict[str, Callable[[float], float]] = {
    "hertz": _hertz,
    "uniform": _uniform,
}


def _ray_integrals(
    phi: float, u: float, density: Callable[[float], float], rtol: float
) -> tuple[float, float]:
    """∫ p q dq and ∫ p (q − c) q dq along the ray of angle φ from the ICR.

    With q = c + h sin t, 1 − ρ² = h² cos² t; for u > 1 the ray crosses the whole
    chord (t from −π/2 to π/2) and p is even in t, so the odd part of the second
    integrand, c h² sin t cos t p, is dropped: it would cancel to rounding error
    times u.
    """
    from scipy.integrate import quad  # on first use: SciPy's quadrature is slow to import

    sine, cosine = math.sin(phi), math.cos(phi)
    half_chord2 = 1.0 - u * u * cosine * cosine
    if half_chord2 <= 0.0:
        return 0.0, 0.0
    half_chord = math.sqrt(half_chord2)
    centre = -u * sine
    if centre + half_chord <= 0.0:
        return 0.0, 0.0
    full_chord = centre - half_chord >= 0.0
    t_lower = -0.5 * math.pi
    if not full_chord:  # the ray starts at the ICR inside the disk, q = 0
        t_lower = math.asin(max(-1.0, min(1.0, -centre / half_chord)))

    def load(t: float) -> float:
        """p(ρ) dq/dt along the ray."""
        cos_t = math.cos(t)
        return density(1.0 - half_chord2 * cos_t * cos_t) * half_chord * cos_t

    def first(t: float) -> float:
        return load(t) * (centre + half_chord * math.sin(t))

    def second(t: float) -> float:
        offset = half_chord * math.sin(t)  # q − c
        lever = offset if full_chord else centre + offset
        return load(t) * offset * lever

    options = {"epsabs": 1e-15 * (1.0 + u), "epsrel": rtol, "limit": 200}
    return (
        quad(first, t_lower, 0.5 * math.pi, **options)[0],
        quad(second, t_lower, 0.5 * math.pi, **options)[0],
    )


def friction_integrals(
    u: float, pressure: str = "hertz", rtol: float = 1e-11
) -> tuple[float, float]:
    """F/(fN) and M/(fNε) at u = |V1| / (ε|Ω_n|) >= 0 by quadrature.

    Parameters
    ----------
    u : float
        Slip ratio [1], in [0, ``MAX_QUADRATURE_SLIP_RATIO``] (1e4).
    pressure : str, optional
        ``"hertz"`` (paper eq. 2) or ``"uniform"``.
    rtol : float, optional
        Relative tolerance of each one-dimensional quadrature.

    Returns
    -------
    force : float
        |F| / (f N) [1].
    moment : float
        |M| / (f N ε) [1].

    Raises
    ------
    ParameterError
        for u outside its range or an unknown pressure.
    """
    from scipy.integrate import quad  # on first use: SciPy's quadrature is slow to import

    ratio = real_number(u)
    if ratio is None or not 0.0 <= ratio <= MAX_QUADRATURE_SLIP_RATIO:
        raise ParameterError(
            "slip_ratio",
            u,
            f"a number in [0, {MAX_QUADRATURE_SLIP_RATIO:g}]",
            "the quadrature loses accuracy beyond; friction_functions has the closed forms",
        )
    u = ratio
    require_choice("contact_pressure", pressure, PRESSURE_DENSITIES)
    density = PRESSURE_DENSITIES[pressure]
    if u <= 1.0:
        start, stop = 0.0, 2.0 * math.pi
        breaks = [0.5 * math.pi, math.pi, 1.5 * math.pi]
    else:
        # rays towards the disk: φ = 3π/2 ± asin(1/u)
        half_width = math.asin(1.0 / u)
        start, stop = 1.5 * math.pi - half_width, 1.5 * math.pi + half_width
        breaks = [1.5 * math.pi]
    options = {"epsabs": 1e-14 / (1.0 + u), "epsrel": rtol, "limit": 400, "points": breaks}

    def force(phi: float) -> float:
        return -math.sin(phi) * _ray_integrals(phi, u, density, rtol)[0]

    def moment(phi: float) -> float:
        # q + u sin φ = q − c: the moment arm of the slip direction about the centre
        return _ray_integrals(phi, u, density, rtol)[1]

    return (
        quad(force, start, stop, **options)[0],
        quad(moment, start, stop, **options)[0],
    )
