"""The state's structure that the Radau Jacobian and its LU rely on (``kernels.layout``).

The rates of the dynamics (n, ω, V1: the first ``N_DYNAMIC`` components) never read the
driven components (attitude, position, work), and no rate reads position or work (the
components from ``N_READ`` on). ``solvers._radau`` therefore differences only the first
``N_READ`` columns and factors the iteration matrix block by block; a model whose
dynamics read the attitude would be factored whole (``jacobian`` returns split 0), and
one that read position or work would be wrong: these tests fail first.
"""

from __future__ import annotations

import numpy as np
import pytest

import celtstone as cs
from celtstone.kernels import system
from celtstone.kernels.layout import (
    N_DYNAMIC,
    N_READ,
    N_STATE,
    Y_QUAT,
    Y_SLIP,
    ModelCode,
    ShapeCode,
)
from celtstone.simulation.models import initial_vector, kernel_parameters
from celtstone.solvers import _radau, _system
from tests.test_kernel_dispatch import BODIES, STATE

MODELS = {
    "rolling": cs.RollingModel(damping=1e-4, rolling_resistance=1e-5),
    "sliding": cs.SlidingModel(0.2, 2e-3, "dynamic", 1e-4, 1e-7, "exact", "uniform"),
    "sliding-ellipse": cs.SlidingModel(
        contact_shape="ellipse", elastic_modulus=3e9, poisson_ratio=0.35, rolling_resistance=1e-5
    ),
}
CODES = {"rolling": [ModelCode.ROLLING], "sliding": [ModelCode.SLIDING, ModelCode.STICK]}


def _cases() -> list[tuple[str, ModelCode, object]]:
    cases = []
    for name, model in MODELS.items():
        for code in CODES[model.name]:
            for shape in BODIES:
                cases.append((name, code, shape))
    return cases


def _state(seed: int) -> np.ndarray:
    """The test state with a slip, a turned attitude, a position and a work."""
    rng = np.random.default_rng(seed)
    y = initial_vector(STATE)
    y[Y_SLIP : Y_SLIP + 2] = (1e-3, -2e-3)
    attitude = rng.normal(size=4)
    y[Y_QUAT : Y_QUAT + 4] = attitude / np.linalg.norm(attitude)
    y[N_READ:] = rng.normal(size=N_STATE - N_READ)
    return y


def _rates(code: int, y: np.ndarray, params: np.record) -> np.ndarray:
    rates = np.empty(N_STATE)
    system.rhs(int(code), 0.0, y, params, rates)
    return rates


@pytest.mark.parametrize(("model", "code", "shape"), _cases(), ids=str)
def test_the_dynamics_do_not_read_the_driven_components(model: str, code: int, shape) -> None:
    params = kernel_parameters(MODELS[model], BODIES[shape])
    y = _state(int(code))
    rates = _rates(code, y, params)
    assert np.all(np.isfinite(rates))
    for j in range(N_DYNAMIC, N_STATE):
        moved = y.copy()
        moved[j] += 0.25
        changed = _rates(code, moved, params)
        assert np.array_equal(changed[:N_DYNAMIC], rates[:N_DYNAMIC]), f"dynamics read y[{j}]"
        if j >= N_READ:
            assert np.array_equal(changed, rates), f"a rate reads y[{j}]"


def test_the_radau_jacobian_is_block_triangular_and_matches_a_full_one() -> None:
    """``_radau.jacobian`` returns the split ``N_DYNAMIC`` and equals the forward-difference
    Jacobian of every column (the skipped ones are exactly zero)."""
    params = kernel_parameters(MODELS["sliding"], BODIES[ShapeCode.ELLIPSOID])
    code = int(ModelCode.SLIDING)
    y = _state(3)
    f = _rates(code, y, params)
    jacobian = np.empty((N_STATE, N_STATE))
    system = (params, _system.rhs_link(params))  # as the run loop passes it
    split = _radau.jacobian(code, system, 0.0, y, f, jacobian, np.empty(N_STATE), np.empty(N_STATE))
    assert split == N_DYNAMIC
    full = np.empty_like(jacobian)
    for j in range(N_STATE):
        moved = y.copy()
        step = _radau.SQRT_EPS * max(abs(y[j]), 1e-5)
        moved[j] = y[j] + step
        # as the kernel: one reciprocal of the step, multiplied into every row
        full[:, j] = (_rates(code, moved, params) - f) * (1.0 / (moved[j] - y[j]))
    assert np.array_equal(jacobian, full)
    assert not np.any(jacobian[:N_DYNAMIC, N_DYNAMIC:])
