"""Is this a stone the models can describe? Checks of a body and its contact before a run.

Two kinds of finding, both naming the parameter to look at:

* :func:`require_runnable` raises :class:`ParameterError` where no run can mean anything:
  a flat rest contact (unbounded contact rate), a mass matrix about the contact that is
  singular in double precision, a contact disk as large as the surface's radius of
  curvature, a viscous torque that stops the body within a nanosecond.
* :func:`concerns` lists what is possible but implausible for a rattleback (a body
  written in centimetres, a density lighter than air, a damping torque that lifts the
  stone at once): :func:`celtstone.simulate` issues each as a :class:`PlausibilityWarning`
  and names it again if the run then stops early.

Every threshold is a dimensionless ratio stated beside its constant.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from celtstone.bodies import Body
from celtstone.errors import ParameterError

__all__ = [
    "Concern",
    "ContactSettings",
    "concerns",
    "contact_radius_at_rest",
    "require_runnable",
]

# (A_max + m l²) / A_min above this leaves fewer than ~6 significant digits in the
# solve for ω̇ (paper eq. 5, 9) at double precision
MAX_CONDITION = 1e10
# viscous decay rate σ / A_min [1/s] above this stops the body within 1 ns
MAX_DAMPING_RATE = 1e9
# viscous decay time A_min / σ [s] below which no reversal can develop
MIN_DAMPING_TIME = 0.1
# Hertz theory and the disk contact need ε ≪ ρ; warn above this fraction of ρ_min
CONTACT_RADIUS_WARNING = 0.25
# densities outside [kg/m³]: lighter than foams / heavier than osmium (22 590 kg/m³)
DENSITY_RANGE = (10.0, 30_000.0)
# half-extent of the body [m] outside which it is not a hand-held stone
SIZE_RANGE = (1e-3, 1.0)
# radius of gyration sqrt(A_min/m) below this fraction of the height l of G
GYRATION_FRACTION = 0.1
# gravitational acceleration [m/s²] outside: Pluto (0.62) to the Sun's surface (274)
GRAVITY_RANGE = (0.1, 300.0)

_UNITS = "lengths are in m, mass in kg, inertia in kg m^2"


@dataclass(frozen=True)
class ContactSettings:
    """What the checks read of a model.

    Parameters
    ----------
    damping : σ, viscous torque coefficient [N m s]
    contact_radius : ε [m] of a sliding contact, None for rolling
    effective_modulus : E* [Pa] when ε is the Hertz radius, else 0
    contact_shape : "circle" or "ellipse" (the Hertz ellipse, sized by E*)
    """

    damping: float = 0.0
    contact_radius: float | None = None
    effective_modulus: float = 0.0
    contact_shape: str = "circle"


@dataclass(frozen=True)
class Concern:
    """A parameter whose value is possible but implausible, and why."""

    parameter: str
    value: float
    reason: str

    def __str__(self) -> str:
        return f"{self.parameter} = {self.value:.6g}: {self.reason}"


def _principal_moments(body: Body) -> tuple[float, float, float]:
    """Principal moments, smallest first [kg m²], as Python floats: the ratios below
    overflow to inf without a NumPy warning (damping = 1e308 is refused, not warned)."""
    first, second, third = (float(m) for m in np.linalg.eigvalsh(body.inertia_array))
    return first, second, third


def contact_radius_at_rest(
    body: Body, contact_radius: float, effective_modulus: float = 0.0
) -> float:
    """ε at rest [m]: ``contact_radius``, or for ``effective_modulus`` E* > 0 [Pa] the Hertz
    radius (3 m g R_eq / (4 E*))^(1/3) with R_eq = sqrt(ρ1 ρ2) at the rest contact."""
    if effective_modulus <= 0.0:
        return contact_radius
    rho1, rho2 = body.shape.radii_of_curvature
    load = body.mass * body.gravity
    return (3.0 * load * math.sqrt(rho1 * rho2) / (4.0 * effective_modulus)) ** (1.0 / 3.0)


def require_runnable(body: Body, settings: ContactSettings) -> None:
    """Raise where no run of ``body`` with the model ``settings`` can mean anything.

    Raises
    ------
    ParameterError
        naming the parameter, its value, the allowed range and the reason.
    """
    rho = body.shape.radii_of_curvature
    if not all(0.0 < radius < math.inf for radius in rho):
        radii = tuple(float(r) for r in rho)
        if all(radius > 0.0 for radius in radii):
            why = (
                "at a flat point the contact moves at an unbounded rate as the stone rocks "
                "through upright, so neither model applies (a superellipsoid needs exponent 2; "
                "`celtstone stability` refuses it for the same reason)"
            )
        else:
            why = "the surface is not convex there, so the rest contact is not a single point"
        raise ParameterError(
            "shape",
            body.shape.kind,
            "a convex surface curved at its rest contact (finite radii of curvature > 0)",
            f"radii of curvature {radii} m: {why}",
        )
    moments = _principal_moments(body)
    height = body.shape.rest_height
    condition = (moments[2] + body.mass * height**2) / moments[0]
    if not condition <= MAX_CONDITION:
        raise ParameterError(
            "inertia",
            f"{moments[0]:.3g} kg m^2 (smallest principal moment) for mass {body.mass:.3g} kg",
            f"(A_max + m l^2) / A_min <= {MAX_CONDITION:.0e}",
            f"it is {condition:.3g}: the inertia about the contact is singular in double "
            f"precision; {_UNITS}",
        )
    rate = settings.damping / moments[0]
    if not rate <= MAX_DAMPING_RATE:
        raise ParameterError(
            "damping",
            settings.damping,
            f"a number <= {MAX_DAMPING_RATE * moments[0]:.3g} N m s for this body "
            f"(sigma / A_min <= {MAX_DAMPING_RATE:.0e} 1/s)",
            "the viscous torque would stop the body within a nanosecond; Kane & Levinson "
            "use sigma = 1e-4 N m s",
        )
    if settings.contact_radius is not None:
        _require_contact_radius(body, settings.contact_radius, settings.effective_modulus, min(rho))
    if settings.contact_shape == "ellipse":
        _require_ellipse_in_range(body, settings.effective_modulus)


def _require_ellipse_in_range(body: Body, effective_modulus: float) -> None:
    """The Hertz ellipse at rest must lie in the range of the elliptic law's table."""
    from celtstone.contact.ellipse import hertz_ellipse  # SciPy: only for this check
    from celtstone.contact.ellipse_table import ASPECT_MIN

    first, second = (float(r) for r in body.shape.radii_of_curvature)
    radii = (first, second)
    ellipse = hertz_ellipse(radii, body.mass * body.gravity, effective_modulus)
    aspect = ellipse.semi_minor_axis / ellipse.semi_major_axis
    if aspect < ASPECT_MIN:
        raise ParameterError(
            "contact_shape",
            "ellipse",
            f"a body whose Hertz ellipse at rest has B/A >= {ASPECT_MIN:g}",
            f"this body's has B/A = {aspect:.3g} (radii of curvature {radii} m): the "
            "elliptic law is tabulated down to that ratio; use contact_shape circle",
        )


def _require_contact_radius(
    body: Body, contact_radius: float, effective_modulus: float, rho_min: float
) -> None:
    radius = contact_radius_at_rest(body, contact_radius, effective_modulus)
    if radius < rho_min:
        return
    if effective_modulus > 0.0:
        rho1, rho2 = body.shape.radii_of_curvature
        load = body.mass * body.gravity
        least = 3.0 * load * math.sqrt(rho1 * rho2) / (4.0 * rho_min**3)
        raise ParameterError(
            "elastic_modulus",
            f"E* = E / (2 (1 - nu^2)) = {effective_modulus:.3g} Pa",
            f"E* > {least:.3g} Pa for this body",
            f"its Hertz contact radius at rest would be {radius:.3g} m, not smaller than the "
            f"radius of curvature {rho_min:.3g} m at the rest contact",
        )
    raise ParameterError(
        "contact_radius",
        contact_radius,
        f"a number < {rho_min:.3g} m, the smaller radius of curvature at the rest contact",
        "the contact disk must be small beside the surface's curvature (Hertz)",
    )


def concerns(body: Body, settings: ContactSettings) -> list[Concern]:
    """What is possible but implausible for ``body`` and the model ``settings`` (see the
    module)."""
    found: list[Concern] = []
    damping = settings.damping
    contact_radius = settings.contact_radius
    effective_modulus = settings.effective_modulus
    moments = _principal_moments(body)
    height = body.shape.rest_height
    gyration = math.sqrt(moments[0] / body.mass)
    if gyration < GYRATION_FRACTION * height:
        found.append(
            Concern(
                "inertia",
                moments[0],
                f"the radius of gyration sqrt(A_min/m) = {gyration:.3g} m is "
                f"{gyration / height:.2g} of the height of G above the contact "
                f"({height:.3g} m): a mass this concentrated is not a stone; {_UNITS}",
            )
        )
    extent = body.shape.bounding_radius
    if extent is not None:
        largest = math.sqrt(moments[2] / body.mass)
        if largest > extent:
            found.append(
                Concern(
                    "inertia",
                    moments[2],
                    f"the radius of gyration sqrt(A_max/m) = {largest:.3g} m exceeds the "
                    f"body's half-extent {extent:.3g} m: no mass inside the body has this "
                    f"inertia; {_UNITS}",
                )
            )
        if not SIZE_RANGE[0] <= extent <= SIZE_RANGE[1]:
            found.append(
                Concern(
                    "shape",
                    extent,
                    f"the body reaches {extent:.3g} m from G, outside "
                    f"[{SIZE_RANGE[0]:g}, {SIZE_RANGE[1]:g}] m for a hand-held stone; {_UNITS}",
                )
            )
    volume = body.shape.volume
    if volume is not None:
        density = body.mass / volume
        if not DENSITY_RANGE[0] <= density <= DENSITY_RANGE[1]:
            found.append(
                Concern(
                    "mass",
                    body.mass,
                    f"the mean density m / V = {density:.3g} kg/m^3 is outside "
                    f"[{DENSITY_RANGE[0]:g}, {DENSITY_RANGE[1]:g}] kg/m^3; {_UNITS}",
                )
            )
    if not GRAVITY_RANGE[0] <= body.gravity <= GRAVITY_RANGE[1]:
        found.append(
            Concern(
                "gravity",
                body.gravity,
                f"outside [{GRAVITY_RANGE[0]:g}, {GRAVITY_RANGE[1]:g}] m/s^2 (Pluto to the "
                "Sun); the rocking time scale sqrt(l/g) sets the steps",
            )
        )
    if damping > 0.0 and moments[0] / damping < MIN_DAMPING_TIME:
        found.append(
            Concern(
                "damping",
                damping,
                f"the viscous torque stops the rocking within A_min / sigma = "
                f"{moments[0] / damping:.3g} s, too soon for any reversal to show "
                f"(Kane & Levinson's sigma = 1e-4 N m s gives 2 s)",
            )
        )
    if contact_radius is not None:
        radius = contact_radius_at_rest(body, contact_radius, effective_modulus)
        rho_min = min(body.shape.radii_of_curvature)
        if radius > CONTACT_RADIUS_WARNING * rho_min:
            name = "elastic_modulus" if effective_modulus > 0.0 else "contact_radius"
            value = effective_modulus if effective_modulus > 0.0 else contact_radius
            found.append(
                Concern(
                    name,
                    value,
                    f"the contact radius at rest, {radius:.3g} m, is "
                    f"{radius / rho_min:.2g} of the smaller radius of curvature "
                    f"{rho_min:.3g} m; the disk contact assumes it is much smaller",
                )
            )
    return found
