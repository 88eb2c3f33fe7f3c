"""The method registry (``solvers.METHOD_ENTRIES``) is the one place a method is named:
the codes, the validation and the CLI's help read it; a method registered without a
branch in the compiled dispatch ends its run with ``unknown_code``."""

from __future__ import annotations

import numpy as np
import pytest

import celtstone as cs
from celtstone import solvers
from celtstone.cli.main import build_parser
from celtstone.simulation.models import initial_vector, kernel_parameters
from celtstone.solvers import codes

THROWAWAY = codes.Method(code=99, words="a method with no module")


def _help(command: str) -> str:
    parser = build_parser()
    (subparsers,) = (a for a in parser._actions if a.dest == "command")
    return " ".join(subparsers.choices[command].format_help().split())


def test_the_codes_are_the_registry_s() -> None:
    assert solvers.METHODS == {name: entry.code for name, entry in codes.METHOD_ENTRIES.items()}
    assert len(set(solvers.METHODS.values())) == len(solvers.METHODS)


@pytest.mark.parametrize("command", ["run", "sweep"])
def test_the_help_names_every_registered_method_with_its_words(
    monkeypatch: pytest.MonkeyPatch, command: str
) -> None:
    monkeypatch.setitem(codes.METHOD_ENTRIES, "throwaway", THROWAWAY)
    text = _help(command)
    for name, entry in codes.METHOD_ENTRIES.items():
        assert f"{name}: {entry.words}" in text, name


def test_a_registered_method_without_a_branch_ends_its_run_with_unknown_code(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setitem(codes.METHOD_ENTRIES, "throwaway", THROWAWAY)
    monkeypatch.setitem(codes.METHODS, "throwaway", THROWAWAY.code)
    model = cs.RollingModel()
    params = kernel_parameters(model, cs.load_body("kane_levinson_1982"))
    y0 = initial_vector(cs.InitialState(omega=(0.0, 0.0, -5.0)))
    raw = solvers.solve(
        model.code,
        "throwaway",
        params,
        y0,
        1.0,
        rtol=1e-8,
        atol=1e-10,
        sample_times=np.linspace(0.0, 1.0, 5),
    )
    assert solvers.Status(raw.status) == solvers.Status.UNKNOWN_CODE
    assert raw.t_stop == 0.0


def test_an_unregistered_method_is_refused_in_one_line() -> None:
    body = cs.load_body("kane_levinson_1982")
    with pytest.raises(cs.ParameterError, match="method") as refused:
        cs.simulate(cs.RollingModel(), body, cs.InitialState(omega=(0, 0, -5)), 1.0, method="rk4")
    assert "\n" not in str(refused.value)
