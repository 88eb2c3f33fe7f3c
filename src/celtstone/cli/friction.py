"""``celtstone friction``: the friction law's force and moment against u, as numbers or a plot."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from celtstone import ParameterError
from celtstone.contact import CONTACT_PRESSURES, FRICTION_LAWS, check_choice, friction_functions
from celtstone.export import atomic_path, check_target
from celtstone.schema import PARAMETERS

HELP = "force F/(f N) and pivoting moment M/(f N eps) of a friction law against u"

PLOT_FORMATS = (".png", ".svg", ".pdf")


def _ratios(text: str) -> list[float]:
    allowed = "comma-separated numbers >= 0"
    try:
        values = [float(part) for part in text.split(",")]
    except ValueError:
        raise ParameterError("u", text, allowed) from None
    if not all(math.isfinite(v) and v >= 0.0 for v in values):
        raise ParameterError("u", text, allowed)
    return values


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone friction``."""
    parser.add_argument("--law", default="exact", help="exact or pade")
    parser.add_argument("--pressure", default="hertz", help="hertz (paper eq. 2) or uniform")
    parser.add_argument(
        "--u", default="0.1,0.5,1,2", metavar="U1,U2,...", help=PARAMETERS["slip_ratio"].help()
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument(
        "--plot",
        default=None,
        metavar="FILE.png|FILE.svg|FILE.pdf",
        help="draw both laws against u for the chosen pressure",
    )
    parser.add_argument("--overwrite", action="store_true", help="replace an existing --plot file")


def handle(args: argparse.Namespace) -> int:
    """Print F/(fN) and M/(fN eps) at each u; draw ``--plot``."""
    check_choice("friction_law", args.law, FRICTION_LAWS)
    check_choice("contact_pressure", args.pressure, CONTACT_PRESSURES)
    ratios = _ratios(args.u)
    if args.plot is not None:
        check_target(args.plot, PLOT_FORMATS, "plot", overwrite=args.overwrite)
    force, moment = friction_functions(ratios, args.law, args.pressure)
    if args.plot is not None:
        _plot(args.plot, args.pressure, overwrite=args.overwrite)
    if args.json:
        print(
            json.dumps(
                {
                    "law": args.law,
                    "pressure": args.pressure,
                    "u": ratios,
                    "force": force.tolist(),
                    "moment": moment.tolist(),
                }
            )
        )
        return 0
    print(f"{args.law} law, {args.pressure} pressure")
    print(f"{'u':>12} {'F/(f N)':>14} {'M/(f N eps)':>14}")
    for u, f, m in zip(ratios, force, moment, strict=True):
        print(f"{u:12.6g} {f:14.10f} {m:14.10f}")
    return 0


def _plot(path: str, pressure: str, *, overwrite: bool) -> None:
    """Both laws' F/(fN) and M/(fNε) against u on a logarithmic axis."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    u = np.logspace(-3, 3, 601)
    figure = Figure(figsize=(9.0, 3.8), layout="constrained")
    force_axes, moment_axes = figure.subplots(1, 2, sharex=True)
    for law, style in (("exact", "-"), ("pade", "--")):
        force, moment = friction_functions(u, law, pressure)
        label = "exact (Coulomb–Contensou)" if law == "exact" else "Padé (Zhuravlev)"
        force_axes.plot(u, force, style, label=label)
        moment_axes.plot(u, moment, style, label=label)
    force_axes.set_ylabel("friction force F / (f N)")
    moment_axes.set_ylabel("pivoting moment M / (f N ε)")
    for axes in (force_axes, moment_axes):
        axes.set_xscale("log")
        axes.set_xlabel("slip ratio u = |V1| / (ε |Ω_n|)")
        axes.grid(True, which="both", alpha=0.3)
        axes.legend()
    figure.suptitle(f"Coulomb–Contensou friction on a disk, {pressure} pressure")
    suffix = Path(path).suffix.lower().lstrip(".")
    with atomic_path(path, overwrite=overwrite, parameter="plot") as temporary:
        figure.savefig(temporary, format=suffix)
