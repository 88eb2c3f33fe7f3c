"""The atlas's family of stones: a half-ellipsoid plus two point masses (docs/bodies.md).

Oracles: the mass, centre of mass and inertia tensor by an independent numerical
integration over the half-ellipsoid (Gauss–Legendre, the general tensor form of the
point masses and of the shift to G); the angle asked against ``Body.misalignment_angle``;
the toy rattleback's file (docs/bodies.md) as a member; Johnson's E* of two materials.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import celtstone as cs
from celtstone.atlas import MATERIALS, MaterialPair, StoneDesign, half_ellipsoid_inertia
from celtstone.atlas.family import POINT_MASS_X_FRACTION

DESIGNS = [
    StoneDesign(0.1, 0.2, 0.2, 2.0),
    StoneDesign(0.05, 0.3, 0.15, 0.2, density=2500.0),
    StoneDesign(0.4, 0.12, 0.08, 4.0, mass_fraction=0.5),
    StoneDesign(0.25, 0.5, 0.3, 10.0, mass_fraction=0.4),
]


def _integrated(design: StoneDesign) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass [kg], centre of mass [m] and central inertia tensor [kg m²] of ``design`` by
    Gauss–Legendre quadrature over the lower half-ellipsoid in scaled spherical
    coordinates, plus the two point masses, all in the general tensor form."""
    a, b, c = design.semi_axes
    radius, w_r = np.polynomial.legendre.leggauss(12)
    polar, w_t = np.polynomial.legendre.leggauss(24)
    azimuth, w_p = np.polynomial.legendre.leggauss(48)
    r = 0.5 * (radius + 1.0)  # r in [0, 1]
    theta = 0.25 * math.pi * (polar + 3.0)  # θ in [π/2, π]: the lower half
    phi = math.pi * (azimuth + 1.0)  # φ in [0, 2π]
    weights = (0.5 * w_r)[:, None, None] * (0.25 * math.pi * w_t)[None, :, None]
    weights = weights * (math.pi * w_p)[None, None, :]
    rr, tt, pp = np.meshgrid(r, theta, phi, indexing="ij")
    points = np.stack(
        [
            a * rr * np.sin(tt) * np.cos(pp),
            b * rr * np.sin(tt) * np.sin(pp),
            c * rr * np.cos(tt),
        ]
    )
    dm = design.density * a * b * c * rr**2 * np.sin(tt) * weights
    masses = [dm.ravel()]
    positions = [points.reshape(3, -1)]
    x0, y0 = design.point_mass_position
    masses.append(np.full(2, design.point_mass))
    positions.append(np.array([[x0, -x0], [y0, -y0], [0.0, 0.0]]))
    m = np.concatenate(masses)
    p = np.concatenate(positions, axis=1)
    total = m.sum()
    centre = p @ m / total
    about_o = np.sum(m * np.sum(p * p, axis=0)) * np.eye(3) - (p * m) @ p.T
    shift = total * (centre @ centre * np.eye(3) - np.outer(centre, centre))
    return total, centre, about_o - shift


@pytest.mark.parametrize("design", DESIGNS, ids=lambda d: d.name)
def test_mass_centre_and_inertia_equal_an_independent_integration(design: StoneDesign) -> None:
    mass, centre, inertia = _integrated(design)
    body = design.body()
    assert body.mass == pytest.approx(mass, rel=1e-12)
    np.testing.assert_allclose(
        centre, [0.0, 0.0, -body.shape.com_offset], atol=1e-12 * design.length
    )
    np.testing.assert_allclose(
        body.inertia_array, inertia, rtol=0, atol=1e-11 * np.abs(inertia).max()
    )


@pytest.mark.parametrize("design", DESIGNS, ids=lambda d: d.name)
def test_the_principal_axis_turns_by_the_angle_asked(design: StoneDesign) -> None:
    body = design.body()
    assert math.degrees(body.misalignment_angle) == pytest.approx(design.misalignment, rel=1e-10)
    x0, y0 = design.point_mass_position
    a, b, _ = design.semi_axes
    assert x0 == pytest.approx(POINT_MASS_X_FRACTION * a)
    assert (x0 / a) ** 2 + (y0 / b) ** 2 <= 0.9**2 + 1e-12  # on the flat top, inside the rim
    assert all(math.isfinite(p) for p in body.rocking_periods)  # it rests upright, rocks


def test_the_toy_rattleback_is_a_member() -> None:
    """docs/bodies.md: 10 cm, b = c = 1 cm, PMMA, two 1 g masses at (30, 5) mm; its file
    keeps 7 significant digits of the inertia, 11 of the mass and of h."""
    toy = cs.load_body("toy_rattleback_10cm")
    design = StoneDesign(0.1, 0.2, 0.2, math.degrees(toy.misalignment_angle))
    body = design.body()
    assert design.point_mass == pytest.approx(1.0e-3, rel=1e-12)
    np.testing.assert_allclose(design.point_mass_position, (0.030, 0.005), rtol=1e-6)
    assert body.mass == pytest.approx(toy.mass, rel=1e-10)
    assert body.shape.semi_axes == pytest.approx(toy.shape.semi_axes, rel=1e-15)
    assert body.shape.com_offset == pytest.approx(toy.shape.com_offset, rel=1e-10)
    np.testing.assert_allclose(body.inertia_array, toy.inertia_array, rtol=1e-6, atol=1e-13)
    assert body.rocking_period == pytest.approx(toy.rocking_period, rel=1e-6)


def test_the_closed_forms_of_the_toy_by_hand() -> None:
    """docs/bodies.md's numbers: m_s = 12.4617 g, h = 3.2314 mm, D = −3.0e-7 kg m²."""
    mass, depth, inertia = half_ellipsoid_inertia((0.05, 0.01, 0.01), 1190.0, 1e-3, (0.03, 0.005))
    assert mass - 2e-3 == pytest.approx(12.4617e-3, rel=1e-5)
    assert depth == pytest.approx(3.2314e-3, rel=1e-4)
    assert inertia[0][1] == pytest.approx(-3.0e-7, rel=1e-12)
    assert inertia[1][1] == pytest.approx(8.12905e-6, rel=1e-6)


@pytest.mark.parametrize(
    ("settings", "name", "words"),
    [
        ({"length": 0.04}, "length", r"\[0.05, 0.4\] m"),
        ({"length": 0.5}, "length", r"\[0.05, 0.4\] m"),
        ({"misalignment": 0.1}, "misalignment", r"\[0.2, 10\] deg"),
        ({"misalignment": 12.0}, "misalignment", r"\[0.2, 10\] deg"),
        ({"misalignment": 5.0}, "misalignment", "at most 2.99 deg"),  # too light to turn 5°
        ({"width_ratio": 1.0}, "width_ratio", r"\(0, 1\)"),
        ({"height_ratio": 0.25}, "height_ratio", "does not rest upright"),
        ({"mass_fraction": 0.0}, "mass_fraction", r"\(0, 1\]"),
        ({"density": -1.0}, "density", "> 0 kg/m"),
    ],
)
def test_impossible_stones_are_refused_naming_the_parameter(
    settings: dict[str, float], name: str, words: str
) -> None:
    values = {"length": 0.1, "width_ratio": 0.2, "height_ratio": 0.2, "misalignment": 2.0}
    values.update(settings)
    with pytest.raises(cs.ParameterError, match=words) as caught:
        StoneDesign(**values)
    assert caught.value.name == name


def test_a_material_pair_gives_the_model_its_effective_modulus() -> None:
    """Johnson (1985), ch. 4: 1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2."""
    pmma, glass = MATERIALS["pmma"], MATERIALS["glass"]
    expected = 1.0 / (
        (1 - pmma.poisson_ratio**2) / pmma.elastic_modulus
        + (1 - glass.poisson_ratio**2) / glass.elastic_modulus
    )
    model = cs.SlidingModel(**MaterialPair("pmma", "glass").model_settings())
    assert model.effective_modulus == pytest.approx(expected, rel=1e-14)
    same = cs.SlidingModel(**MaterialPair("pmma", "pmma").model_settings())
    assert same.effective_modulus == pytest.approx(pmma.elastic_modulus / (2 * (1 - 0.35**2)))
    with pytest.raises(cs.ParameterError, match="plane"):
        MaterialPair("pmma", "granite")


def test_the_atlas_stone_follows_from_its_derivation_and_its_design() -> None:
    """``atlas_stone_25cm`` (docs/bodies.md): its mass, G and inertia are the independent
    integration's of its [derivation] table, its design's, and the design is the one the
    stored refined search found with all five findings "yes" (PMMA on glass)."""
    import tomllib
    from importlib import resources

    from celtstone.atlas.search import STORED_SEARCHES, stored_search
    from celtstone.reproduce.study import ATLAS_STONE_STUDY

    text = resources.files("celtstone.bodies").joinpath("data/atlas_stone_25cm.toml")
    derivation = tomllib.loads(text.read_text(encoding="utf-8"))["derivation"]
    body = cs.load_body("atlas_stone_25cm")
    design = StoneDesign(0.2461, 0.5074, 0.1331, 1.336, 0.1222)
    assert tuple(derivation["semi_axes"]) == design.semi_axes == body.shape.semi_axes
    assert derivation["point_mass"] == pytest.approx(design.point_mass, rel=1e-15)
    assert tuple(derivation["point_mass_position"]) == design.point_mass_position
    mass, centre, inertia = _integrated(design)
    assert body.mass == pytest.approx(mass, rel=1e-9)
    assert body.shape.com_offset == pytest.approx(-centre[2], rel=1e-8)
    np.testing.assert_allclose(body.inertia_array, inertia, rtol=1e-8, atol=1e-15)
    assert math.degrees(body.misalignment_angle) == pytest.approx(design.misalignment)
    search = stored_search(STORED_SEARCHES["refined"])
    assert search is not None
    found = [
        d
        for d in search["full"]
        if all(v == "yes" for v in d["verdicts"].values()) and d["name"] == design.name
    ]
    assert [d["contact"] for d in found] == ["hertz_pmma_glass"]
    # the study's E and ν are those of the atlas's PMMA-on-glass pair
    settings = MaterialPair("pmma", "glass").model_settings()
    assert ATLAS_STONE_STUDY.elastic_modulus == pytest.approx(settings["elastic_modulus"])
    assert ATLAS_STONE_STUDY.poisson_ratio == settings["poisson_ratio"]
    assert ATLAS_STONE_STUDY.contact == "hybrid"
