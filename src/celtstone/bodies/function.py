"""A convex body bounded by a user's implicit function F(x) = 1, given in Python.

F, its gradient and (optionally) its Hessian are compiled by numba into one C
callback whose address travels in the kernel parameter record, so the compiled, cached
kernels call it in the Newton contact solve with no Python per call
(docs/decisions.md section 18). The body is validated as every implicit surface
(``bodies.implicit_surface``).
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Self

import numpy as np

from celtstone.bodies.declaration import KL_COM_OFFSET, KL_SEMI_AXES
from celtstone.bodies.implicit_surface import ImplicitSurface
from celtstone.errors import ParameterError
from celtstone.kernels._jit import (
    HESSIAN_STEP,
    compile_batch_values,
    compile_level_function,
    differenced_hessian,
    jit_user_function,
)

__all__ = ["ImplicitFunction"]

GRADIENT_CHECK_STEP = 1e-6  # central-difference step of the gradient check, × body size
GRADIENT_CHECK_TOLERANCE = 1e-5  # relative disagreement at which the gradient is refused
GRADIENT_CHECK_POINTS = 50


@dataclass(frozen=True)
class ImplicitFunction(ImplicitSurface):
    """Body {F(x) <= 1} for a user's smooth convex F, x about the origin O [m].

    Parameters
    ----------
    value : callable
        F(x) -> float [1], x a NumPy array of shape (3,) [m] in body axes about O.
    gradient : callable
        ∇F(x) -> array of shape (3,) [1/m].
    com_offset : float
        Distance h of G below O along axis 3 [m]; F(0, 0, -h) < 1.
    hessian : callable, optional
        ∇²F(x) -> array of shape (3, 3) [1/m²]; without it the central difference of
        ``gradient`` (step 1e-5 × the body size, error ~1e-10 relative) is used in the
        contact rate.
    name : str, optional
        A label for the run's attributes (default: the function's name).

    Notes
    -----
    The functions must be compilable by numba in nopython mode (NumPy arithmetic on
    x). Checked once here: they compile, the gradient agrees with a central
    difference of F and the Hessian with one of the gradient at 50 points on the
    surface (1e-5 relative), and the body is
    bounded, strictly convex and upright as for :class:`ImplicitPolynomial`. The
    compiled callback lives in this process: a run's file records the functions'
    source text but cannot be redrawn or repeated without them, and sweeps, which
    may run on other machines, take named parameter sets only.
    """

    value: Callable[..., Any]
    gradient: Callable[..., Any]
    com_offset: float
    hessian: Callable[..., Any] | None = None
    name: str = ""
    start_centre: tuple[float, float, float] = field(init=False, repr=False, compare=False)
    start_semi_axes: tuple[float, float, float] = field(init=False, repr=False, compare=False)
    _compiled: tuple[Any, ...] = field(init=False, repr=False, compare=False)
    _callback: Any = field(init=False, repr=False, compare=False)
    _values: Any = field(init=False, repr=False, compare=False)

    kind = "implicit_function"
    surface = "F(x) = 1 about O for a Python function F, G = (0, 0, -h)"
    entries = ()  # not in body files: the functions are Python
    stored = False
    parameter = "value"

    def __post_init__(self) -> None:
        compiled: list[Any] = []
        for parameter in ("value", "gradient", "hessian"):
            function = getattr(self, parameter)
            if function is None and parameter == "hessian":
                compiled.append(None)
                continue
            if not callable(function):
                raise ParameterError(parameter, function, "a function of x, an array of 3 in m")
            try:
                compiled.append(jit_user_function(function, parameter))
            except ValueError as error:
                raise ParameterError(
                    parameter,
                    getattr(function, "__name__", function),
                    "a function numba compiles (NumPy arithmetic on x; helpers it calls "
                    "decorated with numba.njit)",
                    str(error).split(": ", 1)[1],
                ) from None
        object.__setattr__(self, "_compiled", tuple(compiled))
        object.__setattr__(self, "_values", compile_batch_values(compiled[0]))
        if not self.name:
            object.__setattr__(self, "name", getattr(self.value, "__name__", "F"))
        self._validate()

    def _prepare(self, surface_points: np.ndarray) -> None:
        """Check the gradient on the surface, then compile the callback (its Hessian
        step scales with the body's size, known now)."""
        self._check_gradient(surface_points[:: len(surface_points) // GRADIENT_CHECK_POINTS])
        object.__setattr__(
            self,
            "_callback",
            compile_level_function(
                self._compiled[0], self._compiled[1], self._compiled[2], self.size
            ),
        )

    def _evaluate(self, points: np.ndarray) -> np.ndarray:
        values: np.ndarray = self._values(np.ascontiguousarray(points, dtype=float))
        return values

    def _level_fields(self) -> dict[str, Any]:
        return {"level_function": int(self._callback.address)}

    def _check_gradient(self, points: np.ndarray) -> None:
        """∇F against a central difference of F, and a given Hessian against one of ∇F,
        at ``points`` (k, 3) [m]."""
        value, gradient, hessian = self._compiled
        step = GRADIENT_CHECK_STEP * self.size
        differenced_second = differenced_hessian(gradient, HESSIAN_STEP * self.size)
        for x in points:
            differenced = np.array(
                [(value(x + step * e) - value(x - step * e)) / (2.0 * step) for e in np.eye(3)]
            )
            _refuse_unless_close(
                "gradient", self.gradient, "the gradient of value", gradient(x), differenced, x
            )
            if hessian is not None:
                _refuse_unless_close(
                    "hessian",
                    self.hessian,
                    "the Hessian of value (the derivative of gradient)",
                    hessian(x),
                    differenced_second(x),
                    x,
                )

    @classmethod
    def example(cls) -> Self:
        """Kane & Levinson's ellipsoid as a Python function."""
        return cls(_example_value, _example_gradient, KL_COM_OFFSET, name="kane_levinson_ellipsoid")

    def attributes(self) -> dict[str, str | float]:
        """Give the shape's provenance for a run's attributes.

        Returns
        -------
        dict of str to str or float
            Kind, recorded numbers, the functions' name and source text (not enough to
            rebuild the shape) and h [m].
        """
        return {
            **super().attributes(),
            "body_shape_function": self.name,
            "body_shape_function_source": self.source_text(),
            "body_shape_com_offset": self.com_offset,
        }

    def source_text(self) -> str:
        """Give the functions' source, for the run's attributes (not enough to rerun it).

        Returns
        -------
        str
            The source of ``value``, ``gradient`` and ``hessian``, where Python has it.
        """
        parts = []
        for function in (self.value, self.gradient, self.hessian):
            if function is None:
                continue
            try:
                parts.append(inspect.getsource(function))
            except (OSError, TypeError):
                parts.append(f"# {getattr(function, '__qualname__', function)}: no source")
        return "\n".join(parts)


def _example_value(x: np.ndarray) -> float:
    """F of Kane & Levinson's ellipsoid (``KL_SEMI_AXES``) about O [1]."""
    a, b, c = KL_SEMI_AXES
    return float((x[0] / a) ** 2 + (x[1] / b) ** 2 + (x[2] / c) ** 2)


def _example_gradient(x: np.ndarray) -> np.ndarray:
    """∇F of :func:`_example_value` [1/m]."""
    a, b, c = KL_SEMI_AXES
    return np.array([2.0 * x[0] / a**2, 2.0 * x[1] / b**2, 2.0 * x[2] / c**2])


def _refuse_unless_close(
    parameter: str,
    function: object,
    allowed: str,
    given: object,
    expected: np.ndarray,
    x: np.ndarray,
) -> None:
    """A ParameterError naming ``parameter`` unless |given - expected| <= 1e-5 |expected|."""
    values = np.asarray(given, dtype=float)
    if not np.linalg.norm(values - expected) <= GRADIENT_CHECK_TOLERANCE * np.linalg.norm(expected):
        raise ParameterError(
            parameter,
            getattr(function, "__name__", parameter),
            allowed,
            f"at x = {np.round(x, 6).tolist()} m it is {values.tolist()}, the central "
            f"difference gives {expected.tolist()}",
        )
