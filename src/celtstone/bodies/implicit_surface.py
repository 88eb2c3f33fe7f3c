"""What every body bounded by an implicit surface F(x) = 1 shares, whatever gives F.

Validated once here (bounded, G inside, strictly convex, resting upright) with the
Newton contact solve of ``kernels.implicit``, and packed into the kernel parameter
record (``kernels.layout``, docs/decisions.md sections 17 and 18). Subclasses say how F is
evaluated: ``bodies.polynomial.ImplicitPolynomial`` (terms, stored with the run) and
``bodies.function.ImplicitFunction`` (a user's compiled Python function).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from celtstone.bodies.declaration import DeclaredShape
from celtstone.errors import ParameterError
from celtstone.kernels import implicit
from celtstone.kernels.layout import ShapeCode, parameter_record

N_DIRECTIONS = 2000  # Fibonacci-sphere normals on which convexity is checked
RAY_LIMIT = 1e3  # m: a ray from G that has not left the body by then: unbounded
AXIS_TOLERANCE = 1e-9  # |x|, |y| of the rest contact relative to the body size
SUPPORT_TOLERANCE = 1e-9  # slack of the "lowest point" check, relative to the body size

Evaluate = Callable[[np.ndarray], np.ndarray]  # F at points of shape (k, 3) [m] -> (k,)


def fibonacci_directions(count: int = N_DIRECTIONS) -> np.ndarray:
    """``count`` nearly uniform unit vectors, shape (count, 3)."""
    k = np.arange(count) + 0.5
    z = 1.0 - 2.0 * k / count
    radius = np.sqrt(1.0 - z * z)
    angle = math.pi * (3.0 - math.sqrt(5.0)) * k
    return np.column_stack([radius * np.cos(angle), radius * np.sin(angle), z])


def ray_points(
    evaluate: Evaluate, centre: np.ndarray, directions: np.ndarray, parameter: str
) -> np.ndarray:
    """First crossing of F = 1 on rays from ``centre`` (F < 1 there), shape (k, 3) [m]."""
    low = np.zeros(len(directions))
    high = np.full(len(directions), 1e-6)
    outside = evaluate(centre + high[:, None] * directions) > 1.0
    while not outside.all():
        low = np.where(outside, low, high)
        high = np.where(outside, high, 2.0 * high)
        if high.max() > RAY_LIMIT:
            worst = directions[np.argmax(high)]
            raise ParameterError(
                parameter,
                "the surface",
                "a bounded body {F <= 1}",
                f"it extends beyond {RAY_LIMIT:g} m in the direction {np.round(worst, 3).tolist()}",
            )
        outside = evaluate(centre + high[:, None] * directions) > 1.0
    for _ in range(60):
        middle = 0.5 * (low + high)
        inside = evaluate(centre + middle[:, None] * directions) <= 1.0
        low = np.where(inside, middle, low)
        high = np.where(inside, high, middle)
    return centre + (0.5 * (low + high))[:, None] * directions


class ImplicitSurface(DeclaredShape):
    """Body {F(x) <= 1}, x about the origin O [m], G = (0, 0, -h) inside.

    Subclasses are frozen dataclasses with the fields ``com_offset``, ``start_centre``
    and ``start_semi_axes`` (the last two derived by :meth:`_validate`), and define
    ``parameter`` (the input named in errors), ``_evaluate`` and ``_level_fields``.
    """

    com_offset: float
    start_centre: tuple[float, float, float]
    start_semi_axes: tuple[float, float, float]
    parameter = "terms"

    def _evaluate(self, points: np.ndarray) -> np.ndarray:
        """F at ``points`` (k, 3) about O [m]."""
        raise NotImplementedError

    def _level_fields(self) -> dict[str, Any]:
        """The record fields that say how the kernels evaluate F (``kernels.layout``):
        the polynomial's terms, or the C address of a compiled function."""
        raise NotImplementedError

    def _prepare(self, surface_points: np.ndarray) -> None:
        """Hook run once the start ellipsoid and points on F = 1 (k, 3) [m] are known,
        before the first kernel call."""

    def _validate(self) -> None:
        """Check G inside, bounded, strictly convex and upright; set the start ellipsoid."""
        try:
            offset = float(self.com_offset)
        except (TypeError, ValueError):
            raise ParameterError("com_offset", self.com_offset, "a number in m") from None
        centre = np.array([0.0, 0.0, -offset])
        if not math.isfinite(offset) or not self._evaluate(centre[None, :])[0] < 1.0:
            raise ParameterError(
                "com_offset", self.com_offset, "a number in m with F(0, 0, -h) < 1", "G inside"
            )
        object.__setattr__(self, "com_offset", offset)
        points = ray_points(self._evaluate, centre, fibonacci_directions(), self.parameter)
        low, high = points.min(axis=0), points.max(axis=0)
        object.__setattr__(self, "start_centre", tuple(float(v) for v in 0.5 * (low + high)))
        object.__setattr__(self, "start_semi_axes", tuple(float(v) for v in 0.5 * (high - low)))
        self._prepare(points)
        self._check_convex(points)
        self._check_upright()

    # --- kernel packing -------------------------------------------------------

    code = ShapeCode.IMPLICIT

    def kernel_parameters(self) -> tuple[float, float, float, float]:
        """Give the shape numbers a run records (``body_shape_parameters``).

        The start ellipsoid is the box of the body's extents (derived, not an input).

        Returns
        -------
        tuple of 4 float
            (a0, b0, c0, h): start-ellipsoid semi-axes and h [m].
        """
        a, b, c = self.start_semi_axes
        return (a, b, c, self.com_offset)

    def kernel_fields(self) -> dict[str, Any]:
        """Give the fields of the kernel parameter record this shape sets.

        Returns
        -------
        dict of str to object
            Field name of ``kernels.layout`` -> value (SI).
        """
        return {
            "shape_code": self.code,
            "com_offset": self.com_offset,
            "start_centre": self.start_centre,
            "start_semi_axes": self.start_semi_axes,
            **self._level_fields(),
        }

    def kernel_record(self) -> np.record:
        """Make a parameter record with only the shape filled (for the geometry kernels).

        Returns
        -------
        numpy.record
            A record of ``kernels.layout``'s dtype.
        """
        return parameter_record(**self.kernel_fields())

    # --- geometry --------------------------------------------------------------

    @property
    def size(self) -> float:
        """Largest half-extent of the body [m]."""
        return max(self.start_semi_axes)

    def contact_point(self, n: tuple[float, float, float]) -> tuple[float, ...] | None:
        """Find the lowest point x* of the surface for an upward vertical.

        Parameters
        ----------
        n : tuple of 3 float
            Upward vertical in body axes [1], unit length.

        Returns
        -------
        tuple of 3 float or None
            The point x* about O [m], or None if the Newton solve did not converge.
        """
        x, _, _, _, ok = implicit.implicit_point(n, self.kernel_record())
        return tuple(x) if ok else None

    def _check_convex(self, points: np.ndarray) -> None:
        params = self.kernel_record()
        size = self.size
        normals = fibonacci_directions()
        for n in normals:
            x, _, _, _, ok = implicit.implicit_point((n[0], n[1], n[2]), params)
            lowest = float(np.min(points @ n))
            if not ok or float(np.dot(x, n)) > lowest + SUPPORT_TOLERANCE * size:
                outward = np.round(-n, 3).tolist()
                raise ParameterError(
                    self.parameter,
                    "the surface",
                    "a strictly convex closed surface F = 1",
                    f"not strictly convex where the outward normal is {outward}",
                )

    def _check_upright(self) -> None:
        x = self.contact_point((0.0, 0.0, 1.0))
        size = self.size
        if x is None:
            raise ParameterError(
                self.parameter, "the surface", "a surface curved at its lowest point (n = e3)"
            )
        if abs(x[0]) > AXIS_TOLERANCE * size or abs(x[1]) > AXIS_TOLERANCE * size:
            raise ParameterError(
                self.parameter,
                "the surface",
                "a lowest point (n = e3) on body axis 3",
                f"it is at x = {x[0]:.3g} m, y = {x[1]:.3g} m: the stone does not rest upright",
            )

    @property
    def bounding_radius(self) -> float:
        """The start box's size plus |h| [m], a bound of the distance from G to the surface."""
        return self.size + abs(self.com_offset)

    @property
    def rest_height(self) -> float:
        """Height l of G above the contact point at rest, -(z* + h) [m]."""
        x = self.contact_point((0.0, 0.0, 1.0))
        assert x is not None  # checked at construction
        return -(x[2] + self.com_offset)

    @property
    def radii_of_curvature(self) -> tuple[float, float]:
        """Normal radii of curvature along body axes 1, 2 at the rest contact, |∇F|/H_ii [m]."""
        _, _, gradient, hessian, _ = implicit.implicit_point((0.0, 0.0, 1.0), self.kernel_record())
        norm = math.sqrt(gradient[0] ** 2 + gradient[1] ** 2 + gradient[2] ** 2)
        return (norm / hessian[0], norm / hessian[4])
