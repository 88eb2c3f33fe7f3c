"""Zhuravlev's Padé approximation of Coulomb–Contensou friction on a Hertz disk.

Force and pivoting moment per unit normal force and friction coefficient, so
that F = f N ``force_direction`` and M = f N ``moment_factor`` n (paper eq. 10, 12).
"""

from __future__ import annotations

import math

from celtstone.kernels._jit import kernel
from celtstone.kernels.vector import Vec, scale

PADE_B = 8.0 / (3.0 * math.pi)  # b in paper eq. (12), fixes F ≈ fN(3π/8)u at small u
PADE_A = 15.0 * math.pi / 16.0  # a in paper eq. (12), fixes M ≈ fNε/(5u) at large u
HERTZ_MOMENT = 3.0 * math.pi / 16.0  # M0 / (f N ε) for the Hertz pressure, eq. (12)


@kernel
def pade_friction(
    slip_velocity: Vec, spin_rate: float, contact_radius: float, regularisation_speed: float
) -> tuple[Vec, float]:
    """Friction force and pivoting moment of the Zhuravlev–Padé law, per unit f N.

    Parameters
    ----------
    slip_velocity : V1, sliding velocity of the contact point [m/s]
    spin_rate : Ω_n = ω · n, angular velocity about the vertical [rad/s]
    contact_radius : ε, radius of the Hertz contact disk [m]
    regularisation_speed : δ, speed scale replacing |V1| by sqrt(|V1|² + δ²) [m/s]

    Returns
    -------
    force : F / (f N) [1], antiparallel to V1
    moment : M / (f N) [m], the moment about n, opposite in sign to Ω_n

    Notes
    -----
    Paper eq. (10) with (12): F = -F0 V1 / (|V1| + b|εΩn|),
    M = -M0 εΩn / (|εΩn| + a|V1|), F0 = fN, M0 = 3πfNε/16, b = 8/(3π), a = 15π/16.
    The regularisation removes the 0/0 of the singular state (eq. 11); see
    ``docs/decisions.md``.
    """
    speed = math.sqrt(
        slip_velocity[0] * slip_velocity[0]
        + slip_velocity[1] * slip_velocity[1]
        + slip_velocity[2] * slip_velocity[2]
        + regularisation_speed * regularisation_speed
    )
    pivot_speed = contact_radius * abs(spin_rate)
    force = scale(-1.0 / (speed + PADE_B * pivot_speed), slip_velocity)
    moment = (
        -HERTZ_MOMENT * contact_radius * contact_radius * spin_rate / (pivot_speed + PADE_A * speed)
    )
    return force, moment
