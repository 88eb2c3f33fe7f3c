"""Exact Coulomb–Contensou friction: limits, quadrature, fast representation, Padé.

Oracles: the exact limits of ../shared/references.md, two independent
quadratures of the integrals of paper section 2 (``celtstone.contact.quadrature``,
polar coordinates about the instantaneous centre of rotation, and a plain
double integral about the disk centre written here), exact rational series,
and the energy budget of a run.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

import celtstone as cs
from celtstone.contact import friction_functions, friction_integrals
from celtstone.contact.series import coefficients
from celtstone.kernels import friction_exact
from celtstone.kernels.friction import (
    PADE_A,
    PADE_B,
    UNIFORM_PADE_A,
    UNIFORM_PADE_B,
    contact_friction,
)
from celtstone.kernels.layout import ContactPressure, FrictionLaw
from tests.conftest import LITERATURE_EULER_ANGLES

PRESSURES = ["hertz", "uniform"]
# references.md: M0/(fNε), small-u slope of F/(fN) (= 1/b), lim u M/(fNε) (= M0/a)
LIMITS = {
    "hertz": (3 * math.pi / 16, 3 * math.pi / 8, 1 / 5),
    "uniform": (2 / 3, 1.0, 1 / 4),
}
# stated bound of the closed forms against the quadrature, u in [0, 1e4]
# (the quadrature's own error dominates: measured 6e-12 at u ~ 1e4, <= 5e-14 for u <= 1e3)
REPRESENTATION_BOUND = 1e-11


def exact(u: float, pressure: str) -> tuple[float, float]:
    force, moment = friction_functions([u], "exact", pressure)
    return float(force[0]), float(moment[0])


@pytest.mark.parametrize("pressure", PRESSURES)
def test_exact_limits(pressure: str) -> None:
    """F -> fN, M(0) = M0, F ≈ fN u/b at small u, M u -> M0/a at large u (references.md)."""
    moment_zero, slope, tail = LIMITS[pressure]
    assert exact(0.0, pressure) == (0.0, pytest.approx(moment_zero, rel=1e-14))
    assert exact(1e9, pressure)[0] == pytest.approx(1.0, abs=1e-15)
    u = 1e-6
    assert exact(u, pressure)[0] / u == pytest.approx(slope, rel=1e-10)
    u = 1e6
    assert exact(u, pressure)[1] * u == pytest.approx(tail, rel=1e-10)


@pytest.mark.parametrize("pressure", PRESSURES)
def test_reference_quadrature_has_the_exact_limits(pressure: str) -> None:
    """The quadrature itself, independently of the closed forms (references.md)."""
    moment_zero, slope, tail = LIMITS[pressure]
    assert friction_integrals(0.0, pressure)[1] == pytest.approx(moment_zero, rel=1e-11)
    assert friction_integrals(1e-4, pressure)[0] / 1e-4 == pytest.approx(slope, rel=1e-7)
    assert friction_integrals(1e4, pressure)[0] == pytest.approx(1.0, abs=1e-7)
    assert friction_integrals(1e4, pressure)[1] * 1e4 == pytest.approx(tail, rel=1e-7)


def _disk_integrals(u: float, pressure: str) -> tuple[float, float]:
    """Paper section 2 integrals in polar coordinates about the disk centre (ε = 1, Ω_n = 1).

    v = u e1 + e3 × ρ; F = ∫ p v1/|v| dS, M = ∫ p (ρ × v)3/|v| dS. The jump of
    v/|v| at the centre of rotation (r = u, θ = π/2) is left to the adaptive rule,
    with breakpoints there.
    """

    def density(r: float) -> float:
        if pressure == "hertz":
            return 1.5 / math.pi * math.sqrt(max(0.0, 1.0 - r * r))
        return 1.0 / math.pi

    def ring(r: float, moment: bool) -> float:
        def integrand(theta: float) -> float:
            x, y = r * math.cos(theta), r * math.sin(theta)
            vx, vy = u - y, x
            speed = math.hypot(vx, vy)
            if speed == 0.0:
                return 0.0
            value = (x * vy - y * vx) if moment else vx
            return density(r) * r * value / speed

        return integrate.quad(
            integrand, -0.5 * math.pi, 1.5 * math.pi, points=[0.5 * math.pi], epsabs=1e-13,
            epsrel=1e-10, limit=200,
        )[0]  # fmt: skip

    breaks = [u] if u < 1.0 else None
    options = {"epsabs": 1e-12, "epsrel": 1e-10, "limit": 200, "points": breaks}
    return (
        integrate.quad(ring, 0.0, 1.0, args=(False,), **options)[0],
        integrate.quad(ring, 0.0, 1.0, args=(True,), **options)[0],
    )


@pytest.mark.parametrize("pressure", PRESSURES)
@pytest.mark.parametrize("u", [0.6, 2.5])
def test_two_quadratures_agree(pressure: str, u: float) -> None:
    """ICR-centred quadrature vs a plain double integral about the disk centre."""
    reference = _disk_integrals(u, pressure)
    assert friction_integrals(u, pressure) == pytest.approx(reference, abs=1e-9)


@pytest.mark.parametrize("pressure", PRESSURES)
def test_fast_representation_matches_quadrature_at_random_u(pressure: str) -> None:
    """Closed forms (and series) vs quadrature at seeded random u in [1e-3, 1e4],
    plus the branch points u = 1 and the series switches u = 1/4, 4."""
    rng = np.random.default_rng(20240605)
    limit = friction_exact.SERIES_LIMIT
    special = [0.0, limit, 1.0, 1.0 - 1e-9, 1.0 + 1e-9, 1.0 / limit]
    for u in [*special, *(10.0 ** rng.uniform(-3.0, 4.0, 25))]:
        reference = friction_integrals(u, pressure)
        assert exact(u, pressure) == pytest.approx(reference, abs=REPRESENTATION_BOUND), u


@pytest.mark.parametrize("pressure", PRESSURES)
def test_representation_is_continuous_at_its_switches(pressure: str) -> None:
    """u = 1 (centre of rotation on the rim) and the series switches: both sides agree."""
    limit = friction_exact.SERIES_LIMIT
    for u in (limit, 1.0, 1.0 / limit):
        below = exact(u * (1.0 - 1e-12), pressure)
        above = exact(u * (1.0 + 1e-12), pressure)
        assert below == pytest.approx(above, abs=1e-11)


def test_hertz_closed_form_below_one_at_a_hand_value() -> None:
    """u = 1/2: F = (3π/32)(1/2)(15/4) = 45π/256, M = (3π/128)(8 − 2 + 3/16) = 297π/2048."""
    assert exact(0.5, "hertz") == (
        pytest.approx(45 * math.pi / 256, rel=1e-15),
        pytest.approx(297 * math.pi / 2048, rel=1e-15),
    )


def test_uniform_force_at_u_one_is_eight_over_three_pi() -> None:
    """u = 1, uniform: F = 4·2E(1)/(3π) = 8/(3π) with E(1) = 1; M = 8/(9π)."""
    assert exact(1.0, "uniform") == (
        pytest.approx(8 / (3 * math.pi), rel=1e-15),
        pytest.approx(8 / (9 * math.pi), rel=1e-15),
    )


@pytest.mark.parametrize(
    "name, table",
    [
        ("hertz_force", friction_exact.HERTZ_FORCE_SERIES),
        ("hertz_moment", friction_exact.HERTZ_MOMENT_SERIES),
        ("uniform_force", friction_exact.UNIFORM_FORCE_SERIES),
        ("uniform_moment", friction_exact.UNIFORM_MOMENT_SERIES),
    ],
)
def test_series_tables_equal_the_rational_coefficients(name: str, table: tuple) -> None:
    expected = [float(c) for c in coefficients(name, len(table))]
    assert list(table) == expected


def test_elliptic_integrals_match_scipy() -> None:
    from scipy.special import ellipe, ellipk

    for k in [0.0, 0.1, 0.26, 0.5, 0.9, 0.999, 1.0 - 1e-12]:
        e_value, reduced_k = friction_exact.complete_elliptic_integrals(k)
        assert e_value == pytest.approx(ellipe(k * k), rel=1e-14)
        assert reduced_k == pytest.approx((1 - k * k) * ellipk(k * k), rel=1e-13, abs=1e-15)
    assert friction_exact.complete_elliptic_integrals(1.0) == (1.0, 0.0)


@pytest.mark.parametrize(
    "pressure, b, a", [("hertz", PADE_B, PADE_A), ("uniform", UNIFORM_PADE_B, UNIFORM_PADE_A)]
)
def test_pade_is_the_one_one_approximant_with_the_exact_ends(
    pressure: str, b: float, a: float
) -> None:
    """Padé F = u/(u + b), M = M0/(1 + a u): b = 1/F'(0), a = M(0)/lim u M(u) of the
    exact law, so both laws agree to first order at u -> 0 and u -> ∞."""
    moment_zero = exact(0.0, pressure)[1]
    u = 1e-7
    assert b == pytest.approx(u / exact(u, pressure)[0], rel=1e-9)
    u = 1e7
    assert a == pytest.approx(moment_zero / (u * exact(u, pressure)[1]), rel=1e-9)
    for u in (1e-6, 1e6):
        pade = friction_functions([u], "pade", pressure)
        assert pade[0][0] == pytest.approx(exact(u, pressure)[0], rel=1e-5)
        assert pade[1][0] == pytest.approx(exact(u, pressure)[1], rel=1e-5)


@pytest.mark.parametrize("pressure", [pressure.value for pressure in ContactPressure])
def test_exact_kernel_opposes_motion_and_depends_on_u_only(pressure: int) -> None:
    """F ∥ −V1, M opposite to Ω_n, magnitudes functions of u alone (references.md);
    the regularisation gives zero friction in the singular state (paper eq. 11)."""
    rng = np.random.default_rng(7)
    for _ in range(20):
        slip = tuple(rng.normal(size=3) * 10 ** rng.uniform(-4, -1))
        spin = rng.normal() * 5
        radius = 10 ** rng.uniform(-4, -2)
        force, moment = contact_friction(slip, spin, radius, 0.0, FrictionLaw.EXACT.value, pressure)
        speed = math.sqrt(sum(v * v for v in slip))
        u = speed / (radius * abs(spin))
        name = ContactPressure(pressure).name.lower()
        magnitude, pivot = exact(u, name)
        assert np.allclose(force, -magnitude * np.array(slip) / speed, rtol=1e-13, atol=0)
        assert moment == pytest.approx(-math.copysign(pivot * radius, spin), rel=1e-13)
    force, moment = contact_friction(
        (0.0, 0.0, 0.0), 0.0, 1e-3, 1e-6, FrictionLaw.EXACT.value, pressure
    )
    assert force == (0.0, 0.0, 0.0) and moment == 0.0


@pytest.fixture(scope="module")
def exact_and_pade_runs(kane_levinson: cs.Body) -> dict[str, cs.Trajectory]:
    state = cs.InitialState((0.0, 0.0, -5.0), LITERATURE_EULER_ANGLES)
    return {
        f"{law}-{pressure}": cs.simulate(
            cs.SlidingModel(0.35, 1e-3, friction_law=law, contact_pressure=pressure),
            kane_levinson,
            state,
            4.0,
            rtol=1e-9,
        )
        for law, pressure in [("exact", "hertz"), ("pade", "hertz"), ("exact", "uniform")]
    }


@pytest.mark.parametrize("case", ["exact-hertz", "exact-uniform"])
def test_exact_law_run_energy_lost_equals_friction_work(
    exact_and_pade_runs: dict[str, cs.Trajectory], case: str
) -> None:
    """E(0) − E(t) = W(t) to solver accuracy (as for the Padé law in test_invariants)."""
    run = exact_and_pade_runs[case]
    assert run.ok, run.message
    energy = run.dataset["energy"].values
    work = run.dataset["dissipated_work"].values
    assert work[-1] > 1e-2 * energy[0]
    assert np.max(np.abs(energy[0] - energy - work)) < 1e-6 * energy[0]
    assert np.all(np.diff(work) >= -1e-12)
    assert run.summary()["friction_law"] == "exact"


def test_exact_and_pade_runs_agree_qualitatively(
    exact_and_pade_runs: dict[str, cs.Trajectory],
) -> None:
    """Same contact, f and start: both laws reverse the −5 rad/s spin, at times within
    a third of each other (the laws differ by up to 0.34 f N in force)."""
    exact_run, pade_run = exact_and_pade_runs["exact-hertz"], exact_and_pade_runs["pade-hertz"]
    exact_time, pade_time = exact_run.first_spin_crossing_time, pade_run.first_spin_crossing_time
    assert exact_time is not None and pade_time is not None
    assert abs(exact_time - pade_time) < 0.33 * pade_time
