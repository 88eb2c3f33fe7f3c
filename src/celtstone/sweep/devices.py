"""Where a sweep computes: the CPU (threads or a Dask cluster) or a CUDA GPU.

``resolve_device`` (``solvers.devices``, which ``simulate_many`` reads too) turns the
user's ``device`` ("cpu", "cuda" or "auto") into the one that runs, and refuses "cuda" in
one line where the GPU cannot run the sweep. A sweep asked to run on the GPU never falls
back to the CPU; "auto" takes the GPU where it can and says nothing.

``CudaPool`` gathers the runner's tasks (blocks of points) into launches of
``solvers.batch.run_batch`` on the GPU (``device="cuda"``), one thread per point, as
many points at a time as the GPU's memory holds (``batch_cuda.launch_points``), and
hands each task its rows back: the store, its blocks, resuming and the fields are the CPU
sweep's.
"""

from __future__ import annotations

from collections import deque
from typing import Any

import numpy as np

from celtstone.solvers.devices import DEVICES as DEVICES
from celtstone.solvers.devices import announce_first_launch
from celtstone.solvers.devices import resolve_device as resolve_device

__all__ = ["DEVICES", "CudaPool", "describe_gpu", "resolve_device"]


def describe_gpu() -> str:
    """The GPU's name ("NVIDIA H200"), or "numba's CUDA simulator"."""
    from celtstone.solvers.batch_cuda import device_name

    return device_name()


class CudaPool:
    """The runner's pool on the GPU: tasks submitted are gathered, and launched together
    when the runner asks for the next result (``slots`` sets how many it submits first).

    Parameters
    ----------
    n_samples : samples per point (the launch's memory)
    task_points : points per task (the runner's block)
    """

    def __init__(self, n_samples: int, task_points: int) -> None:
        from celtstone.solvers.batch_cuda import launch_points

        self.n_samples = n_samples
        self.points_per_launch = launch_points(n_samples, 1)  # at most: see ``_launch``
        self.slots = max(1, self.points_per_launch // (4 * task_points))
        self._waiting: list[tuple[int, tuple[Any, ...], dict[str, Any]]] = []
        self._done: deque[tuple[int, np.ndarray]] = deque()

    def submit(self, key: int, *args: Any, **kwargs: Any) -> None:
        self._waiting.append((key, args, kwargs))

    def next_done(self) -> tuple[int, np.ndarray]:
        if not self._done:
            self._launch()
        return self._done.popleft()

    def close(self) -> None:
        self._waiting.clear()
        self._done.clear()

    def _launch(self) -> None:
        """One launch of every waiting task's points; their rows to ``_done``."""
        from celtstone.solvers.batch import run_batch
        from celtstone.solvers.batch_cuda import KEPT_CROSSINGS, launch_points
        from celtstone.solvers.codes import DEFAULT_MAX_PHASES

        tasks, self._waiting = self._waiting, []
        if not tasks:
            raise RuntimeError("the runner asked for a result with no task submitted")
        model, method, _, _, t_end = tasks[0][1]
        settings = dict(tasks[0][2])
        counts = [len(args[2]) for _, args, _ in tasks]
        is_hybrid = settings.get("capture_speeds") is not None  # the stick-slip contact
        per_point_names: tuple[str, ...] = ("reversal_bands", "reversal_windows")
        if is_hybrid:
            per_point_names += ("capture_speeds",)
        per_point = {
            name: np.concatenate(
                [
                    np.broadcast_to(kw[name], (n,))
                    for (_, _, kw), n in zip(tasks, counts, strict=True)
                ]
            )
            for name in per_point_names
        }
        params = np.concatenate([args[2] for _, args, _ in tasks])
        states = np.concatenate([args[3] for _, args, _ in tasks])
        announce_first_launch("sweeping")
        # as many as fit at once; points whose rocking window is 0 keep their crossing
        # times, and fewer of them fit, as do points with a phase log
        kept = bool(np.any(per_point["reversal_windows"] <= 0.0))
        phase_capacity = settings.get("max_phases", DEFAULT_MAX_PHASES) if is_hybrid else 0
        size = launch_points(self.n_samples, KEPT_CROSSINGS if kept else 1, phase_capacity)
        parts = []
        for start in range(0, len(params), size):
            part = slice(start, start + size)
            settings.update({name: values[part] for name, values in per_point.items()})
            parts.append(
                run_batch(
                    model, method, params[part], states[part], t_end, device="cuda", **settings
                )
            )
        results = np.concatenate(parts)
        first = 0
        for (key, _, _), n in zip(tasks, counts, strict=True):
            self._done.append((key, results[first : first + n]))
            first += n
