"""A fit's directory: ``summary.json``, ``fit.png``/``fit.svg`` and ``run.nc``, written
whole or not at all; with a comparison of models, each other model's figure beside them
(``fit-<model>.png``/``.svg``, :func:`comparison_figures`).

The files are written into a staging directory beside the target
(``.NAME.<pid>.<random>.part``, ``export.temporary_directory``) with the manifest of
``celtstone.files.ownership`` (the files with their hashes), and the directory is renamed into
place. An existing directory is replaced only with ``overwrite`` and only if its manifest
proves it a fit's and it holds nothing else, unchanged (``ownership.check_replaceable``):
a user's file put into a former fit, a ``summary.json`` copied elsewhere, or the fit's
own input data keep the directory from being replaced.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from celtstone.errors import ParameterError
from celtstone.files.export import (
    OVERWRITE_HINT,
    replace_directory,
    temporary_directory,
    write,
    write_json,
)
from celtstone.files.ownership import (
    MANIFEST,
    check_replaceable,
    new_manifest,
    record_files,
    write_manifest,
)
from celtstone.fitting.nuisance import sensor_reading
from celtstone.fitting.result import FitResult
from celtstone.fitting.series import SERIES

__all__ = ["FILES", "check_fit_target", "comparison_figures", "write_fit"]

FILES = ("summary.json", "fit.png", "fit.svg", "run.nc", MANIFEST)


_COMMAND = "fit"
_FIGURE = "fit"  # the best model's figure: fit.png, fit.svg


def comparison_figures(ranking: Iterable[str]) -> dict[str, str]:
    """Each compared model's figure (PNG) in the fit's directory, best first: the best
    model's is ``fit.png``, another's ``fit-<its label in lower case, words joined by
    "-">.png`` ("sliding, N = m g" -> ``fit-sliding-n-m-g.png``).

    Parameters
    ----------
    ranking : iterable of str
        The models' labels, the best first.

    Returns
    -------
    dict of str to str
        Label -> the figure's file name.
    """
    names = {}
    for index, label in enumerate(ranking):
        slug = "-".join(re.findall(r"[a-z0-9]+", label.lower())) or str(index)
        names[label] = f"{_FIGURE}.png" if index == 0 else f"{_FIGURE}-{slug}.png"
    return names


def check_fit_target(
    out: str | Path, *, overwrite: bool = False, inputs: Iterable[str | Path] = ()
) -> Path:
    """``out`` as a Path if a fit may be written there: a new directory in an existing one,
    or with ``overwrite`` a fit's directory holding only the fit's files, unchanged, and
    none of ``inputs`` (``ownership.check_replaceable``). Call it before fitting.

    Raises
    ------
    ParameterError
        naming ``out`` otherwise.
    """
    target = Path(out)
    if str(out) == "" or target.name in ("", ".", ".."):
        raise ParameterError("out", str(out), "a directory name", "the path names no directory")
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise ParameterError("out", str(out), "a directory in an existing directory")
    if os.path.lexists(target):
        if not overwrite:
            raise ParameterError(
                "out", str(out), "a directory that does not exist yet", OVERWRITE_HINT
            )
        check_replaceable(target, _COMMAND, inputs=inputs)
    return target


def _figure(result: FitResult, staging: Path, stem: str = _FIGURE, model: str = "") -> None:
    from celtstone.plotting import FitPanel, FittedValue, plot_fit, save_figure_formats

    trajectory = result.trajectory.samples
    values_used = result.problem.values(result.values)
    panels = []
    for name, measured in result.problem.record.series.items():
        series = SERIES[name]
        # with the fitted (or held) gyroscope bias and scale, as the residuals compare it
        fitted = sensor_reading(name, series.model(trajectory), values_used)
        if series.is_angle_offset_free:  # drawn with the offset the residuals remove
            fitted = fitted - float((fitted - measured).mean())
        unit = series.plot_unit or series.unit
        scale = series.plot_scale
        panels.append(FitPanel(f"{name} [{unit}]", measured * scale, fitted * scale))
    values = [
        FittedValue(free.name, float(value), float(error), free.unit)
        for free, value, error in zip(
            result.problem.free, result.values, result.standard_errors, strict=True
        )
    ]
    title = f"{result.problem.body.name}, {model or result.problem.model_name} model"
    figure = plot_fit(result.problem.record.times, panels, title, values)
    save_figure_formats(figure, staging, stem)


def write_fit(
    result: FitResult,
    out: str | Path,
    *,
    overwrite: bool = False,
    inputs: Iterable[str | Path] = (),
    summary: Mapping[str, Any] | None = None,
    compared: Mapping[str, FitResult] | None = None,
) -> Path:
    """Write the fit's files (``FILES``) and their manifest into the directory ``out``,
    whole or not at all.

    Parameters
    ----------
    result : FitResult
        The fit.
    out : str or pathlib.Path
        The directory written.
    overwrite : bool, optional
        Whether a fit's directory there may be replaced (:func:`check_fit_target`).
    inputs : iterable of path, optional
        Files the fit read, besides its record's own file: never inside ``out``.
    summary : mapping, optional
        What ``summary.json`` holds (default ``result.summary()``; the CLI adds the
        comparison of models).
    compared : mapping of str to FitResult, optional
        Model label -> its fit, the best first (``result`` itself): each other model's
        figure is written too, named by :func:`comparison_figures`.

    Returns
    -------
    pathlib.Path
        The directory written.
    """
    read = [*inputs]
    if Path(result.problem.record.source).is_file():
        read.append(result.problem.record.source)
    target = check_fit_target(out, overwrite=overwrite, inputs=read)
    with temporary_directory(target) as staging:
        write_json(dict(result.summary() if summary is None else summary), staging / "summary.json")
        _figure(result, staging)
        names = comparison_figures(compared or {})
        for label, other in (compared or {}).items():
            if other is not result:
                _figure(other, staging, names[label].removesuffix(".png"), label)
        if result.trajectory.samples.values("time").size >= 2:
            write(result.trajectory.dataset, staging / "run.nc")
        manifest = new_manifest(_COMMAND)
        record_files(manifest, staging, sorted(p for p in staging.iterdir() if p.is_file()))
        write_manifest(staging, manifest)
        if os.path.lexists(target):  # checked again: it may have changed during the fit
            check_fit_target(target, overwrite=overwrite, inputs=read)
        replace_directory(staging, target)
    return target
