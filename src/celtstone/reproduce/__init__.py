"""Reproduce the paper's findings: Figures 2 and 3, the friction threshold, a report.

>>> from celtstone.reproduce import reproduce          # doctest: +SKIP
>>> reproduce(["all"], out="results")                  # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from celtstone.errors import ParameterError
from celtstone.reproduce.figure2 import figure2, figure2_models
from celtstone.reproduce.figure3 import figure3
from celtstone.reproduce.progress import progress_bar
from celtstone.reproduce.report import render_report, write_report
from celtstone.reproduce.study import STUDIES, TARGETS, Study, reduced, study_for
from celtstone.reproduce.threshold import threshold

__all__ = [
    "STUDIES",
    "TARGETS",
    "Study",
    "figure2",
    "figure3",
    "reduced",
    "render_report",
    "reproduce",
    "study_for",
    "threshold",
    "write_report",
]

_RUNNERS = {"fig2": figure2, "fig3": figure3, "threshold": threshold}


def _targets(names: Sequence[str]) -> list[str]:
    chosen: list[str] = []
    for name in names:
        if name == "all":
            chosen.extend(TARGETS)
        elif name in TARGETS:
            chosen.append(name)
        else:
            raise ParameterError("target", name, "one of: " + ", ".join((*TARGETS, "all")))
    return list(dict.fromkeys(chosen))


def _runs(study: Study, target: str) -> int:
    if target == "fig2":
        return len(figure2_models(study))
    if target == "fig3":
        return 2
    return len(study.friction_grid())


def reproduce(
    targets: Sequence[str],
    out: str | Path = "results",
    studies: Sequence[Study] = STUDIES,
    progress: bool = True,
) -> Path:
    """Run ``targets`` (``fig2``, ``fig3``, ``threshold`` or ``all``) for each study.

    Writes figures, tables and NetCDF runs into ``out`` and rebuilds
    ``out/report.md`` from every target's numbers found there; returns its path.
    Each file is written whole or not at all, so an interrupted run leaves only
    complete files.
    """
    chosen = _targets(targets)
    directory = Path(out)
    if directory.exists() and not directory.is_dir():
        raise ParameterError("out", str(out), "a directory")
    directory.mkdir(parents=True, exist_ok=True)
    total = sum(_runs(study, target) for study in studies for target in chosen)
    bar = progress_bar(total, "reproduce", progress)
    try:
        for target in chosen:
            for study in studies:
                _RUNNERS[target](study, directory, bar)
    finally:
        bar.close()
    return write_report(directory)
