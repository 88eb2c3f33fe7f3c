"""Runs to draw: short simulations of the shipped bodies (Kane & Levinson's initial state)."""

from __future__ import annotations

import pytest
import xarray as xr

import celtstone as cs
from tests.conftest import BODY_NAMES, LITERATURE_EULER_ANGLES

W3 = -5.0  # rad/s, the paper's Figure 2 spin


def simulate_run(model: object, body_name: str, t_end: float) -> xr.Dataset:
    """Dataset of a finished run of ``body_name`` from the literature's initial state."""
    state = cs.InitialState(omega=(0.0, 0.0, W3), euler_angles=LITERATURE_EULER_ANGLES)
    body = cs.load_body(body_name)
    return cs.simulate(model, body, state, t_end).raise_for_status().dataset  # type: ignore[arg-type]


@pytest.fixture(scope="session")
def rolling_runs() -> dict[str, xr.Dataset]:
    """4 s rolling run of each shipped body, by name: spin reverses near 2.7 s."""
    return {name: simulate_run(cs.RollingModel(), name, 4.0) for name in BODY_NAMES}


@pytest.fixture(params=BODY_NAMES)
def rolling_run(request: pytest.FixtureRequest, rolling_runs: dict[str, xr.Dataset]) -> xr.Dataset:
    """The 4 s rolling run of each shipped body in turn."""
    return rolling_runs[request.param]


@pytest.fixture(scope="session")
def sliding_run() -> xr.Dataset:
    """2 s sliding run of the Kane & Levinson ellipsoid, f = 0.35, ε = 1 mm (Figure 2)."""
    model = cs.SlidingModel(friction_coefficient=0.35, contact_radius=1e-3)
    return simulate_run(model, "kane_levinson_1982", 2.0)


@pytest.fixture(scope="session")
def long_run() -> xr.Dataset:
    """100 s rolling run of the Kane & Levinson ellipsoid (200 samples/s: 20 001 samples)."""
    return simulate_run(cs.RollingModel(), "kane_levinson_1982", 100.0)
