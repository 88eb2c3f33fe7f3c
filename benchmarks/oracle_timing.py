"""Wall time of the plain SciPy + NumPy oracle (tests/oracle) on Kane & Levinson's rolling run.

The baseline a researcher would write: ``solve_ivp`` (DOP853) on a NumPy right-hand side.
Run ``python benchmarks/oracle_timing.py`` to print the time of the 50 s run at rtol 1e-11.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tests.oracle import rattleback as oracle

TILT = (0.5, 0.5)
"""Kane & Levinson's initial Euler tilts alpha, beta [deg]."""
OMEGA0 = (0.0, 0.0, -5.0)
"""Initial angular velocity in body axes [rad/s]."""


def time_oracle_rolling(t_end: float = 50.0, rtol: float = 1e-11, atol: float = 1e-12) -> float:
    """Wall seconds of one rolling run of the oracle from t = 0 to ``t_end``.

    Kane & Levinson body, alpha = beta = 0.5 deg, omega0 = (0, 0, -5) rad/s, no damping,
    solve_ivp with DOP853, output at ``t_end`` only.
    """
    body = oracle.kane_levinson_body()
    y0 = oracle.initial_state(*TILT, OMEGA0, "rolling")
    start = time.perf_counter()
    run = oracle.simulate(
        "rolling", body, y0, t_end, t_eval=np.array([t_end]), rtol=rtol, atol=atol
    )
    elapsed = time.perf_counter() - start
    if not run.success:
        raise RuntimeError(f"oracle run failed: {run.message}")
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--t-end", type=float, default=50.0, help="simulated time [s]")
    parser.add_argument("--rtol", type=float, default=1e-11)
    parser.add_argument("--atol", type=float, default=1e-12)
    args = parser.parse_args()
    elapsed = time_oracle_rolling(args.t_end, args.rtol, args.atol)
    print(
        f"oracle rolling run, {args.t_end:g} s, rtol {args.rtol:g}, atol {args.atol:g}: "
        f"{elapsed:.2f} s wall"
    )


if __name__ == "__main__":
    main()
