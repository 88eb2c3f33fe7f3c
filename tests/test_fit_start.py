"""A record that starts mid-motion: the contact may already slide at its first sample, so
the fit frees the initial slip velocity there.

Oracles: the generating run itself (a run from Kane & Levinson's release, sampled from
0.3 s on: its state at the first sample is the truth, slip included), the table plane
(V · n = 0) and the mirror symmetry of the equations.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import celtstone as cs
from celtstone.errors import ParameterError
from celtstone.fitting.problem import SLIP_NAMES, Settings, make_problem
from celtstone.fitting.runs import Runs
from celtstone.fitting.solve import FIT_ATOL, FIT_RTOL, _minimise
from celtstone.simulation.models import initial_vector
from celtstone.sweep.spec import PointBuilder, build_state
from test_fit_trust import KL_RELEASE, Truth, phone_record

RATES = ("omega1", "omega2", "omega3")
OFFSET = 0.3  # s from the release to the first sample
SIGMA = 0.02  # rad/s, the noise a phone adds (given: the record below has none)


def _state_at(body: cs.Body, model: cs.SlidingModel, time: float) -> dict[str, float]:
    """The rates [rad/s], Euler angles [deg] and slip [m/s] of the run from the release at
    ``time`` [s]."""
    run = cs.simulate(model, body, KL_RELEASE, time, sample_times=np.array([0.0, time]))
    omega = run.samples.values("omega")[-1]
    n = run.samples.values("n")[-1]
    slip = run.samples.values("slip_velocity")[-1]
    return {
        **dict(zip(RATES, map(float, omega), strict=True)),
        "euler_alpha": math.degrees(math.asin(n[1])),
        "euler_beta": math.degrees(math.atan2(-n[0], n[2])),
        "slip_velocity1": float(slip[0]),
        "slip_velocity2": float(slip[1]),
    }


def test_a_record_that_starts_sliding_is_fitted_exactly_with_its_slip_free(
    kane_levinson: cs.Body,
) -> None:
    """A noise-free three-axis record that starts 0.3 s after the release, while the
    contact slides (≈ 1.7 cm/s), fitted from its first sample with the state there free:
    with the initial slip free (by default) the fit returns the truth, f and ε to 1e-6;
    with the slip held at 0 no state explains the record (residuals of a tenth of a
    phone's noise and more) and f and ε are biased."""
    truth = Truth(0.31, 6e-4, OFFSET, RATES)
    model = cs.SlidingModel(friction_coefficient=0.31, contact_radius=6e-4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cs.FrictionBoundWarning)
        state = _state_at(kane_levinson, model, OFFSET)
        record = phone_record(kane_levinson, truth, 2.0, seed=3, noise=0.0)
    assert math.hypot(state["slip_velocity1"], state["slip_velocity2"]) > 0.01
    physical = {"friction_coefficient": 0.31, "contact_radius": 6e-4}
    start = {**physical, **{k: v for k, v in state.items() if k not in SLIP_NAMES}}
    ends = {}
    for slip_free in (True, False):
        problem = make_problem(
            record,
            kane_levinson,
            "sliding",
            list(start),
            Settings(
                start=start,
                sigma=dict.fromkeys(RATES, SIGMA),
                initial_slip=slip_free,
                rtol=FIT_RTOL,
                atol=FIT_ATOL,
            ),
        )
        assert (SLIP_NAMES[0] in problem.names) is slip_free
        with warnings.catch_warnings(), Runs(problem, workers=2) as runs:
            warnings.simplefilter("ignore", cs.FrictionBoundWarning)
            x, cost = _minimise(runs, problem.start, list(range(len(problem.free))))[:2]
        ends[slip_free] = (dict(zip(problem.names, x, strict=True)), cost, problem.n_residuals)
    fitted, cost, count = ends[True]
    for name, value in physical.items():
        assert fitted[name] == pytest.approx(value, rel=1e-6)
    for name in SLIP_NAMES:
        assert fitted[name] == pytest.approx(state[name], abs=1e-5)
    assert math.sqrt(2.0 * cost / count) < 1e-3  # RMS residual in units of σ
    held, cost, count = ends[False]
    assert math.sqrt(2.0 * cost / count) > 0.1
    assert abs(held["contact_radius"] / 6e-4 - 1.0) > 1e-3


def test_the_initial_slip_lies_in_the_table_plane_and_is_checked(kane_levinson: cs.Body) -> None:
    """V3 follows from V · n0 = 0; the state array carries V; the mirror flips V2 (a
    velocity, unlike ω); a slip beyond the schema's range, or with the rolling model, is
    refused naming ``slip_velocity``; the sweep names build it."""
    state = cs.InitialState((1.0, 0.5, -4.0), (3.0, -2.0), slip_velocity=(0.02, -0.01))
    assert np.dot(state.slip, state.vertical) == pytest.approx(0.0, abs=1e-15)
    y = initial_vector(state)
    np.testing.assert_array_equal(y[6:9], state.slip)
    mirrored = state.mirrored()
    assert mirrored.slip_velocity == (0.02, 0.01)
    assert np.dot(mirrored.slip, mirrored.vertical) == pytest.approx(0.0, abs=1e-15)
    assert not cs.InitialState().is_sliding and state.is_sliding
    with pytest.raises(ParameterError, match=r"slip_velocity = 20.*\[-10, 10\] m/s"):
        cs.InitialState(slip_velocity=(20.0, 0.0))
    with pytest.raises(ParameterError, match=r"slip_velocity.*rolling"):
        cs.simulate(cs.RollingModel(), kane_levinson, state, 0.1)
    built = build_state({"slip_velocity1": 0.02, "slip_velocity2": -0.01})
    assert built.slip_velocity == (0.02, -0.01)
    varied = {"slip_velocity1": np.array([0.0, 0.01])}
    with pytest.raises(ParameterError, match=r"slip_velocity1 = '2 values .*rolling"):
        PointBuilder(kane_levinson, "rolling", {}, varied)


@pytest.mark.parametrize(
    ("fixed", "free", "model", "is_free"),
    [
        ({}, (), "sliding", True),  # the rates read from the first sample
        ({}, RATES, "sliding", True),  # the rates fitted
        (dict(zip(RATES, (0.0, 0.0, -5.0), strict=True)), (), "sliding", False),  # given
        ({}, ("release_offset",), "sliding", False),  # a release before the record
        ({}, (), "rolling", False),
    ],
)
def test_the_slip_is_free_where_the_run_starts_mid_motion(
    kane_levinson: cs.Body,
    fixed: dict[str, float],
    free: tuple[str, ...],
    model: str,
    is_free: bool,
) -> None:
    """Free by default where the run starts at a state of the motion (read from the record
    or fitted); held at 0 at a release or a state the user gives, and with rolling."""
    truth = Truth(0.3, 1e-3, 0.0, RATES)
    record = phone_record(kane_levinson, truth, 0.2, seed=0)
    names = (*(("friction_coefficient",) if model == "sliding" else ()), *free)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cs.CeltstoneWarning)  # the rates read and held
        problem = make_problem(
            record, kane_levinson, model, names, Settings(fixed=fixed, rtol=1e-8, atol=1e-10)
        )
    assert all((name in problem.names) is is_free for name in SLIP_NAMES)


def test_a_slip_with_the_rolling_model_is_refused(kane_levinson: cs.Body) -> None:
    truth = Truth(0.3, 1e-3, 0.0, RATES)
    record = phone_record(kane_levinson, truth, 0.2, seed=0)
    with pytest.raises(ParameterError, match=r"slip_velocity1.*cannot slip"):
        make_problem(
            record, kane_levinson, "rolling", ["slip_velocity1"], Settings(rtol=1e-8, atol=1e-10)
        )
