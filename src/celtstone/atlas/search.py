"""A search of the family for the long-run finding (issue 15: the one that binds).

The coarse and fine atlases found no design where all five findings hold, and the
long-run finding (the paper's Figure 3) "yes" on none: it alone excludes all five
(docs/decisions.md §32). It is also the cheapest to compute (two 50 s runs a design), so
this module scans it alone, widely, over the axes those grids held fixed:

* a Latin hypercube (``scipy.stats.qmc.LatinHypercube``, a seed) over the five shape and
  mass axes of :data:`SEARCH_AXES` and the contact (:data:`SEARCH_CONTACTS`, its sixth
  coordinate cut into three equal strata): L and κ log-uniform, b/a uniform, c/a uniform
  between its lower end and the smaller of its upper end and 98 % of the rest-stability
  bound of that b/a and κ, δ uniform between 0.5° and the largest δ the masses make
  (:func:`~celtstone.atlas.family.largest_misalignment`, at most 10°);
* each point's long run as the atlas computes it (``fields._long_runs``: rolling and
  sliding at f = 0.35 for 50 s, summarised as ``celtstone reproduce`` does), in the study
  of its contact, judged by the report's judge (``reproduce.findings.JUDGES``);
* for each point the reversal counts, the intervals after the second reversal that the
  judge compares, the verdict and the judge's words (:func:`search_dataset`).

``benchmarks/atlas_search.py`` runs it with its seed and stores the table, the Zarr store
and the summary (:func:`search_summary`) that the report's section 7 states.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import statistics
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from celtstone.atlas.family import (
    LENGTH_RANGE,
    MISALIGNMENT_RANGE,
    MaterialPair,
    StoneDesign,
    highest_height_ratio,
    largest_misalignment,
)
from celtstone.atlas.fields import (
    ATLAS_STUDY,
    _long_runs,
    atlas_device,
    hertz_study,
    outcome_units,
)
from celtstone.errors import ParameterError
from celtstone.reproduce import JUDGES, Study

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

__all__ = [
    "ATLAS_STONE_DESIGN",
    "REFINED_AXES",
    "SEARCH_AXES",
    "SEARCH_BOXES",
    "SEARCH_CONTACTS",
    "SEARCH_FORMAT",
    "STONE_AXES",
    "SearchPoint",
    "closest_points",
    "contact_study",
    "rank_points",
    "search_dataset",
    "search_long_runs",
    "search_points",
    "search_summary",
    "search_table",
    "stored_search",
    "stored_searches",
]


SEARCH_FORMAT = "celtstone-atlas-search-1"  # the ``format`` attribute of a search store

SEARCH_AXES: dict[str, tuple[float, float, str]] = {
    # name: (low, high, scale) of the hypercube (issue 15, the brief of the search)
    "length": (*LENGTH_RANGE, "log"),  # L [m]
    "width_ratio": (0.1, 0.6, "linear"),  # b/a [1]
    "height_ratio": (0.08, 0.3, "linear"),  # c/a [1], below the rest-stability bound
    "mass_fraction": (0.1, 1.0, "log"),  # κ [1]
    "misalignment": (0.5, MISALIGNMENT_RANGE[1], "linear"),  # δ [deg], at most the largest
}
"""The hypercube's axes: a :class:`StoneDesign` field -> (low, high, "log" or "linear")."""

REFINED_AXES: dict[str, tuple[float, float, str]] = {
    # the box around the designs of the wide search (seed 15) where the threshold, the
    # energy order and the energy decrease hold and the sliding run reverses at least
    # twice: L 0.19–0.25 m, b/a 0.49–0.57, c/a 0.16–0.17, δ 1.2–1.7°, κ 0.17–0.34
    # (docs/decisions.md §32), widened by about a third on each side
    "length": (0.15, 0.3, "log"),
    "width_ratio": (0.45, 0.6, "linear"),
    "height_ratio": (0.13, 0.2, "linear"),
    "mass_fraction": (0.12, 0.4, "log"),
    "misalignment": (0.8, 2.0, "linear"),
}
"""A second, narrower box: where the wide search came closest to all five."""

ATLAS_STONE_DESIGN = {
    # the design of the refined search (seed 16) where all five hold, shipped as
    # atlas_stone_25cm (docs/bodies.md)
    "length": 0.2461,
    "width_ratio": 0.5074,
    "height_ratio": 0.1331,
    "mass_fraction": 0.1222,
    "misalignment": 1.336,
}
NEIGHBOURHOOD = 0.05  # the stone box: each parameter within ±5 % of the stone's

STONE_AXES: dict[str, tuple[float, float, str]] = {
    name: (
        float(f"{value * (1 - NEIGHBOURHOOD):.4g}"),
        float(f"{value * (1 + NEIGHBOURHOOD):.4g}"),
        "linear",
    )
    for name, value in ATLAS_STONE_DESIGN.items()
}
"""The neighbourhood of the stone where all five hold: how far the region reaches."""

SEARCH_BOXES = {"wide": SEARCH_AXES, "refined": REFINED_AXES, "stone": STONE_AXES}
"""The search's boxes by name (``benchmarks/atlas_search.py --box``)."""

STORED_SEARCHES = {
    box: Path(__file__).with_name("data") / f"long_run_search_{box}.json" for box in SEARCH_BOXES
}
"""The summaries of the searches of record (``benchmarks/atlas_search.py --store``),
which the report's section 7 states."""

STABILITY_MARGIN = 0.98  # c/a at most 98 % of the bound of a stone that rests upright

SEARCH_CONTACTS: dict[str, MaterialPair | None] = {
    "eps_1mm": None,  # the paper's disk of ε = 1 mm
    "hertz_pmma_glass": MaterialPair("pmma", "glass"),
    "hertz_pmma_pmma": MaterialPair("pmma", "pmma"),
}
"""The contact axis: the paper's ε, or ε the Hertz radius of a material pair."""

_LONG_CASES = ("rolling", "sliding")


@dataclass(frozen=True)
class SearchPoint:
    """One point of the search: a design and the name of its contact (:data:`SEARCH_CONTACTS`)."""

    design: StoneDesign
    contact: str

    def __post_init__(self) -> None:
        if self.contact not in SEARCH_CONTACTS:
            raise ParameterError("contact", self.contact, "one of: " + ", ".join(SEARCH_CONTACTS))


def contact_study(contact: str, study: Study = ATLAS_STUDY) -> Study:
    """``study`` with the contact named ``contact`` (:data:`SEARCH_CONTACTS`)."""
    if contact not in SEARCH_CONTACTS:
        raise ParameterError("contact", contact, "one of: " + ", ".join(SEARCH_CONTACTS))
    pair = SEARCH_CONTACTS[contact]
    return study if pair is None else hertz_study(study, pair)


def _scaled(unit: float, low: float, high: float, scale: str) -> float:
    if scale == "log":
        return float(math.exp(math.log(low) + unit * (math.log(high) - math.log(low))))
    return float(low + unit * (high - low))


def _point(unit: Sequence[float], axes: Mapping[str, tuple[float, float, str]]) -> SearchPoint:
    """The search point of one row of the unit hypercube (module docstring)."""
    values = {
        name: _scaled(u, low, high, scale)
        for u, (name, (low, high, scale)) in zip(unit, axes.items(), strict=False)
    }
    low, high, _ = axes["height_ratio"]
    top = min(
        high,
        STABILITY_MARGIN * highest_height_ratio(values["width_ratio"], values["mass_fraction"]),
    )
    values["height_ratio"] = _scaled(unit[2], low, top, "linear")
    low, high, _ = axes["misalignment"]
    largest = min(high, largest_misalignment(values["width_ratio"], values["mass_fraction"]))
    values["misalignment"] = _scaled(unit[4], min(low, largest), largest, "linear")
    contacts = list(SEARCH_CONTACTS)
    contact = contacts[min(int(unit[5] * len(contacts)), len(contacts) - 1)]
    rounded = {k: float(f"{v:.4g}") for k, v in values.items()}  # names and tables read well
    # rounding δ up could leave the rim: the largest δ, rounded down, stays on it
    if rounded["misalignment"] > largest:
        rounded["misalignment"] = math.floor(largest * 1e3) / 1e3
    return SearchPoint(StoneDesign(**rounded), contact)


def search_points(count: int, seed: int, box: str = "wide") -> list[SearchPoint]:
    """``count`` points of a Latin hypercube over the axes of ``box`` (:data:`SEARCH_BOXES`)
    × the contact, drawn with ``seed`` (the same count, seed and box give the same points)."""
    from scipy.stats import qmc

    if int(count) < 1:
        raise ParameterError("count", count, "an integer >= 1")
    if box not in SEARCH_BOXES:
        raise ParameterError("box", box, "one of: " + ", ".join(SEARCH_BOXES))
    axes = SEARCH_BOXES[box]
    unit = qmc.LatinHypercube(d=len(axes) + 1, seed=seed).random(int(count))
    return [_point(row, axes) for row in unit]


def search_long_runs(
    points: Sequence[SearchPoint],
    study: Study = ATLAS_STUDY,
    out: str | Path | None = None,
    *,
    workers: int | None = 2,
    overwrite: bool = False,
    progress: Callable[[str], None] | None = None,
    device: str = "cpu",
) -> list[dict[str, Any]]:
    """Each point's long-run numbers (the ``fig3`` dict the judge reads), as the atlas
    computes them, in the study of the point's contact: on ``workers`` threads, or with
    ``device`` "cuda" (or "auto" where there is a GPU) on the GPU, each contact's
    rolling runs as one launch and its sliding runs as another (``fields._long_runs``).
    With ``out``, each contact's runs are kept in ``out/CONTACT/long_run/design_NNNNN.json``
    (a search run again finds them there: resumable)."""
    studies = {contact: contact_study(contact, study) for contact in SEARCH_CONTACTS}
    # every contact's device before any run: a missing GPU is refused at once
    devices = {contact: atlas_device(device, studies[contact]) for contact in studies}
    numbers: list[dict[str, Any] | None] = [None] * len(points)
    directory = None if out is None else Path(out)
    for contact in SEARCH_CONTACTS:
        chosen = [k for k, p in enumerate(points) if p.contact == contact]
        if not chosen:
            continue
        if progress is not None:
            progress(f"{contact}: {len(chosen)} designs")
        designs = [points[k].design for k in chosen]
        target = None if directory is None else directory / contact
        if target is not None:
            target.mkdir(parents=True, exist_ok=True)
        runs = _long_runs(
            studies[contact],
            designs,
            [d.body() for d in designs],
            target,
            workers,
            overwrite,
            devices[contact],
        )
        for k, run in zip(chosen, runs, strict=True):
            numbers[k] = run
    return [n for n in numbers if n is not None]


def _after_second(times: Sequence[float]) -> list[float]:
    """The intervals between reversals from the second on [s] (what the judge compares)."""
    return [b - a for a, b in itertools.pairwise(times[1:])]


def search_dataset(
    points: Sequence[SearchPoint],
    numbers: Sequence[Mapping[str, Any]],
    study: Study = ATLAS_STUDY,
    *,
    seed: int | None = None,
    box: str = "wide",
) -> xr.Dataset:
    """The search as a Dataset on dimension ``point``: each design's parameters and
    contact (coordinates), its mass and rocking period, per long run (``long_case``:
    rolling, sliding) the reversal count, spin crossing count, final spin and reversal times,
    the extreme and mean intervals after the second reversal, and the long-run verdict and words
    of the report's judge."""
    import xarray as xr

    from celtstone.simulation.integrate import version

    target, judge = JUDGES["long_run"]
    verdicts = [v for v in (judge(dict(n)) for n in numbers) if v is not None]
    if len(verdicts) != len(numbers):
        raise ValueError("the long-run judge gave no verdict")  # it always gives one
    bodies = [p.design.body() for p in points]
    times = [[c["reversal_times"] for c in n["cases"]] for n in numbers]
    width = max([len(t) for pair in times for t in pair] + [1])
    table = np.full((len(points), len(_LONG_CASES), width), np.nan)
    for k, pair in enumerate(times):
        for j, row in enumerate(pair):
            table[k, j, : len(row)] = row

    def per_case(key: str) -> np.ndarray:
        return np.array([[c[key] for c in n["cases"]] for n in numbers], dtype=float).reshape(
            len(numbers), len(_LONG_CASES)
        )

    def extreme(pick: Callable[[list[float]], float], index: int) -> list[float]:
        values = [_after_second(pair[index]) for pair in times]
        return [pick(v) if v else math.nan for v in values]

    point_dim, case_dim = ("point",), ("point", "long_case")
    data = {
        "mass": (point_dim, [b.mass for b in bodies], {"units": "kg"}),
        "rocking_period": (point_dim, [b.rocking_period for b in bodies], {"units": "s"}),
        "reversals": (
            case_dim,
            np.array([[len(t) for t in pair] for pair in times], dtype=int).reshape(
                len(points), len(_LONG_CASES)
            ),
            {"units": "1", "long_name": "held reversals in the 50 s run (decisions §8)"},
        ),
        "spin_crossing_count": (
            case_dim,
            per_case("spin_crossing_count"),
            outcome_units("spin_crossing_count"),
        ),
        "spin_final": (case_dim, per_case("spin_final"), outcome_units("spin_final")),
        "reversal_times": (
            ("point", "long_case", "reversal"),
            table,
            {"units": "s", "long_name": "reversal times, NaN after the last"},
        ),
        "rolling_shortest_interval": (
            point_dim,
            extreme(min, 0),
            {"units": "s", "long_name": "rolling run: shortest interval after the 2nd reversal"},
        ),
        "sliding_longest_interval": (
            point_dim,
            extreme(max, 1),
            {"units": "s", "long_name": "sliding run: longest interval after the 2nd reversal"},
        ),
        "mean_interval": (
            case_dim,
            np.array(
                [
                    [statistics.fmean(_after_second(t)) if len(t) >= 3 else math.nan for t in pair]
                    for pair in times
                ],
                dtype=float,
            ).reshape(len(points), len(_LONG_CASES)),
            {"units": "s", "long_name": "mean interval after the 2nd reversal"},
        ),
        "long_run": (
            point_dim,
            np.array([v.reproduced for v in verdicts]),
            {"long_name": "the long-run verdict (reproduce.findings.JUDGES)"},
        ),
        "long_run_ours": (point_dim, np.array([v.ours for v in verdicts]), {}),
        "long_run_why": (point_dim, np.array([v.why for v in verdicts]), {}),
    }
    fields = [f.name for f in dataclasses.fields(StoneDesign)]
    coords: dict[str, Any] = {
        name: (point_dim, [float(getattr(p.design, name)) for p in points]) for name in fields
    }
    coords["contact"] = (point_dim, np.array([p.contact for p in points]))
    coords["long_case"] = (("long_case",), list(_LONG_CASES))
    attrs = {
        "format": SEARCH_FORMAT,
        "title": "celtstone atlas: a search of the family for the long-run finding",
        "celtstone_version": version(),
        "study": study.describe(),
        "study_settings": repr(study),
        "judged_by": f"celtstone.reproduce.findings.JUDGES['long_run'] ({target} numbers)",
        "seed": "none" if seed is None else int(seed),
        "box": box,
    }
    return xr.Dataset(
        {k: xr.Variable(*v) for k, v in data.items()},
        coords={k: xr.Variable(*v) for k, v in coords.items()},
        attrs=attrs,
    )


_ORDER = {"yes": 0, "partly": 1, "no": 2}


def _closeness(dataset: xr.Dataset) -> np.ndarray:
    """The rolling run's shortest interval over the sliding run's longest after the second
    reversal (above 1: every sliding interval the shorter); NaN where a run has fewer
    than three reversals."""
    shortest = dataset["rolling_shortest_interval"].values
    return np.asarray(shortest / dataset["sliding_longest_interval"].values, dtype=float)


def rank_points(dataset: xr.Dataset) -> list[int]:
    """The points from the closest to the long-run finding to the farthest: by the
    judge's verdict (yes, partly, no), then by :func:`_closeness`, then by the sliding
    run's reversals, then by the rolling run's shortest interval after the second (a slow
    rolling stone leaves the sliding one room to be the quicker)."""
    verdict = [_ORDER[str(v)] for v in dataset["long_run"].values]
    ratio = _closeness(dataset)
    sliding = dataset["reversals"].sel(long_case="sliding").values
    rolling = dataset["rolling_shortest_interval"].values

    def finite(value: float) -> float:
        return float(value) if math.isfinite(value) else -math.inf

    def key(k: int) -> tuple[float, float, float, float]:
        return (verdict[k], -finite(ratio[k]), -float(sliding[k]), -finite(rolling[k]))

    return sorted(range(dataset.sizes["point"]), key=key)


def closest_points(dataset: xr.Dataset, count: int) -> list[int]:
    """The ``count`` first points of :func:`rank_points`, then the ``count`` closest of
    those whose runs both have three held reversals (judged on the intervals alone, by
    :func:`_closeness`), without repeats: the points whose five findings are worth
    computing."""
    ranked = rank_points(dataset)
    ratio = _closeness(dataset)
    both = [k for k in ranked if math.isfinite(ratio[k])]
    return list(dict.fromkeys(ranked[:count] + both[:count]))


def search_table(dataset: xr.Dataset) -> pd.DataFrame:
    """One row per point: parameters, contact, mass, counts, intervals, verdict."""
    import pandas as pd

    columns = [f.name for f in dataclasses.fields(StoneDesign)] + ["contact", "mass"]
    table: dict[str, Any] = {name: dataset[name].values for name in columns}
    table["rocking_period"] = dataset["rocking_period"].values
    for case in _LONG_CASES:
        table[f"{case}_reversals"] = dataset["reversals"].sel(long_case=case).values
        table[f"{case}_spin_crossing_count"] = (
            dataset["spin_crossing_count"].sel(long_case=case).values
        )
    table["rolling_shortest_interval"] = dataset["rolling_shortest_interval"].values
    table["sliding_longest_interval"] = dataset["sliding_longest_interval"].values
    for case in _LONG_CASES:
        table[f"{case}_mean_interval"] = dataset["mean_interval"].sel(long_case=case).values
    for case in _LONG_CASES:
        table[f"{case}_reversal_times"] = [
            " ".join(f"{t:.4g}" for t in row[np.isfinite(row)])
            for row in dataset["reversal_times"].sel(long_case=case).values
        ]
    table["long_run"] = dataset["long_run"].values
    table["long_run_why"] = dataset["long_run_why"].values
    return pd.DataFrame(table)


def _point_words(dataset: xr.Dataset, k: int) -> dict[str, Any]:
    row = dataset.isel(point=k)
    return {
        "parameters": {f.name: float(row[f.name]) for f in dataclasses.fields(StoneDesign)},
        "contact": str(row["contact"].values),
        "reversals": {c: int(row["reversals"].sel(long_case=c)) for c in _LONG_CASES},
        "rolling_shortest_interval": _finite(row["rolling_shortest_interval"]),
        "sliding_longest_interval": _finite(row["sliding_longest_interval"]),
        "mean_interval": {c: _finite(row["mean_interval"].sel(long_case=c)) for c in _LONG_CASES},
        "long_run": str(row["long_run"].values),
        "ours": str(row["long_run_ours"].values),
    }


def _finite(value: Any) -> float | None:
    number = float(value)
    return number if math.isfinite(number) else None


def search_summary(dataset: xr.Dataset, best: int = 4) -> dict[str, Any]:
    """The search in numbers for the report (JSON-safe): the axes, the points per contact
    and per verdict, the points where each run has at least three reversals, where the
    sliding run has more reversals than the rolling one, where its mean interval after
    the second is the shorter, the most sliding reversals per contact, the largest ratio
    of the rolling run's shortest (and mean) interval to the sliding run's longest (and
    mean) one after the second reversal, and the points of :func:`closest_points`
    (``best`` of each kind) with their counts, intervals and verdict."""
    verdicts = [str(v) for v in dataset["long_run"].values]
    contacts = [str(c) for c in dataset["contact"].values]
    rolling = dataset["reversals"].sel(long_case="rolling").values
    sliding = dataset["reversals"].sel(long_case="sliding").values
    mean = dataset["mean_interval"].values  # NaN where a run has fewer than 3 reversals
    ratio = _closeness(dataset)
    mean_ratio = mean[:, 0] / mean[:, 1]
    return {
        "points": int(dataset.sizes["point"]),
        "seed": dataset.attrs["seed"],
        "box": dataset.attrs["box"],
        "axes": {name: list(axis) for name, axis in SEARCH_BOXES[dataset.attrs["box"]].items()},
        "contacts": {
            name: {
                "points": contacts.count(name),
                **{
                    v: sum(c == name and w == v for c, w in zip(contacts, verdicts, strict=True))
                    for v in _ORDER
                },
            }
            for name in SEARCH_CONTACTS
        },
        "verdicts": {v: verdicts.count(v) for v in _ORDER},
        "rolling_three": int(np.sum(rolling >= 3)),
        "sliding_three": int(np.sum(sliding >= 3)),
        "both_three": int(np.sum((rolling >= 3) & (sliding >= 3))),
        "sliding_more": int(np.sum(sliding > rolling)),
        "sliding_quicker_on_average": int(np.sum(mean[:, 1] < mean[:, 0])),
        "most_sliding": {
            name: int(
                max((s for c, s in zip(contacts, sliding, strict=True) if c == name), default=0)
            )
            for name in SEARCH_CONTACTS
        },
        "largest_interval_ratio": _finite(np.nanmax(ratio)) if np.isfinite(ratio).any() else None,
        "largest_mean_ratio": (
            _finite(np.nanmax(mean_ratio)) if np.isfinite(mean_ratio).any() else None
        ),
        "study": dataset.attrs["study"],
        "best": [_point_words(dataset, k) for k in closest_points(dataset, best)],
    }


def stored_searches() -> list[dict[str, Any]]:
    """The stored summaries of the searches of record (:data:`STORED_SEARCHES`), in the
    order of :data:`SEARCH_BOXES`; those not stored are left out."""
    return [s for s in (stored_search(path) for path in STORED_SEARCHES.values()) if s]


def stored_search(path: str | Path) -> dict[str, Any] | None:
    """The search summary stored at ``path``, or None when none is stored there."""
    import json

    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        return None
    summary: dict[str, Any] = json.loads(text)
    return summary
