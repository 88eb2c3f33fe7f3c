"""Sliding sweeps with two contacts, or two slip methods: what a sweep's points cost.

Issue 17, item 4. The grid of ``bench_sweep.py`` (Kane & Levinson body, f = 0.02..0.5,
initial spin -8..8 rad/s, eps = 1 mm, N = m g, tilt 0.5/0.5 deg, 10 s, rtol 1e-8, atol
1e-12) is swept once per variant on every core. By default the variants are the two
contacts: ``sliding`` (the regularised law, slip speed regularised below delta =
``regularisation_speed``) and ``hybrid`` (exact stick phases), each with the model's
default method (``auto`` in slip, DOP853 in stick). ``--slip-methods radau5,auto``
sweeps the hybrid contact once with each slip method instead (stick phases DOP853).
Printed:

1. wall and CPU time of each sweep;
2. agreement of the answer "does the spin reverse" (``reversal_count > 0``) point by point
   between the first variant and each other, and every point where they disagree, with
   both first reversal times and final spins;
3. where the time goes: on a sample of grid points (and the disagreeing ones), one run of
   each variant with its steps (and Radau's share of them, and the method switches),
   right-hand-side evaluations, LU factorisations, wall time, and for the hybrid
   contact its stick and slip phases and the time spent in stick.

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
DEFAULT_VARIANTS = (("sliding", None), ("hybrid", None))  # (contact, slip method)


def variant_name(contact: str, slip_method: str | None) -> str:
    return contact if slip_method is None else f"{contact}/{slip_method}"


def methods_of(contact: str, slip_method: str | None) -> dict[str, str]:
    """``simulate``'s and ``Sweep``'s method arguments for a variant: the slip method if
    one is named, with DOP853 in stick as by default (None: the model's defaults)."""
    if slip_method is None:
        return {}
    return {"method": slip_method, **({"stick_method": "dop853"} if contact == "hybrid" else {})}


def grid_sweep(n: int, t_end: float, contact: str, slip_method: str | None = None) -> Sweep:
    return Sweep(
        {
            "friction_coefficient": np.linspace(*FRICTION, n),
            "initial_spin": np.linspace(*SPIN, n),
        },
        model="sliding",
        fixed={"contact_radius": CONTACT_RADIUS, "contact": contact},
        t_end=t_end,
        **methods_of(contact, slip_method),
    )


def time_sweep(
    n: int, t_end: float, contact: str, slip_method: str | None = None
) -> tuple[dict[str, Any], Any]:
    """One grid sweep with ``contact`` and ``slip_method`` (None: the model's default):
    its times and its results (an xarray Dataset)."""
    sweep = grid_sweep(n, t_end, contact, slip_method)
    with tempfile.TemporaryDirectory() as directory:
        warm = Sweep({"initial_spin": [-5.0]}, fixed={"contact": contact}, t_end=0.01)
        warm.run()  # load the compiled driver
        start, cpu_start = time.perf_counter(), time.process_time()
        results = sweep.run(Path(directory) / "grid.zarr")
        elapsed, cpu = time.perf_counter() - start, time.process_time() - cpu_start
    return {
        "contact": contact,
        "variant": variant_name(contact, slip_method),
        "slip_method": sweep.method,
        "points": sweep.size,
        "wall_s": elapsed,
        "cpu_s": cpu,
        "failures": int((results["status"] != "success").sum()),
        "reversing_points": int((results["reversal_count"] > 0).sum()),
    }, results


def disagreements(first: Any, other: Any) -> tuple[float, list[dict[str, Any]]]:
    """Fraction of points whose reversal yes/no agrees between two sweeps' results, and
    the points where it does not (fields ``first_*`` and ``other_*``)."""
    differ = (first["reversal_count"] > 0).values != (other["reversal_count"] > 0).values
    rows = []
    frictions = first["friction_coefficient"].values
    spins = first["initial_spin"].values
    for i, j in zip(*np.nonzero(differ), strict=True):
        rows.append(
            {
                "friction_coefficient": float(frictions[i]),
                "initial_spin": float(spins[j]),
                **{
                    f"{name}_{field}": _plain(data[field].values[i, j])
                    for name, data in (("first", first), ("other", other))
                    for field in ("reversal_count", "first_reversal_time", "spin_final", "status")
                },
            }
        )
    return 1.0 - float(differ.mean()), rows


def largest_differences(first: Any, other: Any) -> dict[str, float | None]:
    """The largest |difference| of the final spin [rad/s] and of the first reversal time
    [s] over the points where both are defined."""
    spin = np.abs(first["spin_final"].values - other["spin_final"].values)
    reversal = np.abs(first["first_reversal_time"].values - other["first_reversal_time"].values)
    return {
        "final_spin": _plain(np.nanmax(spin)) if np.isfinite(spin).any() else None,
        "first_reversal_time": _plain(np.nanmax(reversal)) if np.isfinite(reversal).any() else None,
    }


def _plain(value: Any) -> Any:
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value


def profile(
    points: list[tuple[float, float]],
    t_end: float,
    variants: tuple[tuple[str, str | None], ...],
) -> list[dict[str, Any]]:
    """Steps and time of one run of each variant at each (f, initial spin) point."""
    body = cs.load_body("kane_levinson_1982")
    models = {"sliding": cs.SlidingModel, "hybrid": cs.HybridModel}
    rows = []
    for friction, spin in points:
        unit = cs.InitialState((0.0, 0.0, 1.0), TILT)
        state = cs.InitialState((0.0, 0.0, spin / unit.vertical[2]), TILT)
        settings = {"friction_coefficient": friction, "contact_radius": CONTACT_RADIUS}
        for contact, slip_method in variants:
            model = models[contact](**settings)
            start = time.perf_counter()
            run = cs.simulate(
                model, body, state, t_end, rtol=1e-8, atol=1e-12, **methods_of(contact, slip_method)
            )
            elapsed = time.perf_counter() - start
            summary = run.summary()
            row = {
                "friction_coefficient": friction,
                "initial_spin": spin,
                "contact": contact,
                "variant": variant_name(contact, slip_method),
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
    parser.add_argument(
        "--slip-methods",
        default=None,
        help="two or more slip methods, comma-separated (e.g. radau5,auto): sweep the hybrid "
        "contact once with each instead of the two contacts",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args = parser.parse_args()
    variants: tuple[tuple[str, str | None], ...] = DEFAULT_VARIANTS
    if args.slip_methods:
        variants = tuple(("hybrid", name) for name in args.slip_methods.split(","))
    sweeps, results = [], []
    for contact, slip_method in variants:
        timing, data = time_sweep(args.grid, args.t_end, contact, slip_method)
        sweeps.append(timing)
        results.append(data)
    comparisons, differing = [], []
    for timing, data in zip(sweeps[1:], results[1:], strict=True):
        agreement, rows = disagreements(results[0], data)
        comparisons.append(
            {
                "first": sweeps[0]["variant"],
                "other": timing["variant"],
                "reversal_agreement": agreement,
                "largest_difference": largest_differences(results[0], data),
                "disagreeing_points": rows,
            }
        )
        differing += rows
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
        "comparisons": comparisons,
        "profile": profile(points, args.t_end, variants),
    }
    if args.json:
        print(json.dumps(report, indent=2))
        return
    print(f"{report['date']}, {report['machine']}")
    print(f"{args.grid} x {args.grid} grid, {args.t_end:g} s runs")
    for s in sweeps:
        print(
            f"  {s['variant']:14s} wall {s['wall_s']:8.1f} s  cpu {s['cpu_s']:8.1f} s  "
            f"reversing {s['reversing_points']:5d}  failures {s['failures']}"
        )
    for c in comparisons:
        rows = c["disagreeing_points"]
        largest = c["largest_difference"]
        print(
            f"{c['first']} against {c['other']}: reversal yes/no agrees on "
            f"{100 * c['reversal_agreement']:.2f} % of points; {len(rows)} differ; largest "
            f"difference of the final spin {largest['final_spin']} rad/s, of the first "
            f"reversal {largest['first_reversal_time']} s"
        )
        for d in rows:
            print(
                f"  f {d['friction_coefficient']:.4f} spin {d['initial_spin']:+.4f}: "
                f"{d['first_n_reversals']} against {d['other_n_reversals']} reversals "
                f"(first {d['first_first_reversal_time']} / {d['other_first_reversal_time']}), "
                f"final {d['first_final_spin']:.4g} / {d['other_final_spin']:.4g}"
            )
    print("profile (one run each, rtol 1e-8):")
    header = f"  {'f':>6s} {'spin':>7s} {'variant':14s} {'steps':>7s} {'radau':>7s} {'switch':>6s}"
    print(header + f" {'rejected':>8s} {'nfev':>8s} {'nlu':>6s} {'wall s':>8s}  phases")
    for r in report["profile"]:
        phases = (
            f"stick {r['stick_phases']}, slip {r['slip_phases']}, "
            f"{r['time_in_stick_s']:.2f} s in stick"
            if r["contact"] == "hybrid"
            else ""
        )
        print(
            f"  {r['friction_coefficient']:6.3f} {r['initial_spin']:+7.3f} {r['variant']:14s} "
            f"{r['n_accepted']:7d} {r['n_radau_steps']:7d} {r['n_switches']:6d} "
            f"{r['n_rejected']:8d} {r['nfev']:8d} {r['nlu']:6d} {r['wall_s']:8.3f}  {phases}"
        )


if __name__ == "__main__":
    main()
