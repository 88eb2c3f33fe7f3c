"""The design form of a body (``[design]``, ``celtstone.Design``): a stone from its outer
dimensions, mass or density, misalignment and added masses.

Oracles: the textbook moments of a solid hemisphere, a numerical quadrature of the
half-ellipsoid written here, the invariance of the principal moments under a turn, the
rolling model's own runs (a design without misalignment has no Celt coupling and keeps
its sense of spin; the same design turned by 8° reverses, so the test can fail).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy import integrate

import celtstone as cs
from celtstone.bodies import load_design
from celtstone.cli.main import main
from celtstone.errors import BodyFileError, ParameterError

PRINTED = {"length": 0.12, "width": 0.03, "height": 0.012, "mass": 0.027, "misalignment": 8.0}
"""The worked example of docs/bodies.md: a 3D-printed stone 12 × 3 × 1.2 cm of 27 g."""


def test_solid_hemisphere_has_the_textbook_moments() -> None:
    """A hemisphere of radius R: centroid 3R/8 below the flat face, central moments
    83/320 m R² about a horizontal axis and 2/5 m R² about the vertical (e.g. Meriam &
    Kraige, Engineering Mechanics: Dynamics, table D/4)."""
    radius, mass = 0.05, 0.3
    design = cs.Design(length=2 * radius, width=2 * radius, height=radius, mass=mass)
    body = design.body()
    assert body.shape.com_offset == pytest.approx(3 * radius / 8, rel=1e-14)
    assert body.shape.rest_height == pytest.approx(5 * radius / 8, rel=1e-14)
    expected = np.diag([83 / 320, 83 / 320, 2 / 5]) * mass * radius**2
    np.testing.assert_allclose(body.inertia_array, expected, rtol=1e-13, atol=0.0)


def _quadrature_inertia(a: float, b: float, c: float, density: float) -> tuple[float, np.ndarray]:
    """Mass and central inertia of the solid lower half-ellipsoid by tplquad over
    x ∈ [−a, a], y within the ellipse, z from −c·sqrt(1 − x²/a² − y²/b²) to 0."""

    def depth(x: float, y: float) -> float:
        return -c * math.sqrt(max(0.0, 1.0 - (x / a) ** 2 - (y / b) ** 2))

    def half_width(x: float) -> float:
        return b * math.sqrt(max(0.0, 1.0 - (x / a) ** 2))

    def moment(f):
        value, _ = integrate.tplquad(
            lambda z, y, x: density * f(x, y, z),
            -a,
            a,
            lambda x: -half_width(x),
            half_width,
            depth,
            lambda x, y: 0.0,
            epsabs=0.0,
            epsrel=1e-10,
        )
        return value

    mass = moment(lambda x, y, z: 1.0)
    zg = moment(lambda x, y, z: z) / mass
    about_origin = np.array(
        [
            [moment(lambda x, y, z: y * y + z * z), 0.0, 0.0],
            [0.0, moment(lambda x, y, z: x * x + z * z), 0.0],
            [0.0, 0.0, moment(lambda x, y, z: x * x + y * y)],
        ]
    )
    return mass, about_origin - mass * zg**2 * np.diag([1.0, 1.0, 0.0])


def test_solid_half_ellipsoid_matches_a_quadrature() -> None:
    """Mass and inertia of the closed form against a numerical integration."""
    a, b, c, density = 0.06, 0.015, 0.012, 1240.0
    design = cs.Design(length=2 * a, width=2 * b, height=c, density=density)
    mass, inertia = _quadrature_inertia(a, b, c, density)
    body = design.body()
    assert body.mass == pytest.approx(mass, rel=1e-8)
    np.testing.assert_allclose(body.inertia_array, inertia, rtol=1e-7, atol=0.0)


@pytest.mark.parametrize("angle", [-20.0, 0.0, 2.5, 8.0, 30.0])
def test_misalignment_turns_the_principal_axes_and_keeps_the_moments(angle: float) -> None:
    turned = cs.Design(**{**PRINTED, "misalignment": angle}).body()
    straight = cs.Design(**{**PRINTED, "misalignment": 0.0}).body()
    assert math.degrees(turned.misalignment_angle) == pytest.approx(angle, abs=1e-9)
    np.testing.assert_allclose(
        np.linalg.eigvalsh(turned.inertia_array),
        np.linalg.eigvalsh(straight.inertia_array),
        rtol=1e-12,
    )
    if angle > 0.0:
        assert turned.inertia[0][1] < 0.0  # the sign of Kane & Levinson's D


def test_mass_and_density_give_the_same_stone() -> None:
    by_mass = cs.Design(**PRINTED)
    density = by_mass.solid_density
    by_density = cs.Design(**{**PRINTED, "mass": None, "density": density})
    np.testing.assert_allclose(by_density.body().inertia_array, by_mass.body().inertia_array)
    assert by_density.body().mass == pytest.approx(0.027, rel=1e-14)


def test_added_masses_count_by_the_parallel_axis_theorem() -> None:
    """Two masses μ at ±(x, y, 0) on the flat top of a design: the toy rattleback of
    docs/bodies.md, whose file holds the numbers derived by hand there."""
    toy = cs.load_body("toy_rattleback_10cm")
    design = cs.Design(
        length=0.1,
        width=0.02,
        height=0.01,
        density=1190.0,
        added_masses=(
            cs.AddedMass(1e-3, (0.03, 0.005, 0.0)),
            cs.AddedMass(1e-3, (-0.03, -0.005, 0.0)),
        ),
    )
    body = design.body()
    assert body.mass == pytest.approx(toy.mass, rel=1e-10)
    assert body.shape.com_offset == pytest.approx(toy.shape.com_offset, rel=1e-9)
    np.testing.assert_allclose(body.inertia_array, toy.inertia_array, rtol=2e-6, atol=1e-13)


@pytest.mark.parametrize("spin", [-5.0, 5.0])
def test_no_misalignment_no_reversal_in_rolling(spin: float) -> None:
    """Without misalignment nothing couples rocking to spin: the stone keeps its sense
    both ways; turned by 8°, the same stone reverses from -5 rad/s (the control)."""
    state = cs.InitialState(omega=(0.0, 0.0, spin), euler_angles=(0.5, 0.5))
    straight = cs.Design(**{**PRINTED, "misalignment": 0.0}).body()
    run = cs.simulate(cs.RollingModel(), straight, state, t_end=5.0).raise_for_status()
    assert run.first_reversal_time is None
    assert np.all(np.sign(run.dataset["spin"].values) == np.sign(spin))
    if spin < 0.0:
        turned = cs.simulate(cs.RollingModel(), cs.Design(**PRINTED).body(), state, t_end=5.0)
        assert turned.first_reversal_time is not None


REFUSED = [
    ({"height": 0.02}, "height", "centre of curvature"),  # G above b²/c
    ({"mass": None}, "mass", "either mass or density"),
    ({"density": 1200.0}, "mass", "either mass or density"),
    ({"misalignment": 50.0}, "misalignment", "(-45, 45)"),
    ({"length": -0.12}, "length", "> 0"),
    ({"width": math.nan}, "width", "> 0"),
    ({"mass": 0.001, "added_masses": [cs.AddedMass(0.001, (0.0, 0.0, -0.001))]}, "mass", "> 0.001"),
    ({"added_masses": [cs.AddedMass(0.001, (0.07, 0.0, 0.0))]}, "added_masses", "inside"),
    ({"added_masses": [cs.AddedMass(0.001, (0.0, 0.0, 0.001))]}, "added_masses", "inside"),
    ({"added_masses": [cs.AddedMass(0.001, (0.03, 0.0, 0.0))]}, "added_masses", "on axis 3"),
]


@pytest.mark.parametrize(("change", "name", "words"), REFUSED)
def test_refused_designs_name_the_parameter(change: dict, name: str, words: str) -> None:
    with pytest.raises(ParameterError) as caught:
        cs.Design(**{**PRINTED, **change})
    assert caught.value.name == name
    assert words in str(caught.value)
    assert "\n" not in str(caught.value)


def test_a_stone_that_cannot_stand_is_refused_at_its_bound() -> None:
    """A uniform solid stands while G (5c/8 above the contact) is below b²/c:
    c < b·sqrt(8/5); just below stands, just above is refused."""
    bound = 0.015 * math.sqrt(8.0 / 5.0)
    cs.Design(**{**PRINTED, "height": bound * (1 - 1e-9)})
    with pytest.raises(ParameterError, match="height"):
        cs.Design(**{**PRINTED, "height": bound * (1 + 1e-9)})


DESIGN_FILE = """\
title = "a design"
[design]
length = 0.12
width = 0.03
height = {height}
mass = 0.027
misalignment = 8.0
{extra}
"""


def test_the_shipped_design_file_loads_and_runs() -> None:
    body = cs.load_body("printed_stone_12cm")
    expected = cs.Design(**PRINTED).body()
    assert body.mass == expected.mass and body.inertia == expected.inertia
    assert body.shape == expected.shape
    assert load_design("printed_stone_12cm") == cs.Design(**PRINTED)
    state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
    sliding = cs.SlidingModel(friction_coefficient=0.3, friction_load="dynamic")
    run = cs.simulate(sliding, body, state, t_end=1.0).raise_for_status()
    assert run.dataset.attrs["body"] == "printed_stone_12cm"


def test_design_files_are_checked_in_one_line(tmp_path) -> None:
    path = tmp_path / "tall.toml"
    path.write_text(DESIGN_FILE.format(height=0.03, extra=""), encoding="utf-8")
    with pytest.raises(BodyFileError, match="height") as caught:
        cs.load_body(path)
    assert str(path) in str(caught.value) and "\n" not in str(caught.value)
    path.write_text(DESIGN_FILE.format(height=0.012, extra="heigth = 1"), encoding="utf-8")
    with pytest.raises(BodyFileError, match="did you mean"):
        cs.load_body(path)
    path.write_text(
        DESIGN_FILE.format(height=0.012, extra="[shape]\nkind = 'ellipsoid'"), encoding="utf-8"
    )
    with pytest.raises(BodyFileError, match=r"\[shape\] beside \[design\]"):
        cs.load_body(path)
    path.write_text(DESIGN_FILE.format(height='"0.012"', extra=""), encoding="utf-8")
    with pytest.raises(BodyFileError, match="not a number"):
        cs.load_body(path)
    rows = "added_masses = [[0.001, 0.03, 0.005, 0.0], [0.001, -0.03, -0.005, 0.0]]"
    path.write_text(DESIGN_FILE.format(height=0.012, extra=rows), encoding="utf-8")
    assert cs.load_body(path).mass == pytest.approx(0.027)


def test_bodies_show_prints_the_derived_numbers(capsys) -> None:
    assert main(["bodies", "show", "printed_stone_12cm", "--json"]) == 0
    numbers = json.loads(capsys.readouterr().out)
    body = cs.load_body("printed_stone_12cm")
    assert numbers["mass_kg"] == body.mass
    assert numbers["inertia_kg_m2"] == [list(row) for row in body.inertia]
    assert numbers["misalignment_angle_deg"] == pytest.approx(8.0, abs=1e-9)
    assert numbers["design"]["solid_density_kg_per_m3"] == pytest.approx(
        0.027 / ((2 / 3) * math.pi * 0.06 * 0.015 * 0.012)
    )
    assert main(["bodies", "show", "printed_stone_12cm"]) == 0
    assert "misalignment" in capsys.readouterr().out


def test_bodies_show_refuses_in_one_line(tmp_path, capsys) -> None:
    path = tmp_path / "tall.toml"
    path.write_text(DESIGN_FILE.format(height=0.03, extra=""), encoding="utf-8")
    assert main(["bodies", "show", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "height" in err
