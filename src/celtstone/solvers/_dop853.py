"""Dormand–Prince 8(5,3) explicit Runge–Kutta step with 7th-order dense output.

Hairer, Nørsett & Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
sec. II.10 (code DOP853). The coefficient tables are SciPy's
(``scipy.integrate._ivp.dop853_coefficients``), read once at import.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate._ivp import dop853_coefficients as _coefficients

from celtstone.kernels._jit import kernel
from celtstone.kernels.system import rhs

N_STAGES = int(_coefficients.N_STAGES)  # 12
N_STAGES_EXTENDED = int(_coefficients.N_STAGES_EXTENDED)  # 16
A = np.ascontiguousarray(_coefficients.A, dtype=np.float64)
B = np.ascontiguousarray(_coefficients.B, dtype=np.float64)
C = np.ascontiguousarray(_coefficients.C, dtype=np.float64)
E3 = np.ascontiguousarray(_coefficients.E3, dtype=np.float64)
E5 = np.ascontiguousarray(_coefficients.E5, dtype=np.float64)
D = np.ascontiguousarray(_coefficients.D, dtype=np.float64)
ERROR_ORDER = 7
DENSE_ROWS = 7


@kernel
def evaluate_stage(model, params, s, t, y, h, stages, scratch):
    """Stage s: stages[s] = f(t + c_s h, y + h Σ_k a_sk stages[k])."""
    for j in range(y.shape[0]):
        total = 0.0
        for k in range(s):
            total += A[s, k] * stages[k, j]
        scratch[j] = y[j] + h * total
    rhs(model, t + C[s] * h, scratch, params, stages[s])


@kernel
def dop853_attempt(model, params, t, y, h, rtol, atol, stages, y_new, scratch):
    """One trial step of size h from (t, y), ``stages[0]`` = f(t, y) on entry.

    Fills ``y_new`` and ``stages[12]`` = f(t + h, y_new); returns the scaled error norm.
    """
    n = y.shape[0]
    for s in range(1, N_STAGES):
        evaluate_stage(model, params, s, t, y, h, stages, scratch)
    for j in range(n):
        total = 0.0
        for k in range(N_STAGES):
            total += B[k] * stages[k, j]
        y_new[j] = y[j] + h * total
    rhs(model, t + h, y_new, params, stages[N_STAGES])
    error5 = 0.0
    error3 = 0.0
    for j in range(n):
        scale = atol + max(abs(y[j]), abs(y_new[j])) * rtol
        e5 = 0.0
        e3 = 0.0
        for k in range(N_STAGES + 1):
            e5 += E5[k] * stages[k, j]
            e3 += E3[k] * stages[k, j]
        error5 += (e5 / scale) ** 2
        error3 += (e3 / scale) ** 2
    if error5 == 0.0 and error3 == 0.0:
        return 0.0
    return abs(h) * error5 / math.sqrt((error5 + 0.01 * error3) * n)


@kernel
def dop853_dense(model, params, t, y, y_new, h, stages, dense, scratch):
    """Coefficients of the 7th-order interpolant over the accepted step (3 extra stages)."""
    n = y.shape[0]
    for s in range(N_STAGES + 1, N_STAGES_EXTENDED):
        evaluate_stage(model, params, s, t, y, h, stages, scratch)
    for j in range(n):
        delta = y_new[j] - y[j]
        dense[0, j] = delta
        dense[1, j] = h * stages[0, j] - delta
        dense[2, j] = 2.0 * delta - h * (stages[N_STAGES, j] + stages[0, j])
        for i in range(4):
            total = 0.0
            for k in range(N_STAGES_EXTENDED):
                total += D[i, k] * stages[k, j]
            dense[3 + i, j] = h * total


@kernel
def dop853_interpolate(dense, y_old, x, out):
    """State at the fraction x in [0, 1] of the step from the interpolant."""
    n = y_old.shape[0]
    for j in range(n):
        value = 0.0
        for i in range(DENSE_ROWS):
            value += dense[DENSE_ROWS - 1 - i, j]
            if i % 2 == 0:
                value *= x
            else:
                value *= 1.0 - x
        out[j] = value + y_old[j]
