"""Nothing lost: a sweep killed (SIGKILL), interrupted (SIGINT) or terminated (SIGTERM)
resumes to the same store."""

from __future__ import annotations

import json
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

# 24 sliding runs of 3 s, one thread, blocks of 2 points: about 3 s of work, so that the
# signal sent once the first block is on disk arrives with 11 blocks to go even when the
# test's process waits for a core (with 1 s runs a loaded machine let the sweep finish)
ARGS = [
    "sweep",
    "--vary",
    "friction_coefficient=0.2:0.5:6",
    "--vary",
    "initial_spin=-5,-3,3,5",
    "--t-end",
    "3",
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


# `python -m celtstone` as a terminal starts it: Ctrl-C raises KeyboardInterrupt. A child
# inherits an ignored or blocked SIGINT from its parent, and Python then leaves it so;
# the test worker's may be either after the tests run before it in the same process
# It also logs each numba compile (thread, function, argument types) to the file its first
# argument names: the cache is warm, so a compile shows what made a stopped sweep fail
# (a worker compiled ``batch._batch`` after four blocks once, decisions §41)
_AS_FROM_A_TERMINAL = """
import runpy, signal, sys, threading
from numba.core import event

class Compiles(event.Listener):
    def on_start(self, ev):
        function = ev.data["dispatcher"].py_func
        with open(LOG, "a") as log:
            print(threading.current_thread().name, function.__module__,
                  function.__qualname__, ev.data["args"], file=log)
    def on_end(self, ev):
        pass

LOG = sys.argv.pop(1)
event.register("numba:compile", Compiles())
signal.pthread_sigmask(signal.SIG_UNBLOCK, [signal.SIGINT])
signal.signal(signal.SIGINT, signal.default_int_handler)
sys.argv = ["celtstone", *sys.argv[1:]]
runpy.run_module("celtstone", run_name="__main__", alter_sys=True)
"""


def _start_and_stop(store: Path, sig: signal.Signals) -> tuple[subprocess.CompletedProcess, str]:
    """The sweep started and sent ``sig`` once its first block is on disk; with what the
    test saw then, for the assertion messages."""
    compiles = store.with_name("compiles.log")
    command = [sys.executable, "-c", _AS_FROM_A_TERMINAL, str(compiles), *ARGS, "--out", str(store)]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120.0
    while _blocks_written(store) < 1 and time.monotonic() < deadline:
        if process.poll() is not None:
            break
        time.sleep(0.005)
    finished_before = process.poll() is not None
    process.send_signal(sig)
    stdout, stderr = process.communicate(timeout=60)
    blocks = _blocks_written(store)
    compiled = compiles.read_text() if compiles.exists() else "none\n"
    seen = (
        f"{stderr}[test: {blocks} blocks; finished before the signal: {finished_before}; "
        f"numba compiled in the sweep:\n{compiled}]"
    )
    return subprocess.CompletedProcess(command, process.returncode, stdout, stderr), seen


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> xr.Dataset:
    """The same sweep, uninterrupted."""
    store = tmp_path_factory.mktemp("reference") / "sweep.zarr"
    assert main([*ARGS, "--out", str(store)]) == 0
    return open_sweep(store)


@pytest.mark.xdist_group("sweep-reference")  # `reference` once, in one worker
@pytest.mark.parametrize(
    "sig", [signal.SIGKILL, signal.SIGINT, signal.SIGTERM], ids=["SIGKILL", "SIGINT", "SIGTERM"]
)
def test_stopped_sweep_resumes_to_the_uninterrupted_store(
    tmp_path: Path, reference: xr.Dataset, sig: signal.Signals
) -> None:
    store = tmp_path / "sweep.zarr"
    stopped, seen = _start_and_stop(store, sig)
    if sig == signal.SIGKILL:
        assert stopped.returncode == -signal.SIGKILL
    else:  # SIGTERM unwinds like Ctrl-C: the same message, exit 128 + the signal
        assert stopped.returncode == 128 + sig, seen
        assert "--resume" in stopped.stderr
        assert len(stopped.stderr.splitlines()) == 1, seen
    mask = np.asarray(zarr.open_group(store, mode="r")["completed"][...])
    assert 0 < mask.sum() < mask.size, "the sweep was not stopped midway"
    with pytest.raises(cs.CeltstoneError, match="incomplete"):
        open_sweep(store)
    partial = open_sweep(store, allow_incomplete=True)
    assert np.all(partial["status"].values[~mask] == "")
    np.testing.assert_array_equal(
        partial["spin_final"].values[mask], reference["spin_final"].values[mask]
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


MEMORY_SCRIPT = """
import resource, sys
import numpy as np
from celtstone.sweep import Sweep
grid = {"damping": np.linspace(0.0, 1e-5, 256), "initial_spin": np.linspace(-8.0, 8.0, 256)}
Sweep(grid, model="rolling", t_end=0.01).run(sys.argv[1])
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
"""


@pytest.mark.slow
def test_256_by_256_sweep_streams_within_2_gib(tmp_path: Path) -> None:
    """Peak resident memory of a 65 536-point sweep to a store (short runs: the
    batch driver's buffers do not grow with the number of points)."""
    command = [sys.executable, "-c", MEMORY_SCRIPT, str(tmp_path / "big.zarr")]
    output = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    peak_kib = int(output.split()[-1])
    assert peak_kib < 2 * 1024 * 1024
    assert open_sweep(tmp_path / "big.zarr")["status"].shape == (256, 256)


def test_a_store_of_the_raw_spin_reversal_is_not_resumed(tmp_path: Path) -> None:
    """A store begun before reversals were read from the rocking average (its spec has no
    ``reversal_window``) would mix two definitions: resuming it is refused in one line
    naming the setting; it still opens."""
    sweep = cs.Sweep({"initial_spin": [-5.0, 5.0]}, t_end=0.05)
    store = tmp_path / "old.zarr"
    sweep.run(store)
    group = zarr.open_group(store, mode="r+")
    spec = json.loads(str(group.attrs["sweep_spec"]))
    del spec["reversal_window"]
    group.attrs["sweep_spec"] = json.dumps(spec, sort_keys=True)
    with pytest.raises(cs.ParameterError, match="differ from the stored ones: reversal_window"):
        sweep.run(store, resume=True)
    assert open_sweep(store)["reversal_count"].size == 2
