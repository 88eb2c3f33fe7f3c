"""The paper's five findings as fields over a family of stones.

For each :class:`~celtstone.atlas.family.StoneDesign` the numbers the report's judges
read (``reproduce.findings.JUDGES``) are computed with the settings of one
:class:`~celtstone.reproduce.study.Study` (start, contact, run lengths, f grid), then
judged by those same judges:

* **Figure 2** (findings ``period``, ``energy_order``, ``energy_decrease``): one sweep per
  model (rolling; sliding with each friction load of the study) over every design × the
  study's f, run by the sweep engine (``celtstone.sweep.Sweep``, a list of points);
* **threshold**: one sweep over every design × the study's f grid, then one sweep per
  bisection round over the midpoints of every open bracket of every design at once, to
  the study's ``bisection_tolerance``;
* **long run** (``long_run``): the judge reads every reversal *time* of two runs (a
  list of any length, which a sweep's one-number-per-point fields do not hold), so the
  two runs per design are direct :func:`~celtstone.simulate` calls summarised by
  ``reproduce.cases.summarise``, exactly as ``celtstone reproduce`` does, on threads;
  on a GPU (``device="cuda"``) the rolling runs of every design are one
  :func:`~celtstone.simulation.integrate.simulate_many` launch and the sliding runs another.

With ``out``, every sweep is a Zarr store in ``out`` (resumable as any sweep), each
long run's numbers a JSON file there, and the result ``out/atlas.zarr``.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import warnings
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from celtstone.atlas.family import MaterialPair, StoneDesign
from celtstone.bodies import Body, Ellipsoid
from celtstone.errors import CeltstoneError, FrictionBoundWarning, ParameterError
from celtstone.files.export import (
    output_error,
    replace_directory,
    temporary_directory,
    write_json,
)
from celtstone.files.ownership import check_replaceable
from celtstone.reproduce import (
    FINDINGS,
    JUDGES,
    Study,
    boundary,
    case_name,
    figure2_models,
    summarise,
    threshold_numbers,
)
from celtstone.simulation.integrate import simulate, simulate_many
from celtstone.simulation.models import Model
from celtstone.simulation.outcome import OUTCOMES, SWEPT, is_energy_monotone, json_number
from celtstone.sweep import Sweep

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "ATLAS_FORMAT",
    "ATLAS_STUDY",
    "COARSE_THRESHOLD_GRID",
    "LONG_RUN_BATCH",
    "atlas_device",
    "atlas_numbers",
    "compute_atlas",
    "judge_design",
]

COARSE_THRESHOLD_GRID = (0.02, 0.5, 13)
"""f grid of the atlas's threshold [1]: steps of 0.04 (the report's 49 points step 0.01),
then three bisection rounds reach Δf = 0.005 as the report's one does; a reversing window
narrower than 0.04 between two grid points can be missed (docs/decisions.md §32)."""

ATLAS_STUDY = Study(
    body="atlas",
    variant="atlas",
    contact="hybrid",
    threshold_grid=COARSE_THRESHOLD_GRID,
)
"""The atlas's runs: the reproduction's start (ω = (0, 0, −5) rad/s, α = β = 0.5°), the
paper's contact (ε = 1 mm, Padé law), Figure 2 runs of 20 s at f = 0.35, 0.25, 0.15 with
both friction loads, threshold runs of 20 s, long runs of 50 s at f = 0.35 (the report's
lengths), with the stick–slip contact (``contact = hybrid``: the same physics without
the regularised law's creep, and cheaper; docs/decisions.md §28, §30)."""

ATLAS_FORMAT = "celtstone-atlas-1"  # the ``format`` attribute of an atlas store
_DESIGN_FIELDS = tuple(f.name for f in dataclasses.fields(StoneDesign))
_DESIGN_UNITS = {
    "length": "m",
    "width_ratio": "1",
    "height_ratio": "1",
    "misalignment": "deg",
    "mass_fraction": "1",
    "density": "kg/m^3",
}
_MAX_REVERSALS = 64  # reversal times kept per long run in the store (the count is whole)
LONG_RUN_BATCH = 512
"""Designs whose long runs go to the GPU together (a launch per model kind): a launch's
runs are held until summarised, about 3.5 MB each at 50 s and 200 samples per second."""


# ----------------------------------------------------------------------- judging


def judge_design(numbers: Mapping[str, dict[str, Any]]) -> dict[str, Any]:
    """Every finding's verdict on one design, by the report's judges.

    Parameters
    ----------
    numbers : mapping of str to dict
        The design's numbers ``{"fig2": ..., "threshold": ..., "fig3": ...}``: the dicts
        ``celtstone reproduce`` writes, with the keys its judges read
        (:func:`atlas_numbers`).

    Returns
    -------
    dict of str to Verdict
        Each finding of ``reproduce.findings.JUDGES`` and its
        :class:`~celtstone.reproduce.findings.Verdict`.
    """
    verdicts = {}
    for finding, (target, judge) in JUDGES.items():
        verdicts[finding] = judge(numbers[target])
    return verdicts


# ----------------------------------------------------------------------- sweeps


def _ellipsoid(body: Body) -> Ellipsoid:
    """The shape of a design's body (always an ellipsoid, ``StoneDesign.body``)."""
    if not isinstance(body.shape, Ellipsoid):
        raise TypeError(f"{body.name}: not a stone of the atlas family")
    return body.shape


def _design_columns(bodies: Sequence[Body]) -> dict[str, list[float]]:
    """Sweep parameters that make each design's body from the first one (``sweep.spec``)."""
    columns: dict[str, list[float]] = {
        "mass": [b.mass for b in bodies],
        **{
            f"inertia_{i + 1}{j + 1}": [b.inertia[i][j] for b in bodies]
            for i, j in ((0, 0), (1, 1), (2, 2), (0, 1))
        },
        **{
            f"semi_axis_{axis}": [_ellipsoid(b).semi_axes[k] for b in bodies]
            for k, axis in enumerate("abc")
        },
        "com_offset": [_ellipsoid(b).com_offset for b in bodies],
    }
    return columns


def _fixed(study: Study, model: Model) -> dict[str, float | str]:
    """The study's start and ``model``'s settings as a sweep's fixed parameters (f apart)."""
    fixed: dict[str, float | str] = {
        "omega1": study.omega[0],
        "omega2": study.omega[1],
        "omega3": study.omega[2],
        "euler_alpha": study.euler_angles[0],
        "euler_beta": study.euler_angles[1],
    }
    for field in dataclasses.fields(model):
        value = getattr(model, field.name)
        if value is not None and field.name != "friction_coefficient":
            fixed[field.name] = value
    if model.name == "sliding":
        fixed["contact"] = model.contact
    return fixed


class _Runner:
    """Runs the atlas's sweeps over ``bodies``, each into its own store in ``out``."""

    def __init__(
        self,
        study: Study,
        bodies: Sequence[Body],
        out: Path | None,
        options: Mapping[str, Any],
        device: str = "cpu",
    ) -> None:
        self.study = study
        self.bodies = bodies
        self.columns = _design_columns(bodies)
        self.out = out
        self.options = dict(options)
        self.device = device

    def run(
        self,
        name: str,
        model: Model,
        designs: Sequence[int],
        frictions: Sequence[float],
        t_end: float,
    ) -> xr.Dataset:
        """Sweep ``model`` over the points (designs[k], frictions[k]) for ``t_end`` [s];
        the result's dimension ``point`` follows their order."""
        points = {key: [values[d] for d in designs] for key, values in self.columns.items()}
        if model.name == "sliding":
            points["friction_coefficient"] = [float(f) for f in frictions]
        sweep = Sweep(
            points=points,
            body=self.bodies[0],
            model=model.name,
            fixed=_fixed(self.study, model),
            t_end=t_end,
            rtol=self.study.rtol,
            atol=self.study.atol,
            reversal_threshold=self.study.band,
            device=self.device,
        )
        target = None if self.out is None else self.out / f"{name}.zarr"
        return sweep.run(target, **self.options)


def _case(point: xr.Dataset, model: Model, body: Body) -> dict[str, Any]:
    """One sweep point as a case of ``reproduce.cases.summarise``: its outcomes by their
    names (``simulation.outcome``; NaN as None), the settings the judges read."""
    settings = model.attributes()
    is_sliding = model.name == "sliding"
    outcome = {
        name: _number(point[name]) if OUTCOMES[name].dtype != "str" else str(point[name].values)
        for name in SWEPT
        if name != "message"
    }
    return {
        "case": case_name(model),
        "model": model.name,
        "friction_coefficient": float(point["friction_coefficient"]) if is_sliding else None,
        "friction_load": settings["friction_load"] if is_sliding else None,
        **outcome,
        "energy_rest": body.mass * body.gravity * body.shape.rest_height,
        "energy_monotone": is_energy_monotone(
            float(point["max_energy_rise"]), float(point["energy_initial"])
        ),
    }


def _number(value: xr.DataArray) -> float | int | None:
    """A point's number: a count as int, a float as float, NaN as None."""
    number = value.values.item()
    return number if isinstance(number, int) else json_number(number)


def _group(model: Model) -> str:
    """The sweep a Figure 2 model runs in: ``rolling``, or ``sliding_LOAD``."""
    if model.name == "rolling":
        return "rolling"
    return f"sliding_{model.attributes()['friction_load']}"


def _figure2(runner: _Runner) -> list[dict[str, Any]]:
    """Each design's Figure 2 numbers: ``reproduce.figure2``'s cases, in its order, from
    one sweep per model kind and friction load over every design at every f."""
    study = runner.study
    models = figure2_models(study)
    groups: dict[str, list[Model]] = {}
    for model in models:
        groups.setdefault(_group(model), []).append(model)
    cases: list[dict[str, dict[str, Any]]] = [{} for _ in runner.bodies]
    for group, chosen in groups.items():
        points = [(d, k) for d in range(len(runner.bodies)) for k in range(len(chosen))]
        frictions = [getattr(chosen[k], "friction_coefficient", math.nan) for _, k in points]
        designs = [d for d, _ in points]
        result = runner.run(f"fig2_{group}", chosen[0], designs, frictions, study.fig2_t_end)
        for index, (d, k) in enumerate(points):
            point = result.isel(point=index)
            case = _case(point, chosen[k], runner.bodies[d])
            cases[d][case["case"]] = case
    return [
        {"cases": [c[case_name(m)] for m in models], "frictions": list(study.frictions)}
        for c in cases
    ]


def _reverses(result: xr.Dataset) -> list[bool]:
    """Whether each point's spin reverses (``threshold``: a first reversal exists)."""
    return [bool(n > 0) for n in result["reversal_count"].values]


@dataclasses.dataclass
class _Bracket:
    """An open bracket of one design: the grid's bracket [1] and its current ends, each a
    point as ``reproduce.threshold``'s rows (``friction_coefficient``, ``reverses``)."""

    design: int
    grid_bracket: tuple[float, float]
    low: dict[str, Any]
    high: dict[str, Any]

    @property
    def width(self) -> float:
        return float(self.high["friction_coefficient"] - self.low["friction_coefficient"])


def _threshold(runner: _Runner) -> list[dict[str, Any]]:
    """Each design's threshold numbers (``reproduce.threshold.threshold_numbers``): the
    study's f grid for every design in one sweep, then each bisection round's midpoints
    of every design in one sweep, as ``reproduce.threshold`` bisects one design."""
    study, count = runner.study, len(runner.bodies)
    grid = [float(f) for f in study.friction_grid()]
    model = study.sliding(grid[0])
    designs = [d for d in range(count) for _ in grid]
    result = runner.run("threshold_grid", model, designs, grid * count, study.threshold_t_end)
    reverses = np.array(_reverses(result)).reshape(count, len(grid))

    def point(d: int, k: int) -> dict[str, Any]:
        return {"friction_coefficient": grid[k], "reverses": bool(reverses[d, k])}

    brackets = [
        _Bracket(d, (grid[k], grid[k + 1]), point(d, k), point(d, k + 1))
        for d in range(count)
        for k in range(len(grid) - 1)
        if reverses[d, k] != reverses[d, k + 1]
    ]
    round_number = 0
    while opened := [b for b in brackets if b.width > study.bisection_tolerance]:
        round_number += 1
        middles = [
            0.5 * (b.low["friction_coefficient"] + b.high["friction_coefficient"]) for b in opened
        ]
        result = runner.run(
            f"threshold_bisection_{round_number}",
            model,
            [b.design for b in opened],
            middles,
            study.threshold_t_end,
        )
        for bracket, middle, reversed_ in zip(opened, middles, _reverses(result), strict=True):
            middle_point = {"friction_coefficient": middle, "reverses": reversed_}
            if reversed_ == bracket.low["reverses"]:
                bracket.low = middle_point
            else:
                bracket.high = middle_point
    return [
        threshold_numbers(
            np.array(grid),
            list(reverses[d]),
            [boundary(b.grid_bracket, b.low, b.high) for b in brackets if b.design == d],
        )
        for d in range(count)
    ]


def _long_run(study: Study, body: Body) -> dict[str, Any]:
    """The Figure 3 numbers of one body: rolling and sliding at the study's long-run f for
    ``fig3_t_end``, each summarised as ``celtstone reproduce`` does."""
    cases = []
    for model in _long_run_models(study):
        trajectory = simulate(
            model, body, study.initial_state, study.fig3_t_end, rtol=study.rtol, atol=study.atol
        )
        cases.append({"case": case_name(model), **summarise(trajectory, body, study.band)})
    return {"cases": cases, "friction": study.fig3_friction, "band": study.band}


def _long_run_models(study: Study) -> tuple[Model, Model]:
    """The models of a design's long runs: rolling, and sliding at the long-run f."""
    return study.rolling(), study.sliding(study.fig3_friction)


def _long_runs_together(study: Study, bodies: Sequence[Body], device: str) -> list[dict[str, Any]]:
    """:func:`_long_run` of each of ``bodies``: the rolling runs of all as one
    ``simulate_many`` on ``device``, then the sliding runs, each summarised as
    ``celtstone reproduce`` does."""
    cases: list[list[dict[str, Any]]] = [[] for _ in bodies]
    for model in _long_run_models(study):
        runs = simulate_many(
            [(model, body, study.initial_state) for body in bodies],
            study.fig3_t_end,
            device=device,
            rtol=study.rtol,
            atol=study.atol,
        )
        for design_cases, trajectory, body in zip(cases, runs, bodies, strict=True):
            if isinstance(trajectory, CeltstoneError):  # none with errors="raise"
                raise trajectory
            design_cases.append(
                {"case": case_name(model), **summarise(trajectory, body, study.band)}
            )
    return [{"cases": c, "friction": study.fig3_friction, "band": study.band} for c in cases]


def _long_runs(
    study: Study,
    designs: Sequence[StoneDesign],
    bodies: Sequence[Body],
    out: Path | None,
    workers: int | None,
    overwrite: bool,
    device: str = "cpu",
    batch: bool | None = None,
) -> list[dict[str, Any]]:
    """Every design's long run: on ``workers`` threads (the compiled loop releases the
    GIL), or on the GPU (``device`` "cuda"; ``batch`` True: on the CPU too, through
    ``simulate_many``'s threads) the designs not yet stored in batches of
    ``LONG_RUN_BATCH``, one per model kind; with ``out`` each one's numbers are kept in
    ``out/long_run/DESIGN.json`` as soon as they exist, and found there again by a
    resumed atlas (which checks they are of the same design and study)."""
    directory = None if out is None else out / "long_run"
    if directory is not None:
        directory.mkdir(exist_ok=True)

    def path(index: int) -> Path | None:
        return None if directory is None else directory / f"design_{index:05d}.json"

    def identity(index: int) -> dict[str, Any]:
        return {"design": dataclasses.asdict(designs[index]), "study": repr(study)}

    def stored(index: int) -> dict[str, Any] | None:
        found = path(index)
        if found is None or not found.exists() or overwrite:
            return None
        kept = json.loads(found.read_text(encoding="utf-8"))
        if kept["identity"] != identity(index):
            raise ParameterError(
                "resume",
                str(found),
                "the long run of the same design and study",
                "the atlas's designs or settings changed: use a new out or overwrite",
            )
        return dict(kept["numbers"])

    def keep(index: int, numbers: dict[str, Any]) -> dict[str, Any]:
        target = path(index)
        if target is not None:
            write_json(
                {"identity": identity(index), "numbers": numbers}, target, overwrite=overwrite
            )
        return numbers

    def one(index: int) -> dict[str, Any]:
        found = stored(index)
        return found if found is not None else keep(index, _long_run(study, bodies[index]))

    with warnings.catch_warnings():  # the paper's N = m g exceeds Coulomb's bound: recorded
        warnings.simplefilter("ignore", FrictionBoundWarning)
        if not (device != "cpu" if batch is None else batch):
            threads = workers or len(os.sched_getaffinity(0))
            with ThreadPoolExecutor(max_workers=threads) as pool:
                return list(pool.map(one, range(len(designs))))
        numbers = [stored(index) for index in range(len(designs))]
        todo = [index for index, found in enumerate(numbers) if found is None]
        for first in range(0, len(todo), LONG_RUN_BATCH):
            part = todo[first : first + LONG_RUN_BATCH]
            together = _long_runs_together(study, [bodies[i] for i in part], device)
            for index, found in zip(part, together, strict=True):
                numbers[index] = keep(index, found)
    return [found for found in numbers if found is not None]


def atlas_device(device: object, study: Study) -> str:
    """The device that runs an atlas of ``study``: "cpu" or "cuda", for ``device`` "cpu",
    "cuda" or "auto" (``sweep.devices.resolve_device`` of each model kind it runs).

    Raises
    ------
    ParameterError
        for another ``device``, and for "cuda" where no GPU can run the atlas's runs:
        before any run.
    """
    from celtstone.simulation.models import HybridModel
    from celtstone.sweep.devices import resolve_device

    if device == "cpu":
        return "cpu"
    resolved = {
        resolve_device(device, model.name, model.default_method, isinstance(model, HybridModel))
        for model in _long_run_models(study)
    }
    return "cuda" if resolved == {"cuda"} else "cpu"


# ----------------------------------------------------------------------- the atlas


def atlas_numbers(
    designs: Sequence[StoneDesign],
    study: Study = ATLAS_STUDY,
    out: Path | None = None,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    resume: bool = False,
    overwrite: bool = False,
    progress: Callable[[str], None] | None = None,
    device: str = "cpu",
) -> list[dict[str, dict[str, Any]]]:
    """Each design's numbers for the judges, computed with the settings of ``study``.

    The work of :func:`compute_atlas`, whose parameters these are, without the dataset.

    Parameters
    ----------
    designs : sequence of StoneDesign
        The stones.
    study : Study, default ATLAS_STUDY
        The runs' settings.
    out : pathlib.Path, optional
        The directory of the sweeps' stores and the long runs' numbers, or None.
    workers, scheduler : int or str, optional
        Local threads, or a ``dask.distributed`` scheduler for the sweeps.
    resume, overwrite : bool, default False
        Keep the finished sweeps and long runs in ``out``, or replace them.
    progress : callable, optional
        Told each stage as it starts.
    device : str, default "cpu"
        Where the runs go: "cpu", "cuda" or "auto" (:func:`compute_atlas`).

    Returns
    -------
    list of dict
        Per design, ``{"fig2": ..., "threshold": ..., "fig3": ...}``: the dicts of
        ``celtstone reproduce`` with the keys its judges read (module docstring).
    """
    device = atlas_device(device, study)
    if device == "cuda" and scheduler is not None:
        raise ParameterError(
            "scheduler", scheduler, "no value with device cuda", "the GPU runs every point"
        )
    bodies = [design.body() for design in designs]
    options: dict[str, Any] = {"resume": resume, "overwrite": overwrite}
    if device == "cpu":  # the GPU's sweeps take no threads
        options.update({"workers": workers} if scheduler is None else {"scheduler": scheduler})
    runner = _Runner(study, bodies, out, options, device)
    say = progress or (lambda _: None)
    say("Figure 2 sweeps")
    fig2 = _figure2(runner)
    say("threshold sweeps")
    thresholds = _threshold(runner)
    say("long runs")
    long_runs = _long_runs(study, designs, bodies, out, workers, overwrite, device)
    return [
        {"fig2": f, "threshold": t, "fig3": r}
        for f, t, r in zip(fig2, thresholds, long_runs, strict=True)
    ]


def outcome_units(name: str) -> dict[str, str]:
    """The attributes of an atlas field that holds the outcome ``name`` of its runs: its
    unit as declared (``simulation.outcome.OUTCOMES``)."""
    return {"units": OUTCOMES[name].variable.unit}


def _padded(rows: Sequence[Sequence[float]], width: int) -> np.ndarray:
    table = np.full((len(rows), width), np.nan)
    for k, row in enumerate(rows):
        table[k, : min(len(row), width)] = row[:width]
    return table


def _verdict_variables(verdicts: Sequence[Mapping[str, Any]]) -> dict[str, tuple]:
    """Per finding of ``FINDINGS`` its verdict ``FINDING`` and our number in words
    ``FINDING_ours``, and ``all_findings_hold``: Dataset variables on ``design``."""
    variables: dict[str, tuple] = {}
    for finding, statement in FINDINGS.items():
        variables[finding] = (
            ("design",),
            np.array([v[finding].reproduced for v in verdicts], dtype=str),
            {"long_name": statement},
        )
        variables[f"{finding}_ours"] = (
            ("design",),
            np.array([v[finding].ours for v in verdicts], dtype=str),
            {},
        )
    variables["all_findings_hold"] = (
        ("design",),
        [all(v[f].reproduced == "yes" for f in FINDINGS) for v in verdicts],
        {},
    )
    return variables


def _design_coordinates(designs: Sequence[StoneDesign]) -> dict[str, tuple]:
    """The designs' parameters as coordinates on ``design``, with their units."""
    return {
        name: (
            ("design",),
            [float(getattr(d, name)) for d in designs],
            {"units": _DESIGN_UNITS[name]},
        )
        for name in _DESIGN_FIELDS
    }


def atlas_dataset(
    designs: Sequence[StoneDesign], numbers: Sequence[Mapping[str, dict[str, Any]]], study: Study
) -> xr.Dataset:
    """The atlas as a Dataset on dimension ``design``.

    Parameters
    ----------
    designs : sequence of StoneDesign
        The stones.
    numbers : sequence of mapping of str to dict
        Each design's numbers, in the same order (:func:`atlas_numbers`).
    study : Study
        The settings the numbers were computed with, recorded in the attributes.

    Returns
    -------
    xarray.Dataset
        The design's parameters (coordinates, with units), what the stone is (mass, G,
        point masses), the numbers the judges read, and per finding of ``FINDINGS`` its
        verdict ``FINDING`` ("yes", "partly", "no") and our number in words
        ``FINDING_ours``.
    """
    import xarray as xr

    from celtstone.simulation.integrate import version

    bodies = [d.body() for d in designs]
    fig2_cases = [c["case"] for c in numbers[0]["fig2"]["cases"]] if numbers else []
    long_cases = [c["case"] for c in numbers[0]["fig3"]["cases"]] if numbers else []
    design_dim, fig2_dims, long_dims = ("design",), ("design", "fig2_case"), ("design", "long_case")

    def per_case(target: str, key: str) -> np.ndarray:
        return np.array(
            [[math.nan if c[key] is None else c[key] for c in n[target]["cases"]] for n in numbers],
            dtype=float,
        ).reshape(len(numbers), -1)

    def appears(n: Mapping[str, dict[str, Any]], kind: str) -> float:
        found = [b["estimate"] for b in n["threshold"]["boundaries"] if b["kind"] == kind]
        return min(found) if found else math.nan

    long_times = [[c["reversal_times"] for c in n["fig3"]["cases"]] for n in numbers]
    width = max([len(t) for pair in long_times for t in pair] + [1])
    width = min(width, _MAX_REVERSALS)
    data = {
        "mass": (design_dim, [b.mass for b in bodies], {"units": "kg"}),
        "com_offset": (
            design_dim,
            [_ellipsoid(b).com_offset for b in bodies],
            {"units": "m", "long_name": "depth h of G below the centre"},
        ),
        "point_mass": (design_dim, [d.point_mass for d in designs], {"units": "kg"}),
        "point_mass_y": (
            design_dim,
            [d.point_mass_position[1] for d in designs],
            {"units": "m", "long_name": "y0 of the point masses"},
        ),
        "rocking_period": (design_dim, [b.rocking_period for b in bodies], {"units": "s"}),
        "fig2_first_reversal_time": (
            fig2_dims,
            per_case("fig2", "first_reversal_time"),
            outcome_units("first_reversal_time"),
        ),
        "fig2_energy_final": (
            fig2_dims,
            per_case("fig2", "energy_final"),
            outcome_units("energy_final"),
        ),
        "fig2_peak_reversed_spin": (
            fig2_dims,
            per_case("fig2", "peak_reversed_spin"),
            outcome_units("peak_reversed_spin"),
        ),
        "energy_rest": (
            design_dim,
            per_case("fig2", "energy_rest")[:, 0] if numbers else [],
            {"units": "J"},
        ),
        "lowest_reversing_f": (
            design_dim,
            [
                math.nan
                if n["threshold"]["lowest_reversing_f"] is None
                else n["threshold"]["lowest_reversing_f"]
                for n in numbers
            ],
            {"units": "1"},
        ),
        "reversal_appears_f": (
            design_dim,
            [appears(n, "appears") for n in numbers],
            {"units": "1", "long_name": "lowest estimate of f where the reversal appears"},
        ),
        "reversal_disappears_f": (
            design_dim,
            [appears(n, "disappears") for n in numbers],
            {"units": "1", "long_name": "lowest estimate of f where the reversal disappears"},
        ),
        "reverses_at_grid_start": (
            design_dim,
            [n["threshold"]["grid_reverses"][0] for n in numbers],
            {},
        ),
        "long_run_reversals": (
            long_dims,
            np.array([[len(t) for t in pair] for pair in long_times], dtype=int).reshape(
                len(numbers), -1
            ),
            {"units": "1"},
        ),
        "long_run_spin_crossing_count": (
            long_dims,
            per_case("fig3", "spin_crossing_count"),
            outcome_units("spin_crossing_count"),
        ),
        "long_run_spin_final": (
            long_dims,
            per_case("fig3", "spin_final"),
            outcome_units("spin_final"),
        ),
        "long_run_reversal_times": (
            ("design", "long_case", "reversal"),
            np.stack([_padded(pair, width) for pair in long_times])
            if numbers
            else np.empty((0, 0, width)),
            {
                "units": "s",
                "long_name": f"reversal times of the long runs (the first {_MAX_REVERSALS}), "
                "NaN after the last",
            },
        ),
    }
    data.update(_verdict_variables([judge_design(n) for n in numbers]))
    coords = _design_coordinates(designs)
    coords.update(
        fig2_case=(("fig2_case",), fig2_cases, {}), long_case=(("long_case",), long_cases, {})
    )
    attrs = {
        "format": ATLAS_FORMAT,
        "title": "celtstone atlas: the paper's findings over a family of stones",
        "celtstone_version": version(),
        "study": study.describe(),
        "study_settings": repr(study),
        "construction": "half-ellipsoid plus two point masses (docs/bodies.md, decisions §32)",
    }
    return xr.Dataset(
        {k: xr.Variable(*v) for k, v in data.items()},
        coords={k: xr.Variable(*v) for k, v in coords.items()},
        attrs=attrs,
    )


def _is_atlas_store(path: Path, store_format: str = ATLAS_FORMAT) -> bool:
    metadata = path / "zarr.json"
    try:
        document = json.loads(metadata.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return (
        isinstance(document, dict) and document.get("attributes", {}).get("format") == store_format
    )


def write_atlas(dataset: xr.Dataset, path: str | Path, *, overwrite: bool = False) -> Path:
    """Write an atlas as a Zarr store, whole or not at all.

    The store is built in a temporary directory beside ``path``, then moved in.

    Parameters
    ----------
    dataset : xarray.Dataset
        The atlas (:func:`atlas_dataset`) or a search's table.
    path : str or pathlib.Path
        The store written.
    overwrite : bool, default False
        Replace an existing ``path``, only if it is a store of the dataset's ``format``
        (default ``celtstone-atlas-1``; a search store's is ``celtstone-atlas-search-1``).

    Returns
    -------
    pathlib.Path
        The store written.

    Raises
    ------
    ParameterError
        When ``path`` exists and is not replaced.
    """
    target = Path(path)
    store_format = str(dataset.attrs.get("format", ATLAS_FORMAT))
    if os.path.lexists(target) and not (overwrite and _is_atlas_store(target, store_format)):
        raise ParameterError(
            "out",
            str(target),
            "a new path, or an atlas store with overwrite",
            "an existing atlas store is replaced only with overwrite; nothing else ever",
        )
    if os.path.lexists(target):  # a store holding a user's file is not replaced either
        check_replaceable(target, "reproduce atlas", zarr=True)
    text = [name for name, v in dataset.variables.items() if v.dtype.kind == "U"]
    # text as variable-length strings, which Zarr v3 specifies (fixed-width ones it warns of)
    dataset = dataset.assign({name: dataset[name].astype(object) for name in text})
    with temporary_directory(target) as temporary:
        try:
            dataset.to_zarr(temporary, mode="w", consolidated=False, zarr_format=3)
        except OSError as error:
            raise output_error(target, error) from error
        replace_directory(temporary, target)
    return target


def compute_atlas(
    designs: Sequence[StoneDesign],
    study: Study = ATLAS_STUDY,
    out: str | Path | None = None,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    resume: bool = False,
    overwrite: bool = False,
    progress: Callable[[str], None] | None = None,
    device: str = "cpu",
) -> xr.Dataset:
    """The paper's five findings over ``designs``, judged as ``celtstone reproduce`` does.

    Parameters
    ----------
    designs : sequence of StoneDesign
        The stones, at least one.
    study : Study, default ATLAS_STUDY
        The runs' settings (start, contact, run lengths, f grid); its ``body`` is unused.
    out : str or pathlib.Path, optional
        A directory for the sweeps' stores, the long runs' numbers and ``atlas.zarr``;
        None keeps everything in memory.
    workers : int, optional
        Local threads (default: every core); unused on the GPU.
    scheduler : str, optional
        A ``dask.distributed`` scheduler ``"tcp://HOST:PORT"`` for the sweeps, instead of
        local threads (the long runs stay local); not with ``device="cuda"``.
    resume : bool, default False
        Continue an atlas in ``out``: every finished sweep and long run is kept.
    overwrite : bool, default False
        Replace the stores and files of an earlier atlas in ``out``.
    progress : callable, optional
        Called with a few words as each stage starts.
    device : str, default "cpu"
        Where the runs go: "cpu"; "cuda", a CUDA GPU: each sweep on it
        (``Sweep(device="cuda")``) and the long runs of every design as one launch per
        model kind, refused where there is none, before any run; "auto", the GPU where
        there is one, else the CPU.

    Returns
    -------
    xarray.Dataset
        The :func:`atlas_dataset` of the designs.

    Raises
    ------
    ParameterError
        When ``designs`` is empty, ``out`` holds files and neither ``resume`` nor
        ``overwrite`` is given, or ``device`` is none of "cpu", "cuda", "auto" or a GPU
        that is not here.
    """
    if not designs:
        raise ParameterError("designs", list(designs), "at least one StoneDesign")
    device = atlas_device(device, study)  # before ``out`` is made
    directory = None if out is None else Path(out)
    if directory is not None:
        if directory.exists() and any(directory.iterdir()) and not (resume or overwrite):
            raise ParameterError(
                "out", str(directory), "a new or empty directory", "use resume or overwrite"
            )
        directory.mkdir(parents=True, exist_ok=True)
    numbers = atlas_numbers(
        designs,
        study,
        directory,
        workers=workers,
        scheduler=scheduler,
        resume=resume,
        overwrite=overwrite,
        progress=progress,
        device=device,
    )
    dataset = atlas_dataset(designs, numbers, study)
    if device == "cuda":  # as a sweep on the GPU records it
        from celtstone.sweep.devices import describe_gpu

        dataset.attrs["device"] = describe_gpu()
    if directory is not None:
        write_atlas(dataset, directory / "atlas.zarr", overwrite=resume or overwrite)
    return dataset


def hertz_study(study: Study, pair: MaterialPair) -> Study:
    """A study whose contact radius ε is the Hertz radius of a pair of materials.

    The atlas's second contact axis (issue 15, item 1): ε the radius
    (3 N R_eq / (4 E*))^(1/3) of the circular Hertz contact of the stone on the plane
    (``SlidingModel`` with E and ν), instead of the fixed ε.

    Parameters
    ----------
    study : Study
        The study whose contact is replaced.
    pair : MaterialPair
        The materials of stone and plane.

    Returns
    -------
    Study
        ``study`` with the pair's ``elastic_modulus`` and ``poisson_ratio``
        (:meth:`MaterialPair.model_settings`) and a ``variant`` naming the pair.
    """
    settings = pair.model_settings()
    return dataclasses.replace(
        study,
        variant=f"{study.variant or 'paper'}-hertz-{pair.stone}-{pair.plane}",
        elastic_modulus=settings["elastic_modulus"],
        poisson_ratio=settings["poisson_ratio"],
    )
