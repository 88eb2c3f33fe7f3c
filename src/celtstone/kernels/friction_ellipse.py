"""Fast Coulomb–Contensou friction over an elliptic Hertz contact: a disk law, corrected.

The exact law over an ellipse of semi-axes A >= B (``celtstone.contact.ellipse``)
costs about a millisecond per call. This kernel evaluates instead the run's law on the
Hertz disk of radius ε = A (``friction.contact_friction``: Zhuravlev–Padé's, paper
eq. 10, 12, the exact closed form, or any other law), multiplied by the ratios of
the exact elliptic law to the exact disk law, read from a table (``docs/decisions.md``
§24, "Fast form"). In the slip-aligned frame, with ŝ the unit tangential slip and
ŝ⊥ = n × ŝ,

    F = F_disk(A) [(1 + d_par) ŝ + r_perp ŝ⊥],   M = M_disk(A) (2E(e)/π)(1 + d_M),

where r_par = 1 + d_par = F·ŝ / F₁, r_perp = F·ŝ⊥ / F₁ and r_M = (2E(e)/π)(1 + d_M) =
M / M₁, F₁ and M₁ the exact disk law of radius A at the same u = |V|/(A|Ω_n|). The
ratios depend on u, the slip direction α from the major axis and k = B/A, not on the
sign of the spin (the ellipse is symmetric under a rotation by π, so F(V, −Ω) = F(V, Ω)
and M(V, −Ω) = −M(V, Ω)). Closed-form limits hold by construction: d_M = 0 at u = 0,
so M = −(3/8) f N A E(e) sign Ω at zero slip; d_par = r_perp = 0 at u = ∞, so pure
slip gives |F| = fN antiparallel to V; A = B is the disk law itself.

Table: cubic B-spline coefficients (C², tensor product) of (d_par, r_perp, d_M) over

    s = [atan(u/k) + atan(u)]/π ∈ [0, 1],   β = [α + atan2(k sin α, cos α)]/2 ∈ [0, π/2],
    q = ln k ∈ [ln ASPECT_MIN, 0],

uniform in each, 45 × 25 × 11 nodes (49 491 coefficients with the end rows). The ratios
are even in u at u = 0 and in 1/u at u = ∞, even (d_par, d_M) or odd (r_perp) in α
about 0 and π/2; s and β are odd about their ends in the same sense, so these
symmetries are reflections about the grid's ends, which the spline's end conditions
impose (not-a-knot in q). Each coordinate is half a plain one and half one scaled by
k, so that both scales of the law are inside the grid for every k: u ≈ k with the
narrow window |α − π/2| ≲ k/u (the centre of sliding crosses the thin ellipse), and
u ≈ 1 with α of order 1 (the disk's scale). The node values are generated from the
exact law by ``python -m celtstone.contact.ellipse_table`` into
``friction_ellipse_table.npz`` beside this module and read here at import into
:data:`COEFFICIENTS`. The kernels read the coefficients through the array's address
(``table``, an int64: :data:`TABLE_ADDRESS` in this process, the parameter record's
``ellipse_table``, a device copy's on a GPU), not as a global array, which numba would
freeze into the code of every function that reads it, each sliding kernel of the cache
and of a GPU's included (docs/decisions.md, "GPU sweeps"). An address of 0 gives NaN.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from celtstone.kernels._jit import kernel, table_entry
from celtstone.kernels.friction import contact_friction
from celtstone.kernels.friction_exact import complete_elliptic_integrals
from celtstone.kernels.layout import ContactPressure
from celtstone.kernels.vector import NAN3, Vec, cross, dot

TABLE_FILE = Path(__file__).with_name("friction_ellipse_table.npz")
HALF_PI = 0.5 * math.pi


def spline_matrix(nodes: int, left: str, right: str) -> np.ndarray:
    """The (nodes + 2)² collocation matrix of a uniform cubic B-spline with end conditions.

    Rows 1 … nodes: (c[i] + 4 c[i+1] + c[i+2]) / 6 = f[i] (value at node i); row 0 and
    the last row: the end conditions, ``"even"`` (c[-1] = c[1]: the spline is the even
    reflection about the end), ``"odd"`` (c[-1] = −c[1]) or ``"not-a-knot"`` (the third
    derivative is continuous at the first interior knot).
    """
    size = nodes + 2
    matrix = np.zeros((size, size))
    for i in range(nodes):
        matrix[i + 1, i : i + 3] = (1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0)
    rows = {
        "even": (1.0, 0.0, -1.0, 0.0, 0.0),
        "odd": (1.0, 0.0, 1.0, 0.0, 0.0),
        "not-a-knot": (1.0, -4.0, 6.0, -4.0, 1.0),
    }
    matrix[0, :5] = rows[left]
    matrix[-1, -5:] = rows[right][::-1]
    return matrix


def spline_coefficients(ratios: np.ndarray) -> np.ndarray:
    """B-spline coefficients, shape (n_s + 2, n_β + 2, n_k + 2, 3), of node values.

    ``ratios`` : (d_par, r_perp, d_M) at the nodes [1], shape (3, n_s, n_β, n_k).
    Ends: even in s (both), even in β for d_par and d_M and odd for r_perp (both),
    not-a-knot in q = ln k.
    """
    quantities, slips, directions, aspects = ratios.shape
    solve_slip = np.linalg.inv(spline_matrix(slips, "even", "even"))
    solve_aspect = np.linalg.inv(spline_matrix(aspects, "not-a-knot", "not-a-knot"))
    coefficients = np.empty((slips + 2, directions + 2, aspects + 2, quantities))
    for index in range(quantities):
        parity = "odd" if index == 1 else "even"
        solve_direction = np.linalg.inv(spline_matrix(directions, parity, parity))
        padded = np.zeros((slips + 2, directions + 2, aspects + 2))
        padded[1:-1, 1:-1, 1:-1] = ratios[index]  # the end-condition rows are zero
        coefficients[..., index] = np.einsum(
            "ai,bj,ck,ijk->abc", solve_slip, solve_direction, solve_aspect, padded, optimize=True
        )
    return coefficients


def _load_table() -> tuple[np.ndarray, float]:
    with np.load(TABLE_FILE, allow_pickle=False) as data:
        coefficients = spline_coefficients(np.asarray(data["ratios"], dtype=float))
        return np.ascontiguousarray(coefficients), float(data["aspect_min"])


COEFFICIENTS, ASPECT_MIN = _load_table()
COEFFICIENTS.flags.writeable = False  # the kernels read it at its address, from any thread
TABLE_ADDRESS: int = COEFFICIENTS.ctypes.data
"""The address of :data:`COEFFICIENTS` (C order) in this process, which keeps the array
for its lifetime: the kernels' ``table`` argument, the records' ``ellipse_table``."""
SLIP_NODES = COEFFICIENTS.shape[0] - 2
DIRECTION_NODES = COEFFICIENTS.shape[1] - 2
ASPECT_NODES = COEFFICIENTS.shape[2] - 2
LOG_ASPECT_MIN = math.log(ASPECT_MIN)
# steps of the flat C-order index of (i, j, m, quantity) in the table
SLIP_STEP = COEFFICIENTS.strides[0] // COEFFICIENTS.itemsize
DIRECTION_STEP = COEFFICIENTS.strides[1] // COEFFICIENTS.itemsize
ASPECT_STEP = COEFFICIENTS.strides[2] // COEFFICIENTS.itemsize


@kernel
def slip_coordinate(slip_speed: float, pivot_speed: float, aspect: float) -> float:
    """s = [atan(u/k) + atan(u)]/π ∈ [0, 1], u = |V|/(A|Ω_n|), from |V|, A|Ω_n| [m/s]."""
    return (
        math.atan2(slip_speed, aspect * pivot_speed) + math.atan2(slip_speed, pivot_speed)
    ) / math.pi


@kernel
def direction_coordinate(slip_major: float, slip_minor: float, aspect: float) -> float:
    """β = [α + atan2(k sin α, cos α)]/2 ∈ [0, π/2], α folded into [0, π/2], from V·a, V·(n×a)."""
    along = abs(slip_major)
    across = abs(slip_minor)
    return 0.5 * (math.atan2(across, along) + math.atan2(aspect * across, along))


@kernel
def _cubic_bspline(position: float, nodes: int) -> tuple[int, float, float, float, float]:
    """Cell and the four uniform cubic B-spline weights at ``position`` in node units."""
    cell = min(max(int(position), 0), nodes - 2)  # position >= 0: int() is floor
    t = position - cell
    t2 = t * t
    t3 = t2 * t
    w0 = (1.0 - t) * (1.0 - t) * (1.0 - t) / 6.0
    w1 = (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0
    w2 = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0
    w3 = t3 / 6.0
    return cell, w0, w1, w2, w3


@kernel
def elliptic_ratios(
    slip_major: float, slip_minor: float, pivot_speed: float, aspect: float, table: int
) -> tuple[float, float, float]:
    """(d_par, r_perp, d_M) [1] of the elliptic law relative to the disk's, from the table.

    Parameters
    ----------
    slip_major, slip_minor : V·a, V·(n × a), the slip along the major and minor axes [m/s]
    pivot_speed : A|Ω_n| [m/s]
    aspect : k = B/A [1], in [ASPECT_MIN, 1]; NaN outside (no extrapolation)
    table : address of the spline coefficients, laid out as :data:`COEFFICIENTS`
        (:data:`TABLE_ADDRESS`, or a device copy's on a GPU); 0 gives NaN

    Returns
    -------
    d_par : F·ŝ / F₁ − 1
    r_perp : F·ŝ⊥ / F₁, ŝ⊥ = n × ŝ
    d_M : (M / M₁) π / (2 E(e)) − 1
    """
    log_aspect = math.log(aspect)
    if table == 0 or not (LOG_ASPECT_MIN <= log_aspect <= 0.0):
        return math.nan, math.nan, math.nan
    slip_speed = math.hypot(slip_major, slip_minor)
    s = slip_coordinate(slip_speed, pivot_speed, aspect) * (SLIP_NODES - 1)
    beta = direction_coordinate(slip_major, slip_minor, aspect) * ((DIRECTION_NODES - 1) / HALF_PI)
    q = (log_aspect - LOG_ASPECT_MIN) * ((ASPECT_NODES - 1) / -LOG_ASPECT_MIN)
    # ``+ 0``: the node counts as ints, not as numba constants, for which numba would
    # compile ``_cubic_bspline`` once per count
    i, a0, a1, a2, a3 = _cubic_bspline(s, SLIP_NODES + 0)
    j, b0, b1, b2, b3 = _cubic_bspline(beta, DIRECTION_NODES + 0)
    m, c0, c1, c2, c3 = _cubic_bspline(q, ASPECT_NODES + 0)
    slip_weights = (a0, a1, a2, a3)
    direction_weights = (b0, b1, b2, b3)
    aspect_weights = (c0, c1, c2, c3)
    parallel = 0.0
    across = 0.0
    moment = 0.0
    for di in range(4):
        for dj in range(4):
            weight = slip_weights[di] * direction_weights[dj]
            for dm in range(4):
                w = weight * aspect_weights[dm]
                at = (i + di) * SLIP_STEP + (j + dj) * DIRECTION_STEP + (m + dm) * ASPECT_STEP
                parallel += w * table_entry(table, at)
                across += w * table_entry(table, at + 1)
                moment += w * table_entry(table, at + 2)
    # r_perp is odd in α about 0 and π/2: its sign is that of V_x V_y
    if slip_major * slip_minor < 0.0:
        across = -across
    return parallel, across, moment


@kernel
def elliptic_correction(
    disk_force: Vec,
    disk_moment: float,
    slip_velocity: Vec,
    spin_rate: float,
    normal: Vec,
    major_axis: Vec,
    semi_major_axis: float,
    semi_minor_axis: float,
    table: int,
) -> tuple[Vec, float]:
    """A disk law of radius A (force ∥ V1, moment about n) turned into the ellipse's.

    F = (1 + d_par) F_disk + r_perp n × F_disk, M = M_disk (2E(e)/π)(1 + d_M), with
    d_par, r_perp, d_M from :func:`elliptic_ratios` at the tangential slip and A|Ω_n|;
    arguments as :func:`elliptic_contact_friction`. A = B returns the disk law unchanged;
    B/A < ASPECT_MIN, B > A, a NaN or the ``table`` 0 returns NaN.
    """
    if table == 0 or not (0.0 < semi_minor_axis <= semi_major_axis):
        return NAN3, math.nan
    if semi_minor_axis == semi_major_axis:
        return disk_force, disk_moment
    aspect = semi_minor_axis / semi_major_axis
    minor_axis = cross(normal, major_axis)
    parallel, across, moment_ratio = elliptic_ratios(
        dot(slip_velocity, major_axis),
        dot(slip_velocity, minor_axis),
        semi_major_axis * abs(spin_rate),
        aspect,
        table,
    )
    turned = cross(normal, disk_force)
    along = 1.0 + parallel
    force = (
        along * disk_force[0] + across * turned[0],
        along * disk_force[1] + across * turned[1],
        along * disk_force[2] + across * turned[2],
    )
    eccentricity = math.sqrt((1.0 - aspect) * (1.0 + aspect))
    e_integral = complete_elliptic_integrals(eccentricity)[0]
    return force, disk_moment * (e_integral / HALF_PI) * (1.0 + moment_ratio)


@kernel
def elliptic_contact_friction(
    slip_velocity: Vec,
    spin_rate: float,
    normal: Vec,
    major_axis: Vec,
    semi_major_axis: float,
    semi_minor_axis: float,
    regularisation_speed: float,
    law: int,
    table: int,
) -> tuple[Vec, float]:
    """Coulomb–Contensou friction over an elliptic Hertz contact, per unit f N.

    Parameters
    ----------
    slip_velocity : V1, sliding velocity of the contact point [m/s], body axes
    spin_rate : Ω_n = ω · n, angular velocity about the normal n [rad/s]
    normal : n, unit normal of the plane (the vertical) [1], body axes
    major_axis : a, unit vector along the ellipse's major axis, ⊥ n [1], body axes
    semi_major_axis : A [m], >= ``semi_minor_axis``
    semi_minor_axis : B [m], with ASPECT_MIN <= B/A <= 1
    regularisation_speed : δ, |V1| -> sqrt(|V1|² + δ²) in the disk law [m/s]
    law : a ``layout.FrictionLaw``: the law of the Hertz disk of radius A
        (``friction.contact_friction``) is corrected; for the exact law the result is
        the exact elliptic law to the table's interpolation error, for Padé's
        Zhuravlev's law of the disk (paper eq. 10, 12) corrected
    table : address of the ratios' spline coefficients (:func:`elliptic_ratios`):
        :data:`TABLE_ADDRESS`, the parameter record's ``ellipse_table``; 0 gives NaN

    Returns
    -------
    force : F / (f N) [1], body axes
    moment : M / (f N) [m], the moment about n, opposite in sign to Ω_n

    Notes
    -----
    Frame: the minor axis is n × a, the slip-aligned frame (ŝ, ŝ⊥ = n × ŝ), so that
    (a, n × a, n) and (ŝ, ŝ⊥, n) are right-handed, as (x, y, e_z) in
    ``contact.ellipse`` with Ω_n about e_z. With u = |V_t|/(A|Ω_n|) (V_t the tangential
    slip, not regularised) and α = atan2(V·(n × a), V·a), :func:`elliptic_correction`
    of the disk law. For the Padé law:

        F = −[(1 + d_par) V1 + r_perp n × V1] / (sqrt(|V1|² + δ²) + b A|Ω_n|),
        M = −M0 A² Ω_n (2E(e)/π)(1 + d_M) / (A|Ω_n| + a sqrt(|V1|² + δ²)),

    b, a, M0 of paper eq. (12), E(e) the complete elliptic integral, e² = 1 − k².
    Symbols: A → semi_major_axis, B → semi_minor_axis, δ → regularisation_speed.
    A law code without a branch in ``friction.law_functions`` gives NaN.
    """
    disk_force, disk_moment = contact_friction(
        slip_velocity,
        spin_rate,
        semi_major_axis,
        regularisation_speed,
        law,
        ContactPressure.HERTZ.value,
    )
    return elliptic_correction(
        disk_force,
        disk_moment,
        slip_velocity,
        spin_rate,
        normal,
        major_axis,
        semi_major_axis,
        semi_minor_axis,
        table,
    )
