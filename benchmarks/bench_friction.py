"""Cost of one friction-law evaluation: exact closed forms against Zhuravlev's Padé law.

Calls ``kernels.friction.contact_friction`` (what the right-hand side calls) in a
compiled loop over random slips and spins spanning u = 1e-3 .. 1e3 and prints
nanoseconds per evaluation for each law and pressure. Run with
``python benchmarks/bench_friction.py``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from numba import njit

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from celtstone.kernels import layout
from celtstone.kernels.friction import contact_friction

CASES = {
    f"{law.name.lower()}, {pressure.name.lower()}": (law.value, pressure.value)
    for pressure in layout.ContactPressure
    for law in layout.FrictionLaw
}


@njit(cache=True)
def _sweep(slips: np.ndarray, spins: np.ndarray, law: int, pressure: int) -> float:
    total = 0.0
    for i in range(spins.size):
        slip = (slips[i, 0], slips[i, 1], slips[i, 2])
        force, moment = contact_friction(slip, spins[i], 1e-3, 1e-6, law, pressure)
        total += force[0] + moment
    return total


def main(count: int = 2_000_000, repeats: int = 5) -> None:
    rng = np.random.default_rng(0)
    spins = rng.uniform(1.0, 10.0, count) * rng.choice([-1.0, 1.0], count)
    u = 10.0 ** rng.uniform(-3.0, 3.0, count)
    directions = rng.normal(size=(count, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    slips = directions * (u * 1e-3 * np.abs(spins))[:, None]
    results = {}
    for name, (law, pressure) in CASES.items():
        _sweep(slips[:10], spins[:10], int(law), int(pressure))  # compile
        best = np.inf
        for _ in range(repeats):
            start = time.perf_counter()
            _sweep(slips, spins, int(law), int(pressure))
            best = min(best, time.perf_counter() - start)
        results[name] = best / count * 1e9
    base = results["pade, hertz"]
    for name, nanoseconds in results.items():
        print(f"{name:16s} {nanoseconds:6.1f} ns per evaluation ({nanoseconds / base:4.2f} x Padé)")


if __name__ == "__main__":
    main()
