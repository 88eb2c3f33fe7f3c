"""Convex surfaces a body can have, and the registry :data:`SHAPES` of them.

Each shape declares once (``bodies.declaration``) its kind, kernel code, body-file
entries with units, sweepable numbers, drawing and provenance; the body-file loader,
sweeps, run attributes and the viewer read :data:`SHAPES`. Adding a shape: a class
here, its ``ShapeCode`` and record fields named as its entries (``kernels/layout.py``)
and its branches in
``kernels/geometry.py`` and ``kernels/hertz.py`` (``docs/architecture.md``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Self

from celtstone.bodies.declaration import (
    KL_COM_OFFSET,
    KL_SEMI_AXES,
    DeclaredShape,
    Entry,
    SweepName,
)
from celtstone.bodies.function import ImplicitFunction
from celtstone.bodies.implicit_surface import ImplicitSurface
from celtstone.bodies.polynomial import ImplicitPolynomial
from celtstone.errors import ParameterError
from celtstone.kernels.layout import ShapeCode
from celtstone.simulation import schema

__all__ = [
    "SHAPES",
    "STORED_SHAPES",
    "Ellipsoid",
    "ImplicitFunction",
    "ImplicitPolynomial",
    "ImplicitSurface",
    "Paraboloid",
    "Shape",
    "Superellipsoid",
]

_Q = schema.PARAMETERS
_SEMI_AXES = Entry("semi_axes", _Q["semi_axes"], (3,))
_COM_OFFSET = Entry("com_offset", _Q["com_offset"])
_ABOUT_CENTRE_SWEEP = (
    SweepName("semi_axis_a", "semi_axes", "semi-axis a along body axis 1", 0),
    SweepName("semi_axis_b", "semi_axes", "semi-axis b along body axis 2", 1),
    SweepName("semi_axis_c", "semi_axes", "semi-axis c along body axis 3", 2),
    SweepName("com_offset", "com_offset", "G below the centre h"),
)


class _AboutCentre(DeclaredShape):
    """Kernel parameters and rest height of a shape given by semi-axes and offset h.

    h is the offset of G below the centre O (ellipsoid, superellipsoid).
    """

    semi_axes: tuple[float, float, float]
    com_offset: float

    def kernel_parameters(self) -> tuple[float, float, float, float]:
        """Give the shape numbers a run records (``body_shape_parameters``).

        Returns
        -------
        tuple of 4 float
            (a, b, c, h) [m].
        """
        a, b, c = self.semi_axes
        return (a, b, c, self.com_offset)

    @property
    def rest_height(self) -> float:
        """Height l of G above the contact point at rest, c - h [m]."""
        return self.semi_axes[2] - self.com_offset

    @property
    def bounding_radius(self) -> float:
        """A bound of the distance from G to the surface, max(a, b, c) + |h| [m]."""
        return max(self.semi_axes) + abs(self.com_offset)

    @property
    def volume(self) -> float:
        """8 a b c Γ(1 + 1/p)³ / Γ(1 + 3/p) [m³] (4/3 π a b c for p = 2)."""
        a, b, c = self.semi_axes
        p = getattr(self, "exponent", 2.0)
        return 8.0 * a * b * c * math.gamma(1.0 + 1.0 / p) ** 3 / math.gamma(1.0 + 3.0 / p)


@dataclass(frozen=True)
class Ellipsoid(_AboutCentre):
    """Ellipsoid x²/a² + y²/b² + z²/c² = 1 about its centre O.

    Parameters
    ----------
    semi_axes : tuple of 3 float
        (a, b, c), semi-axes along body axes 1, 2, 3 [m].
    com_offset : float
        Distance h of the centre of mass G below O along axis 3 [m]; G must lie
        inside the body, |h| < c.
    """

    semi_axes: tuple[float, float, float]
    com_offset: float

    kind = "ellipsoid"
    code = ShapeCode.ELLIPSOID
    surface = "x^2/a^2 + y^2/b^2 + z^2/c^2 = 1, G h below the centre"
    entries = (_SEMI_AXES, _COM_OFFSET)
    sweep_names = _ABOUT_CENTRE_SWEEP

    def __post_init__(self) -> None:
        if len(self.semi_axes) != 3:
            raise ParameterError("semi_axes", self.semi_axes, "three numbers a, b, c in m")
        axes = tuple(schema.check("semi_axes", value) for value in self.semi_axes)
        object.__setattr__(self, "semi_axes", axes)
        c = axes[2]
        allowed = f"a number in (-{c:g}, {c:g}) m"
        try:
            offset = float(self.com_offset)
        except (TypeError, ValueError):
            raise ParameterError("com_offset", self.com_offset, allowed) from None
        if not -c < offset < c:
            raise ParameterError("com_offset", self.com_offset, allowed, "G inside the body")
        object.__setattr__(self, "com_offset", offset)

    @classmethod
    def example(cls) -> Self:
        """Kane & Levinson's ellipsoid."""
        return cls(KL_SEMI_AXES, KL_COM_OFFSET)

    @property
    def radii_of_curvature(self) -> tuple[float, float]:
        """Radii of curvature ρ1 = a²/c, ρ2 = b²/c at the rest contact point [m]."""
        a, b, c = self.semi_axes
        return (a * a / c, b * b / c)


@dataclass(frozen=True)
class Paraboloid(DeclaredShape):
    """Paraboloid cap z = x²/(2ρ1) + y²/(2ρ2) about the rest contact point.

    Parameters
    ----------
    radii_of_curvature : tuple of 2 float
        (ρ1, ρ2), radii of curvature at the rest contact along body axes 1, 2 [m].
    com_height : float
        Height l of the centre of mass above the rest contact [m].

    Notes
    -----
    The cap is unbounded: the contact point exists for every n with n3 > 0; a run
    stops with a clear status if the vertical turns by 90° or more.
    """

    radii_of_curvature: tuple[float, float]
    com_height: float

    kind = "paraboloid"
    code = ShapeCode.PARABOLOID
    surface = "z = x^2/(2 rho1) + y^2/(2 rho2), G l above the rest contact"
    entries = (
        Entry("radii_of_curvature", _Q["radii_of_curvature"], (2,)),
        Entry("com_height", _Q["com_height"]),
    )
    sweep_names = (
        SweepName("radius_of_curvature_1", "radii_of_curvature", "rho1 along body axis 1", 0),
        SweepName("radius_of_curvature_2", "radii_of_curvature", "rho2 along body axis 2", 1),
        SweepName("com_height", "com_height", "G above the rest contact l"),
    )
    closed = False  # an unbounded cap: visual.scene draws it up to the run's contacts

    def __post_init__(self) -> None:
        if len(self.radii_of_curvature) != 2:
            raise ParameterError(
                "radii_of_curvature", self.radii_of_curvature, "two numbers rho1, rho2 in m"
            )
        radii = tuple(schema.check("radii_of_curvature", r) for r in self.radii_of_curvature)
        object.__setattr__(self, "radii_of_curvature", radii)
        object.__setattr__(self, "com_height", schema.check("com_height", self.com_height))

    @classmethod
    def example(cls) -> Self:
        """The cap of Kane & Levinson's ellipsoid at its rest contact (a²/c, b²/c, c - h)."""
        a, b, c = KL_SEMI_AXES
        return cls((a * a / c, b * b / c), c - KL_COM_OFFSET)

    def kernel_parameters(self) -> tuple[float, float, float, float]:
        """Give the shape numbers a run records (``body_shape_parameters``).

        Returns
        -------
        tuple of 4 float
            (ρ1, ρ2, l, 0) [m].
        """
        rho1, rho2 = self.radii_of_curvature
        return (rho1, rho2, self.com_height, 0.0)

    @property
    def rest_height(self) -> float:
        """Height l of G above the contact point at rest [m]."""
        return self.com_height


MAX_SUPERELLIPSOID_EXPONENT = 64.0  # beyond, |w|^(1/(p-1)) is a box to rounding
_EXPONENT = schema.Quantity(  # its range is checked by the class (with hints)
    "exponent", "p", "1", "superellipsoid exponent", lower=2.0, upper=MAX_SUPERELLIPSOID_EXPONENT
)


@dataclass(frozen=True)
class Superellipsoid(_AboutCentre):
    """Superellipsoid |x/a|^p + |y/b|^p + |z/c|^p = 1 about its centre O.

    Parameters
    ----------
    semi_axes : tuple of 3 float
        The semi-axes (a, b, c) [m], as for :class:`Ellipsoid`.
    com_offset : float
        G's offset h below O along axis 3 [m], |h| < c, as for :class:`Ellipsoid`.
    exponent : float
        Exponent p [1], in [2, 64]; p = 2 is the ellipsoid. p < 1 is not convex and
        1 <= p < 2 has edges (infinite curvature), so neither is accepted.

    Notes
    -----
    For p > 2 the surface is flat (zero curvature) at the six axis points, the rest
    contact among them: the rocking there is not harmonic and the rolling model has
    no linearisation about steady spin (``radii_of_curvature`` is infinite).
    """

    semi_axes: tuple[float, float, float]
    com_offset: float
    exponent: float

    kind = "superellipsoid"
    code = ShapeCode.SUPERELLIPSOID
    surface = "|x/a|^p + |y/b|^p + |z/c|^p = 1, G h below the centre"
    entries = (_SEMI_AXES, _COM_OFFSET, Entry("exponent", _EXPONENT))
    sweep_names = (
        *_ABOUT_CENTRE_SWEEP,
        SweepName("exponent", "exponent", "exponent p in [2, 64]"),
    )

    def __post_init__(self) -> None:
        ellipsoid = Ellipsoid(self.semi_axes, self.com_offset)  # the same checks
        object.__setattr__(self, "semi_axes", ellipsoid.semi_axes)
        object.__setattr__(self, "com_offset", ellipsoid.com_offset)
        allowed = f"a number in [2, {MAX_SUPERELLIPSOID_EXPONENT:g}]"
        try:
            exponent = float(self.exponent)
        except (TypeError, ValueError):
            raise ParameterError("exponent", self.exponent, allowed) from None
        if not 2.0 <= exponent <= MAX_SUPERELLIPSOID_EXPONENT:
            if exponent < 1.0:
                hint = "p < 1 gives a non-convex (star-shaped) surface"
            elif exponent < 2.0:
                hint = "1 <= p < 2 gives edges with infinite curvature, no unique contact rate"
            else:
                hint = ""
            raise ParameterError("exponent", self.exponent, allowed, hint)
        object.__setattr__(self, "exponent", exponent)

    @classmethod
    def example(cls) -> Self:
        """Kane & Levinson's ellipsoid as a superellipsoid of exponent 2.

        p > 2 is flat at the rest contact, where a run stops (docs/decisions.md §13).
        """
        return cls(KL_SEMI_AXES, KL_COM_OFFSET, 2.0)

    @property
    def radii_of_curvature(self) -> tuple[float, float]:
        """Radii of curvature at the rest contact [m]: a²/c, b²/c for p = 2, else infinite."""
        if self.exponent != 2.0:
            return (math.inf, math.inf)
        a, b, c = self.semi_axes
        return (a * a / c, b * b / c)


Shape = Ellipsoid | Paraboloid | Superellipsoid | ImplicitPolynomial | ImplicitFunction
"""Any shape of a body: the union of the shape classes (a type, for annotations)."""

SHAPES: dict[str, type[Shape]] = {
    cls.kind: cls
    for cls in (Ellipsoid, Paraboloid, Superellipsoid, ImplicitPolynomial, ImplicitFunction)
}
"""Every shape, by kind: the one list the loader, sweeps, the viewer and the tests read."""

STORED_SHAPES: tuple[str, ...] = tuple(kind for kind, cls in SHAPES.items() if cls.stored)
"""Kinds of the shapes given as numbers: in body files, run files and sweeps."""
