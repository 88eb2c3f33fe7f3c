"""The compiled stick–slip phase loop (``solvers.phases``) against the Python loop it
replaced, written out here as the oracle, and its phase-log capacity."""

from __future__ import annotations

import numpy as np
import pytest

import celtstone as cs
from celtstone import solvers
from celtstone.kernels import layout
from celtstone.kernels import stick as stick_kernels
from celtstone.simulation.models import initial_vector, kernel_parameters

KL_START = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
ROCKING_START = cs.InitialState(omega=(0.0, 0.0, 0.0), euler_angles=(1.0, 0.3))  # no spin, no slip
SLIP, STICK = solvers.PhaseKind.SLIP, solvers.PhaseKind.STICK
MODEL_OF_PHASE = {SLIP: layout.MODEL_SLIDING, STICK: layout.MODEL_STICK}


def _python_phase_loop(  # type: ignore[no-untyped-def]
    params, y0, t_end, *, slip_method, stick_method, rtol, atol, capture_speed, sample_times,
    max_crossings, max_steps,
):  # fmt: skip
    """The phase loop as celtstone ran it in Python before it was compiled: one
    ``solvers.solve`` per phase from t = 0, times shifted by the phase's start."""
    y = np.array(y0, dtype=float)
    kind, jump = SLIP, 0.0
    if stick_kernels.slip_spin_speed(y, params) <= capture_speed:
        captured, start_jump, margin = solvers.capture(params, y)
        if margin >= 0.0:
            y, kind, jump = captured, STICK, start_jump
    t0 = t_stop = 0.0
    next_sample, n_crossings_total, rejected = 0, 0, 0
    times_out, states_out, phase_out, crossings = [], [], [], []
    phases: list[list] = []
    statistics = dict.fromkeys(solvers.STATISTICS, 0)
    min_normal, t_min_normal = np.inf, 0.0
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
        )
        for key in statistics:
            statistics[key] += getattr(raw, key)
        times_out.append(raw.sample_times + t0)
        states_out.append(raw.samples)
        phase_out.append(np.full(raw.sample_times.size, kind, dtype=np.int8))
        next_sample += raw.sample_times.size
        crossings.append(raw.crossings + t0)
        n_crossings_total += raw.n_crossings_total
        if raw.min_normal_force < min_normal:
            min_normal, t_min_normal = raw.min_normal_force, raw.t_min_normal_force + t0
        t_stop = t0 + raw.t_stop
        if phases and phases[-1][0] == kind:
            phases[-1] = [kind, phases[-1][1], t_stop, 0.0]
        else:
            phases.append([kind, t0, t_stop, jump])
        if raw.status != solvers.STATUS_PHASE_CHANGE:
            status = raw.status
            break
        t0, y, jump = t_stop, raw.final_state.copy(), 0.0
        if t0 >= t_end:
            break
        if kind == STICK:
            kind = SLIP
            continue
        captured, capture_jump, margin = solvers.capture(params, y)
        if margin >= 0.0:
            y, kind, jump = captured, STICK, capture_jump
        else:
            rejected += 1
    return {
        "status": status,
        "t_stop": t_stop,
        "sample_times": np.concatenate(times_out),
        "samples": np.concatenate(states_out),
        "sample_phase": np.concatenate(phase_out),
        "crossings": np.concatenate(crossings)[:max_crossings],
        "n_crossings_total": n_crossings_total,
        "min_normal_force": min_normal,
        "t_min_normal_force": t_min_normal,
        "statistics": statistics,
        "phases": phases,
        "rejected_captures": rejected,
    }


def _phase_rows(solution: solvers.RawPhases) -> list[list[float]]:
    """The phase log of a compiled run as rows [kind, start, end, energy jump]."""
    return [
        [kind, start, end, jump]
        for kind, start, end, jump in zip(
            solution.phase_kind,
            solution.phase_start,
            solution.phase_end,
            solution.phase_energy_jump,
            strict=True,
        )
    ]


@pytest.mark.parametrize(
    ("start", "t_end", "max_crossings", "stick_method"),
    [
        (KL_START, 8.0, 100_000, "dop853"),
        (KL_START, 7.0, 2, "radau5"),  # the crossings fill up in the first phase
        (ROCKING_START, 2.0, 100_000, "dop853"),  # starts in stick
    ],
    ids=["spinning", "few-crossings", "rocking"],
)
def test_compiled_loop_is_the_python_loop_to_the_bit(
    start: cs.InitialState, t_end: float, max_crossings: int, stick_method: str
) -> None:
    model = cs.HybridModel(friction_coefficient=0.35, contact_radius=1e-3)
    params = kernel_parameters(model, cs.load_body("kane_levinson_1982"))
    settings = {
        "slip_method": "radau5",
        "stick_method": stick_method,
        "rtol": 1e-10,
        "atol": 1e-12,
        "capture_speed": 1e-10,
        "sample_times": np.linspace(0.0, t_end, round(200 * t_end) + 1),
        "max_crossings": max_crossings,
        "max_steps": 20_000_000,
    }
    compiled = solvers.solve_phases(params, initial_vector(start), t_end, **settings)
    oracle = _python_phase_loop(params, initial_vector(start), t_end, **settings)
    assert len(compiled.phase_kind) >= 2
    assert _phase_rows(compiled) == [list(row) for row in oracle["phases"]]
    for name in ("sample_times", "samples", "sample_phase", "crossings"):
        np.testing.assert_array_equal(getattr(compiled, name), oracle[name], err_msg=name)
    for name in ("status", "t_stop", "n_crossings_total", "min_normal_force"):
        assert getattr(compiled, name) == oracle[name], name
    assert compiled.t_min_normal_force == oracle["t_min_normal_force"]
    assert {key: getattr(compiled, key) for key in solvers.STATISTICS} == oracle["statistics"]
    assert compiled.rejected_captures == oracle["rejected_captures"]


def test_a_full_phase_log_stops_the_run_where_the_next_phase_would_start() -> None:
    """The phase log has a stated capacity; a run needing more phases stops with its own
    status at the end of the last phase it could record, samples up to there."""
    model = cs.HybridModel(friction_coefficient=0.35, contact_radius=1e-3)
    body = cs.load_body("kane_levinson_1982")
    full = cs.simulate(model, body, KL_START, 8.0)
    assert len(full.summary()["phases"]) > 2
    params = kernel_parameters(model, body)
    settings = {
        "slip_method": "radau5",
        "stick_method": "dop853",
        "rtol": 1e-10,
        "atol": 1e-12,
        "capture_speed": 1e-10,
        "sample_times": np.linspace(0.0, 8.0, 1601),
        "max_crossings": 1000,
        "max_steps": 20_000_000,
    }
    cut = solvers.solve_phases(params, initial_vector(KL_START), 8.0, max_phases=2, **settings)
    assert cut.status == solvers.STATUS_MAX_PHASES
    assert len(cut.phase_kind) == 2
    assert cut.t_stop == cut.phase_end[-1] < 8.0
    assert cut.sample_times[-1] <= cut.t_stop
    assert "max_phases" in solvers.STATUS_MESSAGES[solvers.STATUS_MAX_PHASES]
    whole = solvers.solve_phases(params, initial_vector(KL_START), 8.0, **settings)
    assert _phase_rows(cut) == _phase_rows(whole)[:2]  # the same run, cut short
