"""The runs of a fit: residuals of parameter vectors, the forward-difference Jacobian's
runs in parallel on threads (the compiled loops release the GIL), the Jacobian's columns
started speculatively beside each residual on the idle threads, and the count."""

from __future__ import annotations

import os
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from celtstone._threads import map_in_threads
from celtstone.errors import CeltstoneError
from celtstone.fitting.problem import Problem

__all__ = ["FD_RELATIVE_STEP", "Runs"]

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


class Runs:
    """Evaluates ``problem`` at parameter vectors; counts runs, failed runs and the
    speculative runs that were wasted.

    ``least_squares`` asks for r(x) and, if it accepts the step, then for J(x). With
    ``speculate`` on, :meth:`residuals` runs r(x) together with as many of J(x)'s columns
    as there are threads besides it, and :meth:`jacobian` at the same x (the same bytes)
    takes those and runs only the rest: on 2 threads and 3 columns, 2 rounds of runs per
    accepted step instead of 3. The columns started at a rejected step are wasted
    (counted in :attr:`wasted`); the Jacobian is the serial one bit for bit.

    Parameters
    ----------
    problem : the fit
    workers : threads for the runs (default ``os.cpu_count()``); 1: serial
    progress : called after each residual evaluation with (runs so far, its cost)
    speculate : start the Jacobian's columns beside each residual on the idle threads
    """

    def __init__(
        self,
        problem: Problem,
        workers: int | None = None,
        progress: Callable[[int, float], None] | None = None,
        speculate: bool = True,
    ) -> None:
        self.problem = problem
        self.workers = max(1, workers if workers is not None else (os.cpu_count() or 1))
        self.progress = progress
        self.speculate = speculate
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
            trajectory = self.problem.run(x)
            ok = trajectory.ok
        except CeltstoneError:  # a configuration refused (implausible) or a solver error
            trajectory, ok = None, False
        residuals = self.problem.residuals(trajectory, x)
        with self._lock:
            self.count += 1
            self.failed += not ok
        return residuals

    def _map(self, vectors: Sequence[np.ndarray]) -> list[np.ndarray]:
        return list(map_in_threads(self._evaluate, vectors, workers=self.workers))

    def run_many(
        self, function: Callable[[np.ndarray], np.ndarray], vectors: Sequence[np.ndarray]
    ) -> list[np.ndarray]:
        """``function`` of each of ``vectors``, each one run, in parallel (counted)."""

        def counted(x: np.ndarray) -> np.ndarray:
            result = function(x)
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
        Jacobian's first ``columns`` at ``x`` when speculating (one per idle thread)."""
        x = np.asarray(x, dtype=float)
        linear = self.problem.linear_columns
        ahead = (
            [j for j in columns if j not in linear][: self.workers - 1] if self.speculate else []
        )
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
