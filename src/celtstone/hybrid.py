"""The stick–slip loop of the hybrid contact: integrate one phase, switch, go on.

A run alternates two phases, each integrated by ``solvers.solve`` until its event:

* slip: the sliding model (paper eq. 6–12) with the capture event: the slip–spin
  speed sqrt(|V1|² + ε²(ω · n)²) falls below the capture speed v_c, a numerical zero
  (``docs/decisions.md``). Stick starts there if it is admissible after the capture
  impulse (``kernels.stick.capture_state``); otherwise sliding goes on.
* stick: rolling without sliding and without pivoting (``kernels.stick``) until the
  stick margin g falls below zero: the friction it needs leaves the Coulomb–Contensou
  limit set; sliding restarts from that state.

With ω · n ≠ 0 no tangential force can be held without slip (Contensou), so stick
can only start where slip and spin vanish together.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from celtstone import solvers
from celtstone.kernels import layout
from celtstone.kernels import stick as stick_kernels
from celtstone.kernels import system as kernel_system

__all__ = ["PHASE_KINDS", "SLIP", "STICK", "HybridSolution", "Phase", "capture", "solve_phases"]

SLIP = 0
STICK = 1
PHASE_KINDS = {SLIP: "slip", STICK: "stick"}
MODEL_OF_PHASE = {SLIP: layout.MODEL_SLIDING, STICK: layout.MODEL_STICK}


@dataclass(frozen=True)
class Phase:
    """One phase of a hybrid run: ``kind`` "slip" or "stick", its times [s], and the
    kinetic-energy jump of the capture impulse that started it [J] (0 for slip)."""

    kind: str
    t_start: float
    t_end: float
    energy_jump: float = 0.0


@dataclass(frozen=True)
class HybridSolution:
    """The phases joined: samples with their phase (0 slip, 1 stick), SI units."""

    status: int
    t_stop: float
    sample_times: np.ndarray
    samples: np.ndarray
    sample_phase: np.ndarray
    crossings: np.ndarray
    n_crossings_total: int
    min_normal_force: float
    t_min_normal_force: float
    statistics: dict[str, int]
    phases: tuple[Phase, ...]
    rejected_captures: int


def capture(params: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, float, float]:
    """The state after the capture impulse, its energy jump [J] and its stick margin [1].

    The energy removed by the impulse is added to the dissipated work, so that
    E + W stays E(0) across the switch.
    """
    captured = np.empty_like(y)
    stick_kernels.capture_state(y, params, captured)
    jump = kernel_system.energy(layout.MODEL_STICK, captured, params) - kernel_system.energy(
        layout.MODEL_SLIDING, y, params
    )
    captured[layout.Y_WORK] -= jump
    margin = kernel_system.phase_value(layout.MODEL_STICK, captured, params, 0.0)
    return captured, float(jump), float(margin)


def _shifted(progress: Callable[[float], None], t0: float) -> Callable[[float], None]:
    """``progress`` for a phase that starts at ``t0`` [s]."""
    return lambda time: progress(t0 + time)


def solve_phases(
    params: np.ndarray,
    y0: np.ndarray,
    t_end: float,
    *,
    slip_method: str,
    stick_method: str,
    rtol: float,
    atol: float,
    capture_speed: float,
    sample_times: np.ndarray,
    max_crossings: int,
    max_steps: int,
    progress: Callable[[float], None] | None = None,
) -> HybridSolution:
    """Integrate the hybrid contact over [0, t_end]; see the module docstring.

    ``progress``, if given, is called with the time reached [s] while phases run.

    The run starts in stick if y0 neither slides nor pivots (slip–spin speed
    <= ``capture_speed``) and stick is admissible there; else it starts sliding.
    """
    y = np.array(y0, dtype=float)
    kind = SLIP
    jump = 0.0
    if stick_kernels.slip_spin_speed(y, params) <= capture_speed:
        captured, start_jump, margin = capture(params, y)
        if margin >= 0.0:
            y, kind, jump = captured, STICK, start_jump
    t0 = t_stop = 0.0
    next_sample = 0
    times_out: list[np.ndarray] = []
    states_out: list[np.ndarray] = []
    phase_out: list[np.ndarray] = []
    crossings: list[np.ndarray] = []
    n_crossings_total = 0
    phases: list[Phase] = []
    statistics = dict.fromkeys(("nfev", "njev", "nlu", "n_accepted", "n_rejected"), 0)
    min_normal, t_min_normal = np.inf, 0.0
    rejected = 0
    status = solvers.STATUS_SUCCESS
    while True:
        steps_left = max_steps - statistics["n_accepted"] - statistics["n_rejected"]
        if steps_left <= 0:
            status = solvers.STATUS_MAX_STEPS
            break
        raw = solvers.solve(
            MODEL_OF_PHASE[kind],
            slip_method if kind == SLIP else stick_method,
            params,
            y,
            t_end - t0,
            rtol=rtol,
            atol=atol,
            sample_times=sample_times[next_sample:] - t0,
            max_crossings=max(max_crossings - n_crossings_total, 1),
            max_steps=steps_left,
            capture_speed=capture_speed if kind == SLIP else 0.0,
            progress=None if progress is None else _shifted(progress, t0),
        )
        for key in statistics:
            statistics[key] += getattr(raw, key)
        count = raw.sample_times.size
        times_out.append(raw.sample_times + t0)
        states_out.append(raw.samples)
        phase_out.append(np.full(count, kind, dtype=np.int8))
        next_sample += count
        crossings.append(raw.crossings + t0)
        n_crossings_total += raw.n_crossings_total
        if raw.min_normal_force < min_normal:
            min_normal, t_min_normal = raw.min_normal_force, raw.t_min_normal_force + t0
        t_stop = t0 + raw.t_stop
        if phases and phases[-1].kind == PHASE_KINDS[kind]:
            # sliding went on after a capture where stick was not admissible
            phases[-1] = Phase(PHASE_KINDS[kind], phases[-1].t_start, t_stop)
        else:
            phases.append(Phase(PHASE_KINDS[kind], t0, t_stop, jump))
        if raw.status != solvers.STATUS_PHASE_CHANGE:
            status = raw.status
            break
        t0, y, jump = t_stop, raw.final_state.copy(), 0.0
        if t0 >= t_end:
            break
        if kind == STICK:
            kind = SLIP
            continue
        captured, capture_jump, margin = capture(params, y)
        if margin >= 0.0:
            y, kind, jump = captured, STICK, capture_jump
        else:
            rejected += 1
    return HybridSolution(
        status=status,
        t_stop=t_stop,
        sample_times=np.concatenate(times_out),
        samples=np.concatenate(states_out),
        sample_phase=np.concatenate(phase_out),
        crossings=np.concatenate(crossings)[:max_crossings],
        n_crossings_total=n_crossings_total,
        min_normal_force=float(min_normal),
        t_min_normal_force=float(t_min_normal),
        statistics=statistics,
        phases=tuple(phases),
        rejected_captures=rejected,
    )
