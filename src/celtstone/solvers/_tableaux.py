"""The methods' coefficient tables, read from ``tableaux.json`` beside this file.

DOP853's and Radau IIA's are SciPy's (``scipy.integrate._ivp.dop853_coefficients`` and
``scipy.integrate._ivp.radau``), copied once into the data file so that starting a run
does not import ``scipy.integrate`` (0.6 s, with SciPy's optimisation and
special-function modules). ``tests/test_tableaux.py`` checks that the file still equals
SciPy's tables to the last bit; ``python -m celtstone.solvers._tableaux`` rewrites them
and keeps the others. Verner's 9(8) pair (``VERNER_KEYS``), which SciPy does not have, is
J. H. Verner's published table rounded to binary64; the tests check its order conditions
(every rooted tree to order 9, the embedded pair and the interpolant to order 8).
"""

from __future__ import annotations

import json
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

FILE = "tableaux.json"

# table name -> names of its arrays or numbers; a complex number is stored as [re, im]
TABLES = {
    "dop853": ("N_STAGES", "N_STAGES_EXTENDED", "A", "B", "C", "E3", "E5", "D"),
    "radau": ("C", "E", "MU_REAL", "MU_COMPLEX", "T", "TI", "P"),
}
# the table that is not SciPy's: stages, weights, error weights (8th-order minus 9th-order),
# nodes and the interpolant's polynomial coefficients
VERNER_KEYS = ("N_STAGES", "N_STAGES_EXTENDED", "A", "B", "C", "E", "P")


def _plain(value: Any) -> Any:
    """A table entry as JSON: an int, a float, [re, im] for a complex, nested lists."""
    if isinstance(value, complex):
        return [value.real, value.imag]
    if isinstance(value, np.ndarray):
        return value.tolist()
    return value


@cache
def table(name: str) -> dict[str, Any]:
    """The arrays (float64, C order) and numbers of the table ``name`` ("dop853", "radau",
    "vern9")."""
    stored = json.loads(resources.files(__package__).joinpath(FILE).read_text(encoding="utf-8"))
    entries: dict[str, Any] = {}
    for key, value in stored[name].items():
        if key == "MU_COMPLEX":
            entries[key] = complex(*value)
        elif isinstance(value, list):
            entries[key] = np.ascontiguousarray(value, dtype=np.float64)
        else:
            entries[key] = value
    return entries


def from_scipy() -> dict[str, dict[str, Any]]:
    """The tables as SciPy holds them, as plain JSON values."""
    from scipy.integrate._ivp import dop853_coefficients, radau

    modules = {"dop853": dop853_coefficients, "radau": radau}
    return {
        name: {key: _plain(getattr(modules[name], key)) for key in keys}
        for name, keys in TABLES.items()
    }


if __name__ == "__main__":
    path = Path(__file__).with_name(FILE)
    tables = json.loads(path.read_text(encoding="utf-8"))
    tables.update(from_scipy())
    path.write_text(json.dumps(tables, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {path}")
