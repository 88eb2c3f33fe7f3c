"""Scene geometry against physics: the drawn body rests on the plane at the contact.

Oracles: the implicit surface equations of the shapes (not the contact formula the
kernels use), SciPy's quaternion rotation, the closed-form volumes of an
ellipsoid (4/3 π a b c) and of a paraboloid cap (π sqrt(ρ1 ρ2) Z²), the closed-form
principal-axis angle tan 2δ = 2 A12 / (A11 - A22), and mesh refinement.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import xarray as xr
from scipy.spatial.transform import Rotation

import celtstone as cs
from celtstone.visual import scene

# The integrator carries n and the quaternion separately (rtol 1e-10, atol 1e-12):
# they agree to ~1e-9 rad, i.e. ~1e-10 m over the 0.2 m body. Allow 1e-9 m.
GEOMETRIC_TOLERANCE = 1e-9


def _space(ds: xr.Dataset) -> tuple[np.ndarray, np.ndarray]:
    return scene.rotation_matrices(ds["quaternion"].values), scene.centre_positions(ds)


def _surface_residual(geometry: scene.BodyGeometry, points: np.ndarray) -> np.ndarray:
    """The shape's implicit equation at body points (relative to G, body axes) [m]: zero on
    the surface. Ellipsoid c (sqrt(x²/a² + y²/b² + (z-h)²/c²) - 1); paraboloid
    x²/(2ρ1) + y²/(2ρ2) - (z + l)."""
    points = np.atleast_2d(points)
    p0, p1, p2, p3 = geometry.parameters
    x, y, z = points[:, 0], points[:, 1], points[:, 2]
    if geometry.kind == "ellipsoid":
        return p2 * (np.sqrt((x / p0) ** 2 + (y / p1) ** 2 + ((z - p3) / p2) ** 2) - 1.0)
    assert geometry.kind == "paraboloid"
    return 0.5 * x * x / p0 + 0.5 * y * y / p1 - (z + p2)


def _paraboloid_contacts(parameters: tuple[float, ...], n: np.ndarray) -> np.ndarray:
    """The cap's point whose outward normal is -n, relative to G [m] (the surface gradient
    ∝ (x/ρ1, y/ρ2, -1) set parallel to -n)."""
    rho1, rho2, height, _ = parameters
    x, y = -rho1 * n[:, 0] / n[:, 2], -rho2 * n[:, 1] / n[:, 2]
    return np.stack([x, y, 0.5 * x * x / rho1 + 0.5 * y * y / rho2 - height], axis=1)


def _volume(mesh: scene.Mesh) -> float:
    corners = mesh.vertices[mesh.triangles]
    return float(
        np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])).sum() / 6
    )


def _exact_volume(geometry: scene.BodyGeometry) -> float:
    p0, p1, p2, _ = geometry.parameters
    if geometry.kind == "ellipsoid":
        return 4.0 / 3.0 * math.pi * p0 * p1 * p2
    return math.pi * math.sqrt(p0 * p1) * geometry.cap_height**2


def test_body_geometry_reads_back_the_body(rolling_run: xr.Dataset) -> None:
    body = cs.load_body(rolling_run.attrs["body"])
    geometry = scene.body_geometry(rolling_run)
    assert geometry.kind == body.shape.kind
    assert geometry.parameters == pytest.approx(body.shape.kernel_parameters(), rel=1e-15)
    np.testing.assert_allclose(geometry.inertia, body.inertia, rtol=1e-15)


def test_mesh_is_closed_outward_and_fills_the_body(rolling_run: xr.Dataset) -> None:
    geometry = scene.body_geometry(rolling_run)
    mesh = scene.surface_mesh(geometry)
    # closed and consistently wound: each directed edge once, its reverse once
    t = mesh.triangles
    directed = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    as_set = {tuple(e) for e in directed.tolist()}
    assert len(as_set) == len(directed)
    assert all((b, a) in as_set for a, b in as_set)
    # vertices on the surface (or on the paraboloid's flat lid); inscribed in a convex
    # body, so the enclosed volume is below the exact one
    scale = geometry.parameters[2]
    on_surface = np.abs(_surface_residual(geometry, mesh.vertices)) < 1e-14 * scale
    on_lid = np.isclose(mesh.vertices[:, 2], geometry.cap_height - scale, rtol=0, atol=1e-15)
    assert np.all(on_surface | (on_lid if geometry.kind == "paraboloid" else False))
    volume, exact = _volume(mesh), _exact_volume(geometry)
    assert 0.97 * exact < volume < exact  # positive: the normals point outward


def test_body_rests_on_the_plane_at_every_frame(rolling_run: xr.Dataset) -> None:
    """Lowest point of the drawn surface: never below z = 0, and -> 0 as h² under refinement."""
    geometry = scene.body_geometry(rolling_run)
    rotations, centres = _space(rolling_run)
    gaps = []
    for along, around in ((48, 32), (96, 64)):
        mesh = scene.surface_mesh(geometry, along=along, around=around)
        lowest = scene.place(mesh.vertices, rotations, centres)[..., 2].min(axis=1)
        assert lowest.min() > -GEOMETRIC_TOLERANCE
        gaps.append(lowest.max())
    # halving the spacing divides the chord gap by ~4 (second order)
    assert 3.0 < gaps[0] / gaps[1] < 5.0
    assert gaps[1] < 0.01 * cs.load_body(rolling_run.attrs["body"]).shape.rest_height


def test_contact_point_is_on_the_surface_rolling(rolling_run: xr.Dataset) -> None:
    _check_contact_on_surface(rolling_run)


def test_contact_point_is_on_the_surface_sliding(sliding_run: xr.Dataset) -> None:
    _check_contact_on_surface(sliding_run)


def _check_contact_on_surface(ds: xr.Dataset) -> None:
    """The kernel's contact position, taken into the body, satisfies the surface equation
    and the surface normal there is the downward vertical (the plane is tangent)."""
    geometry = scene.body_geometry(ds)
    rotations, centres = _space(ds)
    contact_space = np.column_stack([ds["contact_position"].values, np.zeros(ds.sizes["time"])])
    body_points = np.einsum("fji,fj->fi", rotations, contact_space - centres)  # Rᵀ (A - G)
    assert np.max(np.abs(_surface_residual(geometry, body_points))) < GEOMETRIC_TOLERANCE
    # outward normal = gradient of the implicit function; must be -Rᵀ e_z
    step = 1e-7
    gradient = np.stack(
        [
            _surface_residual(geometry, body_points + step * e)
            - _surface_residual(geometry, body_points - step * e)
            for e in np.eye(3)
        ],
        axis=1,
    )
    normal = gradient / np.linalg.norm(gradient, axis=1, keepdims=True)
    down = -rotations[:, 2, :]
    assert np.max(np.linalg.norm(normal - down, axis=1)) < 1e-6


def test_marks_follow_the_body_axes(rolling_run: xr.Dataset) -> None:
    geometry = scene.body_geometry(rolling_run)
    marks = scene.axis_marks(geometry)
    rotations, centres = _space(rolling_run)
    quaternions = rolling_run["quaternion"].values
    reference = Rotation.from_quat(quaternions, scalar_first=True)
    long_axis = scene.place(marks["long_axis"], rotations, centres)
    direction = long_axis[:, -1] - long_axis[:, 0]
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    np.testing.assert_allclose(direction, reference.apply([1.0, 0.0, 0.0]), atol=1e-12)
    # principal axis: eigenvector of the smallest principal moment (the long axis)
    moments, vectors = np.linalg.eigh(np.asarray(geometry.inertia))
    principal_body = vectors[:, np.argmin(moments)] * np.sign(vectors[0, np.argmin(moments)])
    principal = scene.place(marks["principal_axis"], rotations, centres)
    direction = principal[:, -1] - principal[:, 0]
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    np.testing.assert_allclose(direction, reference.apply(principal_body), atol=1e-12)
    # and the mark passes through G
    np.testing.assert_allclose(principal.mean(axis=1), centres, atol=1e-15)


def test_misalignment_angle_is_the_closed_form() -> None:
    """Kane & Levinson: A11 = 2e-4, A22 = 1.6e-3, A12 = -2e-5 kg m² (references.md):
    tan 2δ = 2 A12 / (A11 - A22) gives δ = 0.818°."""
    ds = xr.Dataset(
        {"n": (("time", "axis"), [[0.0, 0.0, 1.0]])},
        attrs={
            "body_shape": "ellipsoid",
            "body_shape_parameters": "[0.2, 0.03, 0.02, 0.01]",
            "body_inertia": "[[2e-4, -2e-5, 0], [-2e-5, 1.6e-3, 0], [0, 0, 1.7e-3]]",
        },
    )
    delta = scene.body_geometry(ds).misalignment_angle
    assert delta == pytest.approx(0.5 * math.atan(2 * -2e-5 / (2e-4 - 1.6e-3)), rel=1e-12)
    assert math.degrees(delta) == pytest.approx(0.818, abs=5e-4)


def test_rotation_matrices_match_scipy() -> None:
    rng = np.random.default_rng(7)
    quaternions = rng.normal(size=(50, 4)) * 3.0  # not normalised on purpose
    expected = Rotation.from_quat(quaternions, scalar_first=True).as_matrix()
    np.testing.assert_allclose(scene.rotation_matrices(quaternions), expected, atol=1e-14)


def test_paraboloid_cap_holds_every_contact(rolling_runs: dict[str, xr.Dataset]) -> None:
    rolling_run = rolling_runs["kane_levinson_1982_paraboloid"]
    geometry = scene.body_geometry(rolling_run)
    assert geometry.kind == "paraboloid"
    contacts = _paraboloid_contacts(geometry.parameters, rolling_run["n"].values)
    assert np.max(contacts[:, 2] + geometry.parameters[2]) < geometry.cap_height


def test_a_dataset_without_body_attributes_is_refused() -> None:
    with pytest.raises(cs.ParameterError, match="run"):
        scene.body_geometry(xr.Dataset(attrs={"body_shape": "cube"}))


def test_extent_holds_the_body_and_the_track(rolling_run: xr.Dataset) -> None:
    geometry = scene.body_geometry(rolling_run)
    mesh = scene.surface_mesh(geometry)
    rotations, centres = _space(rolling_run)
    contacts = rolling_run["contact_position"].values
    centre, reach, top = scene.extent(geometry, mesh, rotations, centres, contacts)
    placed = scene.place(mesh.vertices, rotations, centres)
    assert np.all(np.abs(placed[..., :2] - centre) <= reach)
    assert np.all(np.abs(contacts - centre) <= reach)
    assert placed[..., 2].max() < top < 1.1 * placed[..., 2].max()


def _superellipsoid_run() -> xr.Dataset:
    """1 s rolling run of the K&L body through the superellipsoid kernel at p = 2 (p > 2
    is flat at the rest contact and stops a run: docs/decisions.md §13)."""
    body = cs.load_body("kane_levinson_1982")
    a, b, c = body.shape.semi_axes
    shape = cs.Superellipsoid((a, b, c), body.shape.com_offset, 2.0)
    body = dataclasses.replace(body, shape=shape)
    state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
    return cs.simulate(cs.RollingModel(), body, state, 1.0).raise_for_status().dataset


def _egg_run() -> xr.Dataset:
    a, b, c, h = 0.20, 0.03, 0.02, 0.01
    terms = [[1 / a**2, 2, 0, 0], [1 / b**2, 0, 2, 0], [1 / c**2, 0, 0, 2]]
    terms += [[0.3 / c**3, 0, 0, 3], [0.1 / c**4, 0, 0, 4]]
    body = dataclasses.replace(
        cs.load_body("kane_levinson_1982"), shape=cs.ImplicitPolynomial(terms=terms, com_offset=h)
    )
    state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
    return cs.simulate(cs.RollingModel(), body, state, 1.0).raise_for_status().dataset


@pytest.mark.parametrize("make_run", [_superellipsoid_run, _egg_run], ids=["super", "egg"])
def test_shapes_drawn_through_the_contact_kernel(make_run) -> None:  # type: ignore[no-untyped-def]
    """Superellipsoid and implicit polynomial bodies: a closed outward mesh whose vertices
    are surface points with the planned outward normals, resting on the plane."""
    run = make_run()
    geometry = scene.body_geometry(run)
    assert geometry.kind == run.attrs["body_shape"] and geometry.kernel_params
    mesh = scene.surface_mesh(geometry, along=24, around=16)
    t = mesh.triangles
    directed = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    as_set = {tuple(e) for e in directed.tolist()}
    assert len(as_set) == len(directed) and all((b, a) in as_set for a, b in as_set)
    assert _volume(mesh) > 0.0
    # the extreme point along +axis 1 is the half length, and the mesh reaches it
    assert np.max(mesh.vertices[:, 0]) == pytest.approx(geometry.half_length, rel=1e-12)
    # every vertex is a support point: no vertex lies below the plane through another
    # vertex with the same outward normal (convex hull property, checked on the poles)
    rotations, centres = _space(run)
    lowest = scene.place(mesh.vertices, rotations, centres)[..., 2].min(axis=1)
    assert lowest.min() > -GEOMETRIC_TOLERANCE
    marks = scene.axis_marks(geometry)
    assert np.all(np.isfinite(marks["long_axis"])) and marks["long_axis"][:, 2].min() > 0.0
