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
    SlidingModel,
    load_body,
    model_from_name,
    simulate,
)
from celtstone.export import check_target, write
from celtstone.schema import PARAMETERS, check

HELP = "simulate one run of a body"
MAX_PHASE_LINES = 10  # stick/slip phases listed in the text summary


def _numbers(name: str, count: int):
    def parse(text: str) -> tuple[float, ...]:
        try:
            values = tuple(float(part) for part in text.split(","))
        except ValueError:
            raise ParameterError(name, text, f"{count} comma-separated numbers") from None
        if len(values) != count or not all(math.isfinite(v) for v in values):
            raise ParameterError(name, text, f"{count} comma-separated finite numbers")
        return values

    return parse


def _number(name: str):
    def parse(text: str) -> float:
        try:
            return float(text)
        except ValueError:
            raise ParameterError(name, text, PARAMETERS[name].allowed) from None

    return parse


def _optional_number(name: str, text: str | None) -> float | None:
    return None if text is None else _number(name)(text)


def _sliding_default(name: str) -> str:
    """Help text: the sliding model's default of ``name``; rolling refuses the option."""
    return f" (default: {getattr(SlidingModel, name)}; sliding model only)"


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
        "--tilt", type=str, default="0.5,0.5", metavar="ALPHA,BETA", help=p["tilt"].help()
    )
    parser.add_argument("--t-end", type=str, default="10", help=p["t_end"].help())
    parser.add_argument("--damping", type=str, default="0", help=p["damping"].help())
    parser.add_argument(
        "--friction-coefficient",
        type=str,
        default=None,
        help=p["friction_coefficient"].help() + _sliding_default("friction_coefficient"),
    )
    parser.add_argument(
        "--contact-radius",
        type=str,
        default=None,
        help=p["contact_radius"].help() + _sliding_default("contact_radius"),
    )
    parser.add_argument(
        "--normal-force",
        default=None,
        help="static (N = m g, the paper's) or dynamic" + _sliding_default("normal_force"),
    )
    parser.add_argument(
        "--contact",
        default=None,
        help="contact of the sliding model: sliding (always slides, default) or hybrid "
        "(stick-slip: rolls without slip and pivoting while friction can hold it)",
    )
    parser.add_argument(
        "--regularisation-speed",
        type=str,
        default=None,
        help=p["regularisation_speed"].help()
        + " (default: 1e-6, hybrid contact 1e-12; sliding model only)",
    )
    parser.add_argument(
        "--capture-speed",
        type=str,
        default=None,
        help=p["capture_speed"].help() + " (default: 100 atol; hybrid contact only)",
    )
    parser.add_argument(
        "--friction-law",
        default=None,
        help="pade (Zhuravlev, paper eq. 10) or exact (Coulomb-Contensou integrals)"
        + _sliding_default("friction_law"),
    )
    parser.add_argument(
        "--contact-pressure",
        default=None,
        help="hertz (paper eq. 2) or uniform" + _sliding_default("contact_pressure"),
    )
    parser.add_argument(
        "--elastic-modulus",
        type=str,
        default=None,
        help=p["elastic_modulus"].help()
        + "; with --poisson-ratio, replaces --contact-radius (sliding model only)",
    )
    parser.add_argument(
        "--poisson-ratio",
        type=str,
        default=None,
        help=p["poisson_ratio"].help() + " (sliding model only)",
    )
    parser.add_argument("--method", default=None, help="dop853 or radau5 (default by model)")
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
    parser.add_argument(
        "--overwrite", action="store_true", help="replace the --out file if it exists"
    )


@contextmanager
def _progress_bar(t_end: float, enabled: bool) -> Iterator[Callable[[float], None] | None]:
    """A progress callback drawing a bar of simulated time on standard error, shown only on
    a terminal and only once the run has lasted a second; None when not shown."""
    if not enabled or not sys.stderr.isatty():
        yield None
        return
    from tqdm import tqdm

    format_ = "{desc}: {percentage:3.0f}%|{bar}| {n:.4g}/{total:.4g} s [{elapsed}<{remaining}]"
    with tqdm(total=t_end, desc="run", file=sys.stderr, delay=1.0, bar_format=format_) as bar:

        def progress(time: float) -> None:
            bar.update(time - bar.n)

        yield progress


def handle(args: argparse.Namespace) -> int:
    """Run, print the summary, write ``--out``; exit 3 if the run stopped early."""
    omega = _numbers("omega", 3)(args.omega)
    tilt = _numbers("tilt", 2)(args.tilt)
    settings = {
        "damping": _number("damping")(args.damping),
        "friction_coefficient": _optional_number("friction_coefficient", args.friction_coefficient),
        "contact_radius": _optional_number("contact_radius", args.contact_radius),
        "normal_force": args.normal_force,
        "contact": args.contact,
        "regularisation_speed": _optional_number("regularisation_speed", args.regularisation_speed),
        "capture_speed": _optional_number("capture_speed", args.capture_speed),
        "friction_law": args.friction_law,
        "contact_pressure": args.contact_pressure,
        "elastic_modulus": _optional_number("elastic_modulus", args.elastic_modulus),
        "poisson_ratio": _optional_number("poisson_ratio", args.poisson_ratio),
    }
    t_end = _number("t_end")(args.t_end)
    rtol = _number("rtol")(args.rtol)
    atol = _number("atol")(args.atol)
    n_samples = None
    if args.samples is not None:
        n_samples = int(check("n_samples", _number("n_samples")(args.samples)))
    if args.out is not None:
        check_target(args.out, overwrite=args.overwrite)  # before the run, not after it
    model = model_from_name(args.model, **settings)
    body = load_body(args.body)
    state = InitialState(omega=omega, tilt=tilt)
    with _progress_bar(t_end, enabled=not args.no_progress) as progress:
        trajectory = simulate(
            model,
            body,
            state,
            t_end,
            method=args.method,
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


def _count(number: int, noun: str) -> str:
    return f"{number} {noun}" + ("" if number == 1 else "s")


def _print_text(summary: dict) -> None:
    first = summary["first_reversal_time"]
    sign_change = summary["first_sign_change_time"]
    # None when the run has no finite value (the JSON summary's null)
    normal = summary["min_normal_force"]
    normal_text = f"{normal:.6g} N" if normal is not None else "unknown"
    lines = [
        f"{summary['model']} run of {summary['body']}, t = 0 .. {summary['t_stop']:g} s "
        f"({summary['status']})",
        f"  spin: {summary['spin_initial']:.6g} -> {summary['spin_final']:.6g} rad/s; "
        + (f"first reversal at {first:.6g} s" if first is not None else "no reversal")
        + f" (band ±{summary['reversal_band']:.3g} rad/s; "
        + _count(len(summary["reversal_times"]), "reversal")
        + ")",
        f"  spin zero crossings: {len(summary['spin_zero_crossings'])}"
        + (f", the first at {sign_change:.6g} s" if sign_change is not None else ""),
        f"  energy: {summary['energy_initial']:.8g} -> {summary['energy_final']:.8g} J, "
        f"dissipated work {summary['dissipated_work']:.6g} J",
        f"  max tilt {summary['max_tilt_deg']:.4g} deg, min normal force "
        f"{normal_text}, max slip speed {summary['max_slip_speed']:.3g} m/s",
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
