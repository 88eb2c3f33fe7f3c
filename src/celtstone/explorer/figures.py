"""The explorer's figures: the stone at the time cursor, spin, energy and tilt (Bokeh).

Bokeh's plotting interface takes a noticeable part of a second to import, so a served
page imports this module once it is shown, after its controls.
"""

from __future__ import annotations

from typing import Any

from bokeh.models import ColumnDataSource
from bokeh.plotting import figure

__all__ = ["run_figures"]


def run_figures(
    sources: dict[str, ColumnDataSource],
    reversal_source: ColumnDataSource,
    stone_source: ColumnDataSource,
    track_source: ColumnDataSource,
) -> tuple[Any, Any, Any, Any]:
    """The four figures, drawing the given data sources.

    Parameters
    ----------
    sources : dict of str to ColumnDataSource
        Columns ``time`` [s] and ``value`` of the curves: ``spin`` and ``pinned_spin``
        [rad/s], ``energy``, ``work`` and ``total`` [J], ``tilt`` and ``pinned_tilt``
        [deg].
    reversal_source : ColumnDataSource
        The reversals' marks: ``time`` [s], ``low`` and ``high`` [rad/s].
    stone_source, track_source : ColumnDataSource
        The stone's projected triangles (``xs``, ``ys``, ``color``) and its contact
        track (``x``, ``y``), as :class:`~celtstone.explorer.stone.StoneView` gives them.

    Returns
    -------
    tuple
        The figures of the stone, the spin, the energy and the tilt.
    """
    options: dict[str, Any] = {
        "height": 230,
        "sizing_mode": "stretch_width",
        "x_axis_label": "time [s]",
        "tools": "pan,wheel_zoom,box_zoom,reset,save",
    }
    spin = figure(y_axis_label="spin ω·n [rad/s]", **options)
    energy = figure(y_axis_label="energy [J]", **options)
    tilt = figure(y_axis_label="tilt of axis 3 [deg]", **options)
    this_run = {"line_width": 2, "legend_label": "this run"}
    pinned_run = {"color": "gray", "line_dash": "dashed", "legend_label": "pinned run"}
    curves = (  # figure, source (the curve's name), style
        (spin, "spin", this_run),
        (spin, "pinned_spin", {**pinned_run, "line_width": 2}),
        (energy, "energy", {"line_width": 2, "legend_label": "energy E"}),
        (energy, "work", {"line_width": 2, "color": "orange", "legend_label": "friction work W"}),
        (energy, "total", {"color": "green", "line_dash": "dashed", "legend_label": "E + W"}),
        (tilt, "tilt", this_run),
        (tilt, "pinned_tilt", pinned_run),
    )
    for plot, key, style in curves:
        plot.line("time", "value", source=sources[key], name=key, **style)
    spin.segment(
        "time",
        "low",
        "time",
        "high",
        source=reversal_source,
        color="crimson",
        line_dash="dotted",
        line_width=2,
        legend_label="reversal",
    )
    for plot in (spin, energy, tilt):
        plot.legend.location = "top_right"
        plot.legend.click_policy = "hide"
    stone = figure(
        height=300,
        sizing_mode="stretch_width",
        match_aspect=True,
        tools="pan,wheel_zoom,reset",
        title="the stone at the time cursor (its contact track on the plane)",
    )
    stone.axis.visible = False
    stone.grid.visible = False
    stone.line("x", "y", source=track_source, color="gray", line_width=1)
    stone.patches("xs", "ys", source=stone_source, fill_color="color", line_color="color")
    return stone, spin, energy, tilt
