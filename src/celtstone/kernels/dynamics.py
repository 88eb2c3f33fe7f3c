"""Accelerations of the two models: rolling (paper eq. 3–5) and sliding (eq. 6–12).

All vectors are in body axes with origin at the centre of mass G; ``r`` is the
vector from G to the contact point (the paper's r_CA).
"""

from __future__ import annotations

import math

from celtstone.kernels._jit import kernel
from celtstone.kernels.friction import contact_friction
from celtstone.kernels.friction_ellipse import elliptic_contact_friction
from celtstone.kernels.hertz import equivalent_radius, hertz_contact_radius
from celtstone.kernels.hertz_ellipse import hertz_ellipse_axes, principal_radii
from celtstone.kernels.layout import ContactShape, FrictionLoad
from celtstone.kernels.vector import (
    NAN3,
    Mat,
    Vec,
    add,
    add_outer,
    cross,
    dot,
    matvec,
    scale,
    solve3,
    sub,
)

# the Hertz radius is computed from max(N, this fraction of m g): N must stay > 0
# there (lift-off itself is detected and reported by the driver)
MIN_LOAD_FRACTION = 1e-9
# fixed-point iteration of the dynamic normal force with a Hertz radius ε(N)
NORMAL_FORCE_RTOL = 1e-14
MAX_NORMAL_FORCE_ITERATIONS = 50


@kernel
def inertia_tensor(params) -> Mat:
    """Central inertia tensor A as a row-major 9-tuple [kg m²]."""
    a = params.inertia
    return (a[0, 0], a[0, 1], a[0, 2], a[1, 0], a[1, 1], a[1, 2], a[2, 0], a[2, 1], a[2, 2])


@kernel
def centripetal_terms(omega: Vec, r: Vec, r_rate: Vec) -> Vec:
    """ω × ṙ + ω × (ω × r): the part of -W_C not containing ω̇ (paper eq. 4, 7) [m/s²]."""
    return add(cross(omega, r_rate), cross(omega, cross(omega, r)))


@kernel
def contact_inertia(inertia: Mat, mass: float, r: Vec) -> Mat:
    """Inertia tensor about the contact point, A + m(|r|²E − r⊗r) [kg m²] (paper eq. 5)."""
    r2 = dot(r, r)
    return (
        inertia[0] + mass * (r2 - r[0] * r[0]),
        inertia[1] - mass * r[0] * r[1],
        inertia[2] - mass * r[0] * r[2],
        inertia[3] - mass * r[1] * r[0],
        inertia[4] + mass * (r2 - r[1] * r[1]),
        inertia[5] - mass * r[1] * r[2],
        inertia[6] - mass * r[2] * r[0],
        inertia[7] - mass * r[2] * r[1],
        inertia[8] + mass * (r2 - r[2] * r[2]),
    )


@kernel
def rolling_resistance_direction(n: Vec, omega: Vec, params) -> Vec:
    """ĥ = ω_t / sqrt(|ω_t|² + ω_0²), ω_t = ω − (ω · n) n: the rolling part of ω, whose
    rolling-resistance moment is M_r = −λ N ĥ [1] (docs/equations.md, "Rolling resistance").

    ω_0 (``rolling_resistance_rate``) regularises the switch of M_r at ω_t = 0 as δ does
    the friction's (decisions §4, §25).
    """
    tangential = sub(omega, scale(dot(omega, n), n))
    rate = params.rolling_resistance_rate
    return scale(1.0 / math.sqrt(dot(tangential, tangential) + rate * rate), tangential)


@kernel
def rolling_system(
    n: Vec, omega: Vec, r: Vec, r_rate: Vec, params, is_true_load: bool
) -> tuple[Mat, Vec, Vec]:
    """Matrix, right-hand side and centripetal terms of rolling, paper eq. (5), with the
    rolling-resistance moment M_r = −λ N ĥ.

    Returns
    -------
    matrix : J_A = A + m(|r|²E − r⊗r), less λ m ĥ ⊗ d with the true load [kg m²]
    torque : Aω × ω + m r × (g n − ω×ṙ − ω×(ω×r)) − σω − λ N0 ĥ (or − λ m g ĥ) [N m]
    centripetal : ω × ṙ + ω × (ω × r) [m/s²]

    Notes
    -----
    With ``is_true_load`` N is the true normal force N = N0 − m d · ω̇, d = r × n,
    N0 = m g − m n · (ω×ṙ + ω×(ω×r)), linear in ω̇, so the λ term enters the matrix
    exactly: (J_A − λ m ĥ dᵀ) ω̇ = τ − λ N0 ĥ. Otherwise N = m g (``friction_load``
    static in stick). λ = 0 leaves eq. (5) untouched, bit for bit.
    """
    mass = params.mass
    gravity = params.gravity
    inertia = inertia_tensor(params)
    centripetal = centripetal_terms(omega, r, r_rate)
    torque = sub(
        cross(matvec(inertia, omega), omega),
        scale(params.damping, omega),
    )
    torque = add(torque, scale(mass, cross(r, sub(scale(gravity, n), centripetal))))
    matrix = contact_inertia(inertia, mass, r)
    resistance = params.rolling_resistance
    if resistance > 0.0:
        direction = rolling_resistance_direction(n, omega, params)
        if is_true_load:
            normal_free = mass * gravity - mass * dot(n, centripetal)
            matrix = add_outer(matrix, -resistance * mass, direction, cross(r, n))
            torque = sub(torque, scale(resistance * normal_free, direction))
        else:
            torque = sub(torque, scale(resistance * mass * gravity, direction))
    return matrix, torque, centripetal


@kernel
def rolling_acceleration(
    n: Vec, omega: Vec, r: Vec, r_rate: Vec, params, is_true_load: bool
) -> tuple[Vec, float, Vec, float]:
    """Angular acceleration, normal force and contact force of rolling without sliding.

    Returns
    -------
    omega_rate : dω/dt [rad/s²]
    normal_force : vertical component of the reaction, N = R · n [N]
    reaction : full contact reaction R in body axes [N]
    determinant : determinant of the system matrix (``rolling_system``) [kg³ m⁶]

    Notes
    -----
    Paper eq. (5): (A + m(r²E - r⊗r)) ω̇ = -ω × Aω + m r × (g n - ω × ṙ - ω × (ω × r)) - σω,
    written with r = r_CA, plus the rolling-resistance moment −λ N ĥ loaded with the
    true N (``is_true_load``) or m g; the reaction follows from eq. (3): R = m(W_C + g n).
    """
    mass = params.mass
    matrix, torque, centripetal = rolling_system(n, omega, r, r_rate, params, is_true_load)
    omega_rate, determinant = solve3(matrix, torque)
    # W_C = -ω̇ × r - ω × ṙ - ω × (ω × r); R = m W_C + m g n
    acceleration = sub(scale(-1.0, cross(omega_rate, r)), centripetal)
    reaction = add(scale(mass, acceleration), scale(mass * params.gravity, n))
    return omega_rate, dot(reaction, n), reaction, determinant


@kernel
def contact_radius(n: Vec, normal_force: float, params) -> float:
    """ε [m]: the fixed contact radius, or the Hertz radius for N and the curvature at n.

    With an effective modulus E* > 0 in ``params``: ε = (3 N R_eq / (4 E*))^(1/3),
    R_eq from the Gaussian curvature at the current contact point, N clamped
    below at ``MIN_LOAD_FRACTION`` m g.
    """
    modulus = params.effective_modulus
    if modulus > 0.0:
        load = max(normal_force, MIN_LOAD_FRACTION * params.mass * params.gravity)
        return hertz_contact_radius(load, equivalent_radius(n, params), modulus)
    return params.contact_radius


@kernel
def contact_ellipse(n: Vec, load: float, params) -> tuple[float, float, Vec]:
    """(A, B, a): semi-axes A >= B [m] and unit major-axis direction [1] (body axes) of the
    Hertz ellipse at the contact point of n under the normal force ``load`` [N], clamped
    below at ``MIN_LOAD_FRACTION`` m g; NaN where the surface has no ellipse (flat, saddle)."""
    radius_major, radius_minor, major_axis = principal_radii(n, params)
    clamped = max(load, MIN_LOAD_FRACTION * params.mass * params.gravity)
    semi_major, semi_minor = hertz_ellipse_axes(
        radius_major, radius_minor, clamped, params.effective_modulus
    )
    return semi_major, semi_minor, major_axis


@kernel
def friction_per_unit_load(
    n: Vec, slip_velocity: Vec, spin_rate: float, load: float, params
) -> tuple[Vec, float]:
    """Friction force [1] and moment [m] per unit f N for the contact in ``params``.

    Parameters
    ----------
    n : upward vertical in body axes [1]
    slip_velocity : V1 [m/s]; spin_rate : Ω_n = ω · n [rad/s]
    load : N_f, the normal force of the friction law (sizes a Hertz contact) [N]

    Notes
    -----
    ``contact_shape`` circle: the law and pressure of ``params`` on the disk of radius
    ``contact_radius`` (fixed or Hertz's). Ellipse: the Hertz ellipse of the principal
    radii of curvature at the contact point of n (:func:`contact_ellipse`) and the law
    of ``params`` (Padé or exact) of the disk of radius A corrected to it
    (``friction_ellipse.elliptic_contact_friction``, its table at ``ellipse_table``). An
    unknown shape code gives NaN.
    """
    shape = params.contact_shape
    if shape == ContactShape.CIRCLE:
        return contact_friction(
            slip_velocity,
            spin_rate,
            contact_radius(n, load, params),
            params.regularisation_speed,
            params.friction_law,
            params.contact_pressure,
        )
    if shape == ContactShape.ELLIPSE:
        semi_major, semi_minor, major_axis = contact_ellipse(n, load, params)
        return elliptic_contact_friction(
            slip_velocity,
            spin_rate,
            n,
            major_axis,
            semi_major,
            semi_minor,
            params.regularisation_speed,
            params.friction_law,
            params.ellipse_table,
        )
    return NAN3, math.nan


@kernel
def sliding_acceleration(
    n: Vec, omega: Vec, slip_velocity: Vec, r: Vec, r_rate: Vec, params
) -> tuple[Vec, Vec, float, Vec, float, float]:
    """Angular and slip accelerations of rolling with sliding.

    Returns
    -------
    omega_rate : dω/dt [rad/s²]
    slip_rate : dV1/dt in body axes [m/s²]
    normal_force : true vertical reaction N [N]
    friction_force : F_fr [N]
    friction_moment : M_fr, moment about n [N m]
    determinant : determinant of the system matrix (≤ 0: no consistent solution)

    Notes
    -----
    Paper eq. (8), (9), with r_AC2 = n × r_AC = r × n = d. The vertical reaction is
    N = N0 - m d · ω̇, N0 = m g - m n · (ω × ṙ + ω × (ω × r)). Friction F = f N_f φ,
    M = f N_f ψ (eq. 10, 12, or the exact law), with N_f = m g ("static", the
    paper's first approximation) or N_f = N ("dynamic"), in which case the linear
    system (A + m k ⊗ d) ω̇ = -ω × Aω + N0 k - σω, k = d + f (r × φ + ψ n), is
    solved exactly. The rolling-resistance moment −λ N_f ĥ
    (``rolling_resistance_direction``) is loaded like the friction: k gains −λ ĥ
    in the dynamic case, the torque −λ m g ĥ in the static one; λ = 0 skips it.
    With a Hertz contact (radius ε(N_f) or the ellipse's A, B of N_f) φ and ψ depend on
    N in the dynamic case: N is then found by fixed-point iteration.
    Slip: W1 = F/m + P(ω̇ × r + ω × ṙ + ω × (ω × r)), P = E - n⊗n, V̇1 = W1 - ω × V1.
    An unknown friction-load option gives NaN.
    """
    mass = params.mass
    gravity = params.gravity
    friction_coefficient = params.friction_coefficient
    inertia = inertia_tensor(params)
    centripetal = centripetal_terms(omega, r, r_rate)
    lever = cross(r, n)
    spin_rate = dot(omega, n)
    normal_free = mass * gravity - mass * dot(n, centripetal)
    torque = sub(cross(matvec(inertia, omega), omega), scale(params.damping, omega))
    resistance = params.rolling_resistance
    direction = rolling_resistance_direction(n, omega, params) if resistance > 0.0 else NAN3
    if params.friction_load == FrictionLoad.DYNAMIC:
        normal_force = normal_free
        for _ in range(MAX_NORMAL_FORCE_ITERATIONS):
            force_unit, moment_unit = friction_per_unit_load(
                n, slip_velocity, spin_rate, normal_force, params
            )
            friction_torque_unit = add(cross(r, force_unit), scale(moment_unit, n))
            coupling = add(lever, scale(friction_coefficient, friction_torque_unit))
            if resistance > 0.0:
                coupling = sub(coupling, scale(resistance, direction))
            matrix = add_outer(inertia, mass, coupling, lever)
            omega_rate, determinant = solve3(matrix, add(torque, scale(normal_free, coupling)))
            previous = normal_force
            normal_force = normal_free - mass * dot(lever, omega_rate)
            if params.effective_modulus <= 0.0 or abs(
                normal_force - previous
            ) <= NORMAL_FORCE_RTOL * (abs(normal_force) + mass * gravity):
                break
        friction_normal = normal_force
    elif params.friction_load == FrictionLoad.STATIC:
        friction_normal = mass * gravity
        force_unit, moment_unit = friction_per_unit_load(
            n, slip_velocity, spin_rate, friction_normal, params
        )
        friction_torque_unit = add(cross(r, force_unit), scale(moment_unit, n))
        torque = add(torque, scale(normal_free, lever))
        torque = add(torque, scale(friction_coefficient * friction_normal, friction_torque_unit))
        if resistance > 0.0:
            torque = sub(torque, scale(resistance * friction_normal, direction))
        matrix = add_outer(inertia, mass, lever, lever)
        omega_rate, determinant = solve3(matrix, torque)
        normal_force = normal_free - mass * dot(lever, omega_rate)
    else:
        return NAN3, NAN3, math.nan, NAN3, math.nan, math.nan
    friction_force = scale(friction_coefficient * friction_normal, force_unit)
    friction_moment = friction_coefficient * friction_normal * moment_unit
    tangential = add(cross(omega_rate, r), centripetal)
    tangential = sub(tangential, scale(dot(tangential, n), n))
    slip_rate = sub(add(scale(1.0 / mass, friction_force), tangential), cross(omega, slip_velocity))
    return omega_rate, slip_rate, normal_force, friction_force, friction_moment, determinant
