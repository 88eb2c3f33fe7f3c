"""The methods' coefficient tables kept in ``solvers/tableaux.json`` equal SciPy's to the
last bit (they were copied so that a run starts without importing ``scipy.integrate``)."""

from __future__ import annotations

import numpy as np
import pytest

from celtstone.solvers import _dop853, _radau, _tableaux


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
