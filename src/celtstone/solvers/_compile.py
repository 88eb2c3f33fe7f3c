"""How the solvers compile a small function that the per-step loop calls.

``inlined`` is ``kernels._jit.kernel`` (numba, on-disk cache, GIL released) plus
numba's own inlining: the function's body is copied into each caller before LLVM
sees it. The driver's step, event and sampling helpers are small and called several
times per step; as separate functions each call passes their arrays as a dozen
words apiece and costs a measurable part of a step (docs/decisions.md §21), as one
body they cost what the single 452-line loop they replace did.

Compiled solver code allocates with ``np.zeros`` only, its dtype omitted for float64
(scratch arrays too, once per run): numba compiles its own ``np.zeros``, ``np.empty`` and
``np.full`` anew for each type of their arguments, an omitted dtype and ``np.float64``
counting as two.
"""

from __future__ import annotations

from celtstone.kernels._jit import cached_njit

inlined = cached_njit(inline="always")
