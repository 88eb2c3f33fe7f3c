"""Nothing lost: a sweep killed (SIGKILL) or interrupted (SIGINT) resumes to the same store."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import zarr

import celtstone as cs
from celtstone.cli.main import main
from celtstone.sweep import open_sweep

# 24 sliding runs of 1 s, one thread, blocks of 2 points: about 1 s of work
ARGS = [
    "sweep",
    "--vary",
    "friction_coefficient=0.2:0.5:6",
    "--vary",
    "spin=-5,-3,3,5",
    "--t-end",
    "1",
    "--workers",
    "1",
    "--chunk-points",
    "2",
    "--no-progress",
    "--no-maps",
]


def _blocks_written(store: Path) -> int:
    chunks = store / "completed" / "c"
    if not chunks.exists():
        return 0
    return sum(1 for p in chunks.rglob("*") if p.is_file() and not p.name.endswith(".partial"))


def _start_and_stop(store: Path, sig: signal.Signals) -> subprocess.CompletedProcess:
    command = [sys.executable, "-m", "celtstone", *ARGS, "--out", str(store)]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120.0
    while _blocks_written(store) < 1 and time.monotonic() < deadline:
        if process.poll() is not None:
            break
        time.sleep(0.005)
    process.send_signal(sig)
    stdout, stderr = process.communicate(timeout=60)
    return subprocess.CompletedProcess(command, process.returncode, stdout, stderr)


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> xr.Dataset:
    """The same sweep, uninterrupted."""
    store = tmp_path_factory.mktemp("reference") / "sweep.zarr"
    assert main([*ARGS, "--out", str(store)]) == 0
    return open_sweep(store)


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGINT], ids=["SIGKILL", "SIGINT"])
def test_stopped_sweep_resumes_to_the_uninterrupted_store(
    tmp_path: Path, reference: xr.Dataset, sig: signal.Signals
) -> None:
    store = tmp_path / "sweep.zarr"
    stopped = _start_and_stop(store, sig)
    if sig == signal.SIGKILL:
        assert stopped.returncode == -signal.SIGKILL
    else:
        assert stopped.returncode == 130, stopped.stderr
        assert "--resume" in stopped.stderr
    mask = np.asarray(zarr.open_group(store, mode="r")["completed"][...])
    assert 0 < mask.sum() < mask.size, "the sweep was not stopped midway"
    with pytest.raises(cs.CeltstoneError, match="incomplete"):
        open_sweep(store)
    partial = open_sweep(store, allow_incomplete=True)
    assert np.all(partial["status"].values[~mask] == "")
    np.testing.assert_array_equal(
        partial["final_spin"].values[mask], reference["final_spin"].values[mask]
    )

    done_before = int(mask.sum())
    counted: list[int] = []
    cli_argv = [*ARGS, "--out", str(store), "--resume"]
    from celtstone.sweep import runner

    original = runner.Sweep.run

    def spy(self, *args, **kwargs):  # type: ignore[no-untyped-def]
        kwargs["on_start"] = lambda done, total: counted.append(done)
        return original(self, *args, **kwargs)

    runner.Sweep.run = spy  # type: ignore[method-assign]
    try:
        assert main(cli_argv) == 0
    finally:
        runner.Sweep.run = original  # type: ignore[method-assign]
    assert counted == [done_before]  # only the missing points were computed
    xr.testing.assert_identical(open_sweep(store), reference)
