"""The stick limit set of the elliptic contact: is the friction that stick needs one that
some slip of the contact would give?

The elliptic law (``friction_ellipse.elliptic_contact_friction``) maps a slip state
(u = |V|/(A|Ω_n|), slip direction α from the major axis), for Ω_n > 0, to a force
F(u, α) (per unit f N, a 2-vector in the ellipse's axes) and a moment M(u, α) (per unit
f N A). As u runs over [0, ∞) and α over the circle, F covers the open unit disk; the
boundary of the limit set is the surface (F, |M|) over it. Stick needs a force F_s and
a moment M_s; it is admissible while |M_s| <= |M|(u, α) at the slip state whose force is
F_s, found by Newton's method on the two components of F(u, α) − F_s. The margin

    g = (|M|(F_s) − |M_s|) / M0,   M0 = |M|(u = 0) = (3/8) E(e) (per unit f N A)

is the circle's (``stick.stick_margin_of``: μ_max(φ) − μ) for B = A, and continues
below zero as −|M_s|/M0 − (|F_s| − 1) when |F_s| >= f N (no moment is admissible there).
"""

from __future__ import annotations

import math

from celtstone.kernels._jit import kernel
from celtstone.kernels.friction import PADE_B
from celtstone.kernels.friction_ellipse import elliptic_contact_friction
from celtstone.kernels.vector import Vec, cross, dot

# Newton on the slip state: coordinates x = u/(u + b) ∈ [0, 1) (b of paper eq. 12, so that
# x = |F| for the disk's Padé law) and α; central differences for the Jacobian
NEWTON_ITERATIONS = 60
NEWTON_TOLERANCE = 1e-13  # |F(u, α) − F_s| per unit f N
DIFFERENCE_STEP = 1e-7
COARSEST_DIFFERENCE = 1e-3  # the widest difference tried when Newton stalls
LARGEST_X = 1.0 - 1e-12  # u ≈ 1e12 b: pure slip to round-off
SMALLEST_FORCE = 1e-14  # |F_s| per unit f N treated as zero: the moment is M0


@kernel
def law_at(
    x: float, direction: float, aspect: float, law: int, table: int
) -> tuple[float, float, float]:
    """(F_x, F_y) per unit f N in the ellipse's axes and |M| per unit f N A at the slip state
    x = u/(u + b), α = ``direction`` [rad], for Ω_n > 0, δ = 0 (a kernel of unit size);
    ``table`` the address of the elliptic law's table (``friction_ellipse``)."""
    u = PADE_B * x / (1.0 - x)
    slip = (u * math.cos(direction), u * math.sin(direction), 0.0)
    force, moment = elliptic_contact_friction(
        slip, 1.0, (0.0, 0.0, 1.0), (1.0, 0.0, 0.0), 1.0, aspect, 0.0, law, table
    )
    return force[0], force[1], abs(moment)


@kernel
def limit_moment_at(force_x: float, force_y: float, aspect: float, law: int, table: int) -> float:
    """|M| per unit f N A of the slip state whose force is (force_x, force_y) per unit f N
    (|F| < 1), in the ellipse's axes [1], ``table`` as :func:`law_at`; NaN if the law has no
    value (B/A out of range, the table 0)."""
    _, _, zero_slip = law_at(0.0, 0.0, aspect, law, table)
    magnitude = math.hypot(force_x, force_y)
    if magnitude <= SMALLEST_FORCE or math.isnan(zero_slip):
        return zero_slip
    # start: the disk's Padé inverse (|F| = x), slip opposite the force
    x = min(magnitude, LARGEST_X)
    direction = math.atan2(force_y, force_x) + math.pi
    fx, fy, moment = law_at(x, direction, aspect, law, table)
    rx, ry = fx - force_x, fy - force_y
    residual = math.hypot(rx, ry)
    difference = DIFFERENCE_STEP
    for _ in range(NEWTON_ITERATIONS):
        if residual <= NEWTON_TOLERANCE:
            break
        hx = difference * max(min(x, 1.0 - x), 1e-6)
        upper, lower = min(x + hx, LARGEST_X), max(x - hx, 0.0)
        ax, ay, _ = law_at(upper, direction, aspect, law, table)
        bx, by, _ = law_at(lower, direction, aspect, law, table)
        j11, j21 = (ax - bx) / (upper - lower), (ay - by) / (upper - lower)
        cx, cy, _ = law_at(x, direction + difference, aspect, law, table)
        dx, dy, _ = law_at(x, direction - difference, aspect, law, table)
        j12, j22 = (cx - dx) / (2.0 * difference), (cy - dy) / (2.0 * difference)
        determinant = j11 * j22 - j12 * j21
        if determinant == 0.0 or not math.isfinite(determinant):
            break
        step_x = (j22 * rx - j12 * ry) / determinant
        step_direction = (j11 * ry - j21 * rx) / determinant
        # the whole step shortened so that x goes at most halfway to either end of
        # [0, 1) (x = 0 has no direction), then halved until the residual falls
        scale = 1.0
        if step_x > 0.0:
            scale = min(scale, 0.5 * x / step_x)
        elif step_x < 0.0:
            scale = min(scale, 0.5 * (LARGEST_X - x) / -step_x)
        improved = False
        for _ in range(40):
            trial_x = x - scale * step_x
            trial_direction = direction - scale * step_direction
            tx, ty, tm = law_at(trial_x, trial_direction, aspect, law, table)
            trial = math.hypot(tx - force_x, ty - force_y)
            if trial < residual:
                x, direction, moment = trial_x, trial_direction, tm
                rx, ry, residual = tx - force_x, ty - force_y, trial
                improved = True
                break
            scale *= 0.5
        if not improved:
            if difference >= COARSEST_DIFFERENCE:
                break
            # a kink of the exact disk law (the centre of sliding on the rim) between the
            # difference points: a wider difference averages across it
            difference *= 100.0
        else:
            difference = DIFFERENCE_STEP
    return moment


@kernel
def elliptic_stick_margin(
    friction_force: Vec,
    pivot_moment: float,
    n: Vec,
    major_axis: Vec,
    semi_major_axis: float,
    semi_minor_axis: float,
    capacity: float,
    law: int,
    table: int,
) -> float:
    """Distance of the friction stick needs inside the elliptic law's limit set [1].

    Parameters
    ----------
    friction_force : tangential reaction F_s that holds the contact [N], body axes
    pivot_moment : M_s, the moment about n that stops the pivoting [N m]
    n : the vertical [1]; major_axis : a, unit, ⊥ n [1], body axes
    semi_major_axis, semi_minor_axis : A >= B [m] of the Hertz ellipse
    capacity : f N of the friction law [N]
    law : ``layout.FrictionLaw`` of the disk law the ellipse's corrects
    table : address of the elliptic law's table (``friction_ellipse.elliptic_ratios``)

    Returns
    -------
    g >= 0 while stick is admissible (module docstring); −1 without friction (f N <= 0)
    and with an ellipse out of the law's range or the table 0 (the slip law then reports
    it).
    """
    if not capacity > 0.0:
        return -1.0
    aspect = semi_minor_axis / semi_major_axis
    force_x = dot(friction_force, major_axis) / capacity
    force_y = dot(friction_force, cross(n, major_axis)) / capacity
    moment = abs(pivot_moment) / (capacity * semi_major_axis)
    _, _, zero_slip = law_at(0.0, 0.0, aspect, law, table)
    if not zero_slip > 0.0:
        return -1.0
    magnitude = math.hypot(force_x, force_y)
    if magnitude >= 1.0:
        return -moment / zero_slip - (magnitude - 1.0)
    largest = limit_moment_at(force_x, force_y, aspect, law, table)
    if math.isnan(largest):
        return -1.0
    return (largest - moment) / zero_slip
