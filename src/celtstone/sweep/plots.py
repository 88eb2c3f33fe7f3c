"""Maps of a finished sweep's result fields, as PNG files (drawn by ``plotting.maps``).

By default the four fields that say what a sweep found: the first reversal time, the
number of reversals, the final spin and the energy lost; any other result field on
request (``fields``, ``celtstone sweep --map-fields``).

Two grid axes give a heat map (first axis vertical, second horizontal); one axis a
curve; more axes a heat map over the first two at the first value of the others (the
title says which). A list of points gives a scatter over its first two parameters.
``status`` is drawn as categories; ``message`` is text and is not drawn.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from celtstone.errors import ParameterError
from celtstone.plotting.maps import plot_field_map
from celtstone.plotting.save import check_figure_target, save_figure
from celtstone.sweep.store import RESULT_FIELDS

if TYPE_CHECKING:
    import xarray as xr


__all__ = ["DEFAULT_MAPPED_FIELDS", "MAPPED_FIELDS", "check_map_fields", "map_paths", "write_maps"]

# every result field but the free-text message can be drawn
MAPPED_FIELDS = tuple(name for name in RESULT_FIELDS if name != "message")
DEFAULT_MAPPED_FIELDS = ("first_reversal_time", "reversal_count", "spin_final", "energy_lost")
"""The maps written unless others are asked for."""
ALL_FIELDS = "all"


def check_map_fields(fields: str | Sequence[str] | None = None) -> tuple[str, ...]:
    """The fields to map: ``None`` gives :data:`DEFAULT_MAPPED_FIELDS`, ``"all"`` every
    one of :data:`MAPPED_FIELDS`; a comma-separated string or a sequence names them.

    Raises
    ------
    ParameterError
        naming ``map_fields``, for a name that is not a mapped field.
    """
    if fields is None:
        return DEFAULT_MAPPED_FIELDS
    names = fields.split(",") if isinstance(fields, str) else list(fields)
    names = [str(name).strip() for name in names]
    if names == [ALL_FIELDS]:
        return MAPPED_FIELDS
    allowed = f"{ALL_FIELDS!r} or result fields among " + ", ".join(MAPPED_FIELDS)
    if not names or any(name not in MAPPED_FIELDS for name in names):
        wrong = [name for name in names if name not in MAPPED_FIELDS] or fields
        raise ParameterError("map_fields", wrong[0] if len(wrong) == 1 else wrong, allowed)
    return tuple(dict.fromkeys(names))


def map_paths(
    directory: str | Path,
    *,
    overwrite: bool = False,
    fields: str | Sequence[str] | None = None,
) -> list[Path]:
    """The map files ``<field>.png`` in ``directory`` (``fields`` as :func:`check_map_fields`),
    checked before a sweep runs: the directory is one (or does not exist yet) and no map
    file is in use unless ``overwrite``.

    Raises
    ------
    ParameterError
        naming ``maps`` or ``map_fields``.
    """
    names = check_map_fields(fields)
    target = Path(directory)
    if target.exists() and not target.is_dir():
        raise ParameterError("maps", str(target), "a directory for the maps")
    paths = [target / f"{name}.png" for name in names]
    if target.is_dir():
        for path in paths:
            check_figure_target(path, "maps", overwrite=overwrite)
    return paths


def write_maps(
    dataset: xr.Dataset,
    directory: str | Path,
    *,
    overwrite: bool = False,
    fields: str | Sequence[str] | None = None,
) -> list[Path]:
    """Write ``<field>.png`` into ``directory`` for each field of ``fields`` (default
    :data:`DEFAULT_MAPPED_FIELDS`; ``"all"``: :data:`MAPPED_FIELDS`); return the paths.
    Existing maps are refused unless ``overwrite`` (:func:`map_paths`)."""
    names = check_map_fields(fields)
    paths = map_paths(directory, overwrite=overwrite, fields=names)
    Path(directory).mkdir(parents=True, exist_ok=True)
    return [
        save_figure(plot_field_map(dataset, name), path, overwrite=overwrite)
        for name, path in zip(names, paths, strict=True)
    ]
