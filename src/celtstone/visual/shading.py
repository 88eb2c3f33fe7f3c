"""The body's faces in a video frame: flat-shaded triangles drawn in one batch.

Imported when a video is drawn (it imports matplotlib).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.artist import Artist
from mpl_toolkits.mplot3d import proj3d

__all__ = ["FlatShadedTriangles"]


class FlatShadedTriangles(Artist):
    """Triangles in space, each in one colour, on a 3-D axes whose camera does not move.

    Agg's Gouraud triangles (one call for all faces, each grown by half a pixel so that
    no seam shows between neighbours) with the three corners of a face in its colour:
    what a ``Poly3DCollection`` draws, without building a path per face and stroking
    its edge every frame to hide the seams. The faces are projected by the axes'
    projection matrix (set when the figure is drawn) and drawn farthest first, as
    mplot3d sorts a collection's faces.

    Parameters
    ----------
    ax : mpl_toolkits.mplot3d.axes3d.Axes3D
        The axes it is drawn in.
    zorder : float
        Its place among the axes' artists.
    """

    def __init__(self, ax: Any, zorder: float) -> None:
        super().__init__()
        self.ax = ax
        self.points = np.zeros((0, 3, 2))  # projected corners, (faces, 3, 2)
        self.colours = np.zeros((0, 3, 4))  # RGBA of each corner, (faces, 3, 4)
        self.set_zorder(zorder)
        ax.add_artist(self)
        self.set_transform(ax.transData)
        self.set_clip_path(ax.patch)

    def set_faces(self, vertices: np.ndarray, triangles: np.ndarray, colours: np.ndarray) -> None:
        """Show faces ``triangles`` (k, 3), indices into ``vertices`` (n, 3) [m] in space,
        in RGB ``colours`` (k, 3) in [0, 1]."""
        x, y, depth = proj3d.proj_transform(*vertices.T, self.ax.M)
        order = np.argsort(depth[triangles].mean(axis=1))[::-1]
        corners = triangles[order]
        self.points = np.stack([x[corners], y[corners]], axis=-1)
        rgba = np.column_stack([colours[order], np.ones(order.size)])
        self.colours = np.repeat(rgba[:, None, :], 3, axis=1)
        self.stale = True

    def draw(self, renderer: Any) -> None:
        """Draw the faces (nothing before :meth:`set_faces`)."""
        if not self.get_visible() or self.points.shape[0] == 0:
            return
        gc = renderer.new_gc()
        if self.get_clip_on():
            gc.set_clip_rectangle(self.get_clip_box())
            gc.set_clip_path(self.get_clip_path())
        renderer.draw_gouraud_triangles(
            gc, self.points, self.colours, self.get_transform().frozen()
        )
        gc.restore()
