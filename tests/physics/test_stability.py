"""Linear stability of steady spin: the Jacobian of the compiled rolling kernel against the
exact characteristic quartic (../shared/references.md), exact limits, and growth rates fitted
from nonlinear runs started at a tiny tilt."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

import celtstone as cs
from celtstone.kernels import layout, system
from celtstone.simulation.models import kernel_parameters
from celtstone.stability import (
    MODE_NAMES,
    linearised_matrix,
    parse_spin_range,
    spin_stability,
)
from tests.physics.test_published import characteristic_roots

SPINS = np.linspace(-10.0, 10.0, 201)  # the default grid [rad/s]


def with_product_of_inertia(body: cs.Body, product: float) -> cs.Body:
    """``body`` with I12 = I21 = ``product`` [kg m²]."""
    inertia = [list(row) for row in body.inertia]
    inertia[0][1] = inertia[1][0] = product
    return dataclasses.replace(body, inertia=inertia)


def rest_geometry(body: cs.Body) -> tuple[float, float, float, float, float]:
    """A' = A + m l², B' = B + m l², D, P1 = ρ1 − l, P2 = ρ2 − l (references.md)."""
    inertia = np.array(body.inertia)
    ell = body.shape.rest_height
    rho1, rho2 = body.shape.radii_of_curvature
    a1 = inertia[0, 0] + body.mass * ell**2
    b1 = inertia[1, 1] + body.mass * ell**2
    return a1, b1, inertia[0, 1], rho1 - ell, rho2 - ell


def test_eigenvalues_are_the_roots_of_the_quartic(any_body: cs.Body) -> None:
    """Every eigenvalue on the default grid within 1e-8 relative of a root of the quartic."""
    result = spin_stability(any_body, SPINS)
    worst = 0.0
    for spin, eigenvalues in zip(SPINS, result.eigenvalues, strict=True):
        roots = characteristic_roots(any_body, spin)
        distance = np.abs(eigenvalues[:, None] - roots[None, :])
        rows, columns = linear_sum_assignment(distance)
        worst = max(worst, float(np.max(distance[rows, columns] / np.abs(roots[columns]))))
    assert worst < 1e-8


def test_spin_and_normal_perturbations_decouple(kane_levinson: cs.Body) -> None:
    """The full (n, ω) Jacobian, by plain central differences here: δn3 and δω3 neither
    drive nor are driven by the tilt at first order, so the 4-D block holds all the
    non-zero eigenvalues."""
    spin = -5.0
    params = kernel_parameters(cs.RollingModel(), kane_levinson)
    base = np.zeros(layout.N_STATE)
    base[layout.Y_N + 2], base[layout.Y_OMEGA + 2], base[layout.Y_QUAT] = 1.0, spin, 1.0
    indices = [layout.Y_N + k for k in range(3)] + [layout.Y_OMEGA + k for k in range(3)]
    full = np.zeros((6, 6))
    for column, index in enumerate(indices):
        rates = []
        for sign in (1.0, -1.0):
            y, dy = base.copy(), np.zeros(layout.N_STATE)
            y[index] += sign * 1e-7
            system.rhs(layout.ModelCode.ROLLING.value, 0.0, y, params, dy)
            rates.append(dy[indices])
        full[:, column] = (rates[0] - rates[1]) / 2e-7
    tilt = [0, 1, 3, 4]  # n1, n2, ω1, ω2
    other = [2, 5]  # n3, ω3
    scale = np.max(np.abs(full))
    assert np.max(np.abs(full[np.ix_(other, range(6))])) < 1e-9 * scale
    assert np.max(np.abs(full[np.ix_(tilt, other)])) < 1e-9 * scale
    block = linearised_matrix(kane_levinson, spin)
    assert np.allclose(full[np.ix_(tilt, tilt)], block, rtol=1e-6, atol=1e-6 * scale)


def test_modes_without_product_of_inertia(kane_levinson: cs.Body) -> None:
    """With D = 0 and no spin the modes separate: pitch λ² = −m g P1/B', roll λ² = −m g P2/A',
    both neutral; labels follow the eigenvectors, not the frequencies' order."""
    aligned = with_product_of_inertia(kane_levinson, 0.0)
    a1, b1, _, p1, p2 = rest_geometry(aligned)
    weight = aligned.mass * aligned.gravity
    result = spin_stability(aligned, [0.0])
    pitch = np.sqrt(weight * p1 / b1)
    roll = np.sqrt(weight * p2 / a1)
    expected = np.array([1j * pitch, -1j * pitch, 1j * roll, -1j * roll])
    assert np.allclose(result.eigenvalues[0], expected, rtol=1e-10, atol=1e-10 * pitch)
    assert result.growth_rate_pitch[0] == 0.0 and result.growth_rate_roll[0] == 0.0
    # swap the curvatures' roles by making the roll stiffer than the pitch
    stiff_roll = dataclasses.replace(aligned, shape=cs.Paraboloid((0.045, 2.0), 0.01))
    swapped = spin_stability(stiff_roll, [0.0])
    a1, b1, _, p1, p2 = rest_geometry(stiff_roll)
    assert swapped.frequency_pitch[0] == pytest.approx(np.sqrt(weight * p1 / b1), rel=1e-10)
    assert swapped.frequency_roll[0] == pytest.approx(np.sqrt(weight * p2 / a1), rel=1e-10)


@pytest.mark.parametrize("damping", [0.0, 1e-4])
def test_sum_of_eigenvalues(kane_levinson: cs.Body, damping: float) -> None:
    """Σλ = −D m l s (ρ2 − ρ1)/Δ (references.md) − σ (A' + B')/Δ (viscous torque −σω on the
    rocking rates through the inverse of [[A', D], [D, B']])."""
    a1, b1, d, p1, p2 = rest_geometry(kane_levinson)
    delta = a1 * b1 - d**2
    ell = kane_levinson.shape.rest_height
    result = spin_stability(kane_levinson, SPINS, cs.RollingModel(damping=damping))
    expected = -d * kane_levinson.mass * ell * SPINS * (p2 - p1) / delta
    expected -= damping * (a1 + b1) / delta
    assert np.allclose(result.eigenvalues.sum(axis=1).real, expected, rtol=1e-8, atol=1e-12)


def test_preferred_direction_follows_the_product_of_inertia(kane_levinson: cs.Body) -> None:
    """Kane & Levinson's body (D < 0, ρ1 > ρ2) prefers positive spin (references.md; the −5 rad/s
    start reverses); mirroring D prefers the other sense; D = 0 prefers neither."""
    assert spin_stability(kane_levinson, SPINS).preferred_direction == 1
    mirrored = with_product_of_inertia(kane_levinson, 2e-5)
    assert spin_stability(mirrored, SPINS).preferred_direction == -1
    aligned = spin_stability(with_product_of_inertia(kane_levinson, 0.0), SPINS)
    assert aligned.preferred_direction == 0
    assert aligned.max_growth_rate_positive == aligned.max_growth_rate_negative == 0.0
    # the preference does not need a symmetric grid: the mirror spins are computed
    assert spin_stability(kane_levinson, [2.0, 7.0]).preferred_direction == 1
    assert spin_stability(kane_levinson, [-7.0]).preferred_direction == 1


def test_preference_matches_the_growth_rates(kane_levinson: cs.Body) -> None:
    """Without dissipation neither sense is stable (the roll mode grows slowly at s > 0, the
    pitch mode fast at s < 0: Garcia & Hubbard 1988): the preferred sense is the slower one."""
    result = spin_stability(kane_levinson, SPINS)
    positive = SPINS > 0
    assert np.all(result.growth_rate_roll[positive] > 0.0)
    assert np.all(result.growth_rate_pitch[positive] < 0.0)
    assert np.all(result.growth_rate_pitch[~positive & (SPINS < 0)] > 0.0)
    assert not result.preferred_direction_is_stable
    assert result.max_growth_rate_positive == pytest.approx(np.max(result.growth_rate_roll))
    assert result.max_growth_rate_negative == pytest.approx(np.max(result.growth_rate_pitch))
    assert result.max_growth_rate_positive < result.max_growth_rate_negative


GROWING_SPINS = [-10.0, -5.0, 5.0, 10.0]  # [rad/s]
START_TILT = 1e-7  # Euler tilts α = β [deg]
LINEAR_TILT = 1e-3  # [rad]: the motion is linear below this tilt


@pytest.mark.parametrize("spin", GROWING_SPINS)
def test_growth_rate_of_nonlinear_runs(any_body: cs.Body, spin: float) -> None:
    """A run from a 1e-7° tilt: the peaks of the tilt grow as exp(σ t) and n1 (pitch) or n2
    (roll) crosses zero at 2ω/2π per second, with σ + iω the growing eigenvalue. The mode
    that grows, and the run's length (the tilt reaching 1e-3 rad), follow from the linear
    analysis of each body: the pitch mode at s < 0 for K&L and the toy, the other for the
    wider atlas stone."""
    linear = spin_stability(any_body, [spin])
    mode = "pitch" if linear.growth_rate_pitch[0] >= linear.growth_rate_roll[0] else "roll"
    growth = linear.growth_rate_pitch[0] if mode == "pitch" else linear.growth_rate_roll[0]
    assert growth > 0.0  # without dissipation one mode grows at every spin
    start_tilt = np.hypot(*np.radians([START_TILT, START_TILT]))
    duration = round(1.1 * np.log(LINEAR_TILT / start_tilt) / growth + 1.0, 1)  # [s]
    run = cs.simulate(
        cs.RollingModel(),
        any_body,
        cs.InitialState((0.0, 0.0, spin), (START_TILT, START_TILT)),
        duration,
        n_samples=round(2000 * duration) + 1,
    )
    assert run.ok
    time = run.dataset["time"].values
    vertical = run.dataset["n"].values
    tilt = np.hypot(vertical[:, 0], vertical[:, 1])
    peaks = np.flatnonzero((tilt[1:-1] > tilt[:-2]) & (tilt[1:-1] >= tilt[2:])) + 1
    # the growing mode dominates 1000 times the start; the motion is linear below 1e-3 rad
    window = peaks[(tilt[peaks] > 1e3 * tilt[0]) & (tilt[peaks] < LINEAR_TILT)]
    assert window.size >= 8  # a decade of growth: 29 peaks for the toy at -10 rad/s, 9 for
    # the printed stone, whose pitch mode grows fast (the fits below still check rate and frequency)
    fitted_growth = np.polyfit(time[window], np.log(tilt[window]), 1)[0]
    span = slice(window[0], window[-1])
    component, times = vertical[span, 0 if mode == "pitch" else 1], time[span]
    k = np.flatnonzero(np.signbit(component[1:]) != np.signbit(component[:-1]))
    zeros = times[k] - component[k] * (times[k + 1] - times[k]) / (component[k + 1] - component[k])
    fitted_frequency = np.pi * (zeros.size - 1) / (zeros[-1] - zeros[0])

    frequency = linear.frequency_pitch[0] if mode == "pitch" else linear.frequency_roll[0]
    assert growth == pytest.approx(np.max(linear.eigenvalues[0].real))  # the mode that grows
    assert fitted_growth == pytest.approx(growth, rel=2e-3)
    assert fitted_frequency == pytest.approx(frequency, rel=1e-3)


def test_summary_lists_eigenvalues_per_spin(kane_levinson: cs.Body) -> None:
    result = spin_stability(kane_levinson, [-1.0, 0.0, 1.0])
    summary = result.summary()
    assert summary["spin"] == [-1.0, 0.0, 1.0]
    assert summary["modes"] == list(MODE_NAMES)
    assert np.array(summary["eigenvalues"]).shape == (3, 4, 2)
    pairs = np.array(summary["eigenvalues"])
    assert np.array_equal(pairs[..., 0] + 1j * pairs[..., 1], result.eigenvalues)
    assert summary["preferred_spin_direction"] == "positive"
    dataset = result.to_dataset()
    assert dataset.attrs["body"] == kane_levinson.name
    assert dataset.attrs["spin_count"] == 3
    assert dataset["growth_rate_roll"].attrs["units"] == "1/s"


def test_bad_input_is_refused(kane_levinson: cs.Body) -> None:
    tilted = [list(row) for row in kane_levinson.inertia]
    tilted[0][2] = tilted[2][0] = 1e-6
    with pytest.raises(cs.ParameterError, match="I13 = I23 = 0"):
        spin_stability(dataclasses.replace(kane_levinson, inertia=tilted), [1.0])
    with pytest.raises(cs.ParameterError, match="rolling model"):
        linearised_matrix(kane_levinson, 1.0, cs.SlidingModel())  # type: ignore[arg-type]
    with pytest.raises(cs.ParameterError, match="finite"):
        spin_stability(kane_levinson, [1.0, float("nan")])
    with pytest.raises(cs.ParameterError, match="spin"):
        spin_stability(kane_levinson, [])


@pytest.mark.parametrize(
    "text", ["-10:10", "a:1:3", "1:-1:3", "0:1:0", "0:1:1", "1:1:5", "0:1:2.5", "0:inf:3"]
)
def test_bad_spin_ranges(text: str) -> None:
    with pytest.raises(cs.ParameterError, match="START:STOP:COUNT"):
        parse_spin_range(text)


def test_spin_range_is_linspace() -> None:
    assert np.array_equal(parse_spin_range("-10:10:201"), SPINS)
    assert np.array_equal(parse_spin_range("3:3:1"), [3.0])
