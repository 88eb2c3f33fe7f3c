"""Pure geometry of the 3-D scene: the body's surface in space at each sample.

Everything here is plain NumPy on arrays in SI units, so the video (matplotlib)
and the page (JavaScript) draw the same triangles. Ellipsoid and paraboloid are
meshed from their formulas; a superellipsoid or implicit polynomial through the
contact kernel (each vertex the surface point of one outward normal).

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

import numpy as np
import xarray as xr

from celtstone.bodies import ImplicitPolynomial, Superellipsoid
from celtstone.errors import ParameterError
from celtstone.kernels.geometry import contact as contact_kernel
from celtstone.kernels.layout import parameter_record

__all__ = [
    "BodyGeometry",
    "Mesh",
    "axis_marks",
    "body_geometry",
    "centre_positions",
    "contact_point_body",
    "extent",
    "place",
    "rotation_matrices",
    "support_points",
    "surface_mesh",
    "surface_residual",
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
    kind : "ellipsoid", "paraboloid", "superellipsoid" or "implicit_polynomial"
    parameters : the kernel's four shape numbers [m]: (a, b, c, h) for the
        ellipsoid (G a distance h below its centre), (ρ1, ρ2, l, 0) for the
        paraboloid cap z = x²/(2ρ1) + y²/(2ρ2) (G a height l above the rest contact)
    inertia : central inertia tensor in body axes [kg m²], shape (3, 3)
    cap_height : height of the drawn paraboloid cap above its rest contact [m]
        (the cap is unbounded; unused for the ellipsoid)
    kernel_params : the kernels' parameter record of the shape, for the shapes drawn
        through the contact kernel (superellipsoid, implicit polynomial), else None
    """

    kind: str
    parameters: tuple[float, float, float, float]
    inertia: tuple[tuple[float, ...], ...]
    cap_height: float = 0.0
    kernel_params: np.record | None = field(default=None, compare=False)

    @property
    def half_length(self) -> float:
        """Half the extent of the drawn body along axis 1 [m]."""
        if self.kind == "ellipsoid":
            return self.parameters[0]
        if self.kernel_params is not None:
            return float(support_points(self, np.array([[1.0, 0.0, 0.0]]))[0, 0])
        return math.sqrt(2.0 * self.parameters[0] * self.cap_height)

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


def contact_point_body(kind: str, parameters: tuple[float, ...], n: np.ndarray) -> np.ndarray:
    """Contact point relative to G in body axes [m] for upward verticals ``n``, shape (k, 3).

    Ellipsoid: r = -Q n / sqrt(nᵀQn) + h e3, Q = diag(a², b², c²); paraboloid:
    (x, y) = (-ρ1 n1/n3, -ρ2 n2/n3), z = x²/(2ρ1) + y²/(2ρ2) - l. The point whose
    outward normal is -n (``kernels.geometry``, paper eq. (3)).
    """
    n = np.atleast_2d(np.asarray(n, dtype=float))
    p0, p1, p2, p3 = parameters
    if kind == "ellipsoid":
        q = np.array([p0 * p0, p1 * p1, p2 * p2])
        s = np.sqrt(np.sum(q * n * n, axis=1))[:, None]
        return -q * n / s + np.array([0.0, 0.0, p3])
    x = -p0 * n[:, 0] / n[:, 2]
    y = -p1 * n[:, 1] / n[:, 2]
    return np.stack([x, y, 0.5 * x * x / p0 + 0.5 * y * y / p1 - p2], axis=1)


def surface_residual(geometry: BodyGeometry, points: np.ndarray) -> np.ndarray:
    """Signed distance-like residual of body points (relative to G, body axes) [m], shape (k,).

    Zero on the surface: for the ellipsoid c (sqrt(x²/a² + y²/b² + (z-h)²/c²) - 1);
    for the paraboloid x²/(2ρ1) + y²/(2ρ2) - (z + l).
    """
    points = np.atleast_2d(points)
    p0, p1, p2, p3 = geometry.parameters
    x, y, z = points[:, 0], points[:, 1], points[:, 2]
    if geometry.kind == "ellipsoid":
        return p2 * (np.sqrt((x / p0) ** 2 + (y / p1) ** 2 + ((z - p3) / p2) ** 2) - 1.0)
    return 0.5 * x * x / p0 + 0.5 * y * y / p1 - (z + p2)


SHAPE_KINDS = ("ellipsoid", "paraboloid", "superellipsoid", "implicit_polynomial")
# closed shapes drawn through the contact kernel: the surface is r(ν) over all normals ν
SUPPORT_DRAWN = ("superellipsoid", "implicit_polynomial")


def _kernel_params(kind: str, parameters: tuple[float, ...], attrs: dict) -> np.record:
    """The kernels' parameter record of a superellipsoid or implicit-polynomial run's shape."""
    if kind == "superellipsoid":
        exponent = float(attrs.get("body_shape_exponent", 2.0))
        a, b, c, h = parameters
        shape: Superellipsoid | ImplicitPolynomial = Superellipsoid((a, b, c), h, exponent)
        return parameter_record(**shape.kernel_fields())
    try:
        terms = json.loads(str(attrs["body_shape_terms"]))
    except (KeyError, ValueError):
        raise ParameterError(
            "run", attrs.get("title", "?"), "a run file with attribute 'body_shape_terms'"
        ) from None
    shape = ImplicitPolynomial(terms=terms, com_offset=parameters[3])
    return shape.kernel_record()


def support_points(geometry: BodyGeometry, normals: np.ndarray) -> np.ndarray:
    """Surface points (relative to G, body axes) [m] with outward normals ``normals``, (k, 3).

    The contact kernel's point for the upward vertical n = -ν (paper eq. 3).
    """
    params = geometry.kernel_params
    still = (0.0, 0.0, 0.0)
    points = []
    for normal in np.atleast_2d(normals):
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
    if kind == "implicit_function":
        raise ParameterError(
            "run",
            str(attrs.get("body_shape_function", kind)),
            "a run of a body whose shape is stored in its file",
            "a shape given by a Python function cannot be redrawn from the file; "
            "write it as an implicit polynomial to animate it",
        )
    if kind not in SHAPE_KINDS:
        raise ParameterError("run", kind, "a run of a body of shape " + ", ".join(SHAPE_KINDS))
    parameters = tuple(float(v) for v in _attr_numbers(attrs, "body_shape_parameters"))
    inertia = tuple(tuple(float(v) for v in row) for row in _attr_numbers(attrs, "body_inertia"))
    if kind in SUPPORT_DRAWN:
        params = _kernel_params(kind, parameters, attrs)
        return BodyGeometry(kind, parameters, inertia, kernel_params=params)  # type: ignore[arg-type]
    cap_height = 0.0
    if kind == "paraboloid":
        height = parameters[2]
        contacts = contact_point_body(kind, parameters, np.asarray(dataset["n"].values))
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
    from outside. ``along`` rings along axis 1 (ellipsoid) or from the rest contact
    to the rim (paraboloid); ``around`` vertices per ring.
    """
    phi = np.linspace(0.0, 2.0 * np.pi, around, endpoint=False)
    if geometry.kernel_params is not None:
        # normals on a sphere with poles on ±axis 1, mapped to their surface points
        theta = np.linspace(0.0, np.pi, along + 1)[1:-1]
        ring_normals = np.stack(
            [
                np.cos(theta)[:, None] * np.ones_like(phi),
                np.sin(theta)[:, None] * np.cos(phi),
                np.sin(theta)[:, None] * np.sin(phi),
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
    elif geometry.kind == "ellipsoid":
        a, b, c, h = geometry.parameters
        theta = np.linspace(0.0, np.pi, along + 1)[1:-1]  # poles at the ends of axis 1
        ring_x = a * np.cos(theta)[:, None] * np.ones_like(phi)
        ring_y = b * np.sin(theta)[:, None] * np.cos(phi)
        ring_z = h + c * np.sin(theta)[:, None] * np.sin(phi)
        rings = np.stack([ring_x, ring_y, ring_z], axis=-1).reshape(-1, 3)
        poles = np.array([[a, 0.0, h], [-a, 0.0, h]])
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


def _top_height(geometry: BodyGeometry, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Height of the body's upper surface above G at body (x, y) [m]."""
    p0, p1, p2, p3 = geometry.parameters
    if geometry.kind == "ellipsoid":
        inside = np.clip(1.0 - (x / p0) ** 2 - (y / p1) ** 2, 0.0, None)
        return p3 + p2 * np.sqrt(inside)
    return np.full_like(x, geometry.cap_height - p2)


def axis_marks(geometry: BodyGeometry, points: int = 25) -> dict[str, np.ndarray]:
    """Marks drawn on the body, relative to G in body axes [m], each shape (points, 3).

    ``long_axis``: along body axis 1 on the top surface, ends at ±0.9 of the half
    length (ends at equal height, so end - start is parallel to axis 1).
    ``principal_axis``: the horizontal principal inertia axis nearest axis 1,
    through G, reaching 1.25 half lengths so that it shows beyond the body's ends.
    """
    half = geometry.half_length
    if geometry.kernel_params is not None:
        # the top curve in the plane of axes 1 and 3: outward normals (cos θ, 0, sin θ)
        theta = np.linspace(0.15 * np.pi, 0.85 * np.pi, points)
        normals = np.stack([np.cos(theta), np.zeros_like(theta), np.sin(theta)], axis=1)
        long_axis = support_points(geometry, normals) + np.array([0.0, 0.0, 0.01 * half])
    else:
        u = np.linspace(-0.9 * half, 0.9 * half, points)
        zero = np.zeros_like(u)
        lift = 0.01 * (geometry.parameters[2] if geometry.kind == "ellipsoid" else half)
        long_axis = np.stack([u, zero, _top_height(geometry, u, zero) + lift], axis=1)
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
