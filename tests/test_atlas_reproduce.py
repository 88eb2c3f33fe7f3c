"""``celtstone reproduce atlas`` (issue 15, item 3): its files whole, the report's section 7
read from them, the CLI's ``--atlas-grid``, nothing left by an interruption.

The atlas read here is the coarse one of the quick reproduction (``tests/conftest.py``:
``celtstone reproduce all --quick``, whose tests in ``test_reproduce.py`` read the same
directory), computed once for both files.

Oracle: the counts of the report are recomputed from the store ``atlas.zarr`` (the
verdicts ``compute_atlas`` wrote), not from the JSON the report reads.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from celtstone.atlas import fields
from celtstone.atlas.search import stored_searches
from celtstone.atlas.target import ATLAS_GRIDS, DEFAULT_ATLAS_GRID, AtlasSlice
from celtstone.cli.main import main
from celtstone.cli.reproduce import ATLAS_GRID_WORDS
from celtstone.errors import ParameterError
from celtstone.files.export import read_table
from celtstone.reproduce import reproduce
from celtstone.reproduce.atlas_report import atlas_counts
from celtstone.reproduce.findings import FINDINGS
from celtstone.reproduce.study import TARGETS
from tests.conftest import QUICK_REPRODUCTION, QuickReproduction

GRID = ATLAS_GRIDS[DEFAULT_ATLAS_GRID]  # the quick reproduction's: no --atlas-grid
(SLICE,) = GRID.slices  # its files are named after it
QUICK = pytest.mark.xdist_group(QUICK_REPRODUCTION)  # one worker computes it (conftest)


@pytest.fixture(scope="module")
def atlas_out(quick_reproduction: QuickReproduction) -> Path:
    """The quick reproduction's directory: the atlas of :data:`GRID` beside the K&L body's
    targets."""
    assert quick_reproduction.status == 0
    assert "--atlas-grid" not in quick_reproduction.argv
    assert GRID.name == "coarse" and len(GRID.designs()) == 4
    return quick_reproduction.out


@QUICK
def test_atlas_writes_its_files_whole(atlas_out: Path) -> None:
    designs = GRID.designs()
    names = {p.name for p in atlas_out.iterdir()}
    stem = f"atlas_{SLICE.name}"
    assert {"atlas.zarr", f"{stem}.csv", f"{stem}.png", f"{stem}.svg"} <= names
    assert {"data", "report.md"} <= names
    assert not list(atlas_out.rglob("*.part"))
    dataset = xr.open_zarr(atlas_out / "atlas.zarr", consolidated=False)
    assert dataset.sizes["design"] == len(designs)
    assert dataset.attrs["atlas_grid"] == GRID.name
    table, header = read_table(atlas_out / f"{stem}.csv")
    assert len(table) == len(designs) and header["atlas_grid"] == GRID.name
    assert header["slice"].startswith("L [m] = 0.1, 0.2 × δ [deg] = 2, 4")
    for finding in FINDINGS:  # the CSV's verdicts are the store's
        assert table[finding].tolist() == dataset[finding].values.tolist()
    assert table["length"].tolist() == [d.length for d in designs]
    assert table["misalignment"].tolist() == [d.misalignment for d in designs]
    numbers = json.loads((atlas_out / "data" / "atlas_atlas.json").read_text())
    figure2 = json.loads((atlas_out / "data" / "fig2_kane_levinson_1982.json").read_text())
    assert numbers["run"]["id"] == figure2["run"]["id"]  # the one run that made both
    assert numbers["run"]["targets"] == [*TARGETS, "atlas"]  # ``all``


@QUICK
def test_report_counts_are_the_stores(atlas_out: Path) -> None:
    dataset = xr.open_zarr(atlas_out / "atlas.zarr", consolidated=False)
    count = len(GRID.designs())
    report = (atlas_out / "report.md").read_text(encoding="utf-8")
    section = report[report.index("## 7. For which stones") :]
    holds = int(dataset["all_findings_hold"].values.sum())
    assert f'All five findings hold ("yes") for {holds} of {count} designs.' in section
    assert f"Atlas grid **{GRID.name}**" in section
    for finding in FINDINGS:
        values = dataset[finding].values.tolist()
        row = f"| {finding} | {values.count('yes')} | {values.count('partly')} | "
        assert row + f"{values.count('no')} |" in section
    designs = [{"verdicts": {f: dataset[f].values[k] for f in FINDINGS}} for k in range(count)]
    counts = atlas_counts(designs)
    both = [
        all(dataset[f].values[k] == "yes" for f in ("period", "threshold")) for k in range(count)
    ]
    assert counts["pairs"]["period+threshold"] == sum(both)
    if holds == 0:
        assert "No design of this grid satisfies all five findings" in section
    assert f"](atlas_{SLICE.name}.png)" in section
    for search in stored_searches():  # the searches of record, from their stored summaries
        assert f"### The search for the long-run finding: the {search['box']} box" in section
        assert f"over **{search['points']} designs**" in section
        yes = search["verdicts"]["yes"]
        assert f'holds ("yes") for {yes} of {search["points"]} designs' in section


def test_atlas_counts_of_hand_made_verdicts() -> None:
    yes = dict.fromkeys(FINDINGS, "yes")
    designs = [
        {"verdicts": yes},
        {"verdicts": {**yes, "long_run": "no"}},
        {"verdicts": {**yes, "period": "partly", "long_run": "partly"}},
    ]
    counts = atlas_counts(designs)
    assert counts["all_five"] == 1
    assert counts["verdicts"]["long_run"] == {"yes": 1, "partly": 1, "no": 1}
    assert counts["pairs"]["period+long_run"] == 1
    assert counts["pairs"]["period+threshold"] == 2
    assert counts["pairs"]["energy_order+threshold"] == 3


def test_cli_grids_and_a_bad_one(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert set(ATLAS_GRID_WORDS) == set(ATLAS_GRIDS)
    for name, grid in ATLAS_GRIDS.items():
        assert f"{len(grid.designs())} designs" in ATLAS_GRID_WORDS[name]
    status = main(["reproduce", "atlas", "--atlas-grid", "huge", "--out", str(tmp_path)])
    assert status == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and "--atlas-grid" in error and "huge" in error
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(ParameterError, match="atlas"):
        reproduce(["atlas"], tmp_path, [], progress=False)  # no atlas target given


def test_interrupted_atlas_leaves_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Ctrl-C in the atlas's threshold sweeps (after its Figure 2 sweeps): exit 130, no
    file of it, no staging directory. (A directory ``atlas.zarr`` celtstone did not write
    is refused before any run: ``test_output_ownership.py``.)"""

    def interrupted(*args: object, **kwargs: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(fields, "_threshold", interrupted)
    argv = ["reproduce", "atlas", "--atlas-grid", "coarse", "--quick", "--no-progress"]
    assert main([*argv, "--out", str(tmp_path)]) == 130
    assert list(tmp_path.iterdir()) == []
    assert not list(tmp_path.rglob("*.part"))


def test_slices_refuse_what_is_no_design_parameter() -> None:
    with pytest.raises(ParameterError, match="slice"):
        AtlasSlice("x", "length", (0.1,), "colour", (1.0,))
    with pytest.raises(ParameterError, match="slice"):
        AtlasSlice("x", "length", (0.1,), "length", (0.2,))
    assert re.fullmatch(r"[a-z_]+", ATLAS_GRIDS["coarse"].slices[0].name)


def test_the_stone_grid_is_a_map_through_the_shipped_stone() -> None:
    """``--atlas-grid stone``: κ × δ at 0.95, 1, 1.05 of the stone's; its centre is the
    shipped ``atlas_stone_25cm`` and its contact the Hertz disk of PMMA on glass."""
    from celtstone import load_body
    from celtstone.atlas.target import STONE_ATLAS

    designs = STONE_ATLAS.designs()
    assert len(designs) == 9
    shipped = load_body("atlas_stone_25cm")
    centre = designs[4].body()
    assert centre.mass == pytest.approx(shipped.mass, rel=1e-9)
    assert np.allclose(centre.inertia, shipped.inertia, rtol=1e-9, atol=0.0)
    assert STONE_ATLAS.study.contact == "hybrid" and STONE_ATLAS.study.elastic_modulus
    assert STONE_ATLAS.study.variant.endswith("hertz-pmma-glass")
