"""Where runs compute: the CPU or a CUDA GPU, for a sweep and a batch of runs alike.

``resolve_device`` turns the user's ``device`` ("cpu", "cuda" or "auto") into the one
that runs, and refuses "cuda" in one line where the GPU cannot run the runs: no CUDA
GPU here, or a model or method that has no GPU thread. Runs asked to run on the GPU never
fall back to the CPU; "auto" takes the GPU where it can and says nothing. The GPU runs
the rolling and the sliding model, the stick–slip contact included, with every method
(``batch_cuda``). ``announce_first_launch`` says, once a process on a terminal, that the
first launch of a model and method may compile its CUDA kernel.

numba's CUDA target is imported only where "cuda" or "auto" is asked for.
"""

from __future__ import annotations

import sys

from celtstone.errors import ParameterError

__all__ = ["DEVICES", "announce_first_launch", "resolve_device"]

DEVICES = ("cpu", "cuda", "auto")
"""The values of ``device`` in ``Sweep``, ``simulate_many`` and ``celtstone sweep --device``."""

_announced: set[str] = set()  # what this process has said it compiles


def _gpu_refusal(model: str, method: str, is_hybrid: bool) -> str | None:
    """Why the GPU cannot run runs of ``model`` with ``method`` (of the stick–slip
    contact if ``is_hybrid``), or None."""
    from celtstone.solvers import batch_cuda

    if model not in batch_cuda.CUDA_MODEL_NAMES:
        return f"the GPU runs the {' and '.join(batch_cuda.CUDA_MODEL_NAMES)} models, not {model}"
    if method not in batch_cuda.CUDA_METHODS:
        return f"the GPU runs {' or '.join(batch_cuda.CUDA_METHODS)}, not {method}"
    return batch_cuda.cuda_unavailable_reason()


def resolve_device(device: object, model: str, method: str, is_hybrid: bool) -> str:
    """The device that runs runs of ``model`` with ``method``: "cpu" or "cuda".

    Parameters
    ----------
    device : one of ``DEVICES``, as the user gave it
    model : the model's name ("rolling", "sliding")
    method : the method's name (``solvers.METHODS``)
    is_hybrid : whether the runs have the stick–slip contact

    Raises
    ------
    ParameterError
        for a ``device`` not in ``DEVICES``, and for "cuda" where the GPU cannot run the
        runs (the reason as the hint).
    """
    if device not in DEVICES:
        raise ParameterError("device", device, "one of: " + ", ".join(DEVICES))
    if device == "cpu":
        return "cpu"
    refusal = _gpu_refusal(model, method, is_hybrid)
    if refusal is None:
        return "cuda"
    if device == "auto":
        return "cpu"
    raise ParameterError(
        "device", device, "cpu, or auto to use a GPU where one can run it", refusal
    )


def announce_first_launch(doing: str) -> None:
    """Say on a terminal, once a process for each ``doing`` ("sweeping", "running a
    batch of runs"), that the first launch of a model and method may compile its CUDA
    kernel (numba's cache serves later processes)."""
    if doing in _announced:
        return
    _announced.add(doing)
    try:
        terminal = sys.stderr is not None and sys.stderr.isatty()
    except (ValueError, OSError):
        terminal = False
    if terminal:
        from celtstone.solvers.batch_cuda import device_name

        print(
            f"celtstone: {doing} on {device_name()}; the first launch of a model and method "
            "on this machine compiles its CUDA kernel (tens of seconds, once)",
            file=sys.stderr,
            flush=True,
        )
