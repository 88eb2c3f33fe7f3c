"""The small typed structures the compiled loops pass around (numba NamedTuples).

A ``typing.NamedTuple`` compiles to a struct whose fields numba reads by name at a
fixed offset, and a function taking one is cached on disk like any other; so the
loops take a few of these instead of long argument lists.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from celtstone.solvers.codes import N_STATS


class Controls(NamedTuple):
    """How a run is stepped.

    Parameters
    ----------
    rtol, atol : relative and absolute local error tolerances [1], [state units]
    first_step : first step size [s]; 0 picks it (``_step_control.initial_step``)
    max_step : largest step size [s]; 0 for none
    max_steps : largest number of steps before the run stops with ``STATUS_MAX_STEPS``
    adaptive : False keeps the step size fixed at ``first_step`` (convergence tests)
    """

    rtol: float
    atol: float
    first_step: float
    max_step: float
    max_steps: int
    adaptive: bool


class Output(NamedTuple):
    """Where a run writes: filled in place by the compiled loop.

    Parameters
    ----------
    sample_times : output times [s], increasing, shape (k,)
    samples : the state at each sample time, shape (k, N_STATE)
    crossings : times of the spin zero crossings [s]; its length is the capacity
    stats : int64 counters, ``codes.STAT_*``, added to (shape (N_STATS,))
    final_state : the state where the run stopped, shape (N_STATE,)
    """

    sample_times: np.ndarray
    samples: np.ndarray
    crossings: np.ndarray
    stats: np.ndarray
    final_state: np.ndarray


class RunEnd(NamedTuple):
    """How a run of ``driver.integrate`` ended.

    Parameters
    ----------
    status : ``codes.STATUS_*``
    n_samples : samples written
    n_crossings : spin zero crossings found (more than stored if the buffer was full)
    t_stop : time the run stopped [s]
    min_normal_force : smallest normal force at the accepted steps [N] (0 at lift-off)
    t_min_normal_force : its time [s]
    """

    status: int
    n_samples: int
    n_crossings: int
    t_stop: float
    min_normal_force: float
    t_min_normal_force: float


class HybridSettings(NamedTuple):
    """What the hybrid contact adds to a run: the method of each phase and v_c.

    Parameters
    ----------
    slip_method, stick_method : method codes (``codes.METHODS``) of slip and stick
    capture_speed : v_c, the slip–spin speed counted as zero [m/s], > 0
    """

    slip_method: int
    stick_method: int
    capture_speed: float


class PhaseLog(NamedTuple):
    """The stick–slip phases of a hybrid run, preallocated; the capacity is their length.

    Parameters
    ----------
    sample_times : the output times as the phases report them [s], shape (k,)
    sample_phase : phase kind of each sample (0 slip, 1 stick), int8, shape (k,)
    kind : kind of each phase, int8, shape (capacity,)
    start, end : start and end time of each phase [s], shape (capacity,)
    energy_jump : kinetic-energy change of the capture impulse that began it [J]
    """

    sample_times: np.ndarray
    sample_phase: np.ndarray
    kind: np.ndarray
    start: np.ndarray
    end: np.ndarray
    energy_jump: np.ndarray


def new_output(sample_times: np.ndarray, n_state: int, max_crossings: int) -> Output:
    """Zeroed output arrays for runs of states of length ``n_state``, sampled at
    ``sample_times`` [s], storing up to ``max_crossings`` crossings (at least 1)."""
    times = np.ascontiguousarray(sample_times, dtype=np.float64)
    return Output(
        times,
        np.zeros((times.shape[0], n_state)),
        np.zeros(max(int(max_crossings), 1)),
        np.zeros(N_STATS, dtype=np.int64),
        np.zeros(n_state),
    )


def new_phase_log(n_samples: int, max_phases: int) -> PhaseLog:
    """A zeroed phase log for ``n_samples`` samples and ``max_phases`` phases (at least 1)."""
    capacity = max(int(max_phases), 1)
    return PhaseLog(
        np.zeros(n_samples),
        np.zeros(n_samples, dtype=np.int8),
        np.zeros(capacity, dtype=np.int8),
        np.zeros(capacity),
        np.zeros(capacity),
        np.zeros(capacity),
    )
