"""``celtstone reproduce``: the paper's Figures 2 and 3, the friction threshold, a report."""

from __future__ import annotations

import argparse
from collections.abc import Callable

from celtstone.errors import ParameterError
from celtstone.files.path_names import check_path_name
from celtstone.reproduce import (
    REALISTIC_STUDIES,
    STUDIES,
    TARGETS,
    Study,
    realistic_study_for,
    reduced,
    study_for,
)
from celtstone.sweep.devices import DEVICES

CONTACTS: dict[str, tuple[str, Callable[[str], Study], tuple[Study, ...]]] = {
    "paper": (
        "each body's shipped study: the paper's idealisation, a disk of radius 1 mm, Padé "
        "law (atlas_stone_25cm: the Hertz disk of PMMA on glass it was found with)",
        study_for,
        STUDIES,
    ),
    "realistic": (
        "the elliptic Hertz contact, exact law, rolling resistance",
        realistic_study_for,
        REALISTIC_STUDIES,
    ),
}
"""The contacts a reproduction can run: words for the help, the study of a body, and the
studies whose bodies it runs without ``--body``."""

ATLAS_GRID_WORDS = {
    "coarse": "4 designs (L = 0.1, 0.2 m × δ = 2, 4°), about 1.5 min on 2 cores",
    "fine": "25 designs (L × δ 4 × 4 and b/a × c/a 3 × 3), about 9 min on 2 cores",
    "stone": "9 designs (κ × δ at 0.95, 1, 1.05 times the atlas stone's, Hertz PMMA on "
    "glass), about 2 min on 2 cores",
}
"""The grids of ``--atlas-grid`` (``celtstone.atlas.target.ATLAS_GRIDS``, tested equal)
in words, so that ``--help`` imports no atlas."""


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone reproduce``."""
    parser.add_argument(
        "targets",
        nargs="*",
        default=["all"],
        metavar="TARGET",
        help=f"one or more of {', '.join(TARGETS)}, atlas (the paper's findings over a "
        "family of stones, once for all bodies), all (default: all)",
    )
    parser.add_argument("--out", default="results", help="output directory (default: results)")
    parser.add_argument(
        "--body",
        action="append",
        default=None,
        help="body to use (repeatable; default: "
        + ", ".join(s.body for s in STUDIES)
        + ") — shipped name or .toml path",
    )
    parser.add_argument(
        "--contact",
        choices=(*CONTACTS, "all"),
        default="all",
        help="contact of the runs: "
        + "; ".join(f"{name}: {words}" for name, (words, _, _) in CONTACTS.items())
        + "; all: both, side by side in the report (default: all)",
    )
    parser.add_argument(
        "--atlas-grid",
        choices=ATLAS_GRID_WORDS,
        default="coarse",
        help="the atlas's designs and runs: "
        + "; ".join(f"{name}: {words}" for name, words in ATLAS_GRID_WORDS.items())
        + " (default: coarse)",
    )
    parser.add_argument(
        "--device",
        default="cpu",
        metavar="|".join(DEVICES),
        help="where the atlas target's runs go: cpu (default), cuda (a CUDA GPU: its sweeps, "
        "and the long runs of every design as one launch per model; an error where there is "
        "none) or auto (the GPU where there is one); the other targets run on the CPU",
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="shortened runs and a 6-point f grid: a smoke test, not the reproduction",
    )
    parser.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress on standard error (a bar at a terminal; elsewhere, as in a log, "
        "a line every 30 s and one as each target ends, with its time)",
    )
    parser.add_argument(
        "--overwrite",
        action="store_true",
        help="replace results of an earlier reproduction in --out (never a file it did not write)",
    )


def handle(args: argparse.Namespace) -> int:
    """Run the targets; print where the report is."""
    from celtstone.atlas.fields import atlas_device
    from celtstone.atlas.target import AtlasTarget, atlas_grid
    from celtstone.reproduce import reproduce

    if str(args.out):  # the empty path: refused by reproduce, with its reason
        check_path_name(args.out, "out")  # before any run, not when the files are moved
    contacts = list(CONTACTS) if args.contact == "all" else [args.contact]
    studies = [
        CONTACTS[contact][1](name)
        for contact in contacts
        for name in (args.body or [study.body for study in CONTACTS[contact][2]])
    ]
    for study in studies:
        study.load_body()  # an unknown body fails before any run
    if args.quick:
        studies = [reduced(study) for study in studies]
    show = not args.no_progress
    atlas = AtlasTarget(atlas_grid(args.atlas_grid), quick=args.quick, device=args.device)
    if args.device != "cpu" and not {"atlas", "all"} & set(args.targets):
        raise ParameterError(
            "device", args.device, "cpu without the target atlas", "only the atlas runs on a GPU"
        )
    atlas_device(args.device, atlas.study)  # a bad device or a missing GPU: before any run
    report = reproduce(
        args.targets, args.out, studies, progress=show, atlas=atlas, overwrite=args.overwrite
    )
    print(f"report: {report}")
    return 0
