"""The growth-rate figure of ``celtstone.plotting.stability``: artists, labels, atomic files."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import celtstone as cs
from celtstone.plotting.save import check_figure_target
from celtstone.plotting.stability import growth_rate_figure


@pytest.fixture(scope="module")
def result() -> cs.SpinStability:
    return cs.spin_stability(cs.load_body("kane_levinson_1982"), np.linspace(-10.0, 10.0, 41))


def test_figure_has_both_modes_labelled(result: cs.SpinStability) -> None:
    figure = growth_rate_figure(result)
    (axes,) = figure.axes
    lines = {line.get_label(): line for line in axes.get_lines()}
    assert np.array_equal(lines["pitch mode"].get_xdata(), result.spin)
    assert np.array_equal(lines["pitch mode"].get_ydata(), result.growth_rate_pitch)
    assert np.array_equal(lines["roll mode"].get_ydata(), result.growth_rate_roll)
    legend = axes.get_legend()
    assert [text.get_text() for text in legend.get_texts()] == ["pitch mode", "roll mode"]
    assert "[rad/s]" in axes.get_xlabel() and "spin" in axes.get_xlabel()
    assert "[1/s]" in axes.get_ylabel() and "growth rate" in axes.get_ylabel()
    assert "kane_levinson_1982" in axes.get_title()


def test_unknown_format_is_refused(tmp_path: Path) -> None:
    assert check_figure_target(tmp_path / "growth.SVG", "plot").name == "growth.SVG"
    with pytest.raises(cs.ParameterError, match=r"plot.*\.png or \.svg"):
        check_figure_target(tmp_path / "growth.jpg", "plot")
    with pytest.raises(cs.ParameterError, match="existing directory"):
        check_figure_target(tmp_path / "missing" / "growth.png", "plot")
