"""The rigid body: mass, central inertia tensor and convex surface."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from celtstone.bodies.shapes import Shape
from celtstone.errors import ParameterError
from celtstone.simulation import schema

__all__ = ["Body"]

Matrix3 = tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]


@dataclass(frozen=True)
class Body:
    """A convex rigid body on a horizontal plane.

    Parameters
    ----------
    name : str
        Identifier, e.g. the parameter file's stem.
    mass : float
        Mass m [kg], > 0.
    inertia : tuple of 3 tuples of 3 float
        Central inertia tensor A in body axes [kg m²], shape (3, 3), symmetric and
        positive-definite, with principal moments obeying the triangle inequality.
    shape : Ellipsoid, Paraboloid, Superellipsoid, ImplicitPolynomial or ImplicitFunction
        The convex surface.
    gravity : float
        Gravitational acceleration g [m/s²], > 0.
    source : str
        Citation of the parameter set.
    notes : str
        Conversions made from the source.
    citation : dict of str to str
        The source as BibTeX fields (``celtstone cite``).
    """

    name: str
    mass: float
    inertia: Matrix3
    shape: Shape
    gravity: float = 9.81
    source: str = ""
    notes: str = ""
    citation: dict[str, str] = field(default_factory=dict, compare=False, hash=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", schema.check("mass", self.mass))
        object.__setattr__(self, "gravity", schema.check("gravity", self.gravity))
        try:
            tensor = np.asarray(self.inertia, dtype=float)
        except (TypeError, ValueError):
            raise ParameterError("inertia", self.inertia, "a 3x3 matrix in kg m^2") from None
        if tensor.shape != (3, 3) or not np.all(np.isfinite(tensor)):
            raise ParameterError("inertia", self.inertia, "a finite 3x3 matrix in kg m^2")
        if not np.allclose(tensor, tensor.T, rtol=1e-12, atol=0.0):
            raise ParameterError("inertia", self.inertia, "a symmetric matrix (A = A^T)")
        principal = np.linalg.eigvalsh(tensor)
        if principal[0] <= 0.0:
            raise ParameterError(
                "inertia",
                self.inertia,
                "a positive-definite matrix",
                f"its smallest principal moment is {principal[0]:.3g} kg m^2",
            )
        if principal[2] > principal[0] + principal[1] * (1 + 1e-12):
            raise ParameterError(
                "inertia",
                self.inertia,
                "principal moments with A3 <= A1 + A2 (a real mass distribution)",
            )
        object.__setattr__(self, "inertia", tuple(tuple(float(v) for v in row) for row in tensor))

    @property
    def inertia_array(self) -> np.ndarray:
        """Central inertia tensor as a (3, 3) array [kg m²]."""
        return np.array(self.inertia)

    @property
    def rocking_periods(self) -> tuple[float, float]:
        """Periods of small rocking at rest without spin [s]: pitch and roll.

        Pitch is about body axis 2 (the long axis 1 tips), roll about axis 1. A rigid
        body rolling on its rest contact, G at height l above it, the surface's radius
        of curvature ρ along the rocking plane: 2π √((A_jj + m l²) / (m g (ρ − l))),
        with A_jj the central moment about the rocking axis (products of inertia, which
        couple the two, are left out: they shift the periods by a few per cent). ``inf``
        where ρ <= l: the rest is not stable in that plane and the body does not rock;
        0 where ρ is infinite (a flat pole, as a superellipsoid's with exponent > 2:
        small rocking there has no period of its own, it shortens with the amplitude).
        """
        height = self.shape.rest_height
        first, second = (float(r) for r in self.shape.radii_of_curvature)
        periods = []
        for radius, moment in ((first, self.inertia[1][1]), (second, self.inertia[0][0])):
            lever = radius - height
            if not lever > 0.0:
                periods.append(math.inf)
                continue
            ratio = (moment + self.mass * height**2) / (self.mass * self.gravity * lever)
            periods.append(2.0 * math.pi * math.sqrt(ratio))
        return periods[0], periods[1]

    @property
    def rocking_period(self) -> float:
        """The longest finite period of :attr:`rocking_periods` [s].

        The window over which a reversal averages the spin (``celtstone.simulation.reversals``); 0
        (no averaging: the raw spin's reversals) if the body rocks in neither plane or
        has a flat pole.
        """
        finite = [p for p in self.rocking_periods if math.isfinite(p)]
        return max(finite) if finite else 0.0

    @property
    def misalignment_angle(self) -> float:
        """Angle from body axis 1 to the horizontal principal axis nearest it [rad]."""
        _, vectors = np.linalg.eigh(self.inertia_array[:2, :2])
        axis = vectors[:, np.argmax(np.abs(vectors[0]))]
        axis = axis if axis[0] > 0 else -axis
        return float(np.arctan2(axis[1], axis[0]))
