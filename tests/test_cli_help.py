"""The command line explains itself: the command list without arguments, every default in
``--help``, and a run's progress while it lasts."""

from __future__ import annotations

import numpy as np
import pytest

import celtstone as cs
from celtstone.cli.main import SUBCOMMANDS, build_parser, main


def test_no_arguments_lists_every_command(capsys: pytest.CaptureFixture[str]) -> None:
    status = main([])
    out, err = capsys.readouterr()
    assert status == 2
    assert out == ""
    for name, command in SUBCOMMANDS.items():
        assert name in err
        assert command.help.split()[0] in err
    assert "Traceback" not in err


def _help(command: str) -> str:
    parser = build_parser()
    subparsers = next(a for a in parser._actions if a.dest == "command")
    sub = subparsers.choices[command]  # type: ignore[index]
    return " ".join(sub.format_help().split())  # argparse wraps lines


@pytest.mark.parametrize(
    ("option", "default"),
    [
        ("--body", "kane_levinson_1982"),
        ("--model", "rolling"),
        ("--omega", "0,0,-5"),
        ("--euler-angles", "0.5,0.5"),
        ("--t-end", "10"),
        ("--damping", "0"),
        ("--friction-coefficient", "0.35; sliding model only"),
        ("--contact-radius", "0.001; sliding model only"),
        ("--friction-load", "static; sliding model only"),
        ("--friction-law", "pade; sliding model only"),
        ("--contact-pressure", "hertz; sliding model only"),
        ("--rtol", "1e-10"),
        ("--atol", "1e-12"),
    ],
)
def test_run_help_shows_every_default(option: str, default: str) -> None:
    text = _help("run")
    start = text.index(option + " ", text.index("options:"))
    following = text[start : start + 400]
    assert f"(default: {default})" in following, following


@pytest.mark.parametrize("command", list(SUBCOMMANDS))
def test_every_valued_option_states_its_default(command: str) -> None:
    """An option with a default value (not None or a flag) says it in its help."""
    parser = build_parser()
    subparsers = next(a for a in parser._actions if a.dest == "command")
    sub = subparsers.choices[command]  # type: ignore[index]
    text = " ".join(sub.format_help().split())
    for action in sub._actions:
        if action.option_strings and action.default not in (None, False, [], "==SUPPRESS=="):
            assert "default" in (action.help or "") or f"(default: {action.default})" in text, (
                command,
                action.option_strings,
            )


def test_progress_reports_time_and_changes_nothing() -> None:
    """A run with a progress callback (the CLI's bar) reports the time reached, ends at
    t_end, and gives the same samples as a run without it."""
    body = cs.load_body("kane_levinson_1982")
    state = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
    model = cs.SlidingModel()
    reported: list[float] = []
    watched = cs.simulate(model, body, state, 2.0, progress=reported.append)
    plain = cs.simulate(model, body, state, 2.0)
    assert reported
    assert np.all(np.diff(reported) >= 0.0)
    assert reported[-1] == 2.0
    for name in ("spin", "energy", "omega", "n"):
        np.testing.assert_array_equal(watched.dataset[name].values, plain.dataset[name].values)


def test_progress_of_the_stick_slip_contact_counts_from_each_phase() -> None:
    body = cs.load_body("toy_rattleback_10cm")
    state = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
    reported: list[float] = []
    run = cs.simulate(cs.HybridModel(), body, state, 1.0, progress=reported.append)
    assert run.ok
    assert np.all(np.diff(reported) >= 0.0)
    assert reported[-1] == 1.0
