"""Compile the solvers into numba's on-disk cache now, instead of on first use.

The compiled drivers (one run's integration loop, the stick–slip phase loop, the
sweep's batch) are compiled the first time they are called and then cached on disk
(``NUMBA_CACHE_DIR``, else ``__pycache__`` beside the sources): about a minute of
one core after an install or an upgrade, 2–3 s to load afterwards. Without it, a first
rolling run compiles the rolling model's loop alone (``solvers.driver.integrate_link``).
Numba compiles per process, so parallel jobs started on a cold cache each compile the
same drivers at once; :func:`compile_solvers` pays the cost once, up front
(``celtstone compile``; ``make test`` runs it on one core while the linters use the
other).
"""

from __future__ import annotations

import time
from collections.abc import Callable
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


def compile_solvers(progress: Callable[[int, int, str], None] | None = None) -> CompileReport:
    """Compile every driver a run, a stick–slip run and a sweep call, or load it from the cache.

    One tiny run of each driver through the public API (the Kane & Levinson body, the
    stick–slip contact and rolling for 0.01 s, with their summaries, and a one-point
    sweep), so that exactly what a user's calls need is compiled: the run loop for
    every model and method code, and the rolling model's own loop for vern9, the most
    common run's, where the cache holds neither loop yet
    (``solvers.driver.integrate_link``); other bodies, shapes and laws differ by values,
    not by types. Safe while other processes use the cache: each entry is saved whole,
    under a lock (``kernels._cache``).

    Parameters
    ----------
    progress : callable, optional
        Called before each warm-up with (warm-ups done, warm-ups in all, what the next
        compiles), and once at the end with (all, all, "").

    Returns
    -------
    CompileReport
        How many functions were compiled and how long it took.
    """
    from celtstone.bodies import load_body
    from celtstone.simulation.integrate import simulate
    from celtstone.simulation.models import HybridModel, InitialState, RollingModel
    from celtstone.sweep import Sweep

    body = load_body("kane_levinson_1982")
    state = InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
    # the rolling run first: where no run loop is compiled yet it compiles the rolling
    # model's own loop for vern9, which later rolling runs take, faster than the loop for
    # every code; the stick–slip run then compiles that one, which runs of other models
    # and methods and the sweep take (``solvers.driver.integrate_link``)
    warm_ups: list[tuple[str, Callable[[], object]]] = [
        ("the rolling run", _run(simulate, RollingModel(), body, state)),
        ("the stick–slip run", _run(simulate, HybridModel(), body, state)),
    ]
    sweep = Sweep({"initial_spin": [-5.0]}, model="sliding", t_end=WARM_UP_TIME)
    warm_ups.append(("the sweep", sweep.run))
    counter = _TopLevelCompiles()
    start = time.perf_counter()
    with event.install_listener("numba:compile", counter):
        for done, (label, warm_up) in enumerate(warm_ups):
            if progress is not None:
                progress(done, len(warm_ups), label)
            warm_up()
    if progress is not None:
        progress(len(warm_ups), len(warm_ups), "")
    return CompileReport(counter.count, time.perf_counter() - start)


def _run(
    simulate: Callable[..., object], model: object, body: object, state: object
) -> Callable[[], object]:
    """A warm-up: a run of ``WARM_UP_TIME`` and its summary."""

    def warm_up() -> object:
        return simulate(model, body, state, WARM_UP_TIME, n_samples=3).summary()  # type: ignore[attr-defined]

    return warm_up
