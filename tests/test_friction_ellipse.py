"""Coulomb–Contensou friction over an elliptic Hertz contact, and the Hertz ellipse (issue 13).

Oracles, none of them the production path (``celtstone.contact.ellipse`` integrates
the radial direction in closed form about the centre of sliding in the mapped
unit disk): a product rule about the ellipse's centre (spectrally accurate where
the centre of sliding lies outside the contact, and for any smooth integrand such
as the dissipated power); nested SciPy quadratures in polar coordinates about the
centre of sliding in the physical plane (where it lies inside); the closed form
M0 = (3/8) f N A E(e); the disk's exact law (``friction_functions``); the exact
symmetries; Hertz's relations with K and E (Johnson, *Contact Mechanics*, 1985,
§4.2) and the numbers of issue 13 for the Kane & Levinson body.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy import integrate, special

from celtstone.contact import friction_functions
from celtstone.contact.ellipse import (
    elliptic_friction,
    elliptic_friction_functions,
    hertz_ellipse,
    zero_slip_moment,
)
from celtstone.errors import ParameterError
from tests.test_cli import Result

# the Kane & Levinson body at rest: principal radii of curvature at the contact [m]
# (docs/equations.md, "Hertz contact radius"), m = 1 kg, g = 9.81 m/s²
KANE_LEVINSON_RADII = (2.0, 0.045)
KANE_LEVINSON_LOAD = 9.81
# issue 13: the circular Hertz radius for this body, and the ellipse it stands for
CIRCULAR_RADIUS = 1.089e-3
ISSUE_SEMI_AXES = (3.14e-3, 0.28e-3)


def _centre_product_rule(
    u: float, direction: float, aspect: float, n_radial: int = 200, n_angular: int = 0
) -> tuple[np.ndarray, float, float]:
    """F/(fN), M/(fNA) and the power (F·V + M Ω_n)/(f N A Ω_n), about the ellipse's centre.

    x = s cos θ, y = (B/A) s sin θ, s = sin τ (A = 1, Ω_n = 1): p dA per unit N is
    (3/2π) cos²τ sin τ dτ dθ, smooth in τ; Gauss–Legendre in τ, midpoints in θ.
    Spectral where v/|v| is smooth on the contact (centre of sliding outside); the
    branch points of |v| lie about B/A off the real θ axis, so the midpoint rule's
    error falls as exp(−n_angular B/A): the default n_angular makes that exp(−40).
    """
    n_angular = n_angular or max(400, round(40.0 / aspect))
    nodes, weights = np.polynomial.legendre.leggauss(n_radial)
    tau = 0.25 * math.pi * (nodes + 1.0)
    theta = (np.arange(n_angular) + 0.5) * (2.0 * math.pi / n_angular)
    radius = np.sin(tau)[:, None]
    x, y = radius * np.cos(theta), aspect * radius * np.sin(theta)
    load = (1.5 / math.pi) * (0.25 * math.pi * weights * np.cos(tau) ** 2 * np.sin(tau))
    load = load[:, None] * (2.0 * math.pi / n_angular)
    vx, vy = u * math.cos(direction) - y, u * math.sin(direction) + x
    speed = np.hypot(vx, vy)
    unit = np.where(speed > 0.0, 1.0 / np.where(speed > 0.0, speed, 1.0), 0.0)
    force = -np.array([(load * vx * unit).sum(), (load * vy * unit).sum()])
    moment = -float((load * (x * vy - y * vx) * unit).sum())
    return force, moment, -float((load * speed).sum())


def _sliding_centre_quadrature(
    u: float, direction: float, aspect: float
) -> tuple[np.ndarray, float]:
    """F/(fN) and M/(fNA) by scipy quad in polar coordinates (q, φ) about the centre of
    sliding ρ* = e_z × V in the physical plane (A = 1, Ω_n = 1), for ρ* inside.

    Along the ray ρ* + q (cos φ, sin φ) the slip direction is (−sin φ, cos φ) and the
    moment arm about the centre is ρ*·(cos φ, sin φ) + q; the ray ends where the
    quadratic 1 − x² − (y/aspect)² vanishes.
    """
    cx, cy = -u * math.sin(direction), u * math.cos(direction)

    def reach(phi: float) -> float:
        c, s = math.cos(phi), math.sin(phi)
        a = c * c + (s / aspect) ** 2
        b = cx * c + cy * s / aspect**2
        k = cx * cx + (cy / aspect) ** 2 - 1.0
        return (-b + math.sqrt(b * b - a * k)) / a

    def ray(phi: float, kind: int) -> float:
        c, s = math.cos(phi), math.sin(phi)

        def weight(q: float) -> float:
            x, y = cx + q * c, cy + q * s
            pressure = (
                1.5 / (math.pi * aspect) * math.sqrt(max(0.0, 1.0 - x * x - (y / aspect) ** 2))
            )
            return pressure * q * ((cx * c + cy * s + q) if kind == 2 else 1.0)

        return integrate.quad(weight, 0.0, reach(phi), epsabs=1e-14, epsrel=1e-12, limit=200)[0]

    options = {"epsabs": 1e-13, "epsrel": 1e-12, "limit": 500, "points": [0.5 * math.pi, math.pi]}
    span = (0.0, 2.0 * math.pi)
    force_x = integrate.quad(lambda p: math.sin(p) * ray(p, 0), *span, **options)[0]
    force_y = integrate.quad(lambda p: -math.cos(p) * ray(p, 1), *span, **options)[0]
    moment = -integrate.quad(lambda p: ray(p, 2), *span, **options)[0]
    return np.array([force_x, force_y]), moment


def _sliding_centre_distance(u: float, direction: float, aspect: float) -> float:
    """|σ*|: the centre of sliding in units of the ellipse (1 on the rim)."""
    return math.hypot(u * math.sin(direction), u * math.cos(direction) / aspect)


# --- (a) zero slip ---------------------------------------------------------------------


@pytest.mark.parametrize("aspect", [1.0, 0.5, 0.09, 0.01])
def test_moment_at_zero_slip_is_three_eighths_e(aspect: float) -> None:
    """M0 = (3/8) f N A E(e), e² = 1 − B²/A²: the closed form against the product rule
    (the integrand ρ × v/|v| = |ρ| is continuous at V = 0) and the quadrature as u → 0
    (M is even in u: M(u) = M0 + O(u²))."""
    closed_form = 0.375 * special.ellipe(1.0 - aspect**2)
    assert zero_slip_moment(aspect) == pytest.approx(closed_form, rel=1e-15)
    force, moment, _ = _centre_product_rule(0.0, 0.0, aspect)
    assert -moment == pytest.approx(closed_form, rel=1e-12)
    assert np.all(elliptic_friction_functions(0.0, 0.4, aspect)[0] == 0.0)
    assert elliptic_friction_functions(0.0, 0.4, aspect)[1] == -zero_slip_moment(aspect)
    force, moment = elliptic_friction_functions(1e-8, 0.4, aspect)
    assert -moment == pytest.approx(closed_form, rel=1e-12)
    assert np.hypot(*force) < 1e-6  # F ≈ (3π/8)-like slope times u


# --- (b) the disk ----------------------------------------------------------------------


@pytest.mark.parametrize("u", [1e-4, 0.1, 0.5, 0.9, 0.999, 1.0, 1.001, 1.5, 4.0, 50.0, 1e4])
@pytest.mark.parametrize("direction", [0.0, 0.7, 2.0, -2.5])
def test_equal_axes_give_the_disk_law(u: float, direction: float) -> None:
    """A = B: F antiparallel to V with |F| = f N F̂(u), M = −f N A M̂(u), the disk's exact law."""
    disk_force, disk_moment = friction_functions([u], "exact", "hertz")
    force, moment = elliptic_friction_functions(u, direction, 1.0)
    slip = np.array([math.cos(direction), math.sin(direction)])
    assert force == pytest.approx(-disk_force[0] * slip, abs=1e-14)
    assert -moment == pytest.approx(disk_moment[0], abs=1e-14)


# --- (c) pure slip and pure spin -------------------------------------------------------


@pytest.mark.parametrize("aspect", [1.0, 0.3, 0.09])
@pytest.mark.parametrize("direction", [0.0, 0.4, 0.5 * math.pi, 2.0, -1.1])
def test_pure_slip_is_coulomb(aspect: float, direction: float) -> None:
    """Ω_n = 0: F = −f N V/|V| in every direction, M = 0 (the pressure's centroid is the
    centre), and the law tends to it as u grows."""
    slip = np.array([math.cos(direction), math.sin(direction)])
    force, moment = elliptic_friction_functions(math.inf, direction, aspect)
    assert force == pytest.approx(-slip, abs=1e-16) and moment == 0.0
    velocity = 0.3 * slip
    force, moment = elliptic_friction(velocity, 0.0, 2e-3, 2e-3 * aspect, 9.81, 0.35)
    assert force == pytest.approx(-0.35 * 9.81 * slip, rel=1e-15) and moment == 0.0
    force, moment = elliptic_friction_functions(1e6, direction, aspect)
    assert force == pytest.approx(-slip, abs=1e-10)
    assert abs(moment) < 1e-6  # ~ 1/(5u) for the disk


def test_pure_spin_and_the_singular_state() -> None:
    """V = 0: F = 0, M = −f N A (3/8) E(e) sign Ω_n; V = 0 with Ω_n = 0 is refused."""
    for spin in (4.0, -4.0):
        force, moment = elliptic_friction((0.0, 0.0), spin, 3e-3, 1e-3, 9.81, 0.2)
        assert np.all(force == 0.0)
        assert moment == pytest.approx(
            -math.copysign(0.2 * 9.81 * 3e-3, spin) * zero_slip_moment(1 / 3)
        )
    with pytest.raises(ParameterError, match="sliding_velocity"):
        elliptic_friction((0.0, 0.0), 0.0, 3e-3, 1e-3)


# --- (d) dissipation and the oracles ---------------------------------------------------

GRID_U = [1e-3, 0.03, 0.1, 0.3, 1.0, 3.0, 30.0]
GRID_DIRECTIONS = [math.radians(d) for d in (0.0, 20.0, 45.0, 70.0, 90.0, 135.0, 200.0, 300.0)]
GRID_ASPECTS = [1.0, 0.5, 0.09, 0.02]


@pytest.mark.parametrize("aspect", GRID_ASPECTS)
def test_dissipated_power_is_minus_the_integral_of_p_times_speed(aspect: float) -> None:
    """F·V + M Ω_n = −f ∫ p |v| dA < 0 (v/|v|·v = |v|): the power against the product rule of
    the continuous integrand p |v|, on a grid of u and slip directions."""
    for u in GRID_U:
        for direction in GRID_DIRECTIONS:
            force, moment = elliptic_friction_functions(u, direction, aspect)
            power = u * (force[0] * math.cos(direction) + force[1] * math.sin(direction)) + moment
            reference = _centre_product_rule(u, direction, aspect)[2]
            # |v| has a cone at the centre of sliding: the product rule converges as N^-3
            # where it is inside or near the rim, spectrally where it is far outside
            bound = 1e-12 if _sliding_centre_distance(u, direction, aspect) > 2.0 else 1e-6
            assert power < 0.0
            assert power == pytest.approx(reference, abs=bound), (u, direction, aspect)


@pytest.mark.parametrize(
    ("u", "direction", "aspect"),
    [(0.5, 1.0, 0.09), (3.0, 0.7, 0.09), (0.2, 0.02, 0.09), (3.0, 2.0, 0.5), (40.0, 1.3, 0.02)],
)
def test_agrees_with_the_product_rule_where_the_centre_of_sliding_is_outside(
    u: float, direction: float, aspect: float
) -> None:
    assert _sliding_centre_distance(u, direction, aspect) > 2.0
    force, moment = elliptic_friction_functions(u, direction, aspect)
    reference_force, reference_moment, _ = _centre_product_rule(u, direction, aspect)
    assert force == pytest.approx(reference_force, abs=1e-13)
    assert moment == pytest.approx(reference_moment, abs=1e-13)


@pytest.mark.parametrize(
    ("u", "direction", "aspect"),
    [(0.05, 0.4, 0.09), (0.0895, 0.0, 0.09), (0.3, 1.5, 0.4)],
)
def test_agrees_with_nested_quadrature_where_the_centre_of_sliding_is_inside(
    u: float, direction: float, aspect: float
) -> None:
    """The second case puts the centre of sliding 0.6 % inside the rim."""
    assert _sliding_centre_distance(u, direction, aspect) < 1.0
    force, moment = elliptic_friction_functions(u, direction, aspect)
    reference_force, reference_moment = _sliding_centre_quadrature(u, direction, aspect)
    assert force == pytest.approx(reference_force, abs=1e-13)
    assert moment == pytest.approx(reference_moment, abs=1e-13)


def test_continuous_where_the_centre_of_sliding_crosses_the_rim() -> None:
    """u = B/A along the major axis puts it on the rim: both sides agree."""
    aspect = 0.09
    below = elliptic_friction_functions(aspect * (1.0 - 1e-12), 0.0, aspect)
    above = elliptic_friction_functions(aspect * (1.0 + 1e-12), 0.0, aspect)
    assert below[0] == pytest.approx(above[0], abs=1e-11)
    assert below[1] == pytest.approx(above[1], abs=1e-11)


def test_physical_units_scale_as_f_n_and_f_n_a() -> None:
    """F = f N F̂(u, α, B/A), M = f N A M̂ with u = |V|/(A |Ω_n|)."""
    semi_major, semi_minor, load, coefficient, spin = 3e-3, 0.6e-3, 9.81, 0.3, 2.0
    velocity = np.array([0.004, -0.002])
    force, moment = elliptic_friction(velocity, spin, semi_major, semi_minor, load, coefficient)
    u = float(np.hypot(*velocity)) / (semi_major * spin)
    direction = math.atan2(velocity[1], velocity[0])
    assert _sliding_centre_distance(u, direction, 0.2) > 2.0
    reference_force, reference_moment, _ = _centre_product_rule(u, direction, 0.2)
    assert force == pytest.approx(coefficient * load * reference_force, abs=1e-12)
    assert moment == pytest.approx(coefficient * load * semi_major * reference_moment, abs=1e-14)


# --- (e) not antiparallel, (f) symmetry ------------------------------------------------


def test_force_is_not_antiparallel_to_an_oblique_slip() -> None:
    """B/A = 0.1: an oblique slip's force is turned from −V (towards the major axis, by
    0.5° to 18° here: more than 1e-3 rad, ten orders of magnitude above the quadrature's
    error); along an axis it stays antiparallel."""
    for u in (0.01, 0.1, 0.5, 3.0):
        for direction in (math.radians(30.0), math.radians(60.0)):
            force, _ = elliptic_friction_functions(u, direction, 0.1)
            sine = force[0] * math.sin(direction) - force[1] * math.cos(direction)
            assert sine / np.hypot(*force) < -1e-3, (u, direction)  # turned towards x
        for direction in (0.0, 0.5 * math.pi, math.pi, -0.5 * math.pi):
            force, _ = elliptic_friction_functions(u, direction, 0.1)
            sine = force[0] * math.sin(direction) - force[1] * math.cos(direction)
            assert abs(sine) < 1e-14


@pytest.mark.parametrize("aspect", [1.0, 0.3, 0.09])
@pytest.mark.parametrize("u", [0.02, 0.3, 2.0])
def test_mirrored_slip_gives_the_mirrored_force(aspect: float, u: float) -> None:
    """The ellipse is symmetric about both axes. With the same spin: slip (Vx, −Vy) gives
    (Fx, −Fy) and slip (−Vx, Vy) gives (−Fx, Fy), the same M; reversed spin mirrors y."""
    direction = 0.6
    force, moment = elliptic_friction_functions(u, direction, aspect)
    mirrored, mirrored_moment = elliptic_friction_functions(u, -direction, aspect)
    assert mirrored == pytest.approx([force[0], -force[1]], abs=1e-14)
    assert mirrored_moment == pytest.approx(moment, abs=1e-14)
    mirrored, mirrored_moment = elliptic_friction_functions(u, math.pi - direction, aspect)
    assert mirrored == pytest.approx([-force[0], force[1]], abs=1e-14)
    assert mirrored_moment == pytest.approx(moment, abs=1e-14)
    slip = (u * math.cos(direction), u * math.sin(direction))
    reversed_force, reversed_moment = elliptic_friction((slip[0], -slip[1]), -1.0, 1.0, aspect)
    assert reversed_force == pytest.approx([force[0], -force[1]], abs=1e-14)
    assert reversed_moment == pytest.approx(-moment, abs=1e-14)


# --- (g) the Hertz ellipse --------------------------------------------------------------


def _circular_modulus() -> float:
    """E* such that (3 N R_eq / (4 E*))^(1/3) = 1.089 mm, R_eq = sqrt(R1 R2) (issue 13)."""
    equivalent = math.sqrt(KANE_LEVINSON_RADII[0] * KANE_LEVINSON_RADII[1])
    return 0.75 * KANE_LEVINSON_LOAD * equivalent / CIRCULAR_RADIUS**3


@pytest.mark.parametrize("radius", [0.01, 0.3, 2.0])
def test_equal_radii_give_the_circular_hertz_radius(radius: float) -> None:
    ellipse = hertz_ellipse((radius, radius), 5.0, 2e9)
    circle = (0.75 * 5.0 * radius / 2e9) ** (1.0 / 3.0)  # Johnson (1985) eq. 4.22
    assert ellipse.semi_major_axis == pytest.approx(circle, rel=1e-15)
    assert ellipse.semi_minor_axis == pytest.approx(circle, rel=1e-15)
    assert ellipse.eccentricity == 0.0
    near = hertz_ellipse((radius * (1 + 1e-9), radius), 5.0, 2e9)
    assert near.semi_minor_axis / near.semi_major_axis == pytest.approx(1.0, abs=1e-8)


@pytest.mark.parametrize("ratio", [1.5, 10.0, 44.4, 1e4])
def test_hertz_ellipse_satisfies_johnsons_relations(ratio: float) -> None:
    """R'/R'' = [E/(1 − e²) − K]/(K − E) and a³ = 3 N (K − E) R'/(π E* e²) (Johnson §4.2)."""
    load, modulus, larger = 3.0, 1e9, 0.5
    ellipse = hertz_ellipse((larger / ratio, larger), load, modulus)
    m = ellipse.eccentricity**2
    k, e = special.ellipk(m), special.ellipe(m)
    assert (e / (1 - m) - k) / (k - e) == pytest.approx(ratio, rel=1e-10)
    cube = 3 * load * (k - e) * larger / (math.pi * modulus * m)
    assert ellipse.semi_major_axis == pytest.approx(cube ** (1 / 3), rel=1e-12)
    assert ellipse.semi_minor_axis**2 == pytest.approx(
        ellipse.semi_major_axis**2 * (1 - m), rel=1e-12
    )
    assert ellipse.major_axis_angle == pytest.approx(0.5 * math.pi)  # along the larger radius


def test_kane_levinson_contact_ellipse() -> None:
    """Issue 13: A ≈ 3.14 mm, B ≈ 0.28 mm, B/A ≈ 0.09 for the body at rest, where the
    circular model gives 1.089 mm; docs/equations.md: sqrt(ab) = 0.859 × that radius."""
    ellipse = hertz_ellipse(KANE_LEVINSON_RADII, KANE_LEVINSON_LOAD, _circular_modulus())
    assert ellipse.semi_major_axis == pytest.approx(ISSUE_SEMI_AXES[0], abs=0.005e-3)
    assert ellipse.semi_minor_axis == pytest.approx(ISSUE_SEMI_AXES[1], abs=0.005e-3)
    assert ellipse.semi_minor_axis / ellipse.semi_major_axis == pytest.approx(0.089, abs=5e-4)
    mean = math.sqrt(ellipse.semi_major_axis * ellipse.semi_minor_axis)
    assert mean / CIRCULAR_RADIUS == pytest.approx(0.859, abs=5e-4)
    assert ellipse.major_axis_angle == 0.0  # along R1 = 2 m, the long axis of the stone


@pytest.mark.parametrize(
    ("arguments", "name"),
    [
        (((0.0, 1.0), 1.0, 1e9), "radii_of_curvature"),
        (((1.0,), 1.0, 1e9), "radii_of_curvature"),
        (((1.0, 1.0), 0.0, 1e9), "normal_force"),
        (((1.0, 1.0), 1.0, -1.0), "effective_modulus"),
    ],
)
def test_hertz_ellipse_refuses_what_has_no_contact(arguments: tuple, name: str) -> None:
    with pytest.raises(ParameterError, match=name):
        hertz_ellipse(*arguments)


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: elliptic_friction_functions(0.5, 0.0, 1.5), "aspect"),
        (lambda: elliptic_friction_functions(0.5, 0.0, 0.0), "aspect"),
        (lambda: elliptic_friction_functions(-0.5, 0.0, 0.5), "slip_ratio"),
        (lambda: elliptic_friction_functions(math.nan, 0.0, 0.5), "slip_ratio"),
        (lambda: elliptic_friction_functions(0.5, math.inf, 0.5), "direction"),
        (lambda: elliptic_friction((1.0, 0.0), 1.0, 1e-3, 2e-3), "ellipse"),
    ],
)
def test_bad_input_is_refused(call: object, name: str) -> None:
    with pytest.raises(ParameterError, match=name):
        call()  # type: ignore[operator]


# --- (h) the command line ---------------------------------------------------------------


def test_friction_ellipse_json_keys_and_values() -> None:
    """B/A = 0.5, u = 3 at 40°: the centre of sliding is outside, the product rule exact."""
    argv = ["friction", "--ellipse", "2e-3,1e-3", "--u", "0,3", "--direction", "40", "--json"]
    result = Result(argv)
    assert result.status == 0, result.err
    value = result.json()
    assert set(value) == {
        "law", "pressure", "ellipse", "direction", "u", "force", "force_direction", "moment",
    }  # fmt: skip
    assert (value["law"], value["pressure"]) == ("exact", "hertz")
    assert value["ellipse"] == [2e-3, 1e-3] and value["direction"] == 40.0
    assert value["u"] == [0.0, 3.0]
    assert value["force"][0] == 0.0
    assert value["moment"][0] == pytest.approx(0.375 * special.ellipe(0.75), rel=1e-15)
    force, moment, _ = _centre_product_rule(3.0, math.radians(40.0), 0.5)
    assert value["force"][1] == pytest.approx(np.hypot(*force), abs=1e-13)
    angle = math.degrees(math.atan2(force[1], force[0])) % 360.0
    assert value["force_direction"][1] == pytest.approx(angle, abs=1e-9)
    assert 180.0 < angle < 220.0  # roughly against the slip at 40°
    assert value["moment"][1] == pytest.approx(-moment, abs=1e-13)  # it opposes Ω_n > 0


def test_friction_ellipse_text_output_and_axis_slip() -> None:
    """Equal axes print the disk's numbers; slip along the major axis is resisted at 180°."""
    result = Result(["friction", "--ellipse", "1e-3,1e-3", "--u", "0.5"])
    assert result.status == 0, result.err
    assert "exact law, hertz pressure, ellipse A = 0.001 m, B = 0.001 m" in result.out
    # u = 1/2: F = 45π/256, M = 297π/2048 (the disk's closed form, tests/test_cli_friction.py)
    line = result.out.splitlines()[-1].split()
    assert float(line[1]) == pytest.approx(45 * math.pi / 256, abs=1e-10)
    assert float(line[2]) == 180.0
    assert float(line[3]) == pytest.approx(297 * math.pi / 2048, abs=1e-10)


def test_friction_ellipse_pade_is_the_kernel_a_run_uses() -> None:
    """``--law pade`` prints the fast form: its closed-form limits (zero slip: (3/8)E(e);
    pure slip: |F| = fN opposite the slip) and, in between, the Padé law's shape."""
    from scipy.special import ellipe

    options = ["--law", "pade", "--u", "0,1,1e9", "--json", "--direction", "30"]
    result = Result(["friction", "--ellipse", "3e-3,1e-3", *options])
    assert result.status == 0, result.err
    data = json.loads(result.out)
    assert data["law"] == "pade"
    assert data["moment"][0] == pytest.approx(0.375 * ellipe(1 - (1 / 3) ** 2), rel=1e-13)
    assert data["force"][0] == 0.0 and data["force_direction"][0] == 0.0
    assert data["force"][2] == pytest.approx(1.0, abs=1e-8)
    assert data["force_direction"][2] == pytest.approx(210.0, abs=1e-6)
    assert 0.0 < data["force"][1] < 1.0 and 0.0 < data["moment"][1] < data["moment"][0]


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["--ellipse", "1e-3,2e-3"], ["ellipse", "A >= B > 0"]),
        (["--ellipse", "1e-3,0"], ["ellipse", "A >= B > 0"]),
        (["--ellipse", "a,b"], ["ellipse", "A >= B > 0"]),
        (["--ellipse", "1e-3"], ["ellipse", "A,B"]),
        (["--ellipse", "3e-3,1e-3,1e-3"], ["ellipse", "A,B"]),
        (["--ellipse", "inf,1e-3"], ["ellipse"]),
        (["--ellipse", "3e-3,3e-5", "--law", "pade"], ["ellipse", "B/A >= 0.02"]),
        (["--ellipse", "3e-3,1e-3", "--pressure", "uniform"], ["contact_pressure", "hertz"]),
        (["--ellipse", "3e-3,1e-3", "--direction", "north"], ["direction", "deg"]),
        (["--ellipse", "3e-3,1e-3", "--direction", "nan"], ["direction"]),
        (["--ellipse", "3e-3,1e-3", "--plot", "x.png"], ["plot", "--ellipse"]),
        (["--direction", "30"], ["direction", "--ellipse"]),
    ],
)
def test_friction_ellipse_bad_input_is_one_line(argv: list[str], words: list[str]) -> None:
    result = Result(["friction", *argv])
    assert result.status == 2
    assert result.out == ""
    assert result.err.count("\n") == 1 and result.err.startswith("celtstone: error:")
    for word in words:
        assert word in result.err
