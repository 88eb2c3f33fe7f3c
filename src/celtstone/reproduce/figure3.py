"""Figure 3 analogue: a long run, rolling against sliding at f = 0.35.

The run is long enough for at least three reversals in rolling; the paper's
statement is about the sign changes after the second one.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from celtstone.plotting import plot_energy_budget, plot_spin_comparison, save_figure_formats
from celtstone.reproduce.cases import run_figure_cases, save_results
from celtstone.reproduce.progress import Progress
from celtstone.reproduce.study import Study
from celtstone.simulation.models import Model

__all__ = ["figure3", "figure3_models"]


def figure3_models(study: Study) -> list[Model]:
    """Rolling, then sliding at the study's ``fig3_friction``."""
    return [study.rolling(), study.sliding(study.fig3_friction)]


def figure3(study: Study, out: Path, progress: Progress) -> dict[str, Any]:
    """Run Figure 3 of the paper for ``study``: a long run, rolling against sliding.

    Parameters
    ----------
    study : Study
        The study: its ``fig3_t_end`` and the sliding run's ``fig3_friction``.
    out : pathlib.Path
        Where its data, figures and table are written (the target's staging directory).
    progress : Progress
        Advanced after each of the two runs.

    Returns
    -------
    dict
        The numbers the findings are judged by (``data/fig3_KEY.json``).
    """
    body, stem, datasets, cases = run_figure_cases(
        "fig3", study, figure3_models(study), study.fig3_t_end, out, progress
    )
    title = (
        f"Figure 3 analogue, {study.key}: long run, rolling and sliding f = {study.fig3_friction:g}"
    )
    figure = plot_spin_comparison([[d] for d in datasets], title, threshold=study.band, columns=1)
    energy = plot_energy_budget(datasets, f"{study.key}: energy over the long run")
    figures = save_figure_formats(figure, out, stem)
    figures += save_figure_formats(energy, out, f"{stem}_energy")
    return save_results(
        "fig3", study, body, out, cases, figures, study.fig3_t_end, friction=study.fig3_friction
    )
