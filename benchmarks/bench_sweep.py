"""Sweep throughput against the plain SciPy oracle run point by point, and sweep memory.

1. A 64 x 64 sweep of 10 s sliding runs (Kane & Levinson body, f = 0.02..0.5,
   initial spin -8..8 rad/s, eps = 1 mm, N = m g, tilt 0.5/0.5 deg, rtol 1e-8, atol
   1e-12) on every core, written to a Zarr store: trajectories per second.
2. The oracle (tests/oracle: solve_ivp Radau + NumPy right-hand side, same tolerances)
   on a random sample of the grid's points, one after the other, and celtstone on one
   core on the same points. The oracle's time over the whole grid is estimated twice:
   from the sample's mean time per point, and by the ratio estimator (the sample's
   oracle/celtstone CPU-time ratio times celtstone's CPU time over the whole grid). The
   cost of a point varies more than twofold over the grid (reversals, slip), so a
   sample of a few points gives a noisy mean; both codes run SciPy's Radau step control
   (their Jacobian and LU counts agree within 10 %), so the cost ratio varies far less
   and the second estimate is the better one.
   ``--oracle-t-end`` shortens each oracle run and scales its time up by
   t_end / oracle_t_end (stated in the output).
3. Peak memory (max RSS) of a 256 x 256 sweep in a fresh process (short runs, so that it
   finishes in seconds: memory does not grow with t_end because runs are reduced on the
   fly).

Run with ``make bench`` (about 25 minutes on 2 cores) or smaller with ``--grid 16``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import celtstone as cs
from celtstone.sweep import Sweep
from tests.oracle import rattleback as oracle

TILT = (0.5, 0.5)
FRICTION = (0.02, 0.5)
SPIN = (-8.0, 8.0)

MEMORY_SCRIPT = """
import resource, sys, tempfile
from pathlib import Path
from celtstone.sweep import Sweep
sweep = Sweep({"friction_coefficient": list(__import__("numpy").linspace(0.02, 0.5, N)),
               "initial_spin": list(__import__("numpy").linspace(-8, 8, N))}, t_end=T_END)
with tempfile.TemporaryDirectory() as directory:
    sweep.run(Path(directory) / "memory.zarr")
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
"""


# δ [m/s] of both codes: the oracle's, and celtstone's former default (now
# 1e-10, which costs 1.6-2.2 times per run; docs/decisions.md §4), kept so that the
# figures compare with earlier ones
REGULARISATION_SPEED = 1e-6


def _cores() -> int:
    return len(os.sched_getaffinity(0))


def grid_sweep(n: int, t_end: float) -> Sweep:
    return Sweep(
        {
            "friction_coefficient": np.linspace(*FRICTION, n),
            "initial_spin": np.linspace(*SPIN, n),
        },
        model="sliding",
        fixed={
            "contact": "sliding",  # the oracle's contact (the sweep default is stick-slip)
            "contact_radius": 1e-3,
            "regularisation_speed": REGULARISATION_SPEED,
        },
        t_end=t_end,
    )


def time_sweep(n: int, t_end: float) -> dict:
    sweep = grid_sweep(n, t_end)
    with tempfile.TemporaryDirectory() as directory:
        Sweep({"initial_spin": [-5.0]}, t_end=0.01).run()  # load the compiled driver
        start, cpu_start = time.perf_counter(), time.process_time()
        results = sweep.run(Path(directory) / "bench.zarr")
        elapsed, cpu = time.perf_counter() - start, time.process_time() - cpu_start
    return {
        "points": sweep.size,
        "wall_s": elapsed,
        "cpu_s": cpu,
        "trajectories_per_s": sweep.size / elapsed,
        "failures": int((results["status"] != "success").sum()),
        "reversing_points": int((results["reversal_count"] > 0).sum()),
    }


def oracle_sample(n: int, t_end: float, oracle_t_end: float, count: int) -> dict:
    """Mean oracle time per point on ``count`` grid points, and celtstone's on the same."""
    rng = np.random.default_rng(20261122)
    frictions = np.linspace(*FRICTION, n)
    spins = np.linspace(*SPIN, n)
    chosen = rng.choice(n * n, size=count, replace=False)
    body = oracle.kane_levinson_body()
    rows = []
    for flat in chosen:
        f = float(frictions[flat // n])
        spin = float(spins[flat % n])
        state = cs.InitialState((0.0, 0.0, 1.0), TILT)
        omega3 = spin / state.vertical[2]  # the sweep's spin is omega . n
        y0 = oracle.initial_state(*TILT, (0.0, 0.0, omega3), "sliding")
        start, cpu_start = time.perf_counter(), time.process_time()
        run = oracle.simulate(
            "sliding",
            body,
            y0,
            oracle_t_end,
            t_eval=np.array([oracle_t_end]),
            rtol=1e-8,
            atol=1e-12,
            friction_coefficient=f,
            contact_radius=1e-3,
            regularisation_speed=REGULARISATION_SPEED,
        )
        oracle_s = (time.perf_counter() - start) * t_end / oracle_t_end
        oracle_cpu_s = (time.process_time() - cpu_start) * t_end / oracle_t_end
        single = Sweep(
            {"friction_coefficient": [f], "initial_spin": [spin]},
            fixed={"contact": "sliding", "regularisation_speed": REGULARISATION_SPEED},
            t_end=t_end,
        )
        start, cpu_start = time.perf_counter(), time.process_time()
        single.run(workers=1)
        engine_s = time.perf_counter() - start
        engine_cpu_s = time.process_time() - cpu_start
        rows.append(
            {
                "friction_coefficient": f,
                "initial_spin": spin,
                "oracle_s": oracle_s,
                "oracle_cpu_s": oracle_cpu_s,
                "oracle_success": bool(run.success),
                "celtstone_one_core_s": engine_s,
                "celtstone_one_core_cpu_s": engine_cpu_s,
                "cost_ratio": oracle_cpu_s / engine_cpu_s,
            }
        )
    return {
        "oracle_t_end": oracle_t_end,
        "scaled_to": t_end,
        "points": rows,
        "oracle_mean_s": float(np.mean([r["oracle_s"] for r in rows])),
        "oracle_mean_cpu_s": float(np.mean([r["oracle_cpu_s"] for r in rows])),
        "celtstone_one_core_mean_s": float(np.mean([r["celtstone_one_core_s"] for r in rows])),
        # Σ oracle / Σ celtstone CPU seconds over the sample, both on one core
        "cost_ratio": float(
            sum(r["oracle_cpu_s"] for r in rows) / sum(r["celtstone_one_core_cpu_s"] for r in rows)
        ),
    }


def memory(n: int, t_end: float) -> dict:
    script = MEMORY_SCRIPT.replace("N)", f"{n})").replace("T_END", repr(t_end))
    start = time.perf_counter()
    output = subprocess.run(
        [sys.executable, "-c", script], check=True, capture_output=True, text=True
    ).stdout
    elapsed = time.perf_counter() - start
    peak_kib = int(output.split()[-1])
    return {"points": n * n, "t_end": t_end, "wall_s": elapsed, "peak_rss_mib": peak_kib / 1024}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--grid", type=int, default=64, help="points per axis (64)")
    parser.add_argument("--t-end", type=float, default=10.0, help="simulated time [s]")
    parser.add_argument("--oracle-points", type=int, default=3, help="oracle sample size")
    parser.add_argument("--oracle-t-end", type=float, default=10.0, help="oracle run [s]")
    parser.add_argument("--memory-grid", type=int, default=256, help="0 skips the memory run")
    parser.add_argument("--memory-t-end", type=float, default=0.05, help="memory run [s]")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args = parser.parse_args()

    sweep = time_sweep(args.grid, args.t_end)
    sample = oracle_sample(args.grid, args.t_end, args.oracle_t_end, args.oracle_points)
    oracle_rate = 1.0 / sample["oracle_mean_s"]
    report = {
        "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}",
        "sweep": sweep,
        "oracle_sample": sample,
        "oracle_trajectories_per_s": oracle_rate,
        "ratio": sweep["trajectories_per_s"] / oracle_rate,
        # the same with CPU seconds, for a machine shared with other work: what the
        # ratio is when the sweep has every core to itself
        "cpu_ratio": sample["oracle_mean_cpu_s"] / (sweep["cpu_s"] / sweep["points"] / _cores()),
        # ratio estimator: the oracle's time over the whole grid estimated as the sample's
        # oracle/celtstone cost ratio times celtstone's CPU time over the whole grid
        # (the cost of a point varies > 2x over the grid, the cost ratio far less)
        "ratio_estimator": sample["cost_ratio"] * sweep["cpu_s"] / sweep["wall_s"],
    }
    if args.memory_grid > 0:
        report["memory"] = memory(args.memory_grid, args.memory_t_end)
    report["this_process_peak_rss_mib"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    if args.json:
        print(json.dumps(report, indent=2))
        return
    s = report["sweep"]
    print(f"machine: {report['machine']}")
    print(
        f"sweep {args.grid} x {args.grid}, sliding, {args.t_end:g} s, rtol 1e-8: "
        f"{s['wall_s']:.1f} s, {s['trajectories_per_s']:.2f} trajectories/s "
        f"({s['failures']} failures, {s['reversing_points']} points reverse)"
    )
    scaled = (
        ""
        if sample["oracle_t_end"] == args.t_end
        else f" (runs of {sample['oracle_t_end']:g} s scaled to {args.t_end:g} s)"
    )
    print(
        f"oracle, {len(sample['points'])} sample points{scaled}: "
        f"{sample['oracle_mean_s']:.1f} s per point, {oracle_rate:.4f} trajectories/s; "
        f"celtstone on one core, same points: {sample['celtstone_one_core_mean_s']:.3f} s"
    )
    for row in sample["points"]:
        print(
            f"  f = {row['friction_coefficient']:.4f}, "
            f"initial spin = {row['initial_spin']:+.3f} rad/s: "
            f"oracle {row['oracle_s']:.1f} s, celtstone {row['celtstone_one_core_s']:.3f} s, "
            f"CPU-time ratio {row['cost_ratio']:.0f}"
        )
    grid_cost = s["cpu_s"] / s["points"]
    print(
        f"celtstone's mean CPU time per point over the whole grid: {grid_cost:.3f} s "
        f"(sample: {np.mean([r['celtstone_one_core_cpu_s'] for r in sample['points']]):.3f} s)"
    )
    print(
        "ratio (sweep throughput / oracle throughput), oracle time per point estimated by "
        f"the sample mean: {report['ratio']:.0f} x"
    )
    print(
        f"  the same from CPU time ({_cores()} cores, for a machine shared with other work): "
        f"{report['cpu_ratio']:.0f} x"
    )
    print(
        "ratio, oracle time per point estimated by the sample's cost ratio "
        f"({sample['cost_ratio']:.0f}) times celtstone's cost over the whole grid: "
        f"{report['ratio_estimator']:.0f} x"
    )
    if "memory" in report:
        m = report["memory"]
        print(
            f"memory: {m['points']} points ({m['t_end']:g} s runs) in {m['wall_s']:.1f} s, "
            f"peak RSS {m['peak_rss_mib']:.0f} MiB"
        )


if __name__ == "__main__":
    from benchmarks._page import recorded

    with recorded("bench_sweep", "A sweep against the SciPy oracle point by point"):
        main()
