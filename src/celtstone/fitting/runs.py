"""The runs of a fit: residuals of parameter vectors, the forward-difference Jacobian's
runs in parallel on threads (the compiled loops release the GIL), and the count."""

from __future__ import annotations

import os
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from celtstone.errors import CeltstoneError
from celtstone.fitting.problem import Problem

__all__ = ["FD_RELATIVE_STEP", "Runs"]

# forward-difference step as a fraction of each parameter's scale: the runs' error
# (rtol 1e-8) is ~1e-9 of the signal, so the Jacobian's error is ~1e-4 of a column
FD_RELATIVE_STEP = 1e-5


class Runs:
    """Evaluates ``problem`` at parameter vectors; counts runs and failed runs.

    Parameters
    ----------
    problem : the fit
    workers : threads for the Jacobian's runs (default ``os.cpu_count()``); 1: serial
    progress : called after each residual evaluation with (runs so far, its cost)
    """

    def __init__(
        self,
        problem: Problem,
        workers: int | None = None,
        progress: Callable[[int, float], None] | None = None,
    ) -> None:
        self.problem = problem
        self.workers = max(1, workers if workers is not None else (os.cpu_count() or 1))
        self.progress = progress
        self.count = 0
        self.failed = 0
        self._lock = threading.Lock()
        self._pool = ThreadPoolExecutor(self.workers) if self.workers > 1 else None
        self._last: tuple[bytes, np.ndarray] | None = None

    def use(self, problem: Problem) -> None:
        """Evaluate ``problem`` from now on (the same runs, other weights)."""
        self.problem = problem
        self._last = None

    def close(self) -> None:
        """Stop the threads (runs under way finish; queued ones are dropped)."""
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)

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
        residuals = self.problem.residuals(trajectory)
        with self._lock:
            self.count += 1
            self.failed += not ok
        return residuals

    def _map(self, vectors: Sequence[np.ndarray]) -> list[np.ndarray]:
        if self._pool is None:
            return [self._evaluate(x) for x in vectors]
        return list(self._pool.map(self._evaluate, vectors))

    def residuals(self, x: np.ndarray) -> np.ndarray:
        """Weighted residuals at ``x`` (the last one is kept for the Jacobian)."""
        x = np.asarray(x, dtype=float)
        residuals = self._evaluate(x)
        self._last = (x.tobytes(), residuals)
        if self.progress is not None:
            self.progress(self.count, 0.5 * float(residuals @ residuals))
        return residuals

    def jacobian(self, x: np.ndarray, columns: Sequence[int] | None = None) -> np.ndarray:
        """∂r/∂x by forward differences (backward at an upper bound), shape (m, len(columns)),
        the columns' runs in parallel.

        Step h_j = ``FD_RELATIVE_STEP`` x scale_j; r(x) is that of the last
        :meth:`residuals` call at ``x`` (least_squares evaluates it first) or a new run.
        """
        x = np.asarray(x, dtype=float)
        chosen = list(range(x.size)) if columns is None else list(columns)
        steps = FD_RELATIVE_STEP * self.problem.scale[chosen]
        upper = self.problem.upper[chosen]
        steps = np.where(x[chosen] + steps > upper, -steps, steps)
        vectors = []
        for j, step in zip(chosen, steps, strict=True):
            shifted = x.copy()
            shifted[j] += step
            vectors.append(shifted)
        if self._last is not None and self._last[0] == x.tobytes():
            base, shifted_residuals = self._last[1], self._map(vectors)
        else:
            base, *shifted_residuals = self._map([x, *vectors])
        return np.column_stack(
            [(r - base) / step for r, step in zip(shifted_residuals, steps, strict=True)]
        )
