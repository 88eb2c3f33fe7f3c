"""Every figure the package makes, drawn from small runs: the registry the figure tests
parametrise over.

Each public function of ``celtstone.plotting`` that returns a Figure has at least one
case here (``test_figure_quality.test_every_figure_function_is_registered`` fails
otherwise), drawn with the longest title it is given in practice. The animation's
frames are checked in ``test_figure_extents``.
"""

from __future__ import annotations

import functools
import importlib
import inspect
import pkgutil
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr
from matplotlib.figure import Figure

import celtstone as cs
import celtstone.plotting
from celtstone.atlas.target import FINE_ATLAS
from celtstone.plotting import (
    plot_energy_budget,
    plot_run,
    plot_spin_comparison,
    plot_threshold,
    plot_verdict_maps,
)
from celtstone.plotting.fit import FitPanel, FittedValue, plot_fit
from celtstone.plotting.friction import friction_law_figure
from celtstone.plotting.maps import plot_field_map
from celtstone.plotting.stability import growth_rate_figure
from celtstone.sweep import Sweep
from celtstone.sweep.plots import MAPPED_FIELDS

LONG_KEY = "kane_levinson_1982+realistic"  # the longest study key of the reproduction
LONG_CONTACT = "Hertz ellipse, E = 3e+09 Pa, ν = 0.35, exact law, λ = 1e-05 m, stick–slip"


@dataclass(frozen=True)
class FigureCase:
    """One figure: the package function that makes it and how it is called here."""

    maker: Callable[..., Figure]
    name: str
    build: Callable[[], Figure]


def figure_functions() -> set[Callable[..., Any]]:
    """The public functions of ``celtstone.plotting``'s modules that make a Figure."""
    found = set()
    for info in pkgutil.iter_modules(celtstone.plotting.__path__):
        module = importlib.import_module(f"celtstone.plotting.{info.name}")
        for name, function in inspect.getmembers(module, inspect.isfunction):
            if name.startswith("_") or function.__module__ != module.__name__:
                continue
            signature = inspect.signature(function)
            takes_a_figure = any(
                p.annotation in ("Figure", Figure) for p in signature.parameters.values()
            )  # it finishes a figure (make_legible), it does not make one
            if signature.return_annotation in ("Figure", Figure) and not takes_a_figure:
                found.add(function)
    return found


@functools.cache
def runs() -> tuple[xr.Dataset, xr.Dataset]:
    """A rolling and a sliding run of the K&L stone (3 s), spun the way that reverses."""
    body = cs.load_body("kane_levinson_1982")
    state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
    sliding = cs.SlidingModel(friction_coefficient=0.35, contact_radius=1e-3)
    return (
        cs.simulate(cs.RollingModel(), body, state, 3.0).dataset,
        cs.simulate(sliding, body, state, 3.0, rtol=1e-8, atol=1e-10).dataset,
    )


@functools.cache
def grid_sweep() -> xr.Dataset:
    """3 × 3 sliding runs of 2 s over friction and initial spin: some reverse, some not."""
    axes = {"friction_coefficient": [0.05, 0.23, 0.5], "initial_spin": [-6.0, -1.2, 4.0]}
    return Sweep(axes, model="sliding", t_end=2.0).run()


@functools.cache
def line_sweep() -> xr.Dataset:
    """One axis: the initial spin, rolling for 1 s."""
    return Sweep({"initial_spin": [-5.0, 5.0]}, model="rolling", t_end=1.0).run()


@functools.cache
def cube_sweep() -> xr.Dataset:
    """Three axes: the map is over the first two at the first value of the third."""
    axes = {"initial_spin": [-5.0, 5.0], "damping": [0.0, 1e-5], "euler_alpha": [0.5, 1.0]}
    return Sweep(axes, model="rolling", t_end=0.3).run()


@functools.cache
def point_sweep() -> xr.Dataset:
    """A list of points over two parameters."""
    points = {"initial_spin": [-5.0, 5.0, -3.0], "euler_alpha": [0.5, 1.0, 2.0]}
    return Sweep(points=points, model="rolling", t_end=1.0).run()


def _threshold() -> Figure:
    table = pd.DataFrame(
        {
            "friction_coefficient": [0.1, 0.2, 0.3],
            "first_reversal_time": [np.nan, 3.0, 2.0],
            "energy_final": [0.099, 0.0985, 0.098],
            "energy_rest": [0.0981] * 3,
        }
    )
    title = f"Threshold, {LONG_KEY}: sliding, {LONG_CONTACT}, N = m g, runs of 20 s"
    return plot_threshold(table, title, [0.15])


def _fit() -> Figure:
    sliding = runs()[1]
    spin = sliding["spin"].values
    noise = 0.05 * np.random.default_rng(1).standard_normal(spin.size)
    values = [
        FittedValue("friction_coefficient", 0.35123, 0.0021),
        FittedValue("contact_radius", 0.00101, 2.1e-5, "m"),
        FittedValue("rolling_resistance", 1.2e-6, 3e-7, "m"),
        FittedValue("damping", 1e-7, float("inf"), "N m s"),
        FittedValue("omega3", -5.012, 0.004, "rad/s"),
    ]
    panel = FitPanel("spin ω·n [rad/s]", spin + noise, spin)
    title = f"celtstone fit of {LONG_KEY}, sliding model, 3 starts"
    return plot_fit(sliding["time"].values, [panel], title, values)


def _atlas() -> Figure:
    long_slice = max(FINE_ATLAS.slices, key=lambda s: len(s.words()))
    cells = len(long_slice.x_values) * len(long_slice.y_values)
    verdicts = (["yes", "partly", "no"] * cells)[:cells]
    findings = ("period", "energy_order", "energy_decrease", "threshold", "long_run", "all five")
    return plot_verdict_maps(
        list(long_slice.x_values),
        list(long_slice.y_values),
        {name: verdicts for name in findings},
        "b/a",
        "c/a",
        f"Atlas (fine grid), {long_slice.words()}: each finding's verdict",
    )


def _stability() -> Figure:
    body = cs.load_body("kane_levinson_1982")
    return growth_rate_figure(cs.spin_stability(body, np.linspace(-10.0, 10.0, 41)))


CASES: list[FigureCase] = [
    FigureCase(plot_run, "run-rolling", lambda: plot_run(runs()[0])),
    FigureCase(plot_run, "run-sliding", lambda: plot_run(runs()[1])),
    FigureCase(
        plot_spin_comparison,
        "figure2",
        lambda: plot_spin_comparison(
            [[runs()[0]], [runs()[1], runs()[1]]],
            f"Figure 2 analogue, {LONG_KEY}: spin against time ({LONG_CONTACT})",
        ),
    ),
    FigureCase(
        plot_spin_comparison,
        "figure3",
        lambda: plot_spin_comparison(
            [[runs()[0]], [runs()[1]]],
            f"Figure 3 analogue, {LONG_KEY}: long run, rolling and sliding f = 0.35",
            columns=1,
        ),
    ),
    FigureCase(
        plot_energy_budget,
        "energy-budget",
        lambda: plot_energy_budget(
            list(runs()), f"{LONG_KEY}: energy and energy budget, sliding with N = m g"
        ),
    ),
    FigureCase(plot_threshold, "threshold", _threshold),
    FigureCase(plot_fit, "fit", _fit),
    FigureCase(friction_law_figure, "friction-hertz", lambda: friction_law_figure("hertz")),
    FigureCase(friction_law_figure, "friction-uniform", lambda: friction_law_figure("uniform")),
    FigureCase(growth_rate_figure, "stability", _stability),
    FigureCase(plot_verdict_maps, "atlas", _atlas),
    *(
        FigureCase(
            plot_field_map,
            f"map-{name}",
            lambda name=name: plot_field_map(grid_sweep(), name),  # type: ignore[misc]
        )
        for name in MAPPED_FIELDS
    ),
    FigureCase(plot_field_map, "map-line", lambda: plot_field_map(line_sweep(), "spin_final")),
    FigureCase(plot_field_map, "map-points", lambda: plot_field_map(point_sweep(), "energy_lost")),
    FigureCase(plot_field_map, "map-cube", lambda: plot_field_map(cube_sweep(), "spin_final")),
]
"""Every figure the package makes, by name."""
