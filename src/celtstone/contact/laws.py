"""Friction laws and contact pressures by name, and their dimensionless functions of u.

``friction_functions(u, law, pressure)`` evaluates the compiled kernels the
integrator uses, so what ``celtstone friction`` prints is what a run feels.
"""

from __future__ import annotations

import numpy as np

from celtstone.errors import ParameterError, require_choice
from celtstone.kernels.friction import contact_friction
from celtstone.kernels.layout import ContactPressure, ContactShape, FrictionLaw

__all__ = [
    "CONTACT_PRESSURES",
    "CONTACT_SHAPES",
    "FRICTION_LAWS",
    "LAW_WORDS",
    "PRESSURE_WORDS",
    "SHAPE_WORDS",
    "choice_words",
    "friction_functions",
    "unit_speeds",
]

# names (the enums' members in lower case) -> plain-int codes (``kernels.layout``)
FRICTION_LAWS = {law.name.lower(): law.value for law in FrictionLaw}
"""Friction law name (``"pade"``, ``"exact"``) -> the kernels' integer code."""
CONTACT_PRESSURES = {pressure.name.lower(): pressure.value for pressure in ContactPressure}
"""Contact pressure name (``"hertz"``, ``"uniform"``) -> the kernels' integer code."""
CONTACT_SHAPES = {shape.name.lower(): shape.value for shape in ContactShape}
"""Contact patch name (``"circle"``, ``"ellipse"``) -> the kernels' integer code."""

# what each law and pressure is, in words (help texts; a test requires one per member)
LAW_WORDS = {
    FrictionLaw.PADE: "Zhuravlev's Padé approximation, paper eq. 10",
    FrictionLaw.EXACT: "the Coulomb-Contensou integrals of paper section 2",
}
"""Each friction law in words, with its paper equation (help texts)."""
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


def choice_words(words: dict) -> str:
    """Say each option's name and what it is: ``"pade (…) or exact (…)"``.

    Parameters
    ----------
    words : dict
        Member of a code enum -> its description (:data:`LAW_WORDS`,
        :data:`PRESSURE_WORDS`, :data:`SHAPE_WORDS`).

    Returns
    -------
    str
        The options joined by "or".
    """
    return " or ".join(f"{member.name.lower()} ({text})" for member, text in words.items())


def friction_functions(
    u: np.ndarray | list[float] | float, law: str = "exact", pressure: str = "hertz"
) -> tuple[np.ndarray, np.ndarray]:
    """F/(fN) and M/(fNε) of a friction law at slip ratios u = |V1| / (ε|Ω_n|).

    Parameters
    ----------
    u : numpy.ndarray or list of float or float
        Slip ratios [1], finite, >= 0; any shape.
    law : str, optional
        ``"pade"`` (Zhuravlev's Padé approximation, paper eq. 10) or ``"exact"`` (the
        Coulomb–Contensou integrals, paper section 2).
    pressure : str, optional
        ``"hertz"`` (paper eq. 2) or ``"uniform"``.

    Returns
    -------
    force : numpy.ndarray
        |F| / (f N) [1], the shape of ``u``.
    moment : numpy.ndarray
        |M| / (f N ε) [1], the shape of ``u``.
    """
    require_choice("friction_law", law, FRICTION_LAWS)
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
            FRICTION_LAWS[law],
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
