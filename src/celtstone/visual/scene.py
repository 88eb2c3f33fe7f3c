"""Pure geometry of the 3-D scene: the body's surface in space at each sample.

Everything here is plain NumPy on arrays in SI units, so the video (matplotlib)
and the page (JavaScript) draw the same triangles. The run's shape is rebuilt from
its attributes through the shape registry (``bodies.SHAPES``); a closed shape is
meshed through the contact kernel (each vertex the surface point of one outward
normal), so a new shape is drawn with no code here; the paraboloid, an open cap, is
meshed from its formula up to the run's highest contact.

Frames
------
Body points are given relative to the centre of mass G in body axes (axis 1
long, 3 up at rest). A body point p is at ``G(t) + R(q(t)) p`` in space, with
G(t) = (com_position, com_height) and R(q) the rotation of the attitude
quaternion q = (w, x, y, z) (body to space, as in ``kernels.vector.rotate``).
The plane is z = 0.
"""

from __future__ import annotations

import ast
import json
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from celtstone.bodies import SHAPES, STORED_SHAPES, Shape, shape_from_table
from celtstone.errors import ParameterError
from celtstone.kernels.geometry import contact as contact_kernel
from celtstone.kernels.layout import parameter_record

if TYPE_CHECKING:
    import xarray as xr


__all__ = [
    "BodyGeometry",
    "Mesh",
    "axis_marks",
    "body_geometry",
    "centre_positions",
    "extent",
    "place",
    "rotation_matrices",
    "support_points",
    "surface_mesh",
]

# a paraboloid cap is drawn up to at least this multiple of l above its rest contact
CAP_HEIGHT_FACTOR = 2.0
# and at least this multiple of the highest contact point of the run
CAP_MARGIN = 1.5


@dataclass(frozen=True)
class BodyGeometry:
    """Shape and inertia of a run's body, read back from a dataset's attributes.

    Parameters
    ----------
    kind : the shape's kind (a key of ``bodies.SHAPES``)
    parameters : the four shape numbers the run recorded [m] (``kernel_parameters``):
        (a, b, c, h) for the ellipsoid, (ρ1, ρ2, l, 0) for the paraboloid cap
        z = x²/(2ρ1) + y²/(2ρ2) (G a height l above the rest contact)
    inertia : central inertia tensor in body axes [kg m²], shape (3, 3)
    cap_height : height of the drawn paraboloid cap above its rest contact [m]
        (the cap is unbounded; unused for a closed shape)
    kernel_params : the kernels' parameter record of a closed shape, drawn through the
        contact kernel; None for the paraboloid cap
    """

    kind: str
    parameters: tuple[float, float, float, float]
    inertia: tuple[tuple[float, ...], ...]
    cap_height: float = 0.0
    kernel_params: np.record | None = field(default=None, compare=False)

    @property
    def half_length(self) -> float:
        """Half the extent of the drawn body along axis 1 [m]."""
        if self.kernel_params is not None:
            return float(support_points(self, np.array([[1.0, 0.0, 0.0]]))[0, 0])
        return math.sqrt(2.0 * self.parameters[0] * self.cap_height)

    @property
    def half_extents(self) -> np.ndarray:
        """Half the extent of a closed body along each body axis [m], shape (3,)."""
        axes = np.concatenate([np.eye(3), -np.eye(3)])
        points = support_points(self, axes)
        return 0.5 * (np.diag(points[:3]) - np.diag(points[3:]))

    @property
    def principal_axis(self) -> np.ndarray:
        """Unit vector of the horizontal principal inertia axis nearest body axis 1, shape (3,)."""
        _, vectors = np.linalg.eigh(np.asarray(self.inertia)[:2, :2])
        axis = vectors[:, np.argmax(np.abs(vectors[0]))]
        axis = axis if axis[0] > 0 else -axis
        return np.array([axis[0], axis[1], 0.0])

    @property
    def misalignment_angle(self) -> float:
        """Angle δ from body axis 1 to the principal axis [rad]."""
        axis = self.principal_axis
        return float(math.atan2(axis[1], axis[0]))


def _attr_numbers(attrs: dict, name: str) -> list:
    try:
        return ast.literal_eval(str(attrs[name]))
    except (KeyError, ValueError, SyntaxError):
        raise ParameterError(
            "run", attrs.get("title", "?"), f"a celtstone run file with attribute {name!r}"
        ) from None


def _cap_contacts(parameters: tuple[float, ...], n: np.ndarray) -> np.ndarray:
    """Contact points of the paraboloid cap relative to G in body axes [m] for upward
    verticals ``n`` (k, 3): (x, y) = (-ρ1 n1/n3, -ρ2 n2/n3), z = x²/(2ρ1) + y²/(2ρ2) - l."""
    n = np.atleast_2d(np.asarray(n, dtype=float))
    rho1, rho2, height, _ = parameters
    x = -rho1 * n[:, 0] / n[:, 2]
    y = -rho2 * n[:, 1] / n[:, 2]
    return np.stack([x, y, 0.5 * x * x / rho1 + 0.5 * y * y / rho2 - height], axis=1)


def _legacy_table(kind: str, parameters: tuple[float, ...], attrs: dict) -> dict[str, object]:
    """The ``[shape]`` table of a run file written before shapes recorded theirs
    (``body_shape_table``), from its four numbers and per-kind attributes."""
    p0, p1, p2, p3 = parameters
    if kind == "paraboloid":
        return {"kind": kind, "radii_of_curvature": [p0, p1], "com_height": p2}
    if kind == "implicit_polynomial":
        try:
            terms = json.loads(str(attrs["body_shape_terms"]))
        except (KeyError, ValueError):
            raise ParameterError(
                "run", attrs.get("title", "?"), "a run file with attribute 'body_shape_table'"
            ) from None
        return {"kind": kind, "terms": terms, "com_offset": p3}
    table: dict[str, object] = {"kind": kind, "semi_axes": [p0, p1, p2], "com_offset": p3}
    if kind == "superellipsoid":
        table["exponent"] = float(attrs.get("body_shape_exponent", 2.0))
    return table


def _run_shape(kind: str, parameters: tuple[float, ...], attrs: dict) -> Shape:
    """The run's shape, rebuilt (and validated) from its recorded table."""
    title = str(attrs.get("title", "the run file"))
    if "body_shape_table" in attrs:
        try:
            table = json.loads(str(attrs["body_shape_table"]))
        except ValueError:
            raise ParameterError(
                "run", title, "a run file whose attribute 'body_shape_table' is JSON"
            ) from None
    else:
        table = _legacy_table(kind, parameters, attrs)
    return shape_from_table(table, file=f"{title} (attribute body_shape_table)")


def support_points(geometry: BodyGeometry, normals: np.ndarray) -> np.ndarray:
    """Surface points (relative to G, body axes) [m] with outward normals ``normals``, (k, 3).

    The contact kernel's point for the upward vertical n = -ν (paper eq. 3); the
    normals need not be unit vectors.
    """
    params = geometry.kernel_params
    still = (0.0, 0.0, 0.0)
    points = []
    normals = np.atleast_2d(np.asarray(normals, dtype=float))
    for normal in normals / np.linalg.norm(normals, axis=1, keepdims=True):
        vertical = (-float(normal[0]), -float(normal[1]), -float(normal[2]))
        point, _ = contact_kernel(vertical, still, params)
        points.append(point)
    return np.array(points, dtype=float)


def body_geometry(dataset: xr.Dataset) -> BodyGeometry:
    """The body's shape and inertia from a run's attributes.

    A paraboloid cap is drawn up to max(2 l, 1.5 × the highest contact point of
    the run) above its rest contact, so every contact of the run lies on it.
    """
    attrs = dict(dataset.attrs)
    kind = str(attrs.get("body_shape", ""))
    if kind not in SHAPES:
        raise ParameterError("run", kind, "a run of a body of shape " + ", ".join(STORED_SHAPES))
    if not SHAPES[kind].stored:
        raise ParameterError(
            "run",
            str(attrs.get("body_shape_function", kind)),
            "a run of a body whose shape is stored in its file",
            "a shape given by a Python function cannot be redrawn from the file; "
            "write it as an implicit polynomial to animate it",
        )
    parameters = tuple(float(v) for v in _attr_numbers(attrs, "body_shape_parameters"))
    inertia = tuple(tuple(float(v) for v in row) for row in _attr_numbers(attrs, "body_inertia"))
    shape = _run_shape(kind, parameters, attrs)
    if shape.closed:
        params = parameter_record(**shape.kernel_fields())
        return BodyGeometry(kind, parameters, inertia, kernel_params=params)  # type: ignore[arg-type]
    height = parameters[2]  # the paraboloid cap, drawn up to the run's highest contact
    contacts = _cap_contacts(parameters, np.asarray(dataset["n"].values))
    highest = float(np.max(contacts[:, 2] + height)) if contacts.size else 0.0
    cap_height = max(CAP_HEIGHT_FACTOR * height, CAP_MARGIN * highest)
    return BodyGeometry(kind, parameters, inertia, cap_height)  # type: ignore[arg-type]


@dataclass(frozen=True)
class Mesh:
    """A triangulated closed surface: ``vertices`` (k, 3) [m] and ``triangles`` (m, 3) indices."""

    vertices: np.ndarray
    triangles: np.ndarray

    @property
    def max_edge_length(self) -> float:
        """Longest triangle edge [m]."""
        corners = self.vertices[self.triangles]
        edges = corners - np.roll(corners, 1, axis=1)
        return float(np.max(np.linalg.norm(edges, axis=2)))


def _grid_triangles(rows: int, columns: int, offset: int = 0) -> np.ndarray:
    """Triangles of a grid of rows × columns vertices, periodic in the columns."""
    r, c = np.meshgrid(np.arange(rows - 1), np.arange(columns), indexing="ij")
    a = offset + r * columns + c
    b = offset + r * columns + (c + 1) % columns
    lower = np.stack([a, b, a + columns], axis=-1).reshape(-1, 3)
    upper = np.stack([b, b + columns, a + columns], axis=-1).reshape(-1, 3)
    return np.concatenate([lower, upper])


def _fan(centre: int, ring: np.ndarray, reverse: bool) -> np.ndarray:
    nxt = np.roll(ring, -1)
    fan = np.stack([np.full_like(ring, centre), ring, nxt], axis=1)
    return fan[:, ::-1] if reverse else fan


def surface_mesh(geometry: BodyGeometry, along: int = 48, around: int = 32) -> Mesh:
    """Closed triangulated surface of the body, vertices relative to G in body axes [m].

    Every vertex lies exactly on the body surface (the paraboloid cap is closed by
    a flat lid at its ``cap_height``). Triangles are wound counter-clockwise seen
    from outside. ``along`` rings along axis 1 (closed shapes) or from the rest contact
    to the rim (paraboloid); ``around`` vertices per ring.
    """
    phi = np.linspace(0.0, 2.0 * np.pi, around, endpoint=False)
    if geometry.kernel_params is not None:
        # poles on ±axis 1; normals ∝ (cos θ/a, sin θ cos φ/b, sin θ sin φ/c) with a, b, c
        # the half extents: for an ellipsoid the vertices are its (θ, φ) grid, and any
        # closed shape is sampled evenly along its length rather than by curvature
        theta = np.linspace(0.0, np.pi, along + 1)[1:-1]
        a, b, c = geometry.half_extents
        ring_normals = np.stack(
            [
                np.cos(theta)[:, None] * np.ones_like(phi) / a,
                np.sin(theta)[:, None] * np.cos(phi) / b,
                np.sin(theta)[:, None] * np.sin(phi) / c,
            ],
            axis=-1,
        ).reshape(-1, 3)
        rings = support_points(geometry, ring_normals)
        poles = support_points(geometry, np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]))
        vertices = np.concatenate([rings, poles])
        body = _grid_triangles(len(theta), around)
        first = np.arange(around)
        last = (len(theta) - 1) * around + np.arange(around)
        caps = [_fan(len(rings), first, reverse=True), _fan(len(rings) + 1, last, reverse=False)]
        triangles = np.concatenate([body, *caps])
    else:
        rho1, rho2, height, _ = geometry.parameters
        top = geometry.cap_height
        s = np.linspace(0.0, 1.0, along + 1)[1:]
        ring_x = math.sqrt(2.0 * rho1 * top) * s[:, None] * np.cos(phi)
        ring_y = math.sqrt(2.0 * rho2 * top) * s[:, None] * np.sin(phi)
        ring_z = top * (s * s)[:, None] * np.ones_like(phi) - height
        rings = np.stack([ring_x, ring_y, ring_z], axis=-1).reshape(-1, 3)
        centres = np.array([[0.0, 0.0, -height], [0.0, 0.0, top - height]])
        vertices = np.concatenate([rings, centres])
        body = _grid_triangles(len(s), around)
        rim = (len(s) - 1) * around + np.arange(around)
        bottom = _fan(len(rings), np.arange(around), reverse=True)
        lid = _fan(len(rings) + 1, rim, reverse=False)
        triangles = np.concatenate([body, bottom, lid])
    triangles = _outward(vertices, triangles)
    return Mesh(vertices=vertices, triangles=triangles.astype(np.int64))


def _outward(vertices: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Flip triangles whose normal points towards the (convex) body's centroid."""
    centroid = vertices.mean(axis=0)
    corners = vertices[triangles]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    inward = np.einsum("ij,ij->i", normals, corners.mean(axis=1) - centroid) < 0.0
    triangles = triangles.copy()
    triangles[inward] = triangles[inward][:, ::-1]
    return triangles


def axis_marks(geometry: BodyGeometry, points: int = 25) -> dict[str, np.ndarray]:
    """Marks drawn on the body, relative to G in body axes [m], each shape (points, 3).

    ``long_axis``: along body axis 1 on the top surface, ends at ±0.9 of the half
    length (ends at equal height, so end - start is parallel to axis 1).
    ``principal_axis``: the horizontal principal inertia axis nearest axis 1,
    through G, reaching 1.25 half lengths so that it shows beyond the body's ends.
    """
    half = geometry.half_length
    if geometry.kernel_params is not None:
        # the top curve in the plane of axes 1 and 3, ends at ±0.9 of the half extent
        a, _, c = geometry.half_extents
        end = math.acos(0.9)
        theta = np.linspace(np.pi - end, end, points)  # from -x to +x
        normals = np.stack([np.cos(theta) / a, np.zeros_like(theta), np.sin(theta) / c], axis=1)
        long_axis = support_points(geometry, normals) + np.array([0.0, 0.0, 0.01 * c])
    else:  # along the paraboloid's flat lid
        u = np.linspace(-0.9 * half, 0.9 * half, points)
        lid = np.full_like(u, geometry.cap_height - geometry.parameters[2] + 0.01 * half)
        long_axis = np.stack([u, np.zeros_like(u), lid], axis=1)
    reach = np.linspace(-1.25 * half, 1.25 * half, points)[:, None]
    principal = reach * geometry.principal_axis[None, :]
    return {"long_axis": long_axis, "principal_axis": principal}


def rotation_matrices(quaternions: np.ndarray) -> np.ndarray:
    """Rotation matrices R(q), body to space, of unit quaternions (w, x, y, z), shape (k, 3, 3).

    The quaternions are normalised first (they drift by the integrator's tolerance).
    """
    q = np.atleast_2d(np.asarray(quaternions, dtype=float))
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=1,
    )


def centre_positions(dataset: xr.Dataset) -> np.ndarray:
    """Position of G in space (com_position x, y and com_height) [m], shape (k, 3)."""
    plane = np.asarray(dataset["com_position"].values, dtype=float)
    height = np.asarray(dataset["com_height"].values, dtype=float)
    return np.column_stack([plane, height])


def place(points: np.ndarray, rotation: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """Body points (relative to G, body axes) in space: centre + R p [m].

    ``points`` (k, 3); ``rotation`` (3, 3) or (f, 3, 3); ``centre`` (3,) or (f, 3).
    Returns (k, 3) or (f, k, 3).
    """
    if np.ndim(rotation) == 2:  # one attitude (a video frame): a plain product is faster
        return points @ np.transpose(rotation) + np.asarray(centre)
    moved = np.einsum("...ij,kj->...ki", rotation, points)
    return moved + np.asarray(centre)[..., None, :]


def extent(
    geometry: BodyGeometry,
    mesh: Mesh,
    rotations: np.ndarray,
    centres: np.ndarray,
    contacts: np.ndarray,
) -> tuple[np.ndarray, float, float]:
    """Region to show: centre (x, y) [m], half width ``reach`` [m] and height ``top`` [m].

    The square of half width ``reach`` about ``centre`` holds the contact track and
    the body at every given attitude (rotations (f, 3, 3), centres (f, 3)); ``top``
    is 5 % above the highest point of the drawn surface.
    """
    top = 0.0
    for start in range(0, rotations.shape[0], 512):
        chunk = slice(start, start + 512)
        placed = place(mesh.vertices, rotations[chunk], centres[chunk])
        top = max(top, float(placed[..., 2].max()))
    xy = np.concatenate([contacts, centres[:, :2]])
    centre = 0.5 * (xy.min(axis=0) + xy.max(axis=0))
    half = geometry.half_length
    reach = max(1.15 * half, float(np.max(np.abs(xy - centre))) + 1.1 * half)
    return centre, reach, 1.05 * top
