"""The careful SciPy baseline (benchmarks/careful_baseline.py) against the oracle.

Two independent plain-Python codes of the same equations: their right-hand sides agree to
rounding at random states, and a short run agrees in its final spin.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from tests.oracle import rattleback as oracle

TILT = (0.5, 0.5)
OMEGA0 = (0.0, 0.0, -5.0)
SLIDING = {"friction_coefficient": 0.35, "contact_radius": 1e-3}


def load_baseline() -> ModuleType:
    path = Path(__file__).resolve().parents[2] / "benchmarks" / "careful_baseline.py"
    spec = importlib.util.spec_from_file_location("careful_baseline", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def baseline() -> ModuleType:
    return load_baseline()


@pytest.fixture(scope="module")
def body() -> dict:
    return oracle.kane_levinson_body()


def random_states(model: str, count: int, seed: int) -> list[np.ndarray]:
    """Unit verticals anywhere on the sphere, spins up to ~10 rad/s, tangent slips from
    1e-6 to 1 m/s (sliding), and a dissipated work."""
    rng = np.random.default_rng(seed)
    states = []
    for _ in range(count):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        omega = rng.normal(scale=5.0, size=3)
        parts = [n, omega]
        if model == "sliding":
            v1 = rng.normal(size=3)
            v1 -= np.dot(v1, n) * n
            v1 *= 10.0 ** rng.uniform(-6.0, 0.0) / np.linalg.norm(v1)
            parts.append(v1)
        parts.append([rng.uniform(0.0, 1.0)])
        states.append(np.concatenate(parts))
    return states


def assert_close_to_rounding(actual: np.ndarray, expected: np.ndarray) -> None:
    """Equal to ~1e-13 relative, per component or against the largest component."""
    scale = np.max(np.abs(expected))
    np.testing.assert_allclose(actual, expected, rtol=1e-13, atol=1e-13 * scale)


@pytest.mark.parametrize("damping", [0.0, 1e-4])
def test_rolling_rhs_matches_oracle(baseline: ModuleType, body: dict, damping: float) -> None:
    fun = baseline.rolling_rhs(body, damping=damping)
    for y in random_states("rolling", 20, seed=17):
        assert_close_to_rounding(fun(0.0, y), oracle.rhs_rolling(0.0, y, body, damping))


@pytest.mark.parametrize("friction_load", ["static", "dynamic"])
@pytest.mark.parametrize("damping", [0.0, 1e-4])
def test_sliding_rhs_matches_oracle(
    baseline: ModuleType, body: dict, friction_load: str, damping: float
) -> None:
    settings = {**SLIDING, "friction_load": friction_load, "damping": damping}
    fun = baseline.sliding_rhs(body, **settings)
    for y in random_states("sliding", 20, seed=5):
        assert_close_to_rounding(fun(0.0, y), oracle.rhs_sliding(0.0, y, body, **settings))


def test_sliding_jacobian_matches_oracle(baseline: ModuleType, body: dict) -> None:
    """Both central differences with the same steps: equal to difference noise."""
    fun = baseline.sliding_rhs(body, **SLIDING)
    jac = baseline.central_jacobian(fun, 10)
    for y in random_states("sliding", 3, seed=3):
        expected = oracle.numerical_jacobian(
            lambda t, x: oracle.rhs_sliding(t, x, body, **SLIDING), 0.0, y
        )
        np.testing.assert_allclose(
            jac(0.0, y), expected, rtol=1e-5, atol=1e-6 * np.abs(expected).max()
        )


def test_rolling_run_matches_oracle(baseline: ModuleType, body: dict) -> None:
    """Kane & Levinson's start, 2 s: the same DOP853 steps, the same final spin.

    rtol 1e-6 keeps the oracle (~0.6 ms per call, np.cross) under 5 s; both codes take the
    same steps, so their spins agree far below the tolerance.
    """
    y0 = oracle.initial_state(*TILT, OMEGA0, "rolling")
    t_eval = np.array([2.0])
    careful = baseline.simulate("rolling", body, y0, 2.0, t_eval=t_eval, rtol=1e-6, atol=1e-12)
    reference = oracle.simulate("rolling", body, y0, 2.0, t_eval=t_eval, rtol=1e-6, atol=1e-12)
    assert careful.success and reference.success
    assert oracle.spin(careful.y[:, -1]) == pytest.approx(
        oracle.spin(reference.y[:, -1]), rel=1e-8, abs=0.0
    )


def test_sliding_run_matches_oracle(baseline: ModuleType, body: dict) -> None:
    """0.01 s of the sliding model (Radau, rtol 1e-8): the same final spin."""
    y0 = oracle.initial_state(*TILT, OMEGA0, "sliding")
    t_eval = np.array([0.01])
    careful = baseline.simulate(
        "sliding", body, y0, 0.01, t_eval=t_eval, rtol=1e-8, atol=1e-12, **SLIDING
    )
    reference = oracle.simulate(
        "sliding", body, y0, 0.01, t_eval=t_eval, rtol=1e-8, atol=1e-12, **SLIDING
    )
    assert careful.success and reference.success
    assert oracle.spin(careful.y[:, -1]) == pytest.approx(
        oracle.spin(reference.y[:, -1]), rel=1e-8, abs=0.0
    )
