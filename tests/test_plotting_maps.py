"""Sweep maps a reader decodes at a glance (issue 38, item 6): names and units from the
declarations, a diverging map centred on zero for a signed field, cells without a value
named in the legend, four maps by default and the others on request."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from matplotlib.collections import PolyCollection, QuadMesh

import celtstone as cs
from celtstone.cli.main import main
from celtstone.plotting.maps import plot_field_map
from celtstone.simulation.outcome import OUTCOMES
from celtstone.simulation.schema import VARIABLES
from celtstone.sweep.plots import (
    DEFAULT_MAPPED_FIELDS,
    MAPPED_FIELDS,
    check_map_fields,
    map_paths,
    write_maps,
)
from tests.figure_registry import cube_sweep, grid_sweep, line_sweep


@pytest.fixture(scope="module")
def grid() -> xr.Dataset:
    return grid_sweep()


def _mesh(figure) -> QuadMesh:  # type: ignore[no-untyped-def]
    (mesh,) = [c for c in figure.axes[0].collections if isinstance(c, QuadMesh)]
    return mesh


def _legend_words(figure) -> list[str]:  # type: ignore[no-untyped-def]
    return [text.get_text() for legend in figure.legends for text in legend.get_texts()]


def test_labels_and_title_are_the_declared_words(grid: xr.Dataset) -> None:
    figure = plot_field_map(grid, "first_reversal_time")
    axes, colorbar = figure.axes
    declared = OUTCOMES["first_reversal_time"].variable
    assert axes.get_title().startswith("First reversal time (sliding model")
    assert colorbar.get_ylabel() == declared.axis_label() == "first reversal time [s]"
    assert axes.get_ylabel() == VARIABLES["friction_coefficient"].axis_label()
    # a parameter without a plot label: its stored long name and unit, no code name
    assert axes.get_xlabel() == "initial spin omega0 . n0 [rad/s]"
    assert grid["initial_spin"].attrs["units"] == "rad/s"


def test_a_signed_field_is_centred_on_zero(grid: xr.Dataset) -> None:
    """The final spin takes both signs: white at zero, the colours symmetric."""
    spin = grid["spin_final"].values
    assert spin.min() < 0.0 < spin.max()  # the premise
    mesh = _mesh(plot_field_map(grid, "spin_final"))
    assert mesh.get_cmap().name == "RdBu_r"
    assert mesh.norm(0.0) == pytest.approx(0.5)
    largest = float(np.abs(spin).max())
    assert mesh.norm(largest) + mesh.norm(-largest) == pytest.approx(1.0)
    lost = grid["energy_lost"].values
    assert lost.min() > 0.0  # one sign: a sequential map
    assert _mesh(plot_field_map(grid, "energy_lost")).get_cmap().name == "viridis"


def test_a_count_is_drawn_in_whole_steps(grid: xr.Dataset) -> None:
    figure = plot_field_map(grid, "reversal_count")
    ticks = figure.axes[1].get_yticks()
    assert np.array_equal(ticks, np.round(ticks))
    counts = np.unique(grid["reversal_count"].values)
    mesh = _mesh(figure)
    colours = {tuple(mesh.cmap(mesh.norm(c))) for c in counts}
    assert len(colours) == len(counts)  # each count its own colour


def test_cells_without_a_value_are_hatched_and_named(grid: xr.Dataset) -> None:
    values = grid["first_reversal_time"].values
    missing = int(np.isnan(values).sum())
    assert 0 < missing < values.size  # the premise: some reverse, some do not
    figure = plot_field_map(grid, "first_reversal_time")
    (hatched,) = [c for c in figure.axes[0].collections if isinstance(c, PolyCollection)]
    assert hatched.get_hatch() == "///"
    assert len(hatched.get_paths()) == missing
    assert _legend_words(figure) == [OUTCOMES["first_reversal_time"].variable.missing]


def test_a_run_stopped_early_is_named_apart(grid: xr.Dataset) -> None:
    """A NaN of a run that stopped early is not "no reversal": the legend says so."""
    status = grid["status"].values.copy()
    spin = grid["spin_final"].values.copy()
    status[0, 0], spin[0, 0] = "max_steps", np.nan
    broken = grid.assign(status=(grid["status"].dims, status))
    broken = broken.assign(spin_final=(grid["spin_final"].dims, spin))
    assert _legend_words(plot_field_map(broken, "spin_final")) == ["stopped early (see the status)"]
    assert "no value" not in _legend_words(plot_field_map(broken, "first_reversal_time"))


def test_beyond_two_axes_the_title_says_where() -> None:
    figure = plot_field_map(cube_sweep(), "spin_final")
    title = figure.axes[0].get_title().replace("\n", " ")
    assert title.endswith(" at initial Euler angle alpha = 0.5 deg")
    drawn = figure.axes[0].collections[0].get_array()
    expected = cube_sweep()["spin_final"].isel(euler_alpha=0).values
    np.testing.assert_array_equal(np.asarray(drawn).reshape(expected.shape), expected)


def test_a_line_marks_its_points_without_a_value() -> None:
    line = line_sweep()
    figure = plot_field_map(line, "first_reversal_time")
    missing = np.isnan(line["first_reversal_time"].values)
    marks = figure.axes[0].get_lines()[1]
    assert list(marks.get_xdata()) == list(line["initial_spin"].values[missing])
    assert _legend_words(figure) == ["no reversal in the run"]


def test_four_maps_by_default_the_others_on_request(grid: xr.Dataset, tmp_path: Path) -> None:
    assert DEFAULT_MAPPED_FIELDS == (
        "first_reversal_time",
        "reversal_count",
        "spin_final",
        "energy_lost",
    )
    written = write_maps(grid, tmp_path / "maps")
    assert sorted(p.name for p in written) == sorted(f"{n}.png" for n in DEFAULT_MAPPED_FIELDS)
    assert check_map_fields("all") == MAPPED_FIELDS
    assert check_map_fields("status, spin_final") == ("status", "spin_final")
    assert [p.name for p in map_paths(tmp_path / "other", fields=["max_tilt"])] == ["max_tilt.png"]
    for wrong in ("final_spin", "message", ""):  # final_spin: the name before spin_final
        with pytest.raises(cs.ParameterError, match="map_fields"):
            check_map_fields(wrong)


def test_cli_maps_the_fields_asked_for(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["sweep", "--model", "rolling", "--vary", "initial_spin=-5,5", "--t-end", "0.2"]
    argv += ["--no-progress", "--out", str(tmp_path / "s.zarr")]
    assert main([*argv, "--map-fields", "final_spin"]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and "map_fields" in error and "final_spin" in error
    assert not (tmp_path / "s.zarr").exists()
    assert main([*argv, "--map-fields", "status,max_tilt"]) == 0
    assert sorted(p.name for p in (tmp_path / "s_maps").iterdir()) == ["max_tilt.png", "status.png"]
