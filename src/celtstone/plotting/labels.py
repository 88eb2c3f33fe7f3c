"""Axis labels with units, and the words that name a run in titles and legends."""

from __future__ import annotations

import textwrap
from typing import TYPE_CHECKING

from celtstone.simulation.outcome import variable
from celtstone.simulation.schema import current_attributes

if TYPE_CHECKING:
    import xarray as xr


__all__ = ["axis_label", "run_label", "run_title", "title_characters", "wrapped_title"]


def axis_label(name: str) -> str:
    """``"spin ω·n [rad/s]"`` for a time series (``schema.VARIABLES``) or an outcome
    (``outcome.OUTCOMES``)."""
    return variable(name).axis_label()


def run_label(dataset: xr.Dataset) -> str:
    """Short legend entry: ``rolling`` or ``sliding f = 0.35, N = m g``."""
    attrs = current_attributes(dataset.attrs)  # a file written before the rename too
    if attrs["model"] != "sliding":
        return str(attrs["model"])
    normal = "N = m g" if attrs["friction_load"] == "static" else "dynamic N"
    return f"sliding f = {float(attrs['friction_coefficient']):g}, {normal}"


def run_title(dataset: xr.Dataset) -> str:
    """Title naming the body, the model and the start."""
    attrs = dataset.attrs
    return f"{attrs['body']}: {run_label(dataset)}; ω0 = {attrs['initial_omega']} rad/s"


# width of an average glyph of the default sans-serif font (DejaVu Sans: about 0.55 em
# for mixed text), with a margin for capitals and wide symbols
_GLYPH_EM = 0.62


def title_characters(width: float, size: str | float | None = None) -> int:
    """How many characters of a title fit ``width`` [inch] at font ``size`` (default:
    the figure title's, ``rcParams["figure.titlesize"]``); at least 20."""
    from matplotlib import rcParams
    from matplotlib.font_manager import FontProperties

    points = FontProperties(size=rcParams["figure.titlesize"] if size is None else size)
    return max(20, int(width * 72.0 / (_GLYPH_EM * points.get_size_in_points())))


def wrapped_title(text: str, width: float, size: str | float | None = None) -> str:
    """``text`` broken into lines that fit ``width`` [inch] at font ``size``
    (:func:`title_characters`), at word boundaries; a title longer than its figure is
    otherwise cut off at both edges."""
    characters = title_characters(width, size)
    return "\n".join(textwrap.fill(line, characters) for line in text.splitlines())
