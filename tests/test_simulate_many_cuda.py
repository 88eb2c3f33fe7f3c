"""``simulate_many(..., device="cuda")``: one GPU thread per run, each run ``simulate``'s.

No GPU is needed. numba's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``) runs the GPU
thread's Python with celtstone's kernels as their compiled CPU code, so the oracle is
``simulate`` itself on the CPU: every variable of each run's dataset must agree to the
last bit, and its attributes, status, message, stop time, smallest normal force, solver
counts, summary and warnings exactly, for runs of different bodies, settings, starts and
sample times in one launch (``tests/simulate_cuda_sample.py``, a process of its own, since
the simulator is chosen when numba is imported). On this machine, without a GPU, asking
for one is a one-line error, never a run on the CPU, and "auto" runs on the CPU.
"""

from __future__ import annotations

import pickle
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import celtstone as cs
from celtstone.errors import ParameterError
from celtstone.simulation.integrate import simulate_many
from tests.processes import sample_in_cuda_simulator

# the simulator's tests run on one worker, in turn: each process then loads the thread
# code that an earlier one compiled into numba's cache (``tests/test_sweep_cuda.py``)
pytestmark = pytest.mark.xdist_group("cuda_simulator")

SAMPLE = Path(__file__).resolve().parent / "simulate_cuda_sample.py"
# what each case of the sample covers, read from the CPU's runs before the GPU's are
# compared: each run's status (None: a run that cannot be made, kept in its place), and
# the phases of the stick–slip runs
COVERAGE = {
    "rolling": ["success", "success", None],
    "sliding": ["success", "success"],
    "sliding_ellipse_exact_dynamic": ["success", "success"],
    "stick_slip": ["success", "lift_off", "success"],
}
COMPARED = ("attrs", "status", "message", "t_stop", "min_normal_force", "statistics", "summary")


def _gpu_here() -> bool:
    """Whether this process sees a CUDA GPU (or the simulator)."""
    from celtstone.solvers.batch_cuda import cuda_unavailable_reason

    return cuda_unavailable_reason() is None


@pytest.mark.parametrize("case", list(COVERAGE))
def test_gpu_threads_give_simulates_runs_in_the_simulator(tmp_path: Path, case: str) -> None:
    sample_in_cuda_simulator(SAMPLE, str(tmp_path), case)
    report = pickle.loads((tmp_path / "runs.pickle").read_bytes())
    cpu, gpu = report["cpu"], report["gpu"]
    assert [run.get("status") for run in cpu] == COVERAGE[case]
    # one launch of every run that could be made, on the (simulated) GPU
    assert report["launched"] == [sum("error" not in run for run in cpu)]
    times = [run["variables"]["time"] for run in cpu if "error" not in run]
    assert len({float(t[0]) for t in times}) == len(times)  # each run its own times
    for expected, got in zip(cpu, gpu, strict=True):
        if "error" in expected:
            assert got["error"] == expected["error"]
            continue
        assert set(got["variables"]) == set(expected["variables"])
        for name, values in expected["variables"].items():
            np.testing.assert_array_equal(got["variables"][name], values, err_msg=name, strict=True)
        for key in COMPARED:
            assert _same(got[key], expected[key]), key
    # the warnings of every run, in order, as simulate warned them one by one
    assert report["gpu_warnings"] == [said for run in cpu for said in run["warnings"]]
    if case == "stick_slip":
        phases = [len(run["variables"]["phase_kind"]) for run in cpu]
        rejected = [run["attrs"]["rejected_captures"] for run in cpu]
        assert max(phases) >= 10 and max(rejected) >= 10, (phases, rejected)
    if case == "sliding":  # the static load's friction bound, warned for each run
        assert len(report["gpu_warnings"]) == 2
        assert all("FrictionBoundWarning" in said for said in report["gpu_warnings"])


def _same(got: Any, expected: Any) -> bool:
    """Equal, NaN equal to NaN (a summary's or an attribute's number)."""
    if isinstance(expected, dict):
        return set(got) == set(expected) and all(_same(got[k], expected[k]) for k in expected)
    if isinstance(expected, list | tuple):
        return len(got) == len(expected) and all(map(_same, got, expected))
    if isinstance(expected, float) and np.isnan(expected):
        return isinstance(got, float) and np.isnan(got)
    return bool(got == expected) and type(got) is type(expected)


def test_cuda_without_a_gpu_is_one_line() -> None:
    if _gpu_here():
        pytest.skip("a CUDA GPU is here: the runs would run on it")
    runs = [(cs.RollingModel(), cs.load_body("kane_levinson_1982"), cs.InitialState())]
    with pytest.raises(ParameterError) as refused:
        simulate_many(runs, 0.1, device="cuda")
    text = str(refused.value)
    assert "\n" not in text and text.startswith("device = 'cuda' is not allowed"), text
    assert "no CUDA GPU or driver found" in text


def test_auto_without_a_gpu_runs_on_the_cpu() -> None:
    if _gpu_here():
        pytest.skip("a CUDA GPU is here: auto takes it")
    body = cs.load_body("kane_levinson_1982")
    start = cs.InitialState()
    (made,) = simulate_many([(cs.RollingModel(), body, start)], 0.1, device="auto")
    expected = cs.simulate(cs.RollingModel(), body, start, 0.1)
    assert isinstance(made, cs.Trajectory)
    for name in expected.dataset.variables:
        np.testing.assert_array_equal(
            made.dataset[name].values, expected.dataset[name].values, err_msg=name, strict=True
        )


class _DeviceRows:
    """A stand-in for a device array of rows: sliced, its size read, copied to the host
    (the calls ``batch_cuda._filled_rows`` makes of numba's device arrays), counting the
    copies."""

    def __init__(self, values: np.ndarray, copies: list[int]) -> None:
        self.values, self.copies = values, copies
        self.size, self.dtype = values.size, values.dtype

    def __getitem__(self, key: Any) -> _DeviceRows:
        return _DeviceRows(self.values[key], self.copies)

    def copy_to_host(self) -> np.ndarray:
        self.copies.append(self.values.size)
        return self.values.copy()


@pytest.mark.parametrize(
    ("lengths", "copies"),
    [([3, 0, 1], [3, 1]), ([10, 9, 10], [30])],  # few filled: row by row; most: whole
)
def test_only_what_each_run_filled_comes_back_from_the_gpu(
    lengths: list[int], copies: list[int]
) -> None:
    from celtstone.solvers.batch_cuda import _filled_rows

    rows = np.arange(30.0).reshape(3, 10)
    made: list[int] = []
    got = _filled_rows(_DeviceRows(rows, made), np.array(lengths))
    assert made == copies
    for row, length, values in zip(rows, lengths, got, strict=True):
        np.testing.assert_array_equal(values, row[:length], strict=True)
