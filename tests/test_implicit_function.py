"""Shapes given as a user's Python function F(x) with its gradient (issue 5, item 5).

Reference: the Kane & Levinson (1982) ellipsoid a, b, c = 0.20, 0.03, 0.02 m, h = 0.01 m
(references.md) written as a function, against the closed-form ellipsoid kernel, and
the superellipsoid |x/a|^4 + |y/b|^4 + |z/c|^4 against ``superellipsoid_contact``.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import celtstone as cs
from celtstone.errors import ParameterError
from celtstone.files import export
from celtstone.kernels import geometry
from celtstone.sweep import Sweep
from celtstone.visual import scene

A, B, C, H = 0.20, 0.03, 0.02, 0.01
STATE = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))


def ellipsoid_value(x: np.ndarray) -> float:
    return (x[0] / A) ** 2 + (x[1] / B) ** 2 + (x[2] / C) ** 2


def ellipsoid_gradient(x: np.ndarray) -> np.ndarray:
    return np.array([2 * x[0] / A**2, 2 * x[1] / B**2, 2 * x[2] / C**2])


def ellipsoid_hessian(x: np.ndarray) -> np.ndarray:
    return np.diag(np.array([2 / A**2, 2 / B**2, 2 / C**2]))


def egg_value(x: np.ndarray) -> float:  # convex for β² < 8γ/3 (test_implicit_shape.py)
    z = x[2] / C
    return (x[0] / A) ** 2 + (x[1] / B) ** 2 + z**2 + 0.3 * z**3 + 0.1 * z**4


def egg_gradient(x: np.ndarray) -> np.ndarray:
    z = x[2] / C
    return np.array([2 * x[0] / A**2, 2 * x[1] / B**2, (2 * z + 0.9 * z**2 + 0.4 * z**3) / C])


@pytest.fixture(scope="module")
def exact() -> cs.ImplicitFunction:
    """The ellipsoid with its Hessian given."""
    return cs.ImplicitFunction(
        ellipsoid_value, ellipsoid_gradient, H, hessian=ellipsoid_hessian, name="kl_ellipsoid"
    )


@pytest.fixture(scope="module")
def differenced() -> cs.ImplicitFunction:
    """The ellipsoid without its Hessian: the Hessian by central differences."""
    return cs.ImplicitFunction(ellipsoid_value, ellipsoid_gradient, H)


def random_pairs(count: int, seed: int) -> list[tuple[tuple, tuple]]:
    rng = np.random.default_rng(seed)
    return [(tuple(rng.normal(size=3)), tuple(rng.normal(size=3))) for _ in range(count)]


def relative(value: tuple, reference: tuple) -> float:
    return float(np.max(np.abs(np.subtract(value, reference))) / np.linalg.norm(reference))


@pytest.mark.parametrize(("fixture", "rate_tolerance"), [("exact", 1e-12), ("differenced", 1e-8)])
def test_function_ellipsoid_matches_closed_form(
    fixture: str, rate_tolerance: float, request: pytest.FixtureRequest
) -> None:
    """r to round-off either way; ṙ to round-off with the Hessian, ~1e-10 without."""
    params = request.getfixturevalue(fixture).kernel_record()
    for n, n_rate in random_pairs(300, 2):
        r, r_rate = geometry.contact(n, n_rate, params)
        r0, r0_rate = geometry.ellipsoid_contact(n, n_rate, A, B, C, H)
        assert relative(r, r0) < 1e-12
        assert relative(r_rate, r0_rate) < rate_tolerance


def test_function_egg_matches_the_polynomial_egg() -> None:
    """The same surface as terms and as a function: the same contact to round-off."""
    terms = [
        [1 / A**2, 2, 0, 0],
        [1 / B**2, 0, 2, 0],
        [1 / C**2, 0, 0, 2],
        [0.3 / C**3, 0, 0, 3],
        [0.1 / C**4, 0, 0, 4],
    ]
    polynomial = cs.ImplicitPolynomial(terms=terms, com_offset=H).kernel_record()
    function = cs.ImplicitFunction(egg_value, egg_gradient, H).kernel_record()
    for n, n_rate in random_pairs(200, 3):
        r, r_rate = geometry.contact(n, n_rate, function)
        r0, r0_rate = geometry.contact(n, n_rate, polynomial)
        assert relative(r, r0) < 1e-12
        assert relative(r_rate, r0_rate) < 1e-8  # the Hessian by differences


def test_sliding_run_matches_closed_form(exact: cs.ImplicitFunction, tmp_path: Path) -> None:
    """Kane & Levinson's body, sliding f = 0.35, eps = 1 mm: the same run to 1e-9 rad/s."""
    body = cs.load_body("kane_levinson_1982")
    model = cs.SlidingModel(friction_coefficient=0.35, contact_radius=1e-3)
    closed = cs.simulate(model, body, STATE, 3.0).dataset
    run = cs.simulate(model, replace(body, shape=exact), STATE, 3.0)
    assert run.status == "success"
    assert np.max(np.abs(run.dataset.spin.values - closed.spin.values)) < 1e-9
    attrs = run.dataset.attrs
    assert attrs["body_shape"] == "implicit_function"
    assert attrs["body_shape_function"] == "kl_ellipsoid"
    assert "def ellipsoid_gradient" in attrs["body_shape_function_source"]
    path = export.write(run.dataset, tmp_path / "run.nc")
    with xr.open_dataset(path) as saved, pytest.raises(ParameterError, match="cannot be redrawn"):
        scene.body_geometry(saved)


def test_sweeps_refuse_a_function_shape(exact: cs.ImplicitFunction) -> None:
    body = replace(cs.load_body("kane_levinson_1982"), shape=exact)
    with pytest.raises(ParameterError, match="implicit polynomial"):
        Sweep({"initial_spin": [-5.0, 5.0]}, body=body)


def plain_python(x: np.ndarray) -> float:
    return 1.0


def not_compilable(x: np.ndarray) -> float:
    return plain_python(x)  # calls a function numba has not compiled


def wrong_gradient(x: np.ndarray) -> np.ndarray:
    return np.array([2 * x[0] / A**2, 2 * x[1] / B**2, 3 * x[2] / C**2])


def wrong_hessian(x: np.ndarray) -> np.ndarray:
    return np.diag(np.array([2 / A**2, 2 / B**2, 3 / C**2]))


def test_a_wrong_hessian_is_refused() -> None:
    with pytest.raises(ParameterError, match="Hessian of value") as error:
        cs.ImplicitFunction(ellipsoid_value, ellipsoid_gradient, H, hessian=wrong_hessian)
    assert error.value.name == "hessian"


def waist_value(x: np.ndarray) -> float:  # x⁴/a⁴ − x²/(2a²) + ...: a waist at x = 0
    return (x[0] / A) ** 4 - 0.5 * (x[0] / A) ** 2 + (x[1] / B) ** 2 + (x[2] / C) ** 2


def waist_gradient(x: np.ndarray) -> np.ndarray:
    return np.array([4 * x[0] ** 3 / A**4 - x[0] / A**2, 2 * x[1] / B**2, 2 * x[2] / C**2])


def cylinder_value(x: np.ndarray) -> float:
    return (x[1] / B) ** 2 + (x[2] / C) ** 2


def cylinder_gradient(x: np.ndarray) -> np.ndarray:
    return np.array([0.0, 2 * x[1] / B**2, 2 * x[2] / C**2])


@pytest.mark.parametrize(
    ("value", "gradient", "offset", "parameter", "words"),
    [
        (not_compilable, ellipsoid_gradient, H, "value", "Untyped global name 'plain_python'"),
        (ellipsoid_value, 3.0, H, "gradient", "function"),
        (ellipsoid_value, wrong_gradient, H, "gradient", "gradient of value"),
        (waist_value, waist_gradient, H, "value", "convex"),
        (cylinder_value, cylinder_gradient, 0.0, "value", "convex"),  # found not closed
        (ellipsoid_value, ellipsoid_gradient, 0.03, "com_offset", "G inside"),
    ],
)
def test_bad_functions_are_refused(
    value: object, gradient: object, offset: float, parameter: str, words: str
) -> None:
    with pytest.raises(ParameterError, match=words) as error:
        cs.ImplicitFunction(value, gradient, offset)  # type: ignore[arg-type]
    assert error.value.name == parameter
    assert "\n" not in str(error.value)
