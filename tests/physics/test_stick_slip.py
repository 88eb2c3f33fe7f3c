"""The hybrid (stick–slip) contact, issue 5 part 2.

Oracles: the algebra of Zhuravlev's Padé law (paper eq. 10, 12), an independent SciPy
integration of rolling without pivoting written as a Lagrange-multiplier (KKT) system on
the test oracle's rolling equations, invariants (energy, |n| = 1, V1 = 0 and ω · n = 0 in
stick), the plain sliding model where the hybrid contact must equal it, and convergence
of the phase times as the numerical zero v_c and the tolerance shrink.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import json
import math

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import solve_ivp

import celtstone as cs
from celtstone import solvers
from celtstone.kernels import layout
from celtstone.kernels import stick as stick_kernels
from celtstone.kernels.friction import contact_friction, pade_friction
from celtstone.simulation.models import initial_vector, kernel_parameters
from tests.oracle import rattleback as oracle
from tests.test_cli import Result

B = 8.0 / (3.0 * math.pi)  # paper eq. (12)
A = 15.0 * math.pi / 16.0
KL_START = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))  # references.md
ROCKING_START = cs.InitialState(omega=(0.0, 0.0, 0.0), euler_angles=(1.0, 0.3))  # no spin, no slip


# ------------------------------------------------------------------ the limit set (5)


def test_pade_boundary_eliminates_u() -> None:
    """φ = u/(u + b), μ = 1/(1 + a u) lie on μ = (1 - φ)/(1 + (ab - 1)φ), ab = 5/2."""
    assert A * B == pytest.approx(2.5, rel=1e-15)
    friction_normal, f, eps = 9.81, 0.35, 1e-3
    m0 = 3.0 * math.pi / 16.0 * f * friction_normal * eps
    for u in np.logspace(-6, 6, 61):
        phi, mu = u / (u + B), 1.0 / (1.0 + A * u)
        assert mu == pytest.approx((1.0 - phi) / (1.0 + 1.5 * phi), rel=1e-12)
        margin = stick_kernels.pade_stick_margin(phi * f * friction_normal, mu * m0, 9.81, f, eps)
        assert abs(margin) < 1e-12
        # inside (less force and moment) stick holds; outside it does not
        inside = stick_kernels.pade_stick_margin(
            0.9 * phi * f * friction_normal, 0.9 * mu * m0, 9.81, f, eps
        )
        outside = stick_kernels.pade_stick_margin(
            1.1 * phi * f * friction_normal, 1.1 * mu * m0, 9.81, f, eps
        )
        assert inside > 0.0 > outside
    assert stick_kernels.pade_stick_margin(0.0, 0.0, 9.81, f, eps) == 1.0
    assert stick_kernels.pade_stick_margin(0.0, 0.0, 9.81, 0.0, eps) < 0.0  # no friction


def test_sliding_friction_lies_on_the_stick_boundary() -> None:
    """Every force/moment pair the sliding law produces has stick margin 0 (δ = 0)."""
    rng = np.random.default_rng(5)
    eps, f, normal = 1e-3, 0.35, 9.81
    for _ in range(50):
        slip = (*tuple(rng.normal(size=2) * 10.0 ** rng.uniform(-6, -1)), 0.0)
        spin = rng.normal() * 10.0 ** rng.uniform(-3, 1)
        force, moment = pade_friction(slip, spin, eps, 0.0)
        margin = stick_kernels.pade_stick_margin(
            f * normal * math.hypot(*force), f * normal * abs(moment), normal, f, eps
        )
        assert abs(margin) < 1e-12


@pytest.mark.parametrize("pressure", [pressure.value for pressure in layout.ContactPressure])
@pytest.mark.parametrize("law", [law.value for law in layout.FrictionLaw])
def test_every_law_slides_on_its_own_stick_boundary(law: int, pressure: int) -> None:
    """For each law and pressure, the (|F|, |M|) that sliding at slip ratio u produces
    has stick margin 0; 10 % less of both is inside (margin > 0), 10 % more outside."""
    eps, f, normal = 1e-3, 0.35, 9.81
    for u in np.logspace(-4, 4, 41):
        force, moment = contact_friction((u * eps, 0.0, 0.0), 1.0, eps, 0.0, law, pressure)
        args = (normal, f, eps, law, pressure)
        margin = stick_kernels.stick_margin_of(
            f * normal * math.hypot(*force), f * normal * abs(moment), *args
        )
        assert abs(margin) < 1e-10  # the exact law is inverted by bisection: about 1e-12
        inside = stick_kernels.stick_margin_of(
            0.9 * f * normal * math.hypot(*force), 0.9 * f * normal * abs(moment), *args
        )
        outside = stick_kernels.stick_margin_of(
            1.1 * f * normal * math.hypot(*force), 1.1 * f * normal * abs(moment), *args
        )
        assert inside > 0.0 > outside
    # the ends: the full moment without force, no moment at the full force
    assert stick_kernels.limit_moment(0.0, law, pressure) == 1.0
    assert stick_kernels.limit_moment(1.0, law, pressure) == 0.0


def test_exact_and_pade_limit_sets_differ_as_their_laws() -> None:
    """The exact Hertz limit set is larger than Padé's where the laws differ most: at
    φ = F̂(1) = 9π/32 the exact law gives M̂(1)/M̂(0) = 3/8; Padé's boundary there is lower."""
    phi = 9.0 * math.pi / 32.0
    hertz = layout.ContactPressure.HERTZ.value
    exact = stick_kernels.limit_moment(phi, layout.FrictionLaw.EXACT.value, hertz)
    pade = stick_kernels.limit_moment(phi, layout.FrictionLaw.PADE.value, hertz)
    assert exact == pytest.approx((3.0 * math.pi / 128.0 * 3.0) / (3.0 * math.pi / 16.0), rel=1e-12)
    assert pade == pytest.approx((1.0 - phi) / (1.0 + 1.5 * phi), rel=1e-15)
    assert exact > pade


def test_hybrid_run_with_the_exact_law_sticks_and_slips(kane_levinson: cs.Body) -> None:
    """The hybrid contact with the exact law: phases alternate, and each stick phase
    starts where the exact limit set still holds the contact."""
    run = cs.simulate(
        cs.HybridModel(friction_law="exact"), kane_levinson, KL_START, 2.0, n_samples=401
    )
    assert run.ok
    summary = run.summary()
    assert summary["friction_law"] == "exact"
    assert summary["stick_phases"] >= 1 and summary["slip_phases"] >= 1
    kinds = [phase["kind"] for phase in summary["phases"]]
    assert all(a != b for a, b in itertools.pairwise(kinds))


def test_capture_impulse_obeys_carnots_theorem(kane_levinson: cs.Body) -> None:
    """A plastic impact loses the kinetic energy of the lost velocities (Carnot):
    E - E' = ½ m |Δv_G|² + ½ Δω · A Δω, and leaves V1 = 0, ω · n = 0."""
    params = kernel_parameters(cs.HybridModel(), kane_levinson)
    y = initial_vector(cs.InitialState(omega=(0.3, -0.2, 0.1), euler_angles=(3.0, -2.0)))
    n = y[0:3]
    slip = np.cross(n, [1e-3, 2e-3, 0.0])  # horizontal, V1 · n = 0
    y[6:9] = slip
    captured, jump, _ = solvers.capture(params, y)
    omega, omega_after = y[3:6], captured[3:6]
    assert np.all(captured[6:9] == 0.0)
    assert abs(omega_after @ n) < 1e-15
    r = oracle.contact_point(n, oracle.kane_levinson_body())
    lost_velocity = (slip - np.cross(omega, r)) - (-np.cross(omega_after, r))
    lost_rotation = omega - omega_after
    inertia = np.array(kane_levinson.inertia)
    mass = kane_levinson.mass
    carnot = (
        0.5 * mass * lost_velocity @ lost_velocity + 0.5 * lost_rotation @ inertia @ lost_rotation
    )
    assert carnot > 1e-8  # a real loss, far above round-off
    assert -jump == pytest.approx(carnot, rel=1e-9)
    assert captured[15] - y[15] == pytest.approx(carnot, rel=1e-9)  # booked as dissipated work


# ---------------------------------------------- stick = rolling without pivoting (1)


def _stick_oracle(body: dict, y0: np.ndarray, t_end: float, times: np.ndarray) -> np.ndarray:
    """Rolling without pivoting, integrated by SciPy from the oracle's rolling model:
    [J -n; nᵀ 0] (ω̇, M) = (τ, 0), τ = J ω̇_rolling; returns (n, ω) at ``times``."""

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        state = np.concatenate([y, [0.0]])
        n_dot, omega_dot_rolling, r, _ = oracle._rolling_acceleration(state, body, 0.0)
        m = body["mass"]
        inertia_contact = body["inertia"] + m * (r @ r * np.eye(3) - np.outer(r, r))
        kkt = np.zeros((4, 4))
        kkt[:3, :3] = inertia_contact
        kkt[:3, 3] = -y[0:3]
        kkt[3, :3] = y[0:3]
        solution = np.linalg.solve(kkt, np.concatenate([inertia_contact @ omega_dot_rolling, [0]]))
        return np.concatenate([n_dot, solution[:3]])

    result = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", t_eval=times, rtol=1e-10, atol=1e-12)
    assert result.success
    return result.y.T


@pytest.fixture(scope="module")
def rocking(kane_levinson: cs.Body) -> cs.Trajectory:
    """Put down without spin or slip, tilted, on a high-friction plane: it sticks."""
    model = cs.HybridModel(friction_coefficient=1.0, contact_radius=1e-3)
    return cs.simulate(model, kane_levinson, ROCKING_START, 1.0, n_samples=101)


def test_rocking_body_sticks_like_rolling_without_pivoting(
    kane_levinson: cs.Body, rocking: cs.Trajectory
) -> None:
    assert rocking.ok, rocking.message
    summary = rocking.summary()
    assert summary["phases"] == [
        {"kind": "stick", "t_start": 0.0, "t_end": 1.0, "energy_jump": 0.0}
    ]
    ds = rocking.dataset
    assert np.all(ds["phase"].values == 1)
    assert np.all(ds["slip_velocity"].values == 0.0)
    assert np.max(np.abs(ds["spin"].values)) < 1e-11  # ω · n held at 0 [rad/s]
    energy = ds["energy"].values
    assert np.max(np.abs(energy - energy[0])) < 1e-9 * energy[0]  # constraints do no work
    assert np.max(np.abs(ds["dissipated_work"].values)) < 1e-15
    # the stone really rocks and the pivot moment is needed (D ≠ 0), so the test bites
    assert np.ptp(np.degrees(ds["tilt"].values)) > 0.5
    rolling = cs.simulate(cs.RollingModel(), kane_levinson, ROCKING_START, 1.0, n_samples=101)
    assert np.max(np.abs(rolling.dataset["spin"].values)) > 1e-3  # rolling alone would spin
    y0 = initial_vector(ROCKING_START)[:6]
    expected = _stick_oracle(oracle.kane_levinson_body(), y0, 1.0, ds["time"].values)
    np.testing.assert_allclose(ds["n"].values, expected[:, 0:3], atol=1e-8)
    np.testing.assert_allclose(ds["omega"].values, expected[:, 3:6], atol=1e-7)


def test_stick_of_a_body_without_product_of_inertia_is_rolling(kane_levinson: cs.Body) -> None:
    """D = 0, tilted about body axis 1 only: rolling keeps ω · n = 0 by itself (M = 0)."""
    inertia = np.diag(np.diag(np.array(kane_levinson.inertia)))
    aligned = dataclasses.replace(kane_levinson, inertia=inertia.tolist())
    state = cs.InitialState(omega=(0.0, 0.0, 0.0), euler_angles=(2.0, 0.0))
    stick = cs.simulate(cs.HybridModel(friction_coefficient=1.0), aligned, state, 1.0)
    rolling = cs.simulate(cs.RollingModel(), aligned, state, 1.0)
    assert stick.summary()["stick_phases"] == 1
    assert stick.summary()["slip_phases"] == 0
    np.testing.assert_allclose(stick.dataset["omega"], rolling.dataset["omega"], atol=1e-9)
    np.testing.assert_allclose(stick.dataset["normal_force"], rolling.dataset["normal_force"])


def test_stick_with_damping_keeps_the_energy_budget(kane_levinson: cs.Body) -> None:
    model = cs.HybridModel(friction_coefficient=1.0, damping=1e-5)
    run = cs.simulate(model, kane_levinson, ROCKING_START, 1.0)
    ds = run.dataset
    assert run.summary()["stick_phases"] == 1
    budget = ds["energy"].values + ds["dissipated_work"].values
    assert ds["dissipated_work"].values[-1] > 1e-7
    assert np.max(np.abs(budget - budget[0])) < 1e-10 * budget[0]


# ------------------------------------------------------------------ stick impossible (2)


def test_low_friction_never_sticks_and_equals_sliding(kane_levinson: cs.Body) -> None:
    """f = 0.001 cannot hold the rocking stone: the hybrid run is the sliding run."""
    hybrid_model = cs.HybridModel(friction_coefficient=1e-3)
    sliding_model = cs.SlidingModel(
        friction_coefficient=1e-3, regularisation_speed=hybrid_model.regularisation_speed
    )
    run = cs.simulate(hybrid_model, kane_levinson, ROCKING_START, 1.0)
    reference = cs.simulate(sliding_model, kane_levinson, ROCKING_START, 1.0)
    assert run.summary()["stick_phases"] == 0
    assert run.summary()["slip_phases"] == 1
    assert np.max(run.dataset["slip_speed"].values) > 1e-3  # it does slide
    for name in ("n", "omega", "slip_velocity"):
        np.testing.assert_allclose(run.dataset[name], reference.dataset[name], atol=1e-9)


# ---------------------------------------------- spin: Contensou (3), K&L run (4)


@pytest.fixture(scope="module")
def kane_levinson_hybrid(kane_levinson: cs.Body) -> cs.Trajectory:
    """Issue 5: K&L at f = 0.35, ε = 1 mm from w3 = -5 rad/s, hybrid contact."""
    model = cs.HybridModel(friction_coefficient=0.35, contact_radius=1e-3)
    return cs.simulate(model, kane_levinson, KL_START, 8.0)


def test_spinning_stone_slides_until_slip_and_spin_vanish(
    kane_levinson: cs.Body, kane_levinson_hybrid: cs.Trajectory
) -> None:
    """With ω · n ≠ 0 any tangential force makes the contact slide (Contensou): the
    hybrid run is the sliding run until slip and spin both reach zero."""
    run = kane_levinson_hybrid
    phases = run.summary()["phases"]
    first_stick = phases[1]["t_start"]
    assert phases[0]["kind"] == "slip" and phases[1]["kind"] == "stick"
    model = cs.SlidingModel(0.35, 1e-3, regularisation_speed=1e-12)
    times = run.dataset["time"].values
    before = times[times <= first_stick]
    reference = cs.simulate(model, kane_levinson, KL_START, float(before[-1]), sample_times=before)
    # equal to the solver's accuracy (captures refused for want of stick restart the steps)
    for name in ("n", "omega", "slip_velocity"):
        np.testing.assert_allclose(
            run.dataset[name].values[: before.size], reference.dataset[name].values, atol=1e-8
        )
    # until then the contact always slid or pivoted: sqrt(|V1|² + ε²Ω²) > v_c
    capture = run.summary()["capture_speed"]
    assert capture == 100 * run.dataset.attrs["atol"]
    slip_spin = np.hypot(reference.dataset["slip_speed"], 1e-3 * reference.dataset["spin"])
    assert np.min(slip_spin[1:]) > capture  # the first sample is the rest contact
    assert np.min(slip_spin[1:]) < 1e-4  # ... and came near zero before sticking


def test_kane_levinson_phases_and_energy_budget(kane_levinson_hybrid: cs.Trajectory) -> None:
    run = kane_levinson_hybrid
    assert run.ok, run.message
    summary = run.summary()
    phases = summary["phases"]
    assert summary["stick_phases"] >= 2 and summary["slip_phases"] >= 2
    assert summary["stick_phases"] + summary["slip_phases"] == len(phases)
    kinds = [p["kind"] for p in phases]
    assert all(a != b for a, b in itertools.pairwise(kinds))  # they alternate
    assert phases[0]["t_start"] == 0.0 and phases[-1]["t_end"] == 8.0
    for before, after in itertools.pairwise(phases):
        assert before["t_end"] == after["t_start"] and after["t_start"] > before["t_start"]
    ds = run.dataset
    energy, work = ds["energy"].values, ds["dissipated_work"].values
    assert work[-1] > 0.1 * energy[0]  # friction took a fifth of the energy
    assert np.max(np.abs(energy[0] - energy - work)) < 1e-9 * energy[0]
    assert np.max(np.abs(np.linalg.norm(ds["n"].values, axis=1) - 1.0)) < 1e-10
    # the capture impulse removes ~ ½ C (v_c/ε)² ≈ 1e-17 J: round-off of E ≈ 0.1 J
    jumps = np.array([p["energy_jump"] for p in phases])
    assert np.max(np.abs(jumps)) < 1e-15
    stick = ds["phase"].values == 1
    assert np.all(ds["slip_speed"].values[stick] == 0.0)
    assert np.max(np.abs(ds["spin"].values[stick])) < 1e-10
    assert np.max(ds["slip_speed"].values[~stick]) > 1e-2


@functools.cache
def _switch_times(capture: float, tolerance: float) -> np.ndarray:
    """Phase-change times of the K&L hybrid run over 6.7 s (δ = 1e-13 m/s) [s]."""
    model = cs.HybridModel(0.35, 1e-3, regularisation_speed=1e-13)
    params = kernel_parameters(model, cs.load_body("kane_levinson_1982"))
    solution = solvers.solve_phases(
        params,
        initial_vector(KL_START),
        6.7,
        slip_method="radau5",
        stick_method="dop853",
        rtol=tolerance,
        atol=1e-12,
        capture_speed=capture,
        sample_times=np.array([0.0]),
        max_crossings=1000,
        max_steps=10_000_000,
    )
    return solution.phase_end[:-1]


@pytest.mark.parametrize(
    ("capture_speed", "rtol"), [(1e-8, 1e-10), (1e-9, 1e-10), (1e-9, 1e-9)], ids=str
)
def test_phase_times_converge_as_the_numerical_zero_shrinks(
    kane_levinson: cs.Body, capture_speed: float, rtol: float
) -> None:
    """Switch times move linearly with v_c (the time the dying spin takes to cross
    v_c/ε), by ~1e3 s²/m · v_c here, and not with rtol: v_c is a numerical zero, not a
    regularisation constant."""
    finest = _switch_times(1e-10, 1e-10)
    trial = _switch_times(capture_speed, rtol)
    assert finest.size == trial.size >= 4
    # a stick phase starts late by the time v_c/ε of spin takes to die, ~1e3 s²/m · v_c
    assert np.max(np.abs(trial - finest)) < 2e3 * capture_speed
    if capture_speed == 1e-8:
        assert np.max(np.abs(trial - finest)) > 1e-6  # the dependence is real and linear


# ------------------------------------------------------------------ CLI and files (6)


def test_cli_reports_the_phases_in_json_and_netcdf(tmp_path) -> None:
    target = tmp_path / "hybrid.nc"
    result = Result(
        [
            "run",
            "--model",
            "sliding",
            "--contact",
            "hybrid",
            "--friction-coefficient",
            "1",
            "--omega",
            "0,0,0",
            "--euler-angles",
            "1,0.3",
            "--t-end",
            "0.5",
            "--capture-speed",
            "1e-9",
            "--json",
            "--out",
            str(target),
        ]
    )
    assert result.status == 0, result.err
    summary = result.json()
    assert summary["contact"] == "hybrid"
    assert summary["stick_phases"] == 1 and summary["slip_phases"] == 0
    assert summary["phases"][0]["kind"] == "stick"
    assert summary["capture_speed"] == 1e-9
    assert summary["regularisation_speed"] == 1e-12
    assert summary["stick_method"] == "dop853"
    json.dumps(summary, allow_nan=False)
    with xr.open_dataset(target) as saved:
        assert saved.attrs["contact"] == "hybrid"
        assert saved.attrs["capture_speed"] == 1e-9
        assert saved["phase"].attrs["units"] == "1"
        assert np.all(saved["phase"].values == 1)
        assert saved["phase_start"].values.tolist() == [0.0]
    plain = Result(["run", "--model", "sliding", "--t-end", "0.2", "--json"])
    assert plain.json()["contact"] == "sliding" and "phases" not in plain.json()


@pytest.mark.parametrize(
    ("argv", "name"),
    [
        (["--model", "rolling", "--contact", "hybrid"], "contact"),
        (["--model", "sliding", "--contact", "stiction"], "contact"),
        (["--model", "sliding", "--contact", "hybrid", "--capture-speed", "0"], "capture_speed"),
        (
            ["--model", "sliding", "--contact", "hybrid", "--regularisation-speed", "1e-6"],
            "regularisation_speed",
        ),
    ],
)
def test_cli_refuses_bad_contact_options(argv: list[str], name: str) -> None:
    result = Result(["run", *argv, "--t-end", "0.1"])
    assert result.status == 2
    assert result.err.count("\n") == 1 and name in result.err
