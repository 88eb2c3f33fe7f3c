"""Every figure the package makes reads at a glance (issue 38, item 6): no offset or
common factor apart from an axis's ticks, no legend over data or over another legend,
no text under 8 pt.

The figures are those of ``tests/figure_registry.py``, which must name every public
figure function of ``celtstone.plotting``; the checks are ``tests/figure_checks.py``,
and each is shown to find the defect it is for.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from matplotlib.figure import Figure
from matplotlib.font_manager import FontProperties
from matplotlib.ticker import MaxNLocator

from celtstone.plotting.fit import FittedValue, fit_title, value_with_error
from celtstone.plotting.legible import make_legible, tick_labels
from tests.figure_checks import defects, legend_overlaps, offset_texts, small_texts
from tests.figure_registry import CASES, FigureCase, figure_functions


def test_every_figure_function_is_registered() -> None:
    """A new figure function is checked as soon as it is written: it must have a case."""
    registered = {case.maker for case in CASES}
    missing = {f.__qualname__ for f in figure_functions() - registered}
    assert missing == set()
    assert len(registered) >= 9


@pytest.mark.parametrize("case", CASES, ids=[case.name for case in CASES])
def test_figure_reads_at_a_glance(case: FigureCase) -> None:
    assert defects(case.build()) == []


# --------------------------------------------------------------------------- the checks fail


def _constant_energy_figure() -> Figure:
    """The rolling run's energy panel as it was: values constant to 1e-12."""
    figure = Figure(figsize=(5.0, 3.0), layout="constrained")
    axes = figure.add_subplot()
    axes.plot(np.arange(5.0), 0.1238853136 + 1e-12 * np.array([3.0, 5.0, 4.0, 7.0, 2.0]))
    return figure


def _legend_over_a_line() -> Figure:
    """A legend in the middle of an axes crossed by a two-point line: the line has no
    vertex under the legend, only a segment."""
    figure = Figure(figsize=(5.0, 3.0), layout="constrained")
    axes = figure.add_subplot()
    axes.plot([0.0, 1.0], [0.5, 0.5], label="level")
    axes.plot([0.0, 1.0], [0.0, 1.0], label="rise")
    axes.legend(loc="center")
    return figure


def test_the_checks_find_an_offset() -> None:
    found = offset_texts(_constant_energy_figure())
    assert len(found) == 1 and "e" in found[0]


def test_the_checks_find_a_legend_over_a_segment() -> None:
    found = legend_overlaps(_legend_over_a_line())
    assert any("level" in f for f in found) and any("rise" in f for f in found)


def test_the_checks_find_a_legend_over_markers_and_over_a_legend() -> None:
    figure = Figure(figsize=(5.0, 3.0), layout="constrained")
    axes = figure.add_subplot()
    axes.plot([0.5], [0.5], "o", label="point")
    axes.set_xlim(0.0, 1.0)
    axes.set_ylim(0.0, 1.0)
    axes.legend(loc="center")
    figure.legend(["again"], loc="center")
    found = legend_overlaps(figure)
    assert any("over Line2D" in f for f in found)
    assert any("overlap" in f for f in found)


def test_the_checks_find_small_text() -> None:
    figure = Figure(figsize=(4.0, 3.0))
    axes = figure.add_subplot()
    axes.set_title("legend-sized", fontsize=7.0)
    axes.legend(handles=axes.plot([0, 1], label="x-small"), fontsize="x-small")
    x_small = FontProperties(size="x-small").get_size_in_points()  # matplotlib's own scale
    assert sorted(small_texts(figure)) == sorted(
        ["'legend-sized' at 7 pt", f"'x-small' at {x_small:.3g} pt"]
    )


def test_make_legible_mends_an_offset_and_a_covering_legend() -> None:
    assert offset_texts(make_legible(_constant_energy_figure())) == []
    assert legend_overlaps(make_legible(_legend_over_a_line())) == []


def test_a_legend_with_no_free_corner_goes_outside() -> None:
    figure = Figure(figsize=(5.0, 3.0), layout="constrained")
    axes = figure.add_subplot()
    x = np.linspace(0.0, 1.0, 50)
    for y in np.linspace(0.0, 1.0, 12):  # a grid of lines through every corner
        axes.plot(x, np.full_like(x, y), color="0.5")
    axes.plot(x, x, label="data")
    axes.legend()
    make_legible(figure)
    legend_box = axes.get_legend().get_window_extent()
    assert not legend_box.overlaps(axes.get_window_extent())
    assert legend_overlaps(figure) == []


# --------------------------------------------------------------------------- tick labels


def _read(label: str) -> float:
    """A label of ``tick_labels`` read back as a number."""
    text = label.replace("\N{MINUS SIGN}", "-")
    superscripts = str.maketrans("⁻⁰¹²³⁴⁵⁶⁷⁸⁹", "-0123456789")
    match = re.fullmatch(r"(-?[0-9.]+)(?:×10([⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+))?", text)
    assert match is not None, label
    power = int(match.group(2).translate(superscripts)) if match.group(2) else 0
    return float(match.group(1)) * 10.0**power


@given(
    centre=st.floats(-1e9, 1e9),
    width=st.floats(1e-12, 1e9),
)
def test_tick_labels_read_back_as_their_ticks(centre: float, width: float) -> None:
    """Every label, read back, is its tick's value to half a tick step, and no two
    ticks read the same: the label alone says the value, no offset is needed."""
    low, high = centre - width / 2, centre + width / 2
    if not (high > low and (high - low) > 1e-9 * max(abs(low), abs(high))):
        return  # ticks closer than floating point can tell apart
    ticks = MaxNLocator().tick_values(low, high)
    labels = tick_labels(list(ticks))
    read = np.array([_read(label) for label in labels])
    step = float(np.min(np.diff(ticks)))
    np.testing.assert_allclose(read, ticks, rtol=0.0, atol=0.5 * step)
    assert len(set(labels)) == len(labels)


# --------------------------------------------------------------------------- the fit's title


@pytest.mark.parametrize(
    ("value", "error"),
    [(0.35123, 0.0021), (0.00101, 2.1e-5), (1.234e-6, 3.1e-7), (-4.9, 0.012), (3.2e5, 1.1e4)],
)
def test_value_with_error_keeps_two_digits_of_the_error(value: float, error: float) -> None:
    """The error reads back to two significant digits, the value to the error's
    second digit (the convention of the Particle Data Group's tables, simplified)."""
    text = value_with_error(value, error).replace("(", "").replace(")", "")
    match = re.fullmatch(r"(-?[0-9.]+) ± ([0-9.]+)(?:×10([⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+))?", text)
    assert match is not None, text
    scale = _read("1×10" + match.group(3)) if match.group(3) else 1.0
    read_value, read_error = float(match.group(1)) * scale, float(match.group(2)) * scale
    assert read_error == pytest.approx(error, rel=0.05)
    assert abs(read_value - value) <= 0.05 * error
    assert len(match.group(2).replace(".", "").lstrip("0")) == 2


def test_fit_title_breaks_between_values_only() -> None:
    values = [
        FittedValue(f"parameter_with_a_long_name_{i}", 0.1 * i + 0.012345, 1e-3, "m")
        for i in range(8)
    ]
    title = fit_title("subject of the fit", values, width=6.0)
    lines = title.splitlines()
    assert lines[0] == "subject of the fit"
    assert len(lines) > 2  # wrapped
    written = [item for line in lines[1:] for item in line.split(",   ")]
    assert written == [value.words() for value in values]
    assert "(undetermined)" in FittedValue("d", 1.0, float("inf")).words()
