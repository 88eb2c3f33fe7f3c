"""The tests' view of other processes: Python run in a new one, and what the hostile
tests read of a running celtstone process."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path

import pytest

SIMULATOR_UNAVAILABLE = 77  # a CUDA sample's exit status where numba's simulator is missing


def python_in_new_process(
    arguments: Sequence[str],
    environment: Mapping[str, str],
    cwd: Path | None = None,
    timeout: float = 600,
) -> list[str]:
    """The lines that ``python ARGUMENTS`` writes to standard output in a new process with
    ``environment``; the test fails with the end of its standard error if it fails."""
    completed = subprocess.run(
        [sys.executable, *arguments],
        capture_output=True,
        text=True,
        env=dict(environment),
        cwd=cwd,
        check=False,
        timeout=timeout,
    )
    assert completed.returncode == 0, completed.stderr[-3000:]
    return completed.stdout.splitlines()


def catches_sigterm(pid: int) -> bool:
    """Whether process ``pid`` has a handler for SIGTERM (``/proc/PID/status``): celtstone's
    first line has run; False once the process is gone."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    caught = next(line for line in status.splitlines() if line.startswith("SigCgt:"))
    return bool(int(caught.split()[1], 16) >> (signal.SIGTERM - 1) & 1)


def sample_in_cuda_simulator(sample: Path, *arguments: str) -> None:
    """Run the script ``sample`` with ``arguments`` in a new process with numba's CUDA
    simulator (``NUMBA_ENABLE_CUDASIM=1``, set before numba is imported); the test skips
    where the sample says the simulator is unavailable, and fails with its output if the
    sample fails."""
    done = subprocess.run(
        [sys.executable, str(sample), *arguments],
        env={**os.environ, "NUMBA_ENABLE_CUDASIM": "1"},
        capture_output=True,
        text=True,
        check=False,
    )
    if done.returncode == SIMULATOR_UNAVAILABLE:
        pytest.skip(done.stderr.strip())
    assert done.returncode == 0, done.stdout + done.stderr
