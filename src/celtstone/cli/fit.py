"""``celtstone fit DATA.csv``: the model parameters that explain a measured motion."""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from celtstone.errors import ParameterError
from celtstone.fitting.problem import DEFAULT_BOUNDS, DEFAULT_RATE_SPAN, parse_bounds
from celtstone.fitting.series import SERIES
from celtstone.sweep.spec import PARAMETERS, parse_setting

EPILOG = (
    "series (NAME for --column NAME[UNIT]=HEADER; UNIT defaults to the header's '(unit)', "
    "else the one shown):\n"
    + "\n".join(
        f"  {s.name:8s} {s.description} [{s.unit}; file: {', '.join(s.units)}, default "
        f"{s.default_unit}]"
        for s in SERIES.values()
    )
    + "\n  time     sample times [s] (default: the first column)\n"
    "phyphox's gyroscope export (Time (s), Gyroscope x/y/z (rad/s)) is read as it is: its\n"
    "rates become omega1..3 through --sensor-rotation.\n\n"
    "free parameters: any name of `celtstone sweep --help` (model settings, initial state,\n"
    "body numbers); default bounds:\n"
    + "\n".join(
        f"  {name:22s} {lo:g}:{hi:g}"
        + (f" {PARAMETERS[name].unit}" if PARAMETERS[name].unit else "")
        for name, (lo, hi) in DEFAULT_BOUNDS.items()
    )
    + f"\n  omega1..3, initial_spin start ± {DEFAULT_RATE_SPAN:g} rad/s\n\n"
    "example: celtstone fit gyro.csv --body toy_rattleback_10cm --model sliding "
    "--free friction_coefficient,contact_radius --sensor-rotation x,-z,y --out fit/"
)


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone fit``."""
    parser.epilog = EPILOG
    parser.add_argument("data", metavar="DATA.csv", help="measured record: a CSV with a header")
    parser.add_argument("--body", required=True, help="shipped body name or .toml path")
    parser.add_argument("--model", default="sliding", help="rolling or sliding")
    parser.add_argument(
        "--free",
        required=True,
        metavar="NAME,NAME,...",
        help="the numbers to fit, e.g. friction_coefficient,contact_radius,damping",
    )
    parser.add_argument(
        "--column",
        action="append",
        default=[],
        metavar="NAME[UNIT]=HEADER",
        help="the file's column of a series or of time (repeat; see below)",
    )
    parser.add_argument(
        "--sensor-rotation",
        default=None,
        metavar="AXES|R11,...,R33",
        help="the gyroscope's x, y, z axes as signed body axes (x,-z,y), or the 9 numbers of "
        "R row by row with omega_body = R omega_sensor (default: the body's axes)",
    )
    parser.add_argument(
        "--bounds",
        action="append",
        default=[],
        metavar="NAME=LO:HI",
        help="bounds of a free number",
    )
    parser.add_argument(
        "--start", action="append", default=[], metavar="NAME=VALUE", help="start of a free number"
    )
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="a fixed number or option (`celtstone sweep` names); the initial state defaults "
        "to the record's first omega1..3 or spin",
    )
    parser.add_argument(
        "--sigma",
        action="append",
        default=[],
        metavar="SERIES=VALUE",
        help="noise scale weighting a series [its SI unit] (default: estimated from the data)",
    )
    parser.add_argument("--starts", default="1", help="number of starts, >= 1")
    parser.add_argument("--seed", default="0", help="seed of the drawn starts")
    parser.add_argument(
        "--profile",
        default=None,
        metavar="NAME",
        help="profile likelihood interval of a free number",
    )
    parser.add_argument("--rtol", default=None, help="the runs' relative tolerance (default 1e-8)")
    parser.add_argument("--atol", default=None, help="the runs' absolute tolerance (default 1e-10)")
    parser.add_argument(
        "--workers",
        default=None,
        help="threads for the runs: the Jacobian's columns, started beside each residual "
        "(default: one per core)",
    )
    parser.add_argument(
        "--out", default=None, metavar="DIR", help="write summary.json, fit.png|svg, run.nc"
    )
    parser.add_argument("--overwrite", action="store_true", help="replace a former fit's --out")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")


def _pairs(option: str, texts: list[str], parse: Callable[[str, str], object]) -> dict:
    values = {}
    for text in texts:
        name, sep, value = text.partition("=")
        if not sep or not name.strip():
            raise ParameterError(option, text, "NAME=VALUE")
        values[name.strip()] = parse(name.strip(), value.strip())
    return values


def _number(name: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ParameterError(name, text, "a number") from None
    if not math.isfinite(value):
        raise ParameterError(name, text, "a finite number")
    return value


def _whole(name: str, text: str, lowest: int) -> int:
    value = _number(name, text)
    if value != int(value) or value < lowest:
        raise ParameterError(name, text, f"a whole number >= {lowest}")
    return int(value)


@contextmanager
def _progress_bar(enabled: bool) -> Iterator[Callable[[int, float], None] | None]:
    """A bar counting runs, with the cost of the latest, on a terminal only."""
    if not enabled or not sys.stderr.isatty():
        yield None
        return
    from tqdm import tqdm

    with tqdm(desc="fit", unit=" runs", file=sys.stderr, delay=1.0) as bar:

        def progress(runs: int, cost: float) -> None:
            bar.update(runs - bar.n)
            bar.set_postfix_str(f"cost {cost:.6g}", refresh=False)

        yield progress


def handle(args: argparse.Namespace) -> int:
    """Read, fit, print the summary, write ``--out``; exit 3 if the fitted run stopped early."""
    from celtstone.fitting import fit, read_record
    from celtstone.fitting.outputs import check_fit_target, write_fit

    free = [name.strip() for name in args.free.split(",") if name.strip()]
    bounds = dict(parse_bounds(text) for text in args.bounds)
    start = _pairs("start", args.start, _number)
    sigma = _pairs("sigma", args.sigma, _number)
    fixed = dict(parse_setting(text) for text in args.set)
    from celtstone.fitting.solve import FIT_ATOL, FIT_RTOL

    rtol = FIT_RTOL if args.rtol is None else _number("rtol", args.rtol)
    atol = FIT_ATOL if args.atol is None else _number("atol", args.atol)
    workers = None if args.workers is None else _whole("workers", args.workers, 1)
    starts, seed = _whole("starts", args.starts, 1), _whole("seed", args.seed, 0)
    if args.out is not None:
        check_fit_target(args.out, overwrite=args.overwrite)  # before the fit, not after it
    record = read_record(args.data, args.column, sensor_rotation=args.sensor_rotation)
    with _progress_bar(not args.no_progress) as progress:
        result = fit(
            record,
            args.body,
            args.model,
            free,
            bounds=bounds,
            start=start,
            fixed=fixed,
            sigma=sigma,
            starts=starts,
            seed=seed,
            profile=args.profile,
            workers=workers,
            progress=progress,
            rtol=rtol,
            atol=atol,
        )
    if args.out is not None:
        write_fit(result, args.out, overwrite=args.overwrite)
    summary = result.summary()
    print(json.dumps(summary) if args.json else _text(summary))
    if not result.trajectory.ok:
        print(f"celtstone: the fitted run stopped: {result.trajectory.message}", file=sys.stderr)
        return 3
    return 0


def _text(summary: dict) -> str:
    lines = [
        f"fit of {summary['body']}, {summary['model']} model, to {summary['record']['source']}"
    ]
    for name, p in summary["parameters"].items():
        error = p["standard_error"]
        spread = f" ± {error:.3g}" if error is not None else " (not determined)"
        unit = f" {p['unit']}" if p["unit"] else ""
        lines.append(f"  {name:22s} {p['value']:.6g}{spread}{unit}")
    for name, s in summary["series"].items():
        lines.append(
            f"  {name}: residual RMS {s['residual_rms']:.4g} {s['unit']}, noise estimate "
            f"{s['noise_estimate']:.4g} {s['unit']} (weight sigma {s['sigma']:.3g}, "
            f"{s['sigma_source']})"
        )
    lines.append(
        f"  cost {summary['cost']:.6g}; {summary['runs']} runs ({summary['failed_runs']} failed, "
        f"{summary['speculative_runs_wasted']} speculative wasted) "
        f"in {summary['wall_time']:.3g} s; {summary['starts_reaching_best']} of "
        f"{len(summary['starts'])} starts reached the best"
    )
    if summary["profile"] is not None:
        low, high = summary["profile"]["interval_95"]
        text = [f"{v:.6g}" if v is not None else "open" for v in (low, high)]
        lines.append(
            f"  95 % profile interval of {summary['profile']['parameter']}: {text[0]} .. {text[1]}"
        )
    return "\n".join(lines)
