"""The ``celtstone`` command's Ctrl-C and SIGTERM while it starts: one line, exit 130/143.

Imported first by ``celtstone/__init__.py``, before any other import, and written with
only the modules the interpreter has already loaded (``os``, ``signal``, ``sys``), so
that a signal in the command's first milliseconds finds the handler in place. It does
nothing when a program or a test imports the package: only the command itself (the
``celtstone`` script or ``python -m celtstone``) ends at once. While the command runs,
``celtstone.cli._interrupts`` takes over; once its work is done, this handler is back.
"""

import os
import signal
import sys

__all__ = ["exit_now", "is_the_command", "stop_at_once"]

_MESSAGES = {signal.SIGINT: "interrupted", signal.SIGTERM: "terminated"}


def is_the_command() -> bool:
    """Whether this process is the ``celtstone`` command itself (the console script, its
    Windows launcher, or ``python -m celtstone``), not a program importing the package."""
    # the interpreter's own arguments: `python -m celtstone` imports the package while
    # sys.argv[0] is still "-m"
    original = list(getattr(sys, "orig_argv", ()))
    for index, argument in enumerate(original[:-1]):
        if argument == "-m":
            return original[index + 1] == "celtstone"
    if not sys.argv:
        return False
    program = os.path.basename(sys.argv[0])
    if program in ("celtstone", "celtstone.exe", "celtstone-script.py"):
        return True
    parent = os.path.basename(os.path.dirname(sys.argv[0]))
    return program == "__main__.py" and parent == "celtstone"


def exit_now(signum: int, frame: object) -> None:
    """Say that the command stopped, in one line, and end the process with 128 + signum.

    ``os._exit``: raising would unwind through whatever import or clean-up is running
    (a traceback); no output of the command is being written at these moments."""
    name = _MESSAGES.get(signum, "stopped")  # type: ignore[call-overload]
    try:
        sys.stdout.flush()
    except (OSError, ValueError, AttributeError):
        pass
    try:
        os.write(2, f"celtstone: {name}\n".encode())
    except OSError:
        pass
    os._exit(128 + signum)


def stop_at_once() -> None:
    """If this process is the command: from now on SIGINT and SIGTERM end it at once
    (exit 130 or 143, one line on standard error). An ignored signal (``nohup``) stays
    ignored; outside the main thread nothing changes."""
    if not is_the_command():
        return
    for number in _MESSAGES:
        try:
            if signal.getsignal(number) is not signal.SIG_IGN:
                signal.signal(number, exit_now)
        except ValueError:
            return


stop_at_once()
