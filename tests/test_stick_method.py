"""The stick–slip contact's two integrators: ``method`` for its slip phases, ``stick_method``
for its stick phases, in ``simulate``, ``Sweep`` and the CLI, declared once
(``integrate.method_names``)."""

from __future__ import annotations

import pytest

import celtstone as cs
from celtstone.errors import ParameterError
from celtstone.simulation.integrate import method_names
from celtstone.sweep import Sweep
from tests.test_cli import Result

# f = 0.5, spin +3 rad/s: the stone sticks within 3 s (tests/test_sweep.py)
STATE = cs.InitialState((0.0, 0.0, 3.0), (0.5, 0.5))
OPTIONS = {"rtol": 1e-8, "atol": 1e-12}


@pytest.mark.parametrize(
    ("method", "stick_method", "expected"),
    [
        (None, None, ("auto", "dop853")),
        ("radau5", None, ("radau5", "radau5")),  # a method given names both, as before
        ("radau5", "dop853", ("radau5", "dop853")),
        (None, "radau5", ("auto", "radau5")),
    ],
)
def test_the_stick_phases_take_stick_method_then_method_then_dop853(
    method: str | None, stick_method: str | None, expected: tuple[str, str]
) -> None:
    assert method_names(cs.HybridModel(0.5), method, stick_method) == expected


def test_stick_method_is_refused_where_there_is_no_stick_phase() -> None:
    for model in (cs.RollingModel(), cs.SlidingModel(0.3)):
        with pytest.raises(ParameterError, match="stick_method"):
            method_names(model, None, "dop853")
        assert method_names(model, None, None)[1] is None
    with pytest.raises(ParameterError, match=r"stick_method.*dop853, radau5, auto"):
        method_names(cs.HybridModel(0.5), None, "radau")


def test_radau_in_slip_and_dop853_in_stick_give_the_same_run(kane_levinson: cs.Body) -> None:
    """Radau in both phases, and Radau in slip with DOP853 in stick: the stick phases'
    steps are Radau's only in the first, and the phases and spins agree to tolerance."""
    model = cs.HybridModel(0.5)
    both = cs.simulate(model, kane_levinson, STATE, 3.0, method="radau5", **OPTIONS)
    split = cs.simulate(
        model, kane_levinson, STATE, 3.0, method="radau5", stick_method="dop853", **OPTIONS
    )
    assert both.summary()["stick_phases"] >= 1  # the case has stick to integrate
    assert both.samples.attrs["stick_method"] == "radau5"
    assert split.samples.attrs["stick_method"] == "dop853"
    assert both.statistics["n_radau_steps"] == both.statistics["n_accepted"]
    assert 0 < split.statistics["n_radau_steps"] < split.statistics["n_accepted"]
    assert both.summary()["stick_phases"] == split.summary()["stick_phases"]
    assert abs(both.summary()["spin_final"] - split.summary()["spin_final"]) < 1e-6


def test_a_sweep_records_and_runs_its_stick_method() -> None:
    sweep = Sweep(
        points={"friction_coefficient": [0.5], "initial_spin": [3.0]},
        fixed={"contact": "hybrid"},
        t_end=0.5,
        method="radau5",
        stick_method="dop853",
    )
    assert (sweep.method, sweep.stick_method) == ("radau5", "dop853")
    assert sweep.spec().count('"stick_method": "dop853"') == 1
    with pytest.raises(ParameterError, match="stick_method"):
        Sweep({"initial_spin": [1.0]}, fixed={"contact": "sliding"}, stick_method="radau5")


def test_cli_takes_stick_method() -> None:
    base = ["run", "--model", "sliding", "--t-end", "0.2", "--json", "--no-progress"]
    result = Result([*base, "--contact", "hybrid", "--stick-method", "radau5"])
    assert result.status == 0, result.err
    summary = result.json()
    assert (summary["method"], summary["stick_method"]) == ("auto", "radau5")
    refused = Result([*base, "--stick-method", "radau5"])
    assert refused.status != 0
    assert "stick_method" in refused.err and "hybrid" in refused.err
