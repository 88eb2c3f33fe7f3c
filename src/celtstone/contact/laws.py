"""Friction laws and contact pressures by name, and their dimensionless functions of u.

:data:`LAWS` is the registry of friction laws: one :class:`FrictionLawEntry` per law
(its name, kernel code, words, plot label and the kernels it reaches) drives every place
a law is chosen: the model setting and its help (``models.SETTINGS``), sweeps,
``celtstone friction`` (disk and ``--ellipse``), its plot and this module's functions.
The compiled side reads a law through one dispatch, ``kernels.friction.law_functions``:
the disk (``contact_friction``), the elliptic contact (``friction_ellipse``) and the
stick limit (``stick.limit_moment``) all follow from it, and a code without a branch
there stops a run with the status ``unknown_code`` (``system.code_status``).

``friction_functions(u, law, pressure)`` evaluates the compiled kernels the
integrator uses, so what ``celtstone friction`` prints is what a run feels.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from celtstone.errors import ParameterError, require_choice
from celtstone.kernels.friction import (
    contact_friction,
    has_friction_law,
    pade_disk_friction,
    pade_functions,
    pade_limit_moment,
)
from celtstone.kernels.friction_exact import exact_friction_functions
from celtstone.kernels.layout import ContactPressure, ContactShape, FrictionLaw

__all__ = [
    "CONTACT_PRESSURES",
    "CONTACT_SHAPES",
    "FRICTION_LAWS",
    "LAWS",
    "LAW_WORDS",
    "PRESSURE_WORDS",
    "SHAPE_WORDS",
    "FrictionLawEntry",
    "choice_words",
    "friction_functions",
    "law_code",
    "unit_speeds",
]

# names (the enums' members in lower case) -> plain-int codes (``kernels.layout``)
CONTACT_PRESSURES = {pressure.name.lower(): pressure.value for pressure in ContactPressure}
"""Contact pressure name (``"hertz"``, ``"uniform"``) -> the kernels' integer code."""
CONTACT_SHAPES = {shape.name.lower(): shape.value for shape in ContactShape}
"""Contact patch name (``"circle"``, ``"ellipse"``) -> the kernels' integer code."""


@dataclass(frozen=True)
class FrictionLawEntry:
    """A friction law, declared once.

    Parameters
    ----------
    name : str
        The law's name in models, the CLI, sweeps and a run's attributes.
    code : int
        Its code in the kernels, a ``kernels.layout.FrictionLaw`` member's value.
    words : str
        What it is, with its paper equation (help texts).
    label : str
        Its name in a plot's legend.
    functions : callable
        The kernel ``kernels.friction.law_functions`` dispatches to for this code:
        (|V1| [m/s], ε|Ω_n| [m/s], pressure code) -> (F/(fN), M/(fNε)) [1].
    disk : callable or None
        The closed-form kernel ``kernels.friction.contact_friction`` takes for the
        disk, arguments as ``contact_friction`` less the law; None: the force and moment
        ``contact_friction`` forms from ``functions``.
    stick_limit : callable or None
        The closed form ``kernels.stick.limit_moment`` takes, (φ, pressure code) ->
        μ_max [1]; None: the bisection of ``functions`` (``stick.bisected_limit_moment``).
    elliptic_reference : callable or None
        The law over a Hertz ellipse by quadrature that ``celtstone friction
        --ellipse`` prints, in the convention of
        ``contact.ellipse.elliptic_friction_functions``; None: the fast form a run uses
        (``contact.ellipse_table.fast_friction_functions``: the disk law of radius A
        corrected by the table built from the exact entry's reference).
    """

    name: str
    code: int
    words: str
    label: str
    functions: Callable[..., tuple[float, float]]
    disk: Callable[..., Any] | None = None
    stick_limit: Callable[..., float] | None = None
    elliptic_reference: Callable[..., tuple[np.ndarray, float]] | None = None


def exact_elliptic_functions(u: float, direction: float, aspect: float) -> tuple[np.ndarray, float]:
    """The exact law over a Hertz ellipse by quadrature,
    ``contact.ellipse.elliptic_friction_functions`` (imported on first use: it loads
    SciPy's optimiser, which a command's help does not need)."""
    from celtstone.contact.ellipse import elliptic_friction_functions

    return elliptic_friction_functions(u, direction, aspect)


LAWS: dict[str, FrictionLawEntry] = {
    entry.name: entry
    for entry in (
        FrictionLawEntry(
            "pade",
            FrictionLaw.PADE.value,
            "Zhuravlev's Padé approximation, paper eq. 10",
            "Padé (Zhuravlev)",
            pade_functions,
            disk=pade_disk_friction,
            stick_limit=pade_limit_moment,
        ),
        FrictionLawEntry(
            "exact",
            FrictionLaw.EXACT.value,
            "the Coulomb-Contensou integrals of paper section 2",
            "exact (Coulomb–Contensou)",
            exact_friction_functions,
            elliptic_reference=exact_elliptic_functions,
        ),
    )
}
"""Friction law name -> its entry, in the order the help texts list them."""


class _LawField(Mapping[str, Any]):
    """A live view of one field of :data:`LAWS` by law name (a law registered later is in it)."""

    def __init__(self, field: str) -> None:
        self._field = field

    def __getitem__(self, name: str) -> Any:
        return getattr(LAWS[name], self._field)

    def __iter__(self) -> Iterator[str]:
        return iter(LAWS)

    def __len__(self) -> int:
        return len(LAWS)

    def __repr__(self) -> str:
        return repr(dict(self))


FRICTION_LAWS: Mapping[str, int] = _LawField("code")
"""Friction law name (``"pade"``, ``"exact"``) -> the kernels' integer code (from :data:`LAWS`)."""
LAW_WORDS: Mapping[str, str] = _LawField("words")
"""Each friction law's name -> its words, with its paper equation (from :data:`LAWS`)."""

# what each pressure and shape is, in words (help texts; a test requires one per member)
PRESSURE_WORDS = {
    ContactPressure.HERTZ: "Hertz, paper eq. 2",
    ContactPressure.UNIFORM: "uniform on the disk",
}
"""Each contact pressure in words, with its paper equation (help texts)."""
SHAPE_WORDS = {
    ContactShape.CIRCLE: "a disk of radius epsilon, the paper's",
    ContactShape.ELLIPSE: "the Hertz ellipse of the two principal curvatures; needs "
    "elastic_modulus and poisson_ratio",
}
"""Each contact patch shape in words (help texts)."""


def choice_words(words: Mapping[Any, str]) -> str:
    """Say each option's name and what it is: ``"pade (…) or exact (…)"``.

    Parameters
    ----------
    words : Mapping
        Option name, or member of a code enum, -> its description (:data:`LAW_WORDS`,
        :data:`PRESSURE_WORDS`, :data:`SHAPE_WORDS`).

    Returns
    -------
    str
        The options joined by "or".
    """
    return " or ".join(
        f"{key if isinstance(key, str) else key.name.lower()} ({text})"
        for key, text in words.items()
    )


def law_code(law: str) -> int:
    """The kernels' code of the friction law named ``law``, checked.

    Raises
    ------
    ParameterError
        If ``law`` is no name in :data:`LAWS`, or its code has no branch in the compiled
        ``kernels.friction.law_functions`` (a run with it stops with ``unknown_code``).
    """
    require_choice("friction_law", law, LAWS)
    code = LAWS[law].code
    if not has_friction_law(code):
        compiled = ", ".join(name for name, entry in LAWS.items() if has_friction_law(entry.code))
        raise ParameterError(
            "friction_law",
            law,
            f"a law the kernels compute: {compiled}",
            f"its code {code} has no branch in kernels/friction.py law_functions "
            "(a run with it stops with status unknown_code)",
        )
    return code


def friction_functions(
    u: np.ndarray | list[float] | float, law: str = "exact", pressure: str = "hertz"
) -> tuple[np.ndarray, np.ndarray]:
    """F/(fN) and M/(fNε) of a friction law at slip ratios u = |V1| / (ε|Ω_n|).

    Parameters
    ----------
    u : numpy.ndarray or list of float or float
        Slip ratios [1], finite, >= 0; any shape.
    law : str, optional
        A name in :data:`LAWS`: ``"pade"`` (Zhuravlev's Padé approximation, paper
        eq. 10) or ``"exact"`` (the Coulomb–Contensou integrals, paper section 2).
    pressure : str, optional
        ``"hertz"`` (paper eq. 2) or ``"uniform"``.

    Returns
    -------
    force : numpy.ndarray
        |F| / (f N) [1], the shape of ``u``.
    moment : numpy.ndarray
        |M| / (f N ε) [1], the shape of ``u``.
    """
    code = law_code(law)
    require_choice("contact_pressure", pressure, CONTACT_PRESSURES)
    given = np.asarray(u)
    if given.dtype.kind not in ("i", "u", "f"):  # booleans and text are not ratios
        raise ParameterError("slip_ratio", u, "finite numbers >= 0")
    ratios = given.astype(float)
    if not np.all(np.isfinite(ratios)) or np.any(ratios < 0.0):
        raise ParameterError("slip_ratio", u, "finite numbers >= 0")
    force = np.empty_like(ratios)
    moment = np.empty_like(ratios)
    for index, ratio in np.ndenumerate(ratios):
        # ε = 1 m, V1 along e1 and no regularisation
        slip_speed, spin_rate = unit_speeds(float(ratio))
        vector, pivot = contact_friction(
            (slip_speed, 0.0, 0.0),
            spin_rate,
            1.0,
            0.0,
            code,
            CONTACT_PRESSURES[pressure],
        )
        force[index] = -vector[0]
        moment[index] = -pivot
    return force, moment


def unit_speeds(u: float) -> tuple[float, float]:
    """A slip speed and a spin rate with ratio u and neither above 1, for ε = 1 m.

    The laws depend on u = |V1| / (ε|Ω_n|) only, but the kernels square |V1|:
    evaluating u = 1e155 as |V1| = 1e155 m/s overflows to a zero force instead of
    F = f N (paper section 2's pure-sliding limit). Each speed is at most 1 m/s here,
    so every finite u >= 0 is evaluated without overflow.

    Parameters
    ----------
    u : float
        Slip ratio [1], finite, >= 0.

    Returns
    -------
    slip_speed : float
        |V1| [m/s]: u for u <= 1, else 1.
    spin_rate : float
        Ω_n [rad/s]: 1 for u <= 1, else 1/u.
    """
    if u <= 1.0:
        return u, 1.0
    return 1.0, 1.0 / u
