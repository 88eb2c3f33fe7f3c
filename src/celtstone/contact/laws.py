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
]

# names (the enums' members in lower case) -> plain-int codes (``kernels.layout``)
FRICTION_LAWS = {law.name.lower(): law.value for law in FrictionLaw}
CONTACT_PRESSURES = {pressure.name.lower(): pressure.value for pressure in ContactPressure}
CONTACT_SHAPES = {shape.name.lower(): shape.value for shape in ContactShape}

# what each law and pressure is, in words (help texts; a test requires one per member)
LAW_WORDS = {
    FrictionLaw.PADE: "Zhuravlev's Padé approximation, paper eq. 10",
    FrictionLaw.EXACT: "the Coulomb-Contensou integrals of paper section 2",
}
PRESSURE_WORDS = {
    ContactPressure.HERTZ: "Hertz, paper eq. 2",
    ContactPressure.UNIFORM: "uniform on the disk",
}
SHAPE_WORDS = {
    ContactShape.CIRCLE: "a disk of radius epsilon, the paper's",
    ContactShape.ELLIPSE: "the Hertz ellipse of the two principal curvatures; needs "
    "elastic_modulus and poisson_ratio",
}


def choice_words(words: dict) -> str:
    """``"pade (…) or exact (…)"``: each option's name and what it is."""
    return " or ".join(f"{member.name.lower()} ({text})" for member, text in words.items())


def friction_functions(
    u: np.ndarray | list[float] | float, law: str = "exact", pressure: str = "hertz"
) -> tuple[np.ndarray, np.ndarray]:
    """F/(fN) and M/(fNε) of a friction law at slip ratios u = |V1| / (ε|Ω_n|).

    Parameters
    ----------
    u : slip ratios [1], finite, >= 0; any shape
    law : "pade" or "exact"
    pressure : "hertz" (paper eq. 2) or "uniform"

    Returns
    -------
    force, moment : arrays of the shape of ``u`` [1]; |F| / (f N) and |M| / (f N ε)
    """
    require_choice("friction_law", law, FRICTION_LAWS)
    require_choice("contact_pressure", pressure, CONTACT_PRESSURES)
    ratios = np.asarray(u, dtype=float)
    if not np.all(np.isfinite(ratios)) or np.any(ratios < 0.0):
        raise ParameterError("slip_ratio", u, "finite numbers >= 0")
    force = np.empty_like(ratios)
    moment = np.empty_like(ratios)
    for index, ratio in np.ndenumerate(ratios):
        # ε = 1 m, Ω_n = 1 rad/s, V1 = u e1 and no regularisation
        vector, pivot = contact_friction(
            (float(ratio), 0.0, 0.0),
            1.0,
            1.0,
            0.0,
            FRICTION_LAWS[law],
            CONTACT_PRESSURES[pressure],
        )
        force[index] = -vector[0]
        moment[index] = -pivot
    return force, moment
