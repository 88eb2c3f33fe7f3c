"""The Zhuravlev–Padé law's exact limits, the singular state, and sliding -> rolling."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import celtstone as cs
from celtstone.kernels.friction import pade_friction
from tests.conftest import LITERATURE_EULER_ANGLES

RADIUS = 1e-3  # m


def _law(u: float, spin: float = 3.0) -> tuple[float, float]:
    """F/(f N) and M/(f N ε) at u = |V1| / (ε |Ω_n|) (no regularisation)."""
    slip = (u * RADIUS * abs(spin), 0.0, 0.0)
    force, moment = pade_friction(slip, spin, RADIUS, 0.0)
    return -force[0], -moment / RADIUS * math.copysign(1.0, spin)


def test_pure_sliding_gives_coulomb_force() -> None:
    """Ω_n -> 0: F -> f N (references.md)."""
    assert _law(1e9)[0] == pytest.approx(1.0, rel=1e-8)


def test_small_slip_slope_is_3pi_over_8() -> None:
    """F ≈ f N (3π/8) u for small u: fixes b = 8/(3π) (references.md)."""
    u = 1e-7
    assert _law(u)[0] / u == pytest.approx(3 * math.pi / 8, rel=1e-6)


def test_pivoting_moment_at_zero_slip_is_hertz_value() -> None:
    """M(V = 0) = (3π/16) f N ε (paper eq. 12; references.md)."""
    assert _law(0.0)[1] == pytest.approx(3 * math.pi / 16, rel=1e-14)


def test_large_slip_moment_falls_as_one_fifth_over_u() -> None:
    """M ≈ f N ε / (5u) for large u: fixes a = 15π/16 (references.md)."""
    u = 1e8
    assert _law(u)[1] * u == pytest.approx(0.2, rel=1e-6)


@given(
    u=st.floats(min_value=0.0, max_value=1e6),
    spin=st.floats(min_value=-50.0, max_value=50.0).filter(lambda s: abs(s) > 1e-6),
)
def test_law_depends_on_u_only_and_opposes_motion(u: float, spin: float) -> None:
    """By symmetry F ∥ -V1 and M opposes Ω_n; both depend on u alone (references.md)."""
    force, moment = _law(u, spin)
    force_ref, moment_ref = _law(u, 1.0)
    assert force == pytest.approx(force_ref, rel=1e-12, abs=1e-300)
    assert moment == pytest.approx(moment_ref, rel=1e-12)
    assert 0.0 <= force <= 1.0
    assert 0.0 < moment <= 3 * math.pi / 16 + 1e-15


def test_singular_state_is_finite_and_dissipative() -> None:
    """Paper eq. (11): V1 = 0 and Ω_n = 0 together. The regularised law gives zero force
    and moment there, and a run that starts exactly there (rocking without spin or slip)
    stays finite, conserves the energy budget and does not stall."""
    force, moment = pade_friction((0.0, 0.0, 0.0), 0.0, RADIUS, 1e-6)
    assert force == (0.0, 0.0, 0.0) and moment == 0.0
    body = cs.load_body("kane_levinson_1982")
    run = cs.simulate(cs.SlidingModel(), body, cs.InitialState((2.0, 0.0, 0.0), (0.0, 0.0)), 2.0)
    assert run.ok, run.message
    ds = run.dataset
    assert np.all(np.isfinite(ds["omega"].values)) and np.all(
        np.isfinite(ds["slip_velocity"].values)
    )
    energy = ds["energy"].values
    assert np.max(np.abs(energy[0] - energy - ds["dissipated_work"].values)) < 1e-8 * energy[0]
    assert run.statistics["n_accepted"] < 200_000


def test_sliding_tends_to_rolling_as_friction_grows_and_pivot_moment_vanishes() -> None:
    """f -> ∞ with f ε -> 0 (references.md): the sliding spin history approaches rolling.
    The regularisation speed shrinks with ε so that the stick zone stays below the slip."""
    body = cs.load_body("kane_levinson_1982")
    state = cs.InitialState((0.0, 0.0, -5.0), LITERATURE_EULER_ANGLES)
    rolling = cs.simulate(cs.RollingModel(), body, state, 4.0, n_samples=401)
    differences = []
    for f, radius, delta in [(5.0, 1e-6, 1e-6), (50.0, 1e-8, 1e-8), (500.0, 1e-10, 1e-9)]:
        model = cs.SlidingModel(f, radius, regularisation_speed=delta)
        run = cs.simulate(model, body, state, 4.0, n_samples=401, rtol=1e-9)
        assert run.ok
        differences.append(
            np.max(np.abs(run.dataset["spin"].values - rolling.dataset["spin"].values))
        )
    assert differences[0] > differences[1] > differences[2]
    assert differences[2] < 2e-3  # rad/s, against a spin of 5 rad/s
