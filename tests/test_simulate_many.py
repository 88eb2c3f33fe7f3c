"""``simulate_many`` on the CPU: each run is ``simulate``'s, to the last bit.

The oracle is ``simulate`` itself, run on its own for each run (tested against SciPy, the
independent oracle and the invariants elsewhere): the batch must change nothing in a run,
each run's own sample times included, and a run that cannot be made takes its error's
place without stopping the others. Bad input to the batch is one ``ParameterError`` line
naming the parameter, before any run. The GPU path is checked in numba's CUDA simulator
(``tests/test_simulate_many_cuda.py``).
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
import pytest

import celtstone as cs
from celtstone.errors import CeltstoneError, ParameterError
from celtstone.simulation.integrate import simulate_many

T_END = 0.3  # s: short runs, the batch's bookkeeping is what is tested
BODY = "kane_levinson_1982"


def _starts() -> list[cs.InitialState]:
    """Three releases of different spin and attitude; the last lifts off at 0.047 s."""
    return [
        cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5)),
        cs.InitialState(omega=(0.0, 0.0, 3.0), euler_angles=(2.0, 1.0)),
        cs.InitialState(omega=(0.0, 0.0, -8.0), euler_angles=(1.0, 1.5)),
    ]


def _assert_same_run(got: object, expected: cs.Trajectory) -> None:
    """Every variable of the dataset to the last bit, its attributes, and the run's
    status, message, stop, smallest normal force and solver counts."""
    assert isinstance(got, cs.Trajectory), got
    for name in expected.dataset.variables:
        np.testing.assert_array_equal(
            got.dataset[name].values, expected.dataset[name].values, err_msg=name, strict=True
        )
    assert set(got.dataset.variables) == set(expected.dataset.variables)
    assert got.dataset.attrs == expected.dataset.attrs
    assert (got.status, got.message, got.t_stop) == (
        expected.status,
        expected.message,
        expected.t_stop,
    )
    assert got.min_normal_force == expected.min_normal_force
    assert got.statistics == expected.statistics


def test_each_run_equals_simulate_of_it_with_its_own_sample_times() -> None:
    body = cs.load_body(BODY)
    models = [cs.RollingModel(), cs.RollingModel(rolling_resistance=1e-5), cs.RollingModel()]
    runs = [(model, body, start) for model, start in zip(models, _starts(), strict=True)]
    # each run its own times, as a fit's runs start at their own release offsets
    times = np.stack([np.linspace(offset, T_END, 31) for offset in (0.0, 0.05, 0.01)])
    made = simulate_many(runs, T_END, sample_times=times, workers=2)
    assert len(made) == len(runs)
    statuses = []
    for (model, _, start), got, own in zip(runs, made, times, strict=True):
        expected = cs.simulate(model, body, start, T_END, sample_times=own)
        sampled = expected.dataset["time"].values
        np.testing.assert_array_equal(sampled, own[: len(sampled)])
        _assert_same_run(got, expected)
        statuses.append(expected.status)
    assert statuses == ["success", "success", "lift_off"]


def test_shared_sample_times_and_n_samples_are_simulates() -> None:
    body = cs.load_body(BODY)
    runs = [(cs.RollingModel(), body, start) for start in _starts()[:2]]
    shared = np.linspace(0.0, T_END, 17)
    for settings in ({"sample_times": shared}, {"n_samples": 11}, {}):
        made = simulate_many(runs, T_END, workers=1, **settings)
        for (model, _, start), got in zip(runs, made, strict=True):
            _assert_same_run(got, cs.simulate(model, body, start, T_END, **settings))


def test_a_run_that_cannot_be_made_keeps_its_place() -> None:
    body = cs.load_body(BODY)
    sliding_start = cs.InitialState(omega=(0.0, 0.0, -5.0), slip_velocity=(0.01, 0.0))
    good = _starts()[0]
    runs = [(cs.RollingModel(), body, good), (cs.RollingModel(), body, sliding_start)]
    kept = simulate_many(runs, T_END, errors="keep")
    assert isinstance(kept[1], ParameterError) and kept[1].name == "slip_velocity"
    _assert_same_run(kept[0], cs.simulate(cs.RollingModel(), body, good, T_END))
    with pytest.raises(ParameterError, match="slip_velocity"):
        simulate_many(runs, T_END)  # errors="raise", the default


def test_each_run_warns_as_simulate_does() -> None:
    """A plausibility concern (a damping that stops the rocking at once) is warned for
    its run, as ``simulate`` warns it."""
    body = cs.load_body(BODY)
    damped = cs.RollingModel(damping=0.05)
    runs = [(cs.RollingModel(), body, _starts()[0]), (damped, body, _starts()[1])]
    with warnings.catch_warnings(record=True) as alone:
        warnings.simplefilter("always")
        cs.simulate(damped, body, _starts()[1], T_END)
    with warnings.catch_warnings(record=True) as batch:
        warnings.simplefilter("always")
        simulate_many(runs, T_END, workers=1)
    expected = [(w.category, str(w.message)) for w in alone]
    assert expected and [(w.category, str(w.message)) for w in batch] == expected


def _one_line(error: pytest.ExceptionInfo[ParameterError], name: str) -> str:
    text = str(error.value)
    assert "\n" not in text and text.startswith(f"{name} = "), text
    return text


@pytest.mark.parametrize(
    ("settings", "name", "words"),
    [
        ({"device": "gpu"}, "device", "expected one of: cpu, cuda, auto"),
        ({"errors": "ignore"}, "errors", "expected one of: raise, keep"),
        ({"sample_times": np.zeros((3, 2, 2))}, "sample_times", "shape (m,) or (2, m)"),
        ({"sample_times": np.zeros((3, 4))}, "sample_times", "shape (m,) or (2, m)"),
        ({"sample_times": [0.2, 0.1]}, "sample_times", "increasing times"),
        ({"t_end": -1.0}, "t_end", "not allowed"),
        ({"method": "rk4"}, "method", "one of"),
        ({"stick_method": "dop853"}, "stick_method", "none for this model"),
    ],
)
def test_a_bad_setting_of_every_run_is_one_line_before_any_run(
    settings: dict[str, object], name: str, words: str
) -> None:
    body = cs.load_body(BODY)
    runs = [(cs.RollingModel(), body, start) for start in _starts()[:2]]
    given: dict[str, Any] = {"errors": "keep", **settings}
    t_end = given.pop("t_end", T_END)
    with pytest.raises(ParameterError) as refused:
        simulate_many(runs, t_end, **given)
    assert words in _one_line(refused, name)


@pytest.mark.parametrize(
    ("runs", "words"),
    [
        ([], "one (model, body, initial_state) or more"),
        ([("rolling", "kane_levinson_1982")], "a (model, body, initial_state) for each run"),
        (None, "models of one kind"),  # filled in below: rolling and sliding
        ("hybrid", "models of one kind"),  # sliding and stick–slip
    ],
)
def test_bad_runs_are_one_line(runs: object, words: str) -> None:
    body = cs.load_body(BODY)
    start = _starts()[0]
    if runs is None:
        runs = [(cs.RollingModel(), body, start), (cs.SlidingModel(), body, start)]
    elif runs == "hybrid":
        runs = [(cs.SlidingModel(), body, start), (cs.HybridModel(), body, start)]
    with pytest.raises(ParameterError) as refused:
        simulate_many(runs, T_END, errors="keep")  # type: ignore[arg-type]
    assert words in _one_line(refused, "runs")


def test_a_bad_row_of_sample_times_is_that_runs_error() -> None:
    """Each run's own times are checked as ``simulate`` checks them: a bad row is its
    run's error, kept in its place."""
    body = cs.load_body(BODY)
    runs = [(cs.RollingModel(), body, start) for start in _starts()[:2]]
    times = np.array([[0.0, 0.1, 0.2], [0.0, 0.2, 0.1]])
    made = simulate_many(runs, T_END, sample_times=times, errors="keep")
    assert isinstance(made[0], cs.Trajectory)
    assert isinstance(made[1], CeltstoneError) and "sample_times" in str(made[1])
