"""The runs of a fit: residuals of parameter vectors, the forward-difference Jacobian's
runs in parallel on threads (the compiled loops release the GIL) or as one batch on a GPU,
the Jacobian's columns started speculatively beside each residual, and the count."""

from __future__ import annotations

import os
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import TypeVar

import numpy as np

from celtstone._threads import map_in_threads
from celtstone.errors import CeltstoneError
from celtstone.fitting.problem import Problem
from celtstone.simulation.trajectory import Trajectory

__all__ = ["FD_RELATIVE_STEP", "Runs", "run_device"]

Read = TypeVar("Read")

# forward-difference step as a fraction of each parameter's scale: the runs' error
# (rtol 1e-8) is ~1e-9 of the signal, so the Jacobian's error is ~1e-4 of a column
FD_RELATIVE_STEP = 1e-5


@dataclass
class _Evaluated:
    """The residuals at ``x`` (its exact bytes) and those of the Jacobian's shifted
    vectors already run there: column -> (step, residuals)."""

    x: bytes
    base: np.ndarray
    columns: dict[int, tuple[float, np.ndarray]] = field(default_factory=dict)


def run_device(device: object, problem: Problem) -> str:
    """The device that runs ``problem``'s runs, "cpu" or "cuda", for ``device`` "cpu",
    "cuda" or "auto" (``sweep.devices.resolve_device``).

    Raises
    ------
    ParameterError
        for another ``device``, and for "cuda" where no GPU can run the runs (no CUDA
        GPU here): before any run.
    """
    from celtstone.simulation.integrate import method_names
    from celtstone.simulation.models import HybridModel
    from celtstone.sweep.devices import resolve_device

    if device == "cpu":
        return "cpu"
    # the model of the fixed numbers alone (``make_problem`` built it): its kind and
    # default method are those of every run
    model = replace(problem, free=()).configuration(np.array([]))[0]
    method, _ = method_names(model, problem.method)
    return resolve_device(device, problem.model_name, method, isinstance(model, HybridModel))


class Runs:
    """Evaluates ``problem`` at parameter vectors; counts runs, failed runs and the
    speculative runs that were wasted.

    ``least_squares`` asks for r(x) and, if it accepts the step, then for J(x). With
    ``speculate`` on, :meth:`residuals` runs r(x) together with as many of J(x)'s columns
    as there are threads besides it (on the GPU: all of them), and :meth:`jacobian` at
    the same x (the same bytes) takes those and runs only the rest: on 2 threads and 3
    columns, 2 rounds of runs per accepted step instead of 3. The columns started at a
    rejected step are wasted (counted in :attr:`wasted`); the Jacobian is the serial one
    bit for bit.

    Each batch of runs (a residual and its columns, the Jacobian's missing columns,
    :meth:`evaluate_many`, :meth:`run_many`) goes on the CPU as ``Problem.run`` on
    threads, and on the GPU (``batch``) as one ``Problem.run_many``: one launch,
    a thread per run.

    Parameters
    ----------
    problem : the fit
    workers : threads for the runs on the CPU (default ``os.cpu_count()``); 1: serial
    progress : called after each residual evaluation with (runs so far, its cost)
    speculate : start the Jacobian's columns beside each residual
    device : where the runs go, resolved: "cpu" or "cuda"
    batch : each batch as one ``Problem.run_many`` (default: on the GPU only); True on
        the CPU runs the GPU's path through ``simulate_many``'s threads
    """

    def __init__(
        self,
        problem: Problem,
        workers: int | None = None,
        progress: Callable[[int, float], None] | None = None,
        speculate: bool = True,
        device: str = "cpu",
        batch: bool | None = None,
    ) -> None:
        self.problem = problem
        self.workers = max(1, workers if workers is not None else (os.cpu_count() or 1))
        self.progress = progress
        self.speculate = speculate
        self.device = device
        self.batch = device != "cpu" if batch is None else batch
        self.count = 0
        self.failed = 0
        self._wasted = 0
        self._lock = threading.Lock()
        self._last: _Evaluated | None = None

    @property
    def wasted(self) -> int:
        """Speculative runs whose column no Jacobian used: those of earlier points, and
        those of the last point so far (no Jacobian has asked for them yet)."""
        return self._wasted + (0 if self._last is None else len(self._last.columns))

    def _keep(self, evaluated: _Evaluated | None) -> None:
        """Replace the point kept for the Jacobian, counting its unused columns as wasted."""
        if self._last is not None:
            self._wasted += len(self._last.columns)
        self._last = evaluated

    def use(self, problem: Problem) -> None:
        """Evaluate ``problem`` from now on (the same runs, other weights)."""
        self.problem = problem
        self._keep(None)

    def close(self) -> None:
        """Nothing to stop: each map's daemon threads end with it, and on Ctrl-C or
        SIGTERM its runs under way are abandoned at once (``celtstone._threads``)."""

    def __enter__(self) -> Runs:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _evaluate(self, x: np.ndarray) -> np.ndarray:
        try:
            run: Trajectory | CeltstoneError = self.problem.run(x)
        except CeltstoneError as error:  # a configuration refused (implausible), a solver error
            run = error
        return self._counted(run, x)

    def _counted(self, run: Trajectory | CeltstoneError, x: np.ndarray) -> np.ndarray:
        """The residuals of ``run``, the run of ``x`` (or the error it raised), counted."""
        trajectory = None if isinstance(run, CeltstoneError) else run
        residuals = self.problem.residuals(trajectory, x)
        with self._lock:
            self.count += 1
            self.failed += trajectory is None or not trajectory.ok
        return residuals

    def _map(self, vectors: Sequence[np.ndarray]) -> list[np.ndarray]:
        if not self.batch:
            return list(map_in_threads(self._evaluate, vectors, workers=self.workers))
        made = self.problem.run_many(vectors, self.device, workers=self.workers)
        return [self._counted(run, x) for run, x in zip(made, vectors, strict=True)]

    def run_many(
        self,
        read: Callable[[Trajectory | None], Read],
        vectors: Sequence[np.ndarray],
        sample_times: np.ndarray | None = None,
    ) -> list[Read]:
        """``read`` of the run of each of ``vectors`` (None for one that cannot be made or
        raised), sampled at ``sample_times`` [s from its start] or the record's times, the
        runs in parallel or as one batch (counted)."""
        if self.batch:
            made = self.problem.run_many(vectors, self.device, sample_times, self.workers)
            with self._lock:
                self.count += len(made)
            return [read(None if isinstance(run, CeltstoneError) else run) for run in made]

        def counted(x: np.ndarray) -> Read:
            try:
                trajectory: Trajectory | None = self.problem.run(x, sample_times)
            except CeltstoneError:  # a refused configuration
                trajectory = None
            result = read(trajectory)
            with self._lock:
                self.count += 1
            return result

        return list(map_in_threads(counted, vectors, workers=self.workers))

    def evaluate_many(self, vectors: Sequence[np.ndarray]) -> list[np.ndarray]:
        """Weighted residuals at each of ``vectors``, the runs in parallel (counted)."""
        residuals = self._map([np.asarray(x, dtype=float) for x in vectors])
        if self.progress is not None and residuals:
            self.progress(self.count, min(0.5 * float(r @ r) for r in residuals))
        return residuals

    def _shifted(
        self, x: np.ndarray, columns: Sequence[int]
    ) -> tuple[np.ndarray, list[np.ndarray]]:
        """The forward-difference steps h_j = ``FD_RELATIVE_STEP`` x scale_j of
        ``columns`` (backward where x + h passes the upper bound) and the shifted vectors."""
        chosen = list(columns)
        steps = FD_RELATIVE_STEP * self.problem.scale[chosen]
        steps = np.where(x[chosen] + steps > self.problem.upper[chosen], -steps, steps)
        vectors = []
        for j, step in zip(chosen, steps, strict=True):
            shifted = x.copy()
            shifted[j] += step
            vectors.append(shifted)
        return steps, vectors

    def residuals(self, x: np.ndarray, columns: Sequence[int] = ()) -> np.ndarray:
        """Weighted residuals at ``x`` (kept for the Jacobian there), run beside the
        Jacobian's first ``columns`` at ``x`` when speculating (one per idle thread; on
        the GPU all of them)."""
        x = np.asarray(x, dtype=float)
        linear = self.problem.linear_columns
        ahead = [j for j in columns if j not in linear] if self.speculate else []
        if self.device == "cpu":  # as many as there are idle threads beside the residual
            ahead = ahead[: self.workers - 1]
        # on the GPU every column goes ahead: each run is a thread of the launch, so a
        # batch of 8 runs takes about as long as a batch of 1, and a column run now is
        # a launch fewer when the step is accepted (a rejected step wastes them all)
        steps, vectors = self._shifted(x, ahead)
        residuals, *shifted = self._map([x, *vectors])
        evaluated = _Evaluated(x.tobytes(), residuals)
        for j, step, r in zip(ahead, steps, shifted, strict=True):
            evaluated.columns[j] = (float(step), r)
        self._keep(evaluated)
        if self.progress is not None:
            self.progress(self.count, 0.5 * float(residuals @ residuals))
        return residuals

    def jacobian(self, x: np.ndarray, columns: Sequence[int] | None = None) -> np.ndarray:
        """∂r/∂x by forward differences (backward at an upper bound), shape (m, len(columns)),
        the columns' runs in parallel; a bias's or a scale's column exactly, from the
        residuals at ``x`` (``Problem.linear_jacobian``).

        r(x) and any columns run ahead are those of the last :meth:`residuals` call at
        ``x`` (least_squares evaluates it first); the rest are run now.
        """
        x = np.asarray(x, dtype=float)
        every = list(range(x.size)) if columns is None else list(columns)
        linear = self.problem.linear_columns
        chosen = [j for j in every if j not in linear]  # a bias's or scale's needs no run
        steps, vectors = self._shifted(x, chosen)
        last = self._last if self._last is not None and self._last.x == x.tobytes() else None
        ahead = {} if last is None else last.columns
        # a column run ahead is taken only with the very step it would be run with now
        missing = [
            i for i, j in enumerate(chosen) if j not in ahead or ahead[j][0] != float(steps[i])
        ]
        if last is None:
            base, *runs = self._map([x, *[vectors[i] for i in missing]])
        else:
            base, runs = last.base, self._map([vectors[i] for i in missing])
        shifted = dict(zip(missing, runs, strict=True))
        for i, j in enumerate(chosen):
            if i not in shifted:
                shifted[i] = ahead.pop(j)[1]
        differenced = {
            j: (shifted[i] - base) / step
            for i, (j, step) in enumerate(zip(chosen, steps, strict=True))
        }
        return np.column_stack(
            [
                differenced[j] if j in differenced else self.problem.linear_jacobian(j, x, base)
                for j in every
            ]
        ).reshape(base.size, len(every))
