"""One paper run, celtstone against a plain SciPy + NumPy implementation of the same equations.

The baseline is the independent oracle in ``tests/oracle`` (``solve_ivp`` with a NumPy
right-hand side), as a researcher would write it. Prints both wall times and their
ratio. Run with ``make bench``.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import celtstone as cs
from tests.oracle import rattleback as oracle

TILT = (0.5, 0.5)


def best_time(function, repeats: int) -> float:  # type: ignore[no-untyped-def]
    """Smallest wall time of ``repeats`` calls [s]."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def case(model_name: str, t_end: float, rtol: float, atol: float, repeats: int) -> dict:
    """Time one case with both implementations and compare their final spins."""
    body = cs.load_body("kane_levinson_1982")
    settings = (
        {"friction_coefficient": 0.35, "contact_radius": 1e-3} if model_name == "sliding" else {}
    )
    model = cs.model_from_name(model_name, **settings)
    state = cs.InitialState((0.0, 0.0, -5.0), TILT)

    def engine() -> cs.Trajectory:
        return cs.simulate(model, body, state, t_end, rtol=rtol, atol=atol)

    engine()  # compile or load the numba cache
    engine_time = best_time(engine, repeats)
    run = engine()

    reference_body = oracle.kane_levinson_body()
    y0 = oracle.initial_state(*TILT, (0.0, 0.0, -5.0), model_name)
    start = time.perf_counter()
    reference = oracle.simulate(
        model_name,
        reference_body,
        y0,
        t_end,
        t_eval=np.array([t_end]),
        rtol=rtol,
        atol=atol,
        **settings,
    )
    oracle_time = time.perf_counter() - start
    return {
        "case": f"{model_name}, Kane & Levinson body, w3 = -5 rad/s, {t_end:g} s, rtol {rtol:g}",
        "celtstone_s": engine_time,
        "scipy_numpy_s": oracle_time,
        "ratio": oracle_time / engine_time,
        "steps": run.statistics["n_accepted"],
        "final_spin_celtstone": float(run.dataset["spin"].values[-1]),
        "final_spin_scipy": float(oracle.spin(reference.y[:, -1])),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--sliding", action="store_true", help="also the 10 s sliding case")
    args = parser.parse_args()
    results = [case("rolling", 50.0, 1e-11, 1e-12, repeats=5)]
    if args.sliding:
        results.append(case("sliding", 10.0, 1e-8, 1e-12, repeats=3))
    machine = f"{platform.processor() or platform.machine()}, {platform.python_version()}"
    if args.json:
        print(json.dumps({"machine": machine, "results": results}, indent=2))
        return
    print(f"machine: {machine}")
    for r in results:
        print(r["case"])
        print(f"  celtstone        {r['celtstone_s']:9.4f} s  ({r['steps']} steps)")
        print(f"  SciPy + NumPy    {r['scipy_numpy_s']:9.4f} s")
        print(f"  ratio            {r['ratio']:9.1f} x")
        spins = f"{r['final_spin_celtstone']:.9f} vs {r['final_spin_scipy']:.9f}"
        print(f"  final spin       {spins} rad/s")


if __name__ == "__main__":
    main()
