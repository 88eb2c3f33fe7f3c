"""Every registered shape and every friction law runs the invariant tests, unlisted.

The shapes come from ``bodies.SHAPES`` (each its ``example()``, Kane & Levinson-sized
and symmetric about y = 0), the laws from ``models.FRICTION_LAWS``: a new one joins
these tests by being declared. Oracles: energy conservation in rolling, the energy
budget E(0) - E(t) = W(t) in sliding, the mirror symmetry of the equations, and the
shape's own declarations read back (table, attributes, sweep names).
"""

from __future__ import annotations

import dataclasses
import json
from functools import cache
from pathlib import Path

import numpy as np
import pytest

import celtstone as cs
from celtstone.bodies import SHAPES, Shape, shape_from_table
from celtstone.simulation.models import FRICTION_LAWS
from celtstone.sweep import spec
from celtstone.visual import scene

START = ((0.3, -0.2, -5.0), (0.7, 0.4))  # ω [rad/s] and Euler angles [deg], not symmetric


@cache
def _example(kind: str) -> Shape:
    return SHAPES[kind].example()


def _body(kind: str) -> cs.Body:
    base = cs.load_body("kane_levinson_1982")
    return dataclasses.replace(base, name=f"kl_{kind}", shape=_example(kind))


def _mirror(body: cs.Body) -> cs.Body:
    inertia = np.array(body.inertia)
    inertia[0, 1] = inertia[1, 0] = -inertia[0, 1]
    inertia[1, 2] = inertia[2, 1] = -inertia[1, 2]
    return dataclasses.replace(body, name=body.name + "_mirrored", inertia=inertia.tolist())


def _state() -> cs.InitialState:
    return cs.InitialState(*START)


@pytest.mark.parametrize("kind", SHAPES)
def test_every_shape_conserves_energy_rolling(kind: str) -> None:
    run = cs.simulate(cs.RollingModel(), _body(kind), _state(), 3.0)
    assert run.ok, run.message
    assert run.summary()["max_relative_energy_drift"] < 1e-8
    n = run.dataset["n"].values
    assert np.max(np.abs(np.linalg.norm(n, axis=1) - 1.0)) < 1e-8


@pytest.mark.parametrize("law", FRICTION_LAWS)
@pytest.mark.parametrize("kind", SHAPES)
def test_every_shape_and_law_balances_energy_sliding(kind: str, law: str) -> None:
    """E(0) - E(t) equals the friction work W(t) to the solver's accuracy."""
    model = cs.SlidingModel(friction_coefficient=0.35, contact_radius=1e-3, friction_law=law)
    run = cs.simulate(model, _body(kind), _state(), 1.5, rtol=1e-9)
    assert run.ok, run.message
    energy, work = run.dataset["energy"].values, run.dataset["dissipated_work"].values
    assert work[-1] > 1e-5 * energy[0]
    assert np.max(np.abs(energy[0] - energy - work)) < 1e-6 * energy[0]
    slip = np.einsum("ij,ij->i", run.dataset["slip_velocity"].values, run.dataset["n"].values)
    assert np.max(np.abs(slip)) < 1e-10


@pytest.mark.parametrize(
    "model",
    [
        cs.RollingModel(),
        *(cs.SlidingModel(contact_radius=1e-3, friction_law=law) for law in FRICTION_LAWS),
    ],
    ids=lambda m: m.name + "-" + getattr(m, "friction_law", ""),
)
@pytest.mark.parametrize("kind", SHAPES)
def test_every_shape_and_law_mirrors(kind: str, model: cs.Model) -> None:
    """Reflected in the plane y = 0 (D -> -D, mirrored start) the spin changes sign."""
    body = _body(kind)
    original = cs.simulate(model, body, _state(), 2.0)
    mirrored = cs.simulate(model, _mirror(body), _state().mirrored(), 2.0)
    assert original.ok and mirrored.ok
    spin, spin_m = original.dataset["spin"].values, mirrored.dataset["spin"].values
    assert np.max(np.abs(spin + spin_m)) < 1e-6 * np.max(np.abs(spin))


@pytest.mark.parametrize("kind", [kind for kind, cls in SHAPES.items() if cls.stored])
def test_a_stored_shape_is_rebuilt_from_its_table_and_its_run(kind: str) -> None:
    shape = _example(kind)
    table = json.loads(json.dumps(shape.table()))  # as a file holds it
    assert table["kind"] == kind
    assert shape_from_table(table) == shape
    run = cs.simulate(cs.RollingModel(), _body(kind), _state(), 0.1)
    attrs = run.dataset.attrs
    assert shape_from_table(json.loads(attrs["body_shape_table"])) == shape
    assert json.loads(attrs["body_shape_parameters"]) == pytest.approx(shape.kernel_parameters())
    geometry = scene.body_geometry(run.dataset)  # the viewer draws it from the file
    assert geometry.kind == kind
    mesh = scene.surface_mesh(geometry, along=12, around=8)
    assert np.all(np.isfinite(mesh.vertices))


@pytest.mark.parametrize("kind", [kind for kind, cls in SHAPES.items() if not cls.stored])
def test_a_shape_that_is_not_data_is_refused_where_a_file_must_rebuild_it(kind: str) -> None:
    body = _body(kind)
    with pytest.raises(cs.ParameterError, match="body"):
        cs.Sweep(body=body, model="sliding", vary=["friction_coefficient=0.2,0.3"], t_end=0.1)
    run = cs.simulate(cs.RollingModel(), body, _state(), 0.1)
    with pytest.raises(cs.ParameterError, match="Python function"):
        scene.body_geometry(run.dataset)


@pytest.mark.parametrize("kind", SHAPES)
def test_every_sweep_name_of_a_shape_is_a_sweep_parameter_that_sets_it(kind: str) -> None:
    cls = SHAPES[kind]
    units = {entry.key: entry.quantity.unit for entry in cls.entries}
    for sweep in cls.sweep_names:
        parameter = spec.PARAMETERS[sweep.name]
        assert parameter.group == spec.BODY
        assert parameter.unit == units[sweep.field]
        assert kind in parameter.description
        shape = _example(kind)
        value = getattr(shape, sweep.field)
        old = value if sweep.index is None else value[sweep.index]
        changed = spec.build_body(_body(kind), {sweep.name: old * 1.01}).shape
        new = getattr(changed, sweep.field)
        assert (new if sweep.index is None else new[sweep.index]) == pytest.approx(old * 1.01)
    foreign = {s.name for c in SHAPES.values() for s in c.sweep_names} - {
        s.name for s in cls.sweep_names
    }
    for name in sorted(foreign):
        with pytest.raises(cs.ParameterError, match=f"{kind} shape"):
            spec.build_body(_body(kind), {name: 0.05})


def test_the_documented_shape_table_is_the_registry() -> None:
    """docs/bodies.md lists each body-file kind with its keys, and nothing else."""
    text = (Path(__file__).parents[2] / "docs" / "bodies.md").read_text(encoding="utf-8")
    rows = [line for line in text.splitlines() if line.startswith("| `") and "=" in line]
    documented = {row.split("`")[1]: row for row in rows}
    stored = {kind: cls for kind, cls in SHAPES.items() if cls.stored}
    assert set(documented) == set(stored)
    for kind, cls in stored.items():
        for entry in cls.entries:
            assert f"`{entry.key}" in documented[kind], (kind, entry.key)
