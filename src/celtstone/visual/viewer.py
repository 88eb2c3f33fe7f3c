"""One self-contained HTML page for a run: 3-D body, time slider, play, linked plots.

The page is the template ``templates/viewer.html`` with the run's data inlined
as JSON and a hand-written 2-D canvas renderer inlined as JavaScript: it loads
nothing from the network and opens from the file system (see docs/decisions.md).
"""

from __future__ import annotations

import html
import json
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from celtstone.files.export import atomic_path, check_target
from celtstone.simulation.schema import VARIABLES
from celtstone.visual import scene
from celtstone.visual.frames import FPS_MAX, PAGE_FRAME_LIMIT, PLOT_BUCKETS, envelope, plan_frames
from celtstone.visual.runs import check_run, default_label

if TYPE_CHECKING:
    import xarray as xr


__all__ = ["PAGE_SIZE_LIMIT", "PageInfo", "check_page_target", "page_data", "write_viewer"]

# The page of any run stays below this size [bytes]. Worst case of the caps, at most
# 13 characters a number: 3000 frames x 14 numbers (0.55 MB) + 4 plots x 2000 points
# x 2 (0.21 MB) + the mesh (0.11 MB) + the template (16 kB) = 0.88 MB.
PAGE_SIZE_LIMIT = 1_000_000
"""The interactive page of any run stays below this size [bytes]."""
_DATA_MARK = "/*__CELTSTONE_DATA__*/"
_TITLE_MARK = "__CELTSTONE_TITLE__"
_DIGITS = 6  # significant digits of the inlined numbers

# the linked plots against time; their labels and units are those of schema.VARIABLES
PLOTS = ("spin", "tilt", "energy", "slip_speed")


@dataclass(frozen=True)
class PageInfo:
    """What was written.

    Parameters
    ----------
    path : pathlib.Path
        The page.
    frames : int
        Number of animation frames.
    plot_points : int
        Most points in a plotted series.
    bytes : int
        The file's size [bytes].
    """

    path: Path
    frames: int
    plot_points: int
    bytes: int


def check_page_target(path: str | Path, *, overwrite: bool = False) -> Path:
    """``path`` if it ends in .html, its directory exists and it is not in use (unless
    ``overwrite``; never a directory), else ParameterError."""
    return check_target(path, (".html", ".htm"), overwrite=overwrite)


class _Numbers:
    """A float array that serialises as a compact JSON list (``_DIGITS`` significant digits)."""

    def __init__(self, values: Any) -> None:
        self.values = np.asarray(values, dtype=float).ravel()

    def json(self) -> str:
        parts = (f"{v:.{_DIGITS}g}" if math.isfinite(v) else "null" for v in self.values)
        return "[" + ",".join(parts) + "]"


def _dumps(value: Any) -> str:
    """JSON of nested dicts/lists with :class:`_Numbers` leaves."""
    if isinstance(value, _Numbers):
        return value.json()
    if isinstance(value, dict):
        return "{" + ",".join(f"{json.dumps(k)}:{_dumps(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list | tuple):
        return "[" + ",".join(_dumps(v) for v in value) + "]"
    return json.dumps(value)


def page_data(dataset: xr.Dataset, label: str | None = None) -> dict[str, Any]:
    """The data the page inlines: mesh, marks, frames, contact track and plot series.

    Frames: at most 30 per simulated second and ``PAGE_FRAME_LIMIT`` in all;
    plots: at most 2 × ``PLOT_BUCKETS`` points per series (``frames.envelope``).
    Lengths in m, times in s, angles in the units the plots name.
    """
    dataset = check_run(dataset)
    geometry = scene.body_geometry(dataset)
    mesh = scene.surface_mesh(geometry)
    marks = scene.axis_marks(geometry)
    times = np.asarray(dataset["time"].values, dtype=float)
    plan = plan_frames(times, max_frames=PAGE_FRAME_LIMIT, speed=1.0, fps=FPS_MAX)
    i = plan.indices
    rotations = scene.rotation_matrices(dataset["quaternion"].values)
    centres = scene.centre_positions(dataset)
    contacts = np.asarray(dataset["contact_position"].values, dtype=float)
    quaternions = np.asarray(dataset["quaternion"].values, dtype=float)
    quaternions = quaternions / np.linalg.norm(quaternions, axis=1, keepdims=True)
    middle, reach, top = scene.extent(geometry, mesh, rotations[i], centres[i], contacts)
    frames: dict[str, Any] = {
        "time": _Numbers(times[i]),
        "quaternion": _Numbers(quaternions[i]),
        "centre": _Numbers(centres[i]),
        "contact": _Numbers(contacts[i]),
    }
    plots = []
    for name in PLOTS:
        variable = VARIABLES[name]
        text, unit = variable.text or variable.long_name, variable.plot_unit or variable.unit
        values = np.asarray(dataset[name].values, dtype=float) * variable.plot_scale
        frames[name] = _Numbers(values[i])
        t, v = envelope(times, values, PLOT_BUCKETS)
        plots.append(
            {"name": name, "label": text, "unit": unit, "time": _Numbers(t), "value": _Numbers(v)}
        )
    return {
        "label": label if label is not None else default_label(dataset),
        "title": str(dataset.attrs.get("title", "celtstone run")),
        "model": str(dataset.attrs.get("model", "")),
        "misalignment_deg": math.degrees(geometry.misalignment_angle),
        "mesh": {
            "vertices": _Numbers(mesh.vertices),
            "triangles": [int(k) for k in mesh.triangles.ravel()],
        },
        "marks": {name: _Numbers(points) for name, points in marks.items()},
        "frames": frames,
        "plots": plots,
        "extent": {"centre": _Numbers(middle), "reach": reach, "top": top},
        "limits": {"frames": PAGE_FRAME_LIMIT, "plot_points": 2 * PLOT_BUCKETS},
    }


def _template() -> str:
    return (
        resources.files("celtstone.visual")
        .joinpath("templates/viewer.html")
        .read_text(encoding="utf-8")
    )


def render_page(dataset: xr.Dataset, label: str | None = None) -> tuple[str, dict[str, Any]]:
    """The page's HTML text and the data it inlines."""
    data = page_data(dataset, label)
    # JSON escapes for <, >, &: the data can never end or open an element early
    payload = _dumps(data).replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")
    # split the template at its markers first and fill in the pieces: neither the title
    # nor the data is ever searched for a marker, so no value can be read as template
    before, mark, after = _template().partition(_DATA_MARK)
    if not mark or _DATA_MARK in after:
        raise RuntimeError("the viewer template must hold the data marker exactly once")
    title = html.escape(data["label"])
    page = before.replace(_TITLE_MARK, title) + payload + after.replace(_TITLE_MARK, title)
    return page, data


def write_viewer(
    dataset: xr.Dataset, path: str | Path, *, label: str | None = None, overwrite: bool = False
) -> PageInfo:
    """Write the interactive page of a run to ``path`` (.html), whole or not at all.

    Parameters
    ----------
    dataset : xarray.Dataset
        The run (``Trajectory.dataset`` or a file read by :func:`load_run`).
    path : str or pathlib.Path
        Output file, .html.
    label : str, optional
        The title; default the model and body of the run.
    overwrite : bool, optional
        Replace ``path`` if it is a file; a directory is always refused.

    Returns
    -------
    PageInfo
        What was written; a failed write raises ``OutputError`` and leaves nothing.
    """
    target = check_page_target(path, overwrite=overwrite)
    page, data = render_page(dataset, label)
    with atomic_path(target, overwrite=overwrite) as temporary:
        temporary.write_text(page, encoding="utf-8")
    return PageInfo(
        path=target,
        frames=int(data["frames"]["time"].values.size),
        plot_points=max(int(p["time"].values.size) for p in data["plots"]),
        bytes=target.stat().st_size,
    )
