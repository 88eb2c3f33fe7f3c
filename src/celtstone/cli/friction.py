"""``celtstone friction``: the friction law's force and moment against u, as numbers or a plot."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

from celtstone import ParameterError
from celtstone.cli._overwrite import add_overwrite_arg
from celtstone.contact import (
    CONTACT_PRESSURES,
    LAW_WORDS,
    LAWS,
    PRESSURE_WORDS,
    choice_words,
    friction_functions,
    law_code,
)
from celtstone.errors import require_choice
from celtstone.files.export import atomic_path, check_target
from celtstone.files.ownership import figure_metadata
from celtstone.simulation.schema import PARAMETERS, parse_number

PLOT_FORMATS = (".png", ".svg", ".pdf")


def _ratios(text: str) -> list[float]:
    allowed = "comma-separated numbers >= 0"
    try:
        values = [parse_number("u", part) for part in text.split(",")]
    except ValueError:
        raise ParameterError("u", text, allowed) from None
    if not all(math.isfinite(v) and v >= 0.0 for v in values):
        raise ParameterError("u", text, allowed)
    return values


def _ellipse_words() -> str:
    """What ``--ellipse`` prints for each law of ``contact.LAWS``."""
    reference = [name for name, entry in LAWS.items() if entry.elliptic_reference is not None]
    fast = [name for name, entry in LAWS.items() if entry.elliptic_reference is None]
    words = []
    if reference:
        words.append(f"{' and '.join(reference)} by quadrature")
    if fast:
        words.append(f"{' and '.join(fast)} in the fast form a run uses")
    return "; ".join(words)


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone friction``."""
    parser.add_argument("--law", default="exact", help=choice_words(LAW_WORDS))
    parser.add_argument("--pressure", default="hertz", help=choice_words(PRESSURE_WORDS))
    parser.add_argument(
        "--u", default="0.1,0.5,1,2", metavar="U1,U2,...", help=PARAMETERS["slip_ratio"].help()
    )
    parser.add_argument(
        "--ellipse",
        default=None,
        metavar="A,B",
        help="semi-axes A >= B > 0 [m] of an elliptic Hertz contact (major axis A): print "
        "the law over the ellipse, F/(f N), its direction and M/(f N A), "
        f"u = |V| / (A |Omega_n|): {_ellipse_words()}",
    )
    parser.add_argument(
        "--direction",
        default=None,
        metavar="DEG",
        help="with --ellipse: direction of the slip V from the major axis [deg] (default: 0)",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument(
        "--plot",
        default=None,
        metavar="FILE.png|FILE.svg|FILE.pdf",
        help="draw every law against u for the chosen pressure",
    )
    add_overwrite_arg(parser, "the --plot file")


def handle(args: argparse.Namespace) -> int:
    """Print F/(fN) and M/(fN eps) at each u; draw ``--plot``."""
    law_code(args.law)
    require_choice("contact_pressure", args.pressure, CONTACT_PRESSURES)
    ratios = _ratios(args.u)
    if args.ellipse is not None:
        return _handle_ellipse(args, ratios)
    if args.direction is not None:
        raise ParameterError(
            "direction", args.direction, "no --direction without --ellipse",
            "the disk's law does not depend on the slip direction",
        )  # fmt: skip
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


def _semi_axes(text: str) -> tuple[float, float]:
    allowed = "two semi-axes A,B [m] with A >= B > 0"
    try:
        values = [parse_number("ellipse", part) for part in text.split(",")]
    except ValueError:
        raise ParameterError("ellipse", text, allowed) from None
    if len(values) != 2 or not (0.0 < values[1] <= values[0] < math.inf):
        raise ParameterError("ellipse", text, allowed)
    return values[0], values[1]


def _degrees(text: str | None) -> float:
    if text is None:
        return 0.0
    try:
        value = parse_number("direction", text)
    except ValueError:
        raise ParameterError("direction", text, "a finite angle [deg]") from None
    if not math.isfinite(value):
        raise ParameterError("direction", text, "a finite angle [deg]")
    return value


def _handle_ellipse(args: argparse.Namespace, ratios: list[float]) -> int:
    """``--ellipse A,B``: |F|/(fN), its direction [deg] and M/(fNA) at each u: the law's
    ``elliptic_reference`` (the exact law by quadrature, ``contact.ellipse``) or, for a
    law without one, the fast form a run uses
    (``contact.ellipse_table.fast_friction_functions``)."""
    from celtstone.contact.ellipse_table import ASPECT_MIN, fast_friction_functions

    semi_major, semi_minor = _semi_axes(args.ellipse)
    if args.pressure != "hertz":
        raise ParameterError(
            "contact_pressure", args.pressure, "hertz with --ellipse",
            "the elliptic law is built for the Hertz pressure",
        )  # fmt: skip
    if args.plot is not None:
        raise ParameterError(
            "plot", args.plot, "no --plot with --ellipse", "--plot draws the disk's laws"
        )
    direction = _degrees(args.direction)
    aspect = semi_minor / semi_major
    reference = LAWS[args.law].elliptic_reference
    if reference is None and aspect < ASPECT_MIN:
        unlimited = [name for name, entry in LAWS.items() if entry.elliptic_reference]
        raise ParameterError(
            "ellipse", args.ellipse, f"B/A >= {ASPECT_MIN:g} with --law {args.law}",
            "the fast form's table starts there; --law " + " or ".join(unlimited)
            + " has no such limit",
        )  # fmt: skip
    force, force_direction, moment = [], [], []
    for u in ratios:  # spin Ω_n > 0; M reported as it opposes the spin, as for the disk
        if reference is not None:
            vector, pivot = reference(u, math.radians(direction), aspect)
        else:  # the kernel a run uses
            vector, pivot = fast_friction_functions(u, math.radians(direction), aspect, args.law)
        magnitude = math.hypot(vector[0], vector[1])
        force.append(magnitude)
        # within 1e-9 deg, so that rounding does not flip 0 to 360; 0 for no force
        angle = math.atan2(vector[1], vector[0]) if magnitude > 0.0 else 0.0
        force_direction.append(round(math.degrees(angle), 9) % 360.0)
        moment.append(-pivot)
    if args.json:
        print(
            json.dumps(
                {
                    "law": args.law,
                    "pressure": args.pressure,
                    "ellipse": [semi_major, semi_minor],
                    "direction": direction,
                    "u": ratios,
                    "force": force,
                    "force_direction": force_direction,
                    "moment": moment,
                }
            )
        )
        return 0
    print(
        f"{args.law} law, {args.pressure} pressure, ellipse A = {semi_major:g} m, "
        f"B = {semi_minor:g} m (B/A = {aspect:.6g}), slip {direction:g} deg from the major axis"
    )
    print(f"{'u':>12} {'F/(f N)':>14} {'F dir [deg]':>14} {'M/(f N A)':>14}")
    for row in zip(ratios, force, force_direction, moment, strict=True):
        print(f"{row[0]:12.6g} {row[1]:14.10f} {row[2]:14.9f} {row[3]:14.10f}")
    return 0


def _plot(path: str, pressure: str, *, overwrite: bool) -> None:
    """Every law's F/(fN) and M/(fNε) against u (``plotting.friction``), written whole."""
    import matplotlib

    matplotlib.use("Agg")
    from celtstone.plotting.friction import friction_law_figure

    figure = friction_law_figure(pressure)
    suffix = Path(path).suffix.lower().lstrip(".")
    with atomic_path(path, overwrite=overwrite, parameter="plot") as temporary:
        figure.savefig(temporary, format=suffix, metadata=figure_metadata(suffix))
