"""The small dense LU of the Radau Newton iteration against NumPy's solver."""

from __future__ import annotations

import numpy as np
import pytest

from celtstone.kernels.layout import N_DYNAMIC, N_STATE
from celtstone.solvers._linalg import block_factor, block_solve, lu_factor, lu_solve


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


@pytest.mark.parametrize("dtype", [np.float64, np.complex128])
@pytest.mark.parametrize("split", [0, 1, 9, 16])
def test_block_triangular_systems_solve_like_numpy(dtype: type, split: int) -> None:
    """[[A, 0], [C, B]] factored block by block: the solution of the whole system; the
    block above the diagonal is never read (it holds garbage here)."""
    rng = np.random.default_rng(split)
    size = 16
    matrix = rng.normal(size=(size, size)).astype(dtype) + 4.0 * np.eye(size)
    if dtype is np.complex128:
        matrix += 1j * rng.normal(size=(size, size))
    matrix[:split, split:] = 0.0
    right = rng.normal(size=size).astype(dtype)
    factored, pivots = matrix.copy(), np.zeros(size, dtype=np.int64)
    factored[:split, split:] = np.nan
    assert block_factor(factored, pivots, split)
    for _ in range(2):
        solution = right.copy()
        block_solve(factored, pivots, solution, split)
        expected = np.linalg.solve(matrix, right)
        assert np.allclose(solution, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())


def test_a_singular_diagonal_block_is_reported() -> None:
    matrix = np.eye(4)
    matrix[1, 1] = 0.0
    assert not block_factor(matrix.copy(), np.zeros(4, dtype=np.int64), 2)
    matrix = np.eye(4)
    matrix[3, 3] = 0.0
    assert not block_factor(matrix.copy(), np.zeros(4, dtype=np.int64), 2)


@pytest.mark.parametrize("dtype", [np.float64, np.complex128])
@pytest.mark.parametrize(("size", "split"), [(N_STATE, N_DYNAMIC), (N_STATE, 0), (12, 5)])
def test_the_block_lu_gives_each_block_s_lu_bits(dtype: type, size: int, split: int) -> None:
    """The 16 × 16 matrix split at 9 (the Radau iteration matrix of the state) takes the
    path with constant block bounds; any other split (0: a Radau matrix whose dynamics read
    the driven components) or size one copy of the LU and of the solve in a loop over the
    two blocks. Each must compute exactly what the LU of each block computes (pivots and
    factors bit for bit; for split 0, the solution too), and solve the system."""
    rng = np.random.default_rng(7 if split == N_DYNAMIC else size + split)
    matrix = rng.normal(size=(size, size)).astype(dtype)
    if dtype is np.complex128:
        matrix += 1j * rng.normal(size=(size, size))
    matrix[:split, split:] = 0.0
    matrix[0, 0] = 0.0  # a row exchange in each block
    matrix[split, split] = 0.0
    blocks, block_pivots = matrix.copy(), np.zeros(size, dtype=np.int64)
    assert block_factor(blocks, block_pivots, split)
    plain, plain_pivots = matrix.copy(), np.zeros(size, dtype=np.int64)
    if split > 0:
        assert lu_factor(plain, plain_pivots, 0, split)
    assert lu_factor(plain, plain_pivots, split, size)
    assert np.array_equal(block_pivots, plain_pivots)
    assert np.array_equal(blocks, plain)
    right = rng.normal(size=size).astype(dtype)
    solution = right.copy()
    block_solve(blocks, block_pivots, solution, split)
    plain_solution = right.copy()
    lu_solve(plain, plain_pivots, plain_solution, 0, split)
    plain_solution[split:] -= plain[split:, :split] @ plain_solution[:split]
    lu_solve(plain, plain_pivots, plain_solution, split, size)
    assert np.allclose(solution, np.linalg.solve(matrix, right), rtol=1e-12, atol=1e-12)
    assert np.allclose(solution, plain_solution, rtol=1e-14, atol=1e-15)
    if split == 0:
        assert np.array_equal(solution, plain_solution)


def test_a_complex_pivot_is_the_largest_by_its_one_norm() -> None:
    """LAPACK's choice (izamax: |Re| + |Im|): 3 + 3j (6) is chosen over 5 (modulus 5 >
    4.24, one-norm 5 < 6)."""
    matrix = np.array([[5.0, 1.0], [3.0 + 3.0j, 2.0]], dtype=np.complex128)
    pivots = np.zeros(2, dtype=np.int64)
    assert lu_factor(matrix, pivots)
    assert pivots[0] == 1
