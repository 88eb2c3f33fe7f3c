"""Shipped bodies: loading, the published numbers and the derived rest-contact geometry.

Expected numbers are Kane & Levinson (1982), Int. J. Non-Linear Mech. 17(3), 175–186,
as quoted in ../shared/references.md, and formulas of docs/bodies.md worked by hand.
"""

from __future__ import annotations

import dataclasses
import math
from importlib import resources

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import celtstone as cs

KL_NAME = "kane_levinson_1982"
PARABOLOID_NAME = "kane_levinson_1982_paraboloid"

# references.md: a = 0.20 m, b = 0.03 m, c = 0.02 m, h = 0.01 m, m = 1.0 kg, g = 9.81 m/s^2
A_AXIS, B_AXIS, C_AXIS, H_OFFSET = 0.20, 0.03, 0.02, 0.01
KL_INERTIA = [[2e-4, -2e-5, 0.0], [-2e-5, 1.6e-3, 0.0], [0.0, 0.0, 1.7e-3]]


def test_list_bodies_names_the_shipped_sets_with_their_sources() -> None:
    bodies = cs.list_bodies()
    assert set(bodies) >= {KL_NAME, PARABOLOID_NAME}
    for name in (KL_NAME, PARABOLOID_NAME):
        source = bodies[name]
        assert "Kane" in source and "Levinson" in source
        assert "1982" in source
        assert "Realistic mathematical modeling of the rattleback" in source
        assert "17(3)" in source and "175-186" in source


def test_every_listed_body_loads(any_body: cs.Body) -> None:
    assert any_body.name in cs.list_bodies()
    assert any_body.source == cs.list_bodies()[any_body.name]


def test_kane_levinson_numbers(kane_levinson: cs.Body) -> None:
    body = kane_levinson
    assert body.name == KL_NAME
    assert body.mass == 1.0
    assert body.gravity == 9.81  # the paper's, not scipy.constants.g
    np.testing.assert_array_equal(body.inertia_array, KL_INERTIA)
    assert isinstance(body.shape, cs.Ellipsoid)
    assert body.shape.semi_axes == (A_AXIS, B_AXIS, C_AXIS)
    assert body.shape.com_offset == H_OFFSET
    assert body.citation["year"] == "1982"


def test_load_by_path_equals_load_by_name(kane_levinson: cs.Body) -> None:
    path = resources.files("celtstone.bodies") / "data" / f"{KL_NAME}.toml"
    with resources.as_file(path) as file:
        by_path = cs.load_body(file)
        by_string = cs.load_body(str(file))
    assert by_path == kane_levinson
    assert by_string == kane_levinson


def test_misalignment_angle_is_plus_0_82_degrees(kane_levinson: cs.Body) -> None:
    """references.md: D = I12 = -2e-5 turns the long principal axis by about +0.82°.

    Independently: the principal axes of [[A, D], [D, B]] are turned by θ with
    tan 2θ = 2D / (A - B) = -4e-5 / -1.4e-3, θ = 0.8184°.
    """
    expected = 0.5 * math.atan(2 * -2e-5 / (2e-4 - 1.6e-3))
    angle = kane_levinson.misalignment_angle
    assert angle == pytest.approx(expected, rel=1e-9)
    assert math.degrees(angle) == pytest.approx(0.82, abs=0.005)
    # the long principal axis is an eigenvector of the tensor with the smallest moment
    axis = np.array([math.cos(angle), math.sin(angle), 0.0])
    image = kane_levinson.inertia_array @ axis
    assert np.linalg.norm(np.cross(image, axis)) < 1e-12 * np.linalg.norm(image)


@pytest.mark.parametrize(
    ("product", "sign"), [(-2e-5, 1.0), (2e-5, -1.0), (0.0, 0.0)], ids=["D<0", "D>0", "D=0"]
)
def test_misalignment_sign_follows_the_product_of_inertia(
    kane_levinson: cs.Body, product: float, sign: float
) -> None:
    inertia = np.array(KL_INERTIA)
    inertia[0, 1] = inertia[1, 0] = product
    body = dataclasses.replace(kane_levinson, inertia=inertia.tolist())
    assert math.degrees(body.misalignment_angle) == pytest.approx(sign * 0.8184, abs=1e-3)


def test_ellipsoid_rest_geometry(kane_levinson: cs.Body) -> None:
    """docs/bodies.md: ρ1 = a²/c = 2.0 m, ρ2 = b²/c = 0.045 m, l = c - h = 0.01 m."""
    rho1, rho2 = kane_levinson.shape.radii_of_curvature
    assert rho1 == pytest.approx(2.0, rel=1e-14)
    assert rho2 == pytest.approx(0.045, rel=1e-14)
    assert kane_levinson.shape.rest_height == pytest.approx(0.01, rel=1e-14)


@pytest.mark.parametrize(
    ("axes", "offset", "radii", "height"),
    [
        ((1.0, 2.0, 4.0), 1.0, (0.25, 1.0), 3.0),
        ((0.3, 0.1, 0.05), -0.02, (1.8, 0.2), 0.07),
    ],
)
def test_ellipsoid_geometry_formulas(
    axes: tuple[float, float, float],
    offset: float,
    radii: tuple[float, float],
    height: float,
) -> None:
    shape = cs.Ellipsoid(axes, offset)
    assert shape.radii_of_curvature == pytest.approx(radii, rel=1e-14)
    assert shape.rest_height == pytest.approx(height, rel=1e-14)


def test_paraboloid_file_is_the_osculating_paraboloid(kane_levinson: cs.Body) -> None:
    paraboloid = cs.load_body(PARABOLOID_NAME)
    assert isinstance(paraboloid.shape, cs.Paraboloid)
    assert paraboloid.shape.radii_of_curvature == pytest.approx(
        kane_levinson.shape.radii_of_curvature, rel=1e-12
    )
    assert paraboloid.shape.com_height == pytest.approx(kane_levinson.shape.rest_height, rel=1e-12)
    assert paraboloid.shape.rest_height == paraboloid.shape.com_height
    assert paraboloid.mass == kane_levinson.mass
    assert paraboloid.gravity == kane_levinson.gravity
    assert paraboloid.inertia == kane_levinson.inertia
    assert paraboloid.notes  # the conversion is written down


def test_body_is_frozen_and_stores_the_tensor_as_tuples(kane_levinson: cs.Body) -> None:
    with pytest.raises(dataclasses.FrozenInstanceError):
        kane_levinson.mass = 2.0  # type: ignore[misc]
    assert isinstance(kane_levinson.inertia, tuple)
    assert all(isinstance(row, tuple) for row in kane_levinson.inertia)
    hash(kane_levinson)


# ---------------------------------------------------------------------------------------
# Random inertia tensors
# ---------------------------------------------------------------------------------------

SHAPE = cs.Ellipsoid((A_AXIS, B_AXIS, C_AXIS), H_OFFSET)


def _rotation(vector: tuple[float, float, float, float]) -> np.ndarray:
    """Rotation matrix of the (not yet normalised) quaternion ``vector``."""
    w, x, y, z = np.asarray(vector) / np.linalg.norm(vector)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _tensor(moments: tuple[float, float, float], quaternion) -> np.ndarray:
    rotation = _rotation(quaternion)
    tensor = rotation @ np.diag(moments) @ rotation.T
    return 0.5 * (tensor + tensor.T)  # exactly symmetric


quaternions = st.tuples(*[st.floats(-1.0, 1.0) for _ in range(4)]).filter(
    lambda q: sum(v * v for v in q) > 0.01
)
scales = st.floats(1e-6, 1.0)
unit_fractions = st.floats(0.05, 1.0)


@given(scale=scales, second=unit_fractions, third=st.floats(0.0, 1.0), q=quaternions)
def test_real_mass_distributions_are_accepted(
    scale: float, second: float, third: float, q: tuple[float, float, float, float]
) -> None:
    """Positive moments A1 >= A2 and A3 strictly inside (A1 - A2, A1 + A2), any orientation."""
    a1 = scale
    a2 = scale * second
    low, high = (a1 - a2) + 1e-3 * (a1 + a2), (a1 + a2) * (1 - 1e-3)
    a3 = low + third * (high - low)
    tensor = _tensor((a1, a2, a3), q)
    body = cs.Body(name="random", mass=1.0, inertia=tensor.tolist(), shape=SHAPE)
    np.testing.assert_allclose(body.inertia_array, tensor, rtol=0, atol=0)
    np.testing.assert_allclose(
        np.linalg.eigvalsh(body.inertia_array), sorted((a1, a2, a3)), rtol=1e-9
    )


@given(scale=scales, second=unit_fractions, negative=st.floats(1e-3, 1.0), q=quaternions)
def test_a_negative_principal_moment_is_rejected(
    scale: float, second: float, negative: float, q: tuple[float, float, float, float]
) -> None:
    tensor = _tensor((scale, scale * second, -negative * scale * second), q)
    with pytest.raises(cs.ParameterError) as caught:
        cs.Body(name="random", mass=1.0, inertia=tensor.tolist(), shape=SHAPE)
    assert caught.value.name == "inertia"
    assert "positive-definite" in caught.value.allowed


@given(scale=scales, second=unit_fractions, excess=st.floats(1e-3, 10.0), q=quaternions)
def test_moments_violating_the_triangle_inequality_are_rejected(
    scale: float, second: float, excess: float, q: tuple[float, float, float, float]
) -> None:
    a1, a2 = scale, scale * second
    tensor = _tensor((a1, a2, (a1 + a2) * (1 + excess)), q)
    with pytest.raises(cs.ParameterError) as caught:
        cs.Body(name="random", mass=1.0, inertia=tensor.tolist(), shape=SHAPE)
    assert caught.value.name == "inertia"
    assert "A3 <= A1 + A2" in caught.value.allowed


def test_toy_rattleback_follows_from_its_derivation() -> None:
    """The toy's mass, G offset and inertia tensor follow from its [derivation] table:
    a solid half-ellipsoid (volume 2πabc/3, G at 3c/8 below the centre, second moments
    m a²/5, m b²/5, m c²/5 about the centre) plus two point masses μ at ±(x0, y0, 0),
    moved to the common centre of mass (parallel-axis theorem)."""
    import tomllib

    text = resources.files("celtstone.bodies").joinpath("data/toy_rattleback_10cm.toml")
    data = tomllib.loads(text.read_text(encoding="utf-8"))["derivation"]
    a, b, c = data["semi_axes"]
    mu = data["point_mass"]
    x0, y0 = data["point_mass_position"]
    shell = data["density"] * 2.0 / 3.0 * math.pi * a * b * c
    mass = shell + 2.0 * mu
    h = 3.0 * c / 8.0 * shell / mass
    expected = np.array(
        [
            [shell * (b * b + c * c) / 5 + 2 * mu * y0 * y0 - mass * h * h, -2 * mu * x0 * y0, 0],
            [-2 * mu * x0 * y0, shell * (a * a + c * c) / 5 + 2 * mu * x0 * x0 - mass * h * h, 0],
            [0, 0, shell * (a * a + b * b) / 5 + 2 * mu * (x0 * x0 + y0 * y0)],
        ]
    )
    toy = cs.load_body("toy_rattleback_10cm")
    assert toy.mass == pytest.approx(mass, rel=1e-9)
    assert toy.shape.com_offset == pytest.approx(h, rel=1e-8)
    assert toy.shape.semi_axes == (a, b, c)
    np.testing.assert_allclose(toy.inertia_array, expected, rtol=2e-6, atol=1e-12)
    # a stable rest (l < rho2) and a misalignment of a few degrees, as in real toys
    assert toy.shape.rest_height < toy.shape.radii_of_curvature[1]
    assert 1.0 < math.degrees(abs(toy.misalignment_angle)) < 5.0
