"""The atlas's findings as fields: judged by the report's own judges, from numbers equal
to a ``celtstone reproduce`` run of the same body, in a resumable store.

Oracles: hand-made numbers whose verdicts follow from the rules' text
(``reproduce/findings.py``), and a reduced reproduction of the same body (its numbers
and verdicts, computed by ``simulate`` one run at a time).
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import xarray as xr

import celtstone as cs
from celtstone.atlas import StoneDesign, atlas_dataset, compute_atlas, judge_design
from celtstone.atlas.fields import ATLAS_STUDY
from celtstone.reproduce import reproduce
from celtstone.reproduce.findings import FINDINGS, JUDGES
from celtstone.simulation.outcome import OUTCOMES

TOY_DESIGN = StoneDesign(0.1, 0.2, 0.2, 2.2187347030504900)  # the toy (test_atlas_family)
# a short study: 3 s runs, a 4-point f grid bisected to 0.04 (each finding still judged)
SHORT = dataclasses.replace(
    ATLAS_STUDY,
    fig2_t_end=3.0,
    fig3_t_end=4.0,
    threshold_grid=(0.05, 0.35, 4),
    threshold_t_end=3.0,
    bisection_tolerance=0.04,
    fig2_loads=("static",),
)


def _case(model: str, f: float | None, first: float | None, energy: float, **extra: Any) -> dict:
    return {
        "case": model if f is None else f"sliding_f{f:g}_static",
        "model": model,
        "friction_coefficient": f,
        "friction_load": None if f is None else "static",
        "first_reversal_time": first,
        "energy_initial": 1.0,
        "energy_final": energy,
        "energy_rest": 0.5,
        "peak_reversed_spin": 0.0 if first is None else 4.0 * energy,
        "max_energy_balance_error": 1e-12,
        "energy_monotone": True,
        "spin_crossing_count": 0,
        "spin_initial": -5.0,
        "spin_final": 0.0,
        "reversal_times": [] if first is None else [first],
        **extra,
    }


def _hand_made() -> dict[str, dict[str, Any]]:
    """Numbers with known verdicts: the reversal comes later as f falls (period: yes);
    the energy falls with f but the reversed spin does not (energy order: partly); one
    run's budget is open by 1e-6 E(0) (energy decrease: no); the lowest reversing f is
    0.1 (threshold: yes); rolling reverses thrice, sliding once, with fewer raw sign
    changes than rolling (long run: no)."""
    fig2 = {
        "cases": [
            _case("rolling", None, 2.0, 1.0),
            _case("sliding", 0.35, 1.0, 0.9, peak_reversed_spin=1.0),
            _case("sliding", 0.25, 1.5, 0.8, peak_reversed_spin=2.0),
            _case("sliding", 0.15, 3.0, 0.7, peak_reversed_spin=3.0, max_energy_balance_error=1e-6),
        ]
    }
    threshold = {
        "grid": [0.02, 0.1, 0.2],
        "grid_reverses": [False, True, True],
        "boundaries": [
            {
                "kind": "appears",
                "grid_bracket": [0.02, 0.1],
                "bracket": [0.095, 0.1],
                "estimate": 0.0975,
            }
        ],
        "lowest_reversing_f": 0.1,
        "reverses_anywhere": True,
    }
    fig3 = {
        "cases": [
            _case(
                "rolling", None, 2.0, 1.0, reversal_times=[2.0, 12.0, 30.0], spin_crossing_count=5
            ),
            _case("sliding", 0.35, 1.0, 0.9, spin_crossing_count=1),
        ],
        "friction": 0.35,
        "band": 0.2,
    }
    return {"fig2": fig2, "threshold": threshold, "fig3": fig3}


def test_verdicts_of_hand_made_numbers_are_the_rules() -> None:
    numbers = _hand_made()
    expected = {
        "period": "yes",
        "energy_order": "partly",
        "energy_decrease": "no",
        "threshold": "yes",
        "long_run": "no",
    }
    verdicts = judge_design(numbers)
    assert {k: v.reproduced for k, v in verdicts.items()} == expected
    dataset = atlas_dataset([TOY_DESIGN], [numbers], ATLAS_STUDY)
    for finding in FINDINGS:
        assert dataset[finding].values.tolist() == [expected[finding]]
        target, judge = JUDGES[finding]
        assert dataset[f"{finding}_ours"].values[0] == judge(numbers[target]).ours
    assert not dataset["all_findings_hold"].values[0]
    assert dataset["lowest_reversing_f"].values[0] == 0.1
    assert dataset["long_run_reversal_times"].sel(long_case="rolling").values[0].tolist() == [
        2.0,
        12.0,
        30.0,
    ]
    assert dataset["length"].attrs["units"] == "m"
    # a field that holds an outcome of the runs has the outcome's declared unit
    for field, outcome in {
        "fig2_first_reversal_time": "first_reversal_time",
        "fig2_energy_final": "energy_final",
        "fig2_peak_reversed_spin": "peak_reversed_spin",
        "long_run_spin_crossing_count": "spin_crossing_count",
        "long_run_spin_final": "spin_final",
    }.items():
        assert dataset[field].attrs["units"] == OUTCOMES[outcome].variable.unit, field


def _body_file(body: cs.Body, path: Path) -> Path:
    """``body`` as a body file (numbers written in full, so it reads back exactly)."""
    a, b, c = body.shape.semi_axes  # type: ignore[union-attr]
    path.write_text(
        f'title = "atlas design"\nsource = "celtstone atlas"\n\n[body]\nmass = {body.mass!r}\n'
        f"gravity = {body.gravity!r}\ninertia = {json.dumps([list(r) for r in body.inertia])}\n\n"
        f'[shape]\nkind = "ellipsoid"\nsemi_axes = [{a!r}, {b!r}, {c!r}]\n'
        f"com_offset = {body.shape.com_offset!r}\n",  # type: ignore[union-attr]
        encoding="utf-8",
    )
    return path


def _comparable(case: dict[str, Any]) -> dict[str, Any]:
    keys = ("first_reversal_time", "peak_reversed_spin", "energy_final", "energy_monotone")
    return {k: case[k] for k in keys}


def test_the_atlas_equals_a_reproduction_of_the_same_body(tmp_path: Path) -> None:
    """The toy's numbers from the atlas's sweeps equal those of ``celtstone reproduce``
    with the same settings, and so do the verdicts; a second design runs beside it."""
    path = _body_file(TOY_DESIGN.body(), tmp_path / "stone.toml")
    study = dataclasses.replace(SHORT, body=str(path))
    reproduce(["fig2", "threshold", "fig3"], tmp_path / "results", [study], progress=False)
    data = tmp_path / "results" / "data"
    expected = {
        target: json.loads((data / f"{target}_{study.key}.json").read_text(encoding="utf-8"))
        for target in ("fig2", "threshold", "fig3")
    }
    other = StoneDesign(0.15, 0.25, 0.15, 3.0, mass_fraction=0.3)
    atlas = compute_atlas([TOY_DESIGN, other], SHORT, tmp_path / "atlas", workers=2)
    from celtstone.atlas import atlas_numbers

    numbers = atlas_numbers([TOY_DESIGN], SHORT, None, workers=2)[0]
    for ours, theirs in zip(numbers["fig2"]["cases"], expected["fig2"]["cases"], strict=True):
        assert ours["case"] == theirs["case"]
        got, want = _comparable(ours), _comparable(theirs)
        assert got["first_reversal_time"] == want["first_reversal_time"]
        assert got["peak_reversed_spin"] == want["peak_reversed_spin"]
        assert got["energy_final"] == pytest.approx(want["energy_final"], rel=1e-13)
    keys = ("grid", "grid_reverses", "boundaries", "lowest_reversing_f", "reverses_anywhere")
    assert {k: numbers["threshold"][k] for k in keys} == {k: expected["threshold"][k] for k in keys}
    for ours, theirs in zip(numbers["fig3"]["cases"], expected["fig3"]["cases"], strict=True):
        assert ours["reversal_times"] == theirs["reversal_times"]
        assert ours["spin_crossing_count"] == theirs["spin_crossing_count"]
    for finding, (target, judge) in JUDGES.items():
        verdict = judge(expected[target])
        assert atlas[finding].values[0] == verdict.reproduced, finding
    assert atlas.sizes["design"] == 2
    assert set(np.unique(atlas["threshold"].values)) <= {"yes", "partly", "no"}
    assert math.isclose(atlas["mass"].values[0], TOY_DESIGN.body().mass)

    # the store: refused without resume or overwrite, resumed without running again
    with pytest.raises(cs.ParameterError, match="resume or overwrite"):
        compute_atlas([TOY_DESIGN, other], SHORT, tmp_path / "atlas")
    again = compute_atlas([TOY_DESIGN, other], SHORT, tmp_path / "atlas", resume=True)
    xr.testing.assert_identical(again.drop_attrs(), atlas.drop_attrs())
    stored = xr.open_zarr(tmp_path / "atlas" / "atlas.zarr", consolidated=False).load()
    assert stored.attrs["format"] == "celtstone-atlas-1"
    assert stored["period"].values.tolist() == atlas["period"].values.tolist()
    with pytest.raises(cs.ParameterError, match="resume"):
        compute_atlas([other, TOY_DESIGN], SHORT, tmp_path / "atlas", resume=True)
