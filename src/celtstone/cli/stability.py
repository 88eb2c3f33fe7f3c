"""``celtstone stability``: eigenvalues of rolling linearised about steady spin, against spin."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from celtstone import ParameterError, RollingModel, load_body
from celtstone._about import version
from celtstone.cli._overwrite import add_overwrite_arg
from celtstone.cli._progress import progress_bar
from celtstone.files.export import atomic_path, check_target, write
from celtstone.files.ownership import CSV_MARK
from celtstone.plotting.save import check_figure_target, save_figure
from celtstone.plotting.stability import growth_rate_figure
from celtstone.simulation.schema import PARAMETERS
from celtstone.stability import SpinStability, parse_spin_range, spin_stability


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone stability``."""
    parser.add_argument(
        "--body", default="kane_levinson_1982", help="shipped body name or .toml path"
    )
    parser.add_argument(
        "--spin",
        default="-10:10:201",
        metavar="START:STOP:COUNT",
        help="spin rates omega . n [rad/s], COUNT equally spaced from START to STOP",
    )
    parser.add_argument("--damping", type=str, default="0", help=PARAMETERS["damping"].help())
    parser.add_argument("--json", action="store_true", help="print the result as one JSON object")
    parser.add_argument("--csv", default=None, metavar="FILE.csv", help="save one row per spin")
    parser.add_argument(
        "--netcdf", default=None, metavar="FILE.nc", help="save as NetCDF with the options"
    )
    parser.add_argument(
        "--plot", default=None, metavar="FILE.png|FILE.svg", help="plot the growth rates"
    )
    add_overwrite_arg(parser, "the --csv, --netcdf and --plot files")
    parser.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress bar (shown on a terminal when the spins take over a second)",
    )


# spin rates from which the command says what it does when not at a terminal (about a
# second of linearising)
ANNOUNCED_SPIN_COUNT = 2_000


def _write_csv(result: SpinStability, path: Path, overwrite: bool) -> None:
    table = result.table()
    names = list(table)
    options = result.options()
    with (
        atomic_path(path, overwrite=overwrite, parameter="csv") as temporary,
        open(temporary, "w", encoding="utf-8") as stream,
    ):
        stream.write(f"# celtstone linear stability of steady spin, {result.body.name}\n")
        stream.write(f"{CSV_MARK} {version()}\n")  # celtstone's: --overwrite may replace it
        stream.write("# " + ", ".join(f"{k} = {v}" for k, v in options.items()) + "\n")
        stream.write("# units: " + ", ".join(f"{k} [{table[k][0]}]" for k in names) + "\n")
        stream.write(",".join(names) + "\n")
        for row in range(result.spin.size):
            stream.write(",".join(repr(float(table[k][1][row])) for k in names) + "\n")


def handle(args: argparse.Namespace) -> int:
    """Compute, print the table or JSON, write the files asked for."""
    spins = parse_spin_range(args.spin)
    try:
        damping = float(args.damping)
    except ValueError:
        raise ParameterError("damping", args.damping, PARAMETERS["damping"].allowed) from None
    model = RollingModel(damping=damping)
    replace = args.overwrite
    csv = netcdf = plot = None
    if args.csv is not None:
        csv = check_target(args.csv, (".csv",), "csv", overwrite=replace)
    if args.netcdf is not None:
        netcdf = check_target(args.netcdf, (".nc",), "netcdf", overwrite=replace)
    if args.plot is not None:
        plot = check_figure_target(args.plot, "plot", overwrite=replace)
    body = load_body(args.body)
    with progress_bar(
        "stability",
        "spin",
        enabled=not args.no_progress,
        announcement="linearising the rolling model at {total} spin rates and their mirror images",
        announce_from=ANNOUNCED_SPIN_COUNT,
    ) as progress:
        result = spin_stability(body, spins, model, progress=progress)
    if csv is not None:
        _write_csv(result, csv, replace)
    if netcdf is not None:
        dataset = result.to_dataset()
        dataset.attrs["spin_range"] = args.spin
        write(dataset, netcdf, overwrite=replace)
    if plot is not None:
        save_figure(growth_rate_figure(result), plot, overwrite=replace)
    summary = {
        **result.summary(),
        "spin_range": args.spin,
        "csv": str(csv) if csv is not None else None,
        "netcdf": str(netcdf) if netcdf is not None else None,
        "plot": str(plot) if plot is not None else None,
    }
    if args.json:
        print(json.dumps(summary))
    else:
        _print_text(result, summary)
    return 0


def _print_text(result: SpinStability, summary: dict) -> None:
    """The table, one row per spin (each column computed once, not once per row)."""
    spin = result.spin
    pitch_growth, roll_growth = result.growth_rate_pitch, result.growth_rate_roll
    pitch_frequency, roll_frequency = result.frequency_pitch, result.frequency_roll
    lines = [
        f"linear stability of steady spin, rolling model, {result.body.name} "
        f"(damping {result.model.damping:g} N m s)",
        f"  preferred spin direction: {summary['preferred_spin_direction']}"
        + (" (stable)" if summary["preferred_direction_is_stable"] else " (not stable)"),
        f"  largest growth rate: {summary['max_growth_rate_positive_spin']:.6g} 1/s at spin > 0, "
        f"{summary['max_growth_rate_negative_spin']:.6g} 1/s at spin < 0",
        f"  {'spin [rad/s]':>12} {'pitch Re λ [1/s]':>17} {'pitch Im λ [rad/s]':>19} "
        f"{'roll Re λ [1/s]':>16} {'roll Im λ [rad/s]':>18}",
    ]
    for row in range(spin.size):
        lines.append(
            f"  {spin[row]:12.6g} {pitch_growth[row]:17.6g} "
            f"{pitch_frequency[row]:19.6g} {roll_growth[row]:16.6g} "
            f"{roll_frequency[row]:18.6g}"
        )
    for key in ("csv", "netcdf", "plot"):
        if summary[key] is not None:
            lines.append(f"  wrote {summary[key]}")
    print("\n".join(lines))
