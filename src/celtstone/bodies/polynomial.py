"""A convex body bounded by an implicit polynomial surface F(x) = 1.

The contact point is found by the Newton solve of ``kernels.implicit``; the checks
and the packing are those of every implicit surface (``bodies.implicit_surface``);
the terms travel in the kernel parameter record and in the run's attributes, so a run of a
polynomial body can be redrawn and repeated from its file (docs/decisions.md section 17).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any, Self

import numpy as np

from celtstone.bodies.declaration import (
    INTEGER,
    KL_COM_OFFSET,
    KL_SEMI_AXES,
    NUMBER,
    Entry,
    SweepName,
)
from celtstone.bodies.implicit_surface import ImplicitSurface
from celtstone.errors import ParameterError
from celtstone.kernels.layout import MAX_TERMS
from celtstone.simulation import schema

__all__ = ["ImplicitPolynomial"]

MAX_EXPONENT = 16  # per variable; enough for superellipsoids up to p = 16

Term = tuple[float, int, int, int]
_TERMS = schema.Quantity("terms", "c, i, j, k", "", "implicit polynomial terms, c in m^-(i+j+k)")


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


@dataclass(frozen=True)
class ImplicitPolynomial(ImplicitSurface):
    """Body {F(x) <= 1}, F(x) = Σ_k c_k x^i_k y^j_k z^l_k, x about the origin O [m].

    Parameters
    ----------
    terms : sequence of (float, int, int, int)
        (c, i, j, l) per term: coefficient c [m^-(i+j+l)] and exponents i, j, l in
        0..16; at least one term of total degree >= 2.
    com_offset : float
        Distance h of the centre of mass G below O along axis 3 [m];
        G = (0, 0, -h) must lie strictly inside, F(G) < 1.

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
    surface = "sum of c x^i y^j z^k = 1 about O, G = (0, 0, -h)"
    entries = (
        Entry(
            "terms",
            _TERMS,
            (None, 4),
            (NUMBER, INTEGER, INTEGER, INTEGER),
            "[c, i, j, k]: coefficient c and whole exponents i, j, k",
        ),
        Entry("com_offset", schema.PARAMETERS["com_offset"]),
    )
    sweep_names = (SweepName("com_offset", "com_offset", "G below the origin h"),)

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
        self._validate()

    @classmethod
    def example(cls) -> Self:
        """Kane & Levinson's ellipsoid as the polynomial x²/a² + y²/b² + z²/c²."""
        a, b, c = KL_SEMI_AXES
        terms = ((1 / a**2, 2, 0, 0), (1 / b**2, 0, 2, 0), (1 / c**2, 0, 0, 2))
        return cls(terms, KL_COM_OFFSET)

    def _evaluate(self, points: np.ndarray) -> np.ndarray:
        return evaluate(self.terms, points)

    def _level_fields(self) -> dict[str, Any]:
        coefficients = np.zeros(MAX_TERMS)
        exponents = np.zeros((MAX_TERMS, 3), dtype=np.int64)
        count = len(self.terms)
        coefficients[:count] = [c for c, _, _, _ in self.terms]
        exponents[:count] = [(i, j, k) for _, i, j, k in self.terms]
        return {
            "term_count": count,
            "term_coefficients": coefficients,
            "term_exponents": exponents,
        }

    def terms_json(self) -> str:
        """Write the terms as JSON, for run attributes.

        Returns
        -------
        str
            A JSON list of [c, i, j, l].
        """
        return json.dumps([[c, i, j, k] for c, i, j, k in self.terms])
