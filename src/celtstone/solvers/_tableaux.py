"""The methods' coefficient tables, read from ``tableaux.json`` beside this file.

They are SciPy's (``scipy.integrate._ivp.dop853_coefficients`` for DOP853 and
``scipy.integrate._ivp.radau`` for Radau IIA), copied once into the data file so that
starting a run does not import ``scipy.integrate`` (0.6 s, with SciPy's optimisation and
special-function modules). ``tests/test_tableaux.py`` checks that the file still equals
SciPy's tables to the last bit; ``python -m celtstone.solvers._tableaux`` rewrites it.
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


def _plain(value: Any) -> Any:
    """A table entry as JSON: an int, a float, [re, im] for a complex, nested lists."""
    if isinstance(value, complex):
        return [value.real, value.imag]
    if isinstance(value, np.ndarray):
        return value.tolist()
    return value


@cache
def table(name: str) -> dict[str, Any]:
    """The arrays (float64, C order) and numbers of the table ``name`` ("dop853", "radau")."""
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
    path.write_text(json.dumps(from_scipy(), indent=1) + "\n", encoding="utf-8")
    print(f"wrote {path}")
