"""The hybrid (stick–slip) contact: its phases, and the call of the compiled phase loop.

A run alternates two phases (``solvers.phases``, compiled; docs/decisions.md §16):

* slip: the sliding model (paper eq. 6–12) with the capture event: the slip–spin
  speed sqrt(|V1|² + ε²(ω · n)²) falls below the capture speed v_c, a numerical zero
  (``docs/decisions.md``). Stick starts there if it is admissible after the capture
  impulse (``kernels.stick.capture_state``); otherwise sliding goes on.
* stick: rolling without sliding and without pivoting (``kernels.stick``) until the
  stick margin g falls below zero: the friction it needs leaves the Coulomb–Contensou
  limit set; sliding restarts from that state.

With ω · n ≠ 0 no tangential force can be held without slip (Contensou), so stick
can only start where slip and spin vanish together. This module only turns the
compiled loop's arrays into :class:`HybridSolution`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from celtstone import solvers
from celtstone.solvers import phases

__all__ = ["PHASE_KINDS", "SLIP", "STICK", "HybridSolution", "Phase", "capture", "solve_phases"]

SLIP = phases.SLIP
STICK = phases.STICK
PHASE_KINDS = {SLIP: "slip", STICK: "stick"}


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


def capture(params: Any, y: np.ndarray) -> tuple[np.ndarray, float, float]:
    """The state after the capture impulse, its energy jump [J] and its stick margin [1].

    The energy removed by the impulse is added to the dissipated work, so that
    E + W stays E(0) across the switch (``solvers.phases.capture``).
    """
    captured = np.empty_like(y)
    jump, margin = phases.capture(params, np.ascontiguousarray(y, dtype=np.float64), captured)
    return captured, float(jump), float(margin)


def solve_phases(
    params: Any,
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
    max_phases: int = solvers.DEFAULT_MAX_PHASES,
    progress: Callable[[float], None] | None = None,
) -> HybridSolution:
    """Integrate the hybrid contact over [0, t_end]; see the module docstring.

    ``progress``, if given, is called with the time reached [s] while phases run.
    ``max_phases`` is the capacity of the phase log: a run that needs more phases stops
    with ``solvers.STATUS_MAX_PHASES`` where the next one would start.

    The run starts in stick if y0 neither slides nor pivots (slip–spin speed
    <= ``capture_speed``) and stick is admissible there; else it starts sliding.
    """
    raw = solvers.solve_phases(
        params,
        y0,
        t_end,
        slip_method=slip_method,
        stick_method=stick_method,
        rtol=rtol,
        atol=atol,
        capture_speed=capture_speed,
        sample_times=sample_times,
        max_crossings=max_crossings,
        max_steps=max_steps,
        max_phases=max_phases,
        progress=progress,
    )
    phases_run = tuple(
        Phase(PHASE_KINDS[int(kind)], float(start), float(end), float(jump))
        for kind, start, end, jump in zip(
            raw.phase_kind, raw.phase_start, raw.phase_end, raw.phase_energy_jump, strict=True
        )
    )
    return HybridSolution(
        status=raw.status,
        t_stop=raw.t_stop,
        sample_times=raw.sample_times,
        samples=raw.samples,
        sample_phase=raw.sample_phase,
        crossings=raw.crossings,
        n_crossings_total=raw.n_crossings_total,
        min_normal_force=raw.min_normal_force,
        t_min_normal_force=raw.t_min_normal_force,
        statistics={key: int(getattr(raw, key)) for key in solvers.STATISTICS},
        phases=phases_run,
        rejected_captures=raw.rejected_captures,
    )
