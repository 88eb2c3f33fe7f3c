"""Rolling resistance: a rolling-friction length λ (issue 13, item 4; docs/equations.md).

The moment M_r = −λ N ω_t / sqrt(|ω_t|² + ω_0²) opposes the rolling part of ω. Oracles:
the energy budget E(0) − E(t) = W(t) (its power −M_r · ω goes into W), energy
conservation without it, the rest energy m g l of the body, mirror symmetry, and λ = 0
reproducing the model without the setting exactly.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import celtstone as cs

SPINNING = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))  # Kane & Levinson's state
ROCKING = cs.InitialState((0.0, 0.0, 0.0), (0.0, 2.0))  # released at 2° about axis 2
LAMBDA = 1e-4  # m


def _aligned(body: cs.Body) -> cs.Body:
    """The body with its inertia's products removed (D = 0): no Celt effect turns rocking
    into spin, so the only rest state is lying still, E = m g l."""
    inertia = np.diag(np.diag(np.array(body.inertia)))
    return dataclasses.replace(body, name=body.name + "_aligned", inertia=inertia.tolist())


def _rest_energy(body: cs.Body) -> float:
    """m g l: the potential energy of the body at rest on the plane (plane as zero) [J]."""
    return body.mass * body.gravity * body.shape.rest_height


@pytest.mark.parametrize(
    ("model", "rtol", "t_end"),
    [
        (cs.RollingModel(rolling_resistance=LAMBDA), 1e-12, 4.0),
        (cs.SlidingModel(friction_coefficient=0.35, rolling_resistance=LAMBDA), 1e-11, 2.0),
        (
            cs.SlidingModel(
                friction_coefficient=0.35, friction_load="dynamic", rolling_resistance=LAMBDA
            ),
            1e-11,
            2.0,
        ),
    ],
    ids=["rolling", "sliding-static", "sliding-dynamic"],
)
def test_energy_budget_closes_with_rolling_resistance(
    kane_levinson: cs.Body, model: cs.Model, rtol: float, t_end: float
) -> None:
    """E(0) − E(t) = W(t) to 1e-8 E0, and W never decreases: M_r never adds energy."""
    run = cs.simulate(model, kane_levinson, SPINNING, t_end, rtol=rtol, atol=1e-14)
    assert run.ok, run.message
    energy = run.dataset["energy"].values
    work = run.dataset["dissipated_work"].values
    assert work[-1] > 1e-5 * energy[0]  # the resistance does real work here
    assert np.max(np.abs(energy[0] - energy - work)) < 1e-8 * energy[0]
    assert np.all(np.diff(work) >= -1e-14 * energy[0])


@pytest.mark.parametrize(("resistance", "t_end"), [(1e-5, 110.0), (1e-4, 12.0)])
def test_rocking_stone_comes_to_rest(
    kane_levinson: cs.Body, resistance: float, t_end: float
) -> None:
    """Released tilted, the stone rocks; with λ > 0 its energy falls to m g l (measured:
    the excess energy is below 1e-3 of its start after 93 s for λ = 1e-5 m, 9.3 s for 1e-4 m;
    docs/decisions.md §25)."""
    body = _aligned(kane_levinson)
    run = cs.simulate(cs.RollingModel(rolling_resistance=resistance), body, ROCKING, t_end)
    assert run.ok, run.message
    energy = run.dataset["energy"].values
    rest = _rest_energy(body)
    excess = energy[0] - rest
    assert excess > 1e-4 * rest  # it starts with energy to lose
    assert energy[-1] - rest < 1e-3 * excess
    assert energy[-1] > rest - 1e-9 * rest  # never below the rest energy


def test_rocking_stone_without_resistance_keeps_its_energy(kane_levinson: cs.Body) -> None:
    run = cs.simulate(cs.RollingModel(), _aligned(kane_levinson), ROCKING, 12.0)
    energy = run.dataset["energy"].values
    assert np.max(np.abs(energy - energy[0])) < 1e-8 * energy[0]


def test_zero_resistance_is_the_model_without_it(kane_levinson: cs.Body) -> None:
    """λ = 0 skips the term: the final state equals the default model's bit for bit."""
    cases = [
        (cs.RollingModel(), 2.0),
        (cs.SlidingModel(friction_coefficient=0.35), 0.5),
        (cs.HybridModel(friction_coefficient=0.35), 0.5),
    ]
    for default, t_end in cases:
        zero = dataclasses.replace(default, rolling_resistance=0.0)
        reference = cs.simulate(default, kane_levinson, SPINNING, t_end, rtol=1e-8)
        run = cs.simulate(zero, kane_levinson, SPINNING, t_end, rtol=1e-8)
        assert run.dataset["spin"].values[-1] == reference.dataset["spin"].values[-1]
        np.testing.assert_array_equal(
            run.dataset["omega"].values, reference.dataset["omega"].values
        )


@pytest.mark.parametrize(
    "model",
    [
        cs.RollingModel(rolling_resistance=LAMBDA),
        cs.SlidingModel(friction_coefficient=0.35, rolling_resistance=LAMBDA),
    ],
    ids=["rolling", "sliding"],
)
def test_mirror_symmetry_holds_with_rolling_resistance(
    kane_levinson: cs.Body, model: cs.Model
) -> None:
    inertia = np.array(kane_levinson.inertia)
    inertia[0, 1] = inertia[1, 0] = -inertia[0, 1]
    mirror = dataclasses.replace(kane_levinson, name="mirrored", inertia=inertia.tolist())
    state = cs.InitialState(omega=(0.3, -0.2, -5.0), euler_angles=(0.7, 0.4))
    original = cs.simulate(model, kane_levinson, state, 3.0)
    mirrored = cs.simulate(model, mirror, state.mirrored(), 3.0)
    spin, spin_m = original.dataset["spin"].values, mirrored.dataset["spin"].values
    assert np.max(np.abs(spin + spin_m)) < 1e-6 * np.max(np.abs(spin))
    omega, omega_m = original.dataset["omega"].values, mirrored.dataset["omega"].values
    np.testing.assert_allclose(omega_m, omega * [-1, 1, -1], atol=1e-6)


@pytest.mark.parametrize("cls", [cs.RollingModel, cs.SlidingModel, cs.HybridModel])
def test_negative_resistance_is_refused(cls: type) -> None:
    with pytest.raises(cs.ParameterError) as raised:
        cls(rolling_resistance=-1e-4)
    text = str(raised.value)
    assert "rolling_resistance" in text and "[0, 0.01]" in text and "\n" not in text


def test_rolling_resistance_is_recorded(kane_levinson: cs.Body) -> None:
    run = cs.simulate(cs.RollingModel(rolling_resistance=LAMBDA), kane_levinson, SPINNING, 0.1)
    assert run.dataset.attrs["rolling_resistance"] == LAMBDA
    summary = run.summary()
    assert summary["rolling_resistance"] == LAMBDA
    assert summary["rolling_resistance_rate"] == pytest.approx(1e-3)
