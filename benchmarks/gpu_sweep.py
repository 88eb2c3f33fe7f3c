"""The GPU sweep backend (``Sweep(device="cuda")``) timed on a GPU and checked against the CPU.

One CUDA thread per point runs ``solvers.batch.run_batch`` with ``device="cuda"``: the
CPU driver's loop and reduction compiled for CUDA. The stages, so that only one needs the GPU
machine and it fits one short call there:

``--prepare DIR`` (any machine): the CPU sweep of ``--model`` (rolling by default)
over initial spin × Euler angle α (``--grid`` points per axis, ``--t-end`` 10 s), timed on every
core; its kernel inputs, its result fields and the initial states of a larger grid
(``--large``) go to ``DIR/inputs.npz``.

``--gpu DIR`` (the GPU machine: numba with a CUDA target, NumPy): the first launch in
this process (the kernel compiled, or loaded from numba's cache), the first launch in a
second process (what the cache saves), the small grid twice, the large grid, and the
large grid tiled ``--copies`` times; ``DIR/gpu.npz`` holds the small grid's fields and
``DIR/gpu.json`` the times. Where ``celtstone.sweep`` imports (zarr), the whole
``Sweep(device="cuda").run()`` of the small grid is timed too.

``--report DIR`` (any machine): the GPU's fields against the CPU's on the small grid
(status, reversal yes/no and counts, spin sign changes exactly; final spin and the other
numbers by their largest difference) and points per second; ``DIR/report.json``.

``--ptx DIR`` (a machine without a GPU, with numba-cuda and NVIDIA's NVVM, e.g.
``pip install numba-cuda[cu12]``): compiles the kernel of ``--model`` and ``--method``
to PTX for compute capability 9.0 and, where ``ptxas`` is found, assembles it and keeps
its report of registers, stack and spills: the CUDA build checked without a GPU.

One call on a lent GPU, the inputs prepared here and carried with the working tree:
``python benchmarks/gpu_sweep.py --gpu DIR && python benchmarks/gpu_sweep.py --report DIR``
(about 2 to 4 minutes, most of it the first compile). Every file is written whole or
not at all, and replaced only with ``--force``.

``--model sliding`` times the sliding model instead (the Padé law on the disk, the
default regularisation δ, no stick phases: ``--set contact=sliding``), with ``--method``
any of the four; the issue's row is 64 × 64 points of 10 s with the sliding default,
``auto``. Prepared here with a CPU grid the 2-core machine computes in a minute or two,
the 64 × 64 grid on the GPU alone:
``--prepare DIR --model sliding --method auto --grid 12 --large 64 --copies 4``
(the GPU stage's first compile is longer than the rolling model's: Radau's Newton
iteration and LU on the thread).

``--model stick_slip`` times the stick–slip contact (a sliding sweep's default) with the
realistic contact (the Hertz ellipse of E = 3 GPa, ν = 0.35, the exact law, the dynamic
load, rolling resistance 10 µm: ``reproduce.study.REALISTIC_CONTACT``), slip with
``--method`` (the issue's row: ``auto``), stick with DOP853; each thread runs the CPU's
phase loop with a phase log of its own. The issue's row is 64 × 64 points of 10 s:
``--prepare DIR --model stick_slip --method auto --grid 12 --large 64 --copies 4``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

SPIN = (-8.0, 8.0)  # initial spin ω0 · n0 [rad/s]
ALPHA = (0.1, 5.0)  # initial Euler angle α [deg]; β stays at the default 0.5°
T_END = 10.0  # [s] the default of --t-end
COMPUTE_CAPABILITY = (9, 0)  # H100, H200: the --ptx stage's target
# the realistic contact (``reproduce.study.REALISTIC_CONTACT``, here to keep this script's
# imports to the sweep)
REALISTIC: dict[str, str | float] = {
    "contact": "hybrid",
    "contact_shape": "ellipse",
    "elastic_modulus": 3e9,  # Pa
    "poisson_ratio": 0.35,
    "friction_law": "exact",
    "rolling_resistance": 1e-5,  # m
    "friction_load": "dynamic",
}
# the sweeps this script times, by --model: the sweep's model and its fixed settings
MODELS: dict[str, tuple[str, dict[str, str | float]]] = {
    "rolling": ("rolling", {}),
    "sliding": ("sliding", {"contact": "sliding"}),
    "stick_slip": ("sliding", REALISTIC),
}


def _write_whole(path: Path, force: bool, data: bytes) -> None:
    """``data`` to ``path`` through a temporary beside it; an existing file only with
    ``force``."""
    if path.exists() and not force:
        raise SystemExit(f"{path} exists: pass --force to replace it")
    temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        temporary.write_bytes(data)
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)


def _save_npz(path: Path, force: bool, **arrays: Any) -> None:
    import io

    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    _write_whole(path, force, buffer.getvalue())


def _load(path: Path, stage: str) -> Any:
    if not path.is_file():
        raise SystemExit(f"{path} does not exist: run {stage} {path.parent} first")
    return np.load(path, allow_pickle=False)


def _parameter_records(values: np.ndarray) -> np.ndarray:
    """``values`` (parameter records read back from ``inputs.npz``) with the kernels' own
    dtype, ``kernels.layout.PARAMETERS``: ``np.load`` returns the same fields and offsets
    without the aligned-struct flag, and numba compiles a record type that differs in that
    flag alone as a kernel of its own, which ``Sweep(device="cuda")`` would not share."""
    from celtstone.kernels.layout import PARAMETERS

    if values.dtype != PARAMETERS:
        raise SystemExit("inputs.npz holds other parameter records: run --prepare again")
    return values.view(PARAMETERS)


def _grid(n: int) -> dict[str, np.ndarray]:
    return {"initial_spin": np.linspace(*SPIN, n), "euler_alpha": np.linspace(*ALPHA, n)}


def _sweep(n: int, method: str, model: str, device: str = "cpu", t_end: float = T_END) -> Any:
    """The benchmark's sweep of ``model``: "rolling", "sliding" on its own (the Padé
    law on the disk with the default regularisation δ, no stick phases), or
    "stick_slip" (the realistic contact)."""
    from celtstone.sweep import Sweep

    name, fixed = MODELS[model]
    return Sweep(_grid(n), model=name, t_end=t_end, method=method, device=device, fixed=fixed)


def _kernel_inputs(sweep: Any) -> dict[str, Any]:
    """What ``run_batch`` takes for every point of ``sweep``."""
    from celtstone.kernels.layout import Y_N, Y_OMEGA
    from celtstone.simulation.reversals import reversal_bands

    points = range(sweep.size)
    params, states = sweep.builder.arrays(points)
    spin = np.einsum("ij,ij->i", states[:, Y_OMEGA : Y_OMEGA + 3], states[:, Y_N : Y_N + 3])
    captures = sweep.builder.capture_speeds(points) if sweep.is_hybrid else np.zeros(len(params))
    return {
        "params": params,
        "y0": states,
        "reversal_bands": reversal_bands(spin),
        "reversal_windows": sweep.builder.rocking_periods(points),
        "capture_speeds": captures,  # 0: no stick phases
    }


def prepare(
    directory: Path, n: int, large: int, method: str, model: str, t_end: float, force: bool
) -> None:
    directory.mkdir(parents=True, exist_ok=True)
    if (directory / "inputs.npz").exists() and not force:  # before the sweep's minutes
        raise SystemExit(f"{directory / 'inputs.npz'} exists: pass --force to replace it")
    sweep = _sweep(n, method, model, t_end=t_end)
    _sweep(1, method, model, t_end=t_end).run()  # compiled before the timing
    start = time.perf_counter()
    results = sweep.run()
    seconds = time.perf_counter() - start
    inputs = _kernel_inputs(sweep)
    big = _kernel_inputs(_sweep(large, method, model, t_end=t_end))
    records = big["params"]
    if not all(records[k].tobytes() == records[0].tobytes() for k in range(len(records))):
        raise SystemExit("the large grid's parameter records differ: this script keeps one")
    big["params"] = records[:1]  # 2.4 kB, not 155 MB for 256 x 256 points
    fields = {f"cpu_{name}": results[name].values.ravel() for name in results.data_vars}
    _save_npz(
        directory / "inputs.npz",
        force,
        **inputs,
        **{f"large_{k}": v for k, v in big.items()},
        **{k: v.astype(str) if v.dtype == object else v for k, v in fields.items()},
        model=int(sweep.builder.model.code),
        model_name=model,
        method=method,
        stick_method=sweep.stick_method,
        grid=n,
        t_end=sweep.t_end,
        rtol=sweep.rtol,
        atol=sweep.atol,
        max_steps=sweep.max_steps,
        sample_times=sweep.sample_times,
        cpu_seconds=seconds,
        cpu_cores=len(os.sched_getaffinity(0)),
        cpu_machine=platform.processor() or platform.machine(),
    )
    print(
        json.dumps(
            {
                "model": model,
                "points": sweep.size,
                "cpu_seconds": round(seconds, 2),
                "method": method,
            }
        )
    )


def _run(data: Any, prefix: str = "", copies: int = 1) -> tuple[np.ndarray, float]:
    """The points of ``data`` (``prefix`` "large_" for the large grid, tiled ``copies``
    times) on the GPU, in launches that fit its memory; (results, seconds)."""
    from celtstone.solvers.batch import run_batch
    from celtstone.solvers.batch_cuda import KEPT_CROSSINGS, launch_points
    from celtstone.solvers.codes import DEFAULT_MAX_PHASES

    def tiled(name: str) -> np.ndarray:
        values = data[prefix + name]
        return np.tile(values, (copies,) + (1,) * (values.ndim - 1))

    y0 = tiled("y0")
    # the large grid keeps its one body's record
    params = _parameter_records(np.resize(tiled("params"), len(y0)))
    bands, windows = tiled("reversal_bands"), tiled("reversal_windows")
    captures = tiled("capture_speeds")
    is_hybrid = bool(np.any(captures > 0.0))
    samples = data["sample_times"]
    capacity = KEPT_CROSSINGS if np.any(windows <= 0.0) else 1
    size = launch_points(len(samples), capacity, DEFAULT_MAX_PHASES if is_hybrid else 0)
    start = time.perf_counter()
    parts = []
    for first in range(0, len(params), size):
        part = slice(first, first + size)
        parts.append(
            run_batch(
                int(data["model"]),
                str(data["method"]),
                params[part],
                y0[part],
                float(data["t_end"]),
                rtol=float(data["rtol"]),
                atol=float(data["atol"]),
                sample_times=samples,
                reversal_bands=bands[part],
                reversal_windows=windows[part],
                max_steps=int(data["max_steps"]),
                capture_speeds=captures[part] if is_hybrid else None,
                stick_method_name=str(data["stick_method"]),
                device="cuda",
            )
        )
    return np.concatenate(parts), time.perf_counter() - start


def _first_launch(directory: Path) -> float:
    """Seconds of one point's first launch in this process: compiling the kernel, or
    loading it from numba's cache."""
    data = _load(directory / "inputs.npz", "--prepare")
    per_point = ("params", "y0", "reversal_bands", "reversal_windows", "capture_speeds")
    one = {k: data[k][:1] for k in per_point}
    one.update(
        {k: data[k] for k in ("model", "method", "stick_method", "rtol", "atol", "max_steps")}
    )
    one.update(t_end=0.01, sample_times=np.array([0.0, 0.01]))
    return _run(one)[1]


def gpu(directory: Path, copies: int, force: bool) -> None:
    from celtstone.solvers.batch import FIELDS
    from celtstone.solvers.batch_cuda import cuda_unavailable_reason, device_name

    data = _load(directory / "inputs.npz", "--prepare")
    for name in ("gpu.npz", "gpu.json"):
        if (directory / name).exists() and not force:
            raise SystemExit(f"{directory / name} exists: pass --force to replace it")
    reason = cuda_unavailable_reason()
    if reason is not None:
        raise SystemExit(f"--gpu needs a CUDA GPU: {reason}")
    figures: dict[str, Any] = {
        "device": device_name(),
        "model": str(data["model_name"]),
        "method": str(data["method"]),
    }
    import numba

    figures["numba"] = numba.__version__
    print(json.dumps(figures), flush=True)
    figures["first_launch_s"] = round(_first_launch(directory), 2)
    print(json.dumps({"first_launch_s": figures["first_launch_s"]}), flush=True)
    probe = subprocess.run(
        [sys.executable, __file__, "--first-launch", str(directory)],
        capture_output=True,
        text=True,
    )
    figures["second_process_first_launch_s"] = (
        float(probe.stdout.strip().splitlines()[-1])
        if probe.returncode == 0
        else f"failed: {probe.stderr.strip()[-400:]}"
    )
    small, small_s = _run(data)
    figures["small_points"] = len(small)
    figures["small_s"] = [round(small_s, 3), round(_run(data)[1], 3)]
    large, large_s = _run(data, "large_")
    figures.update(large_points=len(large), large_s=round(large_s, 3))
    tiled, tiled_s = _run(data, "large_", copies)
    figures.update(tiled_points=len(tiled), tiled_s=round(tiled_s, 3))
    status = large[:, FIELDS.index("status")]
    figures["large_statuses"] = {str(int(c)): int((status == c).sum()) for c in np.unique(status)}
    try:  # the whole backend: Sweep(device="cuda"), where celtstone.sweep imports here
        sweep = _sweep(
            int(data["grid"]),
            str(data["method"]),
            str(data["model_name"]),
            device="cuda",
            t_end=float(data["t_end"]),
        )
        start = time.perf_counter()
        sweep.run()
        figures["sweep_run_small_s"] = round(time.perf_counter() - start, 3)
    except ImportError as error:
        figures["sweep_run_small_s"] = f"not run: {error}"
    print(json.dumps(figures), flush=True)
    _save_npz(directory / "gpu.npz", force, small=small, fields=np.array(FIELDS))
    _write_whole(directory / "gpu.json", force, json.dumps(figures, indent=1).encode())


def report(directory: Path, force: bool) -> None:
    data = _load(directory / "inputs.npz", "--prepare")
    out = _load(directory / "gpu.npz", "--gpu")
    figures = json.loads((directory / "gpu.json").read_text())
    from celtstone.solvers import status_label

    fields = [str(f) for f in out["fields"]]
    small = out["small"]

    def gpu_field(name: str) -> np.ndarray:
        return small[:, fields.index(name)]

    cpu_status = data["cpu_status"]
    gpu_status = np.array([status_label(int(c)) for c in gpu_field("status")])
    ok = (cpu_status == "success") & (gpu_status == "success")
    summary: dict[str, Any] = {
        "points": len(small),
        "status_agrees": int((cpu_status == gpu_status).sum()),
        "reversed_agrees": int(
            ((data["cpu_reversal_count"] > 0) == (gpu_field("reversal_count") > 0)).sum()
        ),
        "reversal_count_agree": int(
            (data["cpu_reversal_count"] == gpu_field("reversal_count")).sum()
        ),
        "spin_crossing_count_agree": int(
            (data["cpu_spin_crossing_count"] == gpu_field("spin_crossing_count")).sum()
        ),
    }
    differences = {}
    for name in fields:
        if name in ("status", "reversal_count", "spin_crossing_count"):
            continue
        cpu, got = data[f"cpu_{name}"].astype(float), gpu_field(name)
        both = ok & np.isfinite(cpu) & np.isfinite(got)
        difference = np.abs(got[both] - cpu[both])
        differences[name] = {
            "max": float(difference.max()) if difference.size else None,
            "median": float(np.median(difference)) if difference.size else None,
            "nan_agrees": int((np.isnan(cpu) == np.isnan(got)).sum()),
        }
    summary["differences"] = differences
    cpu_seconds = float(data["cpu_seconds"])
    summary["speed"] = {
        "cpu_cores": int(data["cpu_cores"]),
        "cpu_points_per_s": len(small) / cpu_seconds,
        "gpu_small_points_per_s": len(small) / min(figures["small_s"]),
        "gpu_large_points_per_s": figures["large_points"] / figures["large_s"],
        "gpu_tiled_points_per_s": figures["tiled_points"] / figures["tiled_s"],
    }
    summary["gpu"] = figures
    text = json.dumps(summary, indent=1)
    _write_whole(directory / "report.json", force, text.encode())
    print(text)


def ptx(directory: Path, methods: list[str], model_name: str) -> None:
    """Each method's kernel compiled to PTX without a GPU (numba-cuda and NVVM), and
    assembled by ptxas where it is found."""
    import shutil

    from numba import cuda, typeof, types

    try:  # numba-cuda asks the current device for its compute capability: give one
        import numba.cuda.dispatcher as dispatcher

        class _Device:
            compute_capability = COMPUTE_CAPABILITY

        dispatcher.get_current_device = lambda: _Device()  # type: ignore[attr-defined]
    except ImportError:
        raise SystemExit("--ptx needs numba-cuda (pip install numba-cuda[cu12])") from None
    from celtstone.solvers import batch_cuda
    from celtstone.solvers._structures import Controls
    from celtstone.solvers.batch import Points
    from celtstone.solvers.codes import METHODS

    directory.mkdir(parents=True, exist_ok=True)
    batch_cuda.declare_device_functions()
    ptxas = shutil.which("ptxas") or next(
        (str(p) for p in Path(sys.prefix).glob("lib/python*/site-packages/nvidia/*/bin/ptxas")),
        None,
    )
    summary: dict[str, Any] = {}
    for method in methods:
        sweep = _sweep(1, method, model_name)
        inputs = _kernel_inputs(sweep)
        points = Points(
            inputs["params"],
            inputs["y0"],
            inputs["reversal_bands"],
            inputs["reversal_windows"],
            inputs["capture_speeds"],
        )
        launch = batch_cuda.launch_inputs(
            int(sweep.builder.model.code),
            (METHODS[method], METHODS[sweep.stick_method]),
            points,
            T_END,
            Controls(sweep.rtol, sweep.atol, 0.0, 0.0, sweep.max_steps, True),
            sweep.sample_times,
            batch_cuda.KEPT_CROSSINGS,
        )
        signature = types.void(typeof(launch.run), typeof(launch.host_buffers()))
        source = batch_cuda._ensemble_source(*launch.kernel, batch_cuda.SOURCE_KEY)
        start = time.perf_counter()
        with batch_cuda.direct_rhs():
            text, _ = cuda.compile_ptx(source, signature, cc=COMPUTE_CAPABILITY)
        entry: dict[str, Any] = {"ptx_s": round(time.perf_counter() - start, 1)}
        entry["ptx_bytes"] = len(text)
        path = directory / f"ensemble_{model_name}_{method}.ptx"
        _write_whole(path, True, text.encode())
        if ptxas is not None:
            arch = f"sm_{COMPUTE_CAPABILITY[0]}{COMPUTE_CAPABILITY[1]}"
            cubin = path.with_suffix(".cubin")
            done = subprocess.run(
                [ptxas, f"-arch={arch}", "-v", str(path), "-o", str(cubin)],
                capture_output=True,
                text=True,
            )
            lines = done.stderr.splitlines()
            entry["ptxas_returncode"] = done.returncode
            entry["ptxas_entry"] = [
                line.strip()
                for k, line in enumerate(lines)
                if "_ensemble_source" in "".join(lines[max(0, k - 2) : k])
                and ("Used" in line or "stack" in line)
            ]
        summary[method] = entry
        print(json.dumps({method: entry}), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--prepare", type=Path)
    parser.add_argument("--gpu", type=Path)
    parser.add_argument("--report", type=Path)
    parser.add_argument("--ptx", type=Path)
    parser.add_argument("--first-launch", type=Path, help=argparse.SUPPRESS)
    parser.add_argument("--method", default="vern9", help="vern9 (default), dop853, radau5 or auto")
    parser.add_argument(
        "--model",
        default="rolling",
        choices=tuple(MODELS),
        help="rolling (default); sliding: the Padé law on the disk, no stick phases; "
        "stick_slip: the realistic contact",
    )
    parser.add_argument("--grid", type=int, default=32, help="points per axis, CPU and GPU")
    parser.add_argument("--large", type=int, default=256, help="points per axis, GPU only")
    parser.add_argument("--copies", type=int, default=4, help="the large grid repeated")
    parser.add_argument(
        "--t-end", type=float, default=T_END, help=f"simulated time of each point [s] ({T_END:g})"
    )
    parser.add_argument("--force", action="store_true", help="replace DIR's earlier output")
    args = parser.parse_args()
    for name in ("grid", "large", "copies"):
        if getattr(args, name) < 1:
            parser.error(f"--{name} must be a whole number >= 1, not {getattr(args, name)}")
    if not args.t_end > 0.0:
        parser.error(f"--t-end must be a time > 0 s, not {args.t_end}")
    if args.method not in ("vern9", "dop853", "radau5", "auto"):
        parser.error(f"--method must be vern9, dop853, radau5 or auto, not {args.method!r}")
    if args.first_launch:
        print(_first_launch(args.first_launch))
    if args.prepare:
        prepare(
            args.prepare, args.grid, args.large, args.method, args.model, args.t_end, args.force
        )
    if args.gpu:
        gpu(args.gpu, args.copies, args.force)
    if args.report:
        report(args.report, args.force)
    if args.ptx:
        ptx(args.ptx, [args.method], args.model)


if __name__ == "__main__":
    main()
