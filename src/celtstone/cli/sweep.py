"""``celtstone sweep``: a grid or list of points, stored as Zarr, with a map per result field."""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

from celtstone import ParameterError
from celtstone.schema import PARAMETERS as SCHEMA
from celtstone.sweep import (
    DEFAULT_ATOL,
    DEFAULT_RTOL,
    PARAMETERS,
    SAMPLES_PER_SECOND,
    Sweep,
    parse_axis,
    parse_setting,
)
from celtstone.sweep.plots import write_maps
from celtstone.sweep.spec import CHOICES

HELP = "run a parameter sweep (grid or list of points) into a Zarr store"

EPILOG = (
    "sweep parameters (NAME for --vary, --set and --points):\n"
    + "\n".join(
        f"  {p.name:22s} {p.description}" + (f" [{p.unit}]" if p.unit else "")
        for p in PARAMETERS.values()
    )
    + "".join(
        f"\n  {name:22s} (--set only) " + " or ".join(options) for name, options in CHOICES.items()
    )
    + "\n\nexample: celtstone sweep --vary friction_coefficient=0.02:0.5:64 "
    "--vary spin=-8:8:64 --t-end 10 --out sweep.zarr"
)


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone sweep``."""
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
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
    parser.add_argument("--method", default=None, help="dop853 or radau5 (default by model)")
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
    parser.add_argument("--overwrite", action="store_true", help="replace an existing store")
    parser.add_argument(
        "--scheduler",
        default=None,
        metavar="tcp://HOST:PORT",
        help="run on a dask.distributed cluster (default: threads on this machine)",
    )
    parser.add_argument("--workers", type=int, default=None, help="local threads (all cores)")
    parser.add_argument("--chunk-points", type=int, default=256, help="points per stored block")
    parser.add_argument(
        "--maps", default=None, metavar="DIR", help="directory of the maps (STORE_maps)"
    )
    parser.add_argument("--no-maps", action="store_true", help="write no maps")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def _number(name: str, text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise ParameterError(name, text, "a number") from None


def read_points(path: str) -> dict[str, list[float]]:
    """Columns of a CSV file whose header names sweep parameters."""
    try:
        with open(path, newline="", encoding="utf-8") as stream:
            rows = [row for row in csv.reader(stream) if row and not row[0].startswith("#")]
    except OSError as error:
        raise ParameterError("points", path, "a readable CSV file", str(error)) from None
    if len(rows) < 2:
        raise ParameterError("points", path, "a header of names and at least one row")
    names = [name.strip() for name in rows[0]]
    columns: dict[str, list[float]] = {name: [] for name in names}
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != len(names):
            raise ParameterError("points", f"{path}:{number}", f"{len(names)} values")
        for name, text in zip(names, row, strict=True):
            columns[name].append(_number(name, text))
    return columns


def handle(args: argparse.Namespace) -> int:
    """Validate every point, run the sweep, write the store and the maps."""
    if not args.vary and args.points is None:
        raise ParameterError("vary", None, "at least one --vary NAME=... or --points FILE.csv")
    axes = [parse_axis(text) for text in args.vary]
    points = read_points(args.points) if args.points is not None else None
    fixed = dict(parse_setting(text) for text in args.set)
    sweep = Sweep(
        axes,
        points=points,
        body=args.body,
        model=args.model,
        fixed=fixed,
        t_end=_number("t_end", args.t_end),
        method=args.method,
        rtol=_number("rtol", args.rtol),
        atol=_number("atol", args.atol),
        samples_per_second=_number("samples_per_second", args.samples_per_second),
        reversal_threshold=(
            None
            if args.reversal_threshold is None
            else _number("reversal_threshold", args.reversal_threshold)
        ),
    )
    out = Path(args.out)
    progress_bar = None
    counts = {"done": 0, "failed": 0, "total": sweep.size}

    def on_start(done: int, total: int) -> None:
        nonlocal progress_bar
        counts["done"] = done
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
    except KeyboardInterrupt:
        if progress_bar is not None:
            progress_bar.close()
        print(
            f"celtstone: interrupted: {counts['done']} of {counts['total']} points are in "
            f"{out}; run the same command with --resume to finish",
            file=sys.stderr,
        )
        return 130
    finally:
        if progress_bar is not None:
            progress_bar.close()
    if not args.no_maps:
        maps = Path(args.maps) if args.maps else out.with_name(out.stem + "_maps")
        write_maps(results, maps)
    failed = results["status"] != "success"
    statuses = sorted({str(s) for s in results["status"].values[failed.values]})
    print(
        f"{sweep.size} points in {out}: {int(failed.sum())} stopped early"
        + (f" ({', '.join(statuses)})" if statuses else "")
    )
    return 0
