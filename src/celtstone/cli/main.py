"""``celtstone`` command: dispatch to subcommands, turn errors into one line and exit 2."""

from __future__ import annotations

import argparse
import atexit
import importlib
import os
import re
import signal
import sys
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from types import ModuleType
from typing import Any

from celtstone._about import version
from celtstone.cli._interrupts import (
    Signals,
    is_the_command,
    quiet_abandoned_writes,
    stop_at_once,
    unwinding,
)
from celtstone.cli._interrupts import Terminated as Terminated
from celtstone.errors import CeltstoneError, CeltstoneWarning


@dataclass(frozen=True)
class Command:
    """A subcommand: its one-line help and the module (``celtstone.cli.<name>``) with its
    ``add_args(parser)`` and ``handle(args) -> int``, imported only when the command runs
    or its help is asked for, so that ``celtstone --help`` starts in a blink."""

    name: str
    help: str

    def module(self) -> ModuleType:
        return importlib.import_module(f"celtstone.cli.{self.name}")


SUBCOMMANDS = {
    command.name: command
    for command in (
        Command("run", "simulate one run of a body"),
        Command("bodies", "list the shipped bodies with their sources"),
        Command(
            "reproduce",
            "reproduce the paper: fig2, fig3, threshold or all (figures, data, report.md)",
        ),
        Command("plot", "plot a saved run (RUN.nc) to PNG or SVG"),
        Command("export", "convert a saved run (RUN.nc) to CSV"),
        Command("animate", "animate a saved run in 3-D (mp4 or gif)"),
        Command(
            "view", "write an interactive page (3-D body, slider, linked plots) of a saved run"
        ),
        Command(
            "stability", "linear stability of steady spin (rolling model): eigenvalues against spin"
        ),
        Command("sweep", "run a parameter sweep (grid or list of points) into a Zarr store"),
        Command(
            "friction", "force F/(f N) and pivoting moment M/(f N eps) of a friction law against u"
        ),
        Command("fit", "fit friction, contact size, damping or initial state to a measured record"),
        Command(
            "compile",
            "compile the solvers into numba's cache now (about 45 s, once per install)",
        ),
        Command("serve", "start the live explorer in the browser (the explore extra)"),
    )
}

EXIT_OK = 0
EXIT_STOPPED = 3  # a run that stopped before t_end (lift-off, singular friction, ...)
EXIT_USAGE = 2
EXIT_OUTPUT_FAILED = 1  # an output (a file, standard output) could not be written
EXIT_INTERRUPTED = 128 + signal.SIGINT  # 130
EXIT_TERMINATED = 128 + signal.SIGTERM  # 143


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


class HelpFormatter(argparse.RawDescriptionHelpFormatter):
    """Help that shows every option's default (unless it is None, False or already said)
    and keeps the epilogs' line breaks."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        text = action.help or ""
        default = action.default
        if (
            default in (None, False, [], argparse.SUPPRESS)
            or "default" in text
            or not action.option_strings
        ):
            return text
        return text + " (default: %(default)s)"


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The argument parser: every command's options, or with ``only`` those of that command
    alone (the others are listed with their help but their modules are not imported)."""
    parser = _Parser(
        prog="celtstone",
        description="Simulate the Celt stone (rattleback): rolling, or rolling with sliding.",
        epilog="`celtstone COMMAND --help` lists a command's options with units and defaults.",
    )
    parser.add_argument("--version", action="version", version=f"celtstone {version()}")
    commands = parser.add_subparsers(
        dest="command", required=True, parser_class=_Parser, metavar="COMMAND", title="commands"
    )
    for name, command in SUBCOMMANDS.items():
        sub = commands.add_parser(
            name, help=command.help, description=command.help, formatter_class=HelpFormatter
        )
        if only is None or name == only:
            module = command.module()
            module.add_args(sub)
            sub.set_defaults(handler=module.handle)
    return parser


def _command_named(arguments: Sequence[str]) -> str:
    """The command among ``arguments``: the first that is not an option (the top level has
    only ``--help`` and ``--version``, which take no value); "" if there is none."""
    return next((a for a in arguments if not a.startswith("-")), "")


def _show_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: Any = None,
    line: str | None = None,
) -> None:
    """A warning as one line on standard error: ``celtstone: warning: ...``, its advice
    spelled as the command line spells it (``CeltstoneWarning.command_line``)."""
    text = " ".join((getattr(message, "command_line", None) or str(message)).split())
    if not issubclass(category, CeltstoneWarning):
        text = f"{category.__name__}: {text}"
    print(f"celtstone: warning: {text}", file=sys.stderr)


@contextmanager
def _one_line_warnings() -> Iterator[None]:
    with warnings.catch_warnings():
        warnings.simplefilter("default")
        # as Python's own filters: a developer's diagnostic, and a signal that lands while
        # a module is imported (xarray imports some during a write) leaves the import's
        # file to the garbage collector, which would add a second line to "terminated"
        warnings.simplefilter("ignore", ResourceWarning)
        warnings.showwarning = _show_warning
        yield


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI with ``argv`` (default: ``sys.argv[1:]``); return the exit status.

    Ctrl-C and SIGTERM at any moment, the command's imports included, give exit 130 or
    143 and one line on standard error (``_interrupts``)."""
    try:
        with unwinding() as signals:
            try:
                status = _main(argv, signals)
            except KeyboardInterrupt as stop:
                return _stopped(stop)
            except Exception as error:
                # an interrupt that Python wrapped on its way (a signal while a class is
                # made: "Error calling __set_name__"), or replaced (a signal while an
                # extension module is imported: an ImportError), is still the interrupt
                behind = _interrupt_behind(error) or signals.lost()
                if behind is None:
                    raise
                return _stopped(behind)
            lost = signals.lost()
            if lost is not None and status not in (EXIT_INTERRUPTED, EXIT_TERMINATED):
                # the signal's exception was swallowed on its way (a library that took the
                # replaced ImportError for a missing optional module): the command went on,
                # but the exit status still says that it was asked to stop
                return _stopped(lost)
            return status
    except KeyboardInterrupt as stop:
        # the signal came as the command ended, after its work and before ``unwinding``
        # put back the handlers that end the process at once
        return _stopped(stop)


def _interrupt_behind(error: BaseException) -> KeyboardInterrupt | None:
    """The KeyboardInterrupt (or :class:`Terminated`) that caused ``error``, if any."""
    seen: set[int] = set()
    cause: BaseException | None = error
    while cause is not None and id(cause) not in seen:
        if isinstance(cause, KeyboardInterrupt):
            return cause
        seen.add(id(cause))
        cause = cause.__cause__ or cause.__context__
    return None


def _stopped(stop: KeyboardInterrupt) -> int:
    """One line for Ctrl-C or SIGTERM; 130 or 143."""
    stop_at_once()  # a second signal while this is said: no traceback
    quiet_abandoned_writes()
    # a signal during a compile leaves LLVM objects half made, whose finalizers complain
    # as the interpreter exits ("Exception ignored in ... ObjectRef.__del__"), and one
    # inside a constructor an object whose finalizer fails as soon as the unwinding frees
    # it (an asyncio event loop that Zarr was making: "no attribute '_signal_handlers'"):
    # the one line below has said what happened
    atexit.register(_quiet_finalizers)
    if is_the_command():  # in-process callers keep their hook until they exit
        _quiet_finalizers()
    if isinstance(stop, Terminated):
        _say("celtstone: terminated; no partial output was written")
        return EXIT_TERMINATED
    _say("celtstone: interrupted; no partial output was written")
    return EXIT_INTERRUPTED


def _quiet_finalizers() -> None:
    """Drop the exceptions of finalizers run as an interrupted process exits."""
    sys.unraisablehook = lambda unraisable: None


def _main(argv: Sequence[str] | None, signals: Signals) -> int:
    arguments = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(only=_command_named(arguments))
    if not arguments:
        parser.print_help(sys.stderr)
        return EXIT_USAGE
    try:
        args = parser.parse_args(arguments)
    except SystemExit as stop:
        return int(stop.code) if isinstance(stop.code, int) else EXIT_USAGE
    try:
        with _one_line_warnings():
            status = int(args.handler(args))
        # a handler that caught the interrupt itself (sweep: its resume message) says 130
        if status == EXIT_INTERRUPTED:
            quiet_abandoned_writes()
            if signals.termination.received:
                return EXIT_TERMINATED
        return status
    except CeltstoneError as error:
        lost = signals.lost()  # an error the signal caused in C code: the signal
        if lost is not None:
            return _stopped(lost)
        _say(f"celtstone: error: {error}")
        return EXIT_USAGE
    except BrokenPipeError:  # the reader of standard output has gone (`| head -1`)
        _drop_standard_output()
        return EXIT_OUTPUT_FAILED
    except OSError as error:
        lost = signals.lost()
        if lost is not None:
            return _stopped(lost)
        _say(f"celtstone: error: cannot write output: {error}")
        return EXIT_OUTPUT_FAILED


def _say(line: str) -> None:
    """``line`` on standard error; if that cannot be written (a full disk, a closed pipe),
    the exit status alone tells, and nothing is left buffered to fail again at exit."""
    try:
        print(line, file=sys.stderr, flush=True)
    except OSError:
        _drop(sys.stderr)


def _drop_standard_output() -> None:
    """Standard output's reader has gone: what is still buffered goes nowhere, quietly."""
    _drop(sys.stdout)


def _drop(stream: Any) -> None:
    """Point ``stream``'s descriptor at the null device, so that Python's final flush of
    what is still buffered succeeds instead of printing an error at exit."""
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, stream.fileno())
        os.close(null)
    except (OSError, ValueError, AttributeError):  # no descriptor (in-process capture)
        pass
