"""Radau IIA, order 5, three stages: the stiff method of the methods registry
(``METHOD_RADAU5``).

Hairer & Wanner, *Solving Ordinary Differential Equations II*, 2nd ed., sec. IV.8
(code RADAU5): the collocation system is transformed to one real and one complex
linear system, solved by simplified Newton iterations that reuse the Jacobian and
its LU factors while Newton converges well; the collocation polynomial gives the
dense output and Newton's starting guess. Step-size control and Newton tolerances
follow SciPy's ``Radau`` (its constants are kept in ``solvers/tableaux.json``), plus
RADAU5's rule that a step accepted after a rejection is not followed by a larger one
(docs/decisions.md §34) and its Jacobian threshold raised for a costly Jacobian
(``JACOBIAN_RATE``, §37).

The module follows the method contract of ``solvers._methods``. What one step leaves
for the next (Jacobian, LU factors, the last collocation polynomial, the controller's
memory) lives in its :class:`Workspace`; the scalars in the record ``memory[0]``
(:data:`MEMORY`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from celtstone.kernels._jit import kernel
from celtstone.kernels.layout import N_DYNAMIC, N_READ, RHS_OK
from celtstone.solvers._compile import inlined
from celtstone.solvers._linalg import block_factor, block_solve
from celtstone.solvers._step_control import rms_scaled, smallest_step
from celtstone.solvers._system import rhs
from celtstone.solvers._tableaux import table
from celtstone.solvers.codes import (
    STAT_NFEV,
    STAT_NJEV,
    STAT_NLU,
    STAT_REJECTED,
    STATUS_STEP_TOO_SMALL,
    STATUS_SUCCESS,
)

_TABLE = table("radau")
C = _TABLE["C"]
E = _TABLE["E"]
MU_REAL = float(_TABLE["MU_REAL"])
MU_COMPLEX = complex(_TABLE["MU_COMPLEX"])
T = _TABLE["T"]
TI = _TABLE["TI"]
P = _TABLE["P"]
NEWTON_MAXITER = 6
# a new Jacobian after a step whose Newton iteration took more than 2 iterations at a
# contraction rate above this: RADAU5's THET, 1e-3 in SciPy and RADAU5 by default, which
# Hairer & Wanner raise "when Jacobian evaluations are costly"; ours costs N_READ = 13
# right-hand sides against 0.9 us for both LUs (docs/decisions.md §37)
JACOBIAN_RATE = 0.03
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
SAFETY = 0.9
ORDER = 5  # of the method: global error O(h^5)
ERROR_ORDER = 3  # of its local error estimate
DENSE_EVERY_STEP = True  # the next step's Newton guess extrapolates the last interpolant
DENSE_ROWS = 3
EPS = float(np.finfo(np.float64).eps)
SQRT_EPS = math.sqrt(EPS)

# the scalars a run carries from step to step
MEMORY = np.dtype(  # records, so that fields read as attributes in Python too
    (
        np.record,
        np.dtype(
            [
                ("newton_tolerance", "f8"),  # of the scaled Newton increment [1]
                ("lu_valid", "b1"),  # the LU factors belong to the current Jacobian and h_lu
                ("h_lu", "f8"),  # step size of the LU factors [s]
                ("current_jacobian", "b1"),  # the Jacobian was evaluated at this step's start
                ("h_abs_old", "f8"),  # last accepted step [s]; -1 before the first
                ("error_norm_old", "f8"),  # its error norm [1]; -1 before the first
                ("has_dense", "b1"),  # a collocation polynomial of an accepted step exists
                ("t_previous", "f8"),  # start of the last accepted step [s]
                ("h_previous", "f8"),  # its size [s]
                ("split", "i8"),  # the Jacobian is block lower triangular after this row (0: not)
            ],
            align=True,
        ),
    )
)


class Workspace(NamedTuple):
    """Arrays of one Radau run (n = state length)."""

    jacobian: np.ndarray  # (n, n) df/dy
    lu_real: np.ndarray  # (n, n) LU of MU_REAL/h I - J
    lu_complex: np.ndarray  # (n, n) complex, LU of MU_COMPLEX/h I - J
    pivots_real: np.ndarray  # (n,) int64
    pivots_complex: np.ndarray  # (n,) int64
    collocation: np.ndarray  # (3, n) Z, stage increments over y
    transformed: np.ndarray  # (3, n) W = TI Z
    stage_rates: np.ndarray  # (3, n) f at the stages
    real_rhs: np.ndarray  # (n,)
    complex_rhs: np.ndarray  # (n,) complex
    weights: np.ndarray  # (n,) 1 / (atol + |y| rtol), Newton's error weights
    scratch: np.ndarray  # (n,)
    column: np.ndarray  # (n,)
    point: np.ndarray  # (n,)
    dense: np.ndarray  # (DENSE_ROWS, n): Q, collocation polynomial of the last accepted step
    y_previous: np.ndarray  # (n,) state at its start
    memory: np.ndarray  # (1,) of MEMORY


@inlined
def workspace(n):
    """A workspace for states of length n, before the first step."""
    memory = np.zeros(1, dtype=MEMORY)
    memory[0].h_abs_old = -1.0
    memory[0].error_norm_old = -1.0
    return Workspace(
        np.zeros((n, n)),
        np.zeros((n, n)),
        np.zeros((n, n), dtype=np.complex128),
        np.zeros(n, dtype=np.int64),
        np.zeros(n, dtype=np.int64),
        np.zeros((3, n)),
        np.zeros((3, n)),
        np.zeros((3, n)),
        np.zeros(n),
        np.zeros(n, dtype=np.complex128),
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros((DENSE_ROWS, n)),
        np.zeros(n),
        memory,
    )


@kernel
def start(model, params, t, y, f, controls, work, stats):
    """Newton's tolerance from rtol (as SciPy's) and the Jacobian at the first state."""
    evaluate_jacobian(model, params, t, y, f, work, stats)
    resume(controls, work)


@kernel
def resume(controls, work):
    """Begin a stretch of steps with the current Jacobian in ``work``: Newton's tolerance,
    and nothing kept of an earlier stretch (method auto hands steps to Radau mid-run)."""
    memory = work.memory[0]
    memory.newton_tolerance = max(10.0 * EPS / controls.rtol, min(0.03, math.sqrt(controls.rtol)))
    memory.lu_valid = False
    memory.h_abs_old = -1.0
    memory.error_norm_old = -1.0
    memory.has_dense = False


@inlined
def evaluate_jacobian(model, params, t, y, f, work, stats):
    """The Jacobian at (t, y), f = f(t, y), into ``work.jacobian``, its block split into
    the memory, marked current and counted."""
    memory = work.memory[0]
    memory.split = jacobian(model, params, t, y, f, work.jacobian, work.scratch, work.column)
    memory.current_jacobian = True
    stats[STAT_NJEV] += 1
    stats[STAT_NFEV] += N_READ


@kernel
def jacobian(model, params, t, y, f, out, scratch, column):
    """Forward-difference Jacobian df/dy into ``out`` (n, n); ``N_READ`` evaluations.

    The columns from ``N_READ`` on are zero (no rate reads those components). Returns the
    block split for the LU: ``N_DYNAMIC`` when the dynamics' rows are zero in the driven
    columns, as ``kernels.layout`` states, else 0 (a plain LU of the whole matrix).
    """
    n = y.shape[0]
    for j in range(n):
        scratch[j] = y[j]
    for j in range(N_READ, n):
        for i in range(n):
            out[i, j] = 0.0
    for j in range(N_READ):
        step = SQRT_EPS * max(abs(y[j]), 1e-5)
        scratch[j] = y[j] + step
        inverse_step = 1.0 / (scratch[j] - y[j])
        rhs(model, t, scratch, params, column)
        for i in range(n):
            out[i, j] = (column[i] - f[i]) * inverse_step
        scratch[j] = y[j]
    for j in range(N_DYNAMIC, N_READ):
        for i in range(N_DYNAMIC):
            if out[i, j] != 0.0:
                return 0
    return N_DYNAMIC


@inlined
def factor_systems(h, jac, lu_real, pivots_real, lu_complex, pivots_complex, split):
    """LU of MU_REAL/h I - J and MU_COMPLEX/h I - J, block lower triangular after row
    ``split`` (``_linalg.block_factor``); False if either is singular."""
    n = jac.shape[0]
    real_shift = MU_REAL / h
    complex_shift = MU_COMPLEX / h
    for i in range(n):
        for j in range(n):
            lu_real[i, j] = -jac[i, j]
            lu_complex[i, j] = -jac[i, j]
        lu_real[i, i] += real_shift
        lu_complex[i, i] += complex_shift
    ok_real = block_factor(lu_real, pivots_real, split)
    ok_complex = block_factor(lu_complex, pivots_complex, split)
    return ok_real and ok_complex


@inlined
def solve_collocation(
    model,
    params,
    t,
    y,
    h,
    stages,
    weights,
    tolerance,
    lu_real,
    pivots_real,
    lu_complex,
    pivots_complex,
    split,
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
        block_solve(lu_real, pivots_real, real_rhs, split)
        block_solve(lu_complex, pivots_complex, complex_rhs, split)
        total = 0.0
        for j in range(n):
            total += (real_rhs[j] * weights[j]) ** 2
            total += (complex_rhs[j].real * weights[j]) ** 2
            total += (complex_rhs[j].imag * weights[j]) ** 2
        norm = math.sqrt(total / (3 * n))
        if norm_old >= 0.0:
            rate = norm / norm_old
        if rate >= 0.0 and (
            rate >= 1.0 or rate ** (NEWTON_MAXITER - k) / (1.0 - rate) * norm > tolerance
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
        if norm == 0.0 or (rate >= 0.0 and rate / (1.0 - rate) * norm < tolerance):
            converged = True
            break
        norm_old = norm
    return converged, iterations, rate


@inlined
def predict_factor(h_abs, h_abs_old, error_norm, error_norm_old):
    """Gustafsson's predictive step-size factor (as SciPy's Radau)."""
    if error_norm_old < 0.0 or h_abs_old < 0.0 or error_norm == 0.0:
        multiplier = 1.0
    else:
        multiplier = h_abs / h_abs_old * (error_norm_old / error_norm) ** 0.25
    if error_norm == 0.0:
        return MAX_FACTOR
    return min(1.0, multiplier) * error_norm**-0.25


@inlined
def newton(model, params, t, y, f, h, controls, work, stats):
    """Solve the collocation system of the step [t, t + h]: predict, factor if the LU
    is stale, iterate; on divergence with an old Jacobian, evaluate it and retry once.

    Returns (converged, iterations, rate) of the last Newton iteration.
    """
    memory = work.memory[0]
    for j in range(y.shape[0]):
        work.weights[j] = 1.0 / (controls.atol + abs(y[j]) * controls.rtol)
    converged = False
    iterations = 0
    rate = -1.0
    while True:  # at most twice: the retry with a new Jacobian (one inlined prediction)
        predict(memory, work.dense, work.y_previous, t, h, y, work.collocation, work.scratch)
        if not memory.lu_valid or memory.h_lu != h:
            factored = factor_systems(
                h,
                work.jacobian,
                work.lu_real,
                work.pivots_real,
                work.lu_complex,
                work.pivots_complex,
                memory.split,
            )
            stats[STAT_NLU] += 2
            memory.lu_valid = factored
            memory.h_lu = h
            if not factored:
                break
        converged, iterations, rate = solve_collocation(
            model,
            params,
            t,
            y,
            h,
            work.collocation,
            work.weights,
            memory.newton_tolerance,
            work.lu_real,
            work.pivots_real,
            work.lu_complex,
            work.pivots_complex,
            memory.split,
            work.transformed,
            work.stage_rates,
            work.scratch,
            work.real_rhs,
            work.complex_rhs,
        )
        stats[STAT_NFEV] += 3 * iterations
        if converged or memory.current_jacobian:
            break
        evaluate_jacobian(model, params, t, y, f, work, stats)
        memory.lu_valid = False
    return converged, iterations, rate


@inlined
def error_norm(model, params, t, y, f, y_new, h, rejected, controls, work, stats):
    """``y_new`` = y + Z_3 and the scaled norm of the embedded error estimate
    (Hairer & Wanner IV.8 (8.20), filtered by (MU_REAL/h I - J)^-1); after a rejection
    a norm above 1 is re-estimated with one more evaluation (8.21)."""
    rtol = controls.rtol
    atol = controls.atol
    collocation = work.collocation
    correction = work.column
    estimate = work.real_rhs
    n = y.shape[0]
    for j in range(n):
        y_new[j] = y[j] + collocation[2, j]
        correction[j] = (
            E[0] * collocation[0, j] + E[1] * collocation[1, j] + E[2] * collocation[2, j]
        ) / h
        estimate[j] = f[j] + correction[j]
    split = work.memory[0].split
    block_solve(work.lu_real, work.pivots_real, estimate, split)
    norm = rms_scaled(estimate, y, y_new, rtol, atol)
    if rejected and norm > 1.0:
        for j in range(n):
            work.scratch[j] = y[j] + estimate[j]
        rhs(model, t, work.scratch, params, work.point)
        stats[STAT_NFEV] += 1
        for j in range(n):
            estimate[j] = work.point[j] + correction[j]
        block_solve(work.lu_real, work.pivots_real, estimate, split)
        norm = rms_scaled(estimate, y, y_new, rtol, atol)
    return norm


@inlined
def attempt(model, params, t, y, f, h, t_end, controls, work, y_new, f_new, stats):
    """Step from (t, y) with f = f(t, y), trying h [s] first: halve h when Newton fails,
    shrink it by the predictive controller when the error norm exceeds 1; the step
    never passes ``t_end``. A step accepted after a rejection is not followed by a larger
    one (as Hairer's RADAU5 and DOP853 do, and SciPy's Radau does not).

    Returns (status, h_taken, h_next, rhs status, normal force [N] at y_new); ``y_new`` and
    ``f_new`` = f(t + h_taken, y_new).
    """
    memory = work.memory[0]
    min_step = smallest_step(t)
    status = STATUS_SUCCESS
    rejected = False
    iterations = 0
    rate = -1.0
    norm = 0.0
    safety = SAFETY
    factor = 1.0
    h_try = h
    while True:
        if h < min_step:
            status = STATUS_STEP_TOO_SMALL
            break
        h_try = min(h, t_end - t)
        converged, iterations, rate = newton(model, params, t, y, f, h_try, controls, work, stats)
        if not converged:
            h = 0.5 * h_try
            memory.lu_valid = False
            stats[STAT_REJECTED] += 1
            rejected = True
            continue
        norm = error_norm(model, params, t, y, f, y_new, h_try, rejected, controls, work, stats)
        safety = SAFETY * (2 * NEWTON_MAXITER + 1) / (2 * NEWTON_MAXITER + iterations)
        # the controller's factor, for a rejection and for the next step alike (inlined once)
        factor = predict_factor(h_try, memory.h_abs_old, norm, memory.error_norm_old)
        if not controls.adaptive:
            break
        if not math.isfinite(norm) or norm > 1.0:
            if not math.isfinite(norm):
                factor = MIN_FACTOR
            h = h_try * max(MIN_FACTOR, safety * factor)
            memory.lu_valid = False
            stats[STAT_REJECTED] += 1
            rejected = True
            continue
        break
    if status != STATUS_SUCCESS:
        return status, h_try, h, RHS_OK, math.nan
    # the next step size, and whether the Jacobian is evaluated anew (slow Newton
    # convergence) or the LU factors are kept (a small change of h)
    recompute_jacobian = iterations > 2 and rate > JACOBIAN_RATE
    factor = min(MAX_FACTOR, safety * factor)
    if rejected:
        factor = min(1.0, factor)
    if not controls.adaptive:
        factor = 1.0
    elif not recompute_jacobian and factor < 1.2:
        factor = 1.0
    else:
        memory.lu_valid = False
    code, normal_force = rhs(model, t + h_try, y_new, params, f_new)
    stats[STAT_NFEV] += 1
    if recompute_jacobian:
        evaluate_jacobian(model, params, t + h_try, y_new, f_new, work, stats)
    else:
        memory.current_jacobian = False
    memory.h_abs_old = h_try
    memory.error_norm_old = norm
    return status, h_try, (h_try * factor if controls.adaptive else h), code, normal_force


@inlined
def dense(model, params, t, y, y_new, h, work, stats):
    """Collocation-polynomial coefficients Q = Z^T P of the accepted step [t, t + h] into
    ``work.dense``, kept with the step for the next step's Newton guess."""
    collocation = work.collocation
    dense = work.dense
    for j in range(y.shape[0]):
        for k in range(3):
            dense[k, j] = (
                collocation[0, j] * P[0, k]
                + collocation[1, j] * P[1, k]
                + collocation[2, j] * P[2, k]
            )
    memory = work.memory[0]
    memory.has_dense = True
    memory.t_previous = t
    memory.h_previous = h
    for j in range(y.shape[0]):  # a loop: a GPU thread runs it too (``batch_cuda``)
        work.y_previous[j] = y[j]


@inlined
def predict(memory, dense, y_previous, t, h, y, stages, scratch):
    """Newton's starting guess ``stages`` (3, n): the last step's collocation polynomial
    extrapolated to the new stage times, minus y (zeros before the first step)."""
    if not memory.has_dense:
        stages[:, :] = 0.0
        return
    for i in range(3):
        x = (t + C[i] * h - memory.t_previous) / memory.h_previous
        interpolate(dense, y_previous, x, scratch)
        for j in range(y.shape[0]):
            stages[i, j] = scratch[j] - y[j]


@inlined
def interpolate(dense, y_old, x, out):
    """State at the fraction x of the last accepted step, which began at y_old:
    y_old + Σ_k Q_k x^(k+1), Q = ``dense`` (``work.dense``)."""
    for j in range(y_old.shape[0]):
        out[j] = y_old[j] + x * (dense[0, j] + x * (dense[1, j] + x * dense[2, j]))
