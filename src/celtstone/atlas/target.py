"""``celtstone reproduce atlas``: each finding's verdict over two-parameter slices of the
family, the designs where all five hold, and the numbers behind them (issue 15, item 3).

An :class:`AtlasGrid` names the slices (two parameters of
:class:`~celtstone.atlas.family.StoneDesign` varied, the others fixed) and the study of
their runs; :data:`ATLAS_GRIDS` holds the coarse default of ``make run`` and a finer one
(``--atlas-grid fine``). :class:`AtlasTarget` is the target ``reproduce`` runs in its
staging directory (``reproduce.targets``: the files appear whole or not at all): it
computes every distinct design of every slice at once (:func:`compute_atlas`, in memory)
and writes

* ``atlas.zarr``, the atlas store of every design (``fields.write_atlas``);
* ``atlas_SLICE.csv``, one row per design of the slice: its parameters, the numbers the
  judges read, each finding's verdict (provenance header, ``export.write_table``);
* ``atlas_SLICE.png`` / ``.svg``, a panel per finding and one for all five;
* ``data/atlas_atlas.json``, the numbers the report's section 7 is written from, with the
  stored summaries of the searches for the long-run finding (``atlas.search``,
  ``benchmarks/atlas_search.py``), which the section states after the grid's verdicts.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from celtstone.atlas.family import MaterialPair, StoneDesign
from celtstone.atlas.fields import ATLAS_STUDY, compute_atlas, hertz_study, write_atlas
from celtstone.atlas.search import ATLAS_STONE_DESIGN, stored_searches
from celtstone.errors import ParameterError
from celtstone.files.export import write_table
from celtstone.plotting import plot_verdict_maps, save_figure_formats
from celtstone.reproduce import FINDINGS, PARAMETER_WORDS, Progress, Study, reduced
from celtstone.simulation.integrate import version

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "ATLAS_GRIDS",
    "COARSE_ATLAS",
    "DEFAULT_ATLAS_GRID",
    "FINE_ATLAS",
    "AtlasGrid",
    "AtlasSlice",
    "AtlasTarget",
]

_PARAMETERS = tuple(f.name for f in dataclasses.fields(StoneDesign))
_CSV_NUMBERS = (
    "mass",
    "rocking_period",
    "lowest_reversing_f",
    "reversal_appears_f",
    "reversal_disappears_f",
)


@dataclass(frozen=True)
class AtlasSlice:
    """Designs over two parameters of :class:`StoneDesign` (``x`` and ``y``, each a field
    name, every pair of their values), the others fixed (``fixed``: name, value pairs;
    the rest the design's defaults). ``name`` names its files, ``atlas_NAME.csv``."""

    name: str
    x: str
    x_values: tuple[float, ...]
    y: str
    y_values: tuple[float, ...]
    fixed: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        for name in (self.x, self.y, *(k for k, _ in self.fixed)):
            if name not in _PARAMETERS:
                raise ParameterError(
                    "slice", name, "a StoneDesign field: " + ", ".join(_PARAMETERS)
                )
        if self.x == self.y or not self.x_values or not self.y_values:
            raise ParameterError("slice", self.name, "two different parameters, each with values")
        if not all(c.isalnum() or c in "_-" for c in self.name):
            raise ParameterError("slice", self.name, "letters, digits, _ and - (file names)")

    def designs(self) -> list[StoneDesign]:
        """Every (x, y) pair's design, x fastest (refused as ``StoneDesign`` refuses)."""
        return [
            StoneDesign(**{**dict(self.fixed), self.x: x, self.y: y})
            for y, x in itertools.product(self.y_values, self.x_values)
        ]

    def words(self) -> str:
        """``L [m] = 0.1, 0.2 × δ [deg] = 2, 4; b/a = 0.25, c/a = 0.15, κ = 0.5``."""
        fixed = ", ".join(f"{PARAMETER_WORDS[k]} = {v:g}" for k, v in self.fixed)
        return (
            f"{PARAMETER_WORDS[self.x]} = {', '.join(f'{v:g}' for v in self.x_values)} × "
            f"{PARAMETER_WORDS[self.y]} = {', '.join(f'{v:g}' for v in self.y_values)}"
            + (f"; {fixed}" if fixed else "")
        )


@dataclass(frozen=True)
class AtlasGrid:
    """The atlas of a reproduction: its ``name`` (the report says it), its slices, and the
    study of every design's runs (start, contact, run lengths, f grid)."""

    name: str
    slices: tuple[AtlasSlice, ...]
    study: Study = ATLAS_STUDY

    def designs(self) -> list[StoneDesign]:
        """Every distinct design of every slice, in order of first appearance."""
        return list(dict.fromkeys(d for s in self.slices for d in s.designs()))


_SLICE_FIXED = (("width_ratio", 0.25), ("height_ratio", 0.15), ("mass_fraction", 0.5))
"""b/a, c/a and κ of the L × δ slices: the first scan of decisions §32."""

COARSE_ATLAS = AtlasGrid(
    name="coarse",
    slices=(
        AtlasSlice(
            "length_misalignment", "length", (0.1, 0.2), "misalignment", (2.0, 4.0), _SLICE_FIXED
        ),
    ),
    study=dataclasses.replace(
        ATLAS_STUDY, threshold_grid=(0.02, 0.5, 7), bisection_tolerance=0.01, fig2_loads=("static",)
    ),
)
"""``make run``'s atlas: 4 designs, L = 0.1, 0.2 m × δ = 2, 4° (the first scan's best
corner), Figure 2 with N = m g only (the load the Figure 2 findings are judged on), a
7-point threshold grid (step 0.08) bisected to Δf = 0.01 (decisions §32: cost)."""

FINE_ATLAS = AtlasGrid(
    name="fine",
    slices=(
        AtlasSlice(
            "length_misalignment",
            "length",
            (0.05, 0.1, 0.2, 0.4),
            "misalignment",
            (0.5, 1.0, 2.0, 4.0),
            _SLICE_FIXED,
        ),
        AtlasSlice(
            "width_height",
            "width_ratio",
            (0.2, 0.3, 0.4),
            "height_ratio",
            (0.1, 0.15, 0.2),
            (("length", 0.1), ("misalignment", 4.0), ("mass_fraction", 0.5)),
        ),
    ),
)
"""``--atlas-grid fine``: 25 designs, the 16 of the first scan (L × δ) and 9 over b/a × c/a
at its best L and δ, with :data:`~celtstone.atlas.fields.ATLAS_STUDY` (both friction loads,
a 13-point threshold grid bisected to Δf = 0.005)."""

_STONE = ATLAS_STONE_DESIGN
STONE_ATLAS = AtlasGrid(
    name="stone",
    slices=(
        AtlasSlice(
            "stone_mass_misalignment",
            "mass_fraction",
            tuple(round(_STONE["mass_fraction"] * k, 4) for k in (0.95, 1.0, 1.05)),
            "misalignment",
            tuple(round(_STONE["misalignment"] * k, 4) for k in (0.95, 1.0, 1.05)),
            tuple(
                (name, value)
                for name, value in _STONE.items()
                if name not in ("mass_fraction", "misalignment")
            ),
        ),
    ),
    study=hertz_study(ATLAS_STUDY, MaterialPair("pmma", "glass")),
)
"""``--atlas-grid stone``: 9 designs, κ × δ at 0.95, 1 and 1.05 times the atlas stone's
(``atlas_stone_25cm``, docs/bodies.md), its L, b/a and c/a, with the Hertz contact of PMMA
on glass it was found with and :data:`~celtstone.atlas.fields.ATLAS_STUDY`'s runs: a map
through the region where all five findings hold (decisions §32)."""

ATLAS_GRIDS = {grid.name: grid for grid in (COARSE_ATLAS, FINE_ATLAS, STONE_ATLAS)}
DEFAULT_ATLAS_GRID = COARSE_ATLAS.name


def _csv_table(dataset: xr.Dataset, rows: Sequence[int]) -> Any:
    """One row per design of ``rows``: parameters, numbers, verdicts."""
    import pandas as pd

    table: dict[str, Any] = {name: dataset[name].values[rows] for name in _PARAMETERS}
    for name in _CSV_NUMBERS:
        table[name] = dataset[name].values[rows]
    for case in dataset["fig2_case"].values:
        table[f"first_reversal_time_{case}"] = (
            dataset["fig2_first_reversal_time"].sel(fig2_case=case).values[rows]
        )
    for case in dataset["long_case"].values:
        table[f"long_run_reversals_{case}"] = (
            dataset["long_run_reversals"].sel(long_case=case).values[rows]
        )
    for finding in FINDINGS:
        table[finding] = dataset[finding].values[rows]
    table["all_five"] = dataset["all_findings_hold"].values[rows]
    return pd.DataFrame(table)


def _index(designs: Sequence[StoneDesign]) -> dict[StoneDesign, int]:
    return {design: k for k, design in enumerate(designs)}


@dataclass(frozen=True)
class AtlasTarget:
    """The ``atlas`` target of ``celtstone reproduce`` for ``grid`` (``quick``: its study
    shortened by ``reproduce.reduced``, a smoke test), its runs on ``device`` ("cpu",
    "cuda" or "auto": ``compute_atlas``)."""

    grid: AtlasGrid = COARSE_ATLAS
    quick: bool = False
    device: str = "cpu"

    @property
    def study(self) -> Study:
        """The study of the runs (shortened with ``quick``)."""
        return reduced(self.grid.study) if self.quick else self.grid.study

    def runs(self) -> int:
        """Steps of the progress bar: one per stage (Figure 2, threshold, long runs)."""
        return 3

    def __call__(self, out: Path, progress: Progress) -> dict[str, Any]:
        """Compute the atlas and write its files into ``out`` (the staging directory);
        the numbers of the report's section 7."""
        study, grid = self.study, self.grid
        designs = grid.designs()

        def say(words: str) -> None:
            progress.set_description(f"atlas ({grid.name}, {len(designs)} designs): {words}")
            if words != "Figure 2 sweeps":
                progress.update(1)

        dataset = compute_atlas(designs, study, progress=say, device=self.device)
        progress.update(1)
        dataset.attrs["atlas_grid"] = grid.name
        write_atlas(dataset, out / "atlas.zarr")
        index = _index(designs)
        header = {
            "software": f"celtstone {version()}",
            "atlas_grid": grid.name,
            "construction": dataset.attrs["construction"],
            "study": study.describe(),
            "study_settings": repr(study),
            "contact": study.contact_words(),
            "reversal_band_rad_per_s": study.band,
            "verdicts": "yes / partly / no by celtstone.reproduce.findings.JUDGES",
        }
        slices = []
        figures: list[str] = []
        for piece in grid.slices:
            rows = [index[d] for d in piece.designs()]
            stem = f"atlas_{piece.name}"
            table = _csv_table(dataset, rows)
            write_table(table, out / f"{stem}.csv", {**header, "slice": piece.words()})
            verdicts = {f: [str(v) for v in table[f]] for f in FINDINGS}
            verdicts["all five"] = ["yes" if v else "no" for v in table["all_five"]]
            figure = plot_verdict_maps(
                list(piece.x_values),
                list(piece.y_values),
                verdicts,
                PARAMETER_WORDS[piece.x],
                PARAMETER_WORDS[piece.y],
                f"Atlas ({grid.name} grid), {piece.words()}: each finding's verdict",
            )
            saved = save_figure_formats(figure, out, stem)
            figures += saved
            slices.append(
                {
                    "name": piece.name,
                    "words": piece.words(),
                    "x": piece.x,
                    "x_values": list(piece.x_values),
                    "y": piece.y,
                    "y_values": list(piece.y_values),
                    "fixed": dict(piece.fixed),
                    "designs": rows,
                    "table": f"{stem}.csv",
                    "figures": saved,
                }
            )
        return {
            "target": "atlas",
            "key": "atlas",
            "body": "atlas family",
            "study": study.describe(),
            "t_end": study.fig2_t_end,
            "grid": grid.name,
            "findings": list(FINDINGS),
            "designs": [_design_numbers(dataset, k) for k in range(len(designs))],
            "slices": slices,
            "store": "atlas.zarr",
            "searches": stored_searches(),
            "figures": figures,
            "table": slices[0]["table"] if slices else "",
        }


def _design_numbers(dataset: xr.Dataset, k: int) -> dict[str, Any]:
    """One design of the store: its parameters, name and every finding's verdict."""
    row = dataset.isel(design=k)
    return {
        "parameters": {name: float(row[name]) for name in _PARAMETERS},
        "verdicts": {f: str(row[f].values) for f in FINDINGS},
        "ours": {f: str(row[f"{f}_ours"].values) for f in FINDINGS},
    }


def atlas_grid(name: str | AtlasGrid) -> AtlasGrid:
    """The grid named ``name`` in :data:`ATLAS_GRIDS` (a grid is returned as it is)."""
    if isinstance(name, AtlasGrid):
        return name
    if name not in ATLAS_GRIDS:
        raise ParameterError("atlas_grid", name, "one of: " + ", ".join(ATLAS_GRIDS))
    return ATLAS_GRIDS[name]
