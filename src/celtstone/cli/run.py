"""``celtstone run``: one simulation, summarised as text or JSON, saved as NetCDF or CSV."""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from celtstone import (
    InitialState,
    ParameterError,
    load_body,
    model_from_name,
    simulate,
)
from celtstone.cli._methods import add_method_args
from celtstone.cli._overwrite import add_overwrite_arg
from celtstone.files.export import check_target, write
from celtstone.simulation.models import MODEL_KINDS, SETTINGS, Setting, setting_defaults
from celtstone.simulation.schema import PARAMETERS, RENAMED, parse_count, parse_number, renamed

MAX_PHASE_LINES = 10  # stick/slip phases listed in the text summary


def _numbers(name: str, count: int):
    def parse(text: str) -> tuple[float, ...]:
        allowed = f"{count} comma-separated numbers"
        try:
            values = tuple(parse_number(name, part, allowed) for part in text.split(","))
        except ParameterError:
            raise ParameterError(name, text, allowed) from None
        if len(values) != count or not all(math.isfinite(v) for v in values):
            raise ParameterError(name, text, f"{count} comma-separated finite numbers")
        return values

    return parse


def _number(name: str):
    def parse(text: str) -> float:
        return parse_number(name, text)

    return parse


def _optional_number(name: str, text: str | None) -> float | None:
    return None if text is None else parse_number(name, text)


def _words(value: object, setting: Setting) -> str:
    if value is None:
        return setting.default_words
    return f"{value:g}" if isinstance(value, float) else str(value)


def _owners_and_default(setting: Setting) -> str:
    """Help text: the default of ``setting`` in each kind of model that has it, and which
    kinds those are (the others refuse the option)."""
    defaults = {
        kind: _words(value, setting) for kind, value in setting_defaults(setting.name).items()
    }
    if len(set(defaults.values())) == 1:
        text = next(iter(defaults.values()))
    else:
        text = "; ".join(f"{kind} {value}" for kind, value in defaults.items())
    if len(defaults) == len(MODEL_KINDS):
        return f" (default: {text})"
    owners = "sliding model" if "sliding" in defaults else "hybrid contact"
    return f" (default: {text}; {owners} only)"


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone run``; help text comes from ``schema``."""
    p = PARAMETERS
    parser.add_argument(
        "--body", default="kane_levinson_1982", help="shipped body name or .toml path"
    )
    parser.add_argument("--model", default="rolling", help="rolling or sliding (see --contact)")
    parser.add_argument(
        "--omega", type=str, default="0,0,-5", metavar="W1,W2,W3", help=p["omega"].help()
    )
    parser.add_argument(
        "--euler-angles",
        type=str,
        default="0.5,0.5",
        metavar="ALPHA,BETA",
        help=p["euler_angles"].help(),
    )
    parser.add_argument("--t-end", type=str, default="10", help=p["t_end"].help())
    for setting in SETTINGS.values():
        parser.add_argument(
            _option(setting.name),
            default=None,
            metavar=setting.name.upper(),
            help=setting.help() + _owners_and_default(setting),
        )
    parser.add_argument(
        "--contact",
        default=None,
        help="contact of the sliding model: sliding (always slides, default) or hybrid "
        "(stick-slip: rolls without slip and pivoting while friction can hold it)",
    )
    add_method_args(parser, " (--contact hybrid)")
    parser.add_argument("--rtol", type=str, default="1e-10", help=p["rtol"].help())
    parser.add_argument("--atol", type=str, default="1e-12", help=p["atol"].help())
    parser.add_argument("--samples", type=str, default=None, help=p["n_samples"].help())
    parser.add_argument("--json", action="store_true", help="print the summary as one JSON object")
    parser.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress bar (shown on a terminal when a run lasts over a second)",
    )
    parser.add_argument("--out", default=None, metavar="FILE.nc|FILE.csv", help="save the run")
    add_overwrite_arg(parser, "the --out file")
    _add_renamed(parser)


def _option(name: str) -> str:
    """The option of the name ``name``: ``--friction-load`` for ``friction_load``."""
    return "--" + name.replace("_", "-")


def _add_renamed(parser: argparse.ArgumentParser) -> None:
    """A hidden option for each old name (``schema.RENAMED``) of an option of ``parser``:
    given, it is refused with its new name (:func:`handle`), not reported as unknown."""
    options = {option for action in parser._actions for option in action.option_strings}
    for old, new in RENAMED.items():
        if _option(new) in options:
            parser.add_argument(_option(old), dest=f"renamed_{old}", help=argparse.SUPPRESS)


def _silent(time: float) -> None:
    """A progress callback that shows nothing (see :func:`_progress_bar`)."""


@contextmanager
def _progress_bar(t_end: float, enabled: bool) -> Iterator[Callable[[float], None]]:
    """A progress callback drawing a bar of simulated time on standard error, shown only on
    a terminal and only once the run has lasted a second; a silent one when not shown.
    Either way the compiled loop runs in a worker thread, so Ctrl-C and SIGTERM stop the
    command at once, not when the run ends."""
    if not enabled or not sys.stderr.isatty():
        yield _silent
        return
    from tqdm import tqdm

    format_ = "{desc}: {percentage:3.0f}%|{bar}| {n:.4g}/{total:.4g} s [{elapsed}<{remaining}]"
    with tqdm(total=t_end, desc="run", file=sys.stderr, delay=1.0, bar_format=format_) as bar:

        def progress(time: float) -> None:
            bar.update(time - bar.n)

        yield progress


def handle(args: argparse.Namespace) -> int:
    """Run, print the summary, write ``--out``; exit 3 if the run stopped early."""
    for old in RENAMED:
        if getattr(args, f"renamed_{old}", None) is not None:
            raise renamed(old, getattr(args, f"renamed_{old}"), spell=_option)
    omega = _numbers("omega", 3)(args.omega)
    euler_angles = _numbers("euler_angles", 2)(args.euler_angles)
    settings: dict[str, float | str | None] = {"contact": args.contact}
    for name, setting in SETTINGS.items():
        text = getattr(args, name)
        settings[name] = _optional_number(name, text) if setting.choices is None else text
    t_end = _number("t_end")(args.t_end)
    rtol = _number("rtol")(args.rtol)
    atol = _number("atol")(args.atol)
    n_samples = None
    if args.samples is not None:
        n_samples = parse_count("n_samples", args.samples)
    if args.out is not None:
        check_target(args.out, overwrite=args.overwrite)  # before the run, not after it
    model = model_from_name(args.model, **settings)
    body = load_body(args.body)
    state = InitialState(omega=omega, euler_angles=euler_angles)
    with _progress_bar(t_end, enabled=not args.no_progress) as progress:
        trajectory = simulate(
            model,
            body,
            state,
            t_end,
            method=args.method,
            stick_method=args.stick_method,
            rtol=rtol,
            atol=atol,
            n_samples=n_samples,
            progress=progress,
        )
    if args.out is not None:
        write(trajectory.dataset, args.out, overwrite=args.overwrite)
    summary = trajectory.summary()
    if args.json:
        print(json.dumps(summary))
    else:
        _print_text(summary)
    if not trajectory.ok:
        print(f"celtstone: {trajectory.message}", file=sys.stderr)
        return 3
    return 0


def _value(value: float | None, spec: str, unit: str, missing: str = "none (stopped early)") -> str:
    """``value`` in ``unit``, or ``missing`` for the JSON's null."""
    return f"{value:{spec}} {unit}" if value is not None else missing


def _count(number: int, noun: str) -> str:
    return f"{number} {noun}" + ("" if number == 1 else "s")


def _print_text(summary: dict) -> None:
    first = summary["first_reversal_time"]
    sign_change = summary["first_spin_crossing_time"]
    lines = [
        f"{summary['model']} run of {summary['body']}, t = 0 .. {summary['t_stop']:g} s "
        f"({summary['status']})",
        f"  spin: {summary['spin_initial']:.6g} -> "
        f"{_value(summary['spin_final'], '.6g', 'rad/s')}; "
        + (f"first reversal at {first:.6g} s" if first is not None else "no reversal")
        + f" (band ±{summary['reversal_band']:.3g} rad/s; "
        + _count(summary["reversal_count"], "reversal")
        + ")",
        f"  spin zero crossings: {summary['spin_crossing_count']}"
        + (f", the first at {sign_change:.6g} s" if sign_change is not None else ""),
        f"  energy: {summary['energy_initial']:.8g} -> "
        f"{_value(summary['energy_final'], '.8g', 'J')}, "
        f"dissipated work {summary['dissipated_work']:.6g} J",
        # degrees for people; the JSON's max_tilt is in rad
        f"  max tilt {math.degrees(summary['max_tilt']):.4g} deg, min normal force "
        f"{_value(summary['min_normal_force'], '.6g', 'N', 'unknown')}, "
        f"max slip speed {summary['max_slip_speed']:.3g} m/s",
    ]
    if "phases" in summary:
        lines.append(
            f"  hybrid contact: {summary['slip_phases']} slip and {summary['stick_phases']} "
            f"stick phases; capture speed {summary['capture_speed']:.3g} m/s, largest capture "
            f"energy jump {summary['max_capture_energy_jump']:.3g} J"
        )
        for phase in summary["phases"][:MAX_PHASE_LINES]:
            lines.append(f"    {phase['kind']:5s} {phase['t_start']:.9g} .. {phase['t_end']:.9g} s")
        if len(summary["phases"]) > MAX_PHASE_LINES:
            lines.append(f"    ... ({len(summary['phases']) - MAX_PHASE_LINES} more in --json)")
    if summary["max_relative_energy_drift"] is not None:
        lines.append(f"  max relative energy drift {summary['max_relative_energy_drift']:.3g}")
    print("\n".join(lines))
