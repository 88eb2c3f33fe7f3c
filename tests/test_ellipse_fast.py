"""The fast elliptic friction law (``kernels.friction_ellipse``) against its oracles.

Oracles: the disk's Padé law (``pade_friction``) for A = B; the closed forms at zero
slip, M0 = (3/8) f N A E(e) (SciPy's ``ellipe``), and at pure slip, |F| = fN
antiparallel to V; the exact symmetries of a centred ellipse; the dissipation
inequality; and the exact elliptic law (``contact.ellipse``, itself checked against
independent quadratures in ``test_friction_ellipse.py``), with the error split into the
disk's own Padé error and the table's interpolation error.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy import special

from celtstone.contact import ellipse_table
from celtstone.contact.ellipse import elliptic_friction, elliptic_friction_functions
from celtstone.contact.ellipse_table import (
    TABLE_FILE,
    exact_ratios,
    node_coordinates,
    node_ratios,
    small_slip_stiffness,
)
from celtstone.kernels.friction import contact_friction, pade_friction
from celtstone.kernels.friction_ellipse import (
    ASPECT_MIN,
    COEFFICIENTS,
    TABLE_ADDRESS,
    elliptic_contact_friction,
)
from celtstone.kernels.layout import ContactPressure, FrictionLaw

NORMAL = (0.0, 0.0, 1.0)
MAJOR = (1.0, 0.0, 0.0)
ASPECTS = (ASPECT_MIN, 0.05, 0.089, 0.2, 0.5, 0.9, 0.999)

# Largest errors of the fast law [1], |F_fast − F_exact|/(fN) and |M_fast − M_exact|/(fNA),
# measured over the first 3000 points of ``random_points`` (k log-uniform in [0.02, 1),
# u log-uniform in [1e-3, 1e3], α uniform), with a margin of about 25 %.
# Padé part: the exact law corrected by the exactly computed ratios, against the exact law
# (the disk's own Padé error, scaled by the ratios); interpolation part: the fast law
# against that exactly corrected law.
PADE_FORCE_ERROR = 0.40
PADE_MOMENT_ERROR = 0.23
INTERPOLATION_FORCE_ERROR = 6.2e-4
INTERPOLATION_MOMENT_ERROR = 7.3e-4


def elliptic_pade(*arguments: object) -> tuple[tuple[float, float, float], float]:
    """:func:`elliptic_contact_friction` with Zhuravlev's Padé law (its other arguments)."""
    return elliptic_contact_friction(*arguments, FrictionLaw.PADE.value, TABLE_ADDRESS)


def random_points(count: int, seed: int = 20240613) -> list[tuple[float, float, float]]:
    """(u, α, k) off the grid: k log-uniform in [ASPECT_MIN, 1), u in [1e-3, 1e3], α in [0, 2π)."""
    rng = np.random.default_rng(seed)
    points = []
    for _ in range(count):
        aspect = math.exp(rng.uniform(math.log(ASPECT_MIN), 0.0))
        direction = rng.uniform(0.0, 2.0 * math.pi)
        u = math.exp(rng.uniform(math.log(1e-3), math.log(1e3)))
        points.append((u, direction, min(aspect, 0.9999)))
    return points


def error_parts(u: float, direction: float, aspect: float) -> tuple[float, ...]:
    """(Padé F, Padé M, interpolation F, interpolation M, total F, total M) errors [1].

    Units A = 1, Ω_n = 1, f N = 1, δ = 0, ellipse axes = body axes.
    """
    slip = (u * math.cos(direction), u * math.sin(direction), 0.0)
    along = np.array([math.cos(direction), math.sin(direction)])
    across = np.array([-math.sin(direction), math.cos(direction)])
    exact_force, exact_moment = elliptic_friction_functions(u, direction, aspect)
    d_par, r_perp, d_moment = exact_ratios(u, direction, aspect)
    pade_force, pade_moment = pade_friction(slip, 1.0, 1.0, 0.0)
    pade_along = pade_force[0] * along[0] + pade_force[1] * along[1]
    corrected_force = pade_along * ((1.0 + d_par) * along + r_perp * across)
    moment_limit = 2.0 * float(special.ellipe(1.0 - aspect * aspect)) / math.pi
    corrected_moment = pade_moment * moment_limit * (1.0 + d_moment)
    fast_force, fast_moment = elliptic_pade(slip, 1.0, NORMAL, MAJOR, 1.0, aspect, 0.0)
    fast = np.array(fast_force[:2])
    return (
        float(np.hypot(*(corrected_force - exact_force))),
        abs(corrected_moment - exact_moment),
        float(np.hypot(*(fast - corrected_force))),
        abs(fast_moment - corrected_moment),
        float(np.hypot(*(fast - exact_force))),
        abs(fast_moment - exact_moment),
    )


def rotate(vector: tuple[float, float, float], angle: float) -> tuple[float, float, float]:
    """``vector`` turned by ``angle`` [rad] about e_z."""
    c, s = math.cos(angle), math.sin(angle)
    return (c * vector[0] - s * vector[1], s * vector[0] + c * vector[1], vector[2])


def test_equal_axes_are_the_pade_law() -> None:
    rng = np.random.default_rng(1)
    for _ in range(20):
        slip = tuple(rng.normal(size=3) * 10.0 ** rng.uniform(-3, 1))
        spin = rng.normal() * 10.0 ** rng.uniform(-2, 2)
        radius = 10.0 ** rng.uniform(-4, -2)
        delta = float(rng.choice([0.0, 1e-6, 1e-3]))
        axis = rotate(MAJOR, rng.uniform(0, 2 * math.pi))
        force, moment = elliptic_pade(slip, spin, NORMAL, axis, radius, radius, delta)
        pade_force, pade_moment = pade_friction(slip, spin, radius, delta)
        np.testing.assert_allclose(force, pade_force, rtol=1e-15, atol=0.0)
        assert moment == pytest.approx(pade_moment, rel=1e-15)


@pytest.mark.parametrize("aspect", ASPECTS)
@pytest.mark.parametrize("spin", [2.5, -0.7])
def test_zero_slip_moment_is_the_closed_form(aspect: float, spin: float) -> None:
    semi_major = 3.1e-3
    force, moment = elliptic_pade(
        (0.0, 0.0, 0.0), spin, NORMAL, MAJOR, semi_major, aspect * semi_major, 0.0
    )
    closed_form = 0.375 * semi_major * float(special.ellipe(1.0 - aspect * aspect))
    assert moment == pytest.approx(-math.copysign(closed_form, spin), rel=1e-14, abs=0.0)
    assert force == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("aspect", ASPECTS)
def test_pure_slip_is_coulomb(aspect: float) -> None:
    for direction in np.linspace(0.0, 2.0 * math.pi, 37):
        slip = (0.3 * math.cos(direction), 0.3 * math.sin(direction), 0.0)
        axis = rotate(MAJOR, 0.4)
        force, moment = elliptic_pade(slip, 0.0, NORMAL, axis, 2e-3, aspect * 2e-3, 0.0)
        assert math.hypot(*force) == pytest.approx(1.0, abs=1e-12)
        np.testing.assert_allclose(force, np.array(slip) / -0.3, rtol=0.0, atol=1e-12)
        assert moment == 0.0


def test_power_is_dissipated() -> None:
    rng = np.random.default_rng(7)
    for _ in range(2000):
        axis = rotate(MAJOR, rng.uniform(0, 2 * math.pi))
        slip = (*rng.normal(size=2) * 10.0 ** rng.uniform(-6, 1), 0.0)
        spin = rng.normal() * 10.0 ** rng.uniform(-3, 3)
        semi_major = 10.0 ** rng.uniform(-4, -2)
        aspect = math.exp(rng.uniform(math.log(ASPECT_MIN), 0.0))
        delta = float(rng.choice([0.0, 1e-6, 1e-3]))
        force, moment = elliptic_pade(
            slip, spin, NORMAL, axis, semi_major, aspect * semi_major, delta
        )
        power = force[0] * slip[0] + force[1] * slip[1] + moment * spin
        assert power <= 0.0


def test_symmetries() -> None:
    rng = np.random.default_rng(11)
    for _ in range(200):
        angle = rng.uniform(0, 2 * math.pi)
        axis = rotate(MAJOR, angle)
        slip = (*rng.normal(size=2), 0.0)
        spin = rng.normal() * 200.0
        args = (2e-3, rng.uniform(ASPECT_MIN, 1.0) * 2e-3, 1e-4)
        force, moment = elliptic_pade(slip, spin, NORMAL, axis, *args)
        # the same ellipse: its major axis either way
        same = elliptic_pade(slip, spin, NORMAL, rotate(axis, math.pi), *args)
        np.testing.assert_allclose(same[0], force, rtol=1e-12, atol=1e-15)
        assert same[1] == pytest.approx(moment, rel=1e-12)
        # a rotation by π maps the ellipse onto itself: V -> −V gives F -> −F, M
        reverse = elliptic_pade(rotate(slip, math.pi), spin, NORMAL, axis, *args)
        np.testing.assert_allclose(reverse[0], -np.array(force), rtol=1e-12, atol=1e-15)
        assert reverse[1] == pytest.approx(moment, rel=1e-12)
        # mirror image in the major axis: the spin changes sign, F is mirrored, M changes sign
        along = slip[0] * axis[0] + slip[1] * axis[1]
        mirrored = tuple(2.0 * along * a - v for a, v in zip(axis, slip, strict=True))
        mirror = elliptic_pade(mirrored, -spin, NORMAL, axis, *args)
        force_along = force[0] * axis[0] + force[1] * axis[1]
        expected = [2.0 * force_along * a - f for a, f in zip(axis, force, strict=True)]
        np.testing.assert_allclose(mirror[0], expected, rtol=1e-12, atol=1e-15)
        assert mirror[1] == pytest.approx(-moment, rel=1e-12)
        # so the spin's sign leaves F unchanged (rotation by π after the mirror)
        opposite = elliptic_pade(slip, -spin, NORMAL, axis, *args)
        np.testing.assert_allclose(opposite[0], force, rtol=1e-12, atol=1e-15)
        assert opposite[1] == pytest.approx(-moment, rel=1e-12)
        # the normal's sense is a convention: −n with −Ω_n is the same motion
        flipped = elliptic_pade(slip, -spin, (0.0, 0.0, -1.0), axis, *args)
        np.testing.assert_allclose(flipped[0], force, rtol=1e-12, atol=1e-15)
        assert flipped[1] == pytest.approx(-moment, rel=1e-12)
        # turning the whole contact turns the force
        turn = rng.uniform(0, 2 * math.pi)
        turned = elliptic_pade(rotate(slip, turn), spin, NORMAL, rotate(axis, turn), *args)
        np.testing.assert_allclose(turned[0], rotate(force, turn), rtol=1e-9, atol=1e-13)
        assert turned[1] == pytest.approx(moment, rel=1e-9)


def test_exact_law_spin_symmetry() -> None:
    """The reference itself: F(V, −Ω) = F(V, Ω), M(V, −Ω) = −M(V, Ω)."""
    velocity = (0.02, -0.013)
    force, moment = elliptic_friction(velocity, 3.0, 1e-3, 0.2e-3)
    mirror_force, mirror_moment = elliptic_friction(velocity, -3.0, 1e-3, 0.2e-3)
    np.testing.assert_allclose(mirror_force, force, rtol=1e-12, atol=1e-15)
    assert mirror_moment == pytest.approx(-moment, rel=1e-12)


def test_minor_axis_is_n_cross_a() -> None:
    """ŝ⊥ = n × ŝ: the fast force's direction (r_perp/r_par, free of the Padé error) is exact."""
    u, direction, aspect = 0.05, 0.3, 0.089
    exact_force, _ = elliptic_friction_functions(u, direction, aspect)
    slip = (u * math.cos(direction), u * math.sin(direction), 0.0)
    force, _ = elliptic_pade(slip, 1.0, NORMAL, MAJOR, 1.0, aspect, 0.0)
    along = (math.cos(direction), math.sin(direction))
    turned = (-math.sin(direction), math.cos(direction))
    exact_slope = (exact_force @ turned) / (exact_force @ along)
    fast_slope = (force[0] * turned[0] + force[1] * turned[1]) / (
        force[0] * along[0] + force[1] * along[1]
    )
    assert abs(exact_slope) > 0.1
    assert fast_slope == pytest.approx(exact_slope, rel=1e-3)


def test_refuses_outside_the_table() -> None:
    for semi_minor in (0.5 * ASPECT_MIN, 1.5, math.nan, 0.0):
        force, moment = elliptic_pade((0.1, 0.0, 0.0), 1.0, NORMAL, MAJOR, 1.0, semi_minor, 0.0)
        assert all(math.isnan(f) for f in force)
        assert math.isnan(moment)


def test_error_against_the_exact_law() -> None:
    errors = np.array([error_parts(*point) for point in random_points(60)])
    pade_force, pade_moment, table_force, table_moment = errors[:, :4].max(axis=0)
    assert pade_force <= PADE_FORCE_ERROR
    assert pade_moment <= PADE_MOMENT_ERROR
    assert table_force <= INTERPOLATION_FORCE_ERROR
    assert table_moment <= INTERPOLATION_MOMENT_ERROR
    # the parts bound the whole
    assert np.all(errors[:, 4] <= errors[:, 0] + errors[:, 2] + 1e-15)
    assert np.all(errors[:, 5] <= errors[:, 1] + errors[:, 3] + 1e-15)


def test_shipped_table_is_the_generators() -> None:
    with np.load(TABLE_FILE, allow_pickle=False) as data:
        ratios = data["ratios"]
        slips, directions, aspects = node_coordinates(*ratios.shape[1:])
        # the nodes are exp(linspace(...)): NumPy's exp may round one node differently on
        # another processor (its SIMD paths), so equal to a few ulps, not bit for bit
        np.testing.assert_allclose(data["aspects"], aspects, rtol=4 * np.finfo(float).eps, atol=0)
        assert float(data["aspect_min"]) == ASPECT_MIN
    assert COEFFICIENTS.size <= 50_000
    rng = np.random.default_rng(3)
    nodes = [(0, 5, 2), (ratios.shape[1] - 1, 7, 4), (10, 0, 0), (20, 24, 9)]
    for _ in range(6):
        i, j, m = (int(rng.integers(n)) for n in ratios.shape[1:])
        nodes.append((i, j, m))
    for i, j, m in nodes:
        expected = node_ratios(float(slips[i]), float(directions[j]), float(aspects[m]))
        np.testing.assert_allclose(ratios[:, i, j, m], expected, rtol=0.0, atol=1e-12)
    assert np.all(ratios[..., -1] == 0.0)  # k = 1: stored exactly


@pytest.mark.parametrize("aspect", [ASPECT_MIN, 0.089, 0.6])
def test_closed_form_limits_match_the_exact_law(aspect: float) -> None:
    """The end rows of the table (u = 0, u = ∞) against the exact law near them."""
    for beta in (0.1, 0.7, 1.3):
        at_zero = node_ratios(0.0, beta, aspect)
        at_infinity = node_ratios(1.0, beta, aspect)
        # the direction α of the node β
        direction = _direction_of(beta, aspect)
        np.testing.assert_allclose(
            exact_ratios(1e-5 * aspect, direction, aspect), at_zero, rtol=0.0, atol=1e-7
        )
        np.testing.assert_allclose(exact_ratios(1e5, direction, aspect), at_infinity, atol=1e-7)
    along, across = small_slip_stiffness(1.0)
    assert along == pytest.approx(3.0 * math.pi / 8.0, rel=1e-15)
    assert across == pytest.approx(3.0 * math.pi / 8.0, rel=1e-15)


def _direction_of(beta: float, aspect: float) -> float:
    """α with [α + atan2(k sin α, cos α)]/2 = β, by bisection."""
    low, high = 0.0, 0.5 * math.pi
    for _ in range(200):
        middle = 0.5 * (low + high)
        value = 0.5 * (middle + math.atan2(aspect * math.sin(middle), math.cos(middle)))
        low, high = (middle, high) if value < beta else (low, middle)
    return 0.5 * (low + high)


def test_exact_disk_law_corrected_is_the_exact_elliptic_law() -> None:
    """``elliptic_contact_friction`` with the exact disk law: the exact elliptic law to the table's
    interpolation error (no Padé part), at the same random points."""
    for u, direction, aspect in random_points(40, seed=7):
        slip = (u * math.cos(direction), u * math.sin(direction), 0.0)
        exact_force, exact_moment = elliptic_friction_functions(u, direction, aspect)
        force, moment = elliptic_contact_friction(
            slip, 1.0, NORMAL, MAJOR, 1.0, aspect, 0.0, FrictionLaw.EXACT.value, TABLE_ADDRESS
        )
        assert float(np.hypot(*(np.array(force[:2]) - exact_force))) <= INTERPOLATION_FORCE_ERROR
        assert abs(moment - exact_moment) <= INTERPOLATION_MOMENT_ERROR


def test_equal_axes_give_the_exact_disk_law_and_unknown_laws_nan() -> None:
    slip, spin = (2e-4, -1e-4, 0.0), 0.7
    force, moment = elliptic_contact_friction(
        slip, spin, NORMAL, MAJOR, 1e-3, 1e-3, 1e-9, 1, TABLE_ADDRESS
    )
    disk_force, disk_moment = contact_friction(
        slip, spin, 1e-3, 1e-9, FrictionLaw.EXACT.value, ContactPressure.HERTZ.value
    )
    assert force == disk_force and moment == disk_moment
    force, moment = elliptic_contact_friction(
        slip, spin, NORMAL, MAJOR, 1e-3, 5e-4, 1e-9, 7, TABLE_ADDRESS
    )
    assert math.isnan(moment) and all(math.isnan(f) for f in force)


@pytest.mark.parametrize("failure", [OSError(28, "No space left on device"), KeyboardInterrupt()])
def test_a_failed_table_write_leaves_the_old_table_and_no_temporary(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, failure: BaseException
) -> None:
    """Whole or not at all: a full disk or a Ctrl-C during the write keeps the table that
    was there and removes the temporary."""
    target = tmp_path / "table.npz"
    target.write_bytes(b"the previous table")
    monkeypatch.setattr(ellipse_table, "generate_table", lambda: {"ratios": np.zeros(3)})

    def fail(*args: object, **kwargs: object) -> None:
        raise failure

    monkeypatch.setattr(ellipse_table.np, "savez", fail)
    with pytest.raises(type(failure)):
        ellipse_table.write_table(target)
    assert target.read_bytes() == b"the previous table"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["table.npz"]


def test_a_table_write_replaces_the_table_whole(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "table.npz"
    target.write_bytes(b"the previous table")
    monkeypatch.setattr(ellipse_table, "generate_table", lambda: {"ratios": np.arange(3.0)})
    ellipse_table.write_table(target)
    with np.load(target) as written:
        np.testing.assert_array_equal(written["ratios"], np.arange(3.0))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["table.npz"]
