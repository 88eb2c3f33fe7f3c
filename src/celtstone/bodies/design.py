"""A stone from what can be measured on it: outer dimensions, mass, misalignment, masses.

A *design* is the lower half (z <= 0) of the ellipsoid x²/a² + y²/b² + z²/c² = 1 with
a = length/2, b = width/2 and c = height (its flat top at z = 0, as a toy rattleback's),
of uniform density, optionally with point masses set into it. Mass, centre of mass G
and central inertia follow in closed form (:func:`half_ellipsoid_inertia`); the
misalignment δ turns the solid's horizontal principal axes of inertia by δ about the
vertical against the axes of curvature (the geometric axes 1 and 2), as the inertia of a
stone whose mass is laid out askew to its rocking surface (Bondi 1986; Garcia & Hubbard
1988). The body file's ``[design]`` table (``bodies.file_schema``) and
``celtstone.atlas.StoneDesign`` build their bodies here; ``docs/bodies.md`` derives the
formulas and works an example.

A design that cannot stand is refused: G must lie below the centres of curvature of the
rest contact, l = c − h < min(a²/c, b²/c), h the depth of G below the ellipsoid's
centre.

References
----------
.. [1] H. Bondi, "The rigid body dynamics of unidirectional spin", Proc. R. Soc. Lond. A
   405 (1986) 265–274, doi:10.1098/rspa.1986.0052.
.. [2] M. Garcia and M. Hubbard, "Spin reversal of the rattleback: theory and
   experiment", Proc. R. Soc. Lond. A 418 (1988) 165–197, doi:10.1098/rspa.1988.0078.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from celtstone.bodies.body import Body
from celtstone.bodies.shapes import Ellipsoid
from celtstone.errors import ParameterError
from celtstone.simulation import schema

__all__ = [
    "DESIGN_QUANTITIES",
    "AddedMass",
    "Design",
    "half_ellipsoid_inertia",
]


def _positive(name: str, symbol: str, unit: str, description: str) -> schema.Quantity:
    return schema.Quantity(name, symbol, unit, description, lower=0.0, lower_open=True)


DESIGN_QUANTITIES: dict[str, schema.Quantity] = {
    q.name: q
    for q in (
        _positive("length", "L", "m", "length 2a of the stone along axis 1"),
        _positive("width", "W", "m", "width 2b of the stone along axis 2"),
        _positive("height", "H", "m", "height c from the rest contact to the flat top"),
        _positive("density", "ρ", "kg/m^3", "density of the solid"),
        schema.Quantity(
            "misalignment",
            "δ",
            "deg",
            "angle from the axes of curvature to the solid's principal axes of inertia",
            lower=-45.0,
            upper=45.0,
            lower_open=True,
            upper_open=True,
        ),
        schema.Quantity("added_masses", "μ, x, y, z", "kg, m", "point masses set into the solid"),
    )
}
"""The numbers of a design, with their units and ranges (the ``[design]`` table's)."""


def half_ellipsoid_inertia(
    semi_axes: tuple[float, float, float],
    density: float,
    point_mass: float,
    position: tuple[float, float],
) -> tuple[float, float, tuple[tuple[float, float, float], ...]]:
    """Mass, centre of mass and inertia of a half-ellipsoid with two point masses on top.

    The lower half (z <= 0) of an ellipsoid, the masses on its flat top.

    Parameters
    ----------
    semi_axes : tuple of 3 float
        Semi-axes (a, b, c) of the full ellipsoid [m].
    density : float
        Density ρ of the solid [kg/m³].
    point_mass : float
        Mass μ of each of the two point masses [kg].
    position : tuple of 2 float
        Position (x0, y0) [m]: the masses sit at (x0, y0, 0) and (−x0, −y0, 0).

    Returns
    -------
    mass : float
        Mass m = m_s + 2μ [kg].
    depth : float
        Depth h of the centre of mass G below the centre O [m].
    inertia : tuple of 3 tuples of 3 float
        Central inertia tensor in body axes [kg m²], shape (3, 3).

    Notes
    -----
    docs/bodies.md, "toy_rattleback_10cm": m_s = ρ (2/3) π a b c; the half's centroid
    3c/8 below O, so h = (3c/8) m_s / m; second moments about O m_s a²/5, m_s b²/5,
    m_s c²/5; the parallel-axis theorem along axis 3 (G on it):
    A = m_s(b²+c²)/5 + 2μy0² − m h², B = m_s(a²+c²)/5 + 2μx0² − m h²,
    C = m_s(a²+b²)/5 + 2μ(x0²+y0²), I12 = −2 μ x0 y0.
    """
    a, b, c = semi_axes
    x0, y0 = position
    shell = density * (2.0 / 3.0) * math.pi * a * b * c
    mass = shell + 2.0 * point_mass
    depth = 3.0 * c / 8.0 * shell / mass
    first = shell * (b**2 + c**2) / 5.0 + 2.0 * point_mass * y0**2 - mass * depth**2
    second = shell * (a**2 + c**2) / 5.0 + 2.0 * point_mass * x0**2 - mass * depth**2
    third = shell * (a**2 + b**2) / 5.0 + 2.0 * point_mass * (x0**2 + y0**2)
    product = -2.0 * point_mass * x0 * y0
    inertia = ((first, product, 0.0), (product, second, 0.0), (0.0, 0.0, third))
    return mass, depth, inertia


@dataclass(frozen=True)
class AddedMass:
    """A point mass set into a design.

    Parameters
    ----------
    mass : float
        Its mass μ [kg], > 0.
    position : tuple of 3 float
        Where it sits (x, y, z) [m], body axes about the ellipsoid's centre O (the middle
        of the flat top); inside the solid: z <= 0 and x²/a² + y²/b² + z²/c² <= 1.
    """

    mass: float
    position: tuple[float, float, float]


def _number(name: str, value: object) -> float:
    """``value`` checked against the range of :data:`DESIGN_QUANTITIES` ``name``."""
    quantity = DESIGN_QUANTITIES[name]
    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        number = math.nan
    low, high = quantity.lower, quantity.upper
    inside = (low < number if quantity.lower_open else low <= number) and (
        number < high if quantity.upper_open else number <= high
    )
    if not (math.isfinite(number) and inside):
        unit = f" {quantity.unit}" if quantity.unit else ""
        raise ParameterError(name, value, quantity.allowed + unit)
    return number


@dataclass(frozen=True)
class Design:
    """A stone given by what can be measured on it (module docstring).

    Parameters
    ----------
    length, width, height : float
        Outer dimensions L = 2a, W = 2b and H = c of the half-ellipsoid [m], > 0.
    misalignment : float
        Angle δ from the axes of curvature to the solid's long principal axis of inertia,
        turned about the vertical [deg], in (−45, 45); positive turns axis 1 towards
        axis 2, and gives I12 < 0 as Kane & Levinson's body (``Body.misalignment_angle``).
    mass : float, optional
        Total mass m [kg], added masses included; give ``mass`` or ``density``.
    density : float, optional
        Density ρ of the solid [kg/m³].
    added_masses : sequence of AddedMass, optional
        Point masses set into the solid; together they must keep G on axis 3
        (Σ μ x = Σ μ y = 0, as masses in pairs at ±(x, y, z)).
    gravity : float, default 9.81
        Gravitational acceleration g [m/s²].

    Raises
    ------
    ParameterError
        For a number out of its range, both or neither of mass and density, an added
        mass outside the solid or off balance, masses heavier than the stone, or a
        stone that cannot stand (G above a centre of curvature of the rest contact).
    """

    length: float
    width: float
    height: float
    misalignment: float = 0.0
    mass: float | None = None
    density: float | None = None
    added_masses: Sequence[AddedMass] = field(default_factory=tuple)
    gravity: float = 9.81

    def __post_init__(self) -> None:
        for name in ("length", "width", "height", "misalignment"):
            object.__setattr__(self, name, _number(name, getattr(self, name)))
        object.__setattr__(self, "gravity", schema.check("gravity", self.gravity))
        if (self.mass is None) == (self.density is None):
            raise ParameterError(
                "mass", self.mass, "either mass or density (one of them, not both)"
            )
        if self.density is not None:
            object.__setattr__(self, "density", _number("density", self.density))
        object.__setattr__(self, "added_masses", tuple(self.added_masses))
        self._check_added_masses()
        if self.mass is not None:
            total = schema.check("mass", self.mass)
            added = sum(m.mass for m in self.added_masses)
            if not total > added:
                raise ParameterError(
                    "mass", self.mass, f"a number > {added:g} kg, the added masses' sum"
                )
            object.__setattr__(self, "mass", total)
        self._check_standing()

    @property
    def semi_axes(self) -> tuple[float, float, float]:
        """(a, b, c) [m] of the full ellipsoid; the stone is its lower half."""
        return (0.5 * self.length, 0.5 * self.width, self.height)

    @property
    def volume(self) -> float:
        """Volume (2/3) π a b c of the solid [m³]."""
        a, b, c = self.semi_axes
        return (2.0 / 3.0) * math.pi * a * b * c

    @property
    def solid_mass(self) -> float:
        """Mass m_s of the solid, without the added masses [kg]."""
        if self.density is not None:
            return self.density * self.volume
        return float(self.mass) - sum(m.mass for m in self.added_masses)  # type: ignore[arg-type]

    @property
    def solid_density(self) -> float:
        """Density ρ = m_s / volume of the solid [kg/m³]."""
        return self.solid_mass / self.volume

    def _check_added_masses(self) -> None:
        a, b, c = self.semi_axes
        for added in self.added_masses:
            mu = float(added.mass)
            x, y, z = (float(v) for v in added.position)
            if not (math.isfinite(mu) and mu > 0.0):
                raise ParameterError("added_masses", added.mass, "masses > 0 kg")
            inside = z <= 0.0 and (x / a) ** 2 + (y / b) ** 2 + (z / c) ** 2 <= 1.0
            if not inside:
                raise ParameterError(
                    "added_masses",
                    [x, y, z],
                    "a position inside the solid: z <= 0 and x²/a² + y²/b² + z²/c² <= 1 (m)",
                )
        moment = np.sum([[m.mass * p for p in m.position[:2]] for m in self.added_masses], 0)
        scale = sum(m.mass for m in self.added_masses) * max(a, b)
        if self.added_masses and np.max(np.abs(moment)) > 1e-12 * scale:
            raise ParameterError(
                "added_masses",
                [[m.mass, *m.position] for m in self.added_masses],
                "masses that keep G on axis 3: Σ μ x = Σ μ y = 0",
                "set them in pairs at (x, y, z) and (−x, −y, z)",
            )

    def properties(self) -> tuple[float, float, np.ndarray]:
        """Mass, depth of G and central inertia of the design.

        Returns
        -------
        mass : float
            Total mass m [kg].
        depth : float
            Depth h of G below the ellipsoid's centre O [m].
        inertia : numpy.ndarray
            Central inertia tensor in body axes [kg m²], shape (3, 3).

        Notes
        -----
        The solid's (``half_ellipsoid_inertia`` without masses), its horizontal block
        turned by δ: I' = R diag(A, B) Rᵀ, R the rotation by δ about axis 3, so that
        I12 = (A − B) sin δ cos δ; each added mass μ at r adds μ (|r|² 1 − r rᵀ) about O,
        and the parallel-axis theorem moves the sum to G.
        """
        solid = self.solid_mass
        rho = solid / self.volume
        _, solid_depth, solid_inertia = half_ellipsoid_inertia(self.semi_axes, rho, 0.0, (0, 0))
        tensor = np.array(solid_inertia) + solid * solid_depth**2 * np.diag([1.0, 1.0, 0.0])
        turn = math.radians(self.misalignment)
        rotation = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
        tensor[:2, :2] = rotation @ tensor[:2, :2] @ rotation.T  # about O, axis 3 unmoved
        mass = solid
        moment_z = -solid * solid_depth  # Σ m z about O
        for added in self.added_masses:
            r = np.asarray(added.position, dtype=float)
            tensor += added.mass * (np.dot(r, r) * np.eye(3) - np.outer(r, r))
            mass += added.mass
            moment_z += added.mass * r[2]
        depth = -moment_z / mass
        tensor -= mass * depth**2 * np.diag([1.0, 1.0, 0.0])  # to G = (0, 0, −h)
        return mass, depth, tensor

    def _check_standing(self) -> None:
        a, b, c = self.semi_axes
        _, depth, _ = self.properties()
        height_of_g = c - depth
        curvature = min(a * a / c, b * b / c)
        if not height_of_g < curvature:
            raise ParameterError(
                "height",
                self.height,
                f"a stone whose centre of mass lies below its centre of curvature: G is "
                f"{height_of_g * 1e3:.4g} mm above the contact, the centre of curvature "
                f"min(a², b²)/c = {curvature * 1e3:.4g} mm",
                "a lower or wider stone, or added masses set lower, stands",
            )

    def body(self, name: str = "design", **provenance: object) -> Body:
        """The stone as a body.

        Parameters
        ----------
        name : str, optional
            The body's name.
        **provenance
            ``source``, ``notes`` and ``citation`` of :class:`Body`.

        Returns
        -------
        Body
            An ellipsoid shape with G at depth h below its centre, the design's mass and
            central inertia.
        """
        mass, depth, inertia = self.properties()
        return Body(
            name=name,
            mass=mass,
            inertia=tuple(tuple(float(v) for v in row) for row in inertia),  # type: ignore[arg-type]
            shape=Ellipsoid(semi_axes=self.semi_axes, com_offset=depth),
            gravity=self.gravity,
            **provenance,  # type: ignore[arg-type]
        )
