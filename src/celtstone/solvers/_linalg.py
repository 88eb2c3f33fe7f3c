"""LU factorisation with partial pivoting for small dense systems (real or complex).

The factors are stored for the Radau Newton iteration, which solves with the same
factors many times per factorisation: the diagonal holds the reciprocal pivots
1 / U[k, k] (a multiplication in every solve instead of a division), and the solves
run column by column, so that the updates of one column are independent of each
other instead of forming one long chain of dependent multiply-adds.

A matrix that is block lower triangular, [[A, 0], [C, B]] with A of size ``split``, is
factored block by block (:func:`block_factor`, :func:`block_solve`): the LU of A and of B,
C kept for the forward substitution. This is the Radau iteration matrix of the state, whose
driven components (attitude, position, work) do not feed back into the dynamics
(``kernels.layout.N_DYNAMIC``): for 9 + 7 components a third of the work of one 16 × 16 LU.
``split`` = 0 is the plain LU of the whole matrix.

The Radau matrices are always 16 × 16 split at 9 (``N_STATE``, ``N_DYNAMIC``), and the block
functions take that case apart from the general one: with the block bounds constants,
LLVM unrolls the short loops (a real solve 0.29 → 0.09 µs, docs/decisions.md §36). Every
other case (a Jacobian split at 0, another size) runs one copy of the LU or the solve in a
loop over the two blocks: each inlined copy of the loops costs its compile, a first run's
CPU. All paths run the same operations in the same order, so they give the same bits.

A complex pivot is chosen by |Re| + |Im|, as LAPACK's ``izamax`` does, not by the modulus,
whose ``hypot`` per candidate cost more than the rest of the complex factorisation.
"""

from __future__ import annotations

from celtstone.kernels._jit import inlined_kernel, kernel
from celtstone.kernels.layout import N_DYNAMIC, N_STATE


@inlined_kernel
def _magnitude(value):
    """|Re| + |Im| (|value| for a real one): the pivot's size, as LAPACK's ``izamax``."""
    return abs(value.real) + abs(value.imag)


@inlined_kernel
def lu_factor(matrix, pivots, first=0, last=-1):
    """Factor the diagonal block ``matrix[first:last, first:last]`` in place (the whole
    matrix by default): L unit lower below the diagonal, U strictly above it, 1 / U[k, k]
    on it; ``pivots[k]`` the row exchanged with row k (absolute indices). Return False if
    singular. Entries outside the block are neither read nor written."""
    size = matrix.shape[0] if last < 0 else last
    for k in range(first, size):
        best = k
        best_value = _magnitude(matrix[k, k])
        for i in range(k + 1, size):
            value = _magnitude(matrix[i, k])
            if value > best_value:
                best, best_value = i, value
        pivots[k] = best
        if best_value == 0.0:
            return False
        if best != k:
            for j in range(first, size):
                matrix[k, j], matrix[best, j] = matrix[best, j], matrix[k, j]
        inverse = 1.0 / matrix[k, k]
        matrix[k, k] = inverse
        for i in range(k + 1, size):
            factor = matrix[i, k] * inverse
            matrix[i, k] = factor
            if factor != 0.0:
                for j in range(k + 1, size):
                    matrix[i, j] -= factor * matrix[k, j]
    return True


@inlined_kernel
def lu_solve(factored, pivots, rhs, first=0, last=-1):
    """Solve in place with the factors of :func:`lu_factor` of the block [first, last);
    ``rhs[first:last]`` is overwritten, the rest of ``rhs`` left alone."""
    size = factored.shape[0] if last < 0 else last
    for k in range(first, size):
        p = pivots[k]
        if p != k:
            rhs[k], rhs[p] = rhs[p], rhs[k]
    for j in range(first, size):  # L y = P b
        value = rhs[j]
        for i in range(j + 1, size):
            rhs[i] -= factored[i, j] * value
    for back in range(size - first):  # U x = y
        j = size - 1 - back
        value = rhs[j] * factored[j, j]
        rhs[j] = value
        for i in range(first, j):
            rhs[i] -= factored[i, j] * value


@kernel
def block_factor(matrix, pivots, split):
    """Factor the block lower-triangular ``matrix`` [[A, 0], [C, B]] (A: split × split)
    in place: the LU of A and of B, C left as it is; the block [0:split, split:] is never
    read. Return False if A or B is singular."""
    size = matrix.shape[0]
    if split == N_DYNAMIC and size == N_STATE:  # the state's blocks: constant bounds
        return lu_factor(matrix, pivots, 0, N_DYNAMIC) and lu_factor(
            matrix, pivots, N_DYNAMIC, N_STATE
        )
    for block in range(2):  # any other: one copy of the LU serves both blocks
        first = 0 if block == 0 else split
        last = split if block == 0 else size
        if not lu_factor(matrix, pivots, first, last):
            return False
    return True


@kernel
def block_solve(factored, pivots, rhs, split):
    """Solve [[A, 0], [C, B]] x = rhs in place with the factors of :func:`block_factor`:
    x1 = A⁻¹ b1, then x2 = B⁻¹ (b2 − C x1)."""
    size = factored.shape[0]
    if split == N_DYNAMIC and size == N_STATE:  # the state's blocks: constant bounds
        lu_solve(factored, pivots, rhs, 0, N_DYNAMIC)
        _subtract_coupling(factored, rhs, N_DYNAMIC, N_STATE)
        lu_solve(factored, pivots, rhs, N_DYNAMIC, N_STATE)
        return
    for block in range(2):  # any other: one copy of the solve serves both blocks
        first = 0 if block == 0 else split
        last = split if block == 0 else size
        if block == 1 and split > 0:
            _subtract_coupling(factored, rhs, split, size)
        lu_solve(factored, pivots, rhs, first, last)


@inlined_kernel
def _subtract_coupling(factored, rhs, split, size):
    """b2 − C x1 into ``rhs[split:size]``, x1 = ``rhs[:split]`` (solved already)."""
    for i in range(split, size):
        total = rhs[i]
        for j in range(split):
            total -= factored[i, j] * rhs[j]
        rhs[i] = total
