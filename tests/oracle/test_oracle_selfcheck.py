"""Self-checks of the plain NumPy + SciPy oracle alone (no celtstone involved)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from tests.oracle import rattleback as oracle

TILT = (0.5, 0.5)


@pytest.fixture(scope="module")
def body() -> dict:
    return oracle.kane_levinson_body()


def vertical_dot_slip(y: np.ndarray) -> np.ndarray:
    return np.einsum("ij,ij->j", y[0:3], y[6:9])


def energies(run: Any, body: dict, model: str) -> np.ndarray:
    return np.array([oracle.energy(y, body, model) for y in run.y.T])


@pytest.mark.parametrize("shape", ["ellipsoid", "paraboloid"])
def test_contact_geometry(shape: str) -> None:
    """r(rest) = -(c - h) e3, and the analytic Jacobian matches central differences."""
    body = (
        oracle.kane_levinson_body()
        if shape == "ellipsoid"
        else oracle.kane_levinson_paraboloid_body()
    )
    np.testing.assert_allclose(
        oracle.contact_point(np.array([0.0, 0.0, 1.0]), body), [0.0, 0.0, -0.01], atol=1e-15
    )
    n = np.array([0.1, -0.15, 1.0])
    n /= np.linalg.norm(n)
    step = 1e-6
    columns = [
        (oracle.contact_point(n + step * e, body) - oracle.contact_point(n - step * e, body))
        / (2 * step)
        for e in np.eye(3)
    ]
    np.testing.assert_allclose(
        oracle.contact_jacobian(n, body), np.array(columns).T, rtol=0, atol=1e-8
    )
    if shape == "ellipsoid":  # the outward normal Q^-1 (r - h e3) is along -n
        q = np.array(body["semi_axes"]) ** 2
        normal = (oracle.contact_point(n, body) - body["com_offset"] * oracle.E3) / q
        np.testing.assert_allclose(normal / np.linalg.norm(normal), -n, atol=1e-14)


def test_rest_is_equilibrium(body: dict) -> None:
    rest = np.array([0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(oracle.rhs_rolling(0.0, rest, body), 0.0, atol=1e-15)
    assert oracle.normal_force(rest, body, "rolling") == pytest.approx(9.81, rel=1e-15)


def test_friction_law_limits() -> None:
    """Exact Coulomb-Contensou facts of ../shared/references.md hold for the Pade law."""
    eps, spin_rate = 1e-3, 5.0
    phi, _ = oracle.friction_shapes(np.array([1.0, 0.0, 0.0]), 0.0, eps, 0.0)
    assert phi[0] == pytest.approx(-1.0, rel=1e-15)  # pure sliding: |F| = f N
    u = 1e-6
    phi, _ = oracle.friction_shapes(np.array([u * eps * spin_rate, 0, 0]), spin_rate, eps, 0.0)
    assert -phi[0] / u == pytest.approx(3 * np.pi / 8, rel=1e-5)
    _, psi = oracle.friction_shapes(np.zeros(3), spin_rate, eps, 0.0)
    assert -psi == pytest.approx(3 * np.pi / 16 * eps, rel=1e-15)  # M0 / (f N)
    u = 1e7
    _, psi = oracle.friction_shapes(np.array([u * eps * spin_rate, 0, 0]), spin_rate, eps, 0.0)
    assert -psi * u / eps == pytest.approx(0.2, rel=1e-6)


@pytest.mark.parametrize("spin_rate", [-5.0, 5.0])
def test_linearised_rolling_matches_stability_quartic(body: dict, spin_rate: float) -> None:
    """Eigenvalues of the numerical Jacobian at steady spin are the roots of the quartic."""
    inertia, m, g = body["inertia"], body["mass"], body["gravity"]
    a, b, c = body["semi_axes"]
    big_a, big_b, big_c, big_d = inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1]
    rho1, rho2, ell = a**2 / c, b**2 / c, c - body["com_offset"]
    a_prime, b_prime = big_a + m * ell**2, big_b + m * ell**2
    delta = a_prime * b_prime - big_d**2
    p1, p2 = rho1 - ell, rho2 - ell
    s1, s2 = big_c - big_a + m * ell * p1, big_c - big_b + m * ell * p2
    n = spin_rate
    quartic = [
        delta,
        big_d * m * ell * n * (rho2 - rho1),
        g * m * (a_prime * p1 + b_prime * p2) + n**2 * (delta + s1 * s2 - big_d**2),
        big_d * m * ell * n**3 * (rho2 - rho1),
        (m * g * p1 + n**2 * s1) * (m * g * p2 + n**2 * s2) - big_d**2 * n**4,
    ]
    y = np.array([0.0, 0.0, 1.0, 0.0, 0.0, spin_rate, 0.0])
    jac = oracle.numerical_jacobian(lambda t, x: oracle.rhs_rolling(t, x, body), 0.0, y)[:6, :6]
    eigenvalues = np.linalg.eigvals(jac)
    eigenvalues = np.sort_complex(eigenvalues[np.abs(eigenvalues) > 1e-4])
    np.testing.assert_allclose(eigenvalues, np.sort_complex(np.roots(quartic)), rtol=1e-6)


def test_rolling_conserves_energy(body: dict) -> None:
    """5 s through the reversal at rtol 1e-11: E constant to 1e-9 relative, |n| = 1."""
    y0 = oracle.initial_state(*TILT, (0.0, 0.0, -5.0), "rolling")
    run = oracle.simulate(
        "rolling", body, y0, 5.0, t_eval=np.linspace(0.0, 5.0, 26), rtol=1e-11, atol=1e-12
    )
    assert run.success
    energy = energies(run, body, "rolling")
    assert np.max(np.abs(energy - energy[0])) < 1e-9 * energy[0]
    np.testing.assert_allclose(np.linalg.norm(run.y[0:3], axis=0), 1.0, rtol=0, atol=1e-10)
    assert np.all(run.y[6] == 0.0)
    spin = np.array([oracle.spin(y) for y in run.y.T])
    assert spin[0] < 0 < spin[-1]  # Kane & Levinson: w3 = -5 rad/s reverses within 5 s


def test_damped_rolling_energy_balance(body: dict) -> None:
    y0 = oracle.initial_state(*TILT, (0.0, 0.0, -5.0), "rolling")
    run = oracle.simulate(
        "rolling", body, y0, 1.0, t_eval=np.linspace(0.0, 1.0, 11), rtol=1e-11, damping=1e-4
    )
    energy = energies(run, body, "rolling")
    work = run.y[6]
    assert work[-1] > 1e-4
    np.testing.assert_allclose(energy + work, energy[0], rtol=1e-10)


@pytest.mark.parametrize(
    ("friction_load", "friction_coefficient"), [("static", 0.35), ("dynamic", 0.25)]
)
def test_sliding_invariants(body: dict, friction_load: str, friction_coefficient: float) -> None:
    """|n| = 1, V1.n = 0, and the energy lost equals the friction work."""
    params = {
        "friction_coefficient": friction_coefficient,
        "contact_radius": 1e-3,
        "friction_load": friction_load,
    }
    y0 = oracle.initial_state(*TILT, (0.0, 0.0, -5.0), "sliding")
    run = oracle.simulate(
        "sliding", body, y0, 0.2, t_eval=np.linspace(0.0, 0.2, 11), rtol=1e-9, **params
    )
    assert run.success
    np.testing.assert_allclose(np.linalg.norm(run.y[0:3], axis=0), 1.0, rtol=0, atol=1e-10)
    np.testing.assert_allclose(vertical_dot_slip(run.y), 0.0, rtol=0, atol=1e-12)
    assert np.max(np.linalg.norm(run.y[6:9], axis=0)) > 1e-3  # it does slip
    energy = energies(run, body, "sliding")
    work = run.y[9]
    assert np.all(np.diff(work) > 0)
    assert work[-1] > 0.01 * energy[0]
    np.testing.assert_allclose(energy + work, energy[0], rtol=1e-10)
    normal = [oracle.normal_force(y, body, "sliding", **params) for y in run.y.T]
    # the rocking modulates N by about 20 % (the contact sits 1.7 cm off axis at 0.5 deg)
    assert 0.5 * 9.81 < min(normal) < max(normal) < 1.5 * 9.81
