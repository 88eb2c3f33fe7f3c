"""One paper run, celtstone against two SciPy implementations of the same equations.

* naive SciPy: the independent oracle in ``tests/oracle`` (``solve_ivp`` on a NumPy
  right-hand side with ``np.cross`` and ``np.linalg.solve``), as a researcher writes it first;
* careful SciPy: ``benchmarks/careful_baseline.py`` (``solve_ivp`` on a scalar right-hand
  side, cross products by component, the 3x3 solve by hand, one output array per call),
  what a competent researcher writes without a compiler.

Both use SciPy's DOP853 for rolling and Radau for sliding. celtstone's rolling model
integrates with Verner's 9(8) pair by default, which is more accurate than DOP853 at the same
rtol (docs/decisions.md §46), so the rolling case also times celtstone's DOP853, the
baselines' own method. Prints the wall times, the ratios (SciPy time / celtstone time: for
rolling against both of celtstone's methods) and, for each case, a profile table:
steps accepted and rejected, right-hand-side evaluations (nfev), Jacobian evaluations (njev),
LU factorisations (nlu), wall time and wall time per accepted step. A stick-slip (hybrid
contact) case is profiled for celtstone alone. Wall times: celtstone best of 5 (3 for
sliding and hybrid), careful SciPy best of 3 (one run for sliding), naive SciPy one run.

The naive oracle's 50 s rolling run takes minutes (~0.6 ms per right-hand side, most of it
in ``np.cross``): ``--quick`` skips it and reports the careful ratio alone. ``--sliding``
adds the 10 s sliding case (careful SciPy ~1 min, naive SciPy ~3 min). Run with
``make bench``.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import sys
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import careful_baseline as careful

import celtstone as cs
from tests.oracle import rattleback as oracle

TILT = (0.5, 0.5)
"""Kane & Levinson's initial Euler tilts alpha, beta [deg]."""
OMEGA0 = (0.0, 0.0, -5.0)
"""Initial angular velocity in body axes [rad/s]."""
FRICTION = {"friction_coefficient": 0.35, "contact_radius": 1e-3}
"""The sliding and stick-slip cases' friction coefficient and Hertz contact radius [m]."""
DOP853_INITIAL_CALLS = 2
"""SciPy DOP853's right-hand-side calls before its first step (f(t0), initial step size)."""
DOP853_CALLS_PER_STEP = 12
"""SciPy DOP853's right-hand-side calls per attempted step (no dense output asked)."""


def progress(message: str) -> None:
    """A line on stderr: the naive runs take minutes."""
    print(message, file=sys.stderr, flush=True)


def best_time(function: Callable[[], Any], repeats: int) -> tuple[float, Any]:
    """Smallest wall time of ``repeats`` calls [s], and the last call's result."""
    times = []
    result = None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return min(times), result


def profile_row(
    name: str,
    wall: float,
    accepted: int,
    rejected: int | None,
    nfev: int,
    njev: int,
    nlu: int,
) -> dict[str, Any]:
    """One row of a profile table; ``rejected`` None where the solver does not count them."""
    return {
        "implementation": name,
        "n_accepted": accepted,
        "n_rejected": rejected,
        "nfev": nfev,
        "njev": njev,
        "nlu": nlu,
        "wall_s": wall,
        "us_per_step": 1e6 * wall / accepted,
    }


def run_celtstone(
    model_name: str, t_end: float, rtol: float, atol: float, repeats: int, method: str | None = None
) -> dict:
    """Time celtstone (compiled beforehand) on one case with ``method`` (None: the model's
    default); its profile row and final spin."""
    body = cs.load_body("kane_levinson_1982")
    if model_name == "rolling":
        model = cs.model_from_name("rolling")
    elif model_name == "sliding":
        # δ = 1e-6 m/s, the oracle's (celtstone's default is 1e-10)
        model = cs.model_from_name("sliding", regularisation_speed=1e-6, **FRICTION)
    else:  # the stick-slip contact of the sliding model
        model = cs.model_from_name("sliding", contact="hybrid", **FRICTION)
    state = cs.InitialState(OMEGA0, TILT)
    progress(f"celtstone, {model_name} ...")

    def engine() -> cs.Trajectory:
        return cs.simulate(model, body, state, t_end, rtol=rtol, atol=atol, method=method)

    with warnings.catch_warnings():
        # the paper's static friction load exceeds Coulomb's bound in these runs (README)
        warnings.simplefilter("ignore", cs.FrictionBoundWarning)
        engine()  # compile or load the numba cache
        wall, run = best_time(engine, repeats)
    stats = run.statistics
    method = run.samples.attrs["method"]
    if model_name == "hybrid":
        method = f"{method} + {run.samples.attrs['stick_method']}"
    row = profile_row(
        f"celtstone ({method})",
        wall,
        stats["n_accepted"],
        stats["n_rejected"],
        stats["nfev"],
        stats["njev"],
        stats["nlu"],
    )
    return {"row": row, "final_spin": float(run.dataset["spin"].values[-1]), "status": run.status}


def run_scipy(
    implementation: Any,
    name: str,
    model_name: str,
    t_end: float,
    rtol: float,
    atol: float,
    repeats: int,
) -> dict:
    """Time a SciPy implementation (``oracle`` or ``careful``): its profile row and final spin.

    Every step is kept (no ``t_eval``, no dense output), so the accepted steps are
    ``len(t) - 1`` and DOP853's rejected ones follow from nfev; Radau does not count them.
    """
    body = oracle.kane_levinson_body()
    y0 = oracle.initial_state(*TILT, OMEGA0, model_name)
    settings = FRICTION if model_name == "sliding" else {}
    progress(f"{name}, {model_name}, {repeats} run(s) ...")

    def baseline() -> Any:
        return implementation.simulate(
            model_name, body, y0, t_end, rtol=rtol, atol=atol, **settings
        )

    wall, run = best_time(baseline, repeats)
    if not run.success:
        raise RuntimeError(f"{name} run failed: {run.message}")
    accepted = len(run.t) - 1
    method = "DOP853" if model_name == "rolling" else "Radau"
    rejected = None
    if method == "DOP853":
        attempts, remainder = divmod(run.nfev - DOP853_INITIAL_CALLS, DOP853_CALLS_PER_STEP)
        rejected = attempts - accepted if remainder == 0 else None
    row = profile_row(f"{name} ({method})", wall, accepted, rejected, run.nfev, run.njev, run.nlu)
    return {"row": row, "final_spin": oracle.spin(run.y[:, -1])}


def case(
    model_name: str, t_end: float, rtol: float, atol: float, repeats: int, quick: bool
) -> dict:
    """One case: celtstone, careful SciPy and (unless ``quick``) naive SciPy."""
    title = f"{model_name}, Kane & Levinson body, w3 = -5 rad/s, {t_end:g} s, rtol {rtol:g}, "
    title += f"atol {atol:g}"
    if model_name == "hybrid":
        title += ", f = 0.35, eps = 1 mm (stick-slip contact, celtstone only)"
    elif model_name == "sliding":
        title += ", f = 0.35, eps = 1 mm"
    runs = {"celtstone": run_celtstone(model_name, t_end, rtol, atol, repeats)}
    if model_name == "rolling":  # the baselines' method, for a like-for-like ratio
        runs["celtstone_dop853"] = run_celtstone(model_name, t_end, rtol, atol, repeats, "dop853")
    if model_name != "hybrid":
        repeats_careful = 3 if model_name == "rolling" else 1  # sliding: ~1 min a run
        runs["careful_scipy"] = run_scipy(
            careful, "careful SciPy", model_name, t_end, rtol, atol, repeats_careful
        )
        if not quick:
            runs["naive_scipy"] = run_scipy(oracle, "naive SciPy", model_name, t_end, rtol, atol, 1)
    engine_time = runs["celtstone"]["row"]["wall_s"]
    result: dict[str, Any] = {
        "case": title,
        "model": model_name,
        "t_end": t_end,
        "rtol": rtol,
        "atol": atol,
        "celtstone_s": engine_time,
        "steps": runs["celtstone"]["row"]["n_accepted"],
        "final_spin": {key: run["final_spin"] for key, run in runs.items()},
        "profile": [run["row"] for run in runs.values()],
    }
    if "careful_scipy" in runs:
        result["careful_scipy_s"] = runs["careful_scipy"]["row"]["wall_s"]
        result["ratio_careful"] = result["careful_scipy_s"] / engine_time
        if "celtstone_dop853" in runs:
            dop853_time = runs["celtstone_dop853"]["row"]["wall_s"]
            result["ratio_careful_dop853"] = result["careful_scipy_s"] / dop853_time
    if "naive_scipy" in runs:
        result["scipy_numpy_s"] = runs["naive_scipy"]["row"]["wall_s"]
        result["ratio"] = result["scipy_numpy_s"] / engine_time
        if "celtstone_dop853" in runs:
            result["ratio_dop853"] = result["scipy_numpy_s"] / dop853_time
    return result


def print_case(r: dict) -> None:
    print(r["case"])
    if "ratio" in r:
        print(f"  naive SciPy / celtstone    {r['ratio']:8.1f} x")
    if "ratio_careful" in r:
        print(f"  careful SciPy / celtstone  {r['ratio_careful']:8.1f} x")
    for key, baseline in (("ratio_dop853", "naive"), ("ratio_careful_dop853", "careful")):
        if key in r:
            print(f"  {baseline} SciPy / celtstone's DOP853 (their method) {r[key]:8.1f} x")
    spins = ", ".join(f"{name} {value:.9f}" for name, value in r["final_spin"].items())
    print(f"  final spin [rad/s]: {spins}")
    header = (
        f"  {'implementation':<30} {'accepted':>9} {'rejected':>9} {'nfev':>9} {'njev':>7} "
        f"{'nlu':>7} {'wall [s]':>9} {'us/step':>8}"
    )
    print(header)
    for row in r["profile"]:
        rejected = "n/a" if row["n_rejected"] is None else str(row["n_rejected"])
        print(
            f"  {row['implementation']:<30} {row['n_accepted']:>9} {rejected:>9} "
            f"{row['nfev']:>9} {row['njev']:>7} {row['nlu']:>7} {row['wall_s']:>9.4f} "
            f"{row['us_per_step']:>8.2f}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--sliding", action="store_true", help="also the 10 s sliding case")
    parser.add_argument(
        "--quick",
        action="store_true",
        help="skip the naive SciPy oracle (minutes per case); report the careful ratio only",
    )
    args = parser.parse_args()
    results = [case("rolling", 50.0, 1e-11, 1e-12, repeats=5, quick=args.quick)]
    if args.sliding:
        results.append(case("sliding", 10.0, 1e-8, 1e-12, repeats=3, quick=args.quick))
    results.append(case("hybrid", 5.0, 1e-8, 1e-12, repeats=3, quick=args.quick))
    machine = (
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}"
    )
    date = datetime.date.today().isoformat()
    if args.json:
        print(json.dumps({"machine": machine, "date": date, "results": results}, indent=2))
        return
    print(f"machine: {machine}; {date}")
    print(
        "wall: celtstone best of 5 (sliding, hybrid 3), careful SciPy best of 3 (sliding 1), "
        "naive SciPy 1 run;"
    )
    print("us/step: wall time per accepted step")
    for r in results:
        print()
        print_case(r)


if __name__ == "__main__":
    from benchmarks._page import recorded

    with recorded("bench_simulate", "One run: celtstone against plain SciPy"):
        main()
