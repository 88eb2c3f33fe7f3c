"""The one exception hierarchy of celtstone.

Every error a user can cause names what to change. The CLI turns a
:class:`CeltstoneError` into one line on standard error and exit status 2.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable

__all__ = [
    "BodyFileError",
    "CeltstoneError",
    "CeltstoneWarning",
    "FitQualityWarning",
    "FrictionBoundWarning",
    "FrictionSingularityError",
    "IdentifiabilityWarning",
    "IntegrationError",
    "LiftOffError",
    "OutputError",
    "ParameterError",
    "PlausibilityWarning",
    "did_you_mean",
    "require_choice",
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
        message = f"{name} = {_shown(value)} is not allowed: expected {allowed}"
        if hint:
            message += f" ({hint})"
        super().__init__(message)


def _shown(value: object, longest: int = 4200) -> str:
    """``repr(value)`` on one line (an array's repr spans lines, and an error is one line),
    cut at ``longest`` characters (more than any path) so that a long list stays readable."""
    text = repr(value)
    if "\n" in text or "\r" in text:
        text = " ".join(text.split())
    return text if len(text) <= longest else text[: longest - 3] + "..."


class BodyFileError(ParameterError):
    """A body file's content is refused: one line naming the file and the key.

    Parameters
    ----------
    file : str
        The body file (its path or the set's name).
    name : str
        The key, as in :class:`ParameterError`.
    value : object
        The value given.
    allowed : str
        The allowed range or set, in words.
    hint : str, optional
        What to do instead.
    problem : str, optional
        Replaces the standard "NAME = VALUE is not allowed" text where the key itself is
        the fault (unknown, missing).
    """

    def __init__(
        self,
        file: str,
        name: str,
        value: object,
        allowed: str,
        hint: str = "",
        *,
        problem: str = "",
    ) -> None:
        super().__init__(name, value, allowed, hint)
        self.file = file
        Exception.__init__(self, f"body file {file}: {problem or self.args[0]}")


class IntegrationError(CeltstoneError, RuntimeError):
    """The integrator could not continue (step size underflow, too many steps)."""


class LiftOffError(CeltstoneError):
    """The normal force became negative: the body leaves the plane."""


class FrictionSingularityError(CeltstoneError):
    """The friction state has no unique solution (paper eq. 11, or a Painlevé-type case)."""


class OutputError(OSError):
    """An output file could not be written (disk full, no permission, ...).

    Nothing was left behind: neither the file nor a temporary. Not a
    :class:`CeltstoneError`, because nothing the user gave is wrong: the CLI reports
    it as it reports any ``OSError``, in one line with exit status 1.

    Parameters
    ----------
    path : str
        The output file as the user named it.
    cause : str
        Why, in words (``"No space left on device"``).
    errno : int, optional
        The system's error number, when there is one.
    """

    def __init__(self, path: str, cause: str, errno: int | None = None) -> None:
        super().__init__(f"{path}: {cause}")
        self.errno = errno
        self.strerror = cause
        self.filename = path
        self.path = path
        self.cause = cause

    def __str__(self) -> str:
        return f"{self.path}: {self.cause}"


class CeltstoneWarning(UserWarning):
    """Base class of every warning celtstone issues; the CLI prints each as one line.

    A warning whose advice names an argument spells it as Python does
    (``friction_load="dynamic"``); its ``command_line``, where set, is the same text spelled
    as the command line does (``--friction-load dynamic``), and the CLI prints that one.
    """

    command_line: str | None = None


class PlausibilityWarning(CeltstoneWarning):
    """A parameter is allowed but implausible for a rattleback (``simulation.plausibility``)."""


class FrictionBoundWarning(CeltstoneWarning):
    """A run's friction exceeded Coulomb's bound f N for the true normal force N.

    The paper's first approximation (the friction law loaded with m g) allows it.
    """


def did_you_mean(value: object, options: Iterable[object], cutoff: float = 0.6) -> str:
    """``"did you mean 'sliding'?"`` for the option closest to ``value``, or ``""``: the one
    suggestion every "unknown name" message of celtstone uses.

    The closest is difflib's best match above ``cutoff``, else the first option that starts
    with the first four letters of ``value`` (``fric`` -> ``friction_coefficient``).
    """
    text, names = str(value), [str(o) for o in options]
    close = difflib.get_close_matches(text, names, n=1, cutoff=cutoff) or [
        name for name in names if text and name.startswith(text[:4])
    ]
    return f"did you mean {close[0]!r}?" if close else ""


def require_choice(name: str, value: object, options: Iterable[object]) -> None:
    """Raise :class:`ParameterError` naming ``name`` unless ``value`` is one of ``options``
    (listed in the message, with the closest as a suggestion)."""
    choices = list(options)
    try:
        found = value in choices
    except (TypeError, ValueError):  # an array compares element by element
        found = False
    if not found:
        allowed = "one of: " + ", ".join(str(c) for c in choices)
        raise ParameterError(name, value, allowed, did_you_mean(value, choices))


class IdentifiabilityWarning(CeltstoneWarning):
    """Fitted parameters that the data do not determine separately.

    Their |correlation| is above the limit, or the Jacobian has no full rank
    (``celtstone.fitting``).
    """


class FitQualityWarning(CeltstoneWarning):
    """A fit not to be believed as it stands: residuals above the noise or not white,
    a parameter at its bound, no convergence, too little in the record
    (``celtstone.fitting.assess``)."""
