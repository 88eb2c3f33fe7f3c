"""The one place in ``kernels`` that imports numba.

``kernel`` compiles a module-level function with ``njit(cache=True)``. With
``NUMBA_DISABLE_JIT=1`` numba returns the Python function unchanged, so the
same kernels run (slowly) as plain Python for coverage and debugging.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

from numba import njit

F = TypeVar("F", bound=Callable[..., Any])


def kernel(function: F) -> F:
    """Compile ``function`` in nopython mode with the on-disk cache on."""
    compiled: F = njit(cache=True, error_model="numpy")(function)  # type: ignore[assignment]
    return compiled
