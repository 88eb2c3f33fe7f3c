"""LU factorisation with partial pivoting for small dense systems (real or complex)."""

from __future__ import annotations

from celtstone.kernels._jit import kernel


@kernel
def lu_factor(matrix, pivots):
    """Factor ``matrix`` in place (L unit lower, U upper); return False if singular."""
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
    for i in range(size):
        total = rhs[i]
        for j in range(i):
            total -= factored[i, j] * rhs[j]
        rhs[i] = total
    for i in range(size - 1, -1, -1):
        total = rhs[i]
        for j in range(i + 1, size):
            total -= factored[i, j] * rhs[j]
        rhs[i] = total / factored[i, i]
