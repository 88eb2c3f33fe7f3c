"""The one exception hierarchy of celtstone.

Every error a user can cause names what to change. The CLI turns a
:class:`CeltstoneError` into one line on standard error and exit status 2.
"""

from __future__ import annotations

__all__ = [
    "CeltstoneError",
    "FrictionSingularityError",
    "IntegrationError",
    "LiftOffError",
    "ParameterError",
]


class CeltstoneError(Exception):
    """Base class of every error celtstone raises on purpose."""


class ParameterError(CeltstoneError, ValueError):
    """A parameter is outside its allowed range.

    Parameters
    ----------
    name : str
        The parameter's name as the user spells it (``friction_coefficient``).
    value : object
        The value given.
    allowed : str
        The allowed range or set, in words (``">= 0"``, ``"one of: rolling, sliding"``).
    hint : str, optional
        What to do instead.
    """

    def __init__(self, name: str, value: object, allowed: str, hint: str = "") -> None:
        self.name = name
        self.value = value
        self.allowed = allowed
        self.hint = hint
        message = f"{name} = {value!r} is not allowed: expected {allowed}"
        if hint:
            message += f" ({hint})"
        super().__init__(message)


class IntegrationError(CeltstoneError, RuntimeError):
    """The integrator could not continue (step size underflow, too many steps)."""


class LiftOffError(CeltstoneError):
    """The normal force became negative: the body leaves the plane."""


class FrictionSingularityError(CeltstoneError):
    """The friction state has no unique solution (paper eq. 11, or a Painlevé-type case)."""
