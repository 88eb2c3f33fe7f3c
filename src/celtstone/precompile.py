"""Compile the solvers into numba's on-disk cache now, instead of on first use.

The compiled drivers (one run's integration loop, the stick–slip phase loop, the
sweep's batch) are compiled the first time they are called and then cached on disk
(``NUMBA_CACHE_DIR``, else ``__pycache__`` beside the sources): about 3 minutes of one
core after an install or an upgrade, 2–3 s to load afterwards. Numba compiles
per process, so parallel jobs started on a cold cache each compile the same drivers at
once; :func:`compile_solvers` pays the cost once, up front (``celtstone compile``;
``make test`` runs it on one core while the linters use the other).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from numba.core import event

WARM_UP_TIME = 0.01  # simulated time of each warm-up run [s]: a few steps reach every driver


@dataclass(frozen=True)
class CompileReport:
    """What :func:`compile_solvers` did.

    Parameters
    ----------
    compiled_functions : int
        Functions compiled now (0: everything came from numba's cache).
    seconds : float
        Wall time of the compile or of the cache load [s].
    """

    compiled_functions: int
    seconds: float


class _TopLevelCompiles(event.Listener):
    """Counts numba's compilations that are not part of another function's."""

    def __init__(self) -> None:
        self.depth = 0
        self.count = 0

    def on_start(self, event: event.Event) -> None:
        self.depth += 1

    def on_end(self, event: event.Event) -> None:
        self.depth -= 1
        if self.depth == 0:
            self.count += 1


def compile_solvers() -> CompileReport:
    """Compile every driver a run, a stick–slip run and a sweep call, or load it from the cache.

    One tiny run of each through the public API (the Kane & Levinson body, rolling and
    the stick–slip contact for 0.01 s, with their summaries, and a one-point sweep), so
    that exactly what a user's calls need is compiled: other bodies, models, methods
    and contacts differ by values, not by types. Safe while other processes use the
    cache: each entry is saved whole, under a lock (``kernels._cache``).

    Returns
    -------
    CompileReport
        How many functions were compiled and how long it took.
    """
    from celtstone.bodies import load_body
    from celtstone.integrate import simulate
    from celtstone.models import HybridModel, InitialState, RollingModel
    from celtstone.sweep import Sweep

    counter = _TopLevelCompiles()
    start = time.perf_counter()
    with event.install_listener("numba:compile", counter):
        body = load_body("kane_levinson_1982")
        state = InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
        for model in (RollingModel(), HybridModel()):
            simulate(model, body, state, WARM_UP_TIME, n_samples=3).summary()
        Sweep({"initial_spin": [-5.0]}, model="sliding", t_end=WARM_UP_TIME).run()
    return CompileReport(counter.count, time.perf_counter() - start)
