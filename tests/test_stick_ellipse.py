"""The elliptic contact's stick limit set (``kernels.stick_ellipse``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from celtstone.kernels.friction import HERTZ_MOMENT
from celtstone.kernels.friction_ellipse import TABLE_ADDRESS as TABLE
from celtstone.kernels.layout import ContactPressure, FrictionLaw
from celtstone.kernels.stick import stick_margin_of
from celtstone.kernels.stick_ellipse import elliptic_stick_margin, law_at, limit_moment_at

LAWS = (FrictionLaw.PADE.value, FrictionLaw.EXACT.value)
NORMAL = (0.0, 0.0, 1.0)
MAJOR = (1.0, 0.0, 0.0)


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("aspect", [0.02, 0.05, 0.089, 0.3, 0.8, 0.999])
def test_the_slip_state_of_a_force_is_found(law: int, aspect: float) -> None:
    """Round trip: the force of a slip state (u, α) leads back to that state's moment, to
    1e-9 M0 for the Padé law everywhere; for the exact law where |F| <= 0.98 f N, and to
    3 % of M0 beyond (measured: 2.6 % at most over 1 800 states, all with |F| > 0.98 f N
    and the slip within a few degrees of the minor axis or u > 10, where the force
    saturates and the tabulated correction is not exactly one-to-one)."""
    rng = np.random.default_rng(17)
    zero_slip = law_at(0.0, 0.0, aspect, law, TABLE)[2]
    for _ in range(60):
        x = float(rng.uniform(0.0005, 0.9995))
        direction = float(rng.uniform(0.0, 2.0 * math.pi))
        force_x, force_y, moment = law_at(x, direction, aspect, law, TABLE)
        error = abs(limit_moment_at(force_x, force_y, aspect, law, TABLE) - moment) / zero_slip
        saturated = law == FrictionLaw.EXACT.value and math.hypot(force_x, force_y) > 0.98
        assert error <= (3e-2 if saturated else 1e-9)


@pytest.mark.parametrize("law", LAWS)
def test_zero_force_gets_the_zero_slip_moment(law: int) -> None:
    """F_s = 0: the whole pivoting moment (3/8) E(e) per unit f N A is available."""
    from scipy.special import ellipe

    aspect = 0.089
    expected = 0.375 * ellipe(1.0 - aspect**2)
    assert limit_moment_at(0.0, 0.0, aspect, law, TABLE) == pytest.approx(expected, rel=1e-13)


def test_a_round_ellipse_is_the_disks_limit_set() -> None:
    """B = A: the margin is ``stick_margin_of`` of the disk's Padé law of radius A."""
    rng = np.random.default_rng(3)
    radius, capacity = 1.2e-3, 3.4
    for _ in range(30):
        phi = float(rng.uniform(0.0, 0.99))
        angle = float(rng.uniform(0.0, 2.0 * math.pi))
        force = (capacity * phi * math.cos(angle), capacity * phi * math.sin(angle), 0.0)
        moment = float(rng.uniform(0.0, 1.2)) * HERTZ_MOMENT * capacity * radius
        margin = elliptic_stick_margin(
            force, moment, NORMAL, MAJOR, radius, radius, capacity, FrictionLaw.PADE.value, TABLE
        )
        disk = stick_margin_of(
            capacity * phi,
            moment,
            capacity / 0.35,
            0.35,
            radius,
            FrictionLaw.PADE.value,
            ContactPressure.HERTZ.value,
        )
        assert margin == pytest.approx(disk, abs=1e-9)


@pytest.mark.parametrize("law", LAWS)
def test_the_margin_changes_sign_on_the_boundary(law: int) -> None:
    """Just inside the moment a slip state gives: g > 0; just outside: g < 0; beyond f N: < 0."""
    aspect, semi_major, capacity = 0.089, 3.1e-3, 3.43
    rng = np.random.default_rng(8)
    axis = (math.cos(0.3), math.sin(0.3), 0.0)  # the ellipse turned in the tangent plane
    across = (-math.sin(0.3), math.cos(0.3), 0.0)
    for _ in range(10):
        x = float(rng.uniform(0.05, 0.95))
        direction = float(rng.uniform(0.0, 2.0 * math.pi))
        fx, fy, moment = law_at(x, direction, aspect, law, TABLE)
        force = tuple(capacity * (fx * a + fy * b) for a, b in zip(axis, across, strict=True))
        scale = capacity * semi_major
        args = (NORMAL, axis, semi_major, aspect * semi_major, capacity, law, TABLE)
        assert elliptic_stick_margin(force, 0.999 * moment * scale, *args) > 0.0
        assert elliptic_stick_margin(force, 1.001 * moment * scale, *args) < 0.0
    beyond = (1.01 * capacity, 0.0, 0.0)
    args = (NORMAL, MAJOR, semi_major, aspect * semi_major, capacity, law, TABLE)
    assert elliptic_stick_margin(beyond, 0.0, *args) < 0.0
    assert (
        elliptic_stick_margin(
            beyond, 0.0, NORMAL, MAJOR, semi_major, 1e-3 * semi_major, capacity, law, TABLE
        )
        == -1.0
    )  # out of the law's range
    assert (
        elliptic_stick_margin(
            (0.0, 0.0, 0.0), 0.0, NORMAL, MAJOR, semi_major, aspect * semi_major, 0.0, law, TABLE
        )
        == -1.0
    )  # no friction
