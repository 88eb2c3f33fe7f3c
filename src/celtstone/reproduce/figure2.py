"""Figure 2 analogue: spin against time, rolling and sliding at f = 0.35, 0.25, 0.15.

Sliding runs use the study's contact (the paper's: ε = 1 mm) with N = m g (the paper's
first approximation) and with the dynamic normal force, same body and start (paper
section 4). A video shows the rolling stone beside the sliding one at the largest f, in
real time. A paper-contact study also runs the one-at-a-time table of the realistic
contact's ingredients (``reproduce.ingredients``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from celtstone.plotting import plot_energy_budget, plot_spin_comparison, save_figure_formats
from celtstone.reproduce.cases import case_name, run_figure_cases, save_results
from celtstone.reproduce.ingredients import run_ingredients
from celtstone.reproduce.progress import Progress
from celtstone.reproduce.study import Study
from celtstone.simulation.models import FRICTION_LOAD_OPTIONS, Model
from celtstone.visual import animate_comparison

__all__ = ["FRICTION_LOADS", "figure2", "figure2_models"]

FRICTION_LOADS = tuple(FRICTION_LOAD_OPTIONS)  # static (N = m g), then dynamic
_LOAD_WORDS = {"static": "N = m g", "dynamic": "the dynamic N"}


def figure2_models(study: Study) -> list[Model]:
    """Rolling, then sliding at each f with each friction load of the study."""
    models: list[Model] = [study.rolling()]
    for friction in study.frictions:
        models.extend(study.sliding(friction, load) for load in study.fig2_loads)
    return models


def figure2(study: Study, out: Path, progress: Progress) -> dict[str, Any]:
    """Run Figure 2 of the paper for ``study``; write its data, figures and table.

    Parameters
    ----------
    study : Study
        The study: rolling, then sliding at each of its ``frictions`` with each of its
        ``fig2_loads``, for ``fig2_t_end``.
    out : pathlib.Path
        The target's staging directory.
    progress : Progress
        Advanced once a run.

    Returns
    -------
    dict
        The numbers the findings are judged by (``data/fig2_KEY.json``).
    """
    models = figure2_models(study)
    body, stem, runs, cases = run_figure_cases(
        "fig2", study, models, study.fig2_t_end, out, progress
    )
    datasets = {case_name(model): run for model, run in zip(models, runs, strict=True)}
    panels = [[datasets["rolling"]]] + [
        [datasets[case_name(study.sliding(f, load))] for load in study.fig2_loads]
        for f in study.frictions
    ]
    title = f"Figure 2 analogue, {study.key}: spin against time ({study.contact_words()})"
    figure = plot_spin_comparison(panels, title, threshold=study.band)
    energy = plot_energy_budget(
        [datasets["rolling"]] + [datasets[case_name(study.sliding(f))] for f in study.frictions],
        f"{study.key}: energy and energy budget, sliding with {_LOAD_WORDS[study.friction_load]}",
    )
    figures = save_figure_formats(figure, out, stem)
    figures += save_figure_formats(energy, out, f"{stem}_energy")
    progress.set_description(f"{stem}: animation")
    animation = _animate(study, datasets, out / f"{stem}_rolling_vs_sliding.mp4")
    ingredients = run_ingredients(study, body, out, progress)
    extra = {} if ingredients is None else {"ingredients": ingredients}
    return save_results(
        "fig2",
        study,
        body,
        out,
        cases,
        figures,
        study.fig2_t_end,
        frictions=list(study.frictions),
        animation=str(animation.relative_to(out)),
        **extra,
    )


def _animate(study: Study, datasets: dict[str, Any], path: Path) -> Path:
    """Rolling beside sliding at the largest f (the study's friction load), side by side in
    real time."""
    friction = max(study.frictions)
    sliding = case_name(study.sliding(friction))
    animate_comparison(
        [datasets["rolling"], datasets[sliding]],
        ["rolling without sliding", f"rolling with sliding, f = {friction:g}"],
        path,
    )
    return path
