"""Fitting speed: three parameters of a 10 s record at 100 Hz from one start.

The record: Kane & Levinson's stone, sliding model (f = 0.3, ε = 1 mm, ω0 = (0, 0, -5)
rad/s, Euler angles 0.5°, 0.5°), its spin sampled at 100 Hz for 10 s with Gaussian noise
of 0.05 rad/s (seed 0). Free: f, ε and the initial spin, started at f = 0.2, ε = 1.4 mm
and the record's first spin sample.

Printed: runs (of which speculative Jacobian columns wasted on rejected steps), wall time,
CPU time and time per run of ``celtstone.fit`` on one thread per core with the Jacobian's
columns started beside each residual (the default), on one thread per core without that,
and on one thread (the serial-vs-parallel comparison); then the plain baseline: SciPy's
``least_squares`` with its own serial 2-point Jacobian around ``cs.simulate``, same
bounds, scales and tolerances. Each line gives the load average before it and the CPU
time other processes took meanwhile: the machine is shared. Target (issue 14): under 20 s
on the 2-core machine.

Run with ``make bench`` or ``python benchmarks/bench_fit.py``.
"""

from __future__ import annotations

import os
import sys
import time
import warnings
from functools import partial
from pathlib import Path
from unittest import mock

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import celtstone as cs
from celtstone.fitting import solve
from celtstone.fitting.runs import Runs
from celtstone.fitting.solve import FIT_ATOL, FIT_RTOL

STATE = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
TRUTH = {"friction_coefficient": 0.3, "contact_radius": 1e-3}
FREE = ("friction_coefficient", "contact_radius", "initial_spin")
START = {"friction_coefficient": 0.2, "contact_radius": 1.4e-3}
DURATION, RATE, NOISE = 10.0, 100.0, 0.05


def record(body: cs.Body) -> cs.Record:
    times = np.round(np.arange(0.0, DURATION + 0.5 / RATE, 1.0 / RATE), 10)
    run = cs.simulate(cs.SlidingModel(**TRUTH), body, STATE, DURATION, sample_times=times)
    spin = run.samples.values("spin")
    return cs.make_record(
        times, {"spin": spin + np.random.default_rng(0).normal(0, NOISE, spin.size)}
    )


def machine_cpu() -> float:
    """CPU time [s] all processes on the machine have used since boot (Linux; else NaN)."""
    try:
        fields = Path("/proc/stat").read_text().split("\n", 1)[0].split()[1:]
    except OSError:
        return float("nan")
    user, nice, system, _idle, _iowait, irq, softirq, steal = map(int, fields[:8])
    return (user + nice + system + irq + softirq + steal) / os.sysconf("SC_CLK_TCK")


def fitted(
    body: cs.Body, data: cs.Record, workers: int, speculate: bool
) -> tuple[cs.FitResult, float, float, float]:
    """The fit, its wall time [s], this process's CPU time [s] (all threads) and other
    processes' CPU time meanwhile [s]; without ``speculate`` the Jacobian's columns wait
    for ``jac`` (the fit's ``Runs`` replaced)."""
    with mock.patch.object(solve, "Runs", partial(Runs, speculate=speculate)):
        began, cpu, machine = time.perf_counter(), time.process_time(), machine_cpu()
        result = cs.fit(data, body, "sliding", FREE, start=START, workers=workers)
        cpu = time.process_time() - cpu
        return result, time.perf_counter() - began, cpu, machine_cpu() - machine - cpu


def baseline(body: cs.Body, data: cs.Record, result: cs.FitResult) -> tuple[int, float, np.ndarray]:
    """Plain least_squares with SciPy's own 2-point Jacobian, serial."""
    from scipy.optimize import least_squares

    problem = result.problem
    measured = data.series["spin"]
    sigma = problem.sigma["spin"]
    runs = 0

    def residuals(x: np.ndarray) -> np.ndarray:
        nonlocal runs
        runs += 1
        model = cs.SlidingModel(friction_coefficient=x[0], contact_radius=x[1])
        vertical = STATE.vertical
        state = cs.InitialState((0.0, 0.0, x[2] / vertical[2]), STATE.euler_angles)
        run = cs.simulate(
            model, body, state, DURATION, sample_times=data.times, rtol=FIT_RTOL, atol=FIT_ATOL
        )
        return (run.samples.values("spin") - measured) / sigma

    began = time.perf_counter()
    plain = least_squares(
        residuals,
        problem.start,
        bounds=(problem.lower, problem.upper),
        x_scale=problem.scale,
        method="trf",
        ftol=1e-8,
        xtol=1e-6,
        gtol=1e-8,
    )
    return runs, time.perf_counter() - began, plain.x


def main() -> None:
    warnings.simplefilter("ignore", cs.FrictionBoundWarning)
    body = cs.load_body("kane_levinson_1982")
    data = record(body)
    cs.simulate(cs.SlidingModel(), body, STATE, 0.1)  # load the compiled kernels first
    cores = os.cpu_count() or 1
    print(f"fit of {', '.join(FREE)} to a {DURATION:g} s record at {RATE:g} Hz "
          f"({data.times.size} samples), one start, {cores} cores")  # fmt: skip
    results = {}
    variants = {
        "speculative": (cores, True),
        "not speculative": (cores, False),
        "serial": (1, False),
    }
    for variant, (workers, speculate) in variants.items():
        load = os.getloadavg()[0]  # the machine is shared: other jobs slow the threads
        result, wall, cpu, others = fitted(body, data, workers, speculate)
        results[variant] = (result, wall)
        values = ", ".join(
            f"{n} = {v:.6g} ± {e:.2g}"
            for n, v, e in zip(FREE, result.values, result.standard_errors, strict=True)
        )
        print(
            f"  celtstone.fit on {workers} thread(s), {variant}: {result.runs} runs "
            f"({result.speculative_runs_wasted} wasted), {wall:.2f} s wall, {cpu:.2f} s CPU, "
            f"{wall / result.runs:.3f} s/run (load average {load:.2f} before, other "
            f"processes {others:.1f} s CPU meanwhile); {values}"
        )
    parallel_wall = results["speculative"][1]
    for variant in ("not speculative", "serial"):
        wall = results[variant][1]
        print(f"  speculative / {variant} wall time: {parallel_wall / wall:.2f}")
    load = os.getloadavg()[0]
    runs, wall, x = baseline(body, data, results["speculative"][0])
    print(
        f"  plain least_squares (2-point Jacobian, serial): {runs} runs, {wall:.2f} s wall, "
        f"{wall / runs:.3f} s/run (load average {load:.2f} before); "
        f"f = {x[0]:.6g}, eps = {x[1]:.6g}"
    )
    print(f"  celtstone.fit / plain wall time: {parallel_wall / wall:.2f}")
    print(f"  target: under 20 s wall: {'met' if parallel_wall < 20.0 else 'NOT met'}")


if __name__ == "__main__":
    main()
