"""The small dense LU of the Radau Newton iteration against NumPy's solver."""

from __future__ import annotations

import numpy as np
import pytest

from celtstone.solvers._linalg import lu_factor, lu_solve


@pytest.mark.parametrize("dtype", [np.float64, np.complex128])
@pytest.mark.parametrize("size", [1, 3, 16])
def test_solves_like_numpy(dtype: type, size: int) -> None:
    rng = np.random.default_rng(size)
    matrix = rng.normal(size=(size, size)).astype(dtype)
    if dtype is np.complex128:
        matrix += 1j * rng.normal(size=(size, size))
    if size > 1:
        matrix[0, 0] = 0.0  # the first column needs a row exchange
    right = rng.normal(size=size).astype(dtype)
    factored, pivots = matrix.copy(), np.zeros(size, dtype=np.int64)
    assert lu_factor(factored, pivots)
    for _ in range(3):  # the factors are reused, as in the Newton iteration
        solution = right.copy()
        lu_solve(factored, pivots, solution)
        expected = np.linalg.solve(matrix, right)
        assert np.allclose(solution, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())


def test_singular_matrix_is_reported() -> None:
    matrix = np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 0.0]])
    assert not lu_factor(matrix, np.zeros(3, dtype=np.int64))
