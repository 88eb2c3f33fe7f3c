"""``celtstone fit DATA.csv``: the model parameters that explain a measured motion."""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from celtstone.cli._overwrite import add_overwrite_arg
from celtstone.errors import ParameterError, require_choice
from celtstone.fitting.nuisance import NUISANCES
from celtstone.fitting.problem import DEFAULT_BOUNDS, DEFAULT_RATE_SPAN, parse_bounds
from celtstone.fitting.series import SERIES
from celtstone.sweep.devices import DEVICES
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
    + f"\n  omega1..3, initial_spin start ± {DEFAULT_RATE_SPAN:g} rad/s\n"
    "the record's own numbers (free or --set like the others):\n"
    + "\n".join(
        f"  {n.name:22s} {n.lower:g}:{n.upper:g}{f' {n.unit}' if n.unit else ''}: {n.description}"
        for n in NUISANCES.values()
    )
    + "\n  (a bias of every rate series is free unless --set or --no-sensor-bias; a scale error\n"
    "  is held at 0 unless --free or --set; the initial slip_velocity1..2 is free where the\n"
    "  run starts mid-motion, unless --set or --no-initial-slip)\n\n"
    "exit status: 0 the fit converged; 3 it did not (converged: false in the summary: the\n"
    "optimiser stopped at its limit, a parameter is at a bound, or the fitted run stopped),\n"
    "or with --strict any warning; 2 bad input; 1 the output could not be written.\n\n"
    "example: celtstone fit gyro.csv --body toy_rattleback_10cm --model sliding "
    "--free friction_coefficient,contact_radius --sensor-rotation x,-z,y --out fit/"
)
# "-y,x,z" is a value, not an option: signed axes (and negative numbers) start with "-"
_NEGATIVE_VALUE = re.compile(r"^-\d+$|^-\d*\.\d+$|^-[xyz123]\s*,")
# a record file larger than this [bytes] is announced while it is read
ANNOUNCED_FILE_SIZE = 5_000_000
# a record of this many samples or more is announced as it is fitted
ANNOUNCED_SAMPLES = 100_000
MODEL_VARIANTS = {
    "rolling": ("rolling", {}),
    "sliding, N = m g": ("sliding", {"friction_load": "static"}),
    "sliding, consistent N": ("sliding", {"friction_load": "dynamic"}),
    "stick-slip": ("sliding", {"contact": "hybrid"}),
}


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone fit``."""
    parser.epilog = EPILOG
    parser._negative_number_matcher = _NEGATIVE_VALUE  # --sensor-rotation -y,x,z
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
    parser.add_argument(
        "--starts",
        default="auto",
        help="local fits from this many starts (1 to 1000), or auto: a global search that "
        "screens the bounds first (default)",
    )
    parser.add_argument(
        "--no-sensor-bias",
        action="store_true",
        help="hold every gyroscope bias at 0 (default: free on each rate series)",
    )
    parser.add_argument(
        "--no-initial-slip",
        action="store_true",
        help="hold the contact's initial sliding velocity at 0 (default: free, "
        "slip_velocity1..2, where the run starts mid-motion: at the first sample with its "
        "rates read from the record or free)",
    )
    parser.add_argument(
        "--compare-models",
        action="store_true",
        help="fit rolling, sliding with N = m g, sliding with the consistent N and "
        "stick-slip, and rank them by AIC and BIC",
    )
    parser.add_argument(
        "--strict", action="store_true", help="exit 3 on any warning, not only when not converged"
    )
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
        "--device",
        default="cpu",
        metavar="|".join(DEVICES),
        help="where the runs go: cpu (default, threads), cuda (a CUDA GPU: each batch of "
        "runs, a residual with the Jacobian's columns, the screening's points, as one "
        "launch; an error where there is none) or auto (the GPU where there is one, else "
        "the CPU)",
    )
    parser.add_argument(
        "--out", default=None, metavar="DIR", help="write summary.json, fit.png|svg, run.nc"
    )
    add_overwrite_arg(parser, "a former fit's --out")
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


def _whole(name: str, text: str, lowest: int, highest: int | None = None) -> int:
    allowed = f"a whole number >= {lowest}" + (f" and <= {highest}" if highest else "")
    try:
        value = _number(name, text)
    except ParameterError:
        raise ParameterError(name, text, allowed) from None
    if value != int(value) or value < lowest or (highest is not None and value > highest):
        raise ParameterError(name, text, allowed)
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


def _setting(text: str) -> tuple[str, float | str]:
    """``--set NAME=VALUE``: a sweep setting, or a number of the record (``bias_spin``)."""
    name, sep, value = text.partition("=")
    if sep and name.strip() in NUISANCES:
        return name.strip(), _number(name.strip(), value.strip())
    return parse_setting(text)


def _announce_reading(path: str) -> None:
    """Say on stderr that a large record is being read (it takes seconds)."""
    try:
        size = os.path.getsize(path)
    except OSError:
        return
    if size > ANNOUNCED_FILE_SIZE:
        print(f"celtstone: reading {path} ({size / 1e6:.0f} MB) ...", file=sys.stderr, flush=True)


def _model_free(model_name: str, free: list[str]) -> list[str]:
    """The free names a model has: a model setting only where the model takes it, the
    initial slip only where the contact slides."""
    from celtstone.fitting.problem import SLIP_NAMES
    from celtstone.simulation.models import MODELS

    fields = MODELS[model_name].__dataclass_fields__
    return [
        name
        for name in free
        if (name not in PARAMETERS or PARAMETERS[name].group != "model" or name in fields)
        and not (model_name == "rolling" and name in SLIP_NAMES)
    ]


def handle(args: argparse.Namespace) -> int:
    """Read, fit, print the summary, write ``--out``; exit 3 if the fit did not converge
    (or the fitted run stopped early; with ``--strict``, on any warning)."""
    from celtstone.fitting import fit, read_record
    from celtstone.fitting.outputs import check_fit_target, comparison_figures, write_fit
    from celtstone.fitting.solve import FIT_ATOL, FIT_RTOL, MAX_STARTS, MAX_WORKERS

    free = [name.strip() for name in args.free.split(",") if name.strip()]
    bounds = dict(parse_bounds(text) for text in args.bounds)
    start = _pairs("start", args.start, _number)
    sigma = _pairs("sigma", args.sigma, _number)
    fixed = dict(_setting(text) for text in args.set)
    rtol = FIT_RTOL if args.rtol is None else _number("rtol", args.rtol)
    atol = FIT_ATOL if args.atol is None else _number("atol", args.atol)
    workers = None if args.workers is None else _whole("workers", args.workers, 1, MAX_WORKERS)
    auto = args.starts.strip().lower() == "auto"
    starts = None if auto else _whole("starts (or auto)", args.starts, 1, MAX_STARTS)
    seed = _whole("seed", args.seed, 0)
    require_choice("device", args.device, DEVICES)  # before the record is read
    if args.out is not None:
        check_fit_target(args.out, overwrite=args.overwrite)  # before the fit, not after it
    _announce_reading(args.data)
    record = read_record(args.data, args.column, sensor_rotation=args.sensor_rotation)
    if args.compare_models:
        variants = {label: variant for label, variant in MODEL_VARIANTS.items()}
    else:
        variants = {args.model: (args.model, {})}
    results = {}
    for label, (model_name, options) in variants.items():
        names = _model_free(model_name, free) if args.compare_models else free
        # the bar shows only on a terminal, after the first run: a long record's first
        # runs take seconds each, so the fit says what it does at once
        if (args.compare_models and not sys.stderr.isatty()) or (
            record.n_points >= ANNOUNCED_SAMPLES
        ):
            print(
                f"celtstone: fitting the {label} model to {record.n_points} samples ...",
                file=sys.stderr,
                flush=True,
            )
        with _progress_bar(not args.no_progress) as progress:
            results[label] = fit(
                record,
                args.body,
                model_name,
                names,
                bounds={k: v for k, v in bounds.items() if k in names},
                start={k: v for k, v in start.items() if k in names},
                fixed={**fixed, **options},
                sigma=sigma,
                sensor_bias=not args.no_sensor_bias,
                initial_slip=not args.no_initial_slip,
                starts=starts,
                seed=seed,
                profile=args.profile,
                workers=workers,
                device=args.device,
                progress=progress,
                rtol=rtol,
                atol=atol,
            )
    ranking = sorted(results, key=lambda label: results[label].summary()["aic"])
    result = results[ranking[0]]
    summary = result.summary()
    compared = {label: results[label] for label in ranking} if args.compare_models else None
    if args.compare_models:
        summary["model_comparison"] = _comparison(results, ranking)
        if args.out is not None:  # each model's fit and residuals in a figure of the folder
            for entry, figure in zip(
                summary["model_comparison"], comparison_figures(ranking).values(), strict=True
            ):
                entry["figure"] = figure
    if args.out is not None:
        write_fit(result, args.out, overwrite=args.overwrite, summary=summary, compared=compared)
    print(json.dumps(summary) if args.json else _text(summary))
    if not result.trajectory.ok:
        print(f"celtstone: the fitted run stopped: {result.trajectory.message}", file=sys.stderr)
        return 3
    if not result.converged:
        print("celtstone: the fit did not converge (converged: false): see the warnings",
              file=sys.stderr)  # fmt: skip
        return 3
    if args.strict and result.warnings:
        print(f"celtstone: {len(result.warnings)} warning(s) and --strict", file=sys.stderr)
        return 3
    return 0


def _comparison(results: dict, ranking: list[str]) -> list[dict]:
    """Each model's fit, best AIC first: AIC, BIC, their differences to the best, χ²."""
    summaries = {label: results[label].summary() for label in ranking}
    best_aic = summaries[ranking[0]]["aic"]
    best_bic = min(s["bic"] for s in summaries.values())
    return [
        {
            "model": label,
            "aic": s["aic"],
            "delta_aic": s["aic"] - best_aic,
            "bic": s["bic"],
            "delta_bic": s["bic"] - best_bic,
            "reduced_chi_square": s["reduced_chi_square"],
            "converged": s["converged"],
            "parameters": {n: p["value"] for n, p in s["parameters"].items()},
            "warnings": s["warnings"],
        }
        for label, s in summaries.items()
    ]


def _text(summary: dict) -> str:
    lines = [
        f"fit of {summary['body']}, {summary['model']} model, to {summary['record']['source']}"
        f": converged {'yes' if summary.get('converged', True) else 'NO'}"
    ]
    for name, p in summary["parameters"].items():
        error = p["standard_error"]
        spread = f" ± {error:.3g}" if error is not None else " (not determined)"
        unit = f" {p['unit']}" if p["unit"] else ""
        low, high = p.get("interval_95", (None, None))
        interval = f"  95 %: {low:.6g} .. {high:.6g}" if low is not None else ""
        flag = "  AT BOUND" if p.get("at_bound") else ""
        lines.append(f"  {name:22s} {p['value']:.6g}{spread}{unit}{interval}{flag}")
    held = summary.get("held", {})
    if held:
        lines.append(
            "  held: "
            + ", ".join(
                f"{n} = {h['value']:.6g} ({h['source'].split(':')[0]})"
                for n, h in held.items()
                if h["value"] is not None and h["source"] != "default"
            )
            + (
                f"; {sum(h['source'] == 'default' for h in held.values())} more at their "
                "defaults (summary.json: held)"
            )
        )
    for name, s in summary["series"].items():
        g = summary.get("goodness_of_fit", {}).get(name)
        checks = (
            f"; residual/noise {g['residual_rms_over_noise']:.3g}, "
            f"{'white' if g['is_white'] else 'NOT white'} (lag-1 autocorrelation "
            f"{g['lag1_autocorrelation']:+.2f})"
            if g
            else ""
        )
        lines.append(
            f"  {name}: residual RMS {s['residual_rms']:.4g} {s['unit']}, noise "
            f"{(g or s)['noise' if g else 'noise_estimate']:.4g} {s['unit']}{checks}"
        )
    if "reduced_chi_square" in summary:
        lines.append(
            f"  chi-square {summary['chi_square']:.6g}, reduced {summary['reduced_chi_square']:.4g}"
            f" ({summary['degrees_of_freedom']} degrees of freedom); AIC {summary['aic']:.6g}, "
            f"BIC {summary['bic']:.6g}"
        )
    lines.append(
        f"  {summary['runs']} runs ({summary['failed_runs']} failed) in "
        f"{summary['wall_time']:.3g} s"
        + (f" on {summary['device']}" if summary.get("device", "cpu") != "cpu" else "")
        + f"; {summary['starts_reaching_best']} of "
        f"{len(summary['starts'])} starts reached the best"
        + (
            f", {summary['distinct_minima']} distinct minima"
            if "distinct_minima" in summary
            else ""
        )
    )
    joint = summary.get("joint_region_95")
    if joint and len(joint["parameters"]) > 1:
        ends = [
            f"{name} {e[0]:.6g} .. {e[1]:.6g}" if e is not None else f"{name} not determined"
            for name, e in joint["simultaneous_intervals_95"].items()
        ]
        lines.append(f"  joint 95 % region, its shadow on each axis: {', '.join(ends)}")
    for name, walked in summary.get("profile_intervals", {}).items():
        ends = [
            f"{v:.6g}" + (" (open)" if is_open else "")
            for v, is_open in zip(walked["interval_95"], walked["open"], strict=True)
        ]
        lines.append(f"  95 % profile-likelihood interval of {name}: {ends[0]} .. {ends[1]}")
    for moved in summary.get("optimum_moved_by_profile", []):
        lines.append(
            f"  a profile's walk found a lower cost than the optimum ({moved['from_cost']:.6g}):"
            f" fitted again from there (cost {moved['to_cost']:.6g})"
        )
    if summary["profile"] is not None:
        low, high = summary["profile"]["interval_95"]
        text = [f"{v:.6g}" if v is not None else "open" for v in (low, high)]
        lines.append(
            f"  95 % profile interval of {summary['profile']['parameter']}: {text[0]} .. {text[1]}"
        )
    for entry in summary.get("model_comparison", []):
        lines.append(
            f"  model {entry['model']:24s} AIC {entry['aic']:12.6g} (Δ {entry['delta_aic']:.4g}), "
            f"BIC {entry['bic']:12.6g} (Δ {entry['delta_bic']:.4g}), reduced chi-square "
            f"{entry['reduced_chi_square']:.4g}"
            + (f", figure {entry['figure']}" if "figure" in entry else "")
        )
    return "\n".join(lines)
