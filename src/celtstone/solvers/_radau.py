"""Radau IIA (order 5, three stages) implicit step with simplified Newton iterations.

Hairer & Wanner, *Solving Ordinary Differential Equations II*, 2nd ed., sec. IV.8
(code RADAU5): the collocation system is transformed to one real and one complex
linear system, the Jacobian is reused while Newton converges well, and the
collocation polynomial gives the dense output. Step-size control and Newton
tolerances follow SciPy's ``Radau`` (whose constants are read once at import).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate._ivp import radau as _radau

from celtstone.kernels._jit import kernel
from celtstone.kernels.system import rhs
from celtstone.solvers._linalg import lu_factor, lu_solve

C = np.ascontiguousarray(_radau.C, dtype=np.float64)
E = np.ascontiguousarray(_radau.E, dtype=np.float64)
MU_REAL = float(_radau.MU_REAL)
MU_COMPLEX = complex(_radau.MU_COMPLEX)
T = np.ascontiguousarray(_radau.T, dtype=np.float64)
TI = np.ascontiguousarray(_radau.TI, dtype=np.float64)
P = np.ascontiguousarray(_radau.P, dtype=np.float64)
NEWTON_MAXITER = 6
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
ERROR_ORDER = 3
DENSE_ROWS = 3
SQRT_EPS = math.sqrt(np.finfo(np.float64).eps)


@kernel
def jacobian(model, params, t, y, f, out, scratch, column):
    """Forward-difference Jacobian df/dy into ``out`` (n, n); N_STATE evaluations."""
    n = y.shape[0]
    for j in range(n):
        scratch[j] = y[j]
    for j in range(n):
        step = SQRT_EPS * max(abs(y[j]), 1e-5)
        scratch[j] = y[j] + step
        step = scratch[j] - y[j]
        rhs(model, t, scratch, params, column)
        for i in range(n):
            out[i, j] = (column[i] - f[i]) / step
        scratch[j] = y[j]


@kernel
def factor_systems(h, jac, lu_real, pivots_real, lu_complex, pivots_complex):
    """LU of MU_REAL/h I - J and MU_COMPLEX/h I - J; False if either is singular."""
    n = jac.shape[0]
    real_shift = MU_REAL / h
    complex_shift = MU_COMPLEX / h
    for i in range(n):
        for j in range(n):
            lu_real[i, j] = -jac[i, j]
            lu_complex[i, j] = -jac[i, j]
        lu_real[i, i] += real_shift
        lu_complex[i, i] += complex_shift
    ok_real = lu_factor(lu_real, pivots_real)
    ok_complex = lu_factor(lu_complex, pivots_complex)
    return ok_real and ok_complex


@kernel
def solve_collocation(
    model,
    params,
    t,
    y,
    h,
    stages,
    scale,
    tol,
    lu_real,
    pivots_real,
    lu_complex,
    pivots_complex,
    work_w,
    work_f,
    scratch,
    real_rhs,
    complex_rhs,
):
    """Simplified Newton for the collocation increments ``stages`` (3, n), in place.

    Returns (converged, iterations, rate); ``stages`` holds the initial guess on entry.
    """
    n = y.shape[0]
    real_shift = MU_REAL / h
    complex_shift = MU_COMPLEX / h
    # W = TI Z
    for i in range(3):
        for j in range(n):
            work_w[i, j] = (
                TI[i, 0] * stages[0, j] + TI[i, 1] * stages[1, j] + TI[i, 2] * stages[2, j]
            )
    norm_old = -1.0
    rate = -1.0
    converged = False
    iterations = 0
    for k in range(NEWTON_MAXITER):
        iterations = k + 1
        finite = True
        for i in range(3):
            for j in range(n):
                scratch[j] = y[j] + stages[i, j]
            rhs(model, t + C[i] * h, scratch, params, work_f[i])
            for j in range(n):
                if not math.isfinite(work_f[i, j]):
                    finite = False
        if not finite:
            break
        for j in range(n):
            fr = TI[0, 0] * work_f[0, j] + TI[0, 1] * work_f[1, j] + TI[0, 2] * work_f[2, j]
            fc_re = TI[1, 0] * work_f[0, j] + TI[1, 1] * work_f[1, j] + TI[1, 2] * work_f[2, j]
            fc_im = TI[2, 0] * work_f[0, j] + TI[2, 1] * work_f[1, j] + TI[2, 2] * work_f[2, j]
            real_rhs[j] = fr - real_shift * work_w[0, j]
            complex_rhs[j] = complex(fc_re, fc_im) - complex_shift * complex(
                work_w[1, j], work_w[2, j]
            )
        lu_solve(lu_real, pivots_real, real_rhs)
        lu_solve(lu_complex, pivots_complex, complex_rhs)
        total = 0.0
        for j in range(n):
            total += (real_rhs[j] / scale[j]) ** 2
            total += (complex_rhs[j].real / scale[j]) ** 2
            total += (complex_rhs[j].imag / scale[j]) ** 2
        norm = math.sqrt(total / (3 * n))
        if norm_old >= 0.0:
            rate = norm / norm_old
        if rate >= 0.0 and (
            rate >= 1.0 or rate ** (NEWTON_MAXITER - k) / (1.0 - rate) * norm > tol
        ):
            break
        for j in range(n):
            work_w[0, j] += real_rhs[j]
            work_w[1, j] += complex_rhs[j].real
            work_w[2, j] += complex_rhs[j].imag
        for i in range(3):
            for j in range(n):
                stages[i, j] = (
                    T[i, 0] * work_w[0, j] + T[i, 1] * work_w[1, j] + T[i, 2] * work_w[2, j]
                )
        if norm == 0.0 or (rate >= 0.0 and rate / (1.0 - rate) * norm < tol):
            converged = True
            break
        norm_old = norm
    return converged, iterations, rate


@kernel
def predict_factor(h_abs, h_abs_old, error_norm, error_norm_old):
    """Gustafsson's predictive step-size factor (as SciPy's Radau)."""
    if error_norm_old < 0.0 or h_abs_old < 0.0 or error_norm == 0.0:
        multiplier = 1.0
    else:
        multiplier = h_abs / h_abs_old * (error_norm_old / error_norm) ** 0.25
    if error_norm == 0.0:
        return MAX_FACTOR
    return min(1.0, multiplier) * error_norm**-0.25


@kernel
def radau_dense(stages, dense):
    """Collocation-polynomial coefficients Q = Z^T P, stored as ``dense[0:3]``."""
    n = stages.shape[1]
    for j in range(n):
        for k in range(3):
            dense[k, j] = stages[0, j] * P[0, k] + stages[1, j] * P[1, k] + stages[2, j] * P[2, k]


@kernel
def radau_predict(has_dense, dense, y_previous, t_previous, h_previous, t, h, y, stages, scratch):
    """Newton's starting guess: the last step's collocation polynomial extrapolated to the
    new stage times, minus y (zeros before the first step)."""
    if not has_dense:
        stages[:, :] = 0.0
        return
    for i in range(3):
        x = (t + C[i] * h - t_previous) / h_previous
        radau_interpolate(dense, y_previous, x, scratch)
        for j in range(y.shape[0]):
            stages[i, j] = scratch[j] - y[j]


@kernel
def radau_interpolate(dense, y_old, x, out):
    """State at the fraction x of the step: y_old + Σ_k Q_k x^(k+1)."""
    for j in range(y_old.shape[0]):
        out[j] = y_old[j] + x * (dense[0, j] + x * (dense[1, j] + x * dense[2, j]))
