"""Batches of runs by ``simulate`` on the CPU and by ``simulate_many`` in numba's CUDA
simulator, for tests/test_simulate_many_cuda.py.

Run as ``NUMBA_ENABLE_CUDASIM=1 python tests/simulate_cuda_sample.py DIR CASE`` (the
variable must be set before numba is imported, hence a process of its own), CASE a key
of ``CASES``. Writes ``DIR/runs.pickle``: for each run of the case, what ``simulate``
made of it and what ``simulate_many(..., device="cuda")`` made of it (every variable of
its dataset, its attributes, status, message, stop time, smallest normal force,
statistics, summary, and the warnings each warned), or the error each raised. Exits 77
where the simulator is unavailable, saying why.

Each case runs different bodies, settings and starts, each run sampled at its own times
(``sample_times`` of shape (runs, m), as a fit's runs start at their own release offset),
over 1 s or less:

* rolling with Verner's pair, and a run that cannot be made (a rolling model started
  sliding), kept in its place (``errors="keep"``);
* sliding without stick phases with ``auto``: Zhuravlev's Padé law on the paper's disk,
  the static load (the paper's first approximation: the friction-bound warning);
* sliding with ``auto`` on the Hertz ellipse (E = 3 GPa, ν = 0.35) with the exact law and
  the dynamic load;
* the stick–slip contact with the realistic contact (``reproduce.study.REALISTIC_CONTACT``:
  the Hertz ellipse, the exact law, the dynamic load, rolling resistance 10 µm): a run of
  40 phases with 20 rejected captures, one that lifts off, one on another body.

``launched`` in the report counts the runs that the simulated GPU ran
(``batch_cuda.run_whole``), so that a batch that ran on the CPU instead cannot pass.
"""

from __future__ import annotations

import pickle
import sys
import warnings
from pathlib import Path
from typing import Any

T_END = 1.0  # s, every run's
SAMPLES = 61  # per run
# each run's first sample time [s]: its own times, as a fit's runs at their release offsets
OFFSETS = (0.0, 0.07, 0.19)

# (body, initial spin [rad/s], Euler angles [deg], slip velocity [m/s]) of each run of a
# case; the models below
STARTS = {
    "rolling": [
        ("kane_levinson_1982", -5.0, (0.5, 0.5), (0.0, 0.0)),
        ("toy_rattleback_10cm", 8.0, (2.0, 4.0), (0.0, 0.0)),
        ("kane_levinson_1982", -5.0, (0.5, 0.5), (0.01, 0.0)),  # sliding: refused, kept
    ],
    "sliding": [
        ("kane_levinson_1982", -6.0, (5.0, 5.0), (0.0, 0.0)),
        ("printed_stone_12cm", -10.0, (3.0, 8.0), (0.002, 0.0)),
    ],
    "sliding_ellipse_exact_dynamic": [
        ("kane_levinson_1982", -8.0, (5.0, 5.0), (0.0, 0.0)),
        ("printed_stone_12cm", 4.0, (10.0, 2.0), (0.0, 0.0)),
    ],
    "stick_slip": [
        ("kane_levinson_1982", 0.0, (5.0, 0.5), (0.0, 0.0)),  # 40 phases, 20 rejected
        ("kane_levinson_1982", -2.0, (20.0, 20.0), (0.0, 0.0)),  # lifts off
        ("printed_stone_12cm", -6.0, (5.0, 5.0), (0.0, 0.0)),
    ],
}


def models(case: str) -> list[Any]:
    """The model of each run of ``case`` (imported here: after the simulator is chosen)."""
    import celtstone as cs
    from celtstone.reproduce.study import REALISTIC_CONTACT

    if case == "rolling":
        return [cs.RollingModel(), cs.RollingModel(damping=1e-5), cs.RollingModel()]
    if case == "sliding":
        return [cs.SlidingModel(0.3, 1e-3), cs.SlidingModel(0.2, 2e-3, damping=1e-5)]
    if case == "sliding_ellipse_exact_dynamic":
        ellipse = {
            "contact_shape": "ellipse",
            "elastic_modulus": 3e9,
            "poisson_ratio": 0.35,
            "friction_law": "exact",
            "friction_load": "dynamic",
        }
        return [cs.SlidingModel(0.3, **ellipse), cs.SlidingModel(0.15, **ellipse)]
    realistic = {key: value for key, value in REALISTIC_CONTACT.items() if key != "contact"}
    return [
        cs.HybridModel(0.3, **realistic),
        cs.HybridModel(0.2, **realistic),
        cs.HybridModel(0.3, **realistic),
    ]


def runs(case: str) -> list[tuple[Any, Any, Any]]:
    """The (model, body, initial state) of each run of ``case``."""
    import celtstone as cs

    made = []
    for model, (body, spin, angles, slip) in zip(models(case), STARTS[case], strict=True):
        state = cs.InitialState(omega=(0.0, 0.0, spin), euler_angles=angles, slip_velocity=slip)
        made.append((model, cs.load_body(body), state))
    return made


def sample_times(count: int) -> Any:
    """Each run's sample times [s], shape (count, SAMPLES), from its own offset to
    T_END."""
    import numpy as np

    return np.stack([np.linspace(OFFSETS[i], T_END, SAMPLES) for i in range(count)])


def record(made: Any, caught: list[warnings.WarningMessage]) -> dict[str, Any]:
    """What the test compares of a run: its dataset's variables and attributes, its
    outcome and the warnings warned (or the error it raised)."""
    said = [f"{w.category.__name__}: {w.message}" for w in caught]
    if isinstance(made, Exception):
        return {"error": f"{type(made).__name__}: {made}", "warnings": said}
    dataset = made.dataset
    return {
        "variables": {name: dataset[name].values for name in dataset.variables},
        "attrs": dict(dataset.attrs),
        "status": made.status,
        "message": made.message,
        "t_stop": made.t_stop,
        "min_normal_force": made.min_normal_force,
        "statistics": dict(made.statistics),
        "summary": made.summary(),
        "warnings": said,
    }


def main() -> int:
    directory, case = Path(sys.argv[1]), sys.argv[2]
    from sweep_cuda_sample import start_simulator

    refused = start_simulator()
    if refused is not None:
        return refused
    import celtstone as cs
    from celtstone.errors import CeltstoneError
    from celtstone.simulation.integrate import simulate_many
    from celtstone.solvers import batch_cuda

    launched: list[int] = []
    run_whole = batch_cuda.run_whole

    def counted(launch: Any) -> Any:
        solutions = run_whole(launch)
        launched.append(len(solutions))
        return solutions

    batch_cuda.run_whole = counted  # type: ignore[assignment]

    batch = runs(case)
    times = sample_times(len(batch))
    cpu = []
    for (model, body, state), own_times in zip(batch, times, strict=True):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                made: Any = cs.simulate(model, body, state, T_END, sample_times=own_times)
            except CeltstoneError as error:
                made = error
        cpu.append(record(made, caught))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        made_on_gpu = simulate_many(batch, T_END, device="cuda", sample_times=times, errors="keep")
    gpu = [record(made, []) for made in made_on_gpu]
    said = [f"{w.category.__name__}: {w.message}" for w in caught]
    report = {"cpu": cpu, "gpu": gpu, "gpu_warnings": said, "launched": launched}
    (directory / "runs.pickle").write_bytes(pickle.dumps(report))
    return 0


if __name__ == "__main__":
    sys.exit(main())
