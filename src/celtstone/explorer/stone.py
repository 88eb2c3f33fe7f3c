"""The stone in 3-D at one instant, for the explorer's time cursor.

The surface, attitude and position come from the 3-D viewer's scene
(``celtstone.visual.scene``: the body's mesh, R(q) and G's position); here they are only
seen from one fixed camera, shaded by a fixed light, and painted back to front as
Bokeh patches.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from celtstone.visual import scene

__all__ = ["StoneView", "stone_view"]

# the camera looks from the front right, above the plane (space axes, z up)
_VIEW = np.array([0.8, -1.0, 0.6]) / np.linalg.norm([0.8, -1.0, 0.6])
_RIGHT = np.cross([0.0, 0.0, 1.0], _VIEW)
_RIGHT /= np.linalg.norm(_RIGHT)
_UP = np.cross(_VIEW, _RIGHT)
_LIGHT = np.array([0.3, -0.5, 1.0]) / np.linalg.norm([0.3, -0.5, 1.0])
_ALONG, _AROUND = 28, 18  # mesh rows and columns: a smooth outline, few patches


@dataclass(frozen=True)
class StoneView:
    """The projected triangles of the stone at one time, back to front.

    ``xs``, ``ys`` are lists of three screen coordinates each [m]; ``shade`` is the
    Lambert brightness in [0, 1] of each triangle; ``track_x``, ``track_y`` the contact
    point's path on the plane so far, projected.
    """

    xs: list[list[float]]
    ys: list[list[float]]
    shade: list[float]
    track_x: list[float]
    track_y: list[float]


class StoneScene:
    """The mesh of one run's body, made once, placed at any sample."""

    def __init__(self, dataset: xr.Dataset) -> None:
        geometry = scene.body_geometry(dataset)
        self.mesh = scene.surface_mesh(geometry, along=_ALONG, around=_AROUND)
        self.rotations = scene.rotation_matrices(dataset["quaternion"].values)
        self.centres = scene.centre_positions(dataset)
        self.contacts = np.asarray(dataset["contact_position"].values, dtype=float)
        self.times = np.asarray(dataset["time"].values, dtype=float)

    def at(self, time: float) -> StoneView:
        """The view at the sample nearest ``time`` [s]."""
        index = int(np.clip(np.searchsorted(self.times, time), 0, len(self.times) - 1))
        points = scene.place(self.mesh.vertices, self.rotations[index], self.centres[index])
        corners = points[self.mesh.triangles]  # (m, 3, 3)
        normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        lengths = np.linalg.norm(normals, axis=1)
        normals = normals / np.where(lengths > 0, lengths, 1.0)[:, None]
        facing = normals @ _VIEW > 0.0  # outward triangles facing the camera
        depth = corners.mean(axis=1) @ _VIEW
        order = np.argsort(depth[facing])  # far first: painted over by the near ones
        seen = corners[facing][order]
        shade = np.clip(0.25 + 0.75 * (normals[facing][order] @ _LIGHT), 0.0, 1.0)
        track = self.contacts[: index + 1]
        track3 = np.column_stack([track, np.zeros(len(track))])
        return StoneView(
            xs=(seen @ _RIGHT).tolist(),
            ys=(seen @ _UP).tolist(),
            shade=shade.tolist(),
            track_x=(track3 @ _RIGHT).tolist(),
            track_y=(track3 @ _UP).tolist(),
        )


def stone_view(dataset: xr.Dataset, time: float) -> StoneView:
    """The stone of ``dataset`` at ``time`` [s] (see :class:`StoneScene`)."""
    return StoneScene(dataset).at(time)
