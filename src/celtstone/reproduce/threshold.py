"""The friction threshold: where the Celt reversal appears or disappears as f varies.

Runs the study's f grid, then brackets every change between "reverses" and
"does not reverse" on the grid by bisection down to ``bisection_tolerance``.
A reversal is a change of the sense of spin held beyond the study's hysteresis
band (``analysis.reversal_times``) within ``threshold_t_end``.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path
from typing import Any

import numpy as np

from celtstone.bodies import Body
from celtstone.files.export import write_json, write_table
from celtstone.plotting import plot_threshold, save_figure_formats
from celtstone.reproduce.cases import (
    provenance,
    quiet_friction_bound,
    simulate_case,
    study_identity,
    summarise,
)
from celtstone.reproduce.parallel import map_in_threads
from celtstone.reproduce.progress import Progress
from celtstone.reproduce.study import Study

__all__ = ["bisection_steps", "boundary", "threshold", "threshold_numbers"]

# the table's columns: the grid or bisection point, then outcomes and settings of its run
# by their names (``simulation.outcome``)
_POINT_COLUMNS = ("source", "reverses")
_COLUMNS = (
    "friction_coefficient",
    *_POINT_COLUMNS,
    "first_reversal_time",
    "reversal_count",
    "peak_reversed_spin",
    "energy_final",
    "energy_rest",
    "dissipated_work",
    "max_energy_balance_error",
    "status",
)
_LOAD_WORDS = {"static": "static (N = m g)", "dynamic": "dynamic (the consistent N)"}
_LOAD_TITLES = {"static": "N = m g", "dynamic": "dynamic N"}


def bisection_steps(width: float, tolerance: float) -> int:
    """Halvings that shrink a bracket of ``width`` to at most ``tolerance``."""
    return max(0, math.ceil(math.log2(width / tolerance))) if width > tolerance else 0


def _point(study: Study, body: Body, friction: float, source: str) -> dict[str, Any]:
    """One threshold run at ``friction`` [1] and its row (inside ``quiet_friction_bound``)."""
    trajectory = simulate_case(study, body, study.sliding(friction), study.threshold_t_end)
    case = summarise(trajectory, body, study.band)
    first = case["first_reversal_time"]
    point = {
        "friction_coefficient": float(friction),
        "source": source,
        "reverses": first is not None,
    }
    row = {name: point[name] if name in point else case[name] for name in _COLUMNS}
    # a table's missing number is NaN (the JSON's null)
    return {name: math.nan if value is None else value for name, value in row.items()}


def _bisect(
    study: Study, body: Body, low: dict[str, Any], high: dict[str, Any]
) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    """Shrink [low, high] (opposite outcomes) to the tolerance: the boundary and the rows
    of its runs."""
    start = (low["friction_coefficient"], high["friction_coefficient"])
    rows = []
    while high["friction_coefficient"] - low["friction_coefficient"] > study.bisection_tolerance:
        middle = _point(
            study,
            body,
            0.5 * (low["friction_coefficient"] + high["friction_coefficient"]),
            "bisection",
        )
        rows.append(middle)
        if middle["reverses"] == low["reverses"]:
            low = middle
        else:
            high = middle
    return boundary(start, low, high), rows


def boundary(
    grid_bracket: tuple[float, float], low: dict[str, Any], high: dict[str, Any]
) -> dict[str, Any]:
    """A change between reversing and not reversing, bisected from the grid's
    ``grid_bracket`` to the points ``low`` and ``high`` (each with
    ``friction_coefficient`` [1] and ``reverses``): its kind ("appears" where the
    higher f reverses), both brackets and the estimate, the bracket's middle."""
    f_low, f_high = low["friction_coefficient"], high["friction_coefficient"]
    return {
        "kind": "appears" if high["reverses"] else "disappears",
        "grid_bracket": list(grid_bracket),
        "bracket": [f_low, f_high],
        "estimate": 0.5 * (f_low + f_high),
    }


def threshold_numbers(
    grid: np.ndarray, grid_reverses: list[bool], boundaries: list[dict[str, Any]]
) -> dict[str, Any]:
    """The numbers :func:`~celtstone.reproduce.findings.judge_threshold` reads: the f grid
    [1], whether each grid point reverses, the bisected ``boundaries`` (:func:`boundary`),
    the lowest reversing f (the upper end of the lowest "appears" bracket, None if none)
    and whether any f reverses (a bisection point reverses only between grid points of
    which one does)."""
    appears = [b for b in boundaries if b["kind"] == "appears"]
    return {
        "grid": [float(f) for f in grid],
        "grid_reverses": [bool(r) for r in grid_reverses],
        "boundaries": boundaries,
        "lowest_reversing_f": min(appears, key=lambda b: b["estimate"])["bracket"][1]
        if appears
        else None,
        "reverses_anywhere": any(grid_reverses),
    }


def threshold(study: Study, out: Path, progress: Progress) -> dict[str, Any]:
    """Find the friction threshold of reversal: run the f grid and the bisections.

    Parameters
    ----------
    study : Study
        The study.
    out : pathlib.Path
        The target's staging directory; its CSV, figure and numbers are written there.
    progress : Progress
        Reports each run.

    Returns
    -------
    dict
        The numbers the findings are judged by (``data/threshold_KEY.json``).
    """
    import pandas as pd

    body = study.load_body()
    stem = f"threshold_{study.key}"
    data = out / "data"
    data.mkdir(parents=True, exist_ok=True)
    rows: list[dict[str, Any]] = []
    progress.set_description(f"{stem}: f grid")
    # the grid's runs, then the bisections of its brackets, side by side on the cores
    with quiet_friction_bound():
        for row in map_in_threads(
            lambda friction: _point(study, body, friction, "grid"), study.friction_grid()
        ):
            rows.append(row)
            progress.update(1)
        grid_rows = list(rows)
        pairs = [(a, b) for a, b in itertools.pairwise(grid_rows) if a["reverses"] != b["reverses"]]
        if progress.total is not None:
            widths = [b["friction_coefficient"] - a["friction_coefficient"] for a, b in pairs]
            progress.total += sum(bisection_steps(w, study.bisection_tolerance) for w in widths)
            progress.refresh()
        progress.set_description(f"{stem}: bisection")
        boundaries = []
        for found, bisection_rows in map_in_threads(
            lambda pair: _bisect(study, body, *pair), pairs
        ):
            boundaries.append(found)
            rows.extend(bisection_rows)
            progress.update(len(bisection_rows))
    table = pd.DataFrame(rows, columns=list(_COLUMNS)).sort_values("friction_coefficient")
    header = provenance(
        study,
        body,
        target="threshold",
        t_end_s=study.threshold_t_end,
        friction_load=_LOAD_WORDS[study.friction_load],
        bisection_tolerance=study.bisection_tolerance,
    )
    write_table(table, out / f"{stem}.csv", header)
    title = (
        f"Threshold, {study.key}: sliding, {study.contact_words()}, "
        f"{_LOAD_TITLES[study.friction_load]}, runs of {study.threshold_t_end:g} s"
    )
    figure = plot_threshold(table, title, [b["estimate"] for b in boundaries])
    figures = save_figure_formats(figure, out, stem)
    result = {
        "target": "threshold",
        "study": study.describe(),
        "body": body.name,
        **study_identity(study),
        "t_end": study.threshold_t_end,
        "band": study.band,
        **threshold_numbers(
            study.friction_grid(), [bool(r["reverses"]) for r in grid_rows], boundaries
        ),
        "reversal_time_by_f": [
            [
                r["friction_coefficient"],
                None if np.isnan(r["first_reversal_time"]) else r["first_reversal_time"],
            ]
            for r in grid_rows
        ],
        "energy_final_by_f": [
            [r["friction_coefficient"], None if np.isnan(r["energy_final"]) else r["energy_final"]]
            for r in grid_rows
        ],
        "figures": figures,
        "table": f"{stem}.csv",
    }
    write_json(result, data / f"{stem}.json")
    return result
