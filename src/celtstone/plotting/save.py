"""Write a figure to PNG or SVG, whole or not at all, never over a file not asked to replace."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from celtstone.files.export import atomic_path, check_target
from celtstone.files.ownership import figure_metadata

if TYPE_CHECKING:
    from matplotlib.figure import Figure


__all__ = ["FIGURE_FORMATS", "check_figure_target", "save_figure", "save_figure_formats"]

FIGURE_FORMATS = (".png", ".svg")
"""The suffixes a figure can be saved to."""
DPI = 150


def check_figure_target(
    path: str | Path, parameter: str = "out", *, overwrite: bool = False
) -> Path:
    """``path`` as a Path if it names a PNG or SVG file in an existing directory, not in use
    unless ``overwrite`` (``export.check_target``)."""
    return check_target(path, FIGURE_FORMATS, parameter, overwrite=overwrite)


def save_figure(figure: Figure, path: str | Path, *, overwrite: bool = False) -> Path:
    """Save ``figure`` to ``path`` (.png at 150 dpi, or .svg) via a temporary file.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
        The figure.
    path : str or pathlib.Path
        The PNG or SVG file (:data:`FIGURE_FORMATS`).
    overwrite : bool, optional
        Whether an existing file may be replaced; a failed write raises ``OutputError``
        and leaves nothing.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    target = check_figure_target(path, overwrite=overwrite)
    with atomic_path(target, overwrite=overwrite) as temporary:
        suffix = target.suffix.lower()[1:]  # marked: --overwrite may replace it later
        figure.savefig(temporary, format=suffix, dpi=DPI, metadata=figure_metadata(suffix))
    return target


def save_figure_formats(
    figure: Figure, directory: Path, stem: str, *, overwrite: bool = False
) -> list[str]:
    """Save ``figure`` as ``stem.png`` and ``stem.svg`` in ``directory``.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
        The figure.
    directory : pathlib.Path
        An existing directory.
    stem : str
        The files' name without suffix.
    overwrite : bool, optional
        Whether existing files may be replaced (they are refused otherwise).

    Returns
    -------
    list of str
        The files' names, relative to ``directory``.
    """
    return [
        str(
            save_figure(figure, directory / f"{stem}{suffix}", overwrite=overwrite).relative_to(
                directory
            )
        )
        for suffix in FIGURE_FORMATS
    ]
