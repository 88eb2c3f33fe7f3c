"""Work-precision of celtstone against heyoka's Taylor integrator on the rolling model.

Kane & Levinson's ellipsoid, alpha = beta = 0.5 deg, omega = (0, 0, -5) rad/s, 50 s, 10 001
equally spaced output samples (celtstone ``n_samples=10001``; heyoka ``propagate_grid`` on
``np.linspace(0, 50, 10001)``). For each tolerance: wall time (best of 3), steps, and the
error of the spin omega.n at 10 s and at 50 s against a converged reference.

* celtstone: each of ``CELTSTONE_METHODS`` (Verner's 9(8) pair, the rolling model's default,
  and DOP853) with rtol = tol, atol = tol/10 (rtol 1e-14 is its smallest).
* heyoka: ``taylor_adaptive`` in double precision with tol = tol (heyoka's error control is
  relative here, since |omega| > 1). The rolling equations are written below as heyoka
  expressions from the oracle's equations (``tests/oracle/rattleback.py``: contact point
  r(n) = -Q n / sqrt(n.Q n) + h e3, Poisson dn/dt = n x omega, the rolling Euler equation
  about the contact point solved by its adjugate), not from celtstone's kernels, and checked
  against the oracle's right-hand side at random states before any timing. The one-time
  build (Taylor decomposition and LLVM compilation) is timed separately, per tolerance
  because the Taylor order follows from it: cold (heyoka's on-disk cache turned off, its
  in-memory cache cleared) and cached (built again in the same process). A timed run
  resets time and state only.
* Reference: heyoka in quadruple precision (``real128``, compact mode, tol 1e-24), started
  from the same double-precision initial state; ``--reference longdouble`` uses 80-bit
  long double (tol = its epsilon, ~1e-11 at 50 s instead of ~1e-19, a few seconds
  instead of about a minute).

The spin at 50 s (after the spin has reversed from -5 to +4.6 rad/s and back) is very
sensitive: rounding errors are amplified by about 1e7 to 1e8 (long double runs, epsilon
1e-19, differ from real128 by ~3e-11 there), so double-precision runs cannot get much
closer than ~1e-9 at 50 s, whatever the tolerance; at 10 s they reach ~1e-14.

``--ensemble`` adds the errors over ``ENSEMBLE``, eight initial states around this one
(tilts 0.3-0.8 deg, spins -4 to -6 rad/s), each against its own long double reference:
their RMS and median at 10 s and 50 s for every tolerance of both codes. One state's error
at 50 s depends on where in the rocking each code's error lands and can be ten times
smaller or larger at the next tolerance, so it cannot rank two codes; the ensemble's
median can (docs/decisions.md §45).
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

import heyoka as hy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import celtstone as cs
from tests.oracle import rattleback as oracle

TILT = (0.5, 0.5)
"""Kane & Levinson's initial Euler tilts alpha, beta [deg]."""
OMEGA0 = (0.0, 0.0, -5.0)
"""Initial angular velocity in body axes [rad/s]."""
T_END = 50.0
"""Simulated time [s]."""
N_SAMPLES = 10_001
"""Equally spaced output samples, t = 0 and t = T_END included."""
CHECK_TIMES = (10.0, 50.0)
"""Times at which the spin error is reported [s]."""
CELTSTONE_TOLERANCES = (1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14)
"""celtstone rtol values (atol = rtol/10); 1e-14 is the smallest rtol it accepts."""
CELTSTONE_METHODS = ("vern9", "dop853")
"""celtstone's explicit methods, the rolling model's default first."""
HEYOKA_TOLERANCES = (1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15, 1e-16)
"""heyoka tol values in double precision."""
REPEATS = 3
"""Timed runs per setting; the smallest wall time is reported."""
ENSEMBLE = (
    (*TILT, OMEGA0[2]),
    (0.3, 0.6, -5.0),
    (0.6, 0.3, -5.0),
    (0.5, 0.5, -4.0),
    (0.5, 0.5, -6.0),
    (0.4, 0.4, -5.5),
    (0.7, 0.5, -4.5),
    (0.5, 0.8, -5.0),
)
"""Initial states of ``--ensemble``: (alpha [deg], beta [deg], omega3 [rad/s]), omega1 =
omega2 = 0; the first is the timed case."""


def best_time(function: Callable[[], Any], repeats: int = REPEATS) -> tuple[float, Any]:
    """Smallest wall time of ``repeats`` calls [s], and the last call's result."""
    times = []
    result = None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return min(times), result


# --------------------------------------------------------------------------- heyoka system


def rolling_equations(body: dict[str, Any]) -> tuple[list[Any], list[Any]]:
    """The rolling model (no damping) as heyoka expressions: (variables, right-hand sides).

    State (n1, n2, n3, w1, w2, w3), the oracle's first six components (W stays 0 without
    damping). With Q = diag(a^2, b^2, c^2), s = sqrt(n.Q n):
    r = -Q n/s + h e3, dr/dt = -Q dn/dt / s + Q n (Q n.dn/dt)/s^3, dn/dt = n x omega,
    (I + m(|r|^2 E - r r^T)) domega/dt = -omega x I omega
    + m r x (g n - omega x dr/dt - omega x (omega x r)).
    """
    m, g = float(body["mass"]), float(body["gravity"])
    inertia = np.asarray(body["inertia"], dtype=float)
    i11, i12, i13 = (float(x) for x in inertia[0])
    i22, i23, i33 = float(inertia[1, 1]), float(inertia[1, 2]), float(inertia[2, 2])
    q1, q2, q3 = (float(x) ** 2 for x in body["semi_axes"])
    h = float(body["com_offset"])
    n1, n2, n3, w1, w2, w3 = hy.make_vars("n1", "n2", "n3", "w1", "w2", "w3")
    # Poisson
    nd1 = n2 * w3 - n3 * w2
    nd2 = n3 * w1 - n1 * w3
    nd3 = n1 * w2 - n2 * w1
    # contact point and its rate
    p1, p2, p3 = q1 * n1, q2 * n2, q3 * n3
    inv_s = 1.0 / hy.sqrt(n1 * p1 + n2 * p2 + n3 * p3)
    r1, r2, r3 = -p1 * inv_s, -p2 * inv_s, h - p3 * inv_s
    u = (p1 * nd1 + p2 * nd2 + p3 * nd3) * inv_s**3
    rd1 = p1 * u - q1 * nd1 * inv_s
    rd2 = p2 * u - q2 * nd2 * inv_s
    rd3 = p3 * u - q3 * nd3 * inv_s
    # omega x rdot + omega x (omega x r)
    wr = w1 * r1 + w2 * r2 + w3 * r3
    ww = w1 * w1 + w2 * w2 + w3 * w3
    f1 = w2 * rd3 - w3 * rd2 + w1 * wr - r1 * ww
    f2 = w3 * rd1 - w1 * rd3 + w2 * wr - r2 * ww
    f3 = w1 * rd2 - w2 * rd1 + w3 * wr - r3 * ww
    # right-hand side of the Euler equation about the contact point
    l1 = i11 * w1 + i12 * w2 + i13 * w3
    l2 = i12 * w1 + i22 * w2 + i23 * w3
    l3 = i13 * w1 + i23 * w2 + i33 * w3
    v1, v2, v3 = g * n1 - f1, g * n2 - f2, g * n3 - f3
    b1 = w3 * l2 - w2 * l3 + m * (r2 * v3 - r3 * v2)
    b2 = w1 * l3 - w3 * l1 + m * (r3 * v1 - r1 * v3)
    b3 = w2 * l1 - w1 * l2 + m * (r1 * v2 - r2 * v1)
    # I + m(|r|^2 E - r r^T), inverted by its adjugate
    a11 = i11 + m * (r2 * r2 + r3 * r3)
    a22 = i22 + m * (r1 * r1 + r3 * r3)
    a33 = i33 + m * (r1 * r1 + r2 * r2)
    a12 = i12 - m * r1 * r2
    a13 = i13 - m * r1 * r3
    a23 = i23 - m * r2 * r3
    c11 = a22 * a33 - a23 * a23
    c12 = a13 * a23 - a12 * a33
    c13 = a12 * a23 - a13 * a22
    c22 = a11 * a33 - a13 * a13
    c23 = a12 * a13 - a11 * a23
    c33 = a11 * a22 - a12 * a12
    inv_det = 1.0 / (a11 * c11 + a12 * c12 + a13 * c13)
    variables = [n1, n2, n3, w1, w2, w3]
    rhs = [
        nd1,
        nd2,
        nd3,
        (c11 * b1 + c12 * b2 + c13 * b3) * inv_det,
        (c12 * b1 + c22 * b2 + c23 * b3) * inv_det,
        (c13 * b1 + c23 * b2 + c33 * b3) * inv_det,
    ]
    return variables, rhs


def check_equations(variables: list[Any], rhs: list[Any], body: dict[str, Any]) -> float:
    """Largest difference from the oracle's right-hand side at 20 random states, relative to
    the largest component; raises above 1e-12."""
    function = hy.cfunc(rhs, variables)
    rng = np.random.default_rng(2024)
    worst = 0.0
    for _ in range(20):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        y = np.concatenate([n, rng.normal(scale=5.0, size=3), [0.0]])
        expected = oracle.rhs_rolling(0.0, y, body)[:6]
        actual = function(y[:6])
        worst = max(worst, float(np.max(np.abs(actual - expected)) / np.max(np.abs(expected))))
    if worst > 1e-12:
        raise RuntimeError(f"heyoka right-hand side differs from the oracle's by {worst:.3g}")
    return worst


# --------------------------------------------------------------------------- runs


def spin_at(times: np.ndarray, spin: np.ndarray) -> list[float]:
    """The spin at each of CHECK_TIMES, which must be sample times."""
    values = []
    for t in CHECK_TIMES:
        index = int(np.argmin(np.abs(times - t)))
        if abs(times[index] - t) > 1e-12:
            raise RuntimeError(f"no sample at t = {t} s")
        values.append(float(spin[index]))
    return values


def simulate_case(rtol: float, method: str, tilt: Any = TILT, omega: Any = OMEGA0) -> cs.Trajectory:
    """celtstone's rolling run of the case from ``tilt`` [deg] and ``omega`` [rad/s] with
    ``method``, at rtol, atol = rtol/10, with N_SAMPLES samples over T_END."""
    return cs.simulate(
        cs.model_from_name("rolling"),
        cs.load_body("kane_levinson_1982"),
        cs.InitialState(omega, tilt),
        T_END,
        rtol=rtol,
        atol=rtol / 10.0,
        n_samples=N_SAMPLES,
        method=method,
    )


def trajectory_spins(trajectory: cs.Trajectory) -> list[float]:
    """The spin at CHECK_TIMES of a finished run."""
    trajectory.raise_for_status()
    data = trajectory.dataset
    return spin_at(data["time"].values, data["spin"].values)


def run_celtstone(rtol: float, method: str) -> dict[str, Any]:
    """celtstone's ``method`` at rtol, atol = rtol/10 (compiled beforehand): best-of-3 wall
    time."""
    wall, trajectory = best_time(lambda: simulate_case(rtol, method))
    spins = trajectory_spins(trajectory)
    stats = trajectory.statistics
    return {
        "code": f"celtstone {method}",
        "tolerance": f"rtol {rtol:.0e}, atol {rtol / 10:.0e}",
        "tol": rtol,
        "build_s": None,
        "cached_build_s": None,
        "wall_s": wall,
        "steps": stats["n_accepted"],
        "rejected": stats["n_rejected"],
        "spin": spins,
    }


def grid_spin(result: tuple) -> np.ndarray:  # type: ignore[type-arg]
    """omega . n on the grid from ``propagate_grid``'s ``result``, which must have reached the
    grid's end."""
    if result[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"heyoka stopped early: {result[0]}")
    states = result[-1]
    return (states[:, 0:3] * states[:, 3:6]).sum(axis=1)


def heyoka_run(
    variables: list[Any],
    rhs: list[Any],
    tol: Any,
    fp_type: Any,
    compact_mode: bool,
    repeats: int,
) -> dict[str, Any]:
    """Build heyoka's integrator (timed once), then ``propagate_grid`` (best of ``repeats``)."""
    y0 = oracle.initial_state(*TILT, OMEGA0, "rolling")[:6]
    grid = np.linspace(0.0, T_END, N_SAMPLES)
    if fp_type is hy.real128:  # exact conversions of the double-precision start and grid
        y0_fp = np.array([hy.real128(float(v)) for v in y0])
        grid_fp = np.array([hy.real128(float(v)) for v in grid])
    else:
        y0_fp, grid_fp = np.asarray(y0, dtype=fp_type), np.asarray(grid, dtype=fp_type)

    def build() -> Any:
        return hy.taylor_adaptive(
            list(zip(variables, rhs, strict=True)),
            y0_fp,
            tol=tol,
            fp_type=fp_type,
            compact_mode=compact_mode,
        )

    hy.llvm_state.clear_memcache()  # a cold build (main turns the on-disk cache off)
    start = time.perf_counter()
    integrator = build()
    cold = time.perf_counter() - start
    cached, _ = best_time(build, 1)  # again, from heyoka's in-memory cache of compiled code

    def run() -> tuple:  # type: ignore[type-arg]
        integrator.time = grid_fp[0]
        integrator.state[:] = y0_fp
        return integrator.propagate_grid(grid_fp)

    wall, result = best_time(run, repeats)
    steps, spin = result[3], grid_spin(result)
    return {
        "build_s": cold,
        "cached_build_s": cached,
        "wall_s": wall,
        "steps": int(steps),
        "order": int(integrator.order),
        "spin": spin_at(grid, spin),
        "spin_text": [str(spin[int(np.argmin(np.abs(grid - t)))]) for t in CHECK_TIMES],
    }


def run_heyoka(variables: list[Any], rhs: list[Any], tol: float) -> dict[str, Any]:
    """heyoka in double precision at ``tol``, non-compact mode (the fastest to run)."""
    out = heyoka_run(variables, rhs, tol, float, compact_mode=False, repeats=REPEATS)
    return {
        "code": "heyoka",
        "tolerance": f"tol {tol:.0e} (order {out['order']})",
        "tol": tol,
        "build_s": out["build_s"],
        "cached_build_s": out["cached_build_s"],
        "wall_s": out["wall_s"],
        "steps": out["steps"],
        "rejected": 0,  # Taylor steps are chosen, never rejected
        "spin": out["spin"],
    }


def reference(variables: list[Any], rhs: list[Any], kind: str) -> dict[str, Any]:
    """The converged spins: heyoka in real128 (tol 1e-24) or long double (tol = epsilon)."""
    if kind == "real128":
        fp_type, tol, label = hy.real128, hy.real128("1e-24"), "real128, tol 1e-24"
    else:
        fp_type, tol = np.longdouble, np.finfo(np.longdouble).eps
        label = f"long double, tol {float(tol):.2e}"
    out = heyoka_run(variables, rhs, tol, fp_type, compact_mode=True, repeats=1)
    return {"label": f"heyoka {label}, compact mode", **out}


def heyoka_ensemble_spins(
    variables: list[Any], rhs: list[Any], tol: Any, fp_type: Any, compact_mode: bool
) -> np.ndarray:
    """The spin at CHECK_TIMES of each ENSEMBLE state, shape (len(ENSEMBLE), 2): one heyoka
    integrator built at ``tol``, reset to each state in turn."""
    grid = np.linspace(0.0, T_END, N_SAMPLES)
    grid_fp = np.asarray(grid, dtype=fp_type)
    starts = [
        np.asarray(oracle.initial_state(a, b, (0.0, 0.0, w), "rolling")[:6], dtype=fp_type)
        for a, b, w in ENSEMBLE
    ]
    integrator = hy.taylor_adaptive(
        list(zip(variables, rhs, strict=True)),
        starts[0],
        tol=tol,
        fp_type=fp_type,
        compact_mode=compact_mode,
    )
    spins = []
    for start in starts:
        integrator.time = grid_fp[0]
        integrator.state[:] = start
        spin = grid_spin(integrator.propagate_grid(grid_fp))
        spins.append(spin_at(grid, np.asarray(spin, dtype=float)))
    return np.array(spins)


def celtstone_ensemble_spins(rtol: float, method: str) -> np.ndarray:
    """The spin at CHECK_TIMES of each ENSEMBLE state, celtstone's ``method`` at rtol, atol =
    rtol/10."""
    return np.array(
        [
            trajectory_spins(simulate_case(rtol, method, (a, b), (0.0, 0.0, w)))
            for a, b, w in ENSEMBLE
        ]
    )


def ensemble_rows(variables: list[Any], rhs: list[Any]) -> list[dict[str, Any]]:
    """RMS and median over ENSEMBLE of each tolerance's spin error at CHECK_TIMES, against
    a long double reference per state."""
    eps = np.finfo(np.longdouble).eps
    reference_spins = heyoka_ensemble_spins(variables, rhs, eps, np.longdouble, True)
    runs = [
        (f"celtstone {method}", f"rtol {r:.0e}", celtstone_ensemble_spins(r, method))
        for method in CELTSTONE_METHODS
        for r in CELTSTONE_TOLERANCES
    ]
    runs += [
        ("heyoka", f"tol {t:.0e}", heyoka_ensemble_spins(variables, rhs, t, float, False))
        for t in HEYOKA_TOLERANCES
    ]
    rows = []
    for code, tolerance, spins in runs:
        errors = np.abs(spins - reference_spins)
        rows.append(
            {
                "code": code,
                "tolerance": tolerance,
                "rms": np.sqrt(np.mean(errors**2, axis=0)).tolist(),
                "median": np.median(errors, axis=0).tolist(),
            }
        )
    return rows


# --------------------------------------------------------------------------- report


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument(
        "--reference",
        choices=("real128", "longdouble"),
        default="real128",
        help="precision of the reference run (real128: about a minute; longdouble: seconds)",
    )
    parser.add_argument(
        "--ensemble",
        action="store_true",
        help="also the errors over ENSEMBLE's eight initial states (about a minute)",
    )
    args = parser.parse_args()

    # cold builds: heyoka would otherwise reuse code compiled by an earlier run (on disk)
    hy.llvm_state.set_diskcache_enabled(False)
    body = oracle.kane_levinson_body()
    variables, rhs = rolling_equations(body)
    rhs_check = check_equations(variables, rhs, body)
    ref = reference(variables, rhs, args.reference)

    with warnings.catch_warnings():
        warnings.simplefilter("error", cs.PlausibilityWarning)  # the case must be plausible
        rows = []
        for method in CELTSTONE_METHODS:
            run_celtstone(1e-9, method)  # compile or load the numba cache
            rows += [run_celtstone(rtol, method) for rtol in CELTSTONE_TOLERANCES]
    rows += [run_heyoka(variables, rhs, tol) for tol in HEYOKA_TOLERANCES]
    for row in rows:
        row["spin_error"] = [abs(s - r) for s, r in zip(row["spin"], ref["spin"], strict=True)]
    ensemble = ensemble_rows(variables, rhs) if args.ensemble else []

    tightest = {row["code"]: row for row in rows}  # the last row of each code
    default = tightest[f"celtstone {CELTSTONE_METHODS[0]}"]
    agreement = [
        abs(a - b) for a, b in zip(default["spin"], tightest["heyoka"]["spin"], strict=True)
    ]
    machine = (
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}, heyoka {hy.__version__}"
    )
    date = datetime.date.today().isoformat()
    if args.json:
        print(
            json.dumps(
                {
                    "machine": machine,
                    "date": date,
                    "case": "rolling, Kane & Levinson body, alpha = beta = 0.5 deg, "
                    f"omega = (0, 0, -5) rad/s, {T_END:g} s, {N_SAMPLES} samples",
                    "rhs_check_max_relative_difference": rhs_check,
                    "reference": ref,
                    "tightest_agreement": dict(zip(map(str, CHECK_TIMES), agreement, strict=True)),
                    "rows": rows,
                    "ensemble": {"states": ENSEMBLE, "rows": ensemble},
                },
                indent=2,
            )
        )
        return

    print(f"machine: {machine}; {date}")
    print(
        f"rolling, Kane & Levinson body, alpha = beta = 0.5 deg, omega = (0, 0, -5) rad/s, "
        f"{T_END:g} s, {N_SAMPLES} output samples; wall: best of {REPEATS}"
    )
    print(f"heyoka right-hand side vs the oracle's: {rhs_check:.1e} relative (20 random states)")
    print(
        f"reference ({ref['label']}, build {ref['build_s']:.2f} s, run {ref['wall_s']:.1f} s, "
        f"{ref['steps']} steps):"
    )
    for t, text in zip(CHECK_TIMES, ref["spin_text"], strict=True):
        print(f"  spin({t:g} s) = {text} rad/s")
    print(
        f"tightest double runs (celtstone {CELTSTONE_METHODS[0]} {default['tolerance']}, heyoka "
        f"{tightest['heyoka']['tolerance']}) differ by "
        + ", ".join(f"{d:.1e} at {t:g} s" for t, d in zip(CHECK_TIMES, agreement, strict=True))
    )
    print()
    header = (
        f"{'code':<16} {'tolerance':<26} {'build [s]':>9} {'cached':>7} {'wall [s]':>9} "
        f"{'steps':>7} {'rejected':>8} {'|err| 10 s':>11} {'|err| 50 s':>11}"
    )
    print(header)
    for row in rows:
        build = "" if row["build_s"] is None else f"{row['build_s']:.2f}"
        cached = "" if row["cached_build_s"] is None else f"{row['cached_build_s']:.3f}"
        errors = " ".join(f"{e:>11.2e}" for e in row["spin_error"])
        print(
            f"{row['code']:<16} {row['tolerance']:<26} {build:>9} {cached:>7} "
            f"{row['wall_s']:>9.4f} {row['steps']:>7} {row['rejected']:>8} {errors}"
        )
    if ensemble:
        print()
        print(
            f"spin error over {len(ENSEMBLE)} initial states (alpha, beta [deg], omega3 "
            "[rad/s]): " + ", ".join(f"({a:g}, {b:g}, {w:g})" for a, b, w in ENSEMBLE)
        )
        print(
            f"{'code':<16} {'tolerance':<26} {'RMS 10 s':>10} {'median 10 s':>11} "
            f"{'RMS 50 s':>10} {'median 50 s':>11}"
        )
        for row in ensemble:
            print(
                f"{row['code']:<16} {row['tolerance']:<26} {row['rms'][0]:>10.2e} "
                f"{row['median'][0]:>11.2e} {row['rms'][1]:>10.2e} {row['median'][1]:>11.2e}"
            )


if __name__ == "__main__":
    from benchmarks._page import recorded

    with recorded("bench_precision", "Work and precision against heyoka"):
        main()
