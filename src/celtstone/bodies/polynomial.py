"""A convex body bounded by an implicit polynomial surface F(x) = 1.

The contact point is found by the Newton solve of ``kernels.implicit``; this
module validates the polynomial once (bounded, G inside, strictly convex, resting
upright) and packs it for the kernels (layout in ``kernels.layout``, the choice
in docs/decisions.md section 17).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from celtstone.errors import ParameterError
from celtstone.kernels import implicit, layout

__all__ = ["ImplicitPolynomial"]

N_DIRECTIONS = 2000  # Fibonacci-sphere normals on which convexity is checked
MAX_EXPONENT = 16  # per variable; enough for superellipsoids up to p = 16
MAX_TERMS = 64
RAY_LIMIT = 1e3  # m: a ray from G that has not left the body by then: unbounded
AXIS_TOLERANCE = 1e-9  # |x|, |y| of the rest contact relative to the body size
SUPPORT_TOLERANCE = 1e-9  # slack of the "lowest point" check, relative to the body size

Term = tuple[float, int, int, int]


def fibonacci_directions(count: int = N_DIRECTIONS) -> np.ndarray:
    """``count`` nearly uniform unit vectors, shape (count, 3)."""
    k = np.arange(count) + 0.5
    z = 1.0 - 2.0 * k / count
    radius = np.sqrt(1.0 - z * z)
    angle = math.pi * (3.0 - math.sqrt(5.0)) * k
    return np.column_stack([radius * np.cos(angle), radius * np.sin(angle), z])


def _term(entry: object) -> Term:
    allowed = "[c, i, j, k]: a finite coefficient c and exponents i, j, k in 0..16"
    try:
        values = list(entry)  # type: ignore[call-overload]
        coefficient = float(values[0])
        exponents = values[1:]
    except (TypeError, ValueError, IndexError):
        raise ParameterError("terms", entry, allowed) from None
    if len(exponents) != 3 or not math.isfinite(coefficient):
        raise ParameterError("terms", entry, allowed)
    powers = []
    for e in exponents:
        if isinstance(e, bool) or not isinstance(e, int | float) or e != int(e):
            raise ParameterError("terms", entry, allowed, "exponents are integers")
        if not 0 <= int(e) <= MAX_EXPONENT:
            raise ParameterError("terms", entry, allowed)
        powers.append(int(e))
    return (coefficient, powers[0], powers[1], powers[2])


def evaluate(terms: tuple[Term, ...], points: np.ndarray) -> np.ndarray:
    """F at ``points`` (shape (..., 3), about O [m])."""
    total = np.zeros(points.shape[:-1])
    for c, i, j, k in terms:
        total += c * points[..., 0] ** i * points[..., 1] ** j * points[..., 2] ** k
    return total


def _ray_points(terms: tuple[Term, ...], centre: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """First crossing of F = 1 on rays from ``centre`` (F < 1 there), shape (k, 3) [m]."""
    low = np.zeros(len(directions))
    high = np.full(len(directions), 1e-6)
    outside = evaluate(terms, centre + high[:, None] * directions) > 1.0
    while not outside.all():
        low = np.where(outside, low, high)
        high = np.where(outside, high, 2.0 * high)
        if high.max() > RAY_LIMIT:
            worst = directions[np.argmax(high)]
            raise ParameterError(
                "terms",
                "the polynomial",
                "a bounded body {F <= 1}",
                f"it extends beyond {RAY_LIMIT:g} m in the direction {np.round(worst, 3).tolist()}",
            )
        outside = evaluate(terms, centre + high[:, None] * directions) > 1.0
    for _ in range(60):
        middle = 0.5 * (low + high)
        inside = evaluate(terms, centre + middle[:, None] * directions) <= 1.0
        low = np.where(inside, middle, low)
        high = np.where(inside, high, middle)
    return centre + (0.5 * (low + high))[:, None] * directions


@dataclass(frozen=True)
class ImplicitPolynomial:
    """Body {F(x) <= 1}, F(x) = Σ_k c_k x^i_k y^j_k z^l_k, x about the origin O [m].

    Parameters
    ----------
    terms : [(c, i, j, l), ...], coefficient c [m^-(i+j+l)] and integer exponents
        i, j, l in 0..16; at least one term of total degree >= 2
    com_offset : h, distance of the centre of mass G below O along axis 3 [m];
        G = (0, 0, -h) must lie strictly inside, F(G) < 1

    Notes
    -----
    Checked once here: the body is bounded, strictly convex (on 2000 Fibonacci
    directions the Newton contact solve converges, the tangent Hessian is positive
    definite and the point found is the lowest of the body) and rests upright
    (the contact for n = e3 lies on body axis 3 below G). A violation is a
    one-line :class:`ParameterError`. The ellipsoid x²/a² + y²/b² + z²/c² is
    ``terms = [(1/a², 2, 0, 0), (1/b², 0, 2, 0), (1/c², 0, 0, 2)]``.
    """

    terms: tuple[Term, ...]
    com_offset: float
    start_centre: tuple[float, float, float] = field(init=False, repr=False, compare=False)
    start_semi_axes: tuple[float, float, float] = field(init=False, repr=False, compare=False)

    kind = "implicit_polynomial"

    def __post_init__(self) -> None:
        try:
            entries = list(self.terms)
        except TypeError:
            raise ParameterError("terms", self.terms, "a list of [c, i, j, k] terms") from None
        if not 1 <= len(entries) <= MAX_TERMS:
            raise ParameterError("terms", self.terms, f"1 to {MAX_TERMS} [c, i, j, k] terms")
        terms = tuple(_term(entry) for entry in entries)
        object.__setattr__(self, "terms", terms)
        degree = max((i + j + k for c, i, j, k in terms if c != 0.0), default=0)
        if degree < 2:
            raise ParameterError("terms", self.terms, "a polynomial of degree >= 2")
        try:
            offset = float(self.com_offset)
        except (TypeError, ValueError):
            raise ParameterError("com_offset", self.com_offset, "a number in m") from None
        centre = np.array([0.0, 0.0, -offset])
        if not math.isfinite(offset) or not evaluate(terms, centre) < 1.0:
            raise ParameterError(
                "com_offset", self.com_offset, "a number in m with F(0, 0, -h) < 1", "G inside"
            )
        object.__setattr__(self, "com_offset", offset)
        points = _ray_points(terms, centre, fibonacci_directions())
        low, high = points.min(axis=0), points.max(axis=0)
        object.__setattr__(self, "start_centre", tuple(float(v) for v in 0.5 * (low + high)))
        object.__setattr__(self, "start_semi_axes", tuple(float(v) for v in 0.5 * (high - low)))
        self._check_convex(points)
        self._check_upright()

    # --- kernel packing -------------------------------------------------------

    @property
    def code(self) -> int:
        """Kernel shape code."""
        return layout.SHAPE_IMPLICIT

    def kernel_parameters(self) -> tuple[float, float, float, float]:
        """(a0, b0, c0, h): start-ellipsoid semi-axes and h, as the kernels read them [m].

        The start ellipsoid is the box of the body's extents (derived, not an input).
        """
        a, b, c = self.start_semi_axes
        return (a, b, c, self.com_offset)

    def kernel_tail(self) -> np.ndarray:
        """The params tail: start-ellipsoid centre [m], then c, i, j, l per term."""
        return np.concatenate([self.start_centre, np.ravel(self.terms)]).astype(float)

    def kernel_array(self) -> np.ndarray:
        """A full params array with only the shape filled (for the geometry kernels)."""
        tail = self.kernel_tail()
        params = np.zeros(layout.N_PARAMS + tail.size)
        params[layout.P_SHAPE] = self.code
        params[layout.P_SHAPE_0 : layout.P_SHAPE_0 + 4] = self.kernel_parameters()
        params[layout.P_SHAPE_4] = len(self.terms)
        params[layout.N_PARAMS :] = tail
        return params

    def terms_json(self) -> str:
        """The terms as a JSON list of [c, i, j, l], for run attributes."""
        return json.dumps([[c, i, j, k] for c, i, j, k in self.terms])

    # --- geometry --------------------------------------------------------------

    @property
    def size(self) -> float:
        """Largest half-extent of the body [m]."""
        return max(self.start_semi_axes)

    def contact_point(self, n: tuple[float, float, float]) -> tuple[float, ...] | None:
        """Lowest point x* about O for the upward vertical n [m], or None if not found."""
        x, _, _, _, ok = implicit.implicit_point(n, self.kernel_array())
        return tuple(x) if ok else None

    def _check_convex(self, points: np.ndarray) -> None:
        params = self.kernel_array()
        size = self.size
        normals = fibonacci_directions()
        for n in normals:
            x, _, _, _, ok = implicit.implicit_point((n[0], n[1], n[2]), params)
            lowest = float(np.min(points @ n))
            if not ok or float(np.dot(x, n)) > lowest + SUPPORT_TOLERANCE * size:
                outward = np.round(-n, 3).tolist()
                raise ParameterError(
                    "terms",
                    "the polynomial",
                    "a strictly convex closed surface F = 1",
                    f"not strictly convex where the outward normal is {outward}",
                )

    def _check_upright(self) -> None:
        x = self.contact_point((0.0, 0.0, 1.0))
        size = self.size
        if x is None:
            raise ParameterError(
                "terms", "the polynomial", "a surface curved at its lowest point (n = e3)"
            )
        if abs(x[0]) > AXIS_TOLERANCE * size or abs(x[1]) > AXIS_TOLERANCE * size:
            raise ParameterError(
                "terms",
                "the polynomial",
                "a lowest point (n = e3) on body axis 3",
                f"it is at x = {x[0]:.3g} m, y = {x[1]:.3g} m: the stone does not rest upright",
            )

    @property
    def rest_height(self) -> float:
        """Height l of G above the contact point at rest, -(z* + h) [m]."""
        x = self.contact_point((0.0, 0.0, 1.0))
        assert x is not None  # checked at construction
        return -(x[2] + self.com_offset)

    @property
    def radii_of_curvature(self) -> tuple[float, float]:
        """Normal radii of curvature along body axes 1, 2 at the rest contact, |∇F|/H_ii [m]."""
        _, _, gradient, hessian, _ = implicit.implicit_point((0.0, 0.0, 1.0), self.kernel_array())
        norm = math.sqrt(gradient[0] ** 2 + gradient[1] ** 2 + gradient[2] ** 2)
        return (norm / hessian[0], norm / hessian[4])
