"""Compiled batch driver for sweeps: many runs in one call, reduced on the fly.

``run_batch`` integrates each point with the shared loop ``driver.integrate`` and
keeps only the run's outcome record, so a batch never holds trajectories: one
sample buffer and one crossing buffer per call are reused point after point. The
compiled function releases the GIL (``nogil``), so threads of one process run
batches in parallel without Python per step.

The outcomes are declared once, in ``simulation.outcome`` (name, unit, meaning, stored
type, fill value); ``RESULT_FIELDS`` numbers the swept ones into the columns that
``_reduce`` writes. ``_reduce`` is the one reduction of a run's samples: every sweep
point here, and every single run through :func:`reduce_run` (``simulate``), so a sweep
point equals the single run on the same sample times by construction.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from celtstone.kernels._jit import kernel
from celtstone.kernels.layout import N_STATE, Y_N, Y_OMEGA, Y_WORK, ellipse_table_address
from celtstone.kernels.reversal import count_reversals, rocking_average_into
from celtstone.kernels.system import energy
from celtstone.simulation.outcome import OUTCOMES, SWEPT
from celtstone.solvers._events import event_table
from celtstone.solvers._linking import NO_LINK, address_call, link_to
from celtstone.solvers._structures import (
    Controls,
    HybridSettings,
    Output,
    PhaseLog,
    RunEnd,
    new_output,
    new_phase_log,
)
from celtstone.solvers._system import (
    RUN_CODES,
    parameters,
    samples_rhs_link,
    spin_and_normal_force,
)
from celtstone.solvers.codes import METHODS, STATUS_SUCCESS
from celtstone.solvers.driver import call_integrate, integrate_link
from celtstone.solvers.phases import DEFAULT_MAX_PHASES, integrate_links, run_phases

call_run_phases = address_call(run_phases)  # neither loop linked in: see ``solvers._linking``

__all__ = ["COLUMN", "FIELDS", "RESULT_FIELDS", "Points", "ResultField", "reduce_run", "run_batch"]


class ResultField(NamedTuple):
    """A swept outcome (``simulation.outcome.OUTCOMES``) and its column: the store's
    arrays, the in-memory results and the runner's conversion of the result array read
    this row.

    Parameters
    ----------
    name : the outcome's name in the store and the Dataset
    dtype : the stored type: "float64", "int32" (the column's value, converted) or
        "str" (text that the runner makes from the status code, see ``sweep.runner``)
    fill : the value of a point not computed yet
    column : its column in ``run_batch``'s result array (written by ``_reduce``), or
        None for text made from other columns
    """

    name: str
    dtype: str
    fill: float | int | str
    column: int | None


# made by the runner from the status code and t_stop (``codes.stop_message``): no column
_TEXT_ONLY = ("message",)


def _result_fields() -> tuple[ResultField, ...]:
    """The swept outcomes in the store's order, numbered into columns."""
    fields: list[ResultField] = []
    for name in SWEPT:
        column = None if name in _TEXT_ONLY else len([f for f in fields if f.column is not None])
        fields.append(ResultField(name, OUTCOMES[name].dtype, OUTCOMES[name].fill, column))
    return tuple(fields)


RESULT_FIELDS: tuple[ResultField, ...] = _result_fields()

_COLUMNS = {f.name: f.column for f in RESULT_FIELDS if f.column is not None}
# the names of the result array's columns, in column order (numbered 0, 1, ...)
FIELDS = tuple(sorted(_COLUMNS, key=_COLUMNS.__getitem__))
N_FIELDS = len(FIELDS)


ResultColumns = NamedTuple(  # type: ignore[misc]
    "ResultColumns", [(name, int) for name in FIELDS]
)
# typed Any: its fields are the declaration's names, which a type checker cannot read
COLUMN: Any = ResultColumns(*range(N_FIELDS))
"""The column of each outcome in ``run_batch``'s result array, by its name (numba folds
the global to its integers): ``out[COLUMN.spin_final]``; the outcome's unit and meaning
are its ``OUTCOMES`` row."""


@kernel
def _reduce(model, system, y0, finished, reversal, spins, work, out):
    """The outcome record of one run into ``out``: ``finished`` is (its ``RunEnd``, sample
    times [s], sampled states, stored spin zero crossings [s]) as its loop left them, on
    the run's ``system`` (``_system``: its parameter record and the link to its
    right-hand side, which the normal force is evaluated at, as in the run loop; on a GPU
    thread the record itself, ``batch_cuda``). ``reversal`` is (band [rad/s], window [s],
    buffer of the averaged spin, buffer of the first reversal time, buffer of the spin's
    running integral) (``kernels.reversal``); every buffer is the caller's, so that a
    CUDA thread (``batch_cuda``) runs it too.

    Compiled once for every model code, the model a value, for a single run
    (:func:`reduce_run`) and a sweep's loop alike: with the right-hand side at its link,
    what depends on the model here is the energy's velocity alone, where a version per
    model (the code a constant) linked and optimised the right-hand side's code again,
    and numba's inlining copied this function's IR into each caller."""
    params = parameters(system)
    end, sample_times, samples, crossings = finished
    n_samples = end.n_samples
    n_stored = min(end.n_crossings, crossings.shape[0])
    min_normal = end.min_normal_force
    max_tilt = 0.0
    energy_initial = energy(model, y0, params)
    spin_initial = (
        y0[Y_OMEGA] * y0[Y_N] + y0[Y_OMEGA + 1] * y0[Y_N + 1] + y0[Y_OMEGA + 2] * y0[Y_N + 2]
    )
    # against the start, as ``reproduce.cases.summarise``: -np.sign(spin_initial) as numba
    # computes it (a zero keeps its sign, NaN stays NaN), which CUDA code has not
    sense = -(1.0 if spin_initial > 0.0 else (-1.0 if spin_initial < 0.0 else spin_initial))
    peak_reversed = -np.inf
    budget_error = 0.0
    energy_rise = 0.0
    previous = energy_initial
    for j in range(n_samples):
        y = samples[j]
        spins[j] = y[Y_OMEGA] * y[Y_N] + y[Y_OMEGA + 1] * y[Y_N + 1] + y[Y_OMEGA + 2] * y[Y_N + 2]
        peak_reversed = max(peak_reversed, sense * spins[j])
        current = energy(model, y, params)
        budget_error = max(budget_error, abs(energy_initial - current - y[Y_WORK]))
        if j > 0:
            energy_rise = max(energy_rise, current - previous)
        previous = current
        norm = math.sqrt(y[Y_N] ** 2 + y[Y_N + 1] ** 2 + y[Y_N + 2] ** 2)
        tilt = math.acos(min(1.0, max(-1.0, y[Y_N + 2] / norm)))
        max_tilt = max(max_tilt, tilt)
        _, normal_force, _ = spin_and_normal_force(model, y, system, work)
        if normal_force < min_normal:  # fmin: a NaN sample does not win
            min_normal = normal_force
    band, window, averaged, first_time, cumulative = reversal
    rocking_average_into(sample_times, spins, n_samples, window, averaged, cumulative)
    exact = n_stored if window <= 0.0 else 0  # the raw spin's crossings time a raw reversal
    first_time[0] = np.nan
    n_reversals = count_reversals(
        sample_times, averaged, n_samples, band, crossings, exact, first_time
    )
    first = first_time[0]
    spin_final = np.nan
    energy_final = np.nan
    if end.status == STATUS_SUCCESS and n_samples > 0:  # at t_end: the run finished
        spin_final = spins[n_samples - 1]
        energy_final = energy(model, samples[n_samples - 1], params)
    out[COLUMN.first_reversal_time] = first
    out[COLUMN.reversal_count] = n_reversals
    out[COLUMN.spin_final] = spin_final
    out[COLUMN.energy_lost] = energy_initial - energy_final
    out[COLUMN.max_tilt] = max_tilt if n_samples > 0 else np.nan
    out[COLUMN.min_normal_force] = min_normal
    out[COLUMN.t_stop] = end.t_stop
    out[COLUMN.status] = end.status
    out[COLUMN.energy_initial] = energy_initial
    out[COLUMN.peak_reversed_spin] = peak_reversed if n_samples > 0 else np.nan
    out[COLUMN.spin_crossing_count] = end.n_crossings
    out[COLUMN.max_energy_balance_error] = budget_error if n_samples > 0 else np.nan
    out[COLUMN.max_energy_rise] = energy_rise if n_samples > 0 else np.nan
    out[COLUMN.spin_initial] = spin_initial
    out[COLUMN.energy_final] = energy_final
    out[COLUMN.dissipated_work] = samples[n_samples - 1][Y_WORK] if n_samples > 0 else np.nan


def reduce_run(
    model: int,
    params: np.record,
    y0: np.ndarray,
    ending: tuple[int, float, float, int],
    sample_times: np.ndarray,
    samples: np.ndarray,
    crossings: np.ndarray,
    reversal_band: float,
    reversal_window: float,
) -> np.ndarray:
    """The outcome record of one finished run, by the reduction of every sweep point.

    Parameters
    ----------
    model : kernel model code (``kernels.layout``); the sliding model for the hybrid
        contact, as in :func:`run_batch`
    params : the run's kernel parameter record
    y0 : the initial state, shape (N_STATE,)
    ending : how the run ended: (status code (``codes.Status``), stop time [s], smallest
        normal force at the steps [N], spin zero crossings found)
    sample_times : the sample times [s], shape (s,)
    samples : the sampled states, shape (s, N_STATE)
    crossings : the stored times of the spin's zero crossings [s]
    reversal_band : half-width of the spin's hysteresis band [rad/s]
    reversal_window : width of the spin's rocking average [s]; 0: the raw spin

    Returns
    -------
    numpy.ndarray
        The outcomes, columns in the order of ``FIELDS``, shape (len(FIELDS),)
    """
    status, t_stop, min_normal_force, n_crossings = ending
    samples = np.ascontiguousarray(samples, dtype=np.float64)
    times = np.ascontiguousarray(sample_times, dtype=np.float64)
    end = RunEnd(
        int(status),
        int(samples.shape[0]),
        int(n_crossings),
        float(t_stop),
        float(min_normal_force),
        math.nan,
    )
    spins, averaged, first_time = np.zeros(times.shape[0]), np.zeros(times.shape[0]), np.zeros(1)
    cumulative = np.zeros(times.shape[0])
    out = np.empty(N_FIELDS)
    system = (params, samples_rhs_link(params, model))
    finished = (end, times, samples, np.ascontiguousarray(crossings, dtype=np.float64))
    reversal = (float(reversal_band), float(reversal_window), averaged, first_time, cumulative)
    y0 = np.ascontiguousarray(y0, dtype=np.float64)
    work = np.zeros(N_STATE)
    _reduce(int(model), system, y0, finished, reversal, spins, work, out)  # one for every code
    return out


class Points(NamedTuple):
    """What differs from point to point of a batch (k points)."""

    params: np.ndarray  # kernel parameter records, shape (k,)
    initial_states: np.ndarray  # shape (k, N_STATE)
    reversal_bands: np.ndarray  # hysteresis half-widths [rad/s], shape (k,)
    reversal_windows: np.ndarray  # widths of the spin's rocking average [s], shape (k,)
    capture_speeds: np.ndarray  # v_c [m/s] > 0: the hybrid contact; 0: one model run


@kernel
def _batch(model, methods, points, t_end, controls, output, log, links, results):
    """Run and reduce every point into its row of ``results``. ``methods`` is (the method,
    the method of stick phases); a point with a capture speed runs the hybrid contact
    (``phases.run_phases``), as ``simulate`` with ``HybridModel``. ``links`` are those of
    ``driver.integrate`` for the model and method with its right-hand side's,
    ``phases.run_phases`` and its links (``_linking``; ``NO_LINK`` where no point runs
    the loop); a point's summary calls the right-hand side at its run's link."""
    to_integrate, phases_link, phase_links = links
    spins = np.zeros(output.sample_times.shape[0])
    averaged = np.zeros(output.sample_times.shape[0])
    cumulative = np.zeros(output.sample_times.shape[0])
    first_time = np.zeros(1)
    work = np.zeros(N_STATE)
    table = event_table(model, 0.0)
    for i in range(points.params.shape[0]):
        p = points.params[i]
        y0 = points.initial_states[i]
        output.stats[:] = 0
        if points.capture_speeds[i] > 0.0:
            contact = HybridSettings(methods[0], methods[1], points.capture_speeds[i])
            arguments = (p, y0, t_end, contact, controls, output, log, phase_links)
            end, _, _ = call_run_phases(phases_link, arguments)
            times = log.sample_times
            system = (p, phase_links[2])
        else:
            run = (model, methods[0], p, y0, t_end, controls, table, output, to_integrate[1])
            end = call_integrate(to_integrate[0], run)
            times = output.sample_times
            system = (p, to_integrate[1])
        reversal = (
            points.reversal_bands[i],
            points.reversal_windows[i],
            averaged,
            first_time,
            cumulative,
        )
        finished = (end, times, output.samples, output.crossings)
        _reduce(model, system, y0, finished, reversal, spins, work, results[i])


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
    reversal_windows: np.ndarray | float = 0.0,
    max_steps: int = 20_000_000,
    max_crossings: int = 100_000,
    capture_speeds: np.ndarray | None = None,
    stick_method_name: str = "dop853",
    max_phases: int = DEFAULT_MAX_PHASES,
    device: str = "cpu",
) -> np.ndarray:
    """Integrate every row of ``params``/``y0`` and return their result fields.

    Parameters
    ----------
    model : kernel model code (``kernels.layout``); the sliding model for the hybrid
        contact
    method_name : a key of ``solvers.METHODS`` (of the slip phases in the hybrid contact)
    params : kernel parameter records, one per point, shape (k,) (``params[i]`` is one
        point's record); their ``ellipse_table`` is set to this process's table, since
        records may come from another process (a Dask worker's task)
    y0 : initial states, shape (k, N_STATE)
    t_end : duration [s]
    rtol, atol : local error tolerances
    sample_times : times [s] at which spin, tilt and normal force are sampled, from 0
        to ``t_end``, increasing
    reversal_bands : half-width of each point's hysteresis band of the spin [rad/s],
        shape (k,)
    reversal_windows : width of each point's rocking average of the spin [s] (its body's
        ``rocking_period``), shape (k,) or one for all; 0: the raw spin
    max_steps : step limit of each run
    max_crossings : spin zero crossings stored per run for timing reversals
    capture_speeds : None for one run of ``model`` per point; for the hybrid
        (stick–slip) contact each point's capture speed v_c [m/s], shape (k,)
    stick_method_name : method of the stick phases (hybrid contact)
    max_phases : phase-log capacity of each hybrid run
    device : "cpu", or "cuda": one GPU thread per point (``batch_cuda.run_points``, the
        same loops and reduction compiled for CUDA), for the models and methods it runs,
        the hybrid contact included

    Returns
    -------
    numpy.ndarray
        shape (k, len(FIELDS)), float64, columns in the order of ``FIELDS``; the hybrid
        contact reduces exactly as ``simulate`` with ``HybridModel`` does
    """
    # every per-point array a writable copy, whatever the caller passed (a sweep's are
    # read-only views): numba types a read-only array apart, so each mix of flags would
    # compile a batch loop of its own
    n_points = len(params)
    speeds = np.zeros(n_points) if capture_speeds is None else capture_speeds

    def per_point(values: Any) -> np.ndarray:
        return np.array(np.broadcast_to(values, (n_points,)), dtype=np.float64)

    records = np.array(params)
    records["ellipse_table"] = ellipse_table_address()  # an address of another process crashes
    points = Points(
        records,
        np.array(y0, dtype=np.float64, order="C"),
        per_point(reversal_bands),
        per_point(reversal_windows),
        per_point(speeds),
    )
    controls = Controls(float(rtol), float(atol), 0.0, 0.0, int(max_steps), True)
    methods = (METHODS[method_name], METHODS[stick_method_name])
    if device == "cuda":
        from celtstone.solvers.batch_cuda import launch_inputs, run_points

        return run_points(
            launch_inputs(
                int(model),
                methods,
                points,
                float(t_end),
                controls,
                sample_times,
                max_crossings,
                max_phases,
            )
        )
    if device != "cpu":
        raise ValueError(f"no device {device!r}: cpu or cuda")
    output = new_output(sample_times, N_STATE, max_crossings)
    log = new_phase_log(output.sample_times.shape[0], max_phases)
    results = np.empty((n_points, N_FIELDS))
    links = _links(int(model), methods, points, float(t_end), controls, output, log)
    _batch(int(model), methods, points, float(t_end), controls, output, log, links, results)
    return results


def _links(
    model: int,
    methods: tuple[int, int],
    points: Points,
    t_end: float,
    controls: Controls,
    output: Output,
    log: PhaseLog,
) -> tuple[
    tuple[tuple[int, int], tuple[int, int]],
    tuple[int, int],
    tuple[tuple[int, int], tuple[int, int], tuple[int, int]],
]:
    """``_batch``'s links: ``driver.integrate`` for ``model`` and the method if a point
    runs one model, ``phases.run_phases`` and its two links if a point runs the hybrid
    contact (else ``NO_LINK``, so that a batch without one does not compile it)."""
    hybrid_points = points.capture_speeds > 0.0
    to_integrate = (NO_LINK, NO_LINK)  # the loop and its right-hand side
    to_phases = NO_LINK
    phase_links = (NO_LINK, NO_LINK, NO_LINK)
    if points.params.shape[0] == 0:
        return to_integrate, to_phases, phase_links
    params, y0 = points.params[0], points.initial_states[0]
    if not np.all(hybrid_points):
        table = event_table(model, 0.0)
        arguments = (model, methods[0], params, y0, t_end, controls, table, output)
        codes_vary = any(np.unique(points.params[name]).size > 1 for name in RUN_CODES)
        to_integrate = integrate_link(arguments, codes_vary=codes_vary)
    if np.any(hybrid_points):
        hybrid = HybridSettings(methods[0], methods[1], 1.0)
        phase_links = integrate_links(params, hybrid, controls, output)
        phase_arguments = (params, y0, t_end, hybrid, controls, output, log, phase_links)
        to_phases = link_to(run_phases, phase_arguments)
    return to_integrate, to_phases, phase_links
