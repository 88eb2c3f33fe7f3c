"""One map per result field of a finished sweep, as PNG files (drawn by ``plotting.maps``).

Two grid axes give a heat map (first axis vertical, second horizontal); one axis a
curve; more axes a heat map over the first two at the first value of the others (the
title says which). A list of points gives a scatter over its first two parameters.
``status`` is drawn as categories; ``message`` is text and is not drawn.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from celtstone.errors import ParameterError
from celtstone.plotting.maps import plot_field_map
from celtstone.plotting.save import check_figure_target, save_figure
from celtstone.sweep.store import RESULT_FIELDS

if TYPE_CHECKING:
    import xarray as xr


__all__ = ["MAPPED_FIELDS", "map_paths", "write_maps"]

# every result field but the free-text message gets a map
MAPPED_FIELDS = tuple(name for name in RESULT_FIELDS if name != "message")


def map_paths(directory: str | Path, *, overwrite: bool = False) -> list[Path]:
    """The map files ``<field>.png`` in ``directory``, checked before a sweep runs: the
    directory is one (or does not exist yet) and no map file is in use unless
    ``overwrite``.

    Raises
    ------
    ParameterError
        naming ``maps``.
    """
    target = Path(directory)
    if target.exists() and not target.is_dir():
        raise ParameterError("maps", str(target), "a directory for the maps")
    paths = [target / f"{name}.png" for name in MAPPED_FIELDS]
    if target.is_dir():
        for path in paths:
            check_figure_target(path, "maps", overwrite=overwrite)
    return paths


def write_maps(
    dataset: xr.Dataset, directory: str | Path, *, overwrite: bool = False
) -> list[Path]:
    """Write ``<field>.png`` for each of ``MAPPED_FIELDS`` into ``directory``; return the
    paths. Existing maps are refused unless ``overwrite`` (:func:`map_paths`)."""
    paths = map_paths(directory, overwrite=overwrite)
    Path(directory).mkdir(parents=True, exist_ok=True)
    return [
        save_figure(plot_field_map(dataset, name), path, overwrite=overwrite)
        for name, path in zip(MAPPED_FIELDS, paths, strict=True)
    ]
