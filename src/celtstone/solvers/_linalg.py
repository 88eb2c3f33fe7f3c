"""LU factorisation with partial pivoting for small dense systems (real or complex).

The factors are stored for the Radau Newton iteration, which solves with the same
factors many times per factorisation: the diagonal holds the reciprocal pivots
1 / U[k, k] (a multiplication in every solve instead of a division), and the solves
run column by column, so that the updates of one column are independent of each
other instead of forming one long chain of dependent multiply-adds.
"""

from __future__ import annotations

from celtstone.kernels._jit import kernel


@kernel
def lu_factor(matrix, pivots):
    """Factor ``matrix`` in place: L unit lower below the diagonal, U strictly above
    it, 1 / U[k, k] on it. Return False if singular."""
    size = matrix.shape[0]
    for k in range(size):
        best = k
        best_value = abs(matrix[k, k])
        for i in range(k + 1, size):
            value = abs(matrix[i, k])
            if value > best_value:
                best, best_value = i, value
        pivots[k] = best
        if best_value == 0.0:
            return False
        if best != k:
            for j in range(size):
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


@kernel
def lu_solve(factored, pivots, rhs):
    """Solve in place with the factors of :func:`lu_factor`; ``rhs`` is overwritten."""
    size = factored.shape[0]
    for k in range(size):
        p = pivots[k]
        if p != k:
            rhs[k], rhs[p] = rhs[p], rhs[k]
    for j in range(size):  # L y = P b
        value = rhs[j]
        for i in range(j + 1, size):
            rhs[i] -= factored[i, j] * value
    for back in range(size):  # U x = y
        j = size - 1 - back
        value = rhs[j] * factored[j, j]
        rhs[j] = value
        for i in range(j):
            rhs[i] -= factored[i, j] * value
