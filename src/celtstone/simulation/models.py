"""The two models of the paper and the initial state, as frozen configurations.

Validation happens here, once; ``kernel_parameters`` strips the meaning and
returns the typed record the kernels read (declared in ``celtstone.kernels.layout``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import KW_ONLY, InitVar, dataclass, fields
from typing import Any, ClassVar

import numpy as np

from celtstone.bodies import Body
from celtstone.contact import (
    CONTACT_PRESSURES,
    CONTACT_SHAPES,
    FRICTION_LAWS,
    LAW_WORDS,
    PRESSURE_WORDS,
    SHAPE_WORDS,
    choice_words,
    effective_modulus,
)
from celtstone.errors import ParameterError, require_choice
from celtstone.kernels import layout
from celtstone.kernels.layout import FrictionLoad, ModelCode, parameter_record
from celtstone.simulation import plausibility, schema

__all__ = [
    "CONTACTS",
    "CONTACT_PRESSURES",
    "CONTACT_SHAPES",
    "FRICTION_LAWS",
    "FRICTION_LOAD_OPTIONS",
    "MODELS",
    "MODEL_KINDS",
    "SETTINGS",
    "HybridModel",
    "InitialState",
    "Model",
    "RollingModel",
    "Setting",
    "SlidingModel",
    "initial_vector",
    "kernel_parameters",
    "model_from_name",
    "setting_defaults",
    "settings_of",
]

FRICTION_LOAD_OPTIONS = {option.name.lower(): option.value for option in FrictionLoad}

# ε [m] of the sliding model by default: the paper's 1 mm Hertz contact radius
FIXED_CONTACT_RADIUS = 1e-3

# ω_0 [rad/s] of the rolling resistance: 0.5 % of the rolling rate of a K&L stone rocking
# at 2° (about 0.2 rad/s); docs/decisions.md §25 measures its effect
DEFAULT_ROLLING_RESISTANCE_RATE = 1e-3


@dataclass(frozen=True)
class Setting:
    """A model setting, declared once: the model's field of this ``name`` is validated,
    offered on the command line (``--name-with-dashes``) and in sweeps, recorded in a
    run's attributes and copied into the kernel record from this row.

    Parameters
    ----------
    name : the model's field, the CLI option, the sweep parameter and the run's attribute
    choices : for a named option, name -> kernel code (an IntEnum's members); None for
        a number, checked by ``schema.PARAMETERS[name]`` (its unit and range)
    words : for a named option, what each choice means (help text)
    record : the kernel record's field it fills (codes for a choice), or None
    optional : whether None ("not set") is allowed
    default_words : what the default means when it is None ("not set" otherwise)
    """

    name: str
    choices: Mapping[str, int] | None = None
    words: str = ""
    record: str | None = None
    optional: bool = False
    default_words: str = ""

    def check(self, value: Any) -> Any:
        """``value`` validated: a choice's name, or a number in its range (None if optional)."""
        if value is None and self.optional:
            return None
        if self.choices is not None:
            require_choice(self.name, value, self.choices)
            return value
        return schema.check(self.name, value)

    def help(self) -> str:
        """The setting in words, with its unit and range or its choices (CLI help)."""
        if self.choices is None:
            return schema.PARAMETERS[self.name].help()
        return self.words or " or ".join(self.choices)


SETTINGS: dict[str, Setting] = {
    s.name: s
    for s in (
        Setting("damping", record="damping"),
        Setting("rolling_resistance", record="rolling_resistance"),
        Setting("rolling_resistance_rate", record="rolling_resistance_rate"),
        Setting("friction_coefficient", record="friction_coefficient"),
        Setting("contact_radius", record="contact_radius"),
        Setting(
            "friction_load",
            FRICTION_LOAD_OPTIONS,
            "the normal force in the friction law: static (N = m g, the paper's first "
            "approximation) or dynamic (the consistent normal force)",
            record="friction_load",
        ),
        Setting("regularisation_speed", record="regularisation_speed"),
        Setting(
            "friction_law",
            FRICTION_LAWS,
            choice_words(LAW_WORDS),
            record="friction_law",
        ),
        Setting(
            "contact_pressure",
            CONTACT_PRESSURES,
            choice_words(PRESSURE_WORDS),
            record="contact_pressure",
        ),
        Setting(
            "contact_shape",
            CONTACT_SHAPES,
            choice_words(SHAPE_WORDS),
            record="contact_shape",
        ),
        Setting(  # the record holds E* (effective_modulus)
            "elastic_modulus",
            optional=True,
            default_words="not set: the fixed contact_radius; given with poisson_ratio, the "
            "Hertz radius, and contact_radius may not be given",
        ),
        Setting("poisson_ratio", optional=True, default_words="not set; given with E"),
        Setting("capture_speed", optional=True, default_words="100 atol"),  # resolved per run
    )
}


MODEL_KINDS: dict[str, type[RollingModel] | type[SlidingModel]] = {}  # filled below


def setting_defaults(name: str) -> dict[str, Any]:
    """Kind of model ("rolling", "sliding", "hybrid") -> its default of setting ``name``,
    for the kinds that have it."""
    found = {}
    for kind, cls in MODEL_KINDS.items():
        for field in fields(cls):
            if field.name == name:
                found[kind] = field.default
    return found


def settings_of(kind: str) -> tuple[str, ...]:
    """The settings (:data:`SETTINGS` names) of the kind of model ``kind`` ("rolling",
    "sliding", "hybrid")."""
    return tuple(field.name for field in fields(MODEL_KINDS[kind]))


def _check_settings(model: Any) -> None:
    """Validate every field of ``model`` by its :data:`SETTINGS` row (numbers as floats)."""
    for field in fields(model):
        object.__setattr__(
            model, field.name, SETTINGS[field.name].check(getattr(model, field.name))
        )


def _recorded(model: Any) -> dict[str, Any]:
    """The kernel-record fields of ``model``'s settings (choices as their codes)."""
    values = {}
    for field in fields(model):
        setting = SETTINGS[field.name]
        if setting.record is not None:
            value = getattr(model, field.name)
            values[setting.record] = value if setting.choices is None else setting.choices[value]
    return values


def _settings_attributes(model: Any) -> dict[str, Any]:
    """Each setting of ``model`` as a provenance attribute ("none": not set)."""
    return {field.name: _or_none(getattr(model, field.name)) for field in fields(model)}


@dataclass(frozen=True)
class RollingModel:
    """Rolling without sliding, paper eq. (3)–(5); energy is conserved when σ = 0.

    Parameters
    ----------
    damping : float
        Coefficient σ of the viscous torque −σω [N m s], >= 0 (Kane & Levinson's
        optional term).
    rolling_resistance : float
        Rolling-friction length λ [m], in [0, 0.01]: the moment −λ N ĥ against the
        rolling part ω_t of ω (docs/equations.md); 0: none.
    rolling_resistance_rate : float
        Regularising rate ω_0 [rad/s], > 0: ĥ = ω_t / sqrt(|ω_t|² + ω_0²).
    """

    damping: float = 0.0
    rolling_resistance: float = 0.0
    rolling_resistance_rate: float = DEFAULT_ROLLING_RESISTANCE_RATE

    name: ClassVar[str] = "rolling"
    contact: ClassVar[str] = "rolling"
    code: ClassVar[int] = ModelCode.ROLLING.value
    default_method: ClassVar[str] = "vern9"

    def __post_init__(self) -> None:
        _check_settings(self)

    @property
    def friction_law(self) -> str:
        """Name of the friction law (none: the contact does not slide)."""
        return "none"

    def attributes(self) -> dict[str, str | float]:
        """Give the model's settings, for provenance attributes.

        Returns
        -------
        dict of str to str or float
            Model, contact, every setting and the friction law ("none").
        """
        return {
            "model": self.name,
            "contact": self.contact,
            **_settings_attributes(self),
            "friction_law": self.friction_law,
        }


@dataclass(frozen=True)
class SlidingModel:
    """Rolling with sliding and pivoting friction, paper eq. (6)–(12).

    Parameters
    ----------
    friction_coefficient : float
        Coefficient f of dry friction [1], >= 0.
    contact_radius : float
        Radius ε of the contact disk [m], > 0; with ``elastic_modulus`` the radius is
        Hertz's, and a ``contact_radius`` other than the default is refused (it would
        have no effect).
    friction_load : {"static", "dynamic"}
        The normal force in the friction law: N = m g (the paper's first
        approximation) or the consistent normal force.
    damping : float
        Coefficient σ of the viscous torque −σω [N m s], >= 0.
    regularisation_speed : float
        Slip speed δ below which friction turns viscous, |V1| -> sqrt(|V1|² + δ²)
        [m/s], > 0 (treatment of paper eq. 11).
    friction_law : {"pade", "exact"}
        Zhuravlev's Padé law (paper eq. 10, 12) or the Coulomb–Contensou integrals
        of paper section 2, in closed form.
    contact_pressure : {"hertz", "uniform"}
        Pressure on the disk (Hertz: paper eq. 2); for "pade" it selects the Padé
        constants (b, a, M0) of that pressure.
    contact_shape : {"circle", "ellipse"}
        The paper's disk of radius ε, or the Hertz ellipse of the two principal radii
        of curvature at the current contact point, semi-axes A >= B from N and E*;
        the ellipse needs ``elastic_modulus`` and the Hertz pressure, and its friction
        law is the disk's law of radius A corrected by the tabulated ratios of the
        exact elliptic to the exact circular law (docs/decisions.md §29).
    elastic_modulus : float or None
        E, Young's modulus of body and plane [Pa], > 0. Given, ε is the Hertz radius
        (3 N R_eq / (4 E*))^(1/3) for the normal force of the friction law (m g, or
        the dynamic N) and the equivalent radius of curvature at the current contact
        point, E* = E / (2(1 − ν²)).
    poisson_ratio : float or None
        Poisson's ratio ν of body and plane [1], in (−1, 0.5); required with
        ``elastic_modulus``.
    rolling_resistance, rolling_resistance_rate : float
        Length λ [m] and rate ω_0 [rad/s] as in :class:`RollingModel`; the moment is
        loaded like the friction (``friction_load``).
    """

    friction_coefficient: float = 0.35
    contact_radius: float = FIXED_CONTACT_RADIUS
    friction_load: str = "static"
    damping: float = 0.0
    regularisation_speed: float = 1e-10
    friction_law: str = "pade"
    contact_pressure: str = "hertz"
    contact_shape: str = "circle"
    elastic_modulus: float | None = None
    poisson_ratio: float | None = None
    rolling_resistance: float = 0.0
    rolling_resistance_rate: float = DEFAULT_ROLLING_RESISTANCE_RATE

    name: ClassVar[str] = "sliding"
    contact: ClassVar[str] = "sliding"
    code: ClassVar[int] = ModelCode.SLIDING.value
    default_method: ClassVar[str] = "auto"

    def __post_init__(self) -> None:
        _check_settings(self)
        _check_elastic(self.elastic_modulus, self.poisson_ratio)
        if self.contact_radius != FIXED_CONTACT_RADIUS:
            _check_radius_source(self.contact_radius, self.elastic_modulus)
        _check_ellipse(self)

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
        """Give the model's settings, for provenance attributes.

        Returns
        -------
        dict of str to str or float
            Model, contact and every setting ("none": not set), with how ε is found.
        """
        return {
            "model": self.name,
            "contact": self.contact,
            **_settings_attributes(self),
            "contact_radius_model": "hertz" if self.is_hertz_radius else "fixed",
            "effective_modulus": _or_none(self.effective_modulus if self.is_hertz_radius else None),
        }


def _or_none(value: Any) -> Any:
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


def _check_radius_source(contact_radius: object, elastic_modulus: float | None) -> None:
    """A fixed ε and the Hertz radius of E, ν are two answers to one question: refused
    together, so that no run records a contact radius it did not use."""
    if elastic_modulus is not None:
        raise ParameterError(
            "contact_radius",
            contact_radius,
            "no value with elastic_modulus",
            "with elastic_modulus and poisson_ratio the contact's size is Hertz's, from the "
            "normal force and the curvature at the contact, and a fixed contact_radius has "
            "no effect: give one or the other",
        )


def _check_ellipse(model: SlidingModel) -> None:
    """The elliptic contact needs the Hertz pressure and E, ν to size the ellipse."""
    if model.contact_shape != "ellipse":
        return
    if model.elastic_modulus is None:
        raise ParameterError(
            "contact_shape",
            "ellipse",
            "circle, or ellipse with elastic_modulus and poisson_ratio",
            "the Hertz ellipse's size follows from E and nu: give --elastic-modulus and "
            "--poisson-ratio",
        )
    if model.contact_pressure != "hertz":
        raise ParameterError(
            "contact_pressure",
            model.contact_pressure,
            "hertz with contact_shape ellipse",
            "the ellipse is Hertz's, with Hertz's pressure",
        )


@dataclass(frozen=True)
class HybridModel(SlidingModel):
    """Stick–slip contact: sliding while the contact slides or pivots, else rolling.

    The sliding model while the contact slides or pivots; rolling without sliding and
    without pivoting while the friction that needs lies inside the Coulomb–Contensou
    limit set. Phase changes are located as events (``celtstone.solvers.phases``).

    Parameters
    ----------
    friction_coefficient, contact_radius, friction_load, damping : float or str
        As :class:`SlidingModel`.
    regularisation_speed : float
        Slip speed δ [m/s], > 0: only smooths the first instant of sliding after stick
        (V1 = 0, ω · n = 0, where Zhuravlev's law is 0/0); must be below
        capture_speed / 10 so that stick is found in the dry-friction regime.
    friction_law, contact_pressure, contact_shape, elastic_modulus : str or float
        As :class:`SlidingModel`.
    poisson_ratio, rolling_resistance, rolling_resistance_rate : float
        As :class:`SlidingModel`.
    capture_speed : float or None
        Capture speed v_c [m/s], > 0, or None for 100 atol: the slip–spin speed
        sqrt(|V1|² + ε²(ω · n)²) counted as zero, a numerical zero like an event
        tolerance (phase times converge as it shrinks; docs/decisions.md §16).
    """

    regularisation_speed: float = 1e-12
    capture_speed: float | None = None

    contact: ClassVar[str] = "hybrid"

    def resolved_capture_speed(self, atol: float) -> float:
        """Return v_c [m/s] for a run at ``atol``, after checking δ < v_c / 10.

        Parameters
        ----------
        atol : float
            The run's absolute tolerance.

        Returns
        -------
        float
            ``capture_speed``, or 100 ``atol`` when it is None [m/s].
        """
        capture = CAPTURE_ATOL_FACTOR * atol if self.capture_speed is None else self.capture_speed
        if not self.regularisation_speed <= 0.1 * capture:
            raise ParameterError(
                "regularisation_speed",
                self.regularisation_speed,
                f"<= capture_speed / 10 = {0.1 * capture:g} m/s in the hybrid contact",
                "lower regularisation_speed or raise capture_speed",
            )
        return capture


# default capture speed of the hybrid contact in units of the absolute tolerance
CAPTURE_ATOL_FACTOR = 100.0

Model = RollingModel | SlidingModel
MODELS: dict[str, type[RollingModel] | type[SlidingModel]] = {
    "rolling": RollingModel,
    "sliding": SlidingModel,
}
"""The models by name: ``model_from_name``, ``celtstone run --model`` and sweeps read it."""

# contact options of the sliding model
CONTACTS: dict[str, type[SlidingModel]] = {"sliding": SlidingModel, "hybrid": HybridModel}
MODEL_KINDS.update(rolling=RollingModel, sliding=SlidingModel, hybrid=HybridModel)


def model_from_name(name: str, **settings: float | str | None) -> Model:
    """Build a model by registry name; unknown names list the valid ones.

    Parameters
    ----------
    name : {"rolling", "sliding"}
        A key of :data:`MODELS`.
    **settings : float, str or None
        The model's settings by name; None leaves a setting at its default.
        ``contact`` ("sliding" or "hybrid") picks the contact of the sliding model. A
        setting the model does not have (a friction setting of the rolling model, a
        capture speed without the hybrid contact) is refused.

    Returns
    -------
    RollingModel, SlidingModel or HybridModel
        The model, its settings checked.
    """
    require_choice("model", name, MODELS)
    contact = settings.pop("contact", None)
    settings = {k: v for k, v in settings.items() if v is not None}
    for key, value in settings.items():
        if key in schema.RENAMED:
            raise schema.renamed(key, value)
    cls = MODELS[name]
    if contact is not None:
        require_choice("contact", str(contact), CONTACTS)
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
        own = settings_of(RollingModel.name)
        for key, value in settings.items():
            if key not in own:  # a sliding setting given to rolling is a mistake, not a no-op
                raise ParameterError(
                    key,
                    value,
                    f"no value with the rolling model (its settings: {', '.join(own)})",
                    "the contact does not slide; use the model 'sliding' for friction settings",
                )
    if "contact_radius" in settings:  # given, even at its default value
        _check_radius_source(settings["contact_radius"], settings.get("elastic_modulus"))  # type: ignore[arg-type]
    return cls(**settings)  # type: ignore[arg-type]


@dataclass(frozen=True)
class InitialState:
    """Initial attitude, angular velocity and sliding velocity of the contact.

    Parameters
    ----------
    omega : tuple of 3 float
        Angular velocity ω0 in body axes [rad/s].
    euler_angles : tuple of 2 float
        (α, β), Euler angles [deg]: the vertical in body axes is
        n0 = (−cos α sin β, sin α, cos α cos β) (Kane & Levinson's convention).
    slip_velocity : tuple of 2 float
        (V1, V2), the contact point's sliding velocity along body axes 1 and 2 [m/s]
        (keyword only). Its axis-3 part V3 = −(V1 n1 + V2 n2) / n3 keeps it in the table
        plane (V · n0 = 0). Default 0: the contact starts without slip (a release); a
        record that starts mid-motion may start sliding. Only the sliding models
        (sliding, stick-slip) have it: a rolling contact cannot slip.
    tilt : None
        The old name of ``euler_angles``, refused (``tilt`` is the output angle [rad]).
    """

    omega: tuple[float, float, float] = (0.0, 0.0, -5.0)
    euler_angles: tuple[float, float] = (0.5, 0.5)
    _: KW_ONLY
    slip_velocity: tuple[float, float] = (0.0, 0.0)
    tilt: InitVar[tuple[float, float] | None] = None

    def __post_init__(self, tilt: tuple[float, float] | None) -> None:
        if tilt is not None:
            raise schema.renamed("tilt", tilt)
        omega = schema.check_components("omega", self.omega, 3, "three numbers W1,W2,W3 in rad/s")
        angles = schema.check_components(
            "euler_angles", self.euler_angles, 2, "two numbers ALPHA,BETA in deg"
        )
        slip = schema.check_components(
            "slip_velocity", self.slip_velocity, 2, "two numbers V1,V2 in m/s"
        )
        object.__setattr__(self, "omega", omega)
        object.__setattr__(self, "euler_angles", angles)
        object.__setattr__(self, "slip_velocity", slip)

    @property
    def is_sliding(self) -> bool:
        """Whether the contact point starts sliding (a slip velocity other than 0)."""
        return any(v != 0.0 for v in self.slip_velocity)

    @property
    def slip(self) -> tuple[float, float, float]:
        """The initial sliding velocity V in body axes [m/s], in the table plane."""
        if not self.is_sliding:
            return (0.0, 0.0, 0.0)  # a release: +0.0, as runs were started before the slip
        n = self.vertical
        v1, v2 = self.slip_velocity
        return (v1, v2, -(v1 * n[0] + v2 * n[1]) / n[2])

    @property
    def vertical(self) -> tuple[float, float, float]:
        """The upward vertical n0 in body axes [1]."""
        alpha, beta = (math.radians(angle) for angle in self.euler_angles)
        return (
            -math.cos(alpha) * math.sin(beta),
            math.sin(alpha),
            math.cos(alpha) * math.cos(beta),
        )

    def mirrored(self) -> InitialState:
        """Mirror the state in the plane x2 = 0 of the body (pairs with D -> -D).

        Returns
        -------
        InitialState
            The mirrored state.
        """
        w1, w2, w3 = self.omega
        alpha, beta = self.euler_angles
        v1, v2 = self.slip_velocity  # a velocity (polar): its axis-2 part flips
        return InitialState(
            omega=(-w1, w2, -w3), euler_angles=(-alpha, beta), slip_velocity=(v1, -v2)
        )


def kernel_parameters(model: Model, body: Body) -> np.record:
    """The kernel parameter record of a run (a record of ``kernels.layout.PARAMETERS``).

    The records of several runs stack with ``np.array([...])`` into an array whose
    ``[i]`` is one run's record (``solvers.batch``).

    Raises
    ------
    ParameterError
        where no run of ``body`` with ``model`` can mean anything
        (:func:`celtstone.simulation.plausibility.require_runnable`).
    """
    plausibility.require_runnable(body, contact_settings(model))
    values = {
        "mass": body.mass,
        "gravity": body.gravity,
        "inertia": body.inertia,
        **body.shape.kernel_fields(),
        **_recorded(model),
    }
    if isinstance(model, SlidingModel):
        values["effective_modulus"] = model.effective_modulus  # 0: the fixed contact_radius
    return parameter_record(**values)


def contact_settings(model: Model) -> plausibility.ContactSettings:
    """What the plausibility checks read of ``model`` (``celtstone.simulation.plausibility``)."""
    if isinstance(model, SlidingModel):
        return plausibility.ContactSettings(
            model.damping, model.contact_radius, model.effective_modulus, model.contact_shape
        )
    return plausibility.ContactSettings(model.damping)


def initial_vector(state: InitialState) -> np.ndarray:
    """Flat state array at t = 0: n0, ω0, V1 (``InitialState.slip``), attitude, position 0,
    work 0.

    The attitude quaternion is the smallest rotation taking n0 to the space
    vertical e_z (heading 0).
    """
    y = np.zeros(layout.N_STATE)
    n = np.array(state.vertical)
    y[layout.Y_N : layout.Y_N + 3] = n
    y[layout.Y_OMEGA : layout.Y_OMEGA + 3] = state.omega
    y[layout.Y_SLIP : layout.Y_SLIP + 3] = state.slip
    axis = np.cross(n, [0.0, 0.0, 1.0])
    sine = float(np.linalg.norm(axis))
    angle = math.atan2(sine, float(n[2]))
    quaternion = np.array([1.0, 0.0, 0.0, 0.0])
    if sine > 0.0:
        quaternion = np.concatenate([[math.cos(angle / 2)], axis / sine * math.sin(angle / 2)])
    y[layout.Y_QUAT : layout.Y_QUAT + 4] = quaternion
    return y
