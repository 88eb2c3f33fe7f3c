"""The superellipsoid |x/a|^p + |y/b|^p + |z/c|^p = 1: its contact kernel against the surface
equation and its normal, p = 2 against the ellipsoid, bad exponents, and the flat points."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

import celtstone as cs
from celtstone.kernels.geometry import ellipsoid_contact, superellipsoid_contact

AXES, OFFSET = (0.20, 0.03, 0.02), 0.01  # Kane & Levinson (references.md)


def superellipsoid_body(kane_levinson: cs.Body, exponent: float) -> cs.Body:
    """Kane & Levinson's mass and inertia on a superellipsoid with their semi-axes."""
    return dataclasses.replace(kane_levinson, shape=cs.Superellipsoid(AXES, OFFSET, exponent))


def unit(vector: np.ndarray) -> tuple[float, float, float]:
    v = np.asarray(vector, dtype=float) / np.linalg.norm(vector)
    return (float(v[0]), float(v[1]), float(v[2]))


directions = st.tuples(*[st.floats(-1.0, 1.0) for _ in range(3)]).filter(
    lambda v: np.linalg.norm(v) > 0.1 and min(abs(c) for c in v) > 1e-3
)


@given(direction=directions, exponent=st.floats(2.0, 12.0))
def test_contact_is_on_the_surface_with_normal_minus_n(
    direction: tuple[float, float, float], exponent: float
) -> None:
    """F(x) = 1 and ∇F(x) ∥ −n, with x = r − h e3 measured from the centre."""
    n = unit(direction)
    r, _ = superellipsoid_contact(n, (0.0, 0.0, 0.0), *AXES, OFFSET, exponent)
    x = np.array(r) - np.array([0.0, 0.0, OFFSET])
    scaled = x / np.array(AXES)
    assert np.sum(np.abs(scaled) ** exponent) == pytest.approx(1.0, rel=1e-12)
    gradient = np.sign(x) * np.abs(scaled) ** (exponent - 1) / np.array(AXES)
    outward = gradient / np.linalg.norm(gradient)
    assert np.allclose(outward, -np.array(n), atol=1e-10)


@given(direction=directions, rate=st.tuples(*[st.floats(-1.0, 1.0) for _ in range(3)]))
@example(direction=(1.0, 1.0, 1.0), rate=(1.0, 1.0, 1.0))  # ṅ ∥ n: a case CI once failed
def test_contact_rate_is_the_derivative(
    direction: tuple[float, float, float], rate: tuple[float, float, float]
) -> None:
    """dr/dt against a central difference of r(n + t ṅ), p = 3, away from the flat curves.

    ṅ is taken in the tangent plane (n · ṅ = 0, as for a unit normal). The absolute tolerance
    is set by the body's size, not by the difference itself: when ṅ is nearly zero the
    difference is pure rounding, about 1e-16 · 0.2 m / step."""
    n = np.array(unit(direction))
    tangent_rate = np.array(rate) - np.dot(rate, n) * n
    step = 1e-6 * min(abs(c) for c in n)
    _, r_rate = superellipsoid_contact(tuple(n), tuple(tangent_rate), *AXES, OFFSET, 3.0)
    ahead = n + step * tangent_rate
    behind = n - step * tangent_rate
    r_ahead, _ = superellipsoid_contact(tuple(ahead), (0.0, 0.0, 0.0), *AXES, OFFSET, 3.0)
    r_behind, _ = superellipsoid_contact(tuple(behind), (0.0, 0.0, 0.0), *AXES, OFFSET, 3.0)
    numerical = (np.array(r_ahead) - np.array(r_behind)) / (2 * step)
    rounding = 1e-14 * max(AXES) / step  # [m/s] per unit |ṅ|, well above 1e-16 · 0.2 / step
    assert np.allclose(r_rate, numerical, rtol=1e-5, atol=rounding + 1e-7 * max(AXES))


@given(direction=directions, rate=st.tuples(*[st.floats(-1.0, 1.0) for _ in range(3)]))
def test_exponent_two_is_the_ellipsoid_kernel(
    direction: tuple[float, float, float], rate: tuple[float, float, float]
) -> None:
    n = unit(direction)
    r_s, rate_s = superellipsoid_contact(n, rate, *AXES, OFFSET, 2.0)
    r_e, rate_e = ellipsoid_contact(n, rate, *AXES, OFFSET)
    assert np.allclose(r_s, r_e, rtol=1e-14, atol=1e-17)
    assert np.allclose(rate_s, rate_e, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("model", [cs.RollingModel(), cs.SlidingModel(friction_coefficient=0.25)])
def test_exponent_two_runs_like_the_ellipsoid(kane_levinson: cs.Body, model: cs.Model) -> None:
    """Kane & Levinson's −5 rad/s start through its reversal: the same run to 1e-8."""
    state = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
    ellipsoid = cs.simulate(model, kane_levinson, state, 4.0)
    superellipsoid = cs.simulate(model, superellipsoid_body(kane_levinson, 2.0), state, 4.0)
    assert ellipsoid.ok and superellipsoid.ok
    for name in ("spin", "tilt", "energy", "normal_force"):
        a, b = ellipsoid.dataset[name].values, superellipsoid.dataset[name].values
        assert np.max(np.abs(a - b)) <= 1e-8 * np.max(np.abs(a)), name
    assert superellipsoid.dataset.attrs["body_shape"] == "superellipsoid"
    assert json.loads(superellipsoid.dataset.attrs["body_shape_table"])["exponent"] == 2.0
    assert superellipsoid.first_spin_crossing_time == pytest.approx(
        ellipsoid.first_spin_crossing_time, rel=1e-8
    )
    if isinstance(model, cs.RollingModel):
        energy = superellipsoid.dataset["energy"].values
        assert np.max(np.abs(energy - energy[0])) < 1e-9 * energy[0]


def test_exponent_two_has_the_ellipsoid_stability(kane_levinson: cs.Body) -> None:
    spins = np.linspace(-10.0, 10.0, 21)
    expected = cs.spin_stability(kane_levinson, spins).eigenvalues
    found = cs.spin_stability(superellipsoid_body(kane_levinson, 2.0), spins).eigenvalues
    assert np.allclose(found, expected, rtol=1e-10, atol=0.0)


@pytest.mark.parametrize(
    ("exponent", "hint"),
    [(0.5, "non-convex"), (1.0, "edges"), (1.9, "edges"), (65.0, ""), (float("nan"), "")],
)
def test_bad_exponents_are_refused(exponent: float, hint: str) -> None:
    with pytest.raises(cs.ParameterError, match=r"exponent = .*\[2, 64\]") as error:
        cs.Superellipsoid(AXES, OFFSET, exponent)
    assert hint in str(error.value)
    assert "\n" not in str(error.value)


def test_body_file_with_a_superellipsoid(tmp_path) -> None:
    path = tmp_path / "rounded_box.toml"
    path.write_text(
        "[body]\nmass = 1.0\ninertia = [[2e-4, 0, 0], [0, 1.6e-3, 0], [0, 0, 1.7e-3]]\n"
        '[shape]\nkind = "superellipsoid"\nsemi_axes = [0.2, 0.03, 0.02]\n'
        "com_offset = 0.01\nexponent = 4.0\n"
    )
    body = cs.load_body(path)
    assert isinstance(body.shape, cs.Superellipsoid) and body.shape.exponent == 4.0
    path.write_text(path.read_text().replace("exponent = 4.0", "exponent = 1.5"))
    with pytest.raises(cs.ParameterError, match="exponent"):
        cs.load_body(path)


@pytest.mark.parametrize("exponent", [2.5, 3.0, 4.0, 64.0])
@pytest.mark.parametrize(
    "model", [cs.RollingModel(), cs.SlidingModel()], ids=["rolling", "sliding"]
)
def test_flat_points_refuse_stability_and_runs_up_front(
    kane_levinson: cs.Body, exponent: float, model: cs.Model
) -> None:
    """For p > 2 the normal curvature vanishes on the coordinate planes (∂²F/∂x² ∝ |x|^(p-2)),
    the rest contact included: dr/dt is unbounded as n1 or n2 crosses zero, so stability and
    every run are refused before anything is integrated, with that reason."""
    flat = superellipsoid_body(kane_levinson, exponent)
    with pytest.raises(cs.ParameterError, match="finite radii of curvature"):
        cs.spin_stability(flat, [1.0])
    with pytest.raises(cs.ParameterError, match="flat point") as caught:
        cs.simulate(model, flat, cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5)), 10.0)
    assert caught.value.name == "shape"
    assert "exponent 2" in str(caught.value)
