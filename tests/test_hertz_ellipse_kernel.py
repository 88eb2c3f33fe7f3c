"""The compiled elliptic Hertz contact: principal radii at the contact point, Carlson's R_D,
and the ellipse's semi-axes against ``contact.ellipse.hertz_ellipse`` (Johnson 1985, §4.2).

Kane & Levinson (1982): semi-axes a, b, c = 0.20, 0.03, 0.02 m, h = 0.01 m, m = 1 kg,
g = 9.81 m/s² (references.md), radii of curvature at rest a²/c = 2 m and b²/c = 0.045 m.
Issue 13: with the E* that makes the circular radius ε = 1.089 mm, the Hertz ellipse
at rest is about 3.14 mm × 0.28 mm, B/A ≈ 0.089 (docs/equations.md: 3.139 mm, 0.2790 mm).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import special

import celtstone as cs
from celtstone.contact.ellipse import hertz_ellipse
from celtstone.kernels import layout
from celtstone.kernels.geometry import contact
from celtstone.kernels.hertz import equivalent_radius, hertz_contact_radius
from celtstone.kernels.hertz_ellipse import (
    axis_ratio_squared,
    carlson_rd,
    complete_rd,
    hertz_ellipse_axes,
    principal_radii,
    radius_of_curvature_tensor,
)
from celtstone.kernels.vector import tangent_basis
from celtstone.simulation.models import kernel_parameters

AXES, OFFSET = (0.20, 0.03, 0.02), 0.01  # Kane & Levinson (references.md)
LOAD = 1.0 * 9.81  # m g of Kane & Levinson's stone [N]
CIRCULAR_RADIUS = 1.089e-3  # issue 13 [m]
ISSUE_SEMI_AXES = (3.139e-3, 0.2790e-3)  # docs/equations.md, issue 13: 3.14 mm × 0.28 mm
EGG_TERMS = (  # x²/a² + y²/b² + z²/c² + 0.3 z³/c³ + 0.1 z⁴/c⁴: convex (test_implicit_shape.py)
    (1 / AXES[0] ** 2, 2, 0, 0),
    (1 / AXES[1] ** 2, 0, 2, 0),
    (1 / AXES[2] ** 2, 0, 0, 2),
    (0.3 / AXES[2] ** 3, 0, 0, 3),
    (0.1 / AXES[2] ** 4, 0, 0, 4),
)
UP = (0.0, 0.0, 1.0)


def random_verticals(
    count: int, seed: int, spread: float = 0.4
) -> list[tuple[float, float, float]]:
    """Unit verticals within ~spread rad of e3, no component near 0 (off the flat curves
    of a superellipsoid)."""
    rng = np.random.default_rng(seed)
    verticals: list[tuple[float, float, float]] = []
    while len(verticals) < count:
        n = np.array([*rng.normal(scale=spread, size=2), 1.0])
        n /= np.linalg.norm(n)
        if min(abs(n)) > 0.02:
            verticals.append((float(n[0]), float(n[1]), float(n[2])))
    return verticals


@pytest.fixture(scope="module")
def kane_levinson_params() -> np.record:
    return kernel_parameters(cs.SlidingModel(), cs.load_body("kane_levinson_1982"))


def shape_params() -> dict[str, np.record]:
    """A record of each shape code: K&L's ellipsoid, paraboloid, superellipsoid p = 2.5 (a
    raw record: models refuse its flat rest point), egg."""
    body = cs.load_body("kane_levinson_1982")
    superellipsoid = layout.parameter_record(
        shape_code=layout.ShapeCode.SUPERELLIPSOID, semi_axes=AXES, com_offset=OFFSET, exponent=2.5
    )
    return {
        "ellipsoid": kernel_parameters(cs.SlidingModel(), body),
        "paraboloid": kernel_parameters(
            cs.SlidingModel(), cs.load_body("kane_levinson_1982_paraboloid")
        ),
        "superellipsoid": superellipsoid,
        "implicit": cs.ImplicitPolynomial(terms=EGG_TERMS, com_offset=OFFSET).kernel_record(),
    }


SHAPES = shape_params()


def test_every_shape_code_is_covered() -> None:
    assert {int(p.shape_code) for p in SHAPES.values()} == {c.value for c in layout.ShapeCode}


# --- Carlson's R_D ----------------------------------------------------------------------


def test_carlson_rd_matches_scipy_at_random_arguments() -> None:
    """Arguments spanning 12 decades, a third with x = 0 (the complete case)."""
    rng = np.random.default_rng(11)
    for _ in range(3000):
        x, y, z = rng.uniform(0.0, 1.0, 3) * 10.0 ** rng.uniform(-6.0, 6.0, 3)
        if rng.random() < 0.3:
            x = 0.0
        assert carlson_rd(x, y, z) == pytest.approx(special.elliprd(x, y, z), rel=1e-14)


def test_carlson_rd_closed_forms() -> None:
    """R_D(z, z, z) = z^(-3/2); R_D(0, 1, 1) = 3π/4 (DLMF 19.20.18, 19.20.2)."""
    assert carlson_rd(4.0, 4.0, 4.0) == 0.125
    assert carlson_rd(0.0, 1.0, 1.0) == pytest.approx(0.75 * math.pi, rel=1e-15)


@pytest.mark.parametrize("p", [1 - 1e-12, 1 - 1e-6, 0.9, 0.5, 0.0079, 1e-4, 1e-8, 1e-12])
def test_complete_rd_by_the_agm_matches_duplication_and_scipy(p: float) -> None:
    major, minor = complete_rd(math.log(p))
    for value, arguments in ((major, (0.0, p, 1.0)), (minor, (0.0, 1.0, p))):
        assert value == pytest.approx(carlson_rd(*arguments), rel=1e-14)
        assert value == pytest.approx(special.elliprd(*arguments), rel=1e-14)


# --- principal radii ----------------------------------------------------------------------


def test_kane_levinson_at_rest(kane_levinson_params: np.record) -> None:
    """n = e3: R1 = a²/c = 2 m along e1, R2 = b²/c = 0.045 m (issue 13)."""
    a, b, c = AXES
    larger, smaller, direction = principal_radii(UP, kane_levinson_params)
    assert larger == pytest.approx(a * a / c, rel=1e-14)
    assert smaller == pytest.approx(b * b / c, rel=1e-14)
    assert (larger, smaller) == pytest.approx((2.0, 0.045), rel=1e-14)
    assert direction == (1.0, 0.0, 0.0)


def ellipsoid_radii_by_second_fundamental_form(
    n: tuple, axes: tuple
) -> tuple[float, float, np.ndarray]:
    """Principal radii and the direction of the larger at the point of outward normal −n of
    x²/a² + y²/b² + z²/c² = 1, from F's Hessian: the shape operator on the tangent plane is
    P ∇²F P / |∇F| (P the projector ⊥ ∇F), ∇F = 2x/a², ∇²F = 2 diag(1/a²)."""
    q = np.diag(np.square(axes))
    u = np.asarray(n) / np.linalg.norm(n)
    x = -q @ u / math.sqrt(u @ q @ u)  # lowest point: F = 1, ∇F ∥ −n
    gradient = 2.0 * x / np.square(axes)
    normal = gradient / np.linalg.norm(gradient)
    projector = np.eye(3) - np.outer(normal, normal)
    shape_operator = projector @ np.diag(2.0 / np.square(axes)) @ projector
    shape_operator /= np.linalg.norm(gradient)
    curvatures, vectors = np.linalg.eigh(shape_operator)
    tangent = np.abs(vectors.T @ normal) < 0.5  # drop the normal's zero eigenvalue
    curvatures, vectors = curvatures[tangent], vectors[:, tangent]
    return 1.0 / curvatures[0], 1.0 / curvatures[1], vectors[:, 0]


def test_tilted_ellipsoid_against_the_second_fundamental_form(
    kane_levinson_params: np.record,
) -> None:
    for n in random_verticals(200, 5, spread=1.0):
        larger, smaller, direction = principal_radii(n, kane_levinson_params)
        expected_larger, expected_smaller, expected_direction = (
            ellipsoid_radii_by_second_fundamental_form(n, AXES)
        )
        assert larger == pytest.approx(expected_larger, rel=1e-12)
        assert smaller == pytest.approx(expected_smaller, rel=1e-12)
        assert abs(np.dot(direction, expected_direction)) == pytest.approx(1.0, abs=1e-12)
        assert np.dot(direction, n) == pytest.approx(0.0, abs=1e-14)
        assert np.linalg.norm(direction) == pytest.approx(1.0, abs=1e-15)


def test_paraboloid_at_rest() -> None:
    """z = x²/(2ρ1) + y²/(2ρ2): the radii at the vertex are ρ1, ρ2 along e1, e2; the larger
    first, whichever axis it lies on."""
    for radii, axis in (((2.0, 0.045), (1.0, 0.0, 0.0)), ((0.045, 2.0), (0.0, 1.0, 0.0))):
        params = layout.parameter_record(
            shape_code=layout.ShapeCode.PARABOLOID, radii_of_curvature=radii, com_height=0.01
        )
        larger, smaller, direction = principal_radii(UP, params)
        assert (larger, smaller) == pytest.approx((2.0, 0.045), rel=1e-14)
        assert direction == axis


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_product_of_the_radii_is_the_gaussian_route(name: str) -> None:
    """R1 R2 = 1/K = R_eq² of ``kernels.hertz.equivalent_radius`` (Gaussian curvature by
    closed forms or the Hessian, not by dr/dn)."""
    params = SHAPES[name]
    for n in random_verticals(100, 7):
        larger, smaller, _ = principal_radii(n, params)
        assert larger * smaller == pytest.approx(equivalent_radius(n, params) ** 2, rel=1e-11)
        assert larger >= smaller > 0.0


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_the_tensor_is_symmetric_and_dr_dn_kills_n(name: str) -> None:
    """R12 = R21 (the Weingarten map is self-adjoint), and r is homogeneous of degree 0 in n,
    so the contact kernel's rate for ṅ = n is 0: the tensor only sees ṅ's tangent part."""
    params = SHAPES[name]
    for n in random_verticals(100, 9):
        _, _, (r11, r12, r21, r22), status = radius_of_curvature_tensor(n, params)
        assert status == layout.RHS_OK
        scale = max(abs(r11), abs(r22))
        assert abs(r12 - r21) <= 1e-12 * scale
        r, along = contact(n, n, params)
        assert np.max(np.abs(along)) <= 1e-13 * np.max(np.abs(r))


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_the_vertical_need_not_be_unit(name: str) -> None:
    params = SHAPES[name]
    for n in random_verticals(20, 13):
        larger, smaller, direction = principal_radii(n, params)
        for factor in (0.3, 7.0):
            stretched = principal_radii((factor * n[0], factor * n[1], factor * n[2]), params)
            assert stretched[:2] == pytest.approx((larger, smaller), rel=1e-13)
            assert stretched[2] == pytest.approx(direction, abs=1e-12)


def test_round_point_gives_a_deterministic_direction() -> None:
    """A sphere, and an ellipsoid with a = b at rest: R1 = R2 and d = t1 of the tangent basis."""
    sphere = layout.parameter_record(
        shape_code=layout.ShapeCode.ELLIPSOID, semi_axes=(0.05, 0.05, 0.05), com_offset=0.01
    )
    spheroid = layout.parameter_record(
        shape_code=layout.ShapeCode.ELLIPSOID, semi_axes=(0.03, 0.03, 0.02), com_offset=0.01
    )
    cases = [(sphere, n, 0.05) for n in [UP, *random_verticals(20, 17)]]
    cases.append((spheroid, UP, 0.045))
    for params, n, radius in cases:
        larger, smaller, direction = principal_radii(n, params)
        assert (larger, smaller) == pytest.approx((radius, radius), rel=1e-13)
        assert np.all(np.isfinite(direction))
        assert abs(np.dot(direction, n)) < 1e-15
        _, t1, _ = tangent_basis(n)
        assert direction == pytest.approx(t1 if max(t1, key=abs) > 0 else -np.array(t1))
        assert principal_radii(n, params)[2] == direction


def test_bad_states_give_nan() -> None:
    """Off the paraboloid cap, a flat point (superellipsoid p > 2 at rest), a saddle, an
    unknown shape code, n = 0: NaN radii and direction, for the caller's status."""
    saddle = layout.parameter_record(
        shape_code=layout.ShapeCode.PARABOLOID, radii_of_curvature=(2.0, -0.045), com_height=0.01
    )
    unknown = layout.parameter_record(shape_code=len(layout.ShapeCode), semi_axes=AXES)
    tilted = (1.0, 0.0, 5e-4)  # n3 < 1e-3: off the cap (geometry.contact_status)
    cases = [
        (SHAPES["paraboloid"], tilted),
        (SHAPES["paraboloid"], (0.0, 0.0, -1.0)),
        (SHAPES["superellipsoid"], UP),
        (saddle, UP),
        (unknown, UP),
        (SHAPES["ellipsoid"], (0.0, 0.0, 0.0)),
    ]
    for params, n in cases:
        larger, smaller, direction = principal_radii(n, params)
        assert math.isnan(larger) and math.isnan(smaller) and np.all(np.isnan(direction))


# --- semi-axes of the Hertz ellipse ---------------------------------------------------------


@pytest.mark.parametrize(
    "ratio",
    [1.0, 1 + 1e-12, 1 + 1e-8, 1 + 9e-7, 1 + 2e-6, *np.geomspace(1.0001, 1e4, 41), 1e6, 1e8],
)
def test_semi_axes_match_the_reference(ratio: float) -> None:
    """Against ``contact.ellipse.hertz_ellipse`` (SciPy's R_D and brentq), 1e-12 relative,
    across the series branch (R1/R2 − 1 < 1e-6), Newton's two starts and beyond 1e4."""
    larger, load, modulus = 0.7, 3.0, 2.5e9
    semi_major, semi_minor = hertz_ellipse_axes(larger, larger / ratio, load, modulus)
    reference = hertz_ellipse((larger, larger / ratio), load, modulus)
    assert semi_major == pytest.approx(reference.semi_major_axis, rel=1e-12)
    assert semi_minor == pytest.approx(reference.semi_minor_axis, rel=1e-12)


@pytest.mark.parametrize("radius", [0.01, 0.3, 2.0])
def test_equal_radii_give_todays_circle(radius: float) -> None:
    circle = hertz_contact_radius(5.0, radius, 2e9)
    assert hertz_ellipse_axes(radius, radius, 5.0, 2e9) == pytest.approx(
        (circle, circle), rel=1e-15
    )


def test_axis_ratio_solves_johnsons_relation() -> None:
    """R1/R2 = [E/(1 − e²) − K]/(K − E) with SciPy's K, E (Johnson eq. 4.36)."""
    for ratio in (1.5, 10.0, 44.4, 1e3):
        p, _ = axis_ratio_squared(ratio)
        k, e = special.ellipk(1.0 - p), special.ellipe(1.0 - p)
        assert (e / p - k) / (k - e) == pytest.approx(ratio, rel=1e-10)


def test_kane_levinson_contact_ellipse_at_rest(kane_levinson_params: np.record) -> None:
    """Issue 13: E* with ε = (3 m g R_eq/(4 E*))^(1/3) = 1.089 mm, R_eq = sqrt(R1 R2)
    (kernels.hertz, as the models compute ε), gives A = 3.139 mm, B = 0.279 mm."""
    larger, smaller, direction = principal_radii(UP, kane_levinson_params)
    equivalent = equivalent_radius(UP, kane_levinson_params)
    modulus = 0.75 * LOAD * equivalent / CIRCULAR_RADIUS**3
    assert modulus == pytest.approx(1.709e9, rel=5e-4)  # docs/equations.md
    assert hertz_contact_radius(LOAD, equivalent, modulus) == pytest.approx(CIRCULAR_RADIUS)
    semi_major, semi_minor = hertz_ellipse_axes(larger, smaller, LOAD, modulus)
    assert semi_major == pytest.approx(ISSUE_SEMI_AXES[0], rel=5e-4)
    assert semi_minor == pytest.approx(ISSUE_SEMI_AXES[1], rel=5e-4)
    assert semi_minor / semi_major == pytest.approx(0.0889, abs=5e-5)
    assert direction == (1.0, 0.0, 0.0)  # the major axis along the stone's long axis


@pytest.mark.parametrize(
    "radii", [(1.0, 0.0), (1.0, -0.5), (0.5, 1.0), (math.nan, 1.0), (1.0, math.nan)]
)
def test_bad_radii_give_nan(radii: tuple[float, float]) -> None:
    assert all(math.isnan(v) for v in hertz_ellipse_axes(*radii, 1.0, 1e9))
