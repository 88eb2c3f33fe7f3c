"""``compile_solvers`` / ``celtstone compile``: the warm-up compiles what runs and sweeps
call, and a second process loads it from numba's cache instead of compiling again."""

from __future__ import annotations

import json
import subprocess
import sys

from numba.core import event

import celtstone as cs
from celtstone.sweep import Sweep


class _Compiles(event.Listener):
    def __init__(self) -> None:
        self.names: list[str] = []

    def on_start(self, event: event.Event) -> None:
        self.names.append(str(event.data["dispatcher"]))

    def on_end(self, event: event.Event) -> None:
        pass


def test_after_the_warm_up_runs_and_sweeps_compile_nothing() -> None:
    """Other bodies, models, methods and contacts than the warm-up's reuse its drivers:
    the code paths differ by values (model, method, shape and law codes), not by types."""
    report = cs.compile_solvers()
    assert isinstance(report, cs.CompileReport) and report.seconds > 0.0
    compiles = _Compiles()
    with event.install_listener("numba:compile", compiles):
        body = cs.load_body("toy_rattleback_10cm")
        state = cs.InitialState((0.0, 0.0, 3.0), (1.0, -0.5))
        cs.simulate(cs.RollingModel(), body, state, 0.02).summary()
        cs.simulate(cs.SlidingModel(friction_coefficient=0.2), body, state, 0.02).summary()
        cs.simulate(
            cs.HybridModel(friction_law="exact"), body, state, 0.02, method="radau5"
        ).summary()
        Sweep({"friction_coefficient": [0.1, 0.3]}, model="sliding", t_end=0.02, body=body).run()
    assert compiles.names == []


def test_a_second_process_loads_the_cache() -> None:
    cs.compile_solvers()
    completed = subprocess.run(
        [sys.executable, "-m", "celtstone", "compile", "--json"],
        capture_output=True,
        text=True,
        check=True,
        timeout=600,
    )
    report = json.loads(completed.stdout)
    assert report["compiled_functions"] == 0, report
    assert 0.0 < report["seconds"] < 60.0
