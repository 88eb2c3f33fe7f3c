"""Plain NumPy + SciPy rattleback (Celt stone): rolling and rolling-with-sliding models.

An independent oracle for celtstone, written from the founding paper
(../shared/paper/celt-rattleback-sliding.txt, eq. 3-12) and ../shared/references.md only.
It imports nothing from celtstone and favours readability over speed: every right-hand side
builds its vectors with ``np.cross`` and solves its 3x3 system with ``np.linalg.solve``.

Conventions (the project's)
---------------------------
* Body axes at the centre of mass G, axis 3 up at rest. ``n`` is the upward vertical unit
  vector in body axes, ``omega`` the angular velocity in body axes [rad/s]; spin = omega . n.
* ``r(n)`` is the contact point relative to G: the surface point whose outward normal is -n.
  Ellipsoid (semi-axes a, b, c about O, O = G + h e3), Q = diag(a^2, b^2, c^2):
  ``r = -Q n / sqrt(n^T Q n) + h e3``. Paraboloid z = x^2/(2 rho1) + y^2/(2 rho2) in a frame
  at the rest contact point with G at height l above it:
  ``r = (-rho1 n1/n3, -rho2 n2/n3, x^2/(2 rho1) + y^2/(2 rho2) - l)``.
  ``dr/dt = J(n) dn/dt`` with the Jacobian J = dr/dn differentiated analytically (below).
* Poisson: dn/dt = n x omega.
* Energy E = 1/2 m |v_G|^2 + 1/2 omega.I omega + m g z_G, z_G = -r.n. The dissipated work W
  is the last state component, dW/dt = -(friction power + damping power) >= 0, so that
  E(t) + W(t) = E(0) along exact solutions.

State vectors
-------------
* rolling: ``y = (n[3], omega[3], W)`` (7 components), v_G = -omega x r.
* sliding: ``y = (n[3], omega[3], V1[3], W)`` (10 components), V1 the velocity of the
  contact material point (body axes, V1.n = 0), v_G = V1 - omega x r.

Friction (Zhuravlev-Pade, paper eq. 10 and 12, Hertz disk of radius eps, coefficient f):
``F = -f N V1 / (|V1| + b eps |Omega_n|)``,
``M = -(3 pi/16) f N eps * eps Omega_n / (eps |Omega_n| + a |V1|)``,
b = 8/(3 pi), a = 15 pi/16, Omega_n = omega.n, moment vector M n. In both laws
|V1| is replaced by sqrt(|V1|^2 + delta^2) (delta = ``regularisation_speed``) so that the
state V1 = 0, Omega_n = 0 is not singular.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

B_FORCE = 8.0 / (3.0 * np.pi)
"""Pade coefficient b of the friction force, 8/(3 pi)."""
A_MOMENT = 15.0 * np.pi / 16.0
"""Pade coefficient a of the pivoting moment, 15 pi/16."""
M0_FACTOR = 3.0 * np.pi / 16.0
"""Hertz pivoting moment at zero slip, M0 = (3 pi/16) f N eps."""

E3 = np.array([0.0, 0.0, 1.0])
MODELS = ("rolling", "sliding")
STATE_SIZE = {"rolling": 7, "sliding": 10}


# --------------------------------------------------------------------------- bodies


def kane_levinson_body() -> dict[str, Any]:
    """Kane & Levinson (1982) ellipsoidal rattleback, SI units (../shared/references.md)."""
    return {
        "mass": 1.0,
        "gravity": 9.81,
        "inertia": np.array([[2e-4, -2e-5, 0.0], [-2e-5, 1.6e-3, 0.0], [0.0, 0.0, 1.7e-3]]),
        "shape": "ellipsoid",
        "semi_axes": (0.20, 0.03, 0.02),
        "com_offset": 0.01,
    }


def paraboloid_body(
    radii_of_curvature: tuple[float, float],
    com_height: float,
    mass: float,
    gravity: float,
    inertia: np.ndarray,
) -> dict[str, Any]:
    """A body whose surface is z = x^2/(2 rho1) + y^2/(2 rho2), G at ``com_height`` above."""
    return {
        "mass": float(mass),
        "gravity": float(gravity),
        "inertia": np.asarray(inertia, dtype=float),
        "shape": "paraboloid",
        "radii_of_curvature": (float(radii_of_curvature[0]), float(radii_of_curvature[1])),
        "com_height": float(com_height),
    }


def kane_levinson_paraboloid_body() -> dict[str, Any]:
    """The osculating paraboloid of Kane & Levinson's ellipsoid at the rest contact.

    rho1 = a^2/c = 2.0 m, rho2 = b^2/c = 0.045 m, l = c - h = 0.01 m.
    """
    body = kane_levinson_body()
    a, b, c = body["semi_axes"]
    return paraboloid_body(
        (a**2 / c, b**2 / c), c - body["com_offset"], body["mass"], body["gravity"], body["inertia"]
    )


# --------------------------------------------------------------------------- geometry


def contact_point(n: np.ndarray, body: dict[str, Any]) -> np.ndarray:
    """Contact point relative to G in body axes, r(n): the surface point with normal -n."""
    if body["shape"] == "ellipsoid":
        q = np.asarray(body["semi_axes"], dtype=float) ** 2
        qn = q * n
        return -qn / np.sqrt(n @ qn) + body["com_offset"] * E3
    if body["shape"] == "paraboloid":
        rho1, rho2 = body["radii_of_curvature"]
        x = -rho1 * n[0] / n[2]
        y = -rho2 * n[1] / n[2]
        z = x**2 / (2.0 * rho1) + y**2 / (2.0 * rho2)
        return np.array([x, y, z - body["com_height"]])
    raise ValueError(f"unknown shape {body['shape']!r}")


def contact_jacobian(n: np.ndarray, body: dict[str, Any]) -> np.ndarray:
    """J = dr/dn (analytic), so that dr/dt = J dn/dt.

    Ellipsoid: with s = sqrt(n^T Q n), J = -Q/s + (Q n)(Q n)^T / s^3.
    Paraboloid: dx = -rho1 (dn1/n3 - n1 dn3/n3^2), dy likewise, dz = x dx/rho1 + y dy/rho2.
    """
    if body["shape"] == "ellipsoid":
        q = np.diag(np.asarray(body["semi_axes"], dtype=float) ** 2)
        qn = q @ n
        s = np.sqrt(n @ qn)
        return -q / s + np.outer(qn, qn) / s**3
    if body["shape"] == "paraboloid":
        rho1, rho2 = body["radii_of_curvature"]
        n1, n2, n3 = n
        x = -rho1 * n1 / n3
        y = -rho2 * n2 / n3
        dx = -rho1 * np.array([1.0 / n3, 0.0, -n1 / n3**2])
        dy = -rho2 * np.array([0.0, 1.0 / n3, -n2 / n3**2])
        dz = x * dx / rho1 + y * dy / rho2
        return np.array([dx, dy, dz])
    raise ValueError(f"unknown shape {body['shape']!r}")


# --------------------------------------------------------------------------- states


def initial_vertical(alpha_deg: float, beta_deg: float) -> np.ndarray:
    """Upward vertical in body axes for Euler tilts alpha, beta [deg]."""
    alpha, beta = np.radians(alpha_deg), np.radians(beta_deg)
    return np.array([-np.cos(alpha) * np.sin(beta), np.sin(alpha), np.cos(alpha) * np.cos(beta)])


def initial_state(alpha_deg: float, beta_deg: float, omega0: Any, model: str) -> np.ndarray:
    """Rolling start: (n, omega, W = 0), or (n, omega, V1 = 0, W = 0) for ``sliding``."""
    n = initial_vertical(alpha_deg, beta_deg)
    omega = np.asarray(omega0, dtype=float).reshape(3)
    if model == "rolling":
        return np.concatenate([n, omega, [0.0]])
    if model == "sliding":
        return np.concatenate([n, omega, np.zeros(3), [0.0]])
    raise ValueError(f"unknown model {model!r}")


def spin(y: np.ndarray) -> float:
    """Spin about the vertical, omega . n [rad/s]."""
    return float(np.dot(y[3:6], y[0:3]))


# --------------------------------------------------------------------------- rolling


def _rolling_acceleration(
    y: np.ndarray, body: dict[str, Any], damping: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(dn/dt, domega/dt, r, dr/dt) of the rolling model, paper eq. 5."""
    m, g, inertia = body["mass"], body["gravity"], body["inertia"]
    n, omega = y[0:3], y[3:6]
    n_dot = np.cross(n, omega)
    r = contact_point(n, body)
    r_dot = contact_jacobian(n, body) @ n_dot
    # inertia about the contact point: I + m (|r|^2 E - r r^T)
    lhs = inertia + m * (np.dot(r, r) * np.eye(3) - np.outer(r, r))
    acceleration_free = np.cross(omega, r_dot) + np.cross(omega, np.cross(omega, r))
    rhs = (
        -np.cross(omega, inertia @ omega)
        + m * np.cross(r, g * n - acceleration_free)
        - damping * omega
    )
    omega_dot = np.linalg.solve(lhs, rhs)
    return n_dot, omega_dot, r, r_dot


def rhs_rolling(t: float, y: np.ndarray, body: dict[str, Any], damping: float = 0.0) -> np.ndarray:
    """Rolling without slip (paper eq. 3-5) with viscous torque -damping * omega."""
    n_dot, omega_dot, _, _ = _rolling_acceleration(y, body, damping)
    omega = y[3:6]
    work_dot = damping * np.dot(omega, omega)
    return np.concatenate([n_dot, omega_dot, [work_dot]])


# --------------------------------------------------------------------------- sliding


def friction_shapes(
    v1: np.ndarray, spin_rate: float, contact_radius: float, regularisation_speed: float
) -> tuple[np.ndarray, float]:
    """Friction per unit (f N): phi with F = f N phi, psi with M = f N psi (paper eq. 10, 12).

    phi = -V1 / (|V1| + b eps |Omega_n|),
    psi = -(3 pi/16) eps * eps Omega_n / (eps |Omega_n| + a |V1|),
    |V1| regularised as sqrt(|V1|^2 + delta^2).
    """
    eps = contact_radius
    speed = np.sqrt(np.dot(v1, v1) + regularisation_speed**2)
    phi = -v1 / (speed + B_FORCE * eps * abs(spin_rate))
    psi = -M0_FACTOR * eps * eps * spin_rate / (eps * abs(spin_rate) + A_MOMENT * speed)
    return phi, psi


def _sliding_terms(
    y: np.ndarray,
    body: dict[str, Any],
    friction_coefficient: float,
    contact_radius: float,
    friction_load: str,
    damping: float,
    regularisation_speed: float,
) -> dict[str, Any]:
    """All intermediate quantities of the sliding model (paper eq. 6-12) at state y."""
    m, g, inertia = body["mass"], body["gravity"], body["inertia"]
    f = friction_coefficient
    n, omega, v1 = y[0:3], y[3:6], y[6:9]
    n_dot = np.cross(n, omega)
    r = contact_point(n, body)
    r_dot = contact_jacobian(n, body) @ n_dot
    d = np.cross(r, n)
    spin_rate = np.dot(omega, n)
    phi, psi = friction_shapes(v1, spin_rate, contact_radius, regularisation_speed)
    acceleration_free = np.cross(omega, r_dot) + np.cross(omega, np.cross(omega, r))
    free_torque = -np.cross(omega, inertia @ omega) - damping * omega  # gyroscopic + viscous
    n0 = m * g - m * np.dot(n, acceleration_free)  # N_true without its domega/dt term

    if friction_load == "static":
        # F and M with N = m g (paper's first approximation); torque of N n with N_true
        friction = m * g * f * phi
        moment = m * g * f * psi
        lhs = inertia + m * np.outer(d, d)
        rhs = free_torque + n0 * d + np.cross(r, friction) + moment * n
        omega_dot = np.linalg.solve(lhs, rhs)
        normal = n0 - m * np.dot(d, omega_dot)
    elif friction_load == "dynamic":
        # F = N f phi, M = N f psi with N = N_true = n0 - m d.domega/dt: linear in domega/dt
        k = d + f * np.cross(r, phi) + f * psi * n
        lhs = inertia + m * np.outer(k, d)
        rhs = free_torque + n0 * k
        omega_dot = np.linalg.solve(lhs, rhs)
        normal = n0 - m * np.dot(d, omega_dot)
        friction = normal * f * phi
        moment = normal * f * psi
    else:
        raise ValueError(f"friction_load must be 'static' or 'dynamic', not {friction_load!r}")

    projector = np.eye(3) - np.outer(n, n)
    w1 = friction / m + projector @ (np.cross(omega_dot, r) + acceleration_free)
    v1_dot = w1 - np.cross(omega, v1)
    friction_power = np.dot(friction, v1) + moment * spin_rate
    damping_power = -damping * np.dot(omega, omega)
    return {
        "n_dot": n_dot,
        "omega_dot": omega_dot,
        "v1_dot": v1_dot,
        "work_dot": -(friction_power + damping_power),
        "normal_force": normal,
        "friction_force": friction,
        "friction_moment": moment,
        "friction_power": friction_power,
    }


def rhs_sliding(
    t: float,
    y: np.ndarray,
    body: dict[str, Any],
    friction_coefficient: float,
    contact_radius: float,
    friction_load: str = "static",
    damping: float = 0.0,
    regularisation_speed: float = 1e-6,
) -> np.ndarray:
    """Rolling with sliding and pivoting friction (paper eq. 6-12)."""
    terms = _sliding_terms(
        y,
        body,
        friction_coefficient,
        contact_radius,
        friction_load,
        damping,
        regularisation_speed,
    )
    return np.concatenate(
        [terms["n_dot"], terms["omega_dot"], terms["v1_dot"], [terms["work_dot"]]]
    )


# --------------------------------------------------------------------------- observables


def centre_of_mass_velocity(y: np.ndarray, body: dict[str, Any], model: str) -> np.ndarray:
    """v_G in body axes: -omega x r (rolling) or V1 - omega x r (sliding)."""
    n, omega = y[0:3], y[3:6]
    r = contact_point(n, body)
    v_g = -np.cross(omega, r)
    if model == "sliding":
        v_g = v_g + y[6:9]
    return v_g


def energy(y: np.ndarray, body: dict[str, Any], model: str) -> float:
    """Mechanical energy 1/2 m |v_G|^2 + 1/2 omega.I omega + m g z_G, z_G = -r.n [J]."""
    m, g, inertia = body["mass"], body["gravity"], body["inertia"]
    n, omega = y[0:3], y[3:6]
    v_g = centre_of_mass_velocity(y, body, model)
    height = -np.dot(contact_point(n, body), n)
    return float(0.5 * m * v_g @ v_g + 0.5 * omega @ inertia @ omega + m * g * height)


def normal_force(y: np.ndarray, body: dict[str, Any], model: str, **params: Any) -> float:
    """Vertical contact reaction N = m g - m n.(domega/dt x r + omega x rdot + omega x (omega x r)).

    ``params`` are those of ``rhs_rolling`` or ``rhs_sliding``. In the sliding model this is
    N_true in both friction loads (the static one uses m g only inside F and M).
    """
    if model == "rolling":
        m, g = body["mass"], body["gravity"]
        n, omega = y[0:3], y[3:6]
        _, omega_dot, r, r_dot = _rolling_acceleration(y, body, params.get("damping", 0.0))
        acceleration = (
            np.cross(omega_dot, r) + np.cross(omega, r_dot) + np.cross(omega, np.cross(omega, r))
        )
        return float(m * g - m * np.dot(n, acceleration))
    if model == "sliding":
        terms = _sliding_terms(
            y,
            body,
            params["friction_coefficient"],
            params["contact_radius"],
            params.get("friction_load", "static"),
            params.get("damping", 0.0),
            params.get("regularisation_speed", 1e-6),
        )
        return float(terms["normal_force"])
    raise ValueError(f"unknown model {model!r}")


# --------------------------------------------------------------------------- integration


def numerical_jacobian(fun: Any, t: float, y: np.ndarray) -> np.ndarray:
    """Central-difference Jacobian d fun/d y, step 1e-7 max(|y_j|, 1e-2) per component.

    Handed to the implicit solvers: SciPy's own adaptive ``num_jac`` keeps enlarging its step
    for the dissipated-work column (identically zero, nothing depends on W) until it
    overflows and warns.
    """
    y = np.asarray(y, dtype=float)
    jac = np.empty((y.size, y.size))
    for j in range(y.size):
        step = 1e-7 * max(abs(y[j]), 1e-2)
        plus, minus = y.copy(), y.copy()
        plus[j] += step
        minus[j] -= step
        jac[:, j] = (fun(t, plus) - fun(t, minus)) / (plus[j] - minus[j])
    return jac


def simulate(
    model: str,
    body: dict[str, Any],
    y0: np.ndarray,
    t_end: float,
    t_eval: np.ndarray | None = None,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    method: str | None = None,
    **params: Any,
) -> Any:
    """Integrate with ``scipy.integrate.solve_ivp`` from t = 0 to ``t_end``.

    ``method`` defaults to "DOP853" for rolling and "Radau" for sliding (the friction law is
    stiff near zero slip); implicit methods get ``numerical_jacobian``. ``params`` go to the
    right-hand side (damping; friction_coefficient, contact_radius, friction_load,
    regularisation_speed). Returns SciPy's OdeResult.
    """
    if model == "rolling":
        rhs, default_method = rhs_rolling, "DOP853"
    elif model == "sliding":
        rhs, default_method = rhs_sliding, "Radau"
    else:
        raise ValueError(f"unknown model {model!r}")
    y0 = np.asarray(y0, dtype=float)
    if y0.shape != (STATE_SIZE[model],):
        raise ValueError(f"{model} state has {STATE_SIZE[model]} components, got {y0.shape}")

    def fun(t: float, y: np.ndarray) -> np.ndarray:
        return rhs(t, y, body, **params)

    method = method or default_method
    options: dict[str, Any] = {}
    if method in ("Radau", "BDF", "LSODA"):
        options["jac"] = lambda t, y: numerical_jacobian(fun, t, y)
    return solve_ivp(
        fun, (0.0, float(t_end)), y0, method=method, t_eval=t_eval, rtol=rtol, atol=atol, **options
    )
