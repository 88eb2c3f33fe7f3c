"""The full first-order system y' = f(t, y) of both models.

These are the functions the integrators call. ``model`` is a ``layout.ModelCode``
(a plain int), ``params`` a record of ``layout.PARAMETERS`` and ``y`` a flat state
array (layouts documented in ``layout``).
"""

from __future__ import annotations

import math

from celtstone.kernels._jit import inlined_kernel, kernel
from celtstone.kernels.dynamics import (
    inertia_tensor,
    rolling_acceleration,
    rolling_resistance_direction,
    sliding_acceleration,
)
from celtstone.kernels.friction import has_friction_law
from celtstone.kernels.geometry import contact, contact_status
from celtstone.kernels.layout import (
    RHS_CONTACT_RANGE,
    RHS_OK,
    RHS_SINGULAR,
    RHS_UNKNOWN_CODE,
    Y_N,
    Y_OMEGA,
    Y_POSITION,
    Y_QUAT,
    Y_SLIP,
    Y_WORK,
    ContactPressure,
    ContactShape,
    FrictionLaw,
    FrictionLoad,
    ModelCode,
    ShapeCode,
)
from celtstone.kernels.stick import slip_spin_speed, stick_acceleration, stick_margin
from celtstone.kernels.vector import NAN3, Vec, cross, dot, matvec, rotate, sub

# determinant of the system matrix relative to det(A) below which it counts as singular
SINGULAR_RATIO = 1e-10

# each code enum is numbered 0 .. len - 1 (tests/test_kernel_dispatch.py checks it)
N_MODELS = len(ModelCode)
N_SHAPES = len(ShapeCode)
N_FRICTION_LOADS = len(FrictionLoad)
N_FRICTION_LAWS = len(FrictionLaw)
N_PRESSURES = len(ContactPressure)
N_CONTACT_SHAPES = len(ContactShape)


@kernel
def code_status(model, params) -> int:
    """``RHS_UNKNOWN_CODE`` if the model code or a code in ``params`` is none of its enum's
    members (no kernel has a branch for it), or the sliding and stick models' friction law
    has no branch in ``friction.law_functions``, else ``RHS_OK``."""
    known = (
        0 <= model < N_MODELS
        and 0 <= params.shape_code < N_SHAPES
        and 0 <= params.friction_load < N_FRICTION_LOADS
        and 0 <= params.friction_law < N_FRICTION_LAWS
        and 0 <= params.contact_pressure < N_PRESSURES
        and 0 <= params.contact_shape < N_CONTACT_SHAPES
    )
    if known and model != ModelCode.ROLLING:  # rolling reads no friction law
        known = has_friction_law(params.friction_law)
    return RHS_OK if known else RHS_UNKNOWN_CODE


@kernel
def unpack(y) -> tuple[Vec, Vec, Vec, tuple[float, float, float, float]]:
    """n, ω, V1 and the attitude quaternion from the state array."""
    n = (y[Y_N], y[Y_N + 1], y[Y_N + 2])
    omega = (y[Y_OMEGA], y[Y_OMEGA + 1], y[Y_OMEGA + 2])
    slip = (y[Y_SLIP], y[Y_SLIP + 1], y[Y_SLIP + 2])
    quat = (y[Y_QUAT], y[Y_QUAT + 1], y[Y_QUAT + 2], y[Y_QUAT + 3])
    return n, omega, slip, quat


@kernel
def evaluate(model, y, params, dy):
    """Fill ``dy`` with dy/dt and return (status, normal force [N], friction power [W],
    friction force |F| [N]).

    The friction power F · V1 + M Ω_n is ≤ 0; rolling returns 0 for it and for |F|
    (its tangential reaction is no friction force bounded by Coulomb's law). In stick
    |F| is the tangential reaction that holds the contact. An unknown code
    (``code_status``) gives the status ``RHS_UNKNOWN_CODE`` and NaN rates.
    """
    n, omega, slip, quat = unpack(y)
    n_rate = cross(n, omega)  # Poisson equation, paper eq. (3): ṅ = n × ω
    r, r_rate = contact(n, n_rate, params)
    status = code_status(model, params)
    if status == RHS_OK:
        status = contact_status(n, r, params)
    inertia = inertia_tensor(params)
    reference = inertia[0] * inertia[4] * inertia[8]
    friction_power = 0.0
    friction_force = 0.0
    if model == ModelCode.ROLLING:
        # the true load: True, written so that it is the constant True only where the
        # model code is one (a loop for one model); in the right-hand side for every code
        # a value, whose ``rolling_system`` the stick model's serves (the constant compiled
        # it once more)
        true_load = model == ModelCode.ROLLING
        omega_rate, normal_force, _, determinant = rolling_acceleration(
            n, omega, r, r_rate, params, true_load
        )
        slip_rate = (0.0, 0.0, 0.0)
        velocity = cross(r, omega)  # v_G = -ω × r
    elif model == ModelCode.STICK:
        # V1 = 0 and ω · n = 0 are held; the friction power is zero up to round-off
        omega_rate, normal_force, force, moment, determinant = stick_acceleration(
            n, omega, r, r_rate, params
        )
        slip_rate = (0.0, 0.0, 0.0)
        friction_power = dot(force, slip) + moment * dot(omega, n)
        friction_force = math.sqrt(dot(force, force))
        velocity = sub(slip, cross(omega, r))
    elif model == ModelCode.SLIDING:
        omega_rate, slip_rate, normal_force, force, moment, determinant = sliding_acceleration(
            n, omega, slip, r, r_rate, params
        )
        if status == RHS_OK and math.isnan(moment) and params.contact_shape == ContactShape.ELLIPSE:
            status = RHS_CONTACT_RANGE  # the ellipse's law has no value here (friction_ellipse)
        friction_power = dot(force, slip) + moment * dot(omega, n)
        friction_force = math.sqrt(dot(force, force))
        velocity = sub(slip, cross(omega, r))  # v_G = V1 - ω × r
    else:
        omega_rate, slip_rate, velocity = NAN3, NAN3, NAN3
        normal_force, friction_power, determinant = math.nan, math.nan, math.nan
        friction_force = math.nan
    if status == RHS_OK and not determinant > SINGULAR_RATIO * reference:
        status = RHS_SINGULAR
    for k in range(3):
        dy[Y_N + k] = n_rate[k]
        dy[Y_OMEGA + k] = omega_rate[k]
        dy[Y_SLIP + k] = slip_rate[k]
    # quaternion kinematics q̇ = ½ q ⊗ (0, ω), ω in body axes
    w, qx, qy, qz = quat
    dy[Y_QUAT] = 0.5 * (-qx * omega[0] - qy * omega[1] - qz * omega[2])
    dy[Y_QUAT + 1] = 0.5 * (w * omega[0] + qy * omega[2] - qz * omega[1])
    dy[Y_QUAT + 2] = 0.5 * (w * omega[1] + qz * omega[0] - qx * omega[2])
    dy[Y_QUAT + 3] = 0.5 * (w * omega[2] + qx * omega[1] - qy * omega[0])
    velocity_space = rotate(quat, velocity)
    dy[Y_POSITION] = velocity_space[0]
    dy[Y_POSITION + 1] = velocity_space[1]
    damping_power = params.damping * dot(omega, omega)
    dy[Y_WORK] = damping_power - friction_power
    if params.rolling_resistance > 0.0:
        dy[Y_WORK] += rolling_resistance_power(model, n, omega, normal_force, params)
    return status, normal_force, friction_power, friction_force


@kernel
def rolling_resistance_power(model, n: Vec, omega: Vec, normal_force: float, params) -> float:
    """−M_r · ω = λ N ĥ · ω ≥ 0, the power the rolling-resistance moment takes [W].

    N is the load of ``dynamics.rolling_system``: the true normal force in rolling and
    with ``friction_load`` dynamic, m g with static (the friction's load).
    """
    load = normal_force
    if model != ModelCode.ROLLING and params.friction_load != FrictionLoad.DYNAMIC:
        load = params.mass * params.gravity
    direction = rolling_resistance_direction(n, omega, params)
    return params.rolling_resistance * load * dot(direction, omega)


@inlined_kernel
def rhs(model, t, y, params, dy):
    """Right-hand side of the state equation; returns (status code, normal force N [N]).

    The integrators pass the normal force of the evaluation at an accepted state on to
    the driver's lift-off check, which so needs no evaluation of its own.
    """
    status, normal_force, _, _ = evaluate(model, y, params, dy)
    return status, normal_force


@kernel
def energy(model, y, params) -> float:
    """Total mechanical energy, kinetic plus potential with the plane as zero [J].

    E = ½ m |v_G|² + ½ ω · Aω + m g z_G, z_G = -r · n the height of G. NaN for an
    unknown model code.
    """
    n, omega, slip, _ = unpack(y)
    r, _ = contact(n, (0.0, 0.0, 0.0), params)
    if model == ModelCode.ROLLING:
        velocity = cross(r, omega)
    elif model == ModelCode.SLIDING or model == ModelCode.STICK:
        velocity = sub(slip, cross(omega, r))
    else:
        return math.nan
    mass = params.mass
    kinetic = 0.5 * mass * dot(velocity, velocity)
    kinetic += 0.5 * dot(omega, matvec(inertia_tensor(params), omega))
    return kinetic - mass * params.gravity * dot(r, n)


# The derived columns that ``derived_columns`` fills, by name; the order is the column index.
# A column is a run's Dataset variable when a ``schema.VARIABLES`` row names it as its
# source (``trajectory.sample_run``).
DERIVED = (
    "spin",  # ω · n [rad/s]
    "energy",  # total energy [J]
    "normal_force",  # N [N]
    "slip_speed",  # |V1| [m/s]
    "tilt",  # angle between n and body axis 3 [rad]
    "friction_power",  # F · V1 + M Ω_n [W]
    "friction_force",  # |F|, tangential friction force (0 in rolling) [N]
    "slip_normal",  # V1 · n [m/s]
    "norm_error",  # |n| - 1 [1]
    "contact_x",  # contact point, space x [m]
    "contact_y",  # contact point, space y [m]
    "com_height",  # height of G above the plane [m]
    "rhs_status",  # right-hand-side status code
)
N_DIAGNOSTICS = len(DERIVED)
# the column indices the kernel writes (numba folds each global to its integer)
D_SPIN = DERIVED.index("spin")
D_ENERGY = DERIVED.index("energy")
D_NORMAL_FORCE = DERIVED.index("normal_force")
D_SLIP_SPEED = DERIVED.index("slip_speed")
D_TILT = DERIVED.index("tilt")
D_FRICTION_POWER = DERIVED.index("friction_power")
D_FRICTION_FORCE = DERIVED.index("friction_force")
D_SLIP_NORMAL = DERIVED.index("slip_normal")
D_NORM_ERROR = DERIVED.index("norm_error")
D_CONTACT_X = DERIVED.index("contact_x")
D_CONTACT_Y = DERIVED.index("contact_y")
D_HEIGHT = DERIVED.index("com_height")
D_STATUS = DERIVED.index("rhs_status")

# the blocks of the state array by name (layout in ``kernels.layout``), as a
# ``schema.VARIABLES`` source names them; a single index is a scalar
STATE_BLOCKS: dict[str, int | slice] = {
    "n": slice(Y_N, Y_N + 3),
    "omega": slice(Y_OMEGA, Y_OMEGA + 3),
    "slip_velocity": slice(Y_SLIP, Y_SLIP + 3),
    "quaternion": slice(Y_QUAT, Y_QUAT + 4),
    "com_position": slice(Y_POSITION, Y_POSITION + 2),
    "work": Y_WORK,
}


@inlined_kernel
def derived_columns(model, y, params, evaluated, out):
    """Fill ``out`` (length N_DIAGNOSTICS) with the derived quantities of state ``y``;
    ``evaluated`` is what :func:`evaluate` returned at ``y`` (status, normal force [N],
    friction power [W], friction force [N]).

    The caller evaluates the right-hand side: a run's samples at the run's link to it
    (``solvers.derived``), where calling :func:`evaluate` here would compile and optimise
    its code once more in every function that holds this one."""
    status, normal_force, friction_power, friction_force = evaluated
    n, omega, slip, quat = unpack(y)
    r, _ = contact(n, (0.0, 0.0, 0.0), params)
    norm = math.sqrt(dot(n, n))
    out[D_SPIN] = dot(omega, n)
    out[D_ENERGY] = energy(model, y, params)
    out[D_NORMAL_FORCE] = normal_force
    out[D_SLIP_SPEED] = math.sqrt(dot(slip, slip)) if model != ModelCode.ROLLING else 0.0
    out[D_TILT] = math.acos(min(1.0, max(-1.0, n[2] / norm)))
    out[D_FRICTION_POWER] = friction_power
    out[D_FRICTION_FORCE] = friction_force
    out[D_SLIP_NORMAL] = dot(slip, n)
    out[D_NORM_ERROR] = norm - 1.0
    contact_space = rotate(quat, r)
    out[D_CONTACT_X] = y[Y_POSITION] + contact_space[0]
    out[D_CONTACT_Y] = y[Y_POSITION + 1] + contact_space[1]
    out[D_HEIGHT] = -dot(r, n)
    out[D_STATUS] = status


@kernel
def spin_and_normal_force(model, y, params, work) -> tuple[float, float, int]:
    """Event quantities: spin ω · n [rad/s], normal force N [N], rhs status."""
    status, normal_force, _, _ = evaluate(model, y, params, work)
    return (
        y[Y_OMEGA] * y[Y_N] + y[Y_OMEGA + 1] * y[Y_N + 1] + y[Y_OMEGA + 2] * y[Y_N + 2],
        normal_force,
        status,
    )


@kernel
def phase_value(model, y, params, capture_speed) -> float:
    """Event function of the hybrid contact; a phase ends when it falls below zero.

    Stick: the stick margin g (``stick.stick_margin``). Sliding with
    ``capture_speed`` v_c > 0: sqrt(|V1|² + ε²(ω · n)²) - v_c, which falls through
    zero when slip and spin die together. Otherwise +1 (no phase event); NaN for an
    unknown model code.
    """
    if model == ModelCode.STICK:
        n, omega, _, _ = unpack(y)
        r, r_rate = contact(n, cross(n, omega), params)
        return stick_margin(n, omega, r, r_rate, params)
    if model == ModelCode.SLIDING:
        return slip_spin_speed(y, params) - capture_speed if capture_speed > 0.0 else 1.0
    if model == ModelCode.ROLLING:
        return 1.0
    return math.nan
