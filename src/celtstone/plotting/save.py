"""Write a figure to PNG or SVG, whole or not at all, never over a file not asked to replace."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from celtstone.export import atomic_path, check_target

if TYPE_CHECKING:
    from matplotlib.figure import Figure


__all__ = ["FIGURE_FORMATS", "check_figure_target", "save_figure", "save_figure_formats"]

FIGURE_FORMATS = (".png", ".svg")
DPI = 150


def check_figure_target(
    path: str | Path, parameter: str = "out", *, overwrite: bool = False
) -> Path:
    """``path`` as a Path if it names a PNG or SVG file in an existing directory, not in use
    unless ``overwrite`` (``export.check_target``)."""
    return check_target(path, FIGURE_FORMATS, parameter, overwrite=overwrite)


def save_figure(figure: Figure, path: str | Path, *, overwrite: bool = False) -> Path:
    """Save ``figure`` to ``path`` (.png at 150 dpi, or .svg) via a temporary file.

    An existing file is refused unless ``overwrite``; a failed write raises
    ``OutputError`` and leaves nothing behind.
    """
    target = check_figure_target(path, overwrite=overwrite)
    with atomic_path(target, overwrite=overwrite) as temporary:
        figure.savefig(temporary, format=target.suffix.lower()[1:], dpi=DPI)
    return target


def save_figure_formats(
    figure: Figure, directory: Path, stem: str, *, overwrite: bool = False
) -> list[str]:
    """Save ``figure`` as ``stem.png`` and ``stem.svg`` in ``directory``; relative names."""
    return [
        str(
            save_figure(figure, directory / f"{stem}{suffix}", overwrite=overwrite).relative_to(
                directory
            )
        )
        for suffix in FIGURE_FORMATS
    ]
