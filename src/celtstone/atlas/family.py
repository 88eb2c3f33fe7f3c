"""A family of buildable stones: a homogeneous half-ellipsoid plus two point masses.

Every member is made the way ``docs/bodies.md`` makes the toy rattleback
(``toy_rattleback_10cm`` is a member): the lower half (z <= 0) of the ellipsoid
x²/a² + y²/b² + z²/c² = 1 of a material of density ρ, and two equal point masses μ set
into its flat top at (x0, y0, 0) and (−x0, −y0, 0). The masses make the product of
inertia that turns the long principal axis by the misalignment angle δ. The centre of
mass G, the mass and the central inertia tensor follow in closed form
(:func:`celtstone.bodies.design.half_ellipsoid_inertia`, shared with the body files'
``[design]`` form); ``docs/decisions.md`` §32 states the choices.

How the masses follow from δ: x0 = 0.6 a (the toy's 30 mm of 50 mm), μ = κ m_s (κ the
design's ``mass_fraction``, m_s the solid's mass), and y0 is solved so that the
principal axis turns by exactly δ: tan 2δ = 4 μ x0 y0 / (K − 2 μ y0²) with
K = m_s (a² − b²)/5 + 2 μ x0², a quadratic in y0 with one positive root. The root must
lie on the flat top with a margin: (x0/a)² + (y0/b)² <= 0.9² (an insert is not a point),
which bounds δ for a given κ; beyond it the design is refused, naming the largest δ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from celtstone.bodies import AddedMass, Body, Design
from celtstone.bodies.design import half_ellipsoid_inertia
from celtstone.contact import effective_modulus
from celtstone.errors import ParameterError

__all__ = [
    "LENGTH_RANGE",
    "MATERIALS",
    "MISALIGNMENT_RANGE",
    "POINT_MASS_X_FRACTION",
    "RIM_FRACTION",
    "TOY_MASS_FRACTION",
    "Material",
    "MaterialPair",
    "StoneDesign",
    "half_ellipsoid_inertia",
    "highest_height_ratio",
    "largest_misalignment",
]

LENGTH_RANGE = (0.05, 0.40)  # L [m], issue 15: stones from 5 cm to 40 cm
MISALIGNMENT_RANGE = (0.2, 10.0)  # δ [deg], issue 15
POINT_MASS_X_FRACTION = 0.6  # x0 / a: the toy's 0.030 m of a = 0.05 m (docs/bodies.md)
RIM_FRACTION = 0.9  # the masses lie within (x0/a)² + (y0/b)² <= 0.9² of the flat top
# κ = μ / m_s of the toy: 1 g each on a 12.4617 g PMMA shell (docs/bodies.md)
TOY_MASS_FRACTION = 1.0e-3 / (1190.0 * (2.0 / 3.0) * math.pi * 0.05 * 0.01 * 0.01)
PMMA_DENSITY = 1190.0  # kg/m³, cast acrylic, handbook value (docs/bodies.md)
GRAVITY = 9.81  # m/s², as every shipped body


@dataclass(frozen=True)
class Material:
    """An isotropic material and where its numbers come from.

    Parameters
    ----------
    name : str
        The key in :data:`MATERIALS` (``"pmma"``, ``"glass"``).
    density : float
        Density ρ [kg/m³].
    elastic_modulus : float
        Young's modulus E [Pa].
    poisson_ratio : float
        Poisson's ratio ν [1].
    source : str
        Where the numbers come from.
    """

    name: str
    density: float
    elastic_modulus: float
    poisson_ratio: float
    source: str


MATERIALS: dict[str, Material] = {
    m.name: m
    for m in (
        Material(
            "pmma",
            PMMA_DENSITY,
            3.0e9,
            0.35,
            "cast acrylic: handbook density (docs/bodies.md); E and ν of the realistic "
            "contact, docs/decisions.md §29",
        ),
        Material(
            "glass",
            2500.0,
            72.0e9,
            0.22,
            "soda-lime glass, handbook values (e.g. Shelby, Introduction to Glass Science "
            "and Technology, 2005, table 10.1: E ≈ 70–74 GPa, ν ≈ 0.22)",
        ),
    )
}
"""The materials of stone and plane by name: cast acrylic (``pmma``) and soda-lime glass
(``glass``), each with its source."""


@dataclass(frozen=True)
class MaterialPair:
    """A stone of one material on a plane of another, for the Hertz contact radius.

    Parameters
    ----------
    stone : str, default "pmma"
        The stone's material, a name of :data:`MATERIALS`.
    plane : str, default "glass"
        The plane's material, a name of :data:`MATERIALS`.

    Raises
    ------
    ParameterError
        When either is not a name of :data:`MATERIALS`.

    Notes
    -----
    The sliding model takes one E and ν for stone and plane, E* = E / (2(1 − ν²))
    (``contact.effective_modulus``); :meth:`model_settings` gives the pair's
    E* = 1 / ((1 − ν1²)/E1 + (1 − ν2²)/E2) (Johnson 1985, ch. 4) in that form, with
    ν = ν of the stone. Only E* enters the Hertz radius and ellipse.
    """

    stone: str = "pmma"
    plane: str = "glass"

    def __post_init__(self) -> None:
        for name, value in (("stone", self.stone), ("plane", self.plane)):
            if value not in MATERIALS:
                raise ParameterError(name, value, "one of: " + ", ".join(MATERIALS))

    @property
    def effective_modulus(self) -> float:
        """E* of the pair [Pa]."""
        first, second = MATERIALS[self.stone], MATERIALS[self.plane]
        compliance = (1.0 - first.poisson_ratio**2) / first.elastic_modulus
        compliance += (1.0 - second.poisson_ratio**2) / second.elastic_modulus
        return 1.0 / compliance

    def model_settings(self) -> dict[str, float]:
        """The settings of a sliding model whose E* is the pair's.

        Returns
        -------
        dict of str to float
            ``elastic_modulus`` E = 2(1 − ν²) E* [Pa] and ``poisson_ratio`` ν of the
            stone [1].
        """
        nu = MATERIALS[self.stone].poisson_ratio
        modulus = 2.0 * (1.0 - nu**2) * self.effective_modulus
        # the model's own E* of these numbers is the pair's (to round-off)
        assert math.isclose(effective_modulus(modulus, nu), self.effective_modulus)
        return {"elastic_modulus": modulus, "poisson_ratio": nu}


def _rim_y(half_width: float) -> float:
    """The largest y0 [m] of masses at x0 = 0.6 a within the rim margin, for half-width b."""
    return half_width * math.sqrt(RIM_FRACTION**2 - POINT_MASS_X_FRACTION**2)


def highest_height_ratio(width_ratio: float, mass_fraction: float) -> float:
    """The c/a [1] below which a stone of width ratio b/a and mass fraction κ rests upright.

    Rest is stable across when b²/c > c − h, with G's depth h = (3c/8) m_s/m and
    m_s/m = 1/(1 + 2κ), which gives c/a < (b/a)/sqrt(1 − 3/8 · m_s/m).
    """
    shell_share = 1.0 / (1.0 + 2.0 * mass_fraction)
    return width_ratio / math.sqrt(1.0 - 3.0 / 8.0 * shell_share)


def largest_misalignment(width_ratio: float, mass_fraction: float) -> float:
    """The largest δ [deg] two masses of fraction κ can make within the rim margin of a
    top of width ratio b/a (the masses at y0 on the rim margin; module docstring).

    Independent of L, c/a and ρ: every term of tan 2δ = 4 μ x0 y0 / (K − 2 μ y0²) scales
    as m_s a². Not capped by ``MISALIGNMENT_RANGE``.
    """
    a, b = 1.0, float(width_ratio)  # lengths in units of a, masses in units of m_s
    x0, y_max, mu = POINT_MASS_X_FRACTION * a, _rim_y(b), float(mass_fraction)
    stiffness = (a**2 - b**2) / 5.0 + 2.0 * mu * x0**2  # K / m_s
    return 0.5 * math.degrees(math.atan2(4.0 * mu * x0 * y_max, stiffness - 2 * mu * y_max**2))


def _in_range(name: str, value: float, low: float, high: float, unit: str) -> float:
    number = float(value)
    if not (math.isfinite(number) and low <= number <= high):
        raise ParameterError(name, value, f"a number in [{low:g}, {high:g}] {unit}".rstrip())
    return number


def _positive(name: str, value: float, unit: str, upper: float = math.inf) -> float:
    number = float(value)
    if not (math.isfinite(number) and 0.0 < number <= upper):
        bound = f"in (0, {upper:g}]" if math.isfinite(upper) else "> 0"
        raise ParameterError(name, value, f"a number {bound} {unit}".rstrip())
    return number


@dataclass(frozen=True)
class StoneDesign:
    """A buildable stone: a half-ellipsoid of one material plus two point masses.

    Parameters
    ----------
    length : float
        Length L = 2a of the stone [m], in [0.05, 0.40].
    width_ratio : float
        Ratio b/a [1], in (0, 1): the flat top's half-width b = width_ratio · a.
    height_ratio : float
        Ratio c/a [1], > 0: the depth c = height_ratio · a. The rest must be stable (the
        transverse radius of curvature b²/c above G's height c − h), which bounds it.
    misalignment : float
        Angle δ from the geometric long axis to the long principal axis [deg], in
        [0.2, 10], made by the point masses (module docstring).
    mass_fraction : float, default the toy's
        Ratio κ = μ / m_s of each point mass to the solid's mass [1], in (0, 1]; the
        toy's is 1 g on 12.46 g.
    density : float, default 1190
        Density ρ of the solid [kg/m³], > 0; the default is PMMA's.

    Raises
    ------
    ParameterError
        When a parameter is out of its range, the stone would not rest upright, or the
        masses cannot make δ within the rim (naming the largest δ they can).

    Notes
    -----
    The toy rattleback is ``StoneDesign(0.1, 0.2, 0.2, δ_toy)`` with δ_toy = 2.2006°
    (``tests/test_atlas_family.py``).
    """

    length: float
    width_ratio: float
    height_ratio: float
    misalignment: float
    mass_fraction: float = TOY_MASS_FRACTION
    density: float = PMMA_DENSITY

    def __post_init__(self) -> None:
        _in_range("length", self.length, *LENGTH_RANGE, "m")
        _in_range("misalignment", self.misalignment, *MISALIGNMENT_RANGE, "deg")
        _positive("mass_fraction", self.mass_fraction, "", upper=1.0)
        _positive("density", self.density, "kg/m^3")
        width = float(self.width_ratio)
        if not (math.isfinite(width) and 0.0 < width < 1.0):
            raise ParameterError("width_ratio", self.width_ratio, "a number in (0, 1)")
        highest = highest_height_ratio(width, self.mass_fraction)
        height = float(self.height_ratio)
        if not (math.isfinite(height) and 0.0 < height < highest):
            raise ParameterError(
                "height_ratio",
                self.height_ratio,
                f"a number in (0, {highest:.4g}) for width_ratio {width:g}",
                "a taller stone does not rest upright: b²/c must exceed G's height c − h",
            )
        _ = self.point_mass_position  # the masses must fit on the top: refused otherwise

    @property
    def semi_axes(self) -> tuple[float, float, float]:
        """(a, b, c) [m] of the full ellipsoid; the stone is its lower half."""
        a = 0.5 * self.length
        return (a, self.width_ratio * a, self.height_ratio * a)

    @property
    def shell_mass(self) -> float:
        """Mass m_s = ρ (2/3) π a b c of the solid half-ellipsoid [kg]."""
        a, b, c = self.semi_axes
        return self.density * (2.0 / 3.0) * math.pi * a * b * c

    @property
    def point_mass(self) -> float:
        """Mass μ = κ m_s of each of the two point masses [kg]."""
        return self.mass_fraction * self.shell_mass

    @property
    def point_mass_position(self) -> tuple[float, float]:
        """(x0, y0) [m]: x0 = 0.6 a, y0 the root that turns the principal axis by δ.

        Raises
        ------
        ParameterError
            naming ``misalignment`` and the largest δ the masses can make within
            the rim (module docstring), when δ is beyond it.
        """
        a, b, _ = self.semi_axes
        x0 = POINT_MASS_X_FRACTION * a
        mu = self.point_mass
        stiffness = self.shell_mass * (a**2 - b**2) / 5.0 + 2.0 * mu * x0**2  # K
        slope = math.tan(2.0 * math.radians(self.misalignment))  # tan 2δ
        ratio = stiffness / (2.0 * mu)
        # y0 = (−x0 + sqrt(x0² + t² K/(2μ))) / t, written without the cancellation
        y0 = slope * ratio / (x0 + math.sqrt(x0**2 + slope**2 * ratio))
        if y0 > _rim_y(b):
            largest = largest_misalignment(self.width_ratio, self.mass_fraction)
            raise ParameterError(
                "misalignment",
                self.misalignment,
                f"at most {largest:.3g} deg with mass_fraction {self.mass_fraction:.3g}",
                "heavier point masses (mass_fraction) turn the axis further",
            )
        return (x0, y0)

    @property
    def name(self) -> str:
        """A body name that says the design: ``stone_L0.1_b0.2_c0.2_d2.2``."""
        return (
            f"stone_L{self.length:.4g}_b{self.width_ratio:.4g}_c{self.height_ratio:.4g}"
            f"_d{self.misalignment:.4g}"
        )

    def design(self) -> Design:
        """The stone as a body file's ``[design]``.

        The half-ellipsoid, its principal axes unturned (δ 0), and the two point masses
        that turn them by δ.

        Returns
        -------
        Design
            The design (``celtstone.bodies.design``).
        """
        a, b, c = self.semi_axes
        x0, y0 = self.point_mass_position
        return Design(
            length=2.0 * a,
            width=2.0 * b,
            height=c,
            density=self.density,
            added_masses=(
                AddedMass(self.point_mass, (x0, y0, 0.0)),
                AddedMass(self.point_mass, (-x0, -y0, 0.0)),
            ),
            gravity=GRAVITY,
        )

    def body(self) -> Body:
        """The stone as a body.

        Returns
        -------
        Body
            An ellipsoid shape with G at depth h below its centre, the mass and central
            inertia of :meth:`design` (:func:`half_ellipsoid_inertia` in closed form).
        """
        x0, y0 = self.point_mass_position
        return self.design().body(
            self.name,
            source="celtstone atlas: half-ellipsoid plus two point masses (docs/bodies.md)",
            notes=(
                f"density {self.density:g} kg/m^3, point masses 2 x {self.point_mass:.4g} kg "
                f"at (+-{x0:.4g}, +-{y0:.4g}) m"
            ),
        )
