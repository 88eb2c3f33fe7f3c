"""Coulomb–Contensou friction on a circular contact: Zhuravlev's Padé law and the dispatch.

Force and pivoting moment per unit normal force and friction coefficient, so
that F = f N ``force_direction`` and M = f N ``moment_factor`` n (paper eq. 10, 12).
The exact law lives in ``friction_exact``; ``contact_friction`` picks the law
and pressure distribution by their codes (``layout.FrictionLaw``, ``ContactPressure``).
"""

from __future__ import annotations

import math

from celtstone.kernels._jit import kernel
from celtstone.kernels.friction_exact import exact_friction
from celtstone.kernels.layout import ContactPressure, FrictionLaw
from celtstone.kernels.vector import NAN3, Vec, regularised_norm, scale

PADE_B = 8.0 / (3.0 * math.pi)  # b in paper eq. (12), fixes F ≈ fN(3π/8)u at small u
PADE_A = 15.0 * math.pi / 16.0  # a in paper eq. (12), fixes M ≈ fNε/(5u) at large u
HERTZ_MOMENT = 3.0 * math.pi / 16.0  # M0 / (f N ε) for the Hertz pressure, eq. (12)
# the same three constants for the uniform pressure N/(πε²) (references.md):
# F ≈ fN u at small u, M0 = (2/3) f N ε, M ≈ fNε/(4u) at large u
UNIFORM_PADE_B = 1.0
UNIFORM_PADE_A = 8.0 / 3.0
UNIFORM_MOMENT = 2.0 / 3.0


@kernel
def zhuravlev_pade(
    slip_velocity: Vec,
    spin_rate: float,
    contact_radius: float,
    regularisation_speed: float,
    force_b: float,
    moment_a: float,
    moment_zero: float,
) -> tuple[Vec, float]:
    """Friction force and pivoting moment of a Padé law with constants b, a, M0/(fNε).

    Parameters
    ----------
    slip_velocity : V1, sliding velocity of the contact point [m/s]
    spin_rate : Ω_n = ω · n, angular velocity about the vertical [rad/s]
    contact_radius : ε, radius of the contact disk [m]
    regularisation_speed : δ, speed scale replacing |V1| by sqrt(|V1|² + δ²) [m/s]
    force_b, moment_a : b and a of paper eq. (10) [1]
    moment_zero : M0 / (f N ε), the pivoting moment without slip [1]

    Returns
    -------
    force : F / (f N) [1], antiparallel to V1
    moment : M / (f N) [m], the moment about n, opposite in sign to Ω_n

    Notes
    -----
    Paper eq. (10): F = -F0 V1 / (|V1| + b|εΩn|), M = -M0 εΩn / (|εΩn| + a|V1|),
    F0 = fN. The regularisation removes the 0/0 of the singular state (eq. 11);
    see ``docs/decisions.md``.
    """
    speed = regularised_norm(slip_velocity, regularisation_speed)
    pivot_speed = contact_radius * abs(spin_rate)
    force = scale(-1.0 / (speed + force_b * pivot_speed), slip_velocity)
    moment = (
        -moment_zero
        * contact_radius
        * contact_radius
        * spin_rate
        / (pivot_speed + moment_a * speed)
    )
    return force, moment


@kernel
def pade_friction(
    slip_velocity: Vec, spin_rate: float, contact_radius: float, regularisation_speed: float
) -> tuple[Vec, float]:
    """Zhuravlev–Padé law for the Hertz pressure, per unit f N (paper eq. 10, 12).

    M0 = 3πfNε/16, b = 8/(3π), a = 15π/16; arguments and returns as in
    :func:`zhuravlev_pade`.
    """
    return zhuravlev_pade(
        slip_velocity,
        spin_rate,
        contact_radius,
        regularisation_speed,
        PADE_B,
        PADE_A,
        HERTZ_MOMENT,
    )


@kernel
def contact_friction(
    slip_velocity: Vec,
    spin_rate: float,
    contact_radius: float,
    regularisation_speed: float,
    law: int,
    pressure: int,
) -> tuple[Vec, float]:
    """Friction force and moment per unit f N for a law and pressure code.

    ``law``: a ``layout.FrictionLaw``; ``pressure``: a ``layout.ContactPressure``.
    Other arguments and the returns as in :func:`zhuravlev_pade`. An unknown code
    gives NaN.
    """
    if law == FrictionLaw.PADE:
        if pressure == ContactPressure.HERTZ:
            return pade_friction(slip_velocity, spin_rate, contact_radius, regularisation_speed)
        if pressure == ContactPressure.UNIFORM:
            return zhuravlev_pade(
                slip_velocity,
                spin_rate,
                contact_radius,
                regularisation_speed,
                UNIFORM_PADE_B,
                UNIFORM_PADE_A,
                UNIFORM_MOMENT,
            )
    if law == FrictionLaw.EXACT:
        return exact_friction(
            slip_velocity, spin_rate, contact_radius, regularisation_speed, pressure
        )
    return NAN3, math.nan
