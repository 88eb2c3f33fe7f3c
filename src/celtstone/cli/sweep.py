"""``celtstone sweep``: a grid or list of points, stored as Zarr, with a map per result field."""

from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from celtstone import ParameterError
from celtstone.cli._interrupts import Terminated
from celtstone.cli._methods import add_method_args
from celtstone.cli._overwrite import add_overwrite_arg
from celtstone.files.path_names import check_path_name
from celtstone.simulation.schema import PARAMETERS as SCHEMA
from celtstone.simulation.schema import parse_number
from celtstone.sweep import (
    DEFAULT_ATOL,
    DEFAULT_RTOL,
    PARAMETERS,
    SAMPLES_PER_SECOND,
    Sweep,
    parse_setting,
)
from celtstone.sweep.budget import (
    HARD_POINT_LIMIT,
    LONG_SWEEP_SECONDS,
    POINT_LIMIT,
    STORE_LIMIT_BYTES,
)
from celtstone.sweep.devices import DEVICES
from celtstone.sweep.plots import DEFAULT_MAPPED_FIELDS, map_paths, write_maps
from celtstone.sweep.points import read_points
from celtstone.sweep.runner import (
    DEFAULT_CONTACT,
    MAX_CHUNK_POINTS,
    MAX_WORKERS,
    check_run_options,
)
from celtstone.sweep.spec import CHOICES, parse_axis_spec
from celtstone.sweep.store import check_store_target

_CHOICE_NOTES = {
    "contact": f" (default {DEFAULT_CONTACT}: stick-slip; sliding: regularised, as celtstone run)"
}
EPILOG = (
    "sweep parameters (NAME for --vary, --set and --points):\n"
    + "\n".join(
        f"  {p.name:22s} {p.description}" + (f" [{p.unit}]" if p.unit else "")
        for p in PARAMETERS.values()
    )
    + "".join(
        f"\n  {name:22s} (--set only) " + " or ".join(options) + _CHOICE_NOTES.get(name, "")
        for name, options in CHOICES.items()
    )
    + "\n\nexample: celtstone sweep --vary friction_coefficient=0.02:0.5:64 "
    "--vary initial_spin=-8:8:64 --t-end 10 --out sweep.zarr"
)


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone sweep`` (the parser's formatter keeps the epilog's lines)."""
    parser.epilog = EPILOG
    parser.add_argument(
        "--vary",
        action="append",
        default=[],
        metavar="NAME=START:STOP:COUNT|NAME=V1,V2,...",
        help="a grid axis: COUNT evenly spaced values, ends included, or a list",
    )
    parser.add_argument(
        "--points", default=None, metavar="FILE.csv", help="a list of points: one column a name"
    )
    parser.add_argument(
        "--set", action="append", default=[], metavar="NAME=VALUE", help="a fixed parameter"
    )
    parser.add_argument("--body", default="kane_levinson_1982", help="body name or .toml path")
    parser.add_argument("--model", default="sliding", help="sliding (default) or rolling")
    parser.add_argument("--t-end", type=str, default="10", help=SCHEMA["t_end"].help())
    add_method_args(parser, "")
    parser.add_argument("--rtol", type=str, default=str(DEFAULT_RTOL), help=SCHEMA["rtol"].help())
    parser.add_argument("--atol", type=str, default=str(DEFAULT_ATOL), help=SCHEMA["atol"].help())
    parser.add_argument(
        "--samples-per-second",
        type=str,
        default=str(SAMPLES_PER_SECOND),
        help="samples behind max tilt, normal force and the reversal band [1/s]",
    )
    parser.add_argument(
        "--reversal-threshold",
        type=str,
        default=None,
        help="half-width of the spin's hysteresis band for reversals [rad/s] "
        "(default: 4 %% of each point's initial |spin|, at least 0.01 rad/s)",
    )
    parser.add_argument("--out", required=True, metavar="STORE.zarr", help="Zarr store to write")
    parser.add_argument("--resume", action="store_true", help="compute only the missing points")
    add_overwrite_arg(parser, "the store")
    parser.add_argument(
        "--scheduler",
        default=None,
        metavar="tcp://HOST:PORT",
        help="run on a dask.distributed cluster (default: threads on this machine)",
    )
    parser.add_argument(
        "--workers",
        type=int,
        default=None,
        help=f"local threads, 1 to {MAX_WORKERS} (default: every core; not with --scheduler)",
    )
    parser.add_argument(
        "--device",
        default="cpu",
        metavar="|".join(DEVICES),
        help="where the points run: cpu (default), cuda (a CUDA GPU, one thread per point: "
        "the rolling model, and sliding with --set contact=sliding, so far; an error where "
        "it cannot run) or "
        "auto (the GPU where it can, else the CPU)",
    )
    parser.add_argument(
        "--chunk-points",
        type=int,
        default=256,
        help=f"points per stored block, 1 to {MAX_CHUNK_POINTS}",
    )
    parser.add_argument(
        "--force",
        action="store_true",
        help=f"run a sweep of more than {POINT_LIMIT} points or a store above "
        f"{STORE_LIMIT_BYTES / 1e9:g} GB (never more than {HARD_POINT_LIMIT} points)",
    )
    parser.add_argument(
        "--maps", default=None, metavar="DIR", help="directory of the maps (STORE_maps)"
    )
    parser.add_argument("--no-maps", action="store_true", help="write no maps")
    parser.add_argument(
        "--map-fields",
        default=None,
        metavar="NAME,NAME,...|all",
        help="the result fields to map (default: " + ", ".join(DEFAULT_MAPPED_FIELDS) + ")",
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def _number(name: str, text: str) -> float:
    return parse_number(name, text, "a number")  # the range: checked by Sweep


def _validation_progress(enabled: bool) -> Callable[[int, int], None]:
    """A bar on standard error for the validation of the points, shown only if it
    takes more than a second."""
    bar: Any = None

    def progress(built: int, total: int) -> None:
        nonlocal bar
        if not enabled:
            return
        if bar is None:
            from tqdm import tqdm

            bar = tqdm(
                total=total,
                desc="validating",
                unit="object",
                file=sys.stderr,
                delay=1.0,
                leave=False,
            )
        if bar.total != total:  # the body-model pairs are counted once the models are built
            bar.total = total
        bar.update(built - bar.n)
        if built >= total:
            bar.close()

    return progress


def _sweep(args: argparse.Namespace) -> tuple[Sweep, int]:
    """The validated sweep of the command line and its local threads (0 with a
    scheduler): options first, then the size from the counts, then every point."""
    if not args.vary and args.points is None:
        raise ParameterError("vary", None, "at least one --vary NAME=... or --points FILE.csv")
    if args.vary and args.points is not None:
        raise ParameterError("points", args.points, "either --vary axes or --points, not both")
    _, threads = check_run_options(args.scheduler, args.workers, args.chunk_points)
    settings = {
        "t_end": _number("t_end", args.t_end),
        "rtol": _number("rtol", args.rtol),
        "atol": _number("atol", args.atol),
        "samples_per_second": _number("samples_per_second", args.samples_per_second),
        "reversal_threshold": (
            None
            if args.reversal_threshold is None
            else _number("reversal_threshold", args.reversal_threshold)
        ),
    }
    axes = [parse_axis_spec(text) for text in args.vary]  # counts only: no values made yet
    fixed = dict(parse_setting(text) for text in args.set)
    points = read_points(args.points, force=args.force) if args.points is not None else None
    sweep = Sweep(
        axes,
        points=points,
        body=args.body,
        model=args.model,
        fixed=fixed,
        method=args.method,
        stick_method=args.stick_method,
        force=args.force,
        device=args.device,
        progress=_validation_progress(not args.no_progress),
        **settings,  # type: ignore[arg-type]
    )
    return sweep, threads


def handle(args: argparse.Namespace) -> int:
    """Validate every option and point, run the sweep, write the store and the maps."""
    inputs = [] if args.points is None else [args.points]  # never inside what is replaced
    out = check_store_target(args.out, overwrite=args.overwrite, resume=args.resume, inputs=inputs)
    maps = None if args.no_maps else Path(args.maps or out.with_name(out.stem + "_maps"))
    replace_maps = args.overwrite or args.resume  # the maps belong to the store replaced
    if maps is not None:
        check_path_name(maps, "maps")
        map_paths(maps, overwrite=replace_maps, fields=args.map_fields)  # before the sweep
    sweep, threads = _sweep(args)
    # the estimate is the CPU's; a GPU sweep says what it runs on as it starts
    if sweep.device == "cpu" and sweep.estimate.wall_seconds(threads) > LONG_SWEEP_SECONDS:
        print(f"celtstone: sweep of {sweep.estimate.describe(threads or None)}", file=sys.stderr)
    progress_bar = None
    counts = {"done": 0, "failed": 0, "total": sweep.size, "started": 0}

    def on_start(done: int, total: int) -> None:  # the store is in place
        nonlocal progress_bar
        counts["done"] = done
        counts["started"] = 1
        if not args.no_progress:
            from tqdm import tqdm

            progress_bar = tqdm(
                total=total, initial=done, unit="pt", desc="sweep", file=sys.stderr, smoothing=0.1
            )
            progress_bar.set_postfix(failed=0)

    def progress(points: int, failures: int) -> None:
        counts["done"] += points
        counts["failed"] += failures
        if progress_bar is not None:
            progress_bar.update(points)
            progress_bar.set_postfix(failed=counts["failed"])

    try:
        results = sweep.run(
            out,
            resume=args.resume,
            overwrite=args.overwrite,
            scheduler=args.scheduler,
            workers=args.workers,
            chunk_points=args.chunk_points,
            progress=progress,
            on_start=on_start,
        )
    except KeyboardInterrupt as stop:
        said = "terminated" if isinstance(stop, Terminated) else "interrupted"
        # Zarr's writes pending in its event loop are abandoned (the store records only
        # finished blocks); asyncio would report each as "Task was destroyed but it is
        # pending!" when the interpreter exits, after our one line
        logging.getLogger("asyncio").setLevel(logging.CRITICAL)
        if progress_bar is not None:
            progress_bar.close()
        if not counts["started"]:  # stopped while the store was built: it never reached out
            print(f"celtstone: {said}; no partial output was written", file=sys.stderr)
            return 130
        print(
            f"celtstone: {said}: {counts['done']} of {counts['total']} points are in "
            f"{out}; run the same command with --resume to finish",
            file=sys.stderr,
        )
        return 130
    finally:
        if progress_bar is not None:
            progress_bar.close()
    if maps is not None:
        write_maps(results, maps, overwrite=replace_maps, fields=args.map_fields)
    failed = results["status"] != "success"
    statuses = sorted({str(s) for s in results["status"].values[failed.values]})
    print(
        f"{sweep.size} points in {out}: {int(failed.sum())} stopped early"
        + (f" ({', '.join(statuses)})" if statuses else "")
    )
    return 0
