"""The two models of the paper and the initial state, as frozen configurations.

Validation happens here, once; ``kernel_parameters`` strips the meaning and
returns the typed record the kernels read (declared in ``celtstone.kernels.layout``).
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from celtstone import plausibility, schema
from celtstone.bodies import Body
from celtstone.contact import CONTACT_PRESSURES, FRICTION_LAWS, effective_modulus
from celtstone.errors import ParameterError
from celtstone.kernels import layout
from celtstone.kernels.layout import ModelCode, NormalForce, parameter_record

__all__ = [
    "CONTACTS",
    "CONTACT_PRESSURES",
    "FRICTION_LAWS",
    "MODELS",
    "NORMAL_FORCE_OPTIONS",
    "HybridModel",
    "InitialState",
    "Model",
    "RollingModel",
    "SlidingModel",
    "initial_vector",
    "kernel_parameters",
    "model_from_name",
]

NORMAL_FORCE_OPTIONS = {option.name.lower(): option.value for option in NormalForce}


def _choice(name: str, value: str, options: dict[str, int] | dict[str, type]) -> None:
    if value not in options:
        close = difflib.get_close_matches(str(value), list(options), n=1)
        hint = f"did you mean {close[0]!r}?" if close else ""
        raise ParameterError(name, value, "one of: " + ", ".join(options), hint)


@dataclass(frozen=True)
class RollingModel:
    """Rolling without sliding, paper eq. (3)–(5); energy is conserved when σ = 0.

    Parameters
    ----------
    damping : σ, viscous torque -σω [N m s], >= 0 (Kane & Levinson's optional term)
    """

    damping: float = 0.0

    name: ClassVar[str] = "rolling"
    contact: ClassVar[str] = "rolling"
    code: ClassVar[int] = ModelCode.ROLLING.value
    default_method: ClassVar[str] = "dop853"

    def __post_init__(self) -> None:
        object.__setattr__(self, "damping", schema.check("damping", self.damping))

    @property
    def friction_law(self) -> str:
        """Name of the friction law (none: the contact does not slide)."""
        return "none"

    def attributes(self) -> dict[str, str | float]:
        """The model's settings, for provenance attributes."""
        return {
            "model": self.name,
            "contact": self.contact,
            "damping": self.damping,
            "friction_law": self.friction_law,
        }


@dataclass(frozen=True)
class SlidingModel:
    """Rolling with sliding and pivoting friction, paper eq. (6)–(12).

    Parameters
    ----------
    friction_coefficient : f [1], >= 0
    contact_radius : ε, radius of the contact disk [m], > 0; not used when
        ``elastic_modulus`` is given
    normal_force : "static" (N = m g in the friction law, the paper's first
        approximation) or "dynamic" (the consistent normal force)
    damping : σ, viscous torque -σω [N m s], >= 0
    regularisation_speed : δ, the slip speed below which friction turns viscous,
        |V1| -> sqrt(|V1|² + δ²) [m/s], > 0 (treatment of paper eq. 11)
    friction_law : "pade" (Zhuravlev's Padé law, paper eq. 10, 12) or "exact"
        (the Coulomb–Contensou integrals of paper section 2, in closed form)
    contact_pressure : "hertz" (paper eq. 2) or "uniform" pressure on the disk;
        for "pade" it selects the Padé constants (b, a, M0) of that pressure
    elastic_modulus : E, Young's modulus of body and plane [Pa], > 0, or None.
        Given, ε is the Hertz radius (3 N R_eq / (4 E*))^(1/3) for the normal
        force of the friction law (m g, or the dynamic N) and the equivalent
        radius of curvature at the current contact point, E* = E / (2(1 − ν²))
    poisson_ratio : ν of body and plane [1], in (−1, 0.5); required with
        ``elastic_modulus``
    """

    friction_coefficient: float = 0.35
    contact_radius: float = 1e-3
    normal_force: str = "static"
    damping: float = 0.0
    regularisation_speed: float = 1e-6
    friction_law: str = "pade"
    contact_pressure: str = "hertz"
    elastic_modulus: float | None = None
    poisson_ratio: float | None = None

    name: ClassVar[str] = "sliding"
    contact: ClassVar[str] = "sliding"
    code: ClassVar[int] = ModelCode.SLIDING.value
    default_method: ClassVar[str] = "radau5"

    def __post_init__(self) -> None:
        for field in ("friction_coefficient", "contact_radius", "damping", "regularisation_speed"):
            object.__setattr__(self, field, schema.check(field, getattr(self, field)))
        _choice("normal_force", self.normal_force, NORMAL_FORCE_OPTIONS)
        _choice("friction_law", self.friction_law, FRICTION_LAWS)
        _choice("contact_pressure", self.contact_pressure, CONTACT_PRESSURES)
        _check_elastic(self.elastic_modulus, self.poisson_ratio)
        for field in ("elastic_modulus", "poisson_ratio"):
            value = getattr(self, field)
            if value is not None:
                object.__setattr__(self, field, schema.check(field, value))

    @property
    def is_hertz_radius(self) -> bool:
        """Whether ε follows from Hertz theory rather than ``contact_radius``."""
        return self.elastic_modulus is not None

    @property
    def effective_modulus(self) -> float:
        """E* = E / (2(1 − ν²)) [Pa], 0 when ε is fixed."""
        if self.elastic_modulus is None or self.poisson_ratio is None:
            return 0.0
        return effective_modulus(self.elastic_modulus, self.poisson_ratio)

    def attributes(self) -> dict[str, str | float]:
        """The model's settings, for provenance attributes ("none": not set)."""
        return {
            "model": self.name,
            "contact": self.contact,
            "damping": self.damping,
            "friction_law": self.friction_law,
            "contact_pressure": self.contact_pressure,
            "friction_coefficient": self.friction_coefficient,
            "contact_radius": self.contact_radius,
            "contact_radius_model": "hertz" if self.is_hertz_radius else "fixed",
            "elastic_modulus": _or_none(self.elastic_modulus),
            "poisson_ratio": _or_none(self.poisson_ratio),
            "effective_modulus": _or_none(self.effective_modulus if self.is_hertz_radius else None),
            "normal_force_option": self.normal_force,
            "regularisation_speed": self.regularisation_speed,
        }


def _or_none(value: float | None) -> float | str:
    return "none" if value is None else value


def _check_elastic(elastic_modulus: float | None, poisson_ratio: float | None) -> None:
    """E and ν come together: one without the other is refused."""
    for given, missing, value in (
        (elastic_modulus, "poisson_ratio", poisson_ratio),
        (poisson_ratio, "elastic_modulus", elastic_modulus),
    ):
        if given is not None and value is None:
            allowed = schema.PARAMETERS[missing].allowed
            raise ParameterError(missing, None, allowed, "E and nu are given together")


@dataclass(frozen=True)
class HybridModel(SlidingModel):
    """Stick–slip contact: the sliding model while the contact slides or pivots, rolling
    without sliding and without pivoting while the friction that needs lies inside the
    Coulomb–Contensou limit set; phase changes are located as events (``celtstone.hybrid``).

    Parameters
    ----------
    friction_coefficient, contact_radius, normal_force, damping : as :class:`SlidingModel`
    regularisation_speed : δ [m/s], > 0: only smooths the first instant of sliding after
        stick (V1 = 0, ω · n = 0, where Zhuravlev's law is 0/0); must be below
        capture_speed / 10 so that stick is found in the dry-friction regime
    capture_speed : v_c [m/s], > 0, or None for 100 atol: the slip–spin speed
        sqrt(|V1|² + ε²(ω · n)²) counted as zero, a numerical zero like an event
        tolerance (phase times converge as it shrinks; docs/decisions.md)
    """

    regularisation_speed: float = 1e-12
    capture_speed: float | None = None

    contact: ClassVar[str] = "hybrid"

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.capture_speed is not None:
            object.__setattr__(
                self, "capture_speed", schema.check("capture_speed", self.capture_speed)
            )

    def resolved_capture_speed(self, atol: float) -> float:
        """v_c for a run at absolute tolerance ``atol``; checks δ < v_c / 10 [m/s]."""
        capture = CAPTURE_ATOL_FACTOR * atol if self.capture_speed is None else self.capture_speed
        if not self.regularisation_speed <= 0.1 * capture:
            raise ParameterError(
                "regularisation_speed",
                self.regularisation_speed,
                f"<= capture_speed / 10 = {0.1 * capture:g} m/s in the hybrid contact",
                "lower regularisation_speed or raise capture_speed",
            )
        return capture

    def attributes(self) -> dict[str, str | float]:
        """The model's settings, for provenance attributes (capture_speed "none": 100 atol;
        a run records the resolved value)."""
        return {**super().attributes(), "capture_speed": _or_none(self.capture_speed)}


# default capture speed of the hybrid contact in units of the absolute tolerance
CAPTURE_ATOL_FACTOR = 100.0

Model = RollingModel | SlidingModel
MODELS: dict[str, type[RollingModel] | type[SlidingModel]] = {
    "rolling": RollingModel,
    "sliding": SlidingModel,
}
# contact options of the sliding model
CONTACTS: dict[str, type[SlidingModel]] = {"sliding": SlidingModel, "hybrid": HybridModel}


def model_from_name(name: str, **settings: float | str | None) -> Model:
    """Build a model by registry name; unknown names list the valid ones.

    ``contact`` ("sliding" or "hybrid") picks the contact of the sliding model. Settings
    that are None are left at their defaults; a setting the model does not have (a
    friction setting of the rolling model, a capture speed without the hybrid contact)
    is refused.
    """
    _choice("model", name, MODELS)
    contact = settings.pop("contact", None)
    settings = {k: v for k, v in settings.items() if v is not None}
    cls = MODELS[name]
    if contact is not None:
        _choice("contact", str(contact), CONTACTS)
        if cls is SlidingModel:
            cls = CONTACTS[str(contact)]
        elif contact != "sliding":
            raise ParameterError(
                "contact", contact, "sliding with the rolling model", "use --model sliding"
            )
    if cls is SlidingModel and "capture_speed" in settings:
        raise ParameterError(
            "capture_speed",
            settings["capture_speed"],
            "no value with the sliding contact",
            "the capture speed belongs to the stick-slip contact: add contact 'hybrid'",
        )
    if cls is RollingModel:
        for key, value in settings.items():
            if key != "damping":  # a sliding setting given to rolling is a mistake, not a no-op
                raise ParameterError(
                    key,
                    value,
                    "no value with the rolling model (its one setting is damping)",
                    "the contact does not slide; use the model 'sliding' for friction settings",
                )
    return cls(**settings)  # type: ignore[arg-type]


@dataclass(frozen=True)
class InitialState:
    """Initial attitude and angular velocity; the contact starts without slip.

    Parameters
    ----------
    omega : ω0, angular velocity in body axes [rad/s]
    tilt : (α, β), Euler angles [deg]: the vertical in body axes is
        n0 = (-cos α sin β, sin α, cos α cos β) (Kane & Levinson's convention)
    """

    omega: tuple[float, float, float] = (0.0, 0.0, -5.0)
    tilt: tuple[float, float] = (0.5, 0.5)

    def __post_init__(self) -> None:
        if len(self.omega) != 3:
            raise ParameterError("omega", self.omega, "three numbers W1,W2,W3 in rad/s")
        if len(self.tilt) != 2:
            raise ParameterError("tilt", self.tilt, "two numbers ALPHA,BETA in deg")
        object.__setattr__(self, "omega", tuple(schema.check("omega", w) for w in self.omega))
        object.__setattr__(self, "tilt", tuple(schema.check("tilt", t) for t in self.tilt))

    @property
    def vertical(self) -> tuple[float, float, float]:
        """n0, the upward vertical in body axes [1]."""
        alpha, beta = (math.radians(t) for t in self.tilt)
        return (
            -math.cos(alpha) * math.sin(beta),
            math.sin(alpha),
            math.cos(alpha) * math.cos(beta),
        )

    def mirrored(self) -> InitialState:
        """The state mirrored in the plane x2 = 0 of the body (pairs with D -> -D)."""
        w1, w2, w3 = self.omega
        alpha, beta = self.tilt
        return InitialState(omega=(-w1, w2, -w3), tilt=(-alpha, beta))


def kernel_parameters(model: Model, body: Body) -> np.record:
    """The kernel parameter record of a run (a record of ``kernels.layout.PARAMETERS``).

    The records of several runs stack with ``np.array([...])`` into an array whose
    ``[i]`` is one run's record (``solvers.batch``).

    Raises
    ------
    ParameterError
        where no run of ``body`` with ``model`` can mean anything
        (:func:`celtstone.plausibility.require_runnable`).
    """
    plausibility.require_runnable(body, contact_settings(model))
    fields = {
        "mass": body.mass,
        "gravity": body.gravity,
        "inertia": body.inertia,
        "damping": model.damping,
        **body.shape.kernel_fields(),
    }
    if isinstance(model, SlidingModel):
        fields |= {
            "friction_coefficient": model.friction_coefficient,
            "contact_radius": model.contact_radius,
            "normal_force_option": NORMAL_FORCE_OPTIONS[model.normal_force],
            "regularisation_speed": model.regularisation_speed,
            "friction_law": FRICTION_LAWS[model.friction_law],
            "contact_pressure": CONTACT_PRESSURES[model.contact_pressure],
            "effective_modulus": model.effective_modulus,  # 0: the fixed contact_radius
        }
    return parameter_record(**fields)


def contact_settings(model: Model) -> plausibility.ContactSettings:
    """What the plausibility checks read of ``model`` (``celtstone.plausibility``)."""
    if isinstance(model, SlidingModel):
        return plausibility.ContactSettings(
            model.damping, model.contact_radius, model.effective_modulus
        )
    return plausibility.ContactSettings(model.damping)


def initial_vector(state: InitialState) -> np.ndarray:
    """Flat state array at t = 0: n0, ω0, V1 = 0, attitude, position 0, work 0.

    The attitude quaternion is the smallest rotation taking n0 to the space
    vertical e_z (heading 0).
    """
    y = np.zeros(layout.N_STATE)
    n = np.array(state.vertical)
    y[layout.Y_N : layout.Y_N + 3] = n
    y[layout.Y_OMEGA : layout.Y_OMEGA + 3] = state.omega
    axis = np.cross(n, [0.0, 0.0, 1.0])
    sine = float(np.linalg.norm(axis))
    angle = math.atan2(sine, float(n[2]))
    quaternion = np.array([1.0, 0.0, 0.0, 0.0])
    if sine > 0.0:
        quaternion = np.concatenate([[math.cos(angle / 2)], axis / sine * math.sin(angle / 2)])
    y[layout.Y_QUAT : layout.Y_QUAT + 4] = quaternion
    return y
