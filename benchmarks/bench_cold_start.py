"""Cold starts: a user's first run of each model after installing, and the same run again.

Each row runs ``celtstone run ... --json`` (or ``celtstone compile``) in a new process
with its own empty numba cache directory (``NUMBA_CACHE_DIR``), as a first run after
``pip install`` does, then once more in a new process on the cache it left (a cached
run). Rows:

- first rolling run: Kane & Levinson's stone, ``--model rolling --t-end 1`` (vern9);
- first sliding run: ``--model sliding --t-end 1`` (Zhuravlev's Padé law, the disk, auto);
- first stick–slip run with the realistic contact: ``--contact hybrid``, the Hertz
  ellipse (E = 3 GPa, ν = 0.35), the exact law, a rolling-friction length of 1e-5 m;
- ``celtstone compile``: every driver a run, a stick–slip run and a sweep call, and the
  rolling model's own loop for vern9 (its cached row loads them).

Printed per row: CPU time (user + system, of the process and its children, which load on
the shared machine disturbs far less than wall time), wall time, and the load average
before the run. Targets (issue 39, 2-core machine): 15 s, 30 s and 45 s of CPU for the
three first runs; a cached run no slower than before (about 1 s).

Run with ``make bench`` or ``python benchmarks/bench_cold_start.py [ROW ...]``.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # benchmarks._page

SOURCE = Path(__file__).resolve().parents[1] / "src"
REALISTIC = (
    "--contact hybrid --contact-shape ellipse --friction-law exact "
    "--elastic-modulus 3e9 --poisson-ratio 0.35 --rolling-resistance 1e-5"
)
ROWS = {
    "rolling": "run --model rolling --t-end 1 --json",
    "sliding": "run --model sliding --t-end 1 --json",
    "stick-slip": "run --model sliding --t-end 1 --json " + REALISTIC,
    "compile": "compile",
}


def run_once(arguments: str, cache: str) -> tuple[float, float]:
    """(CPU time [s], wall time [s]) of one ``celtstone`` command in a new process."""
    environment = dict(os.environ, NUMBA_CACHE_DIR=cache)
    environment["PYTHONPATH"] = os.pathsep.join(
        [str(SOURCE), *filter(None, [environment.get("PYTHONPATH")])]
    )
    command = [sys.executable, "-m", "celtstone", *arguments.split()]
    start = time.perf_counter()
    process = subprocess.Popen(
        command, env=environment, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    )
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    errors = process.stderr.read().decode() if process.stderr else ""
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"celtstone {arguments} failed:\n{errors}")
    return usage.ru_utime + usage.ru_stime, wall


def main(names: list[str]) -> None:
    print(f"{'first run':<12} {'cold CPU':>9} {'cold wall':>10} {'cached CPU':>11} {'load':>5}")
    for name in names or list(ROWS):
        with tempfile.TemporaryDirectory(prefix="celtstone-cold-") as cache:
            load = os.getloadavg()[0]
            cold_cpu, cold_wall = run_once(ROWS[name], cache)
            cached_cpu, _ = run_once(ROWS[name], cache)
        print(
            f"{name:<12} {cold_cpu:8.1f}s {cold_wall:9.1f}s {cached_cpu:10.2f}s {load:5.1f}",
            flush=True,
        )


if __name__ == "__main__":
    from benchmarks._page import recorded

    with recorded("bench_cold_start", "Cold starts: a first run with an empty numba cache"):
        main(sys.argv[1:])
