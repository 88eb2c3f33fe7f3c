"""A small sweep on the CPU and in numba's CUDA simulator, for tests/test_sweep_cuda.py.

Run as ``NUMBA_ENABLE_CUDASIM=1 python tests/sweep_cuda_sample.py DIR MODEL METHOD``
(the variable must be set before numba is imported, hence a process of its own), MODEL
a key of ``SWEEPS``. Writes to
DIR: ``cpu.zarr``, the CPU sweep; ``cuda.zarr``, the same sweep on the (simulated) GPU,
stopped by Ctrl-C after its first block and resumed; ``report.json``, what the test
checks besides the stores. Exits 77 where the simulator is unavailable, saying why.
``NUMBA_ENABLE_CUDASIM=1 python tests/sweep_cuda_sample.py --calmed SCRIPT ARGS...`` runs
another script (the GPU benchmark) in the same simulator. The simulator waits for its
threads instead of polling them in a busy loop (``calm_simulator``).

The rolling points are five initial states of the Kane & Levinson body over 3 s that
cover what the loop and the reduction read: runs that reverse and runs that do not, raw
spin sign changes from 2 to 6, and a run that lifts off (a terminal event) at once. The
sliding points (no stick phases) over 2 s, with the Padé law on the disk and the static
friction load, and three with the exact law and the dynamic load: runs that reverse and
runs that do not, and from none to 19 spin sign changes. (A spin that starts at zero
chatters about it while the slip decides its sense: with an explicit method that takes
millions of steps, too many for a test.) The stick–slip points (the sliding model's
default contact) over 1 s, with the realistic contact (the Hertz ellipse of E = 3 GPa,
ν = 0.35, the exact law, the dynamic load, rolling resistance 10 µm): runs that stay in
slip, runs with from 3 to 40 phases and up to 30 rejected captures, one that reverses.
For them the sample also runs ``solvers.batch.run_batch`` with a phase log too short
for most (``SHORT_PHASE_LOG``) on both, reversals read from the raw spin, into
``max_phases.npz``.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path
from typing import Any

from processes import SIMULATOR_UNAVAILABLE  # this folder is the script's first on sys.path

SWEEPS = {
    "rolling": {
        "points": {
            "initial_spin": [-6.0, -4.0, -2.0, 0.0, -20.0],
            "euler_alpha": [5.0, 0.1, 5.0, 5.0, 20.0],
        },
        "t_end": 3.0,  # s
    },
    "sliding": {
        "points": {
            "initial_spin": [-6.0, -2.0, -20.0, -6.0, 2.0],
            "euler_alpha": [5.0, 5.0, 20.0, 10.0, 5.0],
        },
        "t_end": 2.0,  # s
        "fixed": {"contact": "sliding"},
    },
    "sliding_exact_dynamic": {
        "points": {"initial_spin": [-2.0, -20.0, -8.0], "euler_alpha": [5.0, 20.0, 5.0]},
        "t_end": 2.0,  # s
        "fixed": {"contact": "sliding", "friction_law": "exact", "friction_load": "dynamic"},
        "model": "sliding",
    },
    "stick_slip": {
        "points": {
            "initial_spin": [-6.0, -2.0, 0.0, -6.0, -2.0, 0.0],
            "euler_alpha": [5.0, 5.0, 5.0, 20.0, 20.0, 20.0],
        },
        "t_end": 1.0,  # s
        "fixed": "realistic",  # ``reproduce.study.REALISTIC_CONTACT``, read in main()
        "model": "sliding",
    },
}
CHUNK_POINTS = 2  # three blocks: the interruption falls after the first
CALMED = "--calmed"  # ``--calmed SCRIPT ARGS...``: SCRIPT run in the calmed simulator
POLL_WAIT = 0.001  # [s] the simulator's wait on each live thread per poll (calm_simulator)
SHORT_PHASE_LOG = 4  # phases: the stick–slip points of more stop with status max_phases


def main() -> int:
    directory, model, method = Path(sys.argv[1]), sys.argv[2], sys.argv[3]
    refused = start_simulator()
    if refused is not None:
        return refused
    from celtstone.errors import ParameterError
    from celtstone.sweep import Sweep

    sweep = dict(SWEEPS[model])
    if sweep.get("fixed") == "realistic":
        from celtstone.reproduce.study import REALISTIC_CONTACT

        sweep["fixed"] = dict(REALISTIC_CONTACT)
    points = sweep.pop("points")
    settings = {"model": sweep.pop("model", model), "method": method, **sweep}
    cpu = Sweep(points=points, **settings)
    cpu.run(directory / "cpu.zarr", workers=1, chunk_points=CHUNK_POINTS)
    gpu = Sweep(points=points, device="cuda", **settings)
    report: dict[str, object] = {"device": gpu.device}

    def stop_after_first_block(points: int, failures: int) -> None:
        raise KeyboardInterrupt

    try:
        gpu.run(directory / "cuda.zarr", chunk_points=CHUNK_POINTS, progress=stop_after_first_block)
    except KeyboardInterrupt:
        from celtstone.sweep import open_sweep

        partial = open_sweep(directory / "cuda.zarr", allow_incomplete=True)
        report["points_before_resume"] = int((partial["status"] != "").sum())
    gpu.run(directory / "cuda.zarr", chunk_points=CHUNK_POINTS, resume=True)
    refusals = []
    for options in ({"workers": 2}, {"scheduler": "tcp://127.0.0.1:1"}):
        try:
            gpu.run(**options)  # type: ignore[arg-type]
        except ParameterError as error:
            refusals.append(str(error))
    report["refusals"] = refusals
    if gpu.is_hybrid:
        _short_phase_log(gpu, directory)
    (directory / "report.json").write_text(json.dumps(report))
    return 0


def start_simulator() -> int | None:
    """Calm numba's CUDA simulator for this process (:func:`calm_simulator`), or the exit
    status of a sample that cannot run: 2 without ``NUMBA_ENABLE_CUDASIM=1``, 77 where
    the simulator is unavailable (its test skips)."""
    if os.environ.get("NUMBA_ENABLE_CUDASIM") != "1":
        print("NUMBA_ENABLE_CUDASIM=1 must be set", file=sys.stderr)
        return 2
    try:
        from numba import cuda

        if not cuda.is_available():
            raise RuntimeError("numba.cuda.is_available() is False")
    except Exception as error:
        print(f"numba's CUDA simulator is unavailable: {error}", file=sys.stderr)
        return SIMULATOR_UNAVAILABLE
    calm_simulator()
    return None


def calm_simulator() -> None:
    """Let numba's simulator wait for its threads instead of spinning.

    A launch polls its threads' ``is_alive`` in a loop with no wait until all have ended
    (``numba.cuda.simulator.kernel.BlockManager.run``). celtstone's compiled code releases
    the GIL (``nogil``), so while the threads integrate (and at a first launch compile
    the thread's code), that loop keeps a core busy: as much CPU as the launch's wall
    time, taken from the other test worker. Here each poll
    first waits up to ``POLL_WAIT`` for the thread to end (``join`` with a timeout, which
    sleeps): the same threads, run and checked as before, only fewer polls. Where numba
    has no such class, the simulator polls as it does."""
    try:
        from numba.cuda.simulator import kernel
    except ImportError:
        return

    thread = getattr(kernel, "BlockThread", None)
    if thread is None or getattr(thread, "_celtstone_calm", False):
        return
    alive = thread.is_alive

    def is_alive(self: Any) -> bool:
        self.join(POLL_WAIT)
        return alive(self)

    thread.is_alive = is_alive  # type: ignore[method-assign]
    thread._celtstone_calm = True  # type: ignore[attr-defined]


def _short_phase_log(sweep: Any, directory: Path) -> None:
    """``run_batch`` of the stick–slip points with a phase log of ``SHORT_PHASE_LOG``
    phases, on the CPU and on the (simulated) GPU, into ``max_phases.npz``."""
    import numpy as np

    from celtstone.solvers.batch import run_batch

    builder = sweep.builder
    indices = range(builder.n_points)
    params, y0 = builder.arrays(indices)
    settings = {
        "rtol": sweep.rtol,
        "atol": sweep.atol,
        "sample_times": sweep.sample_times,
        "reversal_bands": np.full(len(params), 0.05),
        # an array as the sweep passes (run_batch reads it back read-only): one compiled
        # batch loop for both; zero, the raw spin's reversals, which the sweep leaves out
        "reversal_windows": np.zeros(len(params)),
        "capture_speeds": builder.capture_speeds(indices),
        "max_phases": SHORT_PHASE_LOG,
        "stick_method_name": sweep.stick_method,
    }
    t_end = sweep.t_end
    model, method = int(builder.model.code), sweep.method
    results = {
        device: run_batch(model, method, params, y0, t_end, device=device, **settings)
        for device in ("cpu", "cuda")
    }
    np.savez(directory / "max_phases.npz", **results)


if __name__ == "__main__":
    if sys.argv[1:2] == [CALMED]:  # another script (the GPU benchmark) in the simulator
        import runpy

        calm_simulator()
        sys.argv = sys.argv[2:]
        runpy.run_path(sys.argv[0], run_name="__main__")
    else:
        sys.exit(main())
