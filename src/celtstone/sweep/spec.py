"""What a sweep varies: parameter names, axis parsing, and points turned into kernel arrays.

Every sweepable name belongs to one group: the body, the model or the initial state.
A point's values are validated once, by building the validated objects
(:class:`Body`, the model, :class:`InitialState`), and then stripped to the flat
kernel arrays. Objects are built once per distinct combination of each group's
values, so a 256 x 256 grid over friction and initial spin builds 256 models and 256
initial states, not 65 536 of each. The model's numbers and options are its settings
(``models.SETTINGS``), with their meaning and unit from ``schema.PARAMETERS``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from celtstone.bodies import SHAPES, Body
from celtstone.bodies.declaration import SweepName
from celtstone.errors import CeltstoneError, ParameterError, did_you_mean, require_choice
from celtstone.simulation import plausibility, schema
from celtstone.simulation.models import (
    CONTACTS,
    SETTINGS,
    HybridModel,
    InitialState,
    Model,
    contact_settings,
    initial_vector,
    kernel_parameters,
    model_from_name,
)
from celtstone.sweep import budget

__all__ = [
    "BODY",
    "MODEL",
    "PARAMETERS",
    "STATE",
    "Axis",
    "AxisSpec",
    "PointBuilder",
    "check_name",
    "parse_axis",
    "parse_axis_spec",
]

BODY = "body"
MODEL = "model"
STATE = "state"


@dataclass(frozen=True)
class SweepParameter:
    """A sweepable name: its group, unit and meaning (units from ``schema``)."""

    name: str
    group: str
    unit: str
    description: str


def _p(
    name: str, group: str, schema_name: str | None, description: str, unit: str = ""
) -> SweepParameter:
    if schema_name is not None:
        unit = schema.PARAMETERS[schema_name].unit
    return SweepParameter(name, group, unit, description)


def _shape_parameters() -> list[SweepParameter]:
    """The numbers of the registry's shapes a sweep may vary (``Shape.sweep_names``),
    each once, with the kinds that have it."""
    kinds: dict[str, list[str]] = {}
    first: dict[str, tuple[SweepName, str]] = {}
    for kind, cls in SHAPES.items():
        units = {entry.key: entry.quantity.unit for entry in cls.entries}
        for sweep in cls.sweep_names:
            kinds.setdefault(sweep.name, []).append(kind)
            first.setdefault(sweep.name, (sweep, units[sweep.field]))
    return [
        SweepParameter(name, BODY, unit, f"{sweep.description} ({', '.join(kinds[name])})")
        for name, (sweep, unit) in first.items()
    ]


def _setting_description(name: str) -> str:
    """A model setting in words, from its ``schema.PARAMETERS`` entry: ``"Coulomb friction
    coefficient (f)"``."""
    quantity = schema.PARAMETERS[name]
    return f"{quantity.description} ({quantity.symbol})"


# the names of numbers of some shape (each shape refuses the others' in ``replaced``)
_SHAPE_NAMES = frozenset(sweep.name for cls in SHAPES.values() for sweep in cls.sweep_names)

PARAMETERS: dict[str, SweepParameter] = {
    p.name: p
    for p in [
        _p("mass", BODY, "mass", "mass of the body m"),
        _p("gravity", BODY, "gravity", "gravitational acceleration g"),
        *(
            _p(f"inertia_{i}{j}", BODY, "inertia", f"central inertia tensor component A{i}{j}")
            for i, j in ((1, 1), (2, 2), (3, 3), (1, 2), (1, 3), (2, 3))
        ),
        _p(
            "misalignment_angle",
            BODY,
            None,
            "angle from body axis 1 to the horizontal principal axis nearest it, in "
            "(-pi/4, pi/4); the principal moments are kept",
            unit="rad",
        ),
        *_shape_parameters(),
        *(  # every number of a model (models.SETTINGS), its meaning from schema
            _p(name, MODEL, name, _setting_description(name))
            for name, setting in SETTINGS.items()
            if setting.choices is None
        ),
        _p(
            "initial_spin",
            STATE,
            None,
            "initial spin omega0 . n0 (sets omega3, given omega1, omega2 and the Euler angles)",
            unit="rad/s",
        ),
        _p("omega1", STATE, "omega", "initial angular velocity, body axis 1"),
        _p("omega2", STATE, "omega", "initial angular velocity, body axis 2"),
        _p("omega3", STATE, "omega", "initial angular velocity, body axis 3"),
        _p("euler_alpha", STATE, "euler_angles", "initial Euler angle alpha"),
        _p("euler_beta", STATE, "euler_angles", "initial Euler angle beta"),
        _p("slip_velocity1", STATE, "slip_velocity", "initial sliding velocity, body axis 1"),
        _p("slip_velocity2", STATE, "slip_velocity", "initial sliding velocity, body axis 2"),
    ]
}
"""Every name a sweep can vary (body, model and initial-state numbers) -> its group, unit
and meaning."""

# fixed settings that are not numbers (``--set`` only), with their options: the model's
# named options (models.SETTINGS) and the contact of the sliding model
CHOICES: dict[str, tuple[str, ...]] = {
    **{name: tuple(s.choices) for name, s in SETTINGS.items() if s.choices is not None},
    "contact": tuple(CONTACTS),  # of the sliding model: "hybrid" is the stick–slip contact
}
_CONFLICTS = (("initial_spin", "omega3"), ("misalignment_angle", "inertia_12"))
VALIDATION_PROGRESS_EVERY = 1000  # objects built between two progress reports


def check_name(name: str) -> SweepParameter:
    """The sweep parameter ``name``; unknown names raise with the closest match, and an
    old name (``schema.RENAMED``) with its new one."""
    if name in PARAMETERS:
        return PARAMETERS[name]
    names = [*PARAMETERS, *CHOICES]
    new = schema.RENAMED.get(name, name)  # an old name suggests its new one, or the closest
    if new != name and new in names:
        hint = schema.renamed_hint(name)
    else:
        hint = did_you_mean(new, names, cutoff=0.5) or "see `celtstone sweep --help`"
    raise ParameterError("parameter", name, "a sweep parameter name", hint)


@dataclass(frozen=True)
class Axis:
    """One varied parameter and its values.

    Parameters
    ----------
    name : str
        A name of :data:`PARAMETERS`.
    values : tuple of float
        Its values, in the unit of ``PARAMETERS[name]`` (SI).
    """

    name: str
    values: tuple[float, ...]

    def __post_init__(self) -> None:
        check_name(self.name)
        given = self.values
        is_list = isinstance(given, Sequence) or getattr(given, "ndim", None) == 1
        if isinstance(given, str | bytes) or not is_list:
            raise ParameterError(self.name, given, "a list of numbers")
        numbers = [schema.real_number(v) for v in given]
        if any(number is None for number in numbers):
            raise ParameterError(self.name, given, "a list of numbers")
        values = tuple(float(number) for number in numbers if number is not None)
        if not values:
            raise ParameterError(self.name, self.values, "at least one value")
        if not all(math.isfinite(v) for v in values):
            raise ParameterError(self.name, self.values, "finite numbers")
        object.__setattr__(self, "values", values)


def _float(name: str, text: str) -> float:
    return schema.parse_number(name, text, "a number")


def _count(name: str, text: str) -> int:
    """The COUNT of START:STOP:COUNT: a whole number, at most ``HARD_POINT_LIMIT``,
    read without making anything of that size."""
    allowed = f"a whole number from 1 to {budget.HARD_POINT_LIMIT}"
    try:
        count = schema.parse_count(f"{name} count", text)
    except ParameterError:
        raise ParameterError(f"{name} count", text, allowed) from None
    if not 1 <= count <= budget.HARD_POINT_LIMIT:
        raise ParameterError(f"{name} count", text, allowed)
    return count


def _spaced(name: str, start: float, stop: float, count: int) -> tuple[float, ...]:
    """``count`` evenly spaced values from ``start`` to ``stop``, ends included."""
    if count == 1:
        return (start,)
    try:
        with np.errstate(all="raise"):
            values = np.linspace(start, stop, count)
    except FloatingPointError:
        raise ParameterError(
            name, f"{start:g}:{stop:g}:{count}", "START and STOP less than 1e308 apart"
        ) from None
    return tuple(values.tolist())


@dataclass(frozen=True)
class AxisSpec:
    """A grid axis as written, its values not made yet.

    Its name and count are known cheaply, so a sweep is sized (``budget``) before it is
    built. Either ``listed`` holds the values, or ``count`` values run from ``start`` to
    ``stop`` (ends included).

    Parameters
    ----------
    name : str
        A name of :data:`PARAMETERS`.
    count : int
        Number of values.
    start : float
        First value, in the unit of ``PARAMETERS[name]`` (SI).
    stop : float
        Last value, in the same unit.
    listed : tuple of float or None
        The values, when they are listed rather than spaced.
    """

    name: str
    count: int
    start: float = 0.0
    stop: float = 0.0
    listed: tuple[float, ...] | None = None

    def axis(self) -> Axis:
        """Make the axis with its values.

        Returns
        -------
        Axis
            The axis.
        """
        if self.listed is not None:
            return Axis(self.name, self.listed)
        return Axis(self.name, _spaced(self.name, self.start, self.stop, self.count))


def parse_axis_spec(text: str) -> AxisSpec:
    """Parse ``name=start:stop:count`` or ``name=v1,v2,...`` without spacing the values.

    Parameters
    ----------
    text : str
        The axis as written (``--grid``); its values are counted, not made.

    Returns
    -------
    AxisSpec
        The axis, its values not made yet.
    """
    name, sep, rest = text.partition("=")
    name = name.strip().replace("-", "_")
    if not sep or not rest.strip():
        raise ParameterError(
            "vary", text, "NAME=START:STOP:COUNT or NAME=V1,V2,...", "e.g. initial_spin=-8:8:64"
        )
    check_name(name)
    if ":" in rest:
        parts = rest.split(":")
        if len(parts) != 3:
            raise ParameterError(name, rest, "START:STOP:COUNT, e.g. 0.02:0.5:64")
        start, stop = _float(name, parts[0]), _float(name, parts[1])
        if not (math.isfinite(start) and math.isfinite(stop)):
            raise ParameterError(name, rest, "a finite START and STOP")
        return AxisSpec(name, _count(name, parts[2].strip()), start, stop)
    values = tuple(_float(name, part) for part in rest.split(","))
    return AxisSpec(name, len(values), listed=values)


def parse_axis(text: str) -> Axis:
    """Parse ``name=start:stop:count`` (evenly spaced, ends included) or ``name=v1,v2,...``.

    Parameters
    ----------
    text : str
        The axis as written (``--grid``), e.g. ``friction_coefficient=0.1:0.5:5``.

    Returns
    -------
    Axis
        The axis with its values.
    """
    return parse_axis_spec(text).axis()


def parse_setting(text: str) -> tuple[str, float | str]:
    """Parse a fixed setting ``name=value``: a number, or an option of ``CHOICES``.

    The options are ``friction_load=static|dynamic``, ``friction_law=pade|exact``,
    ``contact_pressure=hertz|uniform`` and ``contact=sliding|hybrid``.

    Parameters
    ----------
    text : str
        The setting as written (``--set``).

    Returns
    -------
    name : str
        The setting's name.
    value : float or str
        Its number (SI) or option.
    """
    name, sep, value = text.partition("=")
    name = name.strip().replace("-", "_")
    if not sep or not value.strip():
        raise ParameterError("set", text, "NAME=VALUE", "e.g. contact_radius=0.002")
    if name in CHOICES:
        return name, value.strip()
    check_name(name)
    return name, _float(name, value)


def _fixed_number(name: str, value: object) -> float:
    """A fixed number of a sweep (``--set`` reads text with :func:`parse_setting`): a real
    number, not text or a boolean (``schema.real_number``)."""
    number = schema.real_number(value)
    if number is None:
        raise ParameterError(name, value, "a number")
    return number


def _column(name: str, values: object) -> np.ndarray:
    """A varied parameter's values at every point, shape (n_points,): real numbers."""
    array = np.asarray(values)
    if array.ndim != 1 or array.dtype.kind not in ("i", "u", "f"):
        raise ParameterError(name, values, "a 1-D array of numbers, one per point")
    return array.astype(float)


def _refuse_without_effect(
    model_name: str, choices: Mapping[str, str], values: Mapping[str, object]
) -> None:
    """A number that no point of the sweep uses is refused, not swept in vain: a fixed
    contact_radius where the contact's size is Hertz's (``elastic_modulus`` given, as the
    elliptic contact needs); an initial slip with the rolling model (its contact cannot
    slip)."""
    if model_name == "rolling":
        for name in ("slip_velocity1", "slip_velocity2"):
            if name in values:
                given = values[name]
                if isinstance(given, np.ndarray):  # varied: say what, not every value
                    given = f"{given.size} values from {given.min():g} to {given.max():g} m/s"
                raise ParameterError(
                    name, given, "no value with the rolling model: its contact cannot slip"
                )
        return
    if "contact_radius" not in values:
        return
    if "elastic_modulus" in values or choices.get("contact_shape") == "ellipse":
        why = (
            "the Hertz ellipse's semi-axes follow from elastic_modulus, poisson_ratio, the "
            "normal force and the curvatures"
            if choices.get("contact_shape") == "ellipse"
            else "the Hertz radius follows from elastic_modulus, poisson_ratio, the normal "
            "force and the curvature"
        )
        given = values["contact_radius"]
        if isinstance(given, np.ndarray):  # varied: say what, not every value
            given = f"{given.size} values from {given.min():g} to {given.max():g} m"
        raise ParameterError(
            "contact_radius",
            given,
            "no value with elastic_modulus or contact_shape ellipse",
            f"it has no effect at any point: {why}; vary elastic_modulus instead",
        )


def _rotated_inertia(inertia: np.ndarray, angle: float) -> np.ndarray:
    """``inertia`` with its horizontal principal axes turned to ``angle`` from axis 1 [rad]."""
    block = inertia[:2, :2]
    moments, vectors = np.linalg.eigh(block)
    near_axis_1 = int(np.argmax(np.abs(vectors[0])))
    a1, a2 = moments[near_axis_1], moments[1 - near_axis_1]
    c, s = math.cos(angle), math.sin(angle)
    rotation = np.array([[c, -s], [s, c]])
    tensor = inertia.copy()
    tensor[:2, :2] = rotation @ np.diag([a1, a2]) @ rotation.T
    return tensor


def build_body(base: Body, values: Mapping[str, float]) -> Body:
    """``base`` with the body parameters in ``values`` replaced, validated."""
    if not values:
        return base
    inertia = base.inertia_array.copy()
    for name, value in values.items():
        if name.startswith("inertia_"):
            i, j = int(name[-2]) - 1, int(name[-1]) - 1
            inertia[i, j] = inertia[j, i] = value
    if "misalignment_angle" in values:
        angle = values["misalignment_angle"]
        if not -math.pi / 4 < angle < math.pi / 4:
            raise ParameterError("misalignment_angle", angle, "a number in (-0.785, 0.785) rad")
        inertia = _rotated_inertia(inertia, angle)
    shape = base.shape.replaced({k: v for k, v in values.items() if k in _SHAPE_NAMES})
    return replace(
        base,
        mass=values.get("mass", base.mass),
        gravity=values.get("gravity", base.gravity),
        inertia=tuple(tuple(float(v) for v in row) for row in inertia),  # type: ignore[arg-type]
        shape=shape,
    )


def build_model(model_name: str, choices: Mapping[str, str], values: Mapping[str, float]) -> Model:
    """The model with the options ``choices`` (``CHOICES``) and numbers ``values``, validated
    (a setting the model does not have is refused: ``models.model_from_name``)."""
    return model_from_name(model_name, **choices, **values)


def build_state(values: Mapping[str, float]) -> InitialState:
    """The initial state from omega1..3, euler_alpha, euler_beta, initial_spin and
    slip_velocity1..2 (defaults: ``InitialState()``, Kane & Levinson's ω = (0, 0, -5) rad/s,
    α = β = 0.5°, no slip)."""
    default = InitialState()
    omega = [values.get(f"omega{k + 1}", default.omega[k]) for k in range(3)]
    angles = (
        values.get("euler_alpha", default.euler_angles[0]),
        values.get("euler_beta", default.euler_angles[1]),
    )
    if "initial_spin" in values:
        spin = schema.check("omega", values["initial_spin"])
        n = InitialState(omega=(0.0, 0.0, 0.0), euler_angles=angles).vertical
        omega[2] = (spin - omega[0] * n[0] - omega[1] * n[1]) / n[2]
    slip = (
        values.get("slip_velocity1", default.slip_velocity[0]),
        values.get("slip_velocity2", default.slip_velocity[1]),
    )
    return InitialState(
        omega=(omega[0], omega[1], omega[2]), euler_angles=angles, slip_velocity=slip
    )


class PointBuilder:
    """Turns each point of a sweep into kernel arrays; validates every point up front.

    Parameters
    ----------
    base_body : the body before any parameter is applied
    model_name : "rolling" or "sliding"
    fixed : parameter name -> value for the whole sweep (the ``CHOICES`` take strings)
    columns : name -> values of every point, shape (n_points,) each
    progress : called with (objects built, objects to build) while validating
    atol : the runs' absolute tolerance: the hybrid contact's default capture speed is
        100 atol, and its regularisation speed must stay below a tenth of it
    """

    def __init__(
        self,
        base_body: Body,
        model_name: str,
        fixed: Mapping[str, float | str],
        columns: Mapping[str, np.ndarray],
        progress: Callable[[int, int], None] | None = None,
        atol: float = 1e-12,
    ) -> None:
        self.atol = atol
        settings = dict(fixed)
        choices = {name: str(settings.pop(name)) for name in CHOICES if name in settings}
        for name, value in choices.items():
            require_choice(name, value, CHOICES[name])
        for name in settings:  # an old or unknown name first, before its value
            check_name(name)
        numbers = {name: _fixed_number(name, value) for name, value in settings.items()}
        for name in columns:
            check_name(name)
            if name in numbers:
                raise ParameterError(
                    "parameter", name, "either fixed or varied", "it is given in both"
                )
        names = set(numbers) | set(columns)
        for first, second in _CONFLICTS:
            if first in names and second in names:
                raise ParameterError(
                    "parameter", second, f"not together with {first}", f"{first} sets it"
                )
        self.model_name = model_name
        self.choices = choices
        self.base_body = base_body
        self.fixed = numbers
        self.columns = {name: _column(name, values) for name, values in columns.items()}
        _refuse_without_effect(model_name, choices, {**numbers, **self.columns})
        self.n_points = next(iter(self.columns.values())).size if self.columns else 1
        self._groups = {
            group: [name for name in self.columns if PARAMETERS[name].group == group]
            for group in (BODY, MODEL, STATE)
        }
        self._bodies: dict[tuple[float, ...], Body] = {}
        self._models: dict[tuple[float, ...], Model] = {}
        self._capture_speeds: dict[tuple[float, ...], float] = {}
        self._params: dict[tuple[tuple[float, ...], tuple[float, ...]], np.record] = {}
        self._states: dict[tuple[float, ...], np.ndarray] = {}
        # every point checked here; the first point's body and model describe the sweep
        self.validate(progress)
        body_key, model_key, _ = self._keys(0)
        self.model = self._model(model_key)
        self.body = self._body(body_key)

    def _values(self, group: str, key: tuple[float, ...] | None) -> dict[str, float]:
        values = {n: v for n, v in self.fixed.items() if PARAMETERS[n].group == group}
        if key is not None:
            values.update(zip(self._groups[group], key, strict=True))
        return values

    def _body(self, key: tuple[float, ...]) -> Body:
        if key not in self._bodies:
            self._bodies[key] = build_body(self.base_body, self._values(BODY, key))
        return self._bodies[key]

    def _model(self, key: tuple[float, ...]) -> Model:
        if key not in self._models:
            model = build_model(self.model_name, self.choices, self._values(MODEL, key))
            # the hybrid contact's v_c at this atol (0: no capture), checked against δ
            capture = 0.0
            if isinstance(model, HybridModel):
                capture = model.resolved_capture_speed(self.atol)
            self._capture_speeds[key] = capture
            self._models[key] = model
        return self._models[key]

    def _state(self, key: tuple[float, ...]) -> np.ndarray:
        if key not in self._states:
            self._states[key] = initial_vector(build_state(self._values(STATE, key)))
        return self._states[key]

    def _keys(self, index: int) -> tuple[tuple[float, ...], ...]:
        return tuple(
            tuple(float(self.columns[n][index]) for n in self._groups[group])
            for group in (BODY, MODEL, STATE)
        )

    def point(self, index: int) -> dict[str, float]:
        """The varied values of point ``index``."""
        return {name: float(values[index]) for name, values in self.columns.items()}

    def _distinct(self, names: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
        """The distinct value rows of the columns ``names``, shape (m, k), and the first
        point of each, shape (m,), in the order the points first show them.

        Vectorised (a lexicographic sort), so a grid of a million points with a few
        thousand distinct values per group costs a fraction of a second.
        """
        if not names:
            return np.empty((1, 0)), np.zeros(1, dtype=np.intp)
        table = np.column_stack([self.columns[name] for name in names])
        order = np.lexsort(table.T[::-1])
        ordered = table[order]
        starts = np.ones(len(order), dtype=bool)
        starts[1:] = np.any(ordered[1:] != ordered[:-1], axis=1)
        first = np.sort(np.minimum.reduceat(order, np.flatnonzero(starts)))
        return table[first], first

    def _stages(self) -> list[tuple[list[str], Callable[[tuple[float, ...]], object]]]:
        """What is built to validate the points: the columns each stage depends on and
        the function building one distinct row of them."""
        return [
            (self._groups[BODY], self._body),
            (self._groups[MODEL], self._model),
            (self._groups[STATE], self._state),
        ]

    def _numbered(self, names: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
        """Each point's number among the distinct rows of the columns ``names``, shape
        (n_points,), and the first point of each number (vectorised)."""
        if not names:
            return np.zeros(self.n_points, dtype=np.intp), np.zeros(1, dtype=np.intp)
        table = np.column_stack([self.columns[name] for name in names])
        _, first, number = np.unique(table, axis=0, return_index=True, return_inverse=True)
        return number.reshape(-1), first

    def _contact_numbers(self, models: np.ndarray, first: np.ndarray) -> np.ndarray:
        """Each point's number among the distinct contacts of its model: what
        :func:`plausibility.require_runnable` reads of a model (``contact_settings``).
        A model that cannot be built has a number of its own (its error is raised when
        the pair is checked)."""
        numbers: dict[object, int] = {}
        of_model = np.empty(len(first), dtype=np.intp)
        for number, index in enumerate(first):
            key = self._keys(int(index))[1]
            try:
                settings: object = contact_settings(self._model(key))
            except CeltstoneError:
                settings = ("cannot be built", number)
            of_model[number] = numbers.setdefault(settings, len(numbers))
        return of_model[models]

    def _runnable_pairs(self) -> tuple[np.ndarray, np.ndarray]:
        """One point of each distinct body with each distinct contact (a grid of bodies
        by friction coefficients checks each body once): the rows (body columns, then
        model columns) and the first point of each, in the order the points show them."""
        bodies, _ = self._numbered(self._groups[BODY])
        models, first_models = self._numbered(self._groups[MODEL])
        contacts = self._contact_numbers(models, first_models)
        _, first = np.unique(np.column_stack([bodies, contacts]), axis=0, return_index=True)
        first = np.sort(first)
        names = self._groups[BODY] + self._groups[MODEL]
        if not names:
            return np.empty((len(first), 0)), first
        table = np.column_stack([self.columns[name][first] for name in names])
        return table, first

    def _check_runnable(self, row: tuple[float, ...]) -> None:
        """A body and a model checked together (``plausibility.require_runnable``, the
        check of ``models.kernel_parameters``)."""
        n_body = len(self._groups[BODY])
        body, model = self._body(row[:n_body]), self._model(row[n_body:])
        plausibility.require_runnable(body, contact_settings(model))

    def validate(self, progress: Callable[[int, int], None] | None = None) -> None:
        """Build every distinct body, model and state once, and check each distinct body
        with each distinct contact of the models; raise the error of the first point that
        fails, as a point-by-point check would.

        ``progress`` is called with (objects built, objects to build) now and then; the
        number to build grows once, when the pairs are known (after the models).
        """
        stages = [(self._distinct(names), build) for names, build in self._stages()]
        total = sum(len(first) for (_, first), _ in stages)
        built = 0
        failures: list[tuple[int, int, CeltstoneError]] = []

        def run(rank: int, rows: np.ndarray, first: np.ndarray, build: Callable) -> None:
            nonlocal built
            for row, index in zip(rows, first, strict=True):
                try:
                    build(tuple(float(v) for v in row))
                except CeltstoneError as error:
                    failures.append((int(index), rank, error))  # the stage's first failure
                    return
                built += 1
                if progress is not None and built % VALIDATION_PROGRESS_EVERY == 0:
                    progress(built, total)

        for rank, ((rows, first), build) in enumerate(stages):
            run(rank, rows, first, build)
        pairs, first = self._runnable_pairs()
        total += len(first)
        run(len(stages), pairs, first, self._check_runnable)
        if progress is not None:
            progress(total, total)
        if failures:
            index, _, first_error = min(failures, key=lambda failure: failure[:2])
            raise self._at_point(index, first_error)

    def _at_point(self, index: int, error: CeltstoneError) -> CeltstoneError:
        """``error`` with the point it came from added to its hint."""
        if not isinstance(error, ParameterError):
            return error
        where = ", ".join(f"{k}={v:g}" for k, v in self.point(index).items())
        hint = f"at sweep point {index} ({where})"
        if error.hint:
            hint = f"{error.hint}; {hint}"
        return ParameterError(error.name, error.value, error.allowed, hint)

    def _parameters(self, body_key: tuple[float, ...], model_key: tuple[float, ...]) -> np.record:
        """Kernel parameter record of a body and a model, which are checked together here
        (``models.kernel_parameters``: a run of them must be able to mean something)."""
        pair = (body_key, model_key)
        if pair not in self._params:
            self._params[pair] = kernel_parameters(self._model(model_key), self._body(body_key))
        return self._params[pair]

    def capture_speeds(self, indices: Sequence[int] | np.ndarray) -> np.ndarray:
        """Capture speed v_c [m/s] of the hybrid contact at each of ``indices``, shape
        (k,); 0 where the model has no stick–slip contact."""
        return np.array(
            [self._capture_speeds[self._keys(int(index))[1]] for index in indices], dtype=float
        )

    def rocking_periods(self, indices: Sequence[int] | np.ndarray) -> np.ndarray:
        """Each point's body's rocking period [s] (``Body.rocking_period``), the window of
        the rocking average its reversals are read from, shape (k,)."""
        return np.array(
            [self._body(self._keys(int(index))[0]).rocking_period for index in indices],
            dtype=float,
        )

    def arrays(self, indices: Sequence[int] | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Kernel parameter records, shape (k,), and initial states (k, N_STATE) of
        ``indices``."""
        params = []
        states = []
        for index in indices:
            body_key, model_key, state_key = self._keys(int(index))
            params.append(self._parameters(body_key, model_key))
            states.append(self._state(state_key))
        return np.array(params), np.array(states)
