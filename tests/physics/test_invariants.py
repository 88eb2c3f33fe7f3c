"""Invariants of both models, with tolerances tied to the solver tolerance."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import celtstone as cs
from tests.conftest import LITERATURE_EULER_ANGLES

SLIDING_CASES = [
    cs.SlidingModel(friction_coefficient=0.35, contact_radius=1e-3, friction_load="static"),
    cs.SlidingModel(friction_coefficient=0.35, contact_radius=1e-3, friction_load="dynamic"),
    cs.SlidingModel(friction_coefficient=0.15, contact_radius=1e-3, friction_load="static"),
]


@pytest.mark.parametrize("spin", [-5.0, 5.0])
def test_rolling_conserves_energy_over_60_s(kane_levinson: cs.Body, spin: float) -> None:
    """Issue 2: relative drift below 1e-8 over 60 s at the default tolerance (rtol 1e-10)."""
    state = cs.InitialState(omega=(0.0, 0.0, spin), euler_angles=LITERATURE_EULER_ANGLES)
    run = cs.simulate(cs.RollingModel(), kane_levinson, state, 60.0)
    assert run.ok, run.message
    summary = run.summary()
    assert summary["max_relative_energy_drift"] < 1e-8
    assert summary["dissipated_work"] == 0.0


@pytest.mark.parametrize(
    "model", SLIDING_CASES, ids=lambda m: f"f{m.friction_coefficient}-{m.friction_load}"
)
def test_sliding_energy_lost_equals_friction_work(
    kane_levinson: cs.Body, model: cs.SlidingModel
) -> None:
    """E(0) - E(t) = W(t), the integrated friction work, to the solver's accuracy."""
    state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=LITERATURE_EULER_ANGLES)
    run = cs.simulate(model, kane_levinson, state, 4.0, rtol=1e-9)
    assert run.ok, run.message
    ds = run.dataset
    energy = ds["energy"].values
    work = ds["dissipated_work"].values
    lost = energy[0] - energy
    assert work[-1] > 1e-4 * energy[0]  # friction does real work here
    # the balance error is a sum of local errors: a few hundred rtol * E0 at most
    assert np.max(np.abs(lost - work)) < 1e-6 * energy[0]
    # friction only removes energy: the work never decreases
    assert np.all(np.diff(work) >= -1e-12)


@pytest.mark.parametrize("model", [cs.RollingModel(), *SLIDING_CASES[:2]], ids=str)
def test_unit_vertical_and_horizontal_slip_are_held(
    kane_levinson: cs.Body, model: cs.Model
) -> None:
    """|n| = 1 and V1 · n = 0 are first integrals of the equations; they stay to tolerance."""
    state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=LITERATURE_EULER_ANGLES)
    run = cs.simulate(model, kane_levinson, state, 4.0, rtol=1e-10)
    ds = run.dataset
    n = ds["n"].values
    assert np.max(np.abs(np.linalg.norm(n, axis=1) - 1.0)) < 1e-8
    slip_normal = np.einsum("ij,ij->i", ds["slip_velocity"].values, n)
    assert np.max(np.abs(slip_normal)) < 1e-10  # m/s; slip speeds here are ~1e-3 m/s


def test_attitude_quaternion_agrees_with_vertical(kane_levinson: cs.Body) -> None:
    """n(t) from the Poisson equation equals R(q(t))^T e_z from the quaternion."""
    state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(3.0, -2.0))
    run = cs.simulate(cs.SlidingModel(), kane_levinson, state, 3.0)
    q = run.dataset["quaternion"].values
    w, x, y, z = q.T
    # third row of R(q): R^T e_z in body axes
    vertical = np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=1)
    assert np.max(np.abs(vertical - run.dataset["n"].values)) < 1e-7


def _mirror_body(body: cs.Body) -> cs.Body:
    inertia = np.array(body.inertia)
    inertia[0, 1] = inertia[1, 0] = -inertia[0, 1]
    inertia[1, 2] = inertia[2, 1] = -inertia[1, 2]
    return dataclasses.replace(body, name=body.name + "_mirrored", inertia=inertia.tolist())


@pytest.mark.parametrize("model", [cs.RollingModel(), SLIDING_CASES[0], SLIDING_CASES[1]], ids=str)
def test_mirrored_body_spins_the_mirrored_way(kane_levinson: cs.Body, model: cs.Model) -> None:
    """Reflect in the plane x2 = 0: D -> -D, mirrored start; the spin changes sign exactly."""
    state = cs.InitialState(omega=(0.3, -0.2, -5.0), euler_angles=(0.7, 0.4))
    original = cs.simulate(model, kane_levinson, state, 6.0)
    mirrored = cs.simulate(model, _mirror_body(kane_levinson), state.mirrored(), 6.0)
    spin, spin_m = original.dataset["spin"].values, mirrored.dataset["spin"].values
    assert np.max(np.abs(spin + spin_m)) < 1e-6 * np.max(np.abs(spin))
    omega, omega_m = original.dataset["omega"].values, mirrored.dataset["omega"].values
    np.testing.assert_allclose(omega_m, omega * [-1, 1, -1], atol=1e-6)
    np.testing.assert_allclose(original.spin_crossings, mirrored.spin_crossings, atol=1e-6)


@pytest.mark.parametrize("model", [cs.RollingModel(), SLIDING_CASES[0]], ids=str)
def test_aligned_axes_prefer_no_direction(kane_levinson: cs.Body, model: cs.Model) -> None:
    """With D = 0 the +w and -w starts with mirrored tilt are exact mirror images."""
    inertia = np.diag(np.diag(np.array(kane_levinson.inertia)))
    aligned = dataclasses.replace(kane_levinson, inertia=inertia.tolist())
    plus = cs.InitialState(omega=(0.0, 0.0, 5.0), euler_angles=(0.5, 0.5))
    minus = plus.mirrored()
    assert minus.omega == (-0.0, 0.0, -5.0)
    run_plus = cs.simulate(model, aligned, plus, 8.0)
    run_minus = cs.simulate(model, aligned, minus, 8.0)
    spin_plus, spin_minus = run_plus.dataset["spin"].values, run_minus.dataset["spin"].values
    assert np.max(np.abs(spin_plus + spin_minus)) < 1e-6 * 5.0
    # no preferred direction means no Celt effect: rolling keeps its sense; sliding
    # friction only brakes the spin, and what crosses zero once it has died is dither
    if isinstance(model, cs.RollingModel):
        assert run_plus.first_spin_crossing_time is None
    elif run_plus.first_spin_crossing_time is not None:
        after = run_plus.dataset["time"].values >= run_plus.first_spin_crossing_time
        assert np.max(np.abs(spin_plus[after])) < 0.02 * 5.0


def test_frictionless_sliding_conserves_energy_and_vertical_momentum(
    kane_levinson: cs.Body,
) -> None:
    """f = 0: only vertical forces act, so E, the vertical angular momentum about G and
    the horizontal momentum are constant."""
    model = cs.SlidingModel(friction_coefficient=0.0)
    state = cs.InitialState(omega=(0.4, -0.3, -5.0), euler_angles=(2.0, 1.0))
    run = cs.simulate(model, kane_levinson, state, 5.0)
    assert run.ok
    ds = run.dataset
    energy = ds["energy"].values
    assert np.max(np.abs(energy - energy[0])) < 1e-8 * energy[0]
    angular_momentum = ds["omega"].values @ np.array(kane_levinson.inertia)
    vertical = np.einsum("ij,ij->i", angular_momentum, ds["n"].values)
    assert np.max(np.abs(vertical - vertical[0])) < 1e-9
    position = ds["com_position"].values
    time = ds["time"].values
    velocity = np.polyfit(time, position, 1)[0]
    residual = position - np.outer(time, velocity) - position[0]
    assert np.max(np.abs(residual)) < 1e-8
