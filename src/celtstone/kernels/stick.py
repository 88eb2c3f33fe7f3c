"""The stick phase of the hybrid contact: rolling without sliding and without pivoting.

In stick the contact point does not slide (V1 = 0) and the body does not turn about
the vertical (Ω_n = ω · n = 0). The plane supplies whatever reaction R and pivoting
moment M n these two constraints need; stick lasts while that friction lies inside
the limit set of the friction law (Coulomb–Contensou, Zhuravlev–Padé, paper eq. 10, 12).
All vectors are in body axes with origin at G; ``r`` is G → contact point.
"""

from __future__ import annotations

import math

from celtstone.kernels._jit import kernel
from celtstone.kernels.dynamics import (
    contact_ellipse,
    contact_inertia,
    contact_radius,
    inertia_tensor,
    rolling_system,
)
from celtstone.kernels.friction import (
    has_friction_law,
    law_functions,
    pade_limit_moment,
    zero_slip_moment,
)
from celtstone.kernels.geometry import contact
from celtstone.kernels.layout import (
    Y_N,
    Y_OMEGA,
    Y_SLIP,
    ContactPressure,
    ContactShape,
    FrictionLaw,
    FrictionLoad,
)
from celtstone.kernels.stick_ellipse import elliptic_stick_margin
from celtstone.kernels.vector import Vec, add, cross, dot, scale, solve3, sub

BOUNDARY_BISECTIONS = 60  # halvings of t = u/(1 + u) in [0, 1]: below 1e-17


@kernel
def stick_acceleration(
    n: Vec, omega: Vec, r: Vec, r_rate: Vec, params
) -> tuple[Vec, float, Vec, float, float]:
    """Angular acceleration and contact reactions of rolling without pivoting.

    Returns
    -------
    omega_rate : dω/dt [rad/s²]
    normal_force : N = R · n [N]
    friction_force : tangential reaction F = R - N n [N]
    pivot_moment : M, the moment M n about the vertical that holds ω · n = 0 [N m]
    determinant : determinant of the inertia tensor about the contact J_A [kg³ m⁶]

    Notes
    -----
    Paper eq. (5) with the unknown moment M n added: J_A ω̇ = τ + M n, where J_A =
    A + m(|r|²E - r⊗r) and τ the rolling right-hand side. Since ṅ = n × ω (eq. 3),
    d(ω · n)/dt = ω̇ · n, so ω · n = 0 is held by n · ω̇ = 0:
    M = -(n · J_A⁻¹τ)/(n · J_A⁻¹n). The reaction is R = m W_C + m g n with
    W_C = -ω̇ × r - ω × ṙ - ω × (ω × r). The rolling-resistance moment −λ N ĥ
    (``dynamics.rolling_system``) is loaded like the friction: the true N with
    ``friction_load`` dynamic (exactly, in J_A's place), m g with static.
    """
    mass = params.mass
    is_true_load = params.friction_load == FrictionLoad.DYNAMIC
    matrix, torque, centripetal = rolling_system(n, omega, r, r_rate, params, is_true_load)
    free_rate, determinant = solve3(matrix, torque)
    pivot_response, _ = solve3(matrix, n)
    compliance = dot(n, pivot_response)  # n · J_A⁻¹ n > 0 [1/(kg m²)]
    pivot_moment = 0.0
    if compliance > 0.0:
        pivot_moment = -dot(n, free_rate) / compliance
    omega_rate = add(free_rate, scale(pivot_moment, pivot_response))
    acceleration = sub(scale(-1.0, cross(omega_rate, r)), centripetal)
    reaction = add(scale(mass, acceleration), scale(mass * params.gravity, n))
    normal_force = dot(reaction, n)
    friction_force = sub(reaction, scale(normal_force, n))
    return omega_rate, normal_force, friction_force, pivot_moment, determinant


@kernel
def bisected_limit_moment(force_ratio: float, law: int, pressure: int) -> float:
    """Largest μ = |M|/M0 a law gives together with φ = |F|/(f N), from its functions [1].

    The boundary of the limit set: sliding at slip ratio u gives (φ, μ) = (F̂(u),
    M̂(u)/M̂(0)), u in [0, ∞], and φ rises from 0 to 1 with u
    (``friction.law_functions``). F̂(u) = φ is solved by bisection in t = u/(1 + u).
    φ <= 0 gives 1 (u = 0, the full pivoting moment); φ >= 1 the Padé law's expression,
    negative: no moment is admissible with more than f N of force. A law code without
    a branch in ``friction.law_functions`` or an unknown pressure code gives NaN.
    """
    if not has_friction_law(law) or math.isnan(zero_slip_moment(pressure)):
        return math.nan
    if force_ratio <= 0.0:
        return 1.0
    if force_ratio >= 1.0:
        return pade_limit_moment(force_ratio, pressure)
    low, high = 0.0, 1.0
    for _ in range(BOUNDARY_BISECTIONS):
        middle = 0.5 * (low + high)
        force, _ = law_functions(law, middle, 1.0 - middle, pressure)
        if force < force_ratio:
            low = middle
        else:
            high = middle
    middle = 0.5 * (low + high)
    _, moment = law_functions(law, middle, 1.0 - middle, pressure)
    return moment / zero_slip_moment(pressure)


@kernel
def limit_moment(force_ratio: float, law: int, pressure: int) -> float:
    """Largest μ = |M|/M0 the friction law gives together with φ = |F|/(f N) [1].

    The Padé law's in closed form (``friction.pade_limit_moment``, paper eq. 10, 12),
    every other law's by bisection of its functions (:func:`bisected_limit_moment`).
    An unknown law or pressure code gives NaN.
    """
    if law == FrictionLaw.PADE:
        return pade_limit_moment(force_ratio, pressure)
    return bisected_limit_moment(force_ratio, law, pressure)


@kernel
def stick_margin_of(
    force: float,
    moment: float,
    friction_normal: float,
    friction_coefficient: float,
    radius: float,
    law: int,
    pressure: int,
) -> float:
    """Distance of the friction (|F|, |M|) needed for stick inside the law's limit set [1].

    Parameters
    ----------
    force : |F|, tangential friction force [N]
    moment : |M|, pivoting moment about the vertical [N m]
    friction_normal : N used by the friction law (m g or the true N) [N]
    friction_coefficient : f [1]
    radius : ε, contact radius [m]
    law, pressure : friction-law and pressure codes (``layout.FrictionLaw``,
        ``layout.ContactPressure``)

    Returns
    -------
    g = μ_max(φ) - μ (``limit_moment``), φ = |F|/(f N), μ = |M|/M0, M0 = M̂(0) f N ε
    (3π/16 f N ε for the Hertz pressure, paper eq. 12): stick is admissible while
    g >= 0; -1 when f N <= 0 (no friction to hold it).
    """
    capacity = friction_coefficient * friction_normal
    if not capacity > 0.0:
        return -1.0
    force_ratio = force / capacity
    moment_ratio = moment / (zero_slip_moment(pressure) * capacity * radius)
    return limit_moment(force_ratio, law, pressure) - moment_ratio


@kernel
def pade_stick_margin(
    force: float,
    moment: float,
    friction_normal: float,
    friction_coefficient: float,
    radius: float,
) -> float:
    """``stick_margin_of`` for the Padé law on the Hertz disk (the paper's) [1]."""
    return stick_margin_of(
        force,
        moment,
        friction_normal,
        friction_coefficient,
        radius,
        FrictionLaw.PADE.value,
        ContactPressure.HERTZ.value,
    )


@kernel
def stick_margin(n: Vec, omega: Vec, r: Vec, r_rate: Vec, params) -> float:
    """``stick_margin_of`` the friction that stick needs in this state, for the run's law,
    pressure, friction load and contact radius (fixed or Hertz) [1], or with the elliptic
    contact ``stick_ellipse.elliptic_stick_margin`` for the Hertz ellipse at n and the
    friction's load; NaN for an unknown friction-load option."""
    _, normal_force, friction_force, pivot_moment, _ = stick_acceleration(
        n, omega, r, r_rate, params
    )
    option = params.friction_load
    if option == FrictionLoad.STATIC:
        friction_normal = params.mass * params.gravity
    elif option == FrictionLoad.DYNAMIC:
        friction_normal = normal_force
    else:
        return math.nan
    if params.contact_shape == ContactShape.ELLIPSE:
        semi_major, semi_minor, major_axis = contact_ellipse(n, friction_normal, params)
        return elliptic_stick_margin(
            friction_force,
            pivot_moment,
            n,
            major_axis,
            semi_major,
            semi_minor,
            params.friction_coefficient * friction_normal,
            params.friction_law,
            params.ellipse_table,
        )
    return stick_margin_of(
        math.sqrt(dot(friction_force, friction_force)),
        abs(pivot_moment),
        friction_normal,
        params.friction_coefficient,
        contact_radius(n, friction_normal, params),
        params.friction_law,
        params.contact_pressure,
    )


@kernel
def stick_projection(n: Vec, omega: Vec, slip: Vec, r: Vec, params) -> Vec:
    """Angular velocity after the friction impulse that stops slip and pivoting [rad/s].

    Notes
    -----
    At the start of stick a contact impulse Π and a pivoting impulse Q n set V1 and
    ω · n to zero: Δv_G = Π/m, A Δω = r × Π + Q n and V1 + Π/m + Δω × r = 0 give
    J_A Δω = -m r × V1 + Q n, with Q from n · (ω + Δω) = 0. It is the plastic
    (inelastic) impact on the constraint, so the kinetic energy can only drop, by a
    term of second order in (V1, ε ω · n); v_G = -ω' × r after it.
    """
    mass = params.mass
    inertia = contact_inertia(inertia_tensor(params), mass, r)
    slip_response, _ = solve3(inertia, scale(-mass, cross(r, slip)))
    pivot_response, _ = solve3(inertia, n)
    compliance = dot(n, pivot_response)
    impulse = 0.0
    if compliance > 0.0:
        impulse = -(dot(omega, n) + dot(n, slip_response)) / compliance
    return add(omega, add(slip_response, scale(impulse, pivot_response)))


@kernel
def slip_spin_speed(y, params) -> float:
    """sqrt(|V1|² + ε²(ω · n)²): zero exactly when the contact neither slides nor pivots [m/s].

    ε is the model's fixed ``contact_radius``, a length scale here even when the
    friction uses the Hertz radius.
    """
    spin = y[Y_OMEGA] * y[Y_N] + y[Y_OMEGA + 1] * y[Y_N + 1] + y[Y_OMEGA + 2] * y[Y_N + 2]
    pivot_speed = params.contact_radius * spin
    return math.sqrt(
        y[Y_SLIP] * y[Y_SLIP]
        + y[Y_SLIP + 1] * y[Y_SLIP + 1]
        + y[Y_SLIP + 2] * y[Y_SLIP + 2]
        + pivot_speed * pivot_speed
    )


@kernel
def capture_state(y, params, out) -> None:
    """``out`` = ``y`` after the impulse that starts stick: V1 = 0, ω from ``stick_projection``."""
    n = (y[Y_N], y[Y_N + 1], y[Y_N + 2])
    omega = (y[Y_OMEGA], y[Y_OMEGA + 1], y[Y_OMEGA + 2])
    slip = (y[Y_SLIP], y[Y_SLIP + 1], y[Y_SLIP + 2])
    r, _ = contact(n, (0.0, 0.0, 0.0), params)
    omega_after = stick_projection(n, omega, slip, r, params)
    for j in range(y.shape[0]):  # a loop: a GPU thread runs this too (no slice copy in CUDA)
        out[j] = y[j]
    for k in range(3):
        out[Y_OMEGA + k] = omega_after[k]
        out[Y_SLIP + k] = 0.0
