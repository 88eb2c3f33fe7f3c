"""Ctrl-C and SIGTERM at any moment of a command: exit 130 or 143, one line, no traceback
(issue 37, "Interruptions"). Real processes, real signals: the moment after the command's
first line of Python (read from the kernel: the process has started to catch SIGTERM) plus
a delay that lands in the imports, numba's loading, the runs and the writes."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from celtstone.cli.main import main
from celtstone.visual.animation import _count_frames
from tests.processes import catches_sigterm

pytestmark = pytest.mark.skipif(
    not Path("/proc/self/status").exists(), reason="reads a process's signal mask from /proc"
)

CELTSTONE = Path(sys.executable).with_name("celtstone")
DELAYS = (0.0, 0.05, 0.2, 0.5, 1.0)  # s after the command's first line runs
SIGNALS = (signal.SIGINT, signal.SIGTERM)
WAIT = 300  # s: the clean-up after a signal is short; this only stops a hung test


@pytest.fixture(scope="module")
def inputs(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A saved run (for animate) and a spin record (for fit) in a folder."""
    folder = tmp_path_factory.mktemp("inputs")
    assert main(["run", "--t-end", "3", "--out", str(folder / "run.nc")]) == 0
    time_s = np.linspace(0.0, 5.0, 501)
    spin = -5.0 * np.exp(-0.1 * time_s)  # any record: the fit only has to be running
    rows = "".join(f"{float(t)!r},{float(s)!r}\n" for t, s in zip(time_s, spin, strict=True))
    (folder / "spin.csv").write_text("time,spin\n" + rows, encoding="utf-8")
    return folder


def _command(name: str, inputs: Path, out: Path) -> list[str]:
    """A command that runs for well over a second, writing into ``out``."""
    commands = {
        "run": ["run", "--t-end", "200", "--model", "sliding", "--out", str(out / "r.nc")],
        "sweep": [
            "sweep", "--vary", "friction_coefficient=0.1:0.5:8", "--t-end", "30",
            "--out", str(out / "s.zarr"),
        ],
        "fit": [
            "fit", str(inputs / "spin.csv"), "--body", "kane_levinson_1982",
            "--column", "omega3=spin", "--free", "friction_coefficient,contact_radius",
            "--set", "omega3=-5", "--out", str(out / "fit"),
        ],
        "animate": ["animate", str(inputs / "run.nc"), "--out", str(out / "a.mp4")],
        "reproduce": ["reproduce", "fig2", "--quick", "--out", str(out / "paper")],
    }  # fmt: skip
    return commands[name]


def _interrupt(launcher: list[str], arguments: list[str], signum: int, delay: float | None):
    """Start the command, send ``signum`` ``delay`` s after its first line ran (None: at
    once, before the interpreter itself may have started), return (exit status, stderr)."""
    process = subprocess.Popen(
        [*launcher, *arguments],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONWARNINGS": ""},
    )
    try:
        if delay is not None:
            deadline = time.monotonic() + WAIT
            while not catches_sigterm(process.pid) and process.poll() is None:
                assert time.monotonic() < deadline, "the command never started"
                time.sleep(0.001)
            time.sleep(delay)
        assert process.poll() is None, "the command ended before the signal"
        process.send_signal(signum)
        _, error = process.communicate(timeout=WAIT)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    return process.returncode, error


def _assert_stopped_cleanly(status: int, error: str, signum: int) -> None:
    """128 + signum and one line of celtstone's on stderr (a progress bar aside)."""
    assert "Traceback" not in error and "Exception ignored" not in error, error
    assert status == 128 + signum, error
    # a warning the command gave before the signal (reproduce's runs) is not about it
    said = [
        line
        for line in re.split(r"[\r\n]", error)
        if line.startswith("celtstone") and not line.startswith("celtstone: warning:")
    ]
    word = "interrupted" if signum == signal.SIGINT else "terminated"
    assert len(said) == 1 and said[0].startswith(f"celtstone: {word}"), error


@pytest.mark.parametrize("delay", DELAYS)
@pytest.mark.parametrize("signum", SIGNALS, ids=lambda s: signal.Signals(s).name)
@pytest.mark.parametrize("command", ["run", "sweep", "fit", "animate", "reproduce"])
def test_a_signal_at_any_moment_gives_one_line_and_130_or_143(
    command: str, signum: int, delay: float, inputs: Path, tmp_path: Path
) -> None:
    status, error = _interrupt([str(CELTSTONE)], _command(command, inputs, tmp_path), signum, delay)
    _assert_stopped_cleanly(status, error, signum)
    # whatever was under way, nothing partial is left at the targets (the sweep's store
    # and the reproduction's folder keep their finished parts, for --resume); a loaded
    # machine may let the command finish before the signal lands: then its file is whole
    left = [p.name for p in tmp_path.iterdir()]
    assert all(name in ("s.zarr", "paper", "fit", "r.nc", "a.mp4") for name in left), left
    if "r.nc" in left:
        with xr.open_dataset(tmp_path / "r.nc") as run:
            assert float(run["time"][-1]) == 200.0  # --t-end 200: the whole run
    if "a.mp4" in left:
        assert _count_frames(tmp_path / "a.mp4") == 91  # 3 s at 30 fps, both ends included


@pytest.mark.parametrize("delay", (0.0, 0.02, 0.2))
@pytest.mark.parametrize("signum", SIGNALS, ids=lambda s: signal.Signals(s).name)
def test_python_dash_m_stops_as_the_script_does(
    signum: int, delay: float, inputs: Path, tmp_path: Path
) -> None:
    status, error = _interrupt(
        [sys.executable, "-m", "celtstone"], _command("run", inputs, tmp_path), signum, delay
    )
    _assert_stopped_cleanly(status, error, signum)


@pytest.mark.parametrize("signum", SIGNALS, ids=lambda s: signal.Signals(s).name)
def test_a_signal_before_python_reaches_celtstone_leaves_no_traceback_of_ours(
    signum: int, inputs: Path, tmp_path: Path
) -> None:
    """Sent as soon as the process exists: either the interpreter had not started (the
    signal's default action ends it, which a shell reports as 128 + signum) or celtstone's
    handler took it."""
    status, error = _interrupt([str(CELTSTONE)], _command("run", inputs, tmp_path), signum, None)
    if status == -signum:
        assert error == ""
    else:
        _assert_stopped_cleanly(status, error, signum)


def test_a_second_signal_during_the_clean_up_gives_no_traceback(
    inputs: Path, tmp_path: Path
) -> None:
    process = subprocess.Popen(
        [str(CELTSTONE), *_command("run", inputs, tmp_path)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        while not catches_sigterm(process.pid):
            time.sleep(0.001)
        time.sleep(0.5)
        for _ in range(20):  # a user pressing Ctrl-C again and again
            if process.poll() is not None:
                break
            process.send_signal(signal.SIGINT)
            time.sleep(0.001)
        _, error = process.communicate(timeout=WAIT)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert "Traceback" not in error, error
    # 130; or, for a Ctrl-C that lands once Python has put the default handlers back
    # while the process exits, ended by SIGINT itself (which a shell reports as 130)
    assert process.returncode in (130, -signal.SIGINT), error


def test_main_in_process_leaves_the_callers_handlers_alone() -> None:
    """A program calling ``main`` keeps its own Ctrl-C and SIGTERM handling."""
    before = (signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM))
    assert main(["bodies"]) == 0
    assert (signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)) == before


SWALLOWED = """
import sys, time, weakref
from celtstone.cli import bodies, main as cli

class Thing:
    pass

def handle(args):
    thing = Thing()

    def callback(reference):  # as the import system's module-lock callbacks
        raise cli.Terminated  # what the SIGTERM handler raises, landing here

    reference = weakref.ref(thing, callback)
    import signal
    signal.signal(signal.SIGTERM, signal.SIG_IGN)  # as the handler leaves it
    del thing  # the callback runs: Python prints and swallows its exception
    for _ in range(3000):
        time.sleep(0.01)
    print("not stopped", file=sys.stderr)
    return 0

bodies.handle = handle
sys.exit(cli.main(["bodies"]))
"""


def test_a_signal_raised_inside_a_callback_is_not_swallowed() -> None:
    """A signal's exception raised in a weak reference's callback (the import system
    has some) is only printed by Python: it is sent again and stops the command."""
    done = subprocess.run(
        [sys.executable, "-c", SWALLOWED], capture_output=True, text=True, timeout=WAIT
    )
    assert "Traceback" not in done.stderr and "Exception ignored" not in done.stderr
    assert done.stderr == "celtstone: terminated; no partial output was written\n"
    assert done.returncode == 143


def test_an_interrupt_python_wrapped_is_still_an_interrupt(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Python 3.11 wraps a signal that lands while a class is made ("Error calling
    __set_name__") in a RuntimeError: still exit 130, one line."""
    from celtstone.cli import bodies

    def wrapped(args: object) -> int:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as stop:
            raise RuntimeError("Error calling __set_name__ on 'Field' instance") from stop

    monkeypatch.setattr(bodies, "handle", wrapped)
    assert main(["bodies"]) == 130
    assert capsys.readouterr().err == "celtstone: interrupted; no partial output was written\n"


def test_an_error_without_an_interrupt_behind_it_is_not_called_one(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from celtstone.cli import bodies

    def failing(args: object) -> int:
        raise RuntimeError("a defect")

    monkeypatch.setattr(bodies, "handle", failing)
    with pytest.raises(RuntimeError, match="a defect"):
        main(["bodies"])


def _signal_lost_in_c_code(signum: int) -> bool:
    """Send ``signum`` to this process and lose the exception its handler raises, as C
    code does that reports another error instead (``PyCapsule_Import``: an ImportError
    while numpy is imported); True if the handler ran."""
    try:
        signal.raise_signal(signum)
    except KeyboardInterrupt:
        return True
    return False


@pytest.mark.parametrize("signum", SIGNALS, ids=lambda s: signal.Signals(s).name)
def test_a_signal_whose_exception_c_code_replaced_still_stops(
    signum: int, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from celtstone.cli import bodies

    def replaced(args: object) -> int:
        if _signal_lost_in_c_code(signum):  # no exception chained: C code replaced it
            raise ImportError('PyCapsule_Import could not import module "datetime"')
        return 0

    monkeypatch.setattr(bodies, "handle", replaced)
    assert main(["bodies"]) == 128 + signum
    word = "interrupted" if signum == signal.SIGINT else "terminated"
    assert capsys.readouterr().err == f"celtstone: {word}; no partial output was written\n"


@pytest.mark.parametrize("signum", SIGNALS, ids=lambda s: signal.Signals(s).name)
def test_a_signal_whose_exception_was_swallowed_still_sets_the_exit_status(
    signum: int, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A library that takes the replaced ImportError for a missing optional module goes
    on: the command ends, and its status says that it was asked to stop."""
    from celtstone.cli import bodies

    def swallowed(args: object) -> int:
        assert _signal_lost_in_c_code(signum)
        return 0

    monkeypatch.setattr(bodies, "handle", swallowed)
    assert main(["bodies"]) == 128 + signum
    assert capsys.readouterr().err.count("celtstone: ") == 1


def test_no_signal_no_change_of_status(monkeypatch: pytest.MonkeyPatch) -> None:
    from celtstone.cli import bodies

    monkeypatch.setattr(bodies, "handle", lambda args: 0)
    assert main(["bodies"]) == 0


def test_ctrl_c_while_the_sweep_store_is_built_leaves_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Ctrl-C lands while Zarr's first write of the new store is under way on its own
    thread, which then writes into the store's temporary after the interrupt: the
    temporary is removed only once that write is done, so nothing is left."""
    import asyncio
    import threading

    from zarr.storage import LocalStore

    original = LocalStore.set
    interrupted, written = threading.Event(), threading.Event()

    async def slow_first_write(self: LocalStore, key: str, value: object) -> None:
        if interrupted.is_set():
            await original(self, key, value)
            return
        interrupted.set()
        main_thread = threading.main_thread().ident
        assert main_thread is not None
        signal.pthread_kill(main_thread, signal.SIGINT)  # Ctrl-C, while this write waits
        await asyncio.sleep(0.5)  # the write is still under way as the command unwinds
        await original(self, key, value)
        written.set()

    monkeypatch.setattr(LocalStore, "set", slow_first_write)
    out = tmp_path / "s.zarr"
    arguments = ["sweep", "--vary", "friction_coefficient=0.1:0.5:4", "--t-end", "1"]
    status = main([*arguments, "--out", str(out), "--no-progress"])
    assert interrupted.is_set() and status == 130
    assert "interrupted" in capsys.readouterr().err
    written.wait(WAIT)  # the slow write has ended, one way or the other
    assert list(tmp_path.iterdir()) == []


HALF_MADE = """
import sys
from celtstone.cli import bodies, main as cli

class HalfMade:  # as asyncio's event loop, which Zarr makes while a sweep writes
    def __init__(self):
        raise cli.Terminated  # what the SIGTERM handler raises, landing in the constructor
        self.handlers = {}

    def __del__(self):  # as the loop's close(): its attribute was never set
        self.handlers.clear()

def handle(args):
    HalfMade()
    return 0

bodies.handle = handle
sys.exit(cli.main(["bodies"]))
"""


def test_a_signal_inside_a_constructor_leaves_no_finalizer_error(tmp_path: Path) -> None:
    """The object a signal left half made is freed as the command unwinds, after its one
    line; the error of its finalizer is not printed (run as the ``celtstone`` command)."""
    script = tmp_path / "celtstone"  # the command's name: ``is_the_command``
    script.write_text(HALF_MADE, encoding="utf-8")
    done = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=WAIT
    )
    assert done.stderr == "celtstone: terminated; no partial output was written\n"
    assert done.returncode == 143
