"""Output variables and run statuses are declared once; everything else reads them.

Parametrised over the declarations (``schema.VARIABLES``, ``kernels.system.DERIVED``,
``simulation.outcome.OUTCOMES`` through ``solvers.batch.RESULT_FIELDS``,
``solvers.Status``): a new entry is checked here without anyone listing it, and an entry
that lacks a part fails.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import zarr

import celtstone as cs
from celtstone import solvers
from celtstone.kernels import system
from celtstone.plotting.maps import plot_field_map
from celtstone.simulation import trajectory
from celtstone.simulation.integrate import STATUS_NAMES
from celtstone.simulation.outcome import OUTCOMES
from celtstone.simulation.schema import VARIABLES, Variable
from celtstone.solvers import batch, codes
from celtstone.sweep import RESULT_FIELDS, Sweep, open_sweep
from celtstone.sweep.plots import MAPPED_FIELDS
from celtstone.sweep.runner import _fields
from celtstone.sweep.spec import build_state

START = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
TIME_SERIES = [name for name, variable in VARIABLES.items() if variable.source]
FIELD_NAMES = [field.name for field in batch.RESULT_FIELDS]


@pytest.fixture(scope="module")
def runs(kane_levinson: cs.Body) -> dict[str, cs.Trajectory]:
    """One short run of each kind of contact."""
    return {
        "rolling": cs.simulate(cs.RollingModel(), kane_levinson, START, 0.5),
        "sliding": cs.simulate(
            cs.SlidingModel(friction_coefficient=0.35), kane_levinson, START, 0.5, rtol=1e-8
        ),
        "hybrid": cs.simulate(
            cs.HybridModel(friction_coefficient=0.35), kane_levinson, START, 0.5, rtol=1e-8
        ),
    }


@pytest.fixture(scope="module")
def store(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A rolling sweep store with one point reaching t_end and one lifting off."""
    path = tmp_path_factory.mktemp("registry") / "sweep.zarr"
    Sweep({"initial_spin": [-5.0, -40.0]}, model="rolling", t_end=0.5).run(path, workers=1)
    return path


# --------------------------------------------------------------------------- run variables


@pytest.mark.parametrize("kind", ["rolling", "sliding", "hybrid"])
@pytest.mark.parametrize("name", TIME_SERIES)
def test_every_time_series_is_in_a_runs_dataset(
    runs: dict[str, cs.Trajectory], kind: str, name: str
) -> None:
    variable = runs[kind].dataset[name]
    declared = VARIABLES[name]
    assert variable.attrs == declared.attributes
    assert variable.attrs.get("units", "") == declared.unit
    assert variable.dims == (("time", declared.axis) if declared.axis else ("time",))
    assert variable.shape[0] == runs[kind].dataset.sizes["time"]


@pytest.mark.parametrize("kind", ["rolling", "sliding", "hybrid"])
def test_every_variable_of_a_run_is_declared(runs: dict[str, cs.Trajectory], kind: str) -> None:
    """Nothing reaches a Dataset without its declaration, units and long name included."""
    dataset = runs[kind].dataset
    for name in [*dataset.data_vars, "time"]:
        assert name in VARIABLES, name
        assert dataset[name].attrs == VARIABLES[name].attributes, name
        assert VARIABLES[name].long_name, name


def test_sources_read_the_right_columns(runs: dict[str, cs.Trajectory]) -> None:
    """The derived columns named as sources hold what their names say, from the state
    variables of the same Dataset: ω·n, the tilt of axis 3, and |V1|."""
    ds = runs["sliding"].dataset
    omega, n, slip = ds["omega"].values, ds["n"].values, ds["slip_velocity"].values
    np.testing.assert_allclose(ds["spin"].values, np.sum(omega * n, axis=1), rtol=1e-14)
    tilt = np.arccos(np.clip(n[:, 2] / np.linalg.norm(n, axis=1), -1.0, 1.0))
    np.testing.assert_allclose(ds["tilt"].values, tilt, rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(ds["slip_speed"].values, np.linalg.norm(slip, axis=1), rtol=1e-14)
    assert ds["dissipated_work"].values[0] == 0.0 < ds["dissipated_work"].values[-1]
    np.testing.assert_allclose(np.linalg.norm(ds["quaternion"].values, axis=1), 1.0, rtol=1e-8)


def test_derived_columns_are_named_once() -> None:
    names = system.DERIVED
    assert len(set(names)) == len(names) == system.N_DIAGNOSTICS
    indices = [value for key, value in vars(system).items() if re.fullmatch(r"D_[A-Z_]+", key)]
    assert sorted(indices) == list(range(len(names)))  # each column written, each once


@pytest.mark.parametrize(
    ("source", "problem"),
    [
        ("derived:no_such_column", "names no columns"),
        ("state:no_such_block", "names no columns"),
        ("derived:spin,tilt", "not consecutive"),
        ("states:omega", "names no columns"),
    ],
)
def test_a_source_naming_nothing_fails_loudly(source: str, problem: str) -> None:
    with pytest.raises(ValueError, match=problem):
        trajectory._columns("made_up", Variable("1", "made up", source=source))


def test_a_derived_source_defaults_to_its_own_name() -> None:
    assert trajectory._columns("tilt", Variable("rad", "tilt", source="derived")) == (
        True,
        system.DERIVED.index("tilt"),
    )
    assert trajectory._columns("x", Variable("m", "x", source="derived:contact_x,contact_y")) == (
        True,
        slice(system.D_CONTACT_X, system.D_CONTACT_Y + 1),
    )


# --------------------------------------------------------------------------- sweep fields


def test_result_columns_are_numbered_once() -> None:
    columns = [field.column for field in batch.RESULT_FIELDS if field.column is not None]
    assert sorted(columns) == list(range(batch.N_FIELDS))
    assert batch.FIELDS == tuple(
        field.name
        for field in sorted(batch.RESULT_FIELDS, key=lambda f: f.column or 0)
        if field.column is not None
    )
    assert len(set(FIELD_NAMES)) == len(FIELD_NAMES)


@pytest.mark.parametrize("name", FIELD_NAMES)
def test_every_result_field_is_declared(name: str) -> None:
    declared = OUTCOMES[name].variable
    assert declared.long_name and declared.label
    assert not declared.source  # a sweep's field, not a run's time series
    assert RESULT_FIELDS[name] == (
        batch.RESULT_FIELDS[FIELD_NAMES.index(name)].dtype,
        batch.RESULT_FIELDS[FIELD_NAMES.index(name)].fill,
        declared.unit,
        declared.long_name,
    )


def test_the_runner_converts_every_field() -> None:
    """Each field, text included, comes out of the batch driver's columns by name."""
    raw = np.zeros((2, batch.N_FIELDS))
    raw[:, batch.COLUMN.t_stop] = 0.25
    raw[1, batch.COLUMN.status] = solvers.STATUS_MAX_STEPS
    fields = _fields(raw)
    assert list(fields) == FIELD_NAMES
    for field in batch.RESULT_FIELDS:
        expected = object if field.dtype == "str" else np.dtype(field.dtype)
        assert fields[field.name].dtype == expected, field.name
    assert list(fields["status"]) == ["success", "max_steps"]


@pytest.mark.parametrize("name", FIELD_NAMES)
def test_every_result_field_is_in_the_store(store: Path, name: str) -> None:
    """Units and long name from the field's Variable, type and fill value from its row."""
    field = batch.RESULT_FIELDS[FIELD_NAMES.index(name)]
    array = zarr.open_group(store, mode="r")[name]
    assert isinstance(array, zarr.Array)
    assert dict(array.attrs) == OUTCOMES[name].variable.attributes
    fill = array.metadata.fill_value
    if isinstance(field.fill, float) and math.isnan(field.fill):
        assert math.isnan(float(fill))
    else:
        assert fill == field.fill
    results = open_sweep(store)
    assert results[name].attrs == OUTCOMES[name].variable.attributes
    assert results[name].dims == ("initial_spin",)
    if field.dtype != "str":
        assert results[name].dtype == np.dtype(field.dtype)


@pytest.mark.parametrize("name", MAPPED_FIELDS)
def test_maps_label_each_field_as_declared(store: Path, name: str) -> None:
    """The map of a field is labelled, and drawn, in the unit its Variable plots."""
    results = open_sweep(store)
    figure = plot_field_map(results, name)
    axes = figure.axes[0]
    declared = OUTCOMES[name].variable
    assert axes.get_ylabel() == declared.axis_label()
    if name != "status":
        drawn = axes.get_lines()[0].get_ydata()
        expected = results[name].values.astype(float) * declared.plot_scale
        np.testing.assert_allclose(drawn, expected, rtol=1e-15)


# --------------------------------------------------------------------------- statuses


def test_status_codes_and_labels_are_declared_once() -> None:
    codes_in_use = [int(status) for status in solvers.Status]
    assert codes_in_use == list(range(len(solvers.Status)))
    labels = [status.label for status in solvers.Status]
    assert len(set(labels)) == len(labels)
    assert codes.UNDECLARED_STATUS not in labels
    assert STATUS_NAMES == {int(status): status.label for status in solvers.Status}


@pytest.mark.parametrize("status", list(solvers.Status), ids=lambda s: s.label)
def test_every_status_has_a_label_message_and_constant(status: solvers.Status) -> None:
    assert re.fullmatch(r"[a-z]+(_[a-z]+)*", status.label)
    assert len(status.message) > 10
    assert getattr(codes, f"STATUS_{status.name}") == int(status)
    assert type(getattr(codes, f"STATUS_{status.name}")) is int  # folded by numba
    assert solvers.status_label(int(status)) == status.label
    message = solvers.stop_message(int(status), 1.25)
    if status is solvers.Status.SUCCESS:
        assert message == "reached t_end"
    else:
        assert message == f"stopped at t = 1.25 s: {status.message}"
    raw = np.zeros((1, batch.N_FIELDS))
    raw[0, batch.COLUMN.status], raw[0, batch.COLUMN.t_stop] = int(status), 1.25
    fields = _fields(raw)
    assert (fields["status"][0], fields["message"][0]) == (status.label, message)


def test_an_undeclared_code_is_still_a_failure_with_a_time() -> None:
    assert solvers.status_label(99) == codes.UNDECLARED_STATUS
    assert solvers.stop_message(99, 2.0) == "stopped at t = 2 s: "


# each status a rolling run reaches through the public entry points: (initial spin
# [rad/s], max_steps); the others are reached below them, by the tests named
REACHABLE = {
    solvers.Status.SUCCESS: (-5.0, 20_000_000),
    solvers.Status.LIFT_OFF: (-40.0, 20_000_000),
    solvers.Status.MAX_STEPS: (-5.0, 10),
}
REACHED_BELOW = {
    solvers.Status.SINGULAR: "test_solvers.py::test_painleve_case_stops_with_singular_status",
    solvers.Status.OFF_SHAPE: "a paraboloid lifts off before its cap turns by 90 degrees",
    solvers.Status.STEP_TOO_SMALL: "no stable case; the methods' contract (solvers._methods)",
    solvers.Status.NOT_FINITE: "no stable case; driver.integrate checks every step",
    solvers.Status.PHASE_CHANGE: "test_solvers.py: internal to the compiled phase loop",
    solvers.Status.NON_CONVEX: "test_implicit_shape.py: body checks refuse such shapes",
    solvers.Status.UNKNOWN_CODE: "test_kernel_dispatch.py: validation refuses such codes",
    solvers.Status.MAX_PHASES: "test_phases.py: simulate does not take max_phases",
    solvers.Status.CONTACT_RANGE: "physics/test_elliptic_contact.py: body checks refuse such "
    "bodies at rest",
    solvers.Status.STOPPED: "test_stop_request.py: the caller's progress callback raised",
}


def test_every_status_is_reached_somewhere() -> None:
    """A new status is either reached here or names the test that reaches it."""
    assert set(REACHABLE) | set(REACHED_BELOW) == set(solvers.Status)
    assert not set(REACHABLE) & set(REACHED_BELOW)


@pytest.mark.parametrize("status", list(REACHABLE), ids=lambda s: s.label)
def test_a_status_round_trips_through_a_run_and_a_sweep(
    kane_levinson: cs.Body, status: solvers.Status
) -> None:
    """A run's summary and the sweep point of the same run name the status alike, with
    the one stop message."""
    spin, max_steps = REACHABLE[status]
    run = cs.simulate(
        cs.RollingModel(),
        kane_levinson,
        build_state({"initial_spin": spin}),
        0.5,
        max_steps=max_steps,
    )
    summary = run.summary()
    assert summary["status"] == status.label
    assert summary["message"] == solvers.stop_message(int(status), run.t_stop)
    sweep = Sweep(
        {"initial_spin": [spin]},
        model="rolling",
        t_end=0.5,
        rtol=1e-10,
        samples_per_second=400.0,  # the run's 201 samples
        max_steps=max_steps,
    )
    point = sweep.run(workers=1).isel(initial_spin=0)
    assert point["status"] == summary["status"]
    assert point["message"] == summary["message"]
