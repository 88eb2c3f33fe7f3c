"""``celtstone`` command: dispatch to subcommands, turn errors into one line and exit 2."""

from __future__ import annotations

import argparse
import re
import sys
from collections.abc import Sequence
from typing import Any

from celtstone import CeltstoneError, version
from celtstone.cli import (
    animate,
    bodies,
    export,
    friction,
    plot,
    reproduce,
    run,
    stability,
    sweep,
    view,
)

SUBCOMMANDS = {
    "run": run,
    "bodies": bodies,
    "reproduce": reproduce,
    "plot": plot,
    "export": export,
    "animate": animate,
    "view": view,
    "stability": stability,
    "sweep": sweep,
    "friction": friction,
}

EXIT_OK = 0
EXIT_STOPPED = 3  # a run that stopped before t_end (lift-off, singular friction, ...)
EXIT_USAGE = 2


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors in one line, exit status 2.

    Values such as ``-5,0,0``, ``-1e-12`` or ``-nan`` are values, not options:
    argparse's own pattern only knows ``-5`` and ``-0.5``, so ``--omega -5,0,0``
    would fail with "expected one argument" instead of being parsed (and
    range-checked). No option of celtstone starts with ``-`` and a digit.
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = re.compile(r"^-(?:\d|\.\d|inf|nan)", re.IGNORECASE)

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(EXIT_USAGE, f"celtstone: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The full argument parser."""
    parser = _Parser(
        prog="celtstone",
        description="Simulate the Celt stone (rattleback): rolling, or rolling with sliding.",
    )
    parser.add_argument("--version", action="version", version=f"celtstone {version()}")
    commands = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name, module in SUBCOMMANDS.items():
        sub = commands.add_parser(name, help=module.HELP, description=module.HELP)
        module.add_args(sub)
        sub.set_defaults(handler=module.handle)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI with ``argv`` (default: ``sys.argv[1:]``); return the exit status."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as stop:
        return int(stop.code) if isinstance(stop.code, int) else EXIT_USAGE
    try:
        return int(args.handler(args))
    except CeltstoneError as error:
        print(f"celtstone: error: {error}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as error:
        print(f"celtstone: error: cannot write output: {error}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("celtstone: interrupted; no partial output was written", file=sys.stderr)
        return 130
