"""Inputs no run can mean anything with are refused up front; implausible ones are warned
about by name, and named again when the run then stops (``celtstone.simulation.plausibility``).

The cases are the hostile inputs of issue 11: a mass of 1e300 kg (NaN in the normal force
before), a damping of 1e300 N m s, E = 1e-300 Pa and a body written in centimetres (all three
ended as "lift-off ... lower the spin or the tilt").
"""

from __future__ import annotations

import dataclasses
import warnings
from pathlib import Path

import numpy as np
import pytest

import celtstone as cs
import celtstone.simulation.integrate as integrate_module
from celtstone.cli.main import main
from celtstone.simulation import plausibility, schema
from celtstone.simulation.models import contact_settings
from tests.conftest import BODY_NAMES

KL_INERTIA = ((2.0e-4, -2.0e-5, 0.0), (-2.0e-5, 1.6e-3, 0.0), (0.0, 0.0, 1.7e-3))  # kg m^2
STATE = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))

BODY_TOML = """[body]
mass = {mass}
gravity = 9.81
inertia = [[2.0e-4, -2.0e-5, 0.0], [-2.0e-5, 1.6e-3, 0.0], [0.0, 0.0, 1.7e-3]]
[shape]
kind = "ellipsoid"
semi_axes = {semi_axes}
com_offset = {com_offset}
"""


def _kl(**changes: object) -> cs.Body:
    return dataclasses.replace(cs.load_body("kane_levinson_1982"), **changes)  # type: ignore[arg-type]


def _no_integration(monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("the integrator was called although the input is refused")

    monkeypatch.setattr(integrate_module.solvers, "solve", refuse)


# (id, body changes, model, parameter named, fragment of the allowed range or reason)
REFUSED = [
    ("mass-1e300", {"mass": 1e300}, cs.RollingModel(), "inertia", "singular"),
    ("mass-1e300-sliding", {"mass": 1e300}, cs.SlidingModel(), "inertia", "singular"),
    ("damping-1e300", {}, cs.RollingModel(damping=1e300), "damping", "nanosecond"),
    ("damping-1e6", {}, cs.SlidingModel(damping=1e6), "damping", "N m s for this body"),
    (
        "modulus-1e-300",
        {},
        cs.SlidingModel(elastic_modulus=1e-300, poisson_ratio=0.3),
        "elastic_modulus",
        "Hertz contact radius",
    ),
    ("contact-radius-5cm", {}, cs.SlidingModel(contact_radius=0.05), "contact_radius", "0.045"),
    (
        "flat-superellipsoid",
        {"shape": cs.Superellipsoid((0.2, 0.03, 0.02), 0.01, 3.0)},
        cs.RollingModel(),
        "shape",
        "exponent 2",
    ),
]


@pytest.mark.parametrize(
    ("changes", "model", "name", "fragment"),
    [case[1:] for case in REFUSED],
    ids=[case[0] for case in REFUSED],
)
def test_meaningless_inputs_are_refused_before_integration(
    monkeypatch: pytest.MonkeyPatch,
    changes: dict,
    model: cs.Model,
    name: str,
    fragment: str,
) -> None:
    _no_integration(monkeypatch)
    with pytest.raises(cs.ParameterError) as caught:
        cs.simulate(model, _kl(**changes), STATE, 1.0)
    assert caught.value.name == name
    assert fragment in str(caught.value)
    assert "\n" not in str(caught.value)


def test_limits_sit_at_their_stated_ratios() -> None:
    """Just inside each hard limit runs are allowed; just outside they are refused: the
    limits are the documented dimensionless ratios, not hidden constants."""
    body = _kl()
    smallest = float(np.linalg.eigvalsh(np.array(body.inertia))[0])
    limit = plausibility.MAX_DAMPING_RATE * smallest
    plausibility.require_runnable(body, plausibility.ContactSettings(damping=0.999 * limit))
    with pytest.raises(cs.ParameterError):
        plausibility.require_runnable(body, plausibility.ContactSettings(damping=1.001 * limit))
    rho_min = min(body.shape.radii_of_curvature)  # b²/c = 0.045 m
    assert rho_min == pytest.approx(0.03**2 / 0.02)
    plausibility.require_runnable(
        body, plausibility.ContactSettings(contact_radius=0.999 * rho_min)
    )
    with pytest.raises(cs.ParameterError):
        plausibility.require_runnable(body, plausibility.ContactSettings(contact_radius=rho_min))


@pytest.mark.parametrize("name", BODY_NAMES)
@pytest.mark.parametrize(
    "model",
    [
        cs.RollingModel(),
        cs.SlidingModel(),
        cs.SlidingModel(elastic_modulus=3e9, poisson_ratio=0.35),
    ],
    ids=["rolling", "sliding", "sliding-hertz"],
)
def test_shipped_bodies_raise_no_concern(name: str, model: cs.Model) -> None:
    """The published and derived bodies are plausible stones: no warning for any of them."""
    body = cs.load_body(name)
    assert plausibility.concerns(body, contact_settings(model)) == []


def test_body_in_centimetres_is_named_before_and_after_the_run() -> None:
    """Semi-axes 20, 3, 2 "m" with Kane & Levinson's inertia: three warnings name inertia,
    shape and mass with the units; the stop message names them again."""
    body = _kl(shape=cs.Ellipsoid((20.0, 3.0, 2.0), 1.0))
    with pytest.warns(cs.PlausibilityWarning) as record:
        run = cs.simulate(cs.RollingModel(), body, STATE, 1.0)
    texts = [str(w.message) for w in record]
    assert [t.split(" = ")[0] for t in texts] == ["inertia", "shape", "mass"]
    assert all("lengths are in m" in t for t in texts)
    assert not run.ok
    assert "implausible inertia, shape, mass" in run.message


@pytest.mark.parametrize(
    ("changes", "model", "name"),
    [
        ({"gravity": 1000.0}, cs.RollingModel(), "gravity"),
        ({"mass": 1e-6}, cs.RollingModel(), "inertia"),
        ({}, cs.RollingModel(damping=0.01), "damping"),
        ({}, cs.SlidingModel(contact_radius=0.02), "contact_radius"),
        ({}, cs.SlidingModel(elastic_modulus=1e5, poisson_ratio=0.3), "elastic_modulus"),
    ],
    ids=["gravity", "light", "damping", "contact-radius", "soft"],
)
def test_implausible_values_are_warned_by_name(changes: dict, model: cs.Model, name: str) -> None:
    found = plausibility.concerns(_kl(**changes), contact_settings(model))
    assert [concern.parameter for concern in found].count(name) == 1, found


def test_default_samples_are_capped_with_a_warning(monkeypatch: pytest.MonkeyPatch) -> None:
    """A long t_end at the default 200 samples/s would need more than MAX_SAMPLES: the run
    samples MAX_SAMPLES evenly and says so (t_end = 1e12 raised MemoryError before)."""
    monkeypatch.setattr(schema, "MAX_SAMPLES", 501)
    with pytest.warns(cs.CeltstoneWarning, match="sampling 501"):
        run = cs.simulate(cs.RollingModel(), _kl(), STATE, 5.0)
    assert run.dataset.sizes["time"] == 501
    assert run.dataset["time"].values[-1] == 5.0


# ------------------------------------------------------------------------------- CLI


def _write_body(tmp_path: Path, **values: object) -> str:
    fields = {"mass": 1.0, "semi_axes": "[0.2, 0.03, 0.02]", "com_offset": 0.01, **values}
    path = tmp_path / "body.toml"
    path.write_text(BODY_TOML.format(**fields), encoding="utf-8")
    return str(path)


def test_cli_refuses_a_huge_mass_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    status = main(["run", "--body", _write_body(tmp_path, mass="1e300"), "--t-end", "0.1"])
    out, err = capsys.readouterr()
    assert status == 2
    assert out == ""
    assert len(err.splitlines()) == 1
    assert err.startswith("celtstone: error: inertia")


def test_cli_prints_each_warning_as_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    body = _write_body(tmp_path, semi_axes="[20.0, 3.0, 2.0]", com_offset=1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # main() shows them itself; none may escape
        status = main(["run", "--body", body, "--t-end", "1", "--json"])
    _, err = capsys.readouterr()
    lines = err.splitlines()
    assert status == 3
    warned = [line for line in lines if line.startswith("celtstone: warning: ")]
    assert [line.split(" = ")[0][len("celtstone: warning: ") :] for line in warned] == [
        "inertia",
        "shape",
        "mass",
    ]
    assert "Warning" not in err
    assert "implausible inertia, shape, mass" in lines[-1]


def test_stability_refuses_absurd_spins_in_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    for spins in ("0:1e300:3", "-1e5:0:3", "nan:1:3"):
        status = main(["stability", "--spin", spins])
        out, err = capsys.readouterr()
        assert status == 2, spins
        assert out == ""
        assert len(err.splitlines()) == 1, err
        assert "[-10000, 10000] rad/s" in err
    with pytest.raises(cs.ParameterError, match="spin"):
        cs.spin_stability(cs.load_body("kane_levinson_1982"), [2e4])
