"""Sliding sweeps with the two contacts: regularised sliding against stick–slip (hybrid).

Issue 17, item 4. The grid of ``bench_sweep.py`` (Kane & Levinson body, f = 0.02..0.5,
initial spin -8..8 rad/s, eps = 1 mm, N = m g, tilt 0.5/0.5 deg, 10 s, rtol 1e-8, atol
1e-12) is swept twice, once with ``contact = sliding`` (the regularised law, slip speed
regularised below delta = ``regularisation_speed``) and once with ``contact = hybrid``
(exact stick phases, Radau in slip, DOP853 in stick), on every core. Printed:

1. wall and CPU time of each sweep;
2. agreement of the answer "does the spin reverse" (``n_reversals > 0``) point by point,
   and every point where the two contacts disagree, with both first reversal times and
   final spins;
3. where the time goes: on a sample of grid points (and the disagreeing ones), one run of
   each contact with its steps, right-hand-side evaluations, LU factorisations, wall
   time, and for the hybrid contact its stick and slip phases and the time spent in stick.

Run ``python benchmarks/bench_contact.py`` (64 x 64: about 20 minutes on 2 cores) or
smaller with ``--grid 32``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import tempfile
import time
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import celtstone as cs
from celtstone.sweep import Sweep

TILT = (0.5, 0.5)
FRICTION = (0.02, 0.5)
SPIN = (-8.0, 8.0)
CONTACT_RADIUS = 1e-3
CONTACTS = ("sliding", "hybrid")


def grid_sweep(n: int, t_end: float, contact: str) -> Sweep:
    return Sweep(
        {
            "friction_coefficient": np.linspace(*FRICTION, n),
            "initial_spin": np.linspace(*SPIN, n),
        },
        model="sliding",
        fixed={"contact_radius": CONTACT_RADIUS, "contact": contact},
        t_end=t_end,
    )


def time_sweep(n: int, t_end: float, contact: str) -> tuple[dict[str, Any], Any]:
    """One grid sweep with ``contact``: its times and its results (an xarray Dataset)."""
    sweep = grid_sweep(n, t_end, contact)
    with tempfile.TemporaryDirectory() as directory:
        warm = Sweep({"initial_spin": [-5.0]}, fixed={"contact": contact}, t_end=0.01)
        warm.run()  # load the compiled driver
        start, cpu_start = time.perf_counter(), time.process_time()
        results = sweep.run(Path(directory) / f"{contact}.zarr")
        elapsed, cpu = time.perf_counter() - start, time.process_time() - cpu_start
    return {
        "contact": contact,
        "points": sweep.size,
        "wall_s": elapsed,
        "cpu_s": cpu,
        "failures": int((results["status"] != "success").sum()),
        "reversing_points": int((results["n_reversals"] > 0).sum()),
    }, results


def disagreements(results: dict[str, Any]) -> tuple[float, list[dict[str, Any]]]:
    """Fraction of points whose reversal yes/no agrees, and the points where it does not."""
    sliding, hybrid = results["sliding"], results["hybrid"]
    reverses = {name: (data["n_reversals"] > 0).values for name, data in results.items()}
    differ = reverses["sliding"] != reverses["hybrid"]
    rows = []
    frictions = sliding["friction_coefficient"].values
    spins = sliding["initial_spin"].values
    for i, j in zip(*np.nonzero(differ), strict=True):
        rows.append(
            {
                "friction_coefficient": float(frictions[i]),
                "initial_spin": float(spins[j]),
                **{
                    f"{name}_{field}": _plain(data[field].values[i, j])
                    for name, data in (("sliding", sliding), ("hybrid", hybrid))
                    for field in ("n_reversals", "first_reversal_time", "final_spin", "status")
                },
            }
        )
    return 1.0 - float(differ.mean()), rows


def _plain(value: Any) -> Any:
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value


def profile(points: list[tuple[float, float]], t_end: float) -> list[dict[str, Any]]:
    """Steps and time of one run of each contact at each (f, initial spin) point."""
    body = cs.load_body("kane_levinson_1982")
    rows = []
    for friction, spin in points:
        unit = cs.InitialState((0.0, 0.0, 1.0), TILT)
        state = cs.InitialState((0.0, 0.0, spin / unit.vertical[2]), TILT)
        settings = {"friction_coefficient": friction, "contact_radius": CONTACT_RADIUS}
        for contact, model in (
            ("sliding", cs.SlidingModel(**settings)),
            ("hybrid", cs.HybridModel(**settings)),
        ):
            start = time.perf_counter()
            run = cs.simulate(model, body, state, t_end, rtol=1e-8, atol=1e-12)
            elapsed = time.perf_counter() - start
            summary = run.summary()
            row = {
                "friction_coefficient": friction,
                "initial_spin": spin,
                "contact": contact,
                "wall_s": elapsed,
                **run.statistics,
                "n_reversals": len(summary["reversal_times"]),
            }
            if contact == "hybrid":
                phases = summary["phases"]
                row["stick_phases"] = summary["stick_phases"]
                row["slip_phases"] = summary["slip_phases"]
                row["time_in_stick_s"] = sum(
                    p["t_end"] - p["t_start"] for p in phases if p["kind"] == "stick"
                )
            rows.append(row)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--grid", type=int, default=64, help="points per axis (64)")
    parser.add_argument("--t-end", type=float, default=10.0, help="simulated time [s]")
    parser.add_argument("--sample", type=int, default=6, help="points profiled one by one")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args = parser.parse_args()
    sweeps, results = [], {}
    for contact in CONTACTS:
        timing, results[contact] = time_sweep(args.grid, args.t_end, contact)
        sweeps.append(timing)
    agreement, differing = disagreements(results)
    rng = np.random.default_rng(20261124)
    frictions, spins = np.linspace(*FRICTION, args.grid), np.linspace(*SPIN, args.grid)
    chosen = rng.choice(args.grid * args.grid, size=args.sample, replace=False)
    points = [(float(frictions[k // args.grid]), float(spins[k % args.grid])) for k in chosen]
    points += [(d["friction_coefficient"], d["initial_spin"]) for d in differing[:4]]
    report = {
        "date": datetime.now(UTC).strftime("%Y-%m-%d"),
        "machine": f"{platform.processor() or platform.machine()}, "
        f"{len(os.sched_getaffinity(0))} cores, Python {platform.python_version()}",
        "grid": args.grid,
        "t_end": args.t_end,
        "sweeps": sweeps,
        "reversal_agreement": agreement,
        "disagreeing_points": differing,
        "profile": profile(points, args.t_end),
    }
    if args.json:
        print(json.dumps(report, indent=2))
        return
    print(f"{report['date']}, {report['machine']}")
    print(f"{args.grid} x {args.grid} grid, {args.t_end:g} s runs")
    for s in sweeps:
        print(
            f"  {s['contact']:8s} wall {s['wall_s']:8.1f} s  cpu {s['cpu_s']:8.1f} s  "
            f"reversing {s['reversing_points']:5d}  failures {s['failures']}"
        )
    print(f"reversal yes/no agrees on {100 * agreement:.2f} % of points; {len(differing)} differ")
    for d in differing:
        print(
            f"  f {d['friction_coefficient']:.4f} spin {d['initial_spin']:+.4f}: "
            f"sliding {d['sliding_n_reversals']} reversals "
            f"(first {d['sliding_first_reversal_time']}), final {d['sliding_final_spin']:.4g}; "
            f"hybrid {d['hybrid_n_reversals']} "
            f"(first {d['hybrid_first_reversal_time']}), final {d['hybrid_final_spin']:.4g}"
        )
    print("profile (one run each, rtol 1e-8):")
    header = f"  {'f':>6s} {'spin':>7s} {'contact':8s} {'steps':>7s} {'rejected':>8s}"
    print(header + f" {'nfev':>8s} {'nlu':>6s} {'wall s':>8s}  phases")
    for r in report["profile"]:
        phases = (
            f"stick {r['stick_phases']}, slip {r['slip_phases']}, "
            f"{r['time_in_stick_s']:.2f} s in stick"
            if r["contact"] == "hybrid"
            else ""
        )
        print(
            f"  {r['friction_coefficient']:6.3f} {r['initial_spin']:+7.3f} {r['contact']:8s} "
            f"{r['n_accepted']:7d} {r['n_rejected']:8d} {r['nfev']:8d} {r['nlu']:6d} "
            f"{r['wall_s']:8.3f}  {phases}"
        )


if __name__ == "__main__":
    main()
