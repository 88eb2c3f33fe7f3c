"""Pure numeric kernels: the paper's equations as functions of floats and arrays.

Nothing here validates, allocates objects or does I/O. Every function is
compiled by numba through :func:`celtstone.kernels._jit.kernel` (module-level
functions, so numba's on-disk cache works; see ``docs/decisions.md``).
"""
