"""The friction force against Coulomb's bound f N (issue 13, item 6).

With ``friction_load`` static the friction law is loaded with m g (the paper's first
approximation) while the plane presses with the true N, so |F| can exceed f N. The
column ``friction_force`` is checked against the friction law evaluated independently
(``celtstone.contact.friction_functions``) from the slip and spin in the Dataset.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import celtstone as cs
from celtstone.contact import friction_functions

# Kane & Levinson's state (Euler angles 0.5°, 0.5°, ω3 = -5 rad/s) with f = 0.35
START = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
T_END = 0.5
RTOL = 1e-8


Run = tuple[cs.Trajectory, list[str]]


def _run(body: cs.Body, model: cs.SlidingModel | cs.RollingModel) -> Run:
    """The run and the texts of the ``FrictionBoundWarning``s it issued."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        trajectory = cs.simulate(model, body, START, T_END, rtol=RTOL, n_samples=2001)
    return trajectory, [
        str(w.message) for w in caught if issubclass(w.category, cs.FrictionBoundWarning)
    ]


@pytest.fixture(scope="module")
def static_run(kane_levinson: cs.Body) -> Run:
    return _run(kane_levinson, cs.SlidingModel(friction_coefficient=0.35))


@pytest.fixture(scope="module")
def dynamic_run(kane_levinson: cs.Body) -> Run:
    return _run(kane_levinson, cs.SlidingModel(friction_coefficient=0.35, friction_load="dynamic"))


def _force_from_the_law(trajectory: cs.Trajectory, model: cs.SlidingModel) -> np.ndarray:
    """f N_f |φ| of the Padé law (paper eq. 10) from V1 and ω · n in the Dataset, with
    the regularisation |V1| → |V1|_δ = sqrt(|V1|² + δ²): |φ| = (|V1|/|V1|_δ) F̂(u_δ),
    u_δ = |V1|_δ / (ε |Ω_n|)."""
    ds = trajectory.dataset
    speed = np.linalg.norm(ds["slip_velocity"].values, axis=1)
    regularised = np.hypot(speed, model.regularisation_speed)
    spin = np.abs(ds["spin"].values)
    force_ratio, _ = friction_functions(regularised / (model.contact_radius * spin), "pade")
    mass, gravity = float(ds.attrs["body_mass"]), float(ds.attrs["body_gravity"])
    load = mass * gravity if model.friction_load == "static" else ds["normal_force"].values
    return model.friction_coefficient * load * force_ratio * speed / regularised


@pytest.mark.parametrize("load", ["static", "dynamic"])
def test_friction_force_column_is_the_law(static_run: Run, dynamic_run: Run, load: str) -> None:
    trajectory, _ = static_run if load == "static" else dynamic_run
    model = cs.SlidingModel(friction_coefficient=0.35, friction_load=load)
    expected = _force_from_the_law(trajectory, model)
    column = trajectory.dataset["friction_force"].values
    assert trajectory.dataset["friction_force"].attrs["units"] == "N"
    np.testing.assert_allclose(column, expected, rtol=1e-12, atol=1e-15)


def test_static_load_exceeds_coulombs_bound_and_warns_once(static_run: Run) -> None:
    """Issue 13 says |F| exceeds f N_true for K&L at f = 0.35 with the static load."""
    trajectory, texts = static_run
    ds = trajectory.dataset
    ratio = ds["friction_force"].values / (0.35 * ds["normal_force"].values)
    summary = trajectory.summary()
    assert summary["max_friction_bound_ratio"] == pytest.approx(float(np.max(ratio)), rel=1e-12)
    assert summary["max_friction_bound_ratio"] > 1.1  # measured 1.146 at t = 0.091 s
    assert len(texts) == 1
    assert f"{summary['max_friction_bound_ratio']:.3g} f N" in texts[0]
    # from Python the advice names the Python argument, not the command-line flag
    assert 'friction_load="dynamic"' in texts[0]
    assert "--friction-load" not in texts[0]


def test_dynamic_load_never_exceeds_the_bound(dynamic_run: Run) -> None:
    trajectory, texts = dynamic_run
    ratio = trajectory.summary()["max_friction_bound_ratio"]
    assert ratio is not None and 0.5 < ratio <= 1.0 + 1e-9
    assert texts == []


def test_rolling_has_no_friction_bound(kane_levinson: cs.Body) -> None:
    trajectory, texts = _run(kane_levinson, cs.RollingModel())
    assert trajectory.summary()["max_friction_bound_ratio"] is None
    assert np.all(trajectory.dataset["friction_force"].values == 0.0)
    assert texts == []


def test_cli_prints_the_warning_on_stderr(capsys: pytest.CaptureFixture[str]) -> None:
    from celtstone.cli.main import main

    status = main(["run", "--model", "sliding", "--t-end", "0.2", "--json"])
    err = capsys.readouterr().err
    assert status == 0
    lines = [line for line in err.splitlines() if "Coulomb's bound" in line]
    assert len(lines) == 1 and lines[0].startswith("celtstone: warning:")
    assert "--friction-load dynamic" in lines[0] and "friction_load=" not in lines[0]
