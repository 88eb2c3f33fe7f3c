"""Coulomb–Contensou friction on a circular contact: the laws' functions and the one dispatch.

Force and pivoting moment per unit normal force and friction coefficient, so
that F = f N ``force_direction`` and M = f N ``moment_factor`` n (paper eq. 10, 12).

Every friction law is its two functions of the slip: F/(fN) and M/(fNε) at
u = |V1| / (ε|Ω_n|), given as the pair of speeds (|V1|, ε|Ω_n|) so that no u is formed
where it would overflow. :func:`law_functions` is the one compiled dispatch on the law
code (``layout.FrictionLaw``): a law is a branch there and an entry in
``contact.laws.LAWS``. Everything else reads a law through it: the force and moment of
the disk (:func:`contact_friction`), the elliptic contact (``friction_ellipse``, the disk law
of radius A corrected), the stick limit set (``stick.limit_moment``) and
:func:`has_friction_law`, by which the right-hand side reports an unknown law code
(``system.code_status``). Zhuravlev's Padé law keeps closed forms of its own for the
disk and its stick limit (:func:`pade_disk_friction`, :func:`pade_limit_moment`), the
same functions evaluated as paper eq. (10) writes them. The exact law's functions live in
``friction_exact``.
"""

from __future__ import annotations

import math

from celtstone.kernels._jit import kernel
from celtstone.kernels.friction_exact import exact_friction_functions
from celtstone.kernels.layout import ContactPressure, FrictionLaw
from celtstone.kernels.vector import Vec, regularised_norm, scale

PADE_B = 8.0 / (3.0 * math.pi)  # b in paper eq. (12), fixes F ≈ fN(3π/8)u at small u
PADE_A = 15.0 * math.pi / 16.0  # a in paper eq. (12), fixes M ≈ fNε/(5u) at large u
HERTZ_MOMENT = 3.0 * math.pi / 16.0  # M0 / (f N ε) for the Hertz pressure, eq. (12)
# the same three constants for the uniform pressure N/(πε²) (references.md):
# F ≈ fN u at small u, M0 = (2/3) f N ε, M ≈ fNε/(4u) at large u
UNIFORM_PADE_B = 1.0
UNIFORM_PADE_A = 8.0 / 3.0
UNIFORM_MOMENT = 2.0 / 3.0


@kernel
def zero_slip_moment(pressure: int) -> float:
    """M0 / (f N ε), the pivoting moment without slip for a pressure code [1]; NaN if unknown.

    Every law has it: at u = 0 the contact pivots about its centre (paper eq. 12).
    """
    if pressure == ContactPressure.HERTZ:
        return HERTZ_MOMENT
    if pressure == ContactPressure.UNIFORM:
        return UNIFORM_MOMENT
    return math.nan


@kernel
def pade_constants(pressure: int) -> tuple[float, float]:
    """b and a of the Padé law (paper eq. 10, 12) for a pressure code [1]; NaN if unknown."""
    if pressure == ContactPressure.HERTZ:
        return PADE_B, PADE_A
    if pressure == ContactPressure.UNIFORM:
        return UNIFORM_PADE_B, UNIFORM_PADE_A
    return math.nan, math.nan


@kernel
def pade_functions(slip_speed: float, pivot_speed: float, pressure: int) -> tuple[float, float]:
    """F/(fN) and M/(fNε) of Zhuravlev's Padé law at u = slip_speed / pivot_speed [1].

    Parameters
    ----------
    slip_speed : |V1| (or its regularised value) [m/s], >= 0
    pivot_speed : ε|Ω_n| [m/s], >= 0
    pressure : a ``layout.ContactPressure``

    Notes
    -----
    Paper eq. (10): F/(fN) = u/(u + b), M/(fNε) = M0 /(1 + a u), written in the two
    speeds. Both zero gives (0, 0), as every law; an unknown pressure NaN.
    """
    force_b, moment_a = pade_constants(pressure)
    moment_zero = zero_slip_moment(pressure)
    if slip_speed == 0.0 and pivot_speed == 0.0:
        return 0.0, 0.0
    force = slip_speed / (slip_speed + force_b * pivot_speed)
    moment = moment_zero * pivot_speed / (pivot_speed + moment_a * slip_speed)
    return force, moment


@kernel
def law_functions(
    law: int, slip_speed: float, pivot_speed: float, pressure: int
) -> tuple[float, float]:
    """F/(fN) and M/(fNε) [1] of the law with code ``law``.

    The one dispatch on a law code: a code without a branch here gives NaN, and so does
    every kernel that reads a law.

    Parameters
    ----------
    law : a ``layout.FrictionLaw``
    slip_speed : |V1| (or its regularised value) [m/s], >= 0
    pivot_speed : ε|Ω_n| [m/s], >= 0
    pressure : a ``layout.ContactPressure``

    Returns
    -------
    force : |F| / (f N) [1], from 0 at u = 0 to 1 as u -> ∞
    moment : |M| / (f N ε) [1], from M0/(fNε) at u = 0 to 0 as u -> ∞
    """
    if law == FrictionLaw.PADE:
        return pade_functions(slip_speed, pivot_speed, pressure)
    if law == FrictionLaw.EXACT:
        return exact_friction_functions(slip_speed, pivot_speed, pressure)
    return math.nan, math.nan


@kernel
def has_friction_law(law: int) -> bool:
    """Whether :func:`law_functions` has a branch for the code ``law`` (probed at u = 1)."""
    # ``.value``: an int, as the kernels pass the pressure code; the enum member is a
    # type of its own, for which numba would compile every law's functions once more
    return not math.isnan(law_functions(law, 1.0, 1.0, ContactPressure.HERTZ.value)[0])


@kernel
def pade_friction(
    slip_velocity: Vec, spin_rate: float, contact_radius: float, regularisation_speed: float
) -> tuple[Vec, float]:
    """Zhuravlev–Padé law for the Hertz pressure, per unit f N (paper eq. 10, 12).

    M0 = 3πfNε/16, b = 8/(3π), a = 15π/16 (:func:`pade_disk_friction` of the Hertz
    pressure); arguments and returns as :func:`contact_friction`.
    """
    return pade_disk_friction(
        slip_velocity, spin_rate, contact_radius, regularisation_speed, ContactPressure.HERTZ.value
    )


@kernel
def pade_disk_friction(
    slip_velocity: Vec,
    spin_rate: float,
    contact_radius: float,
    regularisation_speed: float,
    pressure: int,
) -> tuple[Vec, float]:
    """The Padé law on the disk for a pressure code, in the closed form of paper eq. (10);
    arguments and returns as :func:`contact_friction`, NaN for an unknown pressure.

    Notes
    -----
    Paper eq. (10): F = -F0 V1 / (|V1| + b|εΩn|), M = -M0 εΩn / (|εΩn| + a|V1|),
    F0 = fN, with the pressure's b, a (:func:`pade_constants`) and M0
    (:func:`zero_slip_moment`). The regularisation removes the 0/0 of the singular state
    (eq. 11); see ``docs/decisions.md``.
    """
    force_b, moment_a = pade_constants(pressure)
    speed = regularised_norm(slip_velocity, regularisation_speed)
    pivot_speed = contact_radius * abs(spin_rate)
    force = scale(-1.0 / (speed + force_b * pivot_speed), slip_velocity)
    moment = (
        -zero_slip_moment(pressure)
        * contact_radius
        * contact_radius
        * spin_rate
        / (pivot_speed + moment_a * speed)
    )
    return force, moment


@kernel
def contact_friction(
    slip_velocity: Vec,
    spin_rate: float,
    contact_radius: float,
    regularisation_speed: float,
    law: int,
    pressure: int,
) -> tuple[Vec, float]:
    """Friction force and pivoting moment of a law on the disk, per unit f N.

    Parameters
    ----------
    slip_velocity : V1, sliding velocity of the contact point [m/s]
    spin_rate : Ω_n = ω · n, angular velocity about the vertical [rad/s]
    contact_radius : ε, radius of the contact disk [m]
    regularisation_speed : δ, |V1| -> sqrt(|V1|² + δ²) [m/s]
    law, pressure : a ``layout.FrictionLaw`` and a ``layout.ContactPressure``

    Returns
    -------
    force : F / (f N) [1], antiparallel to V1
    moment : M / (f N) [m], the moment about n, opposite in sign to Ω_n

    Notes
    -----
    F = −fN F̂(u) V1/|V1|, M = −fNε M̂(u) sign Ω_n, u = |V1|/(ε|Ω_n|) (paper section 2),
    with the law's functions F̂, M̂ (:func:`law_functions`); ε → contact_radius. The Padé
    law takes its closed form (:func:`pade_disk_friction`, the same functions as paper
    eq. 10 writes them). An unknown code gives NaN. The regularisation removes the 0/0 of
    the singular state (paper eq. 11, ``docs/decisions.md`` §4).
    """
    if law == FrictionLaw.PADE:
        return pade_disk_friction(
            slip_velocity, spin_rate, contact_radius, regularisation_speed, pressure
        )
    speed = regularised_norm(slip_velocity, regularisation_speed)
    pivot_speed = contact_radius * abs(spin_rate)
    force_ratio, moment_ratio = law_functions(law, speed, pivot_speed, pressure)
    force = (0.0, 0.0, 0.0)
    if speed > 0.0:
        force = scale(-force_ratio / speed, slip_velocity)
    moment = -math.copysign(moment_ratio * contact_radius, spin_rate) if spin_rate != 0.0 else 0.0
    return force, moment


@kernel
def pade_boundary(pressure: int) -> float:
    """ab - 1 of the Padé limit-set boundary μ = (1 - φ)/(1 + (ab - 1)φ) for a pressure
    code (5/2 - 1 for the Hertz pressure, 8/3 - 1 for the uniform one) [1]; NaN if unknown.
    """
    force_b, moment_a = pade_constants(pressure)
    return moment_a * force_b - 1.0


@kernel
def pade_limit_moment(force_ratio: float, pressure: int) -> float:
    """Largest μ = |M|/M0 the Padé law gives together with φ = |F|/(f N) [1].

    Sliding at slip ratio u gives (φ, μ) = (u/(u + b), 1/(1 + a u)) (paper eq. 10, 12);
    eliminating u gives μ = (1 - φ)/(1 + (ab - 1)φ) (ab = 5/2 for the Hertz pressure,
    8/3 for the uniform one), negative for φ > 1. NaN for an unknown pressure code.
    """
    return (1.0 - force_ratio) / (1.0 + pade_boundary(pressure) * force_ratio)
