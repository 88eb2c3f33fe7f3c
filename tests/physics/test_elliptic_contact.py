"""Runs with the elliptic Hertz contact (``contact_shape = "ellipse"``, issue 13 item 3).

The invariants every sliding model keeps (energy lost = friction work, |n| = 1,
V1 · n = 0, the mirror image), the round limit (a sphere's ellipse is the circle of
the circular Hertz radius), the kernel's ellipse against the SciPy reference at the
current contact point, and bad settings refused.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

import celtstone as cs
from celtstone.contact.ellipse import hertz_ellipse
from celtstone.kernels.dynamics import friction_per_unit_load
from celtstone.kernels.hertz_ellipse import hertz_ellipse_axes, principal_radii
from celtstone.simulation.models import kernel_parameters
from tests.conftest import LITERATURE_EULER_ANGLES

# E = 3 GPa, ν = 0.35: Kane & Levinson's circular Hertz radius is ε = 1.09 mm (equations.md)
ELASTIC = {"elastic_modulus": 3e9, "poisson_ratio": 0.35}
ELLIPSE = cs.SlidingModel(friction_coefficient=0.35, contact_shape="ellipse", **ELASTIC)
STATE = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=LITERATURE_EULER_ANGLES)


@pytest.fixture(scope="module")
def ellipse_run(kane_levinson: cs.Body) -> cs.Trajectory:
    run = cs.simulate(ELLIPSE, kane_levinson, STATE, 4.0, rtol=1e-9)
    assert run.ok, run.message
    return run


def test_energy_lost_equals_friction_work(ellipse_run: cs.Trajectory) -> None:
    """E(0) − E(t) = W(t) to the solver's accuracy; the work never decreases."""
    ds = ellipse_run.dataset
    energy, work = ds["energy"].values, ds["dissipated_work"].values
    assert work[-1] > 1e-4 * energy[0]
    assert np.max(np.abs(energy[0] - energy - work)) < 1e-6 * energy[0]
    assert np.all(np.diff(work) >= -1e-12)


def test_unit_vertical_and_horizontal_slip_are_held(ellipse_run: cs.Trajectory) -> None:
    ds = ellipse_run.dataset
    n = ds["n"].values
    assert np.max(np.abs(np.linalg.norm(n, axis=1) - 1.0)) < 1e-8
    assert np.max(np.abs(np.einsum("ij,ij->i", ds["slip_velocity"].values, n))) < 1e-10


def test_the_ellipse_changes_the_motion(kane_levinson: cs.Body, ellipse_run: cs.Trajectory) -> None:
    """The circle of the same E, ν (ε = 1.09 mm) pivots with a 1.86 times smaller moment:
    the two runs differ well beyond the tolerance."""
    circle = cs.SlidingModel(friction_coefficient=0.35, **ELASTIC)
    circle_run = cs.simulate(circle, kane_levinson, STATE, 4.0, rtol=1e-9)
    spin, spin_circle = ellipse_run.dataset["spin"].values, circle_run.dataset["spin"].values
    assert np.max(np.abs(spin - spin_circle)) > 1e-2


def _mirror_body(body: cs.Body) -> cs.Body:
    inertia = np.array(body.inertia)
    inertia[0, 1] = inertia[1, 0] = -inertia[0, 1]
    inertia[1, 2] = inertia[2, 1] = -inertia[1, 2]
    return dataclasses.replace(body, name=body.name + "_mirrored", inertia=inertia.tolist())


def test_mirrored_body_spins_the_mirrored_way(kane_levinson: cs.Body) -> None:
    """Reflect in x2 = 0: the ellipse's axes reflect with the body, the spin changes sign."""
    state = cs.InitialState(omega=(0.3, -0.2, -5.0), euler_angles=(0.7, 0.4))
    original = cs.simulate(ELLIPSE, kane_levinson, state, 3.0)
    mirrored = cs.simulate(ELLIPSE, _mirror_body(kane_levinson), state.mirrored(), 3.0)
    spin, spin_m = original.dataset["spin"].values, mirrored.dataset["spin"].values
    assert np.max(np.abs(spin + spin_m)) < 1e-6 * np.max(np.abs(spin))
    np.testing.assert_allclose(
        mirrored.dataset["omega"].values, original.dataset["omega"].values * [-1, 1, -1], atol=1e-6
    )


def test_a_sphere_has_the_circle_of_todays_hertz_radius() -> None:
    """Equal principal radii everywhere: the ellipse is the circle (3NR/(4E*))^(1/3) and the
    friction equals the circle's Hertz-radius law to round-off, at any tilt and load."""
    sphere = cs.Body(
        name="sphere",
        mass=0.5,
        inertia=[[2e-4, 0.0, 0.0], [0.0, 2e-4, 0.0], [0.0, 0.0, 2e-4]],
        shape=cs.Ellipsoid(semi_axes=(0.05, 0.05, 0.05), com_offset=0.01),
    )
    round_params = kernel_parameters(dataclasses.replace(ELLIPSE), sphere)
    circle_params = kernel_parameters(cs.SlidingModel(friction_coefficient=0.35, **ELASTIC), sphere)
    rng = np.random.default_rng(11)
    for _ in range(20):
        n = np.array([*rng.normal(scale=0.2, size=2), 1.0])
        n = tuple(n / np.linalg.norm(n))
        slip = rng.normal(scale=1e-3, size=3)
        slip = tuple(slip - np.dot(slip, n) * np.array(n))
        spin = float(rng.normal(scale=3.0))
        load = float(rng.uniform(1.0, 10.0))
        force, moment = friction_per_unit_load(n, slip, spin, load, round_params)
        force_c, moment_c = friction_per_unit_load(n, slip, spin, load, circle_params)
        np.testing.assert_allclose(force, force_c, rtol=1e-13, atol=1e-16)
        assert moment == pytest.approx(moment_c, rel=1e-13, abs=1e-20)


def test_the_kernels_ellipse_is_the_reference_ellipse(kane_levinson: cs.Body) -> None:
    """At tilted contacts: radii from the kernel, semi-axes against SciPy's Johnson §4.2."""
    params = kernel_parameters(ELLIPSE, kane_levinson)
    modulus = ELLIPSE.effective_modulus
    load = kane_levinson.mass * kane_levinson.gravity
    rng = np.random.default_rng(5)
    for _ in range(10):
        n = np.array([*rng.normal(scale=0.1, size=2), 1.0])
        n = tuple(n / np.linalg.norm(n))
        radius_major, radius_minor, _ = principal_radii(n, params)
        semi_major, semi_minor = hertz_ellipse_axes(radius_major, radius_minor, load, modulus)
        reference = hertz_ellipse((radius_major, radius_minor), load, modulus)
        assert semi_major == pytest.approx(reference.semi_major_axis, rel=1e-12)
        assert semi_minor == pytest.approx(reference.semi_minor_axis, rel=1e-12)
    # at rest: 3.139 mm × 0.279 mm (equations.md, issue 13)
    radius_major, radius_minor, _ = principal_radii((0.0, 0.0, 1.0), params)
    semi_major, semi_minor = hertz_ellipse_axes(radius_major, radius_minor, load, modulus)
    assert semi_major == pytest.approx(3.139e-3, rel=2e-3)
    assert semi_minor == pytest.approx(0.2790e-3, rel=2e-3)


def test_zero_slip_moment_is_the_ellipses(kane_levinson: cs.Body) -> None:
    """V1 = 0, δ → 0: M = (3/8) f N A E(e) at the rest contact (per unit f N: (3/8) A E(e))."""
    from scipy.special import ellipe

    model = dataclasses.replace(ELLIPSE, regularisation_speed=1e-300)
    params = kernel_parameters(model, kane_levinson)
    load = kane_levinson.mass * kane_levinson.gravity
    n = (0.0, 0.0, 1.0)
    radius_major, radius_minor, _ = principal_radii(n, params)
    semi_major, semi_minor = hertz_ellipse_axes(
        radius_major, radius_minor, load, model.effective_modulus
    )
    _, moment = friction_per_unit_load(n, (0.0, 0.0, 0.0), 2.0, load, params)
    expected = 0.375 * semi_major * ellipe(1.0 - (semi_minor / semi_major) ** 2)
    assert moment == pytest.approx(-expected, rel=1e-12)


@pytest.mark.parametrize(
    ("settings", "name"),
    [
        ({"contact_shape": "ellipse"}, "contact_shape"),
        (
            {"contact_shape": "ellipse", "contact_pressure": "uniform", **ELASTIC},
            "contact_pressure",
        ),
        ({"contact_shape": "elipse", **ELASTIC}, "contact_shape"),
    ],
)
def test_bad_settings_are_refused(settings: dict, name: str) -> None:
    with pytest.raises(cs.ParameterError) as caught:
        cs.SlidingModel(**settings)
    assert caught.value.name == name


def test_stick_slip_with_the_ellipse_never_gains_energy(kane_levinson: cs.Body) -> None:
    """The hybrid contact with the ellipse's limit set: the stone sticks and slips many
    times, no phase change adds energy (beyond round-off of E0), the budget closes, and the
    energy ends where the regularised contact's does (δ = 1e-10 m/s is unbiased, §4)."""
    hybrid = cs.HybridModel(friction_coefficient=0.35, contact_shape="ellipse", **ELASTIC)
    run = cs.simulate(hybrid, kane_levinson, STATE, 5.0)
    assert run.ok, run.message
    summary = run.summary()
    energy0 = summary["energy_initial"]
    assert summary["stick_phases"] >= 10
    assert all(p["energy_jump"] <= 1e-12 * energy0 for p in summary["phases"])
    assert summary["max_energy_balance_error"] < 1e-8 * energy0
    sliding = cs.simulate(ELLIPSE, kane_levinson, STATE, 5.0).summary()
    assert summary["energy_final"] == pytest.approx(sliding["energy_final"], rel=1e-6)


def test_cli_runs_the_ellipse_and_records_it(capsys: pytest.CaptureFixture[str]) -> None:
    from celtstone.cli.main import main

    code = main(
        [
            "run",
            "--model",
            "sliding",
            "--contact-shape",
            "ellipse",
            "--elastic-modulus",
            "3e9",
            "--poisson-ratio",
            "0.35",
            "--t-end",
            "0.2",
            "--json",
        ]
    )
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["status"] == "success"
    assert math.isfinite(summary["spin_final"])
    assert summary["contact_shape"] == "ellipse"


def test_cli_refuses_an_ellipse_without_elastic_constants(
    capsys: pytest.CaptureFixture[str],
) -> None:
    from celtstone.cli.main import main

    code = main(["run", "--model", "sliding", "--contact-shape", "ellipse", "--t-end", "0.1"])
    assert code == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1
    assert "contact_shape" in error and "elastic" in error


def test_a_sweep_takes_the_ellipse(kane_levinson: cs.Body) -> None:
    """``contact_shape`` is a fixed setting of a sweep like any other: each point is the
    run, with the sweep's contact (stick–slip) and tolerances."""
    from celtstone.sweep import Sweep

    fixed = {"contact_shape": "ellipse", **ELASTIC}
    sweep = Sweep({"friction_coefficient": [0.2, 0.35]}, model="sliding", fixed=fixed, t_end=0.3)
    results = sweep.run()
    for index, friction in enumerate((0.2, 0.35)):
        model = cs.HybridModel(friction_coefficient=friction, **fixed)
        state = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
        run = cs.simulate(model, kane_levinson, state, 0.3, rtol=sweep.rtol, atol=sweep.atol)
        assert results["spin_final"].values[index] == pytest.approx(
            run.summary()["spin_final"], rel=1e-12
        )


THIN = cs.Body(
    name="thin_cap",
    mass=0.2,
    inertia=[[1e-5, 0.0, 0.0], [0.0, 1e-4, 0.0], [0.0, 0.0, 1e-4]],
    shape=cs.Paraboloid(radii_of_curvature=(10.0, 0.01), com_height=0.005),
)


def test_a_contact_beyond_the_tables_range_is_refused_before_the_run() -> None:
    """R1/R2 = 1000 gives B/A < 0.02 at rest: one error naming the setting and the ratio."""
    with pytest.raises(cs.ParameterError) as caught:
        cs.simulate(ELLIPSE, THIN, STATE, 0.1)
    assert caught.value.name == "contact_shape"
    assert "B/A" in str(caught.value) and "circle" in str(caught.value)
    circle = cs.simulate(cs.SlidingModel(friction_coefficient=0.35), THIN, STATE, 0.01)
    assert circle.ok


def test_leaving_the_range_during_a_run_is_a_status_not_a_nan() -> None:
    """The right-hand side reports ``RHS_CONTACT_RANGE`` where the ellipse's law has no
    value, and the driver turns it into the ``contact_range`` status with its message."""
    from celtstone.kernels.layout import MODEL_SLIDING, RHS_CONTACT_RANGE, parameter_record
    from celtstone.kernels.system import rhs
    from celtstone.simulation.models import initial_vector
    from celtstone.solvers.codes import Status
    from celtstone.solvers.driver import rhs_failure

    params = kernel_parameters(cs.SlidingModel(friction_coefficient=0.35), THIN)
    fields = {name: params[name] for name in params.dtype.names}
    fields.update(contact_shape=1, effective_modulus=ELLIPSE.effective_modulus)
    thin = parameter_record(**fields)
    y = initial_vector(STATE)
    assert rhs(MODEL_SLIDING, 0.0, y, thin, np.zeros_like(y))[0] == RHS_CONTACT_RANGE
    status = Status(rhs_failure(RHS_CONTACT_RANGE))
    assert status.label == "contact_range" and "B/A < 0.02" in status.message
