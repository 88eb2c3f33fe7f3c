"""A fit's directory: ``summary.json``, ``fit.png``/``fit.svg`` and ``run.nc``, written
whole or not at all.

The files are written into a staging directory beside the target
(``.NAME.<pid>.<random>.part``, ``export.temporary_directory``) and the directory is
renamed into place. An existing directory is replaced only with ``overwrite`` and only if
its own ``summary.json`` says it is a fit's (``format`` ``celtstone-fit-1``): a thesis
directory given as ``--out`` is never touched.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from celtstone.errors import ParameterError
from celtstone.export import (
    OVERWRITE_HINT,
    replace_directory,
    temporary_directory,
    write,
    write_json,
)
from celtstone.fitting.result import FORMAT, FitResult
from celtstone.fitting.series import SERIES

__all__ = ["FILES", "check_fit_target", "write_fit"]

FILES = ("summary.json", "fit.png", "fit.svg", "run.nc")


def _is_fit_directory(path: Path) -> bool:
    try:
        summary = json.loads((path / "summary.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return isinstance(summary, dict) and summary.get("format") == FORMAT


def check_fit_target(out: str | Path, *, overwrite: bool = False) -> Path:
    """``out`` as a Path if a fit may be written there: a new directory in an existing one,
    or with ``overwrite`` a fit's directory. Call it before fitting.

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
        if not (target.is_dir() and _is_fit_directory(target)):
            raise ParameterError(
                "out",
                str(out),
                "a directory written by `celtstone fit` (its summary.json says so)",
                "--overwrite replaces only a fit's directory",
            )
    return target


def _figure(result: FitResult, staging: Path) -> None:
    from celtstone.plotting import FitPanel, plot_fit, save_figure_formats

    trajectory = result.trajectory.samples
    panels = []
    for name, measured in result.problem.record.series.items():
        series = SERIES[name]
        fitted = series.model(trajectory)
        if series.is_angle_offset_free:  # drawn with the offset the residuals remove
            fitted = fitted - float((fitted - measured).mean())
        unit = series.plot_unit or series.unit
        scale = series.plot_scale
        panels.append(FitPanel(f"{name} [{unit}]", measured * scale, fitted * scale))
    names = ", ".join(f"{n} = {v:.4g}" for n, v in zip(result.names, result.values, strict=True))
    title = f"{result.problem.body.name}, {result.problem.model_name}: {names}"
    save_figure_formats(plot_fit(result.problem.record.times, panels, title), staging, "fit")


def write_fit(result: FitResult, out: str | Path, *, overwrite: bool = False) -> Path:
    """Write the fit's files (``FILES``) into the directory ``out``, whole or not at all."""
    target = check_fit_target(out, overwrite=overwrite)
    with temporary_directory(target) as staging:
        write_json(result.summary(), staging / "summary.json")
        _figure(result, staging)
        if result.trajectory.samples.values("time").size >= 2:
            write(result.trajectory.dataset, staging / "run.nc")
        _replace(staging, target, overwrite)
    return target


def _replace(staging: Path, target: Path, overwrite: bool) -> None:
    """Rename ``staging`` to ``target`` (``export.replace_directory``); an existing
    directory is checked again to be a fit's before it is replaced."""
    if os.path.lexists(target):
        check_fit_target(target, overwrite=overwrite)
    replace_directory(staging, target)
