"""The search for the long-run finding (issue 15): its points, its runs and verdicts, its
summary and the report's lines of it.

Oracles: the definition of a Latin hypercube (one point per stratum of every axis), the
rim and rest-stability bounds the family refuses beyond, direct ``simulate`` runs
summarised as ``celtstone reproduce`` does and judged by the report's judge, and counts
recomputed from the search's own table.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from celtstone.atlas.family import StoneDesign, largest_misalignment
from celtstone.atlas.fields import ATLAS_STUDY, write_atlas
from celtstone.atlas.search import (
    SEARCH_AXES,
    SEARCH_BOXES,
    SEARCH_CONTACTS,
    SearchPoint,
    contact_study,
    rank_points,
    search_dataset,
    search_long_runs,
    search_points,
    search_summary,
    search_table,
    stored_search,
)
from celtstone.errors import ParameterError
from celtstone.reproduce.atlas_report import search_lines
from celtstone.reproduce.cases import summarise
from celtstone.reproduce.findings import JUDGES
from celtstone.simulation.integrate import simulate

SHORT = dataclasses.replace(ATLAS_STUDY, fig3_t_end=3.0)  # long runs of 3 s


def test_the_points_are_a_latin_hypercube_of_buildable_stones() -> None:
    count = 12
    points = search_points(count, seed=7)
    assert points == search_points(count, seed=7)  # the seed makes the points
    assert points != search_points(count, seed=8)
    low, high, scale = SEARCH_AXES["length"]
    assert scale == "log"
    # L is log-uniform and unconditional: one point in each of the count strata
    # (the values are rounded to 4 digits, far inside a stratum's width)
    strata = np.floor(
        count * np.log([p.design.length / low for p in points]) / math.log(high / low)
    )
    assert sorted(strata.tolist()) == list(range(count))
    for point in points:
        design = point.design
        for name, (lowest, highest, _) in SEARCH_AXES.items():
            value = getattr(design, name)
            assert value <= highest * (1 + 1e-3)
            if name != "misalignment":
                assert value >= lowest * (1 - 1e-3)
        assert design.misalignment <= largest_misalignment(design.width_ratio, design.mass_fraction)
    contacts = [p.contact for p in points]
    assert all(contacts.count(name) == count // len(SEARCH_CONTACTS) for name in SEARCH_CONTACTS)


def test_each_box_keeps_its_points_inside() -> None:
    for box, axes in SEARCH_BOXES.items():
        for point in search_points(6, seed=1, box=box):
            for name, (lowest, highest, _) in axes.items():
                value = getattr(point.design, name)
                assert lowest * (1 - 1e-3) <= value <= highest * (1 + 1e-3), (box, name)
    with pytest.raises(ParameterError, match="box"):
        search_points(6, seed=1, box="huge")


@pytest.mark.parametrize(("width_ratio", "mass_fraction"), [(0.2, 0.0802), (0.12, 0.5), (0.6, 1)])
def test_the_largest_misalignment_puts_the_masses_on_the_rim(
    width_ratio: float, mass_fraction: float
) -> None:
    largest = largest_misalignment(width_ratio, mass_fraction)
    for length in (0.05, 0.4):  # independent of the size
        design = StoneDesign(length, width_ratio, 0.05, min(largest, 10.0), mass_fraction)
        if largest <= 10.0:  # y0 on the rim margin (x0/a)² + (y0/b)² = 0.9²
            a, b, _ = design.semi_axes
            x0, y0 = design.point_mass_position
            assert (x0 / a) ** 2 + (y0 / b) ** 2 == pytest.approx(0.81, rel=1e-9)
    if largest < 10.0:
        with pytest.raises(ParameterError, match="misalignment"):
            StoneDesign(0.1, width_ratio, 0.05, largest * 1.001, mass_fraction)


def test_a_contact_axis_makes_the_hertz_radius_of_its_pair() -> None:
    assert contact_study("eps_1mm") is ATLAS_STUDY
    for name in ("hertz_pmma_glass", "hertz_pmma_pmma"):
        model = contact_study(name).sliding(0.35)
        assert model.is_hertz_radius
    with pytest.raises(ParameterError, match="contact"):
        SearchPoint(StoneDesign(0.1, 0.25, 0.15, 2.0), "steel")


@pytest.fixture(scope="module")
def searched() -> tuple[list[SearchPoint], list[dict], object]:
    points = [
        SearchPoint(StoneDesign(0.1, 0.25, 0.15, 4.0, 0.5), "eps_1mm"),
        SearchPoint(StoneDesign(0.2, 0.3, 0.15, 3.0, 0.5), "hertz_pmma_glass"),
    ]
    numbers = search_long_runs(points, SHORT, workers=2)
    return points, numbers, search_dataset(points, numbers, SHORT, seed=None)


@pytest.mark.xdist_group("atlas-search")  # `searched` once, in one worker
def test_each_point_is_judged_as_the_report_judges_a_direct_run(searched) -> None:  # type: ignore[no-untyped-def]
    points, numbers, dataset = searched
    target, judge = JUDGES["long_run"]
    assert target == "fig3"
    for k, point in enumerate(points):
        study = contact_study(point.contact, SHORT)
        body = point.design.body()
        times = []
        for model in (study.rolling(), study.sliding(study.fig3_friction)):
            trajectory = simulate(model, body, study.initial_state, study.fig3_t_end)
            times.append(summarise(trajectory, body, study.band)["reversal_times"])
        assert numbers[k]["cases"][0]["reversal_times"] == times[0]
        assert numbers[k]["cases"][1]["reversal_times"] == times[1]
        row = dataset.isel(point=k)
        assert row["reversals"].values.tolist() == [len(t) for t in times]
        assert str(row["long_run"].values) == judge(numbers[k]).reproduced
        assert str(row["contact"].values) == point.contact
        rolling_after = np.diff(times[0][1:])
        expected = float(rolling_after.min()) if rolling_after.size else math.nan
        assert float(row["rolling_shortest_interval"]) == pytest.approx(expected, nan_ok=True)


@pytest.mark.xdist_group("atlas-search")  # `searched` once, in one worker
def test_summary_and_report_lines_are_the_table(searched, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    _, _, dataset = searched
    table = search_table(dataset)
    summary = search_summary(dataset, best=1)
    summary.update(cost={"date": "today", "wall_s": 1, "cpu_s": 1, "workers": 2})
    summary["cost"].update(load_average_start=0.5, load_average_1min=0.5)
    summary["software"] = "celtstone test"
    assert summary["points"] == len(table) == 2
    for verdict in ("yes", "partly", "no"):
        assert summary["verdicts"][verdict] == int((table["long_run"] == verdict).sum())
    both = (table["rolling_reversals"] >= 3) & (table["sliding_reversals"] >= 3)
    assert summary["both_three"] == int(both.sum())
    assert sorted(rank_points(dataset)) == [0, 1]
    lines = "\n".join(search_lines(summary))
    assert "over **2 designs**" in lines
    assert f'holds ("yes") for {summary["verdicts"]["yes"]} of 2 designs' in lines
    assert "| Hertz, PMMA on glass | 1 |" in lines
    # the store is written whole and replaced only by a store of its own format
    write_atlas(dataset, tmp_path / "search.zarr")
    write_atlas(dataset, tmp_path / "search.zarr", overwrite=True)
    (tmp_path / "other.zarr").mkdir()
    with pytest.raises(ParameterError, match="out"):
        write_atlas(dataset, tmp_path / "other.zarr", overwrite=True)
    assert stored_search(tmp_path / "none.json") is None


def test_the_atlas_stone_is_the_third_study_in_its_own_contact() -> None:
    """``celtstone reproduce`` runs the atlas's stone with the contact it was found with
    (the Hertz radius of PMMA on glass, stick–slip), and gives it no realistic twin."""
    from celtstone.cli.reproduce import CONTACTS
    from celtstone.reproduce.study import (
        ATLAS_STONE_STUDY,
        REALISTIC_STUDIES,
        STUDIES,
        study_for,
    )

    assert STUDIES[-1] is ATLAS_STONE_STUDY and study_for("atlas_stone_25cm") is ATLAS_STONE_STUDY
    assert ATLAS_STONE_STUDY.key == "atlas_stone_25cm+hertz-pmma-glass"
    assert ATLAS_STONE_STUDY.load_body().name == "atlas_stone_25cm"
    model = ATLAS_STONE_STUDY.sliding(0.35)
    assert model.is_hertz_radius and model.name == "sliding"  # the hybrid's sliding phase
    assert "atlas_stone_25cm" not in [s.body for s in REALISTIC_STUDIES]
    assert CONTACTS["paper"][2] == STUDIES and CONTACTS["realistic"][2] == REALISTIC_STUDIES


@pytest.mark.slow
def test_the_atlas_stone_reproduces_all_five_findings(tmp_path: Path) -> None:
    """The full reproduction of the atlas's stone (the report's 49-point f grid, both
    friction loads; about 3 min): every finding "yes" by the report's judges."""
    import json

    from celtstone.reproduce import reproduce
    from celtstone.reproduce.study import ATLAS_STONE_STUDY

    reproduce(["fig2", "fig3", "threshold"], tmp_path, [ATLAS_STONE_STUDY], progress=False)
    for finding, (target, judge) in JUDGES.items():
        path = tmp_path / "data" / f"{target}_{ATLAS_STONE_STUDY.key}.json"
        verdict = judge(json.loads(path.read_text(encoding="utf-8")))
        assert verdict is not None and verdict.reproduced == "yes", (finding, verdict)
