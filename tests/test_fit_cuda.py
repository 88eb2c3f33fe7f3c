"""A fit and the atlas's long runs on a CUDA GPU (``fit(device="cuda")``,
``compute_atlas(device="cuda")``), in numba's CUDA simulator.

No GPU is needed: the simulator runs the GPU thread's Python with celtstone's kernels as
their compiled CPU code, so the oracle is the CPU itself: the fit's values, standard
errors, cost, residuals and run counts, and each design's long-run numbers, must be the
CPU's to the last bit. The sample (``tests/fit_cuda_sample.py``) runs in a process of
its own, since the simulator is chosen when numba is imported. It skips where the
simulator is unavailable, and where ``simulate_many`` has no CUDA path yet (it then
refuses "cuda"), saying so.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.processes import sample_in_cuda_simulator

# one worker runs the simulator's tests in turn (tests/test_sweep_cuda.py)
pytestmark = pytest.mark.xdist_group("cuda_simulator")

SAMPLE = Path(__file__).resolve().parent / "fit_cuda_sample.py"


def test_a_fit_and_the_atlas_long_runs_on_the_gpu_are_the_cpus_in_the_simulator(
    tmp_path: Path,
) -> None:
    sample_in_cuda_simulator(SAMPLE, str(tmp_path))
    report = json.loads((tmp_path / "report.json").read_text())
    cpu, gpu = report["cpu"], report["cuda"]
    assert cpu["fit"]["device"] == "cpu"
    assert gpu["fit"]["device"] == "numba's CUDA simulator"
    # the same numbers to the last bit (JSON keeps a float's every bit); the GPU runs
    # every Jacobian column ahead of each residual where the CPU's two threads run one,
    # so it makes more runs (wasted at rejected steps), never fewer
    for name in ("values", "standard_errors", "cost", "residuals"):
        assert gpu["fit"][name] == cpu["fit"][name], name
    assert gpu["fit"]["runs"] >= cpu["fit"]["runs"] > 20  # the profiles were walked
    assert gpu["fit"]["failed_runs"] >= cpu["fit"]["failed_runs"]
    assert gpu["long_runs"] == cpu["long_runs"]
    reversals = [len(case["reversal_times"]) for n in cpu["long_runs"] for case in n["cases"]]
    assert max(reversals) > 0  # a run reverses: its times are compared too
