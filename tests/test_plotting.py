"""Figures drawn on the Agg backend, checked by their artists (lines, labels, titles)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from matplotlib.lines import Line2D

import celtstone as cs
from celtstone.cli.main import main
from celtstone.files.export import write
from celtstone.plotting import (
    plot_energy_budget,
    plot_run,
    plot_spin_comparison,
    plot_threshold,
    save_figure,
)
from celtstone.simulation.reversals import dataset_reversal_times


@pytest.fixture(scope="module")
def runs(kane_levinson: cs.Body) -> dict[str, cs.Trajectory]:
    state = cs.InitialState(omega=(0.0, 0.0, -5.0))
    return {
        "rolling": cs.simulate(cs.RollingModel(), kane_levinson, state, 4.0),
        "sliding": cs.simulate(
            cs.SlidingModel(friction_coefficient=0.35, contact_radius=1e-3),
            kane_levinson,
            state,
            4.0,
            rtol=1e-8,
            atol=1e-10,
        ),
    }


def _vertical_lines(axes) -> list[Line2D]:
    return [
        line
        for line in axes.get_lines()
        if len(set(np.atleast_1d(line.get_xdata()))) == 1 and len(line.get_xdata()) == 2
    ]


def test_plot_run_panels_labels_and_reversals(runs: dict[str, cs.Trajectory]) -> None:
    dataset = runs["sliding"].dataset
    figure = plot_run(dataset)
    axes = [a for a in figure.axes if a.get_visible()]
    ylabels = [a.get_ylabel() for a in axes]
    for expected in ("[rad/s]", "[deg]", "[J]", "[m/s]", "[N]", "[m]"):
        assert any(expected in label for label in ylabels), expected
    spin_axes = axes[0]
    assert "spin" in spin_axes.get_ylabel()
    reversals = dataset_reversal_times(dataset)
    assert reversals.size == 1
    marks = _vertical_lines(spin_axes)
    assert [float(m.get_xdata()[0]) for m in marks] == pytest.approx(list(reversals))
    assert "kane_levinson_1982" in figure.get_suptitle()
    assert "sliding f = 0.35" in figure.get_suptitle()
    # a legend wherever a panel draws more than one thing, none naming a lone curve
    for panel in axes:
        named = panel.get_legend_handles_labels()[1]
        assert (panel.get_legend() is not None) == (len(named) > 1), panel.get_ylabel()
    # sliding: energy lost and friction work drawn on the energy panel's twin
    labels = {line.get_label() for a in axes for line in a.get_lines()}
    assert {"energy lost", "friction work", "contact point"} <= labels


def test_plot_run_rolling_has_no_budget_axis(runs: dict[str, cs.Trajectory]) -> None:
    figure = plot_run(runs["rolling"].dataset)
    assert len(figure.axes) == 6


def test_a_constant_energy_is_drawn_as_its_relative_drift(
    runs: dict[str, cs.Trajectory],
) -> None:
    """Rolling conserves energy: the panel shows (E − E0)/E0, the integrator's drift,
    instead of E constant to 1e-11 (whose ticks needed an offset); sliding loses a fifth
    of it and keeps E [J]."""
    rolling = runs["rolling"].dataset
    energy = rolling["energy"].values
    assert np.ptp(energy) < 1e-9 * energy[0]  # the premise: rolling conserves it (rtol)
    panel = plot_run(rolling).axes[2]
    assert panel.get_ylabel().startswith("relative energy drift")
    drawn = panel.get_lines()[0].get_ydata()
    np.testing.assert_allclose(drawn, energy / energy[0] - 1.0, rtol=0.0, atol=1e-15)
    sliding = plot_run(runs["sliding"].dataset).axes[2]
    assert sliding.get_ylabel() == "energy $E$ [J]"


def test_spin_comparison_one_line_per_run(runs: dict[str, cs.Trajectory]) -> None:
    datasets = [runs["rolling"].dataset, runs["sliding"].dataset]
    figure = plot_spin_comparison([[datasets[0]], [datasets[1]]], "Figure 2 analogue")
    first, second = figure.axes[:2]
    assert first.get_xlabel() == "time $t$ [s]"
    assert "rolling" in [line.get_label() for line in first.get_lines()]
    assert any(line.get_label().startswith("sliding f = 0.35") for line in second.get_lines())
    assert figure.get_suptitle() == "Figure 2 analogue"
    budget = plot_energy_budget(datasets, "budget")
    assert budget.axes[2].get_yscale() == "log"
    assert len(budget.axes[0].get_lines()) == 2


def test_threshold_plot_marks(tmp_path: Path) -> None:
    table = pd.DataFrame(
        {
            "friction_coefficient": [0.1, 0.2, 0.3],
            "first_reversal_time": [np.nan, 3.0, 2.0],
            "energy_final": [0.099, 0.0985, 0.098],
            "energy_rest": [0.0981] * 3,
        }
    )
    figure = plot_threshold(table, "threshold", boundaries=[0.15])
    time_axes = figure.axes[0]
    reversing = time_axes.get_lines()[0]
    assert list(reversing.get_xdata()) == [0.2, 0.3]
    assert [float(v) for v in time_axes.get_lines()[1].get_xdata()] == [0.1]
    assert any(float(line.get_xdata()[0]) == 0.15 for line in _vertical_lines(time_axes))
    for suffix in (".png", ".svg"):
        path = save_figure(figure, tmp_path / f"t{suffix}")
        assert path.stat().st_size > 1000
    with pytest.raises(cs.ParameterError, match=r"\.png or \.svg"):
        save_figure(figure, tmp_path / "t.pdf")


def test_cli_plot_and_export(runs: dict[str, cs.Trajectory], tmp_path: Path) -> None:
    run_file = write(runs["sliding"].dataset, tmp_path / "run.nc")
    assert main(["plot", str(run_file), "--out", str(tmp_path / "run.svg")]) == 0
    assert (tmp_path / "run.svg").read_text().lstrip().startswith("<?xml")
    assert main(["plot", str(run_file)]) == 0
    assert (tmp_path / "run.png").exists()
    assert main(["export", str(run_file), "--csv"]) == 0
    table = pd.read_csv(tmp_path / "run.csv", comment="#")
    assert table["spin"].to_numpy() == pytest.approx(runs["sliding"].dataset["spin"].values)
    assert main(["export", str(run_file)]) == 2
    assert main(["export", str(run_file), "--csv", "--out", str(tmp_path / "x.txt")]) == 2
    assert main(["plot", str(tmp_path / "missing.nc")]) == 2
    assert main(["plot", str(run_file), "--band", "0"]) == 2


def test_trajectory_in_a_notebook(runs: dict[str, cs.Trajectory]) -> None:
    """``Trajectory`` shows a short HTML table in Jupyter and ``plot()`` returns the run's
    figure (issue 16, item 4)."""
    run = runs["sliding"]
    table = run._repr_html_()
    first = run.first_reversal_time
    assert first is not None
    energy = run.dataset["energy"].values
    for row in (
        "<th style='text-align:left'>body</th><td style='text-align:left'>kane_levinson_1982</td>",
        "sliding, f = 0.35, sliding contact",
        "<td style='text-align:left'>4 s</td>",
        "<td style='text-align:left'>success</td>",
        f"<td style='text-align:left'>{first:.6g} s</td>",
        f"<td style='text-align:left'>{energy[0] - energy[-1]:.6g} J</td>",
    ):
        assert row in table
    rolling = runs["rolling"].first_reversal_time
    words = "none" if rolling is None else f"{rolling:.6g} s"
    assert (
        f"first reversal</th><td style='text-align:left'>{words}<" in runs["rolling"]._repr_html_()
    )
    figure = run.plot()
    assert figure.get_suptitle() == plot_run(run.dataset).get_suptitle()
    assert len(figure.axes) == len(plot_run(run.dataset).axes)
