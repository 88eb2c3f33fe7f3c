"""Hertz contact radius: the formula, the equivalent radius of curvature, runs, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

import celtstone as cs
from celtstone.contact import effective_modulus, hertz_contact_radius
from celtstone.kernels.dynamics import contact_radius
from celtstone.kernels.geometry import contact
from celtstone.kernels.hertz import equivalent_radius
from celtstone.simulation.models import kernel_parameters
from tests.conftest import LITERATURE_EULER_ANGLES


def test_sphere_on_flat_textbook_case() -> None:
    """Steel ball R = 10 mm on a steel flat, P = 100 N, E = 210 GPa, ν = 0.3 (Johnson,
    Contact Mechanics, 1985, ch. 4: a = (3PR/4E*)^(1/3), 1/E* = 2(1 − ν²)/E).
    By hand: E* = 210e9/1.82 Pa, 3PR/(4E*) = 3 · 1.82/840e9 = 6.5e-12 m³ exactly,
    a = 6.5e-12^(1/3) = 0.18663 mm."""
    assert effective_modulus(210e9, 0.3) == pytest.approx(210e9 / 1.82, rel=1e-15)
    radius = hertz_contact_radius(100.0, 0.01, 210e9, 0.3)
    assert radius**3 == pytest.approx(6.5e-12, rel=1e-14)
    assert radius == pytest.approx(1.8663e-4, rel=1e-4)


def test_equivalent_radius_at_rest_is_the_geometric_mean_of_the_shapes_radii(
    any_body: cs.Body,
) -> None:
    """n = e3: R_eq = sqrt(ρ1 ρ2) (ellipsoid ρ = a²/c, b²/c; references.md)."""
    params = kernel_parameters(cs.SlidingModel(), any_body)
    rho1, rho2 = any_body.shape.radii_of_curvature
    assert equivalent_radius((0.0, 0.0, 1.0), params) == pytest.approx(
        math.sqrt(rho1 * rho2), rel=1e-14
    )


def test_equivalent_radius_is_the_gauss_map_area_ratio(any_body: cs.Body) -> None:
    """R1 R2 = 1/K = |det dr/dn| on the tangent plane: finite differences of the contact
    point r(n) of ``kernels.geometry``, an independent route to the curvature."""
    params = kernel_parameters(cs.SlidingModel(), any_body)
    rng = np.random.default_rng(3)
    zero = (0.0, 0.0, 0.0)
    for _ in range(10):
        n = np.array([*rng.normal(scale=0.3, size=2), 1.0])
        n /= np.linalg.norm(n)
        t1 = np.cross(n, [1.0, 0.0, 0.0])
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(n, t1)
        h = 1e-6
        derivatives = []
        for t in (t1, t2):
            plus, _ = contact(tuple(n + h * t), zero, params)
            minus, _ = contact(tuple(n - h * t), zero, params)
            derivatives.append((np.array(plus) - np.array(minus)) / (2 * h))
        area_ratio = abs(np.dot(np.cross(*derivatives), n))
        assert equivalent_radius(tuple(n), params) == pytest.approx(math.sqrt(area_ratio), rel=1e-6)


def test_kernel_radius_follows_the_load_and_is_clamped(kane_levinson: cs.Body) -> None:
    """ε ∝ N^(1/3) at fixed R_eq; N <= 0 is clamped, giving a small positive ε."""
    model = cs.SlidingModel(elastic_modulus=3e9, poisson_ratio=0.35)
    params = kernel_parameters(model, kane_levinson)
    n = (0.0, 0.0, 1.0)
    weight = kane_levinson.mass * kane_levinson.gravity
    at_weight = contact_radius(n, weight, params)
    assert at_weight == pytest.approx(
        hertz_contact_radius(weight, 0.2 * 0.03 / 0.02, 3e9, 0.35), rel=1e-14
    )
    assert contact_radius(n, 8 * weight, params) == pytest.approx(2 * at_weight, rel=1e-14)
    for load in (0.0, -weight):
        assert 0.0 < contact_radius(n, load, params) < 1e-2 * at_weight
    fixed = kernel_parameters(cs.SlidingModel(contact_radius=2e-3), kane_levinson)
    assert contact_radius(n, -weight, fixed) == 2e-3


def _modulus_for_one_millimetre(body: cs.Body) -> float:
    """E (ν = 0) for which the Hertz radius under m g at the rest contact is 1 mm."""
    rho1, rho2 = body.shape.radii_of_curvature
    star = 3 * body.mass * body.gravity * math.sqrt(rho1 * rho2) / (4 * (1e-3) ** 3)
    return 2 * star


@pytest.mark.parametrize("friction_load, tolerance", [("static", 0.01), ("dynamic", 0.05)])
def test_hertz_run_keeps_the_energy_budget_and_matches_the_fixed_radius(
    kane_levinson: cs.Body, friction_load: str, tolerance: float
) -> None:
    """E chosen so that ε = 1 mm at rest: the Hertz run differs from the fixed-ε run
    only by ε's change with tilt (a few degrees; static N) and with N (ε ∝ N^(1/3),
    dynamic N); energy lost = friction work."""
    state = cs.InitialState((0.0, 0.0, -5.0), LITERATURE_EULER_ANGLES)
    modulus = _modulus_for_one_millimetre(kane_levinson)
    runs = [
        cs.simulate(
            cs.SlidingModel(0.35, 1e-3, friction_load, friction_law="exact", **elastic),
            kane_levinson,
            state,
            3.0,
            rtol=1e-9,
        )
        for elastic in ({}, {"elastic_modulus": modulus, "poisson_ratio": 0.0})
    ]
    fixed, hertz = runs
    assert hertz.ok, hertz.message
    energy = hertz.dataset["energy"].values
    work = hertz.dataset["dissipated_work"].values
    assert np.max(np.abs(energy[0] - energy - work)) < 1e-6 * energy[0]
    assert hertz.first_spin_crossing_time == pytest.approx(
        fixed.first_spin_crossing_time, rel=tolerance
    )
    summary = hertz.summary()
    assert summary["contact_radius_model"] == "hertz"
    assert summary["elastic_modulus"] == modulus and summary["poisson_ratio"] == 0.0
    assert fixed.summary()["elastic_modulus"] is None


@pytest.mark.parametrize(
    "settings, name",
    [
        ({"elastic_modulus": 0.0, "poisson_ratio": 0.3}, "elastic_modulus"),
        ({"elastic_modulus": -1e9, "poisson_ratio": 0.3}, "elastic_modulus"),
        ({"elastic_modulus": math.nan, "poisson_ratio": 0.3}, "elastic_modulus"),
        ({"elastic_modulus": 1e9, "poisson_ratio": 0.5}, "poisson_ratio"),
        ({"elastic_modulus": 1e9, "poisson_ratio": -1.0}, "poisson_ratio"),
        ({"elastic_modulus": 1e9}, "poisson_ratio"),
        ({"poisson_ratio": 0.3}, "elastic_modulus"),
        ({"friction_law": "coulomb"}, "friction_law"),
        ({"contact_pressure": "hertzian"}, "contact_pressure"),
    ],
)
def test_bad_contact_settings_are_refused(settings: dict, name: str) -> None:
    with pytest.raises(cs.ParameterError) as error:
        cs.SlidingModel(**settings)
    assert error.value.name == name
    assert "\n" not in str(error.value)


def test_hertz_radius_needs_a_convex_surface(kane_levinson: cs.Body) -> None:
    """A surface with a non-positive radius of curvature (not a shipped shape: the shapes
    refuse it themselves) is refused before any run starts, with a Hertz radius or a fixed
    ε: a saddle does not rest on a single point."""
    shape = cs.Paraboloid((2.0, 0.045), 0.01)
    object.__setattr__(shape, "radii_of_curvature", (2.0, -0.045))
    body = cs.Body("saddle", 1.0, kane_levinson.inertia, shape)
    for model in (cs.SlidingModel(elastic_modulus=1e9, poisson_ratio=0.3), cs.SlidingModel()):
        with pytest.raises(cs.ParameterError, match="not convex"):
            kernel_parameters(model, body)
