"""Which method a GPU thread should run, measured without a GPU: each point's work and
how evenly a warp's 32 threads share it.

A GPU runs a sweep one point per thread, 32 threads to a warp in lockstep: a warp lasts as
long as its slowest thread, so a launch costs about the sum over warps of the warp's
largest per-point work, not the sum of the work. This script measures, on the CPU, both
numbers for the issue's sweeps (``gpu_sweep.MODELS``: the sliding model on the disk with
the Padé law, and the stick–slip realistic contact) with each method a thread can run:

* each point's work: the CPU time of its run on one thread (``time.thread_time``), and
  its right-hand side evaluations, Jacobians and LU factorisations (``Trajectory.statistics``);
* the warp efficiency, the summed work over 32 × the summed warp maxima, for the sweep's
  own order of points and for the points sorted by a predictor known before the run (the
  initial spin's magnitude) and by the work itself (the most any sorting could give);
* the proxy GPU cost, the summed warp maxima, relative to the cheapest method's.

The runs take the sweep's tolerances (``sweep.runner.DEFAULT_RTOL``, ``DEFAULT_ATOL``) and,
for the stick–slip contact, the sweep's stick method (DOP853). An explicit method on the
stiff sliding model takes tens of seconds a point: ``--explicit-grid`` runs it on a
smaller grid (its mean work per point is then the comparable number).

The CPU's time per operation is not a GPU thread's (Radau's LU lives in the thread's local
memory there), so the proxy ranks methods; a GPU's own timing (``gpu_sweep.py``) decides
where the ranking is close.

    python benchmarks/gpu_thread_work.py --model sliding --grid 12
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from _page import recorded
from gpu_sweep import MODELS, T_END, _grid

WARP = 32  # threads that run in lockstep on an NVIDIA GPU
METHODS = ("dop853", "radau5", "auto")  # a sliding thread's methods (vern9 ranks as dop853)
EXPLICIT = ("dop853", "vern9")


def _runs(model_key: str, n: int) -> list[tuple[Any, Any, Any, float]]:
    """The sweep's points in its own order (spin outer, α inner, as ``Sweep``'s grid):
    (model, body, state, initial spin [rad/s])."""
    import celtstone as cs
    from celtstone.sweep.spec import build_model, build_state

    name, fixed = MODELS[model_key]
    choices = {k: str(v) for k, v in fixed.items() if isinstance(v, str)}
    numbers = {k: float(v) for k, v in fixed.items() if not isinstance(v, str)}
    model = build_model(name, choices, numbers)
    body = cs.load_body("kane_levinson_1982")
    grid = _grid(n)
    return [
        (model, body, build_state({"initial_spin": spin, "euler_alpha": alpha}), float(spin))
        for spin in grid["initial_spin"]
        for alpha in grid["euler_alpha"]
    ]


def _work(runs: list[tuple[Any, Any, Any, float]], method: str, t_end: float) -> dict[str, Any]:
    """Each point's CPU time [s] and statistics with ``method`` (the slip phases' method of
    a stick–slip run; its stick phases run DOP853)."""
    import warnings

    import celtstone as cs
    from celtstone.sweep.runner import DEFAULT_ATOL, DEFAULT_RTOL

    seconds, statistics, statuses = [], [], []
    stick = "dop853" if isinstance(runs[0][0], cs.HybridModel) else None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for model, body, state, _ in runs:
            start = time.thread_time()
            run = cs.simulate(
                model,
                body,
                state,
                t_end,
                method=method,
                stick_method=stick,
                rtol=DEFAULT_RTOL,
                atol=DEFAULT_ATOL,
                n_samples=201,
            )
            seconds.append(time.thread_time() - start)
            statistics.append(run.statistics)
            statuses.append(run.status)
    keys = statistics[0].keys()
    return {
        "seconds": np.array(seconds),
        **{key: np.array([s[key] for s in statistics], dtype=float) for key in keys},
        "statuses": statuses,
    }


def warp_cost(work: np.ndarray, order: np.ndarray) -> float:
    """The summed warp maxima of ``work`` launched in ``order`` (the last warp short)."""
    ordered = work[order]
    return float(sum(ordered[k : k + WARP].max() for k in range(0, ordered.size, WARP)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--model", choices=("sliding", "stick_slip"), default="sliding")
    parser.add_argument("--grid", type=int, default=12, help="points per axis")
    parser.add_argument("--t-end", type=float, default=T_END, help="[s]")
    parser.add_argument("--methods", default=",".join(METHODS))
    parser.add_argument(
        "--explicit-grid", type=int, default=4, help="points per axis of an explicit method"
    )
    args = parser.parse_args()
    grids = {
        method: args.explicit_grid if method in EXPLICIT else args.grid
        for method in args.methods.split(",")
    }
    # the sliding model warms up its compile before the clock starts
    _work(_runs(args.model, 1), "auto", 0.01)
    with recorded(f"gpu_thread_work_{args.model}", f"GPU thread work: {args.model}"):
        print(
            f"{args.model}: a grid of initial spin x α, {args.t_end:g} s a point, "
            f"one CPU thread; warp = {WARP} points"
        )
        rows = {}
        for method, grid in grids.items():
            runs = _runs(args.model, grid)
            spins = np.array([abs(spin) for *_, spin in runs])
            result = _work(runs, method, args.t_end)
            seconds = result["seconds"]
            own = np.arange(seconds.size)
            by_spin = np.argsort(spins, kind="stable")
            by_work = np.argsort(seconds, kind="stable")
            rows[method] = {
                "points": seconds.size,
                "total": float(seconds.sum()),
                "median": float(np.median(seconds)),
                "max": float(seconds.max()),
                "nfev": float(np.median(result["nfev"])),
                "nlu": float(np.median(result["nlu"])),
                "warps": {
                    name: warp_cost(seconds, order)
                    for name, order in (("own", own), ("spin", by_spin), ("work", by_work))
                },
                "failed": sum(status != "success" for status in result["statuses"]),
            }
        per_point = {
            method: 32 * row["warps"]["own"] / row["points"]
            for method, row in rows.items()
            if row["points"] >= 2 * WARP
        }
        cheapest = min(per_point.values()) if per_point else math.nan
        print(
            f"{'method':8} {'points':>6} {'mean s':>7} {'max s':>7} {'nfev':>9} {'nlu':>6} "
            f"{'eff own':>8} {'eff |spin|':>10} {'eff work':>9} {'GPU proxy':>10} {'stopped':>7}"
        )
        for method, row in rows.items():
            efficiency = {k: row["total"] / (WARP * v) for k, v in row["warps"].items()}
            warps = row["points"] >= 2 * WARP  # efficiencies need warps to compare
            cells = [
                f"{efficiency[k]:{w}.2f}" if warps else f"{'-':>{w}}"
                for k, w in (("own", 8), ("spin", 10), ("work", 9))
            ]
            proxy = f"{per_point[method] / cheapest:10.2f}" if method in per_point else f"{'-':>10}"
            print(
                f"{method:8} {row['points']:6d} {row['total'] / row['points']:7.3f} "
                f"{row['max']:7.3f} {row['nfev']:9.0f} {row['nlu']:6.0f} {' '.join(cells)} "
                f"{proxy} {row['failed']:7d}"
            )
        print(
            "mean s, max s: CPU seconds of a point; nfev, nlu: medians per point; eff: summed "
            "work / (32 x summed warp maxima) in the sweep's order, sorted by |initial spin|, "
            "sorted by the work itself (the most a sorting gives); GPU proxy: summed warp "
            "maxima per point over the cheapest method's; stopped: points not a success"
        )


if __name__ == "__main__":
    main()
