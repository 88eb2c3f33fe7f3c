"""Hertz contact of the body on the plane: effective modulus and contact radius."""

from __future__ import annotations

from celtstone.kernels.hertz import hertz_contact_radius as _hertz_contact_radius
from celtstone.simulation import schema

__all__ = ["effective_modulus", "hertz_contact_radius"]


def effective_modulus(elastic_modulus: float, poisson_ratio: float) -> float:
    """E* [Pa] of a body and a plane of the same material: E* = E / (2 (1 − ν²)).

    Parameters
    ----------
    elastic_modulus : float
        E, Young's modulus of body and plane [Pa], > 0.
    poisson_ratio : float
        Poisson's ratio ν of body and plane [1], in (−1, 0.5).

    Returns
    -------
    float
        The effective modulus E* [Pa].

    Notes
    -----
    1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2 (Johnson, *Contact Mechanics*, 1985, ch. 4)
    with E1 = E2 = E, ν1 = ν2 = ν.
    """
    modulus = schema.check("elastic_modulus", elastic_modulus)
    ratio = schema.check("poisson_ratio", poisson_ratio)
    return modulus / (2.0 * (1.0 - ratio * ratio))


def hertz_contact_radius(
    normal_force: float, equivalent_radius: float, elastic_modulus: float, poisson_ratio: float
) -> float:
    """Compute the radius ε = (3 N R / (4 E*))^(1/3) [m] of the Hertz contact disk.

    Parameters
    ----------
    normal_force : float
        N, the load on the contact [N], > 0.
    equivalent_radius : float
        R, the sphere's radius, or the equivalent radius sqrt(R1 R2) of an elliptic
        contact [m], > 0 (``docs/equations.md``).
    elastic_modulus : float
        E, Young's modulus of body and plane [Pa], > 0.
    poisson_ratio : float
        Poisson's ratio ν of body and plane [1], in (−1, 0.5); E* from
        :func:`effective_modulus`.

    Returns
    -------
    float
        The contact radius ε [m].
    """
    load = schema.check("load", normal_force)
    radius = schema.check("equivalent_radius", equivalent_radius)
    return float(
        _hertz_contact_radius(load, radius, effective_modulus(elastic_modulus, poisson_ratio))
    )
