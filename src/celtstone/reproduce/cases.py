"""One run of a study: simulate, keep its NetCDF beside the figures, summarise it."""

from __future__ import annotations

import functools
import warnings
from collections.abc import Hashable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

from celtstone.bodies import Body
from celtstone.errors import FrictionBoundWarning
from celtstone.files.export import write, write_json, write_table
from celtstone.reproduce.parallel import map_in_threads, shared_run
from celtstone.reproduce.progress import Progress
from celtstone.reproduce.study import Study
from celtstone.simulation.integrate import simulate, version
from celtstone.simulation.models import HybridModel, Model
from celtstone.simulation.outcome import json_number
from celtstone.simulation.trajectory import Trajectory

if TYPE_CHECKING:
    import xarray as xr


__all__ = [
    "case_key",
    "case_name",
    "compile_run_loop",
    "compute_case",
    "provenance",
    "run_cases",
    "run_figure_cases",
    "save_results",
    "study_identity",
    "summarise",
]


def case_name(model: Model) -> str:
    """File-name stem of a case: ``rolling`` or ``sliding_f0.35_static``."""
    if model.name != "sliding":
        return model.name
    settings = model.attributes()
    return f"sliding_f{settings['friction_coefficient']:g}_{settings['friction_load']}"


def provenance(study: Study, body: Body, **extra: Any) -> dict[str, Any]:
    """Header of a CSV table: what was run, with which software."""
    return {
        "software": f"celtstone {version()}",
        "body": body.name,
        "body_source": body.source,
        "initial_state": (
            f"omega {list(study.omega)} rad/s, Euler angles {list(study.euler_angles)} deg"
        ),
        **study.contact_settings(),
        "rtol": study.rtol,
        "atol": study.atol,
        "reversal_band_rad_per_s": study.band,
        **extra,
    }


def study_identity(study: Study) -> dict[str, Any]:
    """What names a study in its numbers: ``key`` (file names, report column) and, for
    a contact other than the paper's, ``variant`` and ``contact`` (its settings). The
    paper's contact writes neither ``variant`` nor ``contact``, as before variants."""
    if study.is_paper_contact:
        return {"key": study.key}
    return {"key": study.key, "variant": study.variant, "contact": study.contact_settings()}


@contextmanager
def quiet_friction_bound() -> Iterator[None]:
    """The warning filters of a reproduction's runs: the paper's static load exceeding
    Coulomb's bound is the paper's own approximation, which the reproduction follows on
    purpose: not warned, but recorded in each case's summary (``max_friction_bound_ratio``).
    Set around a whole ``parallel.map_in_threads`` of :func:`simulate_case` (the filters
    are the process's)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FrictionBoundWarning)
        yield


def run_cases(
    study: Study,
    body: Body,
    models: list[Model],
    t_end: float,
    out: Path,
    stem: str,
    progress: Progress,
) -> tuple[list[xr.Dataset], list[dict[str, Any]]]:
    """Run each model from the study's start to ``t_end`` [s], the runs side by side on
    the cores (``parallel.map_in_threads``); write each to ``out/data/STEM_CASE.nc`` and
    summarise it.

    The compiled loop runs in a worker thread (a progress callback makes ``simulate`` do
    so) and the threads take no new run once stopped, so that Ctrl-C and SIGTERM stop a
    reproduction within a tenth of a second, not when the runs in progress end.

    Returns the runs' datasets and their cases (case name, file relative to ``out``,
    :func:`summarise`), in the order of ``models``; ``progress`` is advanced once a run.
    """
    progress.set_description(f"{stem}: runs")
    data = out / "data"
    data.mkdir(parents=True, exist_ok=True)
    datasets, cases = [], []
    with quiet_friction_bound():
        runs = map_in_threads(lambda model: simulate_case(study, body, model, t_end), models)
        for model, trajectory in zip(models, runs, strict=True):
            path = data / f"{stem}_{case_name(model)}.nc"
            write(trajectory.dataset, path)
            datasets.append(trajectory.dataset)
            cases.append(
                {
                    "case": case_name(model),
                    "file": str(path.relative_to(out)),
                    **summarise(trajectory, body, study.band),
                }
            )
            progress.update(1)
    return datasets, cases


def run_figure_cases(
    target: str, study: Study, models: list[Model], t_end: float, out: Path, progress: Progress
) -> tuple[Body, str, list[xr.Dataset], list[dict[str, Any]]]:
    """The start of a figure's target (``fig2``, ``fig3``): the study's body, the target's
    file stem ``TARGET_KEY``, and :func:`run_cases` of ``models`` to ``t_end`` [s] (their
    datasets and cases, in the order of ``models``)."""
    body = study.load_body()
    stem = f"{target}_{study.key}"
    datasets, cases = run_cases(study, body, models, t_end, out, stem, progress)
    return body, stem, datasets, cases


def case_key(study: Study, model: Model, t_end: float) -> Hashable:
    """What decides a run of :func:`simulate_case`: two with the same key are the same
    run (the body, by its name or file, is one per name in a reproduction)."""
    return (study.body, study.initial_state, model, t_end, study.rtol, study.atol)


def simulate_case(study: Study, body: Body, model: Model, t_end: float) -> Trajectory:
    """One run of :func:`run_cases`, without its warning filters (safe on several threads):
    the one computed ahead if the reproduction planned it (``parallel.sharing_runs``)."""
    return shared_run(
        case_key(study, model, t_end),
        functools.partial(compute_case, study, body, model, t_end),
    )


def compute_case(study: Study, body: Body, model: Model, t_end: float) -> Trajectory:
    """Compute one run of :func:`simulate_case`, never shared (what a planned run does)."""
    return simulate(
        model,
        body,
        study.initial_state,
        t_end,
        rtol=study.rtol,
        atol=study.atol,
        progress=_keep_signals_live,
    )


WARM_UP_TIME = 0.01
"""Simulated time [s] of :func:`compile_run_loop`'s run: a few steps reach the loop."""


def compile_run_loop(study: Study) -> None:
    """Compile the run loop for every model and method (or load it from numba's cache)
    with a short stick–slip run of ``study``'s body, before a reproduction's runs start.

    Every run of a reproduction takes that loop once it is compiled, unless a loop of
    its own is compiled already (``solvers.driver.integrate_link``: never compiled once
    that one is), and its stick–slip runs need it anyway (their
    phases call one loop). A rolling or sliding run that starts first, on an empty
    cache, compiles a loop of its own for its model, which the other models cannot use:
    a reproduction's first rolling run, computed ahead on the other core from its first
    second, compiled one for nothing, and numba compiles one function at a time in a
    process, so the other core waited for it too. Results do not change: every loop
    gives the same numbers.
    """
    with quiet_friction_bound():
        compute_case(study, study.load_body(), HybridModel(), WARM_UP_TIME)


def _keep_signals_live(time: float) -> None:
    """Progress callback of :func:`simulate_case`: reports nothing; its presence keeps the
    main thread free to take signals while the compiled loop runs."""


def summarise(trajectory: Trajectory, body: Body, band: float) -> dict[str, Any]:
    """JSON-safe numbers of a run used by figures and the report: the run's outcome record
    (``simulation.outcome``) with the study's hysteresis ``band`` [rad/s], the outcomes
    read from its samples, and the settings the report names (SI units; NaN as None)."""
    attrs = trajectory.samples.attrs
    is_sliding = attrs["model"] == "sliding"
    outcome = trajectory.outcome(band)
    summary = trajectory.summary()
    return {
        "model": attrs["model"],
        "friction_coefficient": attrs.get("friction_coefficient") if is_sliding else None,
        "friction_load": attrs.get("friction_load") if is_sliding else None,
        **{
            name: json_number(value) if isinstance(value, float) else value
            for name, value in outcome.items()
            if name != "message"
        },
        "reversal_times": [float(t) for t in trajectory.reversal_times(band)],
        **{name: summary[name] for name in _FROM_SAMPLES},
        "energy_rest": float(body.mass * body.gravity * body.shape.rest_height),
    }


# the outcomes of a case read from the run's whole samples (``Trajectory.summary``)
_FROM_SAMPLES = (
    "first_spin_crossing_time",
    "max_friction_bound_ratio",
    "max_slip_speed",
    "energy_monotone",
)


def save_results(
    target: str,
    study: Study,
    body: Body,
    out: Path,
    cases: list[dict[str, Any]],
    figures: list[str],
    t_end: float,
    **extra: Any,
) -> dict[str, Any]:
    """Write the cases' table (CSV with provenance) and numbers (JSON); return the numbers."""
    import pandas as pd

    stem = f"{target}_{study.key}"
    table = pd.DataFrame(
        [
            {**case, "reversal_times": " ".join(f"{t:.6g}" for t in case["reversal_times"])}
            for case in cases
        ]
    )
    write_table(table, out / f"{stem}.csv", provenance(study, body, t_end_s=t_end, target=target))
    result = {
        "target": target,
        "study": study.describe(),
        "body": body.name,
        **study_identity(study),
        "t_end": t_end,
        "band": study.band,
        "contact_radius": study.contact_radius,
        **extra,
        "cases": cases,
        "figures": sorted(figures),
        "table": f"{stem}.csv",
    }
    write_json(result, out / "data" / f"{stem}.json")
    return result
