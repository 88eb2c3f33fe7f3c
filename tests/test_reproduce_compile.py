"""A reproduction compiles its run loop once: the loop for every model and method before
its runs start (``reproduce.cases.compile_run_loop``), which its rolling and sliding runs
then take, rather than a loop of their own for their model.

Oracle: numba's "numba:compile" event, which fires on a cache miss only, in a new process
with an empty numba cache (a fresh clone's first ``make run``)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

_SCRIPT = """
import json
from numba.core import event

from celtstone.reproduce.cases import WARM_UP_TIME, compile_run_loop, compute_case
from celtstone.reproduce.study import study_for

LOOP = ("celtstone.solvers.driver", "integrate")  # the run loop
loops = []  # the stage in which each compile of the run loop happened


class Loops(event.Listener):
    stage = "warm-up"

    def on_start(self, ev):
        function = ev.data["dispatcher"].py_func
        if (function.__module__, function.__qualname__) == LOOP:
            loops.append(self.stage)

    def on_end(self, ev):
        pass


listener = Loops()
event.register("numba:compile", listener)
study = study_for("kane_levinson_1982")
compile_run_loop(study)
listener.stage = "rolling run"
compute_case(study, study.load_body(), study.rolling(), WARM_UP_TIME)
listener.stage = "sliding run"
compute_case(study, study.load_body(), study.sliding(0.35), WARM_UP_TIME)
print(json.dumps(loops))
"""


@pytest.mark.slow
def test_the_runs_take_the_loop_compiled_first(tmp_path: Path) -> None:
    """On an empty cache, the run loop compiles once, in ``compile_run_loop``; a rolling
    and a sliding run after it compile no loop of their own."""
    completed = subprocess.run(
        [sys.executable, "-c", _SCRIPT],
        capture_output=True,
        text=True,
        env=dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path)),
        check=False,
        timeout=1800,
    )
    assert completed.returncode == 0, completed.stderr[-3000:]
    assert json.loads(completed.stdout.splitlines()[-1]) == ["warm-up"]
