"""Shared fixtures: the shipped bodies and the literature's initial states."""

from __future__ import annotations

import os

import matplotlib
import pytest
from hypothesis import settings

import celtstone as cs

matplotlib.use("Agg")

settings.register_profile("ci", max_examples=30, deadline=None, derandomize=True)
settings.register_profile("dev", max_examples=10, deadline=None)
settings.load_profile("ci" if os.environ.get("CI") else "dev")

BODY_NAMES = sorted(cs.list_bodies())


@pytest.fixture(scope="session")
def kane_levinson() -> cs.Body:
    """Kane & Levinson (1982) ellipsoid, ../shared/references.md."""
    return cs.load_body("kane_levinson_1982")


@pytest.fixture(params=BODY_NAMES, scope="session")
def any_body(request: pytest.FixtureRequest) -> cs.Body:
    """Each shipped body in turn."""
    return cs.load_body(request.param)


# Kane & Levinson's initial state: alpha = beta = 0.5 deg, omega = (0, 0, w3) body axes
LITERATURE_EULER_ANGLES = (0.5, 0.5)
