"""The GPU rolling sweep's thread loop (benchmarks/gpu_rolling_sweep.py) against the CPU sweep.

No GPU is needed: numba's CUDA simulator runs the kernel's Python with celtstone's
kernels as their compiled CPU code, so the loop must repeat the CPU driver's steps
exactly (final spins to the last bit, the same spin sign changes but for pairs of
crossings inside one step, which only the CPU's event location sees), with each of the
thread's methods. The CUDA build itself is checked only on a GPU machine
(docs/decisions.md §44).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "gpu_rolling_sweep.py"


def _script(*arguments: str, simulator: bool = False) -> subprocess.CompletedProcess[str]:
    """Run the benchmark with ``arguments``, in numba's CUDA simulator or without it."""
    environment = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    if simulator:
        environment["NUMBA_ENABLE_CUDASIM"] = "1"
    return subprocess.run(
        [sys.executable, str(SCRIPT), *arguments],
        env=environment,
        capture_output=True,
        text=True,
        timeout=600,
    )


def test_thread_loop_repeats_the_cpu_driver_in_the_simulator() -> None:
    done = _script("--check", simulator=True)
    assert done.returncode == 0, done.stdout + done.stderr
    summaries = {s["method"]: s for s in map(json.loads, done.stdout.strip().splitlines())}
    assert sorted(summaries) == ["dop853", "vern9"]  # both thread methods by default
    for summary in summaries.values():
        assert summary["points"] == 12
        assert summary["status_agrees"] == 12
        assert summary["max_final_spin_difference"] == 0.0
        assert summary["sign_changes"] > 0  # the runs reverse within 3 s: crossings compared
    assert summaries["dop853"]["sign_changes_agree"] == 12
    # Verner's longer steps carry one pair of crossings that only event location sees
    assert summaries["vern9"]["sign_changes_agree"] == 11
    assert summaries["vern9"]["sign_changes_short_by_pairs"] == 1


def test_methods_option_names_the_allowed_methods() -> None:
    done = _script("--check", "--methods", "vern9,rk4", simulator=True)
    assert done.returncode != 0
    assert "expected distinct names among vern9, dop853" in done.stderr


def test_check_refuses_to_run_without_the_simulator() -> None:
    done = _script("--check")
    assert done.returncode != 0
    assert "NUMBA_ENABLE_CUDASIM=1" in done.stderr


def test_stages_keep_earlier_output_and_name_the_missing_stage(tmp_path: Path) -> None:
    directory = tmp_path / "gpu"
    small = ("--grid", "2", "--large", "2")
    assert _script("--prepare", str(directory), *small).returncode == 0
    inputs = directory / "inputs.npz"
    written = inputs.read_bytes()
    again = _script("--prepare", str(directory), *small)
    assert again.returncode != 0
    assert "--force" in again.stderr
    assert inputs.read_bytes() == written  # not replaced
    assert _script("--prepare", str(directory), *small, "--force").returncode == 0
    missing = _script("--report", str(directory))
    assert missing.returncode != 0
    assert "gpu.npz does not exist: run --gpu" in missing.stderr
    assert sorted(p.name for p in directory.iterdir()) == ["inputs.npz"]  # no temporaries


def test_gpu_stage_without_a_gpu_says_so(tmp_path: Path) -> None:
    from numba import cuda

    if cuda.is_available():
        pytest.skip("a GPU is here: the stage would run")
    assert _script("--prepare", str(tmp_path), "--grid", "2", "--large", "2").returncode == 0
    done = _script("--gpu", str(tmp_path))
    assert done.returncode != 0
    assert "--gpu needs an NVIDIA GPU" in done.stderr
    assert not (tmp_path / "gpu.npz").exists()
