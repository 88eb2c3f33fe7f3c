"""One map per result field of a finished sweep, as PNG files (drawn by ``plotting.maps``).

Two grid axes give a heat map (first axis vertical, second horizontal); one axis a
curve; more axes a heat map over the first two at the first value of the others (the
title says which). A list of points gives a scatter over its first two parameters.
``status`` is drawn as categories; ``message`` is text and is not drawn.
"""

from __future__ import annotations

from pathlib import Path

import xarray as xr

from celtstone.plotting.maps import plot_field_map
from celtstone.plotting.save import save_figure
from celtstone.sweep.store import RESULT_FIELDS

__all__ = ["MAPPED_FIELDS", "write_maps"]

# every result field but the free-text message gets a map
MAPPED_FIELDS = tuple(name for name in RESULT_FIELDS if name != "message")


def write_maps(dataset: xr.Dataset, directory: str | Path) -> list[Path]:
    """Write ``<field>.png`` for each of ``MAPPED_FIELDS`` into ``directory``; return the paths."""
    target = Path(directory)
    target.mkdir(parents=True, exist_ok=True)
    return [
        save_figure(plot_field_map(dataset, name), target / f"{name}.png") for name in MAPPED_FIELDS
    ]
