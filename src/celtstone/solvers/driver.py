"""The compiled integration loop shared by both methods: stepping, sampling, events.

``integrate`` runs entirely in numba: no Python per step. After every accepted step
it fills the output samples that fall inside the step from the dense output, locates
every sign change of the spin ω·n (Illinois root finding on the interpolant), tracks
the minimum normal force, and stops at lift-off (N = 0, located the same way), at a
phase change of the hybrid contact (``system.phase_value`` falling from >= 0 to < 0),
at a singular or off-shape right-hand side, or on integrator failure.
"""

from __future__ import annotations

import math

import numpy as np

from celtstone.kernels._jit import kernel
from celtstone.kernels.layout import (
    MODEL_SLIDING,
    MODEL_STICK,
    RHS_NON_CONVEX,
    RHS_OFF_SHAPE,
    RHS_OK,
    Y_N,
    Y_OMEGA,
)
from celtstone.kernels.system import phase_value, rhs, spin_and_normal_force
from celtstone.solvers import _dop853 as dop
from celtstone.solvers import _radau as rad
from celtstone.solvers._linalg import lu_solve
from celtstone.solvers.codes import (
    METHOD_DOP853,
    STAT_SAMPLES_WRITTEN,
    STATUS_LIFT_OFF,
    STATUS_MAX_STEPS,
    STATUS_NON_CONVEX,
    STATUS_NOT_FINITE,
    STATUS_OFF_SHAPE,
    STATUS_PHASE_CHANGE,
    STATUS_SINGULAR,
    STATUS_STEP_TOO_SMALL,
    STATUS_SUCCESS,
)

ROOT_TOLERANCE = 1e-12  # s, event location
EVENT_SUBDIVISIONS = 4  # spin sign checks per step, to catch two crossings in one step
EPS = float(np.finfo(np.float64).eps)


@kernel
def rhs_failure(code):
    """Run status for a right-hand-side status code other than ``RHS_OK``."""
    if code == RHS_OFF_SHAPE:
        return STATUS_OFF_SHAPE
    if code == RHS_NON_CONVEX:
        return STATUS_NON_CONVEX
    return STATUS_SINGULAR


@kernel
def rms_scaled(values, reference, other, rtol, atol):
    """RMS norm of values / (atol + max(|reference|, |other|) rtol)."""
    total = 0.0
    for j in range(values.shape[0]):
        scale = atol + max(abs(reference[j]), abs(other[j])) * rtol
        total += (values[j] / scale) ** 2
    return math.sqrt(total / values.shape[0])


@kernel
def initial_step(model, params, y0, f0, order, rtol, atol, scratch, f1):
    """Hairer's starting step-size heuristic (Solving ODEs I, sec. II.4)."""
    d0 = rms_scaled(y0, y0, y0, rtol, atol)
    d1 = rms_scaled(f0, y0, y0, rtol, atol)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    for j in range(y0.shape[0]):
        scratch[j] = y0[j] + h0 * f0[j]
    rhs(model, h0, scratch, params, f1)
    for j in range(y0.shape[0]):
        f1[j] -= f0[j]
    d2 = rms_scaled(f1, y0, y0, rtol, atol) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (order + 1))
    return min(100.0 * h0, h1)


@kernel
def interpolate(method, dense, y_old, x, out):
    """State at the fraction x of the last accepted step."""
    if method == METHOD_DOP853:
        dop.dop853_interpolate(dense, y_old, x, out)
    else:
        rad.radau_interpolate(dense, y_old, x, out)


@kernel
def spin_of(y):
    """ω · n of a state [rad/s]."""
    return y[Y_OMEGA] * y[Y_N] + y[Y_OMEGA + 1] * y[Y_N + 1] + y[Y_OMEGA + 2] * y[Y_N + 2]


EVENT_SPIN = 0
EVENT_NORMAL_FORCE = 1
EVENT_PHASE = 2


@kernel
def event_value(kind, model, params, method, dense, y_old, x, point, work, capture_speed):
    """Spin (kind 0), normal force (kind 1) or phase value (kind 2) at step fraction x."""
    interpolate(method, dense, y_old, x, point)
    if kind == EVENT_SPIN:
        return spin_of(point)
    if kind == EVENT_PHASE:
        return phase_value(model, point, params, capture_speed)
    _, normal_force, _ = spin_and_normal_force(model, point, params, work)
    return normal_force


@kernel
def locate_root(
    kind, model, params, method, dense, y_old, a, b, ga, gb, h, point, work, capture_speed
):
    """Illinois (modified regula falsi) root of an event function on [a, b] ⊂ [0, 1].

    A phase event returns the end of the bracket where the phase value is < 0.
    """
    tolerance = ROOT_TOLERANCE / max(abs(h), 1e-300)
    side = 0
    x = b
    for _ in range(200):
        if abs(b - a) <= tolerance:
            break
        x = (a * gb - b * ga) / (gb - ga)
        if not (a < x < b):
            x = 0.5 * (a + b)
        gx = event_value(kind, model, params, method, dense, y_old, x, point, work, capture_speed)
        if gx == 0.0 and kind != EVENT_PHASE:
            return x
        # a phase event goes from ga >= 0 to gb < 0: zero counts on the side of a
        same_side = (gx >= 0.0) if kind == EVENT_PHASE else ((gx > 0.0) == (ga > 0.0))
        if same_side:
            a, ga = x, gx
            if side == -1:
                gb *= 0.5
            side = -1
        else:
            b, gb = x, gx
            if side == 1:
                ga *= 0.5
            side = 1
    if kind == EVENT_PHASE:
        return b  # on the new phase's side, so that the restart does not stop at once
    return b if abs(gb) <= abs(ga) else a


@kernel
def _fill_samples(method, dense, y_old, t_old, h, t_limit, sample_times, samples, n_samples, y_end):
    """Fill samples with times in (t_old, t_limit]; returns the new count."""
    while n_samples < sample_times.shape[0] and sample_times[n_samples] <= t_limit:
        time = sample_times[n_samples]
        if time == t_old + h:
            samples[n_samples, :] = y_end
        else:
            interpolate(method, dense, y_old, (time - t_old) / h, samples[n_samples])
        n_samples += 1
    return n_samples


@kernel
def integrate(
    model,
    method,
    params,
    y0,
    t_end,
    rtol,
    atol,
    first_step,
    max_step,
    max_steps,
    adaptive,
    sample_times,
    samples,
    crossings,
    stats,
    capture_speed,
    final_state,
):
    """Integrate from t = 0 to ``t_end``; see the module docstring.

    Returns (status, n_samples, n_crossings, t_stop, min_normal_force,
    t_min_normal_force); ``stats`` receives nfev, njev, nlu, accepted, rejected, and in
    slot ``STAT_SAMPLES_WRITTEN``, after every step, the samples written so far;
    ``final_state`` the state at ``t_stop``. ``capture_speed`` [m/s] > 0 arms the
    slip-capture event of the sliding model (``system.phase_value``).
    """
    n = y0.shape[0]
    y = y0.copy()
    y_new = np.empty(n)
    y_old = np.empty(n)
    f = np.empty(n)
    f_new = np.empty(n)
    scratch = np.empty(n)
    point = np.empty(n)
    work = np.empty(n)
    stages = np.zeros((dop.N_STAGES_EXTENDED, n))
    dense = np.zeros((dop.DENSE_ROWS, n))
    # Radau state
    jac = np.zeros((n, n))
    lu_real = np.zeros((n, n))
    lu_complex = np.zeros((n, n), dtype=np.complex128)
    pivots_real = np.zeros(n, dtype=np.int64)
    pivots_complex = np.zeros(n, dtype=np.int64)
    collocation = np.zeros((3, n))
    work_w = np.zeros((3, n))
    work_f = np.zeros((3, n))
    real_rhs = np.zeros(n)
    complex_rhs = np.zeros(n, dtype=np.complex128)
    scale = np.empty(n)

    nfev = 0
    njev = 0
    nlu = 0
    n_accepted = 0
    n_rejected = 0
    n_samples = 0
    n_crossings = 0
    t = 0.0

    code = rhs(model, t, y, params, f)
    nfev += 1
    spin_old, normal_old, _ = spin_and_normal_force(model, y, params, work)
    has_phases = model == MODEL_STICK or (model == MODEL_SLIDING and capture_speed > 0.0)
    phase_old = phase_value(model, y, params, capture_speed) if has_phases else 1.0
    final_state[:] = y
    min_normal = normal_old
    t_min_normal = 0.0
    while n_samples < sample_times.shape[0] and sample_times[n_samples] <= 0.0:
        samples[n_samples, :] = y
        n_samples += 1
    result = STATUS_SUCCESS
    for j in range(n):
        if not math.isfinite(y[j]) or not math.isfinite(f[j]):
            result = STATUS_NOT_FINITE
    if code != RHS_OK:
        result = rhs_failure(code)
    elif normal_old < 0.0:
        result = STATUS_LIFT_OFF
    if result != STATUS_SUCCESS:
        stats[0] = nfev
        return result, n_samples, 0, 0.0, min_normal, t_min_normal

    order = dop.ERROR_ORDER if method == METHOD_DOP853 else rad.ERROR_ORDER
    if first_step > 0.0:
        h = first_step
    else:
        h = initial_step(model, params, y, f, order, rtol, atol, scratch, f_new)
        nfev += 1
    if max_step > 0.0:
        h = min(h, max_step)

    newton_tol = max(10.0 * EPS / rtol, min(0.03, math.sqrt(rtol)))
    has_dense = False
    h_previous = 0.0
    t_previous = 0.0
    y_previous = np.empty(n)
    h_abs_old = -1.0
    error_norm_old = -1.0
    current_jac = False
    lu_valid = False
    h_lu = 0.0
    if method != METHOD_DOP853:
        rad.jacobian(model, params, t, y, f, jac, scratch, work)
        njev += 1
        nfev += n
        current_jac = True

    steps = 0
    while t < t_end:
        if steps >= max_steps:
            result = STATUS_MAX_STEPS
            break
        steps += 1
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        rejected = False
        h_next = h
        h_try = h
        if method == METHOD_DOP853:
            while True:
                if h < min_step:
                    result = STATUS_STEP_TOO_SMALL
                    break
                h_try = min(h, t_end - t)
                stages[0, :] = f
                error = dop.dop853_attempt(
                    model, params, t, y, h_try, rtol, atol, stages, y_new, scratch
                )
                nfev += dop.N_STAGES
                if not adaptive:
                    h_next = h
                    break
                if not math.isfinite(error):
                    h = h_try * 0.2
                    n_rejected += 1
                    rejected = True
                    continue
                if error < 1.0:
                    factor = 10.0 if error == 0.0 else min(10.0, 0.9 * error ** (-1.0 / 8.0))
                    if rejected:
                        factor = min(1.0, factor)
                    h_next = h_try * factor
                    break
                h = h_try * max(0.2, 0.9 * error ** (-1.0 / 8.0))
                n_rejected += 1
                rejected = True
            if result != STATUS_SUCCESS:
                break
            dop.dop853_dense(model, params, t, y, y_new, h_try, stages, dense, scratch)
            nfev += dop.N_STAGES_EXTENDED - dop.N_STAGES - 1
            f_new[:] = stages[dop.N_STAGES]
        else:
            converged = False
            iterations = 0
            rate = -1.0
            error_norm = 0.0
            safety = 0.9
            while True:
                if h < min_step:
                    result = STATUS_STEP_TOO_SMALL
                    break
                h_try = min(h, t_end - t)
                rad.radau_predict(
                    has_dense,
                    dense,
                    y_previous,
                    t_previous,
                    h_previous,
                    t,
                    h_try,
                    y,
                    collocation,
                    scratch,
                )
                for j in range(n):
                    scale[j] = atol + abs(y[j]) * rtol
                converged = False
                while not converged:
                    if not lu_valid or h_lu != h_try:
                        factored = rad.factor_systems(
                            h_try, jac, lu_real, pivots_real, lu_complex, pivots_complex
                        )
                        nlu += 2
                        lu_valid = factored
                        h_lu = h_try
                        if not factored:
                            break
                    converged, iterations, rate = rad.solve_collocation(
                        model,
                        params,
                        t,
                        y,
                        h_try,
                        collocation,
                        scale,
                        newton_tol,
                        lu_real,
                        pivots_real,
                        lu_complex,
                        pivots_complex,
                        work_w,
                        work_f,
                        scratch,
                        real_rhs,
                        complex_rhs,
                    )
                    nfev += 3 * iterations
                    if not converged:
                        if current_jac:
                            break
                        rad.jacobian(model, params, t, y, f, jac, scratch, work)
                        njev += 1
                        nfev += n
                        current_jac = True
                        lu_valid = False
                        rad.radau_predict(
                            has_dense,
                            dense,
                            y_previous,
                            t_previous,
                            h_previous,
                            t,
                            h_try,
                            y,
                            collocation,
                            scratch,
                        )
                if not converged:
                    h = 0.5 * h_try
                    lu_valid = False
                    n_rejected += 1
                    rejected = True
                    continue
                for j in range(n):
                    y_new[j] = y[j] + collocation[2, j]
                    correction = (
                        rad.E[0] * collocation[0, j]
                        + rad.E[1] * collocation[1, j]
                        + rad.E[2] * collocation[2, j]
                    ) / h_try
                    work[j] = correction
                    real_rhs[j] = f[j] + correction
                lu_solve(lu_real, pivots_real, real_rhs)
                error_norm = rms_scaled(real_rhs, y, y_new, rtol, atol)
                safety = 0.9 * (2 * rad.NEWTON_MAXITER + 1) / (2 * rad.NEWTON_MAXITER + iterations)
                if rejected and error_norm > 1.0:
                    for j in range(n):
                        scratch[j] = y[j] + real_rhs[j]
                    rhs(model, t, scratch, params, point)
                    nfev += 1
                    for j in range(n):
                        real_rhs[j] = point[j] + work[j]
                    lu_solve(lu_real, pivots_real, real_rhs)
                    error_norm = rms_scaled(real_rhs, y, y_new, rtol, atol)
                if not adaptive:
                    break
                if not math.isfinite(error_norm) or error_norm > 1.0:
                    factor = rad.MIN_FACTOR
                    if math.isfinite(error_norm):
                        factor = rad.predict_factor(h_try, h_abs_old, error_norm, error_norm_old)
                    h = h_try * max(rad.MIN_FACTOR, safety * factor)
                    lu_valid = False
                    n_rejected += 1
                    rejected = True
                    continue
                break
            if result != STATUS_SUCCESS:
                break
            recompute_jac = iterations > 2 and rate > 1e-3
            factor = rad.predict_factor(h_try, h_abs_old, error_norm, error_norm_old)
            factor = min(rad.MAX_FACTOR, safety * factor)
            if not adaptive:
                factor = 1.0
            elif not recompute_jac and factor < 1.2:
                factor = 1.0
            else:
                lu_valid = False
            rhs(model, t + h_try, y_new, params, f_new)
            nfev += 1
            if recompute_jac:
                rad.jacobian(model, params, t + h_try, y_new, f_new, jac, scratch, work)
                njev += 1
                nfev += n
                current_jac = True
            else:
                current_jac = False
            h_abs_old = h_try
            error_norm_old = error_norm
            h_next = h_try * factor if adaptive else h
            rad.radau_dense(collocation, dense)
            has_dense = True
            t_previous = t
            h_previous = h_try
            y_previous[:] = y

        # the step [t, t + h_try] is accepted
        finite = True
        for j in range(n):
            if not math.isfinite(y_new[j]):
                finite = False
        if not finite:
            result = STATUS_NOT_FINITE
            break
        t_old = t
        t_new = t_end if h_try == t_end - t else t + h_try
        y_old[:] = y
        n_accepted += 1

        spin_new, normal_new, code = spin_and_normal_force(model, y_new, params, work)
        nfev += 1
        if code != RHS_OK:
            result = rhs_failure(code)
            break
        t_limit = t_new
        if normal_new < 0.0:
            root = locate_root(
                EVENT_NORMAL_FORCE,
                model,
                params,
                method,
                dense,
                y_old,
                0.0,
                1.0,
                normal_old,
                normal_new,
                h_try,
                point,
                work,
                capture_speed,
            )
            t_limit = t_old + root * h_try
            result = STATUS_LIFT_OFF
        x_limit = (t_limit - t_old) / h_try
        # phase change: the phase value falls from >= 0 to < 0 inside (t_old, t_limit]
        phase_new = 1.0
        phase_b = 1.0
        if has_phases:
            x_a = 0.0
            phase_a = phase_old
            for k in range(1, EVENT_SUBDIVISIONS + 1):
                x_b = x_limit * k / EVENT_SUBDIVISIONS
                phase_b = event_value(
                    EVENT_PHASE,
                    model,
                    params,
                    method,
                    dense,
                    y_old,
                    x_b,
                    point,
                    work,
                    capture_speed,
                )
                if phase_a >= 0.0 > phase_b:
                    root = locate_root(
                        EVENT_PHASE,
                        model,
                        params,
                        method,
                        dense,
                        y_old,
                        x_a,
                        x_b,
                        phase_a,
                        phase_b,
                        h_try,
                        point,
                        work,
                        capture_speed,
                    )
                    x_limit = root
                    t_limit = t_old + root * h_try
                    result = STATUS_PHASE_CHANGE
                    break
                x_a = x_b
                phase_a = phase_b
            phase_new = phase_a if result == STATUS_PHASE_CHANGE else phase_b
        # spin sign changes inside (t_old, t_limit]; none in stick, where ω·n = 0 is held
        x_a = 0.0
        spin_a = spin_old
        for k in range(1, EVENT_SUBDIVISIONS + 1 if model != MODEL_STICK else 1):
            x_b = x_limit * k / EVENT_SUBDIVISIONS
            if k == EVENT_SUBDIVISIONS and result == STATUS_SUCCESS:
                spin_b = spin_new
            else:
                spin_b = event_value(
                    EVENT_SPIN, model, params, method, dense, y_old, x_b, point, work, capture_speed
                )
            if (spin_a < 0.0 < spin_b) or (spin_b < 0.0 < spin_a) or (spin_b == 0.0 != spin_a):
                if spin_b == 0.0:
                    root = x_b
                else:
                    root = locate_root(
                        EVENT_SPIN,
                        model,
                        params,
                        method,
                        dense,
                        y_old,
                        x_a,
                        x_b,
                        spin_a,
                        spin_b,
                        h_try,
                        point,
                        work,
                        capture_speed,
                    )
                if n_crossings < crossings.shape[0]:
                    crossings[n_crossings] = t_old + root * h_try
                n_crossings += 1
            x_a = x_b
            spin_a = spin_b
        n_samples = _fill_samples(
            method, dense, y_old, t_old, h_try, t_limit, sample_times, samples, n_samples, y_new
        )
        stats[STAT_SAMPLES_WRITTEN] = n_samples  # read while the loop runs (progress)
        if result == STATUS_LIFT_OFF or result == STATUS_PHASE_CHANGE:
            t = t_limit
            if x_limit >= 1.0:
                final_state[:] = y_new
            else:
                interpolate(method, dense, y_old, x_limit, final_state)
            if result == STATUS_LIFT_OFF:
                min_normal = min(min_normal, 0.0)  # N reaches zero at the located root
                t_min_normal = t_limit
            else:
                normal_limit = spin_and_normal_force(model, final_state, params, work)[1]
                if normal_limit < min_normal:
                    min_normal = normal_limit
                    t_min_normal = t_limit
            break
        if normal_new < min_normal:
            min_normal = normal_new
            t_min_normal = t_new
        y[:] = y_new
        f[:] = f_new
        t = t_new
        spin_old = spin_new
        normal_old = normal_new
        phase_old = phase_new
        h = h_next
        if max_step > 0.0:
            h = min(h, max_step)

    if result != STATUS_LIFT_OFF and result != STATUS_PHASE_CHANGE:
        final_state[:] = y
    stats[0] = nfev
    stats[1] = njev
    stats[2] = nlu
    stats[3] = n_accepted
    stats[4] = n_rejected
    return result, n_samples, n_crossings, t, min_normal, t_min_normal
