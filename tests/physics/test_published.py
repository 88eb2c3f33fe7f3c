"""Published and independently derived behaviour of the Kane & Levinson body."""

from __future__ import annotations

import numpy as np
import pytest

import celtstone as cs
from tests.conftest import LITERATURE_EULER_ANGLES


def characteristic_roots(body: cs.Body, spin: float) -> np.ndarray:
    """Roots of the quartic of ../shared/references.md (linearised rolling about steady spin)."""
    inertia = np.array(body.inertia)
    a_, b_, c_, d_ = inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1]
    m, g = body.mass, body.gravity
    rho1, rho2 = body.shape.radii_of_curvature
    ell = body.shape.rest_height
    a1, b1 = a_ + m * ell**2, b_ + m * ell**2
    delta = a1 * b1 - d_**2
    p1, p2 = rho1 - ell, rho2 - ell
    s1, s2 = c_ - a_ + m * ell * p1, c_ - b_ + m * ell * p2
    n = spin
    coefficients = [
        delta,
        d_ * m * ell * n * (rho2 - rho1),
        g * m * (a1 * p1 + b1 * p2) + n**2 * (delta + s1 * s2 - d_**2),
        d_ * m * ell * n**3 * (rho2 - rho1),
        (m * g * p1 + n**2 * s1) * (m * g * p2 + n**2 * s2) - d_**2 * n**4,
    ]
    return np.roots(coefficients)


def test_linear_theory_prefers_positive_spin(kane_levinson: cs.Body) -> None:
    """The quartic's roots for this body (D < 0, rho1 > rho2): at -5 rad/s the pitch mode grows
    fast; at +5 rad/s only the roll mode grows, ten times more slowly. Without dissipation
    the no-slip rattleback reverses in both directions (Garcia & Hubbard 1988; Kondo &
    Nakanishi 2017), but negative spin is the unstable, "wrong" sense."""
    growth_negative = np.max(characteristic_roots(kane_levinson, -5.0).real)
    growth_positive = np.max(characteristic_roots(kane_levinson, 5.0).real)
    assert growth_positive > 0.0
    assert growth_negative > 5.0 * growth_positive


def test_kane_levinson_negative_spin_reverses_first(kane_levinson: cs.Body) -> None:
    """Kane & Levinson's starts, w3 = -5 and +5 rad/s: the -5 start rattles and reverses
    within a few seconds, while the +5 start keeps its sense at least four times longer
    (the preferred sense of this body)."""
    negative = cs.simulate(
        cs.RollingModel(),
        kane_levinson,
        cs.InitialState((0.0, 0.0, -5.0), LITERATURE_EULER_ANGLES),
        20.0,
    )
    positive = cs.simulate(
        cs.RollingModel(),
        kane_levinson,
        cs.InitialState((0.0, 0.0, 5.0), LITERATURE_EULER_ANGLES),
        20.0,
    )
    assert negative.dataset["spin"].values[0] < 0 < positive.dataset["spin"].values[0]
    assert negative.first_spin_crossing_time is not None
    assert negative.first_spin_crossing_time < 5.0
    assert positive.first_spin_crossing_time is None or (
        positive.first_spin_crossing_time > 4.0 * negative.first_spin_crossing_time
    )


@pytest.mark.parametrize("spin", [-5.0, 5.0])
def test_paraboloid_cap_follows_the_ellipsoid_near_rest(
    kane_levinson: cs.Body, spin: float
) -> None:
    """The osculating paraboloid has the same rest curvature: over a short time from a tiny
    tilt both bodies move alike (difference of second order in the tilt)."""
    paraboloid = cs.load_body("kane_levinson_1982_paraboloid")
    state = cs.InitialState((0.0, 0.0, spin), (0.05, 0.05))
    run_e = cs.simulate(cs.RollingModel(), kane_levinson, state, 1.0)
    run_p = cs.simulate(cs.RollingModel(), paraboloid, state, 1.0)
    tilt_scale = np.max(run_e.dataset["tilt"].values)
    assert (
        np.max(np.abs(run_e.dataset["tilt"].values - run_p.dataset["tilt"].values))
        < 0.05 * tilt_scale
    )
