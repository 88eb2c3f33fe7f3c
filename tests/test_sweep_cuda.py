"""Sweeps on a CUDA GPU (``Sweep(device="cuda")``, ``celtstone sweep --device cuda``).

No GPU is needed. numba's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``) runs the GPU
thread's Python with celtstone's kernels as their compiled CPU code, so the oracle is
the CPU sweep itself: every result field must agree to the last bit and every count
exactly, the reversals and the spin's zero crossings (located inside each step on both)
included; for the stick–slip contact (the realistic contact: Hertz ellipse, exact law,
rolling resistance) also with a phase log too short for some points (``max_phases``).
The sample (``tests/sweep_cuda_sample.py``) runs in a process of its own,
since the simulator is chosen when numba is imported. On this machine, without a GPU,
asking for one is a one-line error (exit 2), never a run on the CPU.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from celtstone.cli.main import main
from celtstone.errors import ParameterError
from celtstone.sweep import Sweep, open_sweep
from tests.processes import sample_in_cuda_simulator

# one worker runs them in turn: each simulator process then loads the thread code that an
# earlier one compiled into numba's cache, where two at once would both compile it
pytestmark = pytest.mark.xdist_group("cuda_simulator")

SAMPLE = Path(__file__).resolve().parent / "sweep_cuda_sample.py"
CALMED = "--calmed"  # the sample's option that runs another script in the calmed simulator
# what each of the sample's sweeps covers, so that the comparison reads every branch of the
# loop and the reduction (from the CPU sweep, checked before the GPU's is compared):
# reversal counts, statuses; every sweep has spin crossing counts of 3 or more values,
# the largest at least 6 (how many depends on the method's steps where the spin chatters)
COVERAGE = {
    "rolling": ([0, 1, 1, 0, 0], ["success"] * 4 + ["lift_off"]),
    "sliding": ([0, 0, 1, 1, 0], ["success"] * 5),
    "sliding_exact_dynamic": ([0, 1, 0], ["success"] * 3),
    "stick_slip": ([0, 0, 0, 0, 0, 3], ["success"] * 6),
}
MAX_PHASES = "max_phases"  # the status of a stick–slip run whose phase log is full
# (sweep of the sample, method): every method on each model; the other sliding sweep takes
# the default method of a sliding sweep
RUNS = [
    ("rolling", "vern9"),
    ("rolling", "dop853"),
    ("sliding", "dop853"),
    ("sliding", "vern9"),
    ("sliding", "radau5"),
    ("sliding", "auto"),
    ("sliding_exact_dynamic", "auto"),
    ("stick_slip", "auto"),
]


def _gpu_here() -> bool:
    """Whether this process sees a CUDA GPU (or the simulator): then the refusals below
    do not happen."""
    from celtstone.solvers.batch_cuda import cuda_unavailable_reason

    return cuda_unavailable_reason() is None


@pytest.mark.parametrize(("sweep", "method"), RUNS)
def test_gpu_thread_gives_the_cpu_sweeps_fields_in_the_simulator(
    tmp_path: Path, sweep: str, method: str
) -> None:
    sample_in_cuda_simulator(SAMPLE, str(tmp_path), sweep, method)
    report = json.loads((tmp_path / "report.json").read_text())
    assert report["device"] == "cuda"
    cpu, gpu = open_sweep(tmp_path / "cpu.zarr"), open_sweep(tmp_path / "cuda.zarr")
    # the sample covers what the loop and the reduction read: reversals, crossings, and
    # (rolling) a lift-off
    reversals, statuses = COVERAGE[sweep]
    assert cpu["reversal_count"].values.tolist() == reversals
    crossings = set(cpu["spin_crossing_count"].values.tolist())
    assert len(crossings) >= 3 and max(crossings) >= 6, crossings
    assert cpu["status"].values.tolist() == statuses
    assert set(cpu.data_vars) == set(gpu.data_vars)
    for name in cpu.data_vars:
        expected, got = cpu[name].values, gpu[name].values
        if expected.dtype.kind == "f":  # to the last bit, NaN where the CPU has NaN
            np.testing.assert_array_equal(got, expected, err_msg=name, strict=True)
        else:
            assert got.tolist() == expected.tolist(), name
    assert gpu.attrs["device"] == "numba's CUDA simulator"
    assert gpu.attrs["sweep_spec"] == cpu.attrs["sweep_spec"]  # either device resumes it
    # Ctrl-C after the first block of three left that block alone; resuming added the others
    assert report["points_before_resume"] == 2
    workers, scheduler = report["refusals"]
    assert workers.startswith("workers = 2 is not allowed: expected no value with device cuda")
    assert scheduler.startswith("scheduler = 'tcp://127.0.0.1:1' is not allowed")
    if sweep == "stick_slip":
        _assert_same_with_a_short_phase_log(tmp_path)


def _assert_same_with_a_short_phase_log(directory: Path) -> None:
    """The stick–slip points with a phase log too short for three of them: the GPU's
    result array is the CPU's, bit for bit, those three stopped with ``max_phases``."""
    from celtstone.solvers.batch import COLUMN
    from celtstone.solvers.codes import status_label

    results = np.load(directory / "max_phases.npz")
    cpu, gpu = results["cpu"], results["cuda"]
    statuses = [status_label(int(code)) for code in cpu[:, COLUMN.status]]
    assert statuses.count(MAX_PHASES) == 3 and statuses.count("success") == 3, statuses
    np.testing.assert_array_equal(gpu, cpu, strict=True)


def test_cuda_without_a_gpu_is_one_line_and_exit_2(tmp_path: Path) -> None:
    if _gpu_here():
        pytest.skip("a CUDA GPU is here: the sweep would run on it")
    store = tmp_path / "sweep.zarr"
    argv = ["sweep", "--model", "rolling", "--vary", "initial_spin=-5,5", "--t-end", "0.1"]
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        status = main([*argv, "--device", "cuda", "--out", str(store), "--no-progress"])
    assert status == 2
    lines = err.getvalue().strip().splitlines()
    assert len(lines) == 1, lines
    assert "device = 'cuda' is not allowed" in lines[0]
    assert "numba.cuda.is_available() is False" in lines[0]
    assert not store.exists()  # refused before the store is made: no CPU run either
    with pytest.raises(ParameterError, match="no CUDA GPU"):
        Sweep({"initial_spin": [-5.0]}, model="rolling", device="cuda")


def test_auto_takes_the_cpu_where_the_gpu_cannot_run() -> None:
    if _gpu_here():
        pytest.skip("a CUDA GPU is here: auto takes it")
    for model in ("rolling", "sliding"):
        assert Sweep({"initial_spin": [-5.0]}, model=model, device="auto").device == "cpu"


@pytest.mark.parametrize("fixed", [{}, {"contact": "hybrid", "stick_method": "vern9"}])
def test_cuda_takes_the_stick_slip_contact(fixed: dict[str, str]) -> None:
    """A sliding sweep's default contact, stick–slip: only the missing GPU refuses it."""
    if _gpu_here():
        pytest.skip("a CUDA GPU is here: the sweep would run on it")
    stick_method = fixed.pop("stick_method", None) if fixed else None
    with pytest.raises(ParameterError, match="no CUDA GPU") as refused:
        Sweep(
            {"initial_spin": [-5.0]},
            model="sliding",
            fixed=fixed,
            stick_method=stick_method,
            device="cuda",
        )
    assert "not allowed" in str(refused.value) and "runs on the cpu" not in str(refused.value)


@pytest.mark.parametrize("method", ["vern9", "dop853", "radau5", "auto"])
def test_cuda_takes_every_method_of_the_sliding_model(method: str) -> None:
    """Only the missing GPU refuses these (where there is one, the sample above runs them)."""
    if _gpu_here():
        pytest.skip("a CUDA GPU is here: the sweep would run on it")
    with pytest.raises(ParameterError, match="no CUDA GPU") as refused:
        Sweep(
            {"initial_spin": [-5.0]},
            model="sliding",
            fixed={"contact": "sliding"},
            method=method,
            device="cuda",
        )
    assert "not allowed" in str(refused.value) and "runs on the cpu" not in str(refused.value)


def test_unknown_device_lists_the_devices() -> None:
    with pytest.raises(ParameterError, match="expected one of: cpu, cuda, auto"):
        Sweep({"initial_spin": [-5.0]}, model="rolling", device="gpu")


BENCHMARK = Path(__file__).resolve().parents[1] / "benchmarks" / "gpu_sweep.py"


def _benchmark(*arguments: str, simulator: bool = False) -> subprocess.CompletedProcess[str]:
    """The benchmark run with ``arguments``; with ``simulator``, in numba's CUDA simulator,
    started by the sample (``CALMED``: the simulator waits for its threads)."""
    environment = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    starter: list[str] = []
    if simulator:
        environment["NUMBA_ENABLE_CUDASIM"] = "1"
        starter = [str(SAMPLE), CALMED]
    return subprocess.run(
        [sys.executable, *starter, str(BENCHMARK), *arguments],
        env=environment,
        capture_output=True,
        text=True,
    )


@pytest.mark.parametrize(
    "sweep",
    # the benchmark's default rolling sweep; the sliding one over 3 s, not 10 s (each of its
    # stages runs the grid in the simulator), in which two of its four points reverse
    [(), ("--model", "sliding", "--method", "auto", "--t-end", "3")],
    ids=["rolling", "sliding"],
)
def test_benchmark_stages_run_and_agree_in_the_simulator(
    tmp_path: Path, sweep: tuple[str, ...]
) -> None:
    """The GPU benchmark's three stages, its GPU stage in the simulator: what a lent GPU
    runs in one call works, and its report compares the fields it should."""
    small = ("--grid", "2", "--large", "2", "--copies", "1")
    prepared = _benchmark("--prepare", str(tmp_path), *small, *sweep)
    assert prepared.returncode == 0, prepared.stderr
    if not _gpu_here():  # without a GPU the stage says so and writes nothing
        refused = _benchmark("--gpu", str(tmp_path))
        assert refused.returncode != 0
        assert "--gpu needs a CUDA GPU: no CUDA GPU or driver found" in refused.stderr
        assert sorted(p.name for p in tmp_path.iterdir()) == ["inputs.npz"]
    ran = _benchmark("--gpu", str(tmp_path), *small, simulator=True)
    if ran.returncode != 0 and "--gpu needs a CUDA GPU" in ran.stderr:
        pytest.skip(f"numba's CUDA simulator is unavailable: {ran.stderr.strip()}")
    assert ran.returncode == 0, ran.stderr
    again = _benchmark("--gpu", str(tmp_path), simulator=True)
    assert again.returncode != 0 and "pass --force" in again.stderr
    reported = _benchmark("--report", str(tmp_path))
    assert reported.returncode == 0, reported.stderr
    summary = json.loads(reported.stdout)
    assert summary["points"] == 4
    for count in ("status_agrees", "reversal_count_agree", "spin_crossing_count_agree"):
        assert summary[count] == 4, count
    # the simulator runs the CPU's code: equal to the last bit, the reversals' times too
    assert summary["differences"]["spin_final"]["max"] == 0.0
    assert summary["differences"]["first_reversal_time"]["max"] == 0.0  # not None: one reverses
    assert summary["gpu"]["device"] == "numba's CUDA simulator"
    assert summary["gpu"]["model"] == ("sliding" if sweep else "rolling")
