"""Compiled batch driver for sweeps: many runs in one call, reduced on the fly.

``run_batch`` integrates each point with the shared loop ``driver.integrate`` and
keeps only the sweep's result fields, so a batch never holds trajectories: one
sample buffer and one crossing buffer per call are reused point after point. The
compiled function releases the GIL (``nogil``), so threads of one process run
batches in parallel without Python per step.

The reduction is the one of ``simulate(...).summary()`` and
``analysis.reversal_times(time, spin, band, crossings)`` on the same sample
times, with each point's own band; the sweep tests check the two agree point for point.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from celtstone.kernels.layout import N_STATE, Y_N, Y_OMEGA
from celtstone.kernels.system import energy, spin_and_normal_force
from celtstone.solvers.codes import METHODS, STATUS_SUCCESS
from celtstone.solvers.driver import integrate

__all__ = ["FIELDS", "run_batch"]

# columns of the result array
F_FIRST_REVERSAL = 0  # first reversal time [s], NaN if none
F_REVERSALS = 1  # number of reversals [1]
F_FINAL_SPIN = 2  # spin ω·n at t_end [rad/s], NaN if the run stopped early
F_ENERGY_LOST = 3  # E(0) - E(t_end) [J], NaN if the run stopped early
F_MAX_TILT = 4  # largest angle between n and body axis 3 over the samples [rad]
F_MIN_NORMAL_FORCE = 5  # smallest normal force [N] (steps and samples; 0 at lift-off)
F_T_STOP = 6  # time the run stopped [s]
F_STATUS = 7  # solver status code (``solvers.codes``)
N_FIELDS = 8

FIELDS = (
    "first_reversal_time",
    "n_reversals",
    "final_spin",
    "energy_lost",
    "max_tilt",
    "min_normal_force",
    "t_stop",
    "status",
)


@njit(cache=True, nogil=True, error_model="numpy")
def _last_zero_before(times, spins, index, crossings, n_stored):
    """Last spin zero at or before times[index]: a stored exact crossing, else the
    linear interpolant of the samples (as ``analysis.reversals._last_zero_before``)."""
    limit = times[index]
    best = -1.0
    found = False
    for k in range(n_stored):
        if crossings[k] <= limit:
            best = crossings[k]
            found = True
        else:
            break
    if found:
        return best
    k = index - 1
    while k >= 0:
        a = math.copysign(1.0, spins[k]) if spins[k] != 0.0 else 0.0
        b = math.copysign(1.0, spins[k + 1]) if spins[k + 1] != 0.0 else 0.0
        if a * b <= 0.0:
            break
        k -= 1
    if k < 0:
        return times[0]
    if spins[k] == spins[k + 1]:
        return times[k]
    fraction = spins[k] / (spins[k] - spins[k + 1])
    return times[k] + fraction * (times[k + 1] - times[k])


@njit(cache=True, nogil=True, error_model="numpy")
def _batch(
    model,
    method,
    params,
    y0,
    t_end,
    rtol,
    atol,
    max_steps,
    sample_times,
    bands,
    crossing_capacity,
    results,
):
    n_points = params.shape[0]
    n_times = sample_times.shape[0]
    samples = np.zeros((n_times, N_STATE))
    spins = np.zeros(n_times)
    crossings = np.zeros(crossing_capacity)
    stats = np.zeros(8, dtype=np.int64)
    work = np.zeros(N_STATE)
    final_state = np.zeros(N_STATE)
    for i in range(n_points):
        p = params[i]
        status, n_samples, n_crossings, t_stop, min_normal, _ = integrate(
            model,
            method,
            p,
            y0[i],
            t_end,
            rtol,
            atol,
            0.0,
            0.0,
            max_steps,
            True,
            sample_times,
            samples,
            crossings,
            stats,
            0.0,  # no capture event: the sweep runs the sliding or rolling model
            final_state,
        )
        n_stored = min(n_crossings, crossing_capacity)
        max_tilt = 0.0
        for j in range(n_samples):
            y = samples[j]
            spins[j] = (
                y[Y_OMEGA] * y[Y_N] + y[Y_OMEGA + 1] * y[Y_N + 1] + y[Y_OMEGA + 2] * y[Y_N + 2]
            )
            norm = math.sqrt(y[Y_N] ** 2 + y[Y_N + 1] ** 2 + y[Y_N + 2] ** 2)
            tilt = math.acos(min(1.0, max(-1.0, y[Y_N + 2] / norm)))
            max_tilt = max(max_tilt, tilt)
            _, normal_force, _ = spin_and_normal_force(model, y, p, work)
            if normal_force < min_normal:  # fmin: a NaN sample does not win
                min_normal = normal_force
        # reversals with hysteresis (analysis.reversals.reversal_times)
        threshold = bands[i]
        sense = 0
        n_reversals = 0
        first = np.nan
        for j in range(n_samples):
            if abs(spins[j]) > threshold:
                current = 1 if spins[j] > 0.0 else -1
                if sense != 0 and current != sense:
                    if n_reversals == 0:
                        first = _last_zero_before(sample_times, spins, j, crossings, n_stored)
                    n_reversals += 1
                sense = current
        final_spin = np.nan
        energy_lost = np.nan
        if status == STATUS_SUCCESS and n_samples > 0:
            final_spin = spins[n_samples - 1]
            energy_lost = energy(model, y0[i], p) - energy(model, samples[n_samples - 1], p)
        results[i, F_FIRST_REVERSAL] = first
        results[i, F_REVERSALS] = n_reversals
        results[i, F_FINAL_SPIN] = final_spin
        results[i, F_ENERGY_LOST] = energy_lost
        results[i, F_MAX_TILT] = max_tilt if n_samples > 0 else np.nan
        results[i, F_MIN_NORMAL_FORCE] = min_normal
        results[i, F_T_STOP] = t_stop
        results[i, F_STATUS] = status


def run_batch(
    model: int,
    method_name: str,
    params: np.ndarray,
    y0: np.ndarray,
    t_end: float,
    *,
    rtol: float,
    atol: float,
    sample_times: np.ndarray,
    reversal_bands: np.ndarray,
    max_steps: int = 20_000_000,
    max_crossings: int = 100_000,
) -> np.ndarray:
    """Integrate every row of ``params``/``y0`` and return their result fields.

    Parameters
    ----------
    model : kernel model code (``kernels.layout``)
    method_name : a key of ``solvers.METHODS``
    params : flat kernel parameters, shape (k, N_PARAMS)
    y0 : initial states, shape (k, N_STATE)
    t_end : duration [s]
    rtol, atol : local error tolerances
    sample_times : times [s] at which spin, tilt and normal force are sampled, from 0
        to ``t_end``, increasing
    reversal_bands : half-width of each point's hysteresis band of the spin [rad/s],
        shape (k,)
    max_steps : step limit of each run
    max_crossings : spin zero crossings stored per run for timing reversals

    Returns
    -------
    numpy.ndarray
        shape (k, len(FIELDS)), float64, columns in the order of ``FIELDS``
    """
    params = np.ascontiguousarray(params, dtype=np.float64)
    y0 = np.ascontiguousarray(y0, dtype=np.float64)
    results = np.empty((params.shape[0], N_FIELDS))
    _batch(
        int(model),
        METHODS[method_name],
        params,
        y0,
        float(t_end),
        float(rtol),
        float(atol),
        int(max_steps),
        np.ascontiguousarray(sample_times, dtype=np.float64),
        np.ascontiguousarray(np.broadcast_to(reversal_bands, params.shape[:1]), dtype=np.float64),
        int(max_crossings),
        results,
    )
    return results
