"""The resolution of a reversal's time: read from the samples, it converges with the
sampling to the time of a converged run (tight rtol, dense sampling), the oracle here.

The averaged spin whose zero times a reversal is the samples' running mean
(``celtstone.simulation.reversals``); sweeps compute it in the same compiled kernel from their own
samples, so the time depends on the sample rate. These tests bound that dependence at
the default rate and check that it is the sampling's: it shrinks as the rate grows.
"""

from __future__ import annotations

import warnings

import pytest

import celtstone as cs
from celtstone.errors import FrictionBoundWarning
from celtstone.simulation.reversals import REVERSAL_TIME_RESOLUTION

START = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))


def _first(model: cs.Model, t_end: float, rate: float, rtol: float = 1e-10) -> float:
    body = cs.load_body("kane_levinson_1982")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FrictionBoundWarning)  # the paper's N = m g
        run = cs.simulate(
            model, body, START, t_end, rtol=rtol, atol=1e-14, n_samples=int(rate * t_end) + 1
        )
    first = run.raise_for_status().first_reversal_time
    assert first is not None
    return first


@pytest.mark.parametrize(
    ("model", "t_end"),
    [(cs.SlidingModel(friction_coefficient=0.35), 2.5), (cs.RollingModel(), 3.5)],
    ids=["sliding", "rolling"],
)
def test_first_reversal_converges_with_the_sampling(model: cs.Model, t_end: float) -> None:
    converged = _first(model, t_end, 20_000.0, rtol=1e-12)
    default = abs(_first(model, t_end, 200.0) - converged)
    finer = abs(_first(model, t_end, 2_000.0) - converged)
    assert default <= REVERSAL_TIME_RESOLUTION
    assert finer < default / 10.0  # the error is the sampling's: O(h²) or better
