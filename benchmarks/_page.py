"""The benchmark page, ``docs/benchmarks.md``: each benchmark script replaces its own section.

A section is what the script printed, headed by the machine, the date and the command
that measured it, between two marker comments that name the script
(``<!-- benchmark: NAME -->`` … ``<!-- end benchmark: NAME -->``). A script run again
replaces its section and leaves the others as they are; a new one is appended. The page
is written whole or not at all (a temporary file moved into place).

    with recorded("bench_simulate", "One run against plain SciPy"):
        main()
"""

from __future__ import annotations

import contextlib
import datetime
import io
import os
import platform
import re
import shlex
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import TextIO

PAGE = Path(__file__).resolve().parents[1] / "docs" / "benchmarks.md"
HEADER = """# Benchmarks

Speed, measured by `make bench` (`benchmarks/*.py`): each section is what one script
printed, with the machine, the date and the command that measured it, and each run of a
script replaces its own section. Tests never bound wall time; these numbers say how fast
celtstone is on one machine, against plain SciPy implementations of the same equations
(the independent oracle of `tests/oracle` and `benchmarks/careful_baseline.py`).
"""


def _markers(name: str) -> tuple[str, str]:
    return f"<!-- benchmark: {name} -->", f"<!-- end benchmark: {name} -->"


def machine() -> str:
    """The machine in words: CPU model, logical cores, OS and Python."""
    model = platform.processor() or platform.machine()
    with contextlib.suppress(OSError):
        for line in Path("/proc/cpuinfo").read_text("utf-8").splitlines():
            if line.startswith("model name"):
                model = line.partition(":")[2].strip()
                break
    return (
        f"{model}, {os.cpu_count()} logical cores, {platform.system()} {platform.release()}, "
        f"Python {platform.python_version()}"
    )


def section(name: str, title: str, text: str, *, command: str, machine: str, date: str) -> str:
    """The Markdown of one section: its title, how it was measured, the printed text."""
    begin, end = _markers(name)
    longest = max((len(run) for run in re.findall(r"`+", text)), default=0)
    fence = "`" * max(3, longest + 1)
    return "\n".join(
        [
            begin,
            f"## {title}",
            "",
            f"- machine: {machine}",
            f"- date: {date}",
            f"- command: `{command}`",
            "",
            f"{fence}text",
            text.rstrip("\n"),
            fence,
            end,
        ]
    )


def replace_section(page: str, name: str, new: str) -> str:
    """``page`` with the section ``name`` replaced by ``new``, or ``new`` appended."""
    begin, end = _markers(name)
    pattern = re.compile(re.escape(begin) + r".*?" + re.escape(end), flags=re.DOTALL)
    if pattern.search(page):
        return pattern.sub(lambda _: new, page, count=1)
    return page.rstrip("\n") + "\n\n" + new + "\n"


def write_section(
    name: str,
    title: str,
    text: str,
    *,
    command: str,
    machine: str,
    date: str,
    page: Path = PAGE,
) -> Path:
    """Replace (or append) the section ``name`` of ``page`` with ``text``, atomically."""
    old = page.read_text("utf-8") if page.exists() else HEADER
    new = replace_section(
        old, name, section(name, title, text, command=command, machine=machine, date=date)
    )
    handle, temporary = tempfile.mkstemp(dir=page.parent, prefix=f".{page.name}.", suffix=".part")
    try:
        with os.fdopen(handle, "w", encoding="utf-8") as file:
            file.write(new if new.endswith("\n") else new + "\n")
        os.replace(temporary, page)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    return page


class _Tee(io.TextIOBase):
    """Writes to the terminal and keeps a copy."""

    def __init__(self, stream: TextIO) -> None:
        self.stream, self.copy = stream, io.StringIO()

    def write(self, text: str) -> int:
        self.copy.write(text)
        return self.stream.write(text)

    def flush(self) -> None:
        self.stream.flush()


@contextlib.contextmanager
def recorded(name: str, title: str, page: Path = PAGE) -> Iterator[None]:
    """Print as usual; when the block ends without an error, write what it printed to
    its section of the page (a benchmark stopped early leaves the page as it was)."""
    tee = _Tee(sys.stdout)
    with contextlib.redirect_stdout(tee):
        yield
    command = shlex.join(["python", *sys.argv])
    date = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    path = write_section(
        name, title, tee.copy.getvalue(), command=command, machine=machine(), date=date, page=page
    )
    print(f"written to {path}", file=sys.stderr)
