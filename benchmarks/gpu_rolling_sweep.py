"""A rolling sweep on a GPU: one CUDA thread per point, celtstone's own kernels in each.

Each thread integrates one initial state of the rolling model (paper eq. 3-5) with one
explicit method's step, ``solvers._vern9`` (Verner's 9(8) pair, the rolling model's
default) or ``solvers._dop853`` (``start`` and ``attempt``: trial steps and step-size
control), and the right-hand side ``kernels.system.rhs``, compiled by numba for CUDA
from the same Python source as the CPU kernels: no second copy of the equations or of
the method. Each stage runs every method of ``--methods`` (both by default), so that the
two can be compared on the same GPU in one call. The thread's loop repeats the CPU
driver's (``solvers.driver.integrate``): Hairer's first step
(``_step_control.initial_step``), then the method's attempts, with the same stopping
rules (a non-finite state, a failed right-hand side, lift-off N < 0, the step limit).
It keeps what a reversal sweep needs: the spin ω · n at ``t_end``, its sign changes at
step ends and the time of the first (linear between the step's ends), steps and
rejections. The CPU sweep counts crossings from its event location, which also finds two
crossings inside one step; the comparison reports such pairs apart from disagreements.

Three stages, so that only the middle one needs the GPU machine:

``--prepare DIR`` (any machine): a celtstone ``Sweep`` of the rolling model over initial
spin x Euler angle alpha on every core with each method, timed; its kernel inputs (one
parameter record, the initial states) and results go to ``DIR/inputs.npz``, with the
initial states of a larger grid (``--large``) made by the sweep's own ``build_state``.

``--gpu DIR`` (the GPU machine; numba with a CUDA target): compiles each method's
ensemble kernel, runs the small grid and the large one, writes ``DIR/gpu.npz`` and prints
the times.

``--report DIR`` (any machine): for each method, agreement of the GPU with the CPU sweep
of the same method on the small grid (final spin, sign changes, status) and points per
second of each; and the two methods' GPU results against each other.

Each stage writes its file whole or not at all and replaces an earlier one only with
``--force``.

``--check`` runs each method's thread loop on a few points in numba's CUDA simulator
(``NUMBA_ENABLE_CUDASIM=1``, no GPU: the kernels run as compiled CPU code) against the
CPU sweep with that method.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from numba import cuda, float64, int64

from celtstone.kernels.layout import N_STATE, RHS_OK, ModelCode
from celtstone.kernels.system import rhs
from celtstone.simulation.integrate import DEFAULT_ATOL, DEFAULT_RTOL
from celtstone.solvers import _dop853, _vern9
from celtstone.solvers._events import spin_of
from celtstone.solvers._step_control import initial_step
from celtstone.solvers._structures import Controls
from celtstone.solvers.codes import N_STATS, STAT_REJECTED, STATUS_SUCCESS
from celtstone.solvers.driver import all_finite

SPIN = (-8.0, 8.0)  # initial spin ω0 · n0 [rad/s]
ALPHA = (0.1, 5.0)  # initial Euler angle α [deg]; β stays at the default 0.5°
T_END = 10.0  # [s]
RTOL, ATOL = DEFAULT_RTOL, DEFAULT_ATOL  # ``simulate``'s: 1e-10, 1e-12
MAX_STEPS = 2_000_000
THREADS_PER_BLOCK = 64
# the thread's methods, by ``simulate``'s name: the module and the shape of its workspace's
# error array (DOP853 keeps its 5th- and 3rd-order estimates, Verner's pair one)
METHODS = {"vern9": (_vern9, N_STATE), "dop853": (_dop853, (2, N_STATE))}

# per-point status codes of the GPU loop
OK, RHS_FAILED, NOT_FINITE, LIFT_OFF, STEP_TOO_SMALL, MAX_STEPS_REACHED = range(6)
RESULT_COLUMNS = ("status", "steps", "rejected", "sign_changes", "first_change", "final_spin")
# numba-cuda 0.30.4 (the GPU machine's) overloads NumPy's row_stack, gone in NumPy 2.5, when
# it first compiles: the alias is given back then (by name: ruff's NumPy 2 fix rewrites it)
REMOVED_ALIAS = "row_stack"


def _cuda_declarations() -> None:
    """What numba's CUDA targets lack for celtstone's kernels (min/max of two numbers,
    ``np.nextafter``): the sweep backend's declarations (``solvers.batch_cuda``)."""
    from celtstone.solvers.batch_cuda import declare_for_cuda

    declare_for_cuda()


def point_loop(method: str) -> Any:
    """The thread's run with ``method`` (a key of ``METHODS``), as a Python function for
    ``cuda.jit(device=True)``: the method's functions and array shapes are its constants."""
    module, error_shape = METHODS[method]
    attempt, start, workspace = module.attempt, module.start, module.Workspace
    n_stages, dense_rows, error_order = (
        module.N_STAGES_EXTENDED,
        module.DENSE_ROWS,
        module.ERROR_ORDER,
    )

    def integrate_point(model, record, y0s, point, t_end, rtol, atol, max_steps, finals, results):
        """One thread's run from ``y0s[point]``; writes ``finals[point]`` and ``results[point]``
        (``RESULT_COLUMNS``). The CPU driver's loop, without samples and events."""
        y = cuda.local.array(N_STATE, float64)
        f = cuda.local.array(N_STATE, float64)
        y_new = cuda.local.array(N_STATE, float64)
        f_new = cuda.local.array(N_STATE, float64)
        scratch = cuda.local.array(N_STATE, float64)
        stages = cuda.local.array((n_stages, N_STATE), float64)
        dense = cuda.local.array((dense_rows, N_STATE), float64)
        error_terms = cuda.local.array(error_shape, float64)
        stats = cuda.local.array(N_STATS, int64)
        for j in range(N_STATE):
            y[j] = y0s[point, j]
        for j in range(N_STATS):
            stats[j] = 0
        work = workspace(stages, dense, scratch, error_terms)
        controls = Controls(rtol, atol, 0.0, 0.0, max_steps, True)
        code, normal_force = rhs(model, 0.0, y, record, f)
        status = OK
        if code != RHS_OK:
            status = RHS_FAILED
        elif normal_force < 0.0:
            status = LIFT_OFF
        h = initial_step(model, record, y, f, error_order, rtol, atol, scratch, f_new)
        start(model, record, 0.0, y, f, controls, work, stats)
        spin = spin_of(y)
        t = 0.0
        steps = 0
        sign_changes = 0
        first_change = math.nan
        while status == OK and t < t_end:
            if steps >= max_steps:
                status = MAX_STEPS_REACHED
                break
            steps += 1
            step_status, h_taken, h_next, code, normal_force = attempt(
                model, record, t, y, f, h, t_end, controls, work, y_new, f_new, stats
            )
            if step_status != STATUS_SUCCESS:
                status = STEP_TOO_SMALL
                break
            if not all_finite(y_new):
                status = NOT_FINITE
                break
            if code != RHS_OK:
                status = RHS_FAILED
                break
            if normal_force < 0.0:
                status = LIFT_OFF
                break
            t_new = t_end if h_taken == t_end - t else t + h_taken
            spin_new = spin_of(y_new)
            if (spin_new > 0.0) != (spin > 0.0):
                if sign_changes == 0:
                    first_change = t + h_taken * spin / (spin - spin_new)
                sign_changes += 1
            for j in range(N_STATE):
                y[j] = y_new[j]
                f[j] = f_new[j]
            spin = spin_new
            t = t_new
            h = h_next
        for j in range(N_STATE):
            finals[point, j] = y[j]
        results[point, 0] = status
        results[point, 1] = steps
        results[point, 2] = stats[STAT_REJECTED]
        results[point, 3] = sign_changes
        results[point, 4] = first_change
        results[point, 5] = spin if status == OK else math.nan

    return integrate_point


def ensemble_kernel(method: str) -> Any:
    """The CUDA kernel of ``method``: thread i integrates point i (compiled at its first
    launch)."""
    _cuda_declarations()
    if not hasattr(np, REMOVED_ALIAS):
        setattr(np, REMOVED_ALIAS, np.vstack)
    thread = cuda.jit(device=True)(point_loop(method))
    rolling = int(ModelCode.ROLLING)  # a constant: the other models' branches are dropped

    @cuda.jit
    def ensemble(params, y0s, t_end, rtol, atol, max_steps, finals, results):
        point = cuda.grid(1)
        if point < y0s.shape[0]:
            thread(rolling, params[0], y0s, point, t_end, rtol, atol, max_steps, finals, results)

    return ensemble


def run_ensemble(kernel, params, y0s, t_end, rtol=RTOL, atol=ATOL, threads=THREADS_PER_BLOCK):
    """Launch ``kernel`` over the rows of ``y0s``, ``threads`` to a block; (final states,
    results, seconds of the launch and copies, synchronised)."""
    count = y0s.shape[0]
    start = time.perf_counter()
    device_y0 = cuda.to_device(np.ascontiguousarray(y0s))
    device_params = cuda.to_device(params)
    finals = cuda.device_array((count, N_STATE))
    results = cuda.device_array((count, len(RESULT_COLUMNS)))
    blocks = (count + threads - 1) // threads
    kernel[blocks, threads](device_params, device_y0, t_end, rtol, atol, MAX_STEPS, finals, results)
    cuda.synchronize()
    finals_host, results_host = finals.copy_to_host(), results.copy_to_host()
    return finals_host, results_host, time.perf_counter() - start


# ---------------------------------------------------------------- the CPU side


def grid_values(n_spin: int, n_alpha: int) -> tuple[np.ndarray, np.ndarray]:
    return np.linspace(*SPIN, n_spin), np.linspace(*ALPHA, n_alpha)


def cpu_sweep(n_spin: int, n_alpha: int, t_end: float, method: str, workers: int | None = None):
    """celtstone's Sweep on the grid with ``method``, timed; (results Dataset, params, y0s,
    seconds)."""
    from celtstone.solvers import batch
    from celtstone.sweep import Sweep

    spins, alphas = grid_values(n_spin, n_alpha)
    captured: list[tuple[np.ndarray, np.ndarray]] = []
    original = batch.run_batch

    def capturing(model, method, params, y0, *args, **kwargs):
        captured.append((np.array(params), np.array(y0)))
        return original(model, method, params, y0, *args, **kwargs)

    sweep = Sweep(
        {"initial_spin": spins, "euler_alpha": alphas},
        model="rolling",
        t_end=t_end,
        rtol=RTOL,
        atol=ATOL,
        method=method,
    )
    Sweep({"initial_spin": [-5.0]}, model="rolling", t_end=0.01, method=method).run()
    batch.run_batch = capturing
    try:
        start = time.perf_counter()
        results = sweep.run(workers=workers)
        seconds = time.perf_counter() - start
    finally:
        batch.run_batch = original
    params = np.concatenate([p for p, _ in captured])
    y0s = np.concatenate([y for _, y in captured])
    return results, params, y0s, seconds


def initial_states(n_spin: int, n_alpha: int) -> np.ndarray:
    """Initial states of the grid in the sweep's order (spin outer), by the sweep's own
    ``build_state``."""
    from celtstone.sweep.spec import build_state, initial_vector

    spins, alphas = grid_values(n_spin, n_alpha)
    rows = [
        initial_vector(build_state({"initial_spin": float(s), "euler_alpha": float(a)}))
        for s in spins
        for a in alphas
    ]
    return np.array(rows)


def save_whole(path: Path, force: bool, option: str, **arrays: object) -> None:
    """``np.savez`` to ``path`` through celtstone's atomic writer: whole or not at all, and
    an existing file only replaced with ``force``."""
    from celtstone.files.export import atomic_path

    with atomic_path(path, overwrite=force, parameter=option) as temporary:
        with open(temporary, "wb") as handle:
            np.savez(handle, **arrays)  # type: ignore[arg-type]


def load(path: Path, stage: str) -> Any:
    """The arrays of ``path``, or a message naming the stage that makes it."""
    if not path.is_file():
        raise SystemExit(f"{path} does not exist: run {stage} {path.parent} first")
    return np.load(path)


def prepare(directory: Path, n: int, large: int, methods: list[str], force: bool) -> None:
    directory.mkdir(parents=True, exist_ok=True)
    if (directory / "inputs.npz").exists() and not force:  # before the sweep's minutes
        raise SystemExit(f"{directory / 'inputs.npz'} exists: pass --force to replace it")
    mine = initial_states(n, n)
    arrays: dict[str, object] = {}
    summary: dict[str, object] = {"points": int(mine.shape[0])}
    for method in methods:
        results, params, y0s, seconds = cpu_sweep(n, n, T_END, method)
        if not all(params[k].tobytes() == params[0].tobytes() for k in range(len(params))):
            raise SystemExit("the grid's parameter records differ: this script assumes one body")
        if "y0s" in arrays and not np.array_equal(arrays["y0s"], y0s):
            raise SystemExit(f"the {method} sweep's initial states differ from the first's")
        arrays.update(params=params[:1], y0s=y0s)
        arrays[f"cpu_final_spin_{method}"] = np.asarray(results["spin_final"]).ravel()
        arrays[f"cpu_raw_sign_changes_{method}"] = np.asarray(
            results["spin_crossing_count"]
        ).ravel()
        arrays[f"cpu_status_{method}"] = np.asarray(results["status"]).ravel().astype(str)
        arrays[f"cpu_seconds_{method}"] = seconds
        summary[f"cpu_seconds_{method}"] = round(seconds, 2)
        summary["max |own y0 - sweep y0|"] = float(np.abs(mine - y0s).max())
    large_y0s = initial_states(large, large)
    save_whole(
        directory / "inputs.npz",
        force,
        "--prepare",
        large_y0s=large_y0s,
        methods=np.array(methods),
        cpu_cores=len(os.sched_getaffinity(0)),
        cpu_machine=platform.processor() or platform.machine(),
        t_end=T_END,
        **arrays,
    )
    summary.update(cores=len(os.sched_getaffinity(0)), large_points=int(large_y0s.shape[0]))
    print(json.dumps(summary))


def gpu_figures(method: str, params, y0s, large_y0s, t_end: float, copies: int):
    """Compile ``method``'s kernel and time it on the small grid (twice), the large one
    (at four block sizes too) and the large one tiled ``copies`` times; (figures, small
    grid's finals and results, large grid's results)."""
    kernel = ensemble_kernel(method)
    start = time.perf_counter()
    run_ensemble(kernel, params, y0s[:1], 0.01)  # compiles
    compile_s = time.perf_counter() - start
    small = run_ensemble(kernel, params, y0s, t_end)
    small_again = run_ensemble(kernel, params, y0s, t_end)
    large = run_ensemble(kernel, params, large_y0s, t_end)
    by_block = {
        threads: round(run_ensemble(kernel, params, large_y0s, t_end, threads=threads)[2], 3)
        for threads in (32, 64, 128, 256)
    }
    # the large grid's states repeated: throughput once the GPU is full
    tiled = np.tile(large_y0s, (copies, 1))
    tiled_s = run_ensemble(kernel, params, tiled, t_end)[2]
    figures = {
        "compile_s": round(compile_s, 2),
        "small_points": int(y0s.shape[0]),
        "small_s": [round(small[2], 3), round(small_again[2], 3)],
        "large_points": int(large_y0s.shape[0]),
        "large_s": round(large[2], 3),
        "large_s_by_threads_per_block": by_block,
        "tiled_points": int(tiled.shape[0]),
        "tiled_s": round(tiled_s, 3),
        "small_steps_max": int(small[1][:, 1].max()),
        "large_steps_median": float(np.median(large[1][:, 1])),
        "large_steps_max": int(large[1][:, 1].max()),
    }
    return figures, small[0], small[1], large[1]


def gpu(directory: Path, copies: int, force: bool) -> None:
    data = load(directory / "inputs.npz", "--prepare")
    if (directory / "gpu.npz").exists() and not force:
        raise SystemExit(f"{directory / 'gpu.npz'} exists: pass --force to replace it")
    if not cuda.is_available():
        raise SystemExit(
            "--gpu needs an NVIDIA GPU and numba's CUDA target (numba.cuda.is_available() "
            "is False here); --check runs the thread loop in the simulator instead"
        )
    params, t_end = data["params"], float(data["t_end"])
    print("numba", __import__("numba").__version__, "device", cuda.get_current_device().name)
    arrays: dict[str, object] = {}
    figures = {}
    for method in [str(m) for m in data["methods"]]:
        figures[method], finals, small, large = gpu_figures(
            method, params, data["y0s"], data["large_y0s"], t_end, copies
        )
        print(json.dumps({method: figures[method]}), flush=True)
        arrays[f"small_finals_{method}"] = finals
        arrays[f"small_results_{method}"] = small
        arrays[f"large_results_{method}"] = large
    save_whole(directory / "gpu.npz", force, "--gpu", figures=json.dumps(figures), **arrays)


def compare(cpu_spin, cpu_changes, results) -> dict:
    """Agreement of GPU ``results`` with the CPU sweep's final spin and sign changes."""
    ok = results[:, 0] == OK
    finite = np.isfinite(cpu_spin)
    both = ok & finite
    difference = np.abs(results[both, 5] - cpu_spin[both])
    missed = cpu_changes[both] - results[both, 3]  # crossings step ends cannot see
    return {
        "points": len(results),
        "gpu_ok": int(ok.sum()),
        "cpu_finished": int(finite.sum()),
        "status_agrees": int((ok == finite).sum()),
        "max_final_spin_difference": float(difference.max()) if difference.size else None,
        "median_final_spin_difference": float(np.median(difference)) if difference.size else None,
        "sign_changes_agree": int((missed == 0).sum()),
        # the CPU's event location found pairs of crossings inside one of the thread's steps
        "sign_changes_short_by_pairs": int(((missed > 0) & (missed % 2 == 0)).sum()),
        "reversed_agrees": int(((results[both, 3] > 0) == (cpu_changes[both] > 0)).sum()),
    }


def report(directory: Path) -> None:
    data = load(directory / "inputs.npz", "--prepare")
    out = load(directory / "gpu.npz", "--gpu")
    figures = json.loads(str(out["figures"]))
    methods = [str(m) for m in data["methods"]]
    summary: dict[str, Any] = {"cpu_cores": int(data["cpu_cores"])}
    for method in methods:
        method_figures = figures[method]
        cpu_seconds = float(data[f"cpu_seconds_{method}"])
        summary[method] = compare(
            data[f"cpu_final_spin_{method}"],
            data[f"cpu_raw_sign_changes_{method}"],
            out[f"small_results_{method}"],
        )
        summary[method].update(
            {
                "cpu_seconds": cpu_seconds,
                "cpu_points_per_s": method_figures["small_points"] / cpu_seconds,
                "gpu_small_points_per_s": method_figures["small_points"]
                / min(method_figures["small_s"]),
                "gpu_large_points_per_s": method_figures["large_points"]
                / method_figures["large_s"],
                "gpu_tiled_points_per_s": method_figures["tiled_points"]
                / method_figures["tiled_s"],
                "gpu": method_figures,
            }
        )
    if len(methods) == 2:  # the two methods' GPU runs against each other, large grid
        first, second = (out[f"large_results_{m}"] for m in methods)
        both = (first[:, 0] == OK) & (second[:, 0] == OK)
        summary[f"{methods[0]}_vs_{methods[1]}_gpu_large"] = {
            "both_ok": int(both.sum()),
            "max_final_spin_difference": float(np.abs(first[both, 5] - second[both, 5]).max()),
            "reversed_agrees": int(((first[both, 3] > 0) == (second[both, 3] > 0)).sum()),
            "steps_ratio_median": float(np.median(second[both, 1] / first[both, 1])),
        }
    print(json.dumps(summary, indent=1))


def check(methods: list[str], points: int = 6, t_end: float = 3.0) -> None:
    """Each method's thread loop in numba's CUDA simulator against the CPU sweep with
    that method on a few points: the simulator runs the kernels as the same compiled CPU
    code, so the final spins must agree to the last bit and the sign changes exactly, but
    for pairs of crossings inside one step, which the CPU's event location finds and the
    thread's step ends cannot."""
    if os.environ.get("NUMBA_ENABLE_CUDASIM") != "1":
        raise SystemExit("--check needs NUMBA_ENABLE_CUDASIM=1 in the environment")
    for method in methods:
        results, params, y0s, _ = cpu_sweep(points, 2, t_end, method, workers=1)
        kernel = ensemble_kernel(method)
        _, gpu_results, _ = run_ensemble(kernel, params[:1], y0s, t_end)
        summary = compare(
            np.asarray(results["spin_final"]).ravel(),
            np.asarray(results["spin_crossing_count"]).ravel(),
            gpu_results,
        )
        summary.update(method=method, sign_changes=int(gpu_results[:, 3].sum()))
        print(json.dumps(summary))
        agrees = (
            summary["status_agrees"] == len(y0s)
            and summary["sign_changes_agree"] + summary["sign_changes_short_by_pairs"] == len(y0s)
            and summary["max_final_spin_difference"] == 0.0
        )
        if not agrees:
            raise SystemExit(f"the simulated GPU loop with {method} disagrees with the CPU sweep")


def method_list(text: str) -> list[str]:
    """``--methods``: names of ``METHODS``, comma-separated, each once."""
    names = [name.strip() for name in text.split(",") if name.strip()]
    unknown = [name for name in names if name not in METHODS]
    if unknown or not names or len(set(names)) != len(names):
        raise argparse.ArgumentTypeError(
            f"expected distinct names among {', '.join(METHODS)}, comma-separated, not {text!r}"
        )
    return names


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--prepare", type=Path)
    parser.add_argument("--gpu", type=Path)
    parser.add_argument("--report", type=Path)
    parser.add_argument("--check", action="store_true")
    parser.add_argument(
        "--methods",
        type=method_list,
        default=list(METHODS),
        help="the threads' methods for --prepare and --check (--gpu runs those of "
        "--prepare): vern9, dop853 or both (default)",
    )
    parser.add_argument("--grid", type=int, default=64, help="points per axis, CPU and GPU")
    parser.add_argument("--large", type=int, default=256, help="points per axis, GPU only")
    parser.add_argument(
        "--copies", type=int, default=4, help="the large grid repeated, for throughput"
    )
    parser.add_argument("--force", action="store_true", help="replace DIR's earlier output")
    args = parser.parse_args()
    for name in ("grid", "large", "copies"):
        if getattr(args, name) < 1:
            parser.error(f"--{name} must be a whole number >= 1, not {getattr(args, name)}")
    if args.prepare:
        prepare(args.prepare, args.grid, args.large, args.methods, args.force)
    if args.gpu:
        gpu(args.gpu, args.copies, args.force)
    if args.report:
        report(args.report)
    if args.check:
        check(args.methods)


if __name__ == "__main__":
    from celtstone.errors import CeltstoneError

    try:
        main()
    except CeltstoneError as error:  # the atomic writer's refusals and write failures
        raise SystemExit(f"gpu_rolling_sweep: {error}") from None
