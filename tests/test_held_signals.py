"""A signal that lands while a child process starts is raised once the child is held, so
that it is stopped: landing inside ``subprocess.Popen`` it left an ffmpeg that created the
video's temporary again after the clean-up (a ``.part`` left beside the target)."""

from __future__ import annotations

import signal
import subprocess
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from celtstone._held_signals import held_signals
from celtstone.cli._interrupts import Terminated, Termination
from celtstone.visual import animation


def test_a_sigterm_while_held_is_raised_as_the_block_ends() -> None:
    """The command's SIGTERM handler inside the block: the block runs on, then Terminated."""
    termination = Termination()
    previous = signal.signal(signal.SIGTERM, termination)
    ran_on = False
    try:
        with pytest.raises(Terminated), held_signals():
            signal.raise_signal(signal.SIGTERM)
            ran_on = True
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert ran_on and termination.received


def test_without_a_signal_the_block_raises_nothing_and_ctrl_c_is_python_s_again() -> None:
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with held_signals():
            assert signal.getsignal(signal.SIGINT) is not signal.default_int_handler
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        signal.signal(signal.SIGINT, previous)


def _frames() -> Iterator[np.ndarray]:
    for shade in range(3):
        yield np.full((48, 64, 3), 80 * shade, dtype=np.uint8)


def test_ctrl_c_as_ffmpeg_starts_leaves_no_ffmpeg_and_no_temporary(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Ctrl-C lands as ``Popen`` returns ffmpeg's handle (Python's own handler, as in a
    program calling celtstone): ffmpeg is killed and nothing is left beside the target, even
    once the pipe to it is closed (an ffmpeg left running then writes its output)."""
    started: list[subprocess.Popen[bytes]] = []
    real_popen = subprocess.Popen

    def popen_then_ctrl_c(*args: Any, **kwargs: Any) -> subprocess.Popen[bytes]:
        process = real_popen(*args, **kwargs)
        if kwargs.get("stdin") is subprocess.PIPE:  # the encoder (not `ffmpeg -version`)
            started.append(process)
            signal.raise_signal(signal.SIGINT)
        return process

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    monkeypatch.setattr(animation.subprocess, "Popen", popen_then_ctrl_c)
    try:
        with pytest.raises(KeyboardInterrupt):
            animation._write(tmp_path / "a.mp4", ".mp4", _frames(), 30.0)
    finally:
        signal.signal(signal.SIGINT, previous)
        monkeypatch.undo()
        for process in started:  # what an orphan would meet when the program goes on
            if process.stdin is not None:
                process.stdin.close()
            process.wait(timeout=30)
    assert len(started) == 1 and started[0].returncode == -signal.SIGKILL
    assert list(tmp_path.iterdir()) == []
