"""The methods' coefficient tables kept in ``solvers/tableaux.json``: DOP853's and Radau's
equal SciPy's to the last bit (they were copied so that a run starts without importing
``scipy.integrate``); Verner's 9(8) pair, which SciPy lacks, meets its order conditions."""

from __future__ import annotations

import math
from functools import cache

import numpy as np
import pytest

from celtstone.solvers import _dop853, _radau, _tableaux, _vern9

Tree = tuple  # a rooted tree: the sorted tuple of its root's subtrees; () is one vertex


@cache
def rooted_trees(order: int) -> tuple[Tree, ...]:
    """Every rooted tree with ``order`` vertices (Butcher's trees: 1, 1, 2, 4, 9, ...)."""
    if order == 1:
        return ((),)
    found: set[Tree] = set()

    def grow(left: int, smallest: tuple[int, Tree] | None, children: tuple[Tree, ...]) -> None:
        if left == 0:
            found.add(tuple(sorted(children)))
            return
        for size in range(1, left + 1):
            for child in rooted_trees(size):
                if smallest is None or (size, child) >= smallest:
                    grow(left - size, (size, child), (*children, child))

    grow(order - 1, None, ())
    return tuple(sorted(found))


def _density(tree: Tree) -> int:
    """γ(t): the tree's order times its subtrees' densities."""
    return _size(tree) * math.prod(_density(child) for child in tree)


def _size(tree: Tree) -> int:
    return 1 + sum(_size(child) for child in tree)


def _stage_products(tree: Tree, a: np.ndarray) -> np.ndarray:
    """Each stage's product over the root's subtrees t_k of (A Φ(t_k)): the vector whose
    weighted sum b · is the tree's elementary weight."""
    out = np.ones(a.shape[0])
    for child in tree:
        out = out * (a @ _stage_products(child, a))
    return out


def _worst_residual(weights: np.ndarray, a: np.ndarray, order: int, x: float = 1.0) -> float:
    """The largest |weights · Φ(t) - x^|t| / γ(t)| over the trees of one order."""
    return max(
        abs(float(weights @ _stage_products(tree, a)) - x**order / _density(tree))
        for tree in rooted_trees(order)
    )


def test_rooted_trees_are_counted_right() -> None:
    assert [len(rooted_trees(n)) for n in range(1, 10)] == [1, 1, 2, 4, 9, 20, 48, 115, 286]


@pytest.mark.parametrize("name", list(_tableaux.TABLES))
def test_stored_tables_equal_scipys(name: str) -> None:
    stored = _tableaux.table(name)
    scipy_table = _tableaux.from_scipy()[name]
    assert set(stored) == set(scipy_table) == set(_tableaux.TABLES[name])
    for key, value in scipy_table.items():
        if key == "MU_COMPLEX":
            assert stored[key] == complex(*value)
        else:
            assert np.array_equal(np.asarray(stored[key]), np.asarray(value)), key


def test_methods_read_the_stored_tables() -> None:
    from scipy.integrate._ivp import dop853_coefficients, radau

    assert np.array_equal(_dop853.A, dop853_coefficients.A)
    assert _dop853.A.flags.c_contiguous and _dop853.A.dtype == np.float64
    assert np.array_equal(_radau.TI, radau.TI)
    assert _radau.MU_COMPLEX == radau.MU_COMPLEX


def test_verner_pair_meets_its_order_conditions() -> None:
    """All 486 trees to order 9 for the solution, to order 8 for the embedded pair, and not
    beyond: a wrong or mistyped coefficient breaks a condition by far more than round-off."""
    stored = _tableaux.table("vern9")
    assert set(stored) == set(_tableaux.VERNER_KEYS)
    a, c = _vern9.A, _vern9.C
    n_stages = _vern9.N_STAGES
    np.testing.assert_allclose(a.sum(axis=1), c, rtol=0, atol=1e-13)  # row sums reach 35
    step_a = a[:n_stages, :n_stages]
    embedded = _vern9.B + _vern9.E
    for order in range(1, 10):
        assert _worst_residual(_vern9.B, step_a, order) < 1e-14, order
    for order in range(1, 9):
        assert _worst_residual(embedded, step_a, order) < 1e-14, order
    assert _worst_residual(_vern9.B, step_a, 10) > 1e-8
    assert _worst_residual(embedded, step_a, 9) > 1e-8
    assert np.array_equal(a[n_stages, :n_stages], _vern9.B)  # stage 17 is f(t + h, y_new)
    assert c[n_stages] == 1.0


@pytest.mark.parametrize("x", [0.2, 0.5, 0.9, 1.0])
def test_verner_interpolant_is_of_order_8(x: float) -> None:
    """The interpolant's weights b(x) = Σ_j P[:, j] x^(j+1) meet the conditions of every tree
    to order 8 with x^|t| / γ(t) (the weights' coefficients reach 1e4, so the round-off of
    the sums grows to 1e-12 at x = 1); at x = 1 they are the 9th-order weights."""
    weights = _vern9.P @ x ** np.arange(1, _vern9.DENSE_ROWS + 1)
    for order in range(1, 9):
        assert _worst_residual(weights, _vern9.A, order, x) < 1e-11, order
    if x < 1.0:
        assert _worst_residual(weights, _vern9.A, 9, x) > 1e-8
