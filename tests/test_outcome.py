"""The outcome record is declared once (``simulation.outcome``): ``run --json``, the sweep
store, the reproduction's cases and the user guide's key list all read that declaration."""

from __future__ import annotations

import json
import math
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

import celtstone as cs
from celtstone.reproduce.results import read_result
from celtstone.simulation.outcome import (
    OUTCOMES,
    RENAMED_OUTCOMES,
    SETTINGS,
    SWEPT,
    current_outcomes,
    units,
)
from celtstone.solvers.batch import RESULT_FIELDS
from celtstone.sweep import Sweep, open_sweep
from celtstone.sweep.store import RESULT_FIELDS as STORE_FIELDS

GUIDE = Path(__file__).parents[1] / "docs" / "guide" / "outputs.md"
STATE = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
RUNS = {
    "rolling": cs.RollingModel(),
    "sliding": cs.SlidingModel(friction_coefficient=0.35, friction_load="dynamic"),
    "hybrid": cs.HybridModel(friction_coefficient=0.35, friction_load="dynamic"),
}


def test_a_name_is_an_outcome_or_a_setting_never_both() -> None:
    assert not set(OUTCOMES) & set(SETTINGS)
    assert not set(RENAMED_OUTCOMES) & (set(OUTCOMES) | set(SETTINGS))
    assert set(RENAMED_OUTCOMES.values()) <= set(OUTCOMES)
    for name, outcome in OUTCOMES.items():
        assert outcome.unit != "deg", f"{name}: angles are in rad"


@pytest.mark.parametrize("contact", list(RUNS))
def test_run_json_keys_are_declared_with_their_units(kane_levinson: cs.Body, contact: str) -> None:
    """Every key ``run --json`` prints is declared, its unit in ``units`` is the
    declaration's, and every outcome of the contact is there."""
    summary = cs.simulate(RUNS[contact], kane_levinson, STATE, 0.5).summary()
    printed = set(summary) - {"units"}
    assert printed <= set(OUTCOMES) | set(SETTINGS)
    assert summary["units"] == units(printed)
    expected = {n for n, o in OUTCOMES.items() if not o.contact or o.contact == contact}
    assert expected <= printed
    assert not {n for n, o in OUTCOMES.items() if o.contact and o.contact != contact} & printed
    json.dumps(summary, allow_nan=False)  # JSON-safe: a missing number is null


def test_units_refuse_an_undeclared_key() -> None:
    with pytest.raises(KeyError, match="max_tilt_deg"):
        units(["max_tilt_deg"])


def test_the_sweep_stores_the_swept_outcomes() -> None:
    """The store's fields are the swept outcomes, in order, with the declared unit and
    meaning; the batch's columns number them."""
    assert tuple(f.name for f in RESULT_FIELDS) == SWEPT == tuple(STORE_FIELDS)
    for name, (dtype, fill, unit, long_name) in STORE_FIELDS.items():
        declared = OUTCOMES[name]
        assert (dtype, unit, long_name) == (
            declared.dtype,
            declared.unit,
            declared.variable.long_name,
        )
        assert fill == declared.fill or (math.isnan(fill) and math.isnan(declared.fill))
    results = Sweep({"initial_spin": [-5.0, 3.0]}, model="rolling", t_end=0.2).run(workers=1)
    assert set(results.data_vars) == set(SWEPT)
    for name in SWEPT:
        assert results[name].attrs.get("units", "") == OUTCOMES[name].unit


def test_a_store_written_with_the_old_names_reads_with_the_names_now(tmp_path: Path) -> None:
    """A sweep store written before the renames (``n_reversals``, ``final_spin``…) opens
    with the names now and the same values."""
    store = tmp_path / "old.zarr"
    written = Sweep({"initial_spin": [-5.0, 3.0]}, model="rolling", t_end=0.2).run(store, workers=1)
    renamed = {new: old for old, new in RENAMED_OUTCOMES.items() if new in SWEPT}
    for new, old in renamed.items():  # a Zarr v3 array is named by its directory
        shutil.move(store / new, store / old)
    loaded = open_sweep(store)
    assert set(loaded.data_vars) == set(SWEPT)
    for name in SWEPT:
        np.testing.assert_array_equal(loaded[name].values, written[name].values, err_msg=name)


def test_a_result_written_with_the_old_names_reads_with_the_names_now(tmp_path: Path) -> None:
    old_case = {"raw_sign_changes": 3, "max_budget_error": 1e-12, "first_raw_sign_change": 1.5}
    assert current_outcomes(old_case) == {
        "spin_crossing_count": 3,
        "max_energy_balance_error": 1e-12,
        "first_spin_crossing_time": 1.5,
    }
    path = tmp_path / "fig3_paper.json"
    result = {"target": "fig3", "body": "b", "study": "s", "t_end": 1.0, "cases": [old_case]}
    path.write_text(json.dumps(result), encoding="utf-8")
    read = read_result(path)
    assert read is not None and read["cases"][0]["spin_crossing_count"] == 3


def _cell(text: str) -> str:
    return text.replace("|", "\\|")  # a bar of |E| inside a Markdown table cell


def _key_tables() -> str:
    """The user guide's tables of ``run --json``'s keys, from the declaration."""
    rows = ["| key | unit | meaning | in a sweep |", "|---|---|---|---|"]
    for name, outcome in OUTCOMES.items():
        where = "yes" if outcome.swept else ""
        meaning = outcome.variable.long_name + (" (stick–slip only)" if outcome.contact else "")
        rows.append(f"| `{name}` | {outcome.unit or '-'} | {_cell(meaning)} | {where} |")
    settings = ["| key | unit | meaning |", "|---|---|---|"]
    settings += [f"| `{n}` | {s.unit or '-'} | {_cell(s.meaning)} |" for n, s in SETTINGS.items()]
    return "\n".join([*rows, "", "Settings:", "", *settings])


def test_the_guides_key_list_is_the_declaration() -> None:
    """docs/guide/outputs.md lists every outcome and setting as declared (the text between
    the ``outcome-keys`` marks is :func:`_key_tables`)."""
    text = GUIDE.read_text(encoding="utf-8")
    found = re.search(r"<!-- outcome-keys -->\n(.*?)\n<!-- /outcome-keys -->", text, re.S)
    assert found, "docs/guide/outputs.md has no outcome-keys section"
    assert found.group(1) == _key_tables(), "regenerate the table from tests/test_outcome.py"


def test_a_store_written_with_the_old_names_is_not_resumed(tmp_path: Path) -> None:
    """Resuming a store written before the renames is refused in one line naming what it
    lacks (it reads, but new points could not be written beside the old names)."""
    store = tmp_path / "old.zarr"
    sweep = Sweep({"initial_spin": [-5.0, 3.0]}, model="rolling", t_end=0.2)
    sweep.run(store, workers=1)
    shutil.move(store / "spin_final", store / "final_spin")
    with pytest.raises(cs.ParameterError, match="has no spin_final") as error:
        sweep.run(store, resume=True, workers=1)
    assert len(str(error.value).splitlines()) == 1
