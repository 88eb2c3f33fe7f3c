"""A careful SciPy baseline: what a competent researcher writes without a compiler.

``scipy.integrate.solve_ivp`` on a right-hand side in plain Python scalar arithmetic:
cross products written out by component, the 3x3 solve done by hand (the adjugate of the
symmetric rolling matrix; a Sherman-Morrison update of the precomputed inverse inertia in the
sliding model), no NumPy temporaries, one output array per call. The equations are those of
the independent oracle ``tests/oracle/rattleback.py`` (paper eq. 3-12), written again from
its docstring; nothing is imported from celtstone, and only ``main`` takes the body and
initial state from the oracle, so that ``tests/oracle/test_careful_baseline.py`` compares two
independent codes.

Same conventions, bodies (the oracle's body dicts, ellipsoid only) and state layout as the
oracle: rolling ``y = (n[3], omega[3], W)``, sliding ``y = (n[3], omega[3], V1[3], W)``.
The rolling model runs with DOP853, the sliding model with Radau and a central-difference
Jacobian (the friction law is stiff near zero slip), as in the oracle.

``python benchmarks/careful_baseline.py`` prints the wall time of Kane & Levinson's 50 s
rolling run at rtol 1e-11, atol 1e-12.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tests.oracle import rattleback as oracle

B_FORCE = 8.0 / (3.0 * math.pi)
"""Pade coefficient b of the friction force, 8/(3 pi) (paper eq. 10)."""
A_MOMENT = 15.0 * math.pi / 16.0
"""Pade coefficient a of the pivoting moment, 15 pi/16 (paper eq. 12)."""
M0_FACTOR = 3.0 * math.pi / 16.0
"""Hertz pivoting moment at zero slip, M0 = (3 pi/16) f N eps."""

Rhs = Callable[[float, np.ndarray], np.ndarray]


def _constants(body: dict[str, Any]) -> tuple[float, ...]:
    """(m, g, I11, I12, I13, I22, I23, I33, a^2, b^2, c^2, h) of an ellipsoidal body dict."""
    if body["shape"] != "ellipsoid":
        raise ValueError(f"the careful baseline has the ellipsoid only, not {body['shape']!r}")
    inertia = np.asarray(body["inertia"], dtype=float)
    if not np.allclose(inertia, inertia.T, rtol=0.0, atol=0.0):
        raise ValueError("the inertia tensor must be symmetric")
    a, b, c = (float(x) for x in body["semi_axes"])
    return (
        float(body["mass"]),
        float(body["gravity"]),
        float(inertia[0, 0]),
        float(inertia[0, 1]),
        float(inertia[0, 2]),
        float(inertia[1, 1]),
        float(inertia[1, 2]),
        float(inertia[2, 2]),
        a * a,
        b * b,
        c * c,
        float(body["com_offset"]),
    )


def rolling_rhs(body: dict[str, Any], damping: float = 0.0) -> Rhs:
    """Right-hand side ``fun(t, y)`` of rolling without slip (paper eq. 3-5).

    dn/dt = n x omega; r = -Q n / sqrt(n.Q n) + h e3; dr/dt = J dn/dt with
    J = -Q/s + (Q n)(Q n)^T/s^3; (I + m(|r|^2 E - r r^T)) domega/dt =
    -omega x I omega + m r x (g n - omega x dr/dt - omega x (omega x r)) - damping omega;
    dW/dt = damping |omega|^2.
    """
    m, g, i11, i12, i13, i22, i23, i33, q1, q2, q3, h = _constants(body)
    c = float(damping)
    sqrt = math.sqrt
    array = np.array

    def fun(t: float, y: np.ndarray) -> np.ndarray:
        n1, n2, n3, w1, w2, w3, _ = y.tolist()
        # Poisson: dn/dt = n x omega
        nd1 = n2 * w3 - n3 * w2
        nd2 = n3 * w1 - n1 * w3
        nd3 = n1 * w2 - n2 * w1
        # contact point and its rate
        p1, p2, p3 = q1 * n1, q2 * n2, q3 * n3
        inv_s = 1.0 / sqrt(n1 * p1 + n2 * p2 + n3 * p3)
        r1, r2, r3 = -p1 * inv_s, -p2 * inv_s, h - p3 * inv_s
        u = (p1 * nd1 + p2 * nd2 + p3 * nd3) * inv_s * inv_s * inv_s
        rd1 = p1 * u - q1 * nd1 * inv_s
        rd2 = p2 * u - q2 * nd2 * inv_s
        rd3 = p3 * u - q3 * nd3 * inv_s
        # acceleration of G without the domega/dt term: omega x rdot + omega x (omega x r)
        wr = w1 * r1 + w2 * r2 + w3 * r3
        ww = w1 * w1 + w2 * w2 + w3 * w3
        f1 = w2 * rd3 - w3 * rd2 + w1 * wr - r1 * ww
        f2 = w3 * rd1 - w1 * rd3 + w2 * wr - r2 * ww
        f3 = w1 * rd2 - w2 * rd1 + w3 * wr - r3 * ww
        # right-hand side: -omega x I omega + m r x (g n - a_free) - c omega
        l1 = i11 * w1 + i12 * w2 + i13 * w3
        l2 = i12 * w1 + i22 * w2 + i23 * w3
        l3 = i13 * w1 + i23 * w2 + i33 * w3
        v1, v2, v3 = g * n1 - f1, g * n2 - f2, g * n3 - f3
        b1 = w3 * l2 - w2 * l3 + m * (r2 * v3 - r3 * v2) - c * w1
        b2 = w1 * l3 - w3 * l1 + m * (r3 * v1 - r1 * v3) - c * w2
        b3 = w2 * l1 - w1 * l2 + m * (r1 * v2 - r2 * v1) - c * w3
        # inertia about the contact point, I + m (|r|^2 E - r r^T), solved by its adjugate
        a11 = i11 + m * (r2 * r2 + r3 * r3)
        a22 = i22 + m * (r1 * r1 + r3 * r3)
        a33 = i33 + m * (r1 * r1 + r2 * r2)
        a12 = i12 - m * r1 * r2
        a13 = i13 - m * r1 * r3
        a23 = i23 - m * r2 * r3
        c11 = a22 * a33 - a23 * a23
        c12 = a13 * a23 - a12 * a33
        c13 = a12 * a23 - a13 * a22
        c22 = a11 * a33 - a13 * a13
        c23 = a12 * a13 - a11 * a23
        c33 = a11 * a22 - a12 * a12
        inv_det = 1.0 / (a11 * c11 + a12 * c12 + a13 * c13)
        return array(
            [
                nd1,
                nd2,
                nd3,
                (c11 * b1 + c12 * b2 + c13 * b3) * inv_det,
                (c12 * b1 + c22 * b2 + c23 * b3) * inv_det,
                (c13 * b1 + c23 * b2 + c33 * b3) * inv_det,
                c * ww,
            ]
        )

    return fun


def sliding_rhs(
    body: dict[str, Any],
    friction_coefficient: float,
    contact_radius: float,
    friction_load: str = "static",
    damping: float = 0.0,
    regularisation_speed: float = 1e-6,
) -> Rhs:
    """Right-hand side ``fun(t, y)`` of rolling with sliding and pivoting (paper eq. 6-12).

    Zhuravlev-Pade friction with |V1| -> sqrt(|V1|^2 + delta^2):
    F = -f N V1 / (|V1| + b eps |Omega_n|), M = -(3 pi/16) f N eps^2 Omega_n /
    (eps |Omega_n| + a |V1|). ``friction_load`` "static": N = m g inside F and M, and
    (I + m d d^T) domega/dt = tau + n0 d + r x F + M n with d = r x n,
    n0 = m g - m n.a_free; "dynamic": N = n0 - m d.domega/dt, so
    (I + m k d^T) domega/dt = tau + n0 k with k = d + f r x phi + f psi n. Both matrices are
    rank-one updates of I, solved with Sherman-Morrison from the precomputed I^-1.
    dV1/dt = F/m + (E - n n^T)(domega/dt x r + a_free) - omega x V1;
    dW/dt = -(F.V1 + M Omega_n) + damping |omega|^2.
    """
    if friction_load not in ("static", "dynamic"):
        raise ValueError(f"friction_load must be 'static' or 'dynamic', not {friction_load!r}")
    dynamic = friction_load == "dynamic"
    m, g, i11, i12, i13, i22, i23, i33, q1, q2, q3, h = _constants(body)
    inverse = np.linalg.inv(np.asarray(body["inertia"], dtype=float))
    j11, j12, j13 = (float(x) for x in inverse[0])
    j22, j23, j33 = float(inverse[1, 1]), float(inverse[1, 2]), float(inverse[2, 2])
    c = float(damping)
    f = float(friction_coefficient)
    eps = float(contact_radius)
    delta2 = float(regularisation_speed) ** 2
    b_eps = B_FORCE * eps
    m0_eps2 = M0_FACTOR * eps * eps
    mgf = m * g * f
    sqrt = math.sqrt
    array = np.array

    def fun(t: float, y: np.ndarray) -> np.ndarray:
        n1, n2, n3, w1, w2, w3, s1, s2, s3, _ = y.tolist()  # s = V1
        nd1 = n2 * w3 - n3 * w2
        nd2 = n3 * w1 - n1 * w3
        nd3 = n1 * w2 - n2 * w1
        p1, p2, p3 = q1 * n1, q2 * n2, q3 * n3
        inv_s = 1.0 / sqrt(n1 * p1 + n2 * p2 + n3 * p3)
        r1, r2, r3 = -p1 * inv_s, -p2 * inv_s, h - p3 * inv_s
        u = (p1 * nd1 + p2 * nd2 + p3 * nd3) * inv_s * inv_s * inv_s
        rd1 = p1 * u - q1 * nd1 * inv_s
        rd2 = p2 * u - q2 * nd2 * inv_s
        rd3 = p3 * u - q3 * nd3 * inv_s
        # d = r x n
        d1 = r2 * n3 - r3 * n2
        d2 = r3 * n1 - r1 * n3
        d3 = r1 * n2 - r2 * n1
        # friction per unit f N: phi (vector), psi
        spin = w1 * n1 + w2 * n2 + w3 * n3
        speed = sqrt(s1 * s1 + s2 * s2 + s3 * s3 + delta2)
        eps_spin = eps * abs(spin)
        k_phi = -1.0 / (speed + b_eps * abs(spin))
        ph1, ph2, ph3 = k_phi * s1, k_phi * s2, k_phi * s3
        psi = -m0_eps2 * spin / (eps_spin + A_MOMENT * speed)
        # a_free = omega x rdot + omega x (omega x r)
        wr = w1 * r1 + w2 * r2 + w3 * r3
        ww = w1 * w1 + w2 * w2 + w3 * w3
        f1 = w2 * rd3 - w3 * rd2 + w1 * wr - r1 * ww
        f2 = w3 * rd1 - w1 * rd3 + w2 * wr - r2 * ww
        f3 = w1 * rd2 - w2 * rd1 + w3 * wr - r3 * ww
        # free torque: -omega x I omega - c omega
        l1 = i11 * w1 + i12 * w2 + i13 * w3
        l2 = i12 * w1 + i22 * w2 + i23 * w3
        l3 = i13 * w1 + i23 * w2 + i33 * w3
        t1 = w3 * l2 - w2 * l3 - c * w1
        t2 = w1 * l3 - w3 * l1 - c * w2
        t3 = w2 * l1 - w1 * l2 - c * w3
        n0 = m * g - m * (n1 * f1 + n2 * f2 + n3 * f3)
        if dynamic:
            # k = d + f r x phi + f psi n; (I + m k d^T) x = tau + n0 k
            k1 = d1 + f * (r2 * ph3 - r3 * ph2 + psi * n1)
            k2 = d2 + f * (r3 * ph1 - r1 * ph3 + psi * n2)
            k3 = d3 + f * (r1 * ph2 - r2 * ph1 + psi * n3)
            b1, b2, b3 = t1 + n0 * k1, t2 + n0 * k2, t3 + n0 * k3
        else:
            # F = m g f phi, M = m g f psi; (I + m d d^T) x = tau + n0 d + r x F + M n
            k1, k2, k3 = d1, d2, d3
            fr1, fr2, fr3 = mgf * ph1, mgf * ph2, mgf * ph3
            moment = mgf * psi
            b1 = t1 + n0 * d1 + r2 * fr3 - r3 * fr2 + moment * n1
            b2 = t2 + n0 * d2 + r3 * fr1 - r1 * fr3 + moment * n2
            b3 = t3 + n0 * d3 + r1 * fr2 - r2 * fr1 + moment * n3
        # Sherman-Morrison: x = I^-1 b - I^-1 k (m d.I^-1 b) / (1 + m d.I^-1 k)
        x1 = j11 * b1 + j12 * b2 + j13 * b3
        x2 = j12 * b1 + j22 * b2 + j23 * b3
        x3 = j13 * b1 + j23 * b2 + j33 * b3
        e1 = j11 * k1 + j12 * k2 + j13 * k3
        e2 = j12 * k1 + j22 * k2 + j23 * k3
        e3 = j13 * k1 + j23 * k2 + j33 * k3
        scale = m * (d1 * x1 + d2 * x2 + d3 * x3) / (1.0 + m * (d1 * e1 + d2 * e2 + d3 * e3))
        o1, o2, o3 = x1 - scale * e1, x2 - scale * e2, x3 - scale * e3  # domega/dt
        if dynamic:
            normal_f = (n0 - m * (d1 * o1 + d2 * o2 + d3 * o3)) * f
            fr1, fr2, fr3 = normal_f * ph1, normal_f * ph2, normal_f * ph3
            moment = normal_f * psi
        # dV1/dt = F/m + (E - n n^T)(domega/dt x r + a_free) - omega x V1
        z1 = o2 * r3 - o3 * r2 + f1
        z2 = o3 * r1 - o1 * r3 + f2
        z3 = o1 * r2 - o2 * r1 + f3
        nz = n1 * z1 + n2 * z2 + n3 * z3
        power = fr1 * s1 + fr2 * s2 + fr3 * s3 + moment * spin
        return array(
            [
                nd1,
                nd2,
                nd3,
                o1,
                o2,
                o3,
                fr1 / m + z1 - n1 * nz - (w2 * s3 - w3 * s2),
                fr2 / m + z2 - n2 * nz - (w3 * s1 - w1 * s3),
                fr3 / m + z3 - n3 * nz - (w1 * s2 - w2 * s1),
                c * ww - power,
            ]
        )

    return fun


def central_jacobian(fun: Rhs, size: int) -> Callable[[float, np.ndarray], np.ndarray]:
    """Central-difference Jacobian, step 1e-7 max(|y_j|, 1e-2), the work column W skipped.

    Nothing depends on the dissipated work W (the last component), so its column is zero.
    """

    def jac(t: float, y: np.ndarray) -> np.ndarray:
        out = np.zeros((size, size))
        probe = np.array(y, dtype=float)
        for j in range(size - 1):
            yj = probe[j]
            step = 1e-7 * max(abs(yj), 1e-2)
            probe[j] = yj + step
            plus = fun(t, probe)
            probe[j] = yj - step
            minus = fun(t, probe)
            probe[j] = yj
            out[:, j] = (plus - minus) / (2.0 * step)
        return out

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
    """``solve_ivp`` from t = 0 to ``t_end``: DOP853 (rolling) or Radau (sliding) by default.

    ``params`` go to ``rolling_rhs`` / ``sliding_rhs``. Returns SciPy's OdeResult.
    """
    if model == "rolling":
        fun, default_method, size = rolling_rhs(body, **params), "DOP853", 7
    elif model == "sliding":
        fun, default_method, size = sliding_rhs(body, **params), "Radau", 10
    else:
        raise ValueError(f"unknown model {model!r}")
    y0 = np.asarray(y0, dtype=float)
    if y0.shape != (size,):
        raise ValueError(f"{model} state has {size} components, got {y0.shape}")
    method = method or default_method
    options: dict[str, Any] = {}
    if method in ("Radau", "BDF", "LSODA"):
        options["jac"] = central_jacobian(fun, size)
    return solve_ivp(
        fun, (0.0, float(t_end)), y0, method=method, t_eval=t_eval, rtol=rtol, atol=atol, **options
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--t-end", type=float, default=50.0, help="simulated time [s]")
    parser.add_argument("--rtol", type=float, default=1e-11)
    parser.add_argument("--atol", type=float, default=1e-12)
    args = parser.parse_args()
    body = oracle.kane_levinson_body()  # the body and start only; the numerics are ours
    y0 = oracle.initial_state(0.5, 0.5, (0.0, 0.0, -5.0), "rolling")
    start = time.perf_counter()
    run = simulate(
        "rolling",
        body,
        y0,
        args.t_end,
        t_eval=np.array([args.t_end]),
        rtol=args.rtol,
        atol=args.atol,
    )
    elapsed = time.perf_counter() - start
    spin = float(np.dot(run.y[0:3, -1], run.y[3:6, -1]))
    print(
        f"careful baseline, rolling, {args.t_end:g} s, rtol {args.rtol:g}, atol {args.atol:g}: "
        f"{elapsed:.2f} s wall, {run.nfev} evaluations, final spin {spin:.10f} rad/s"
    )


if __name__ == "__main__":
    main()
