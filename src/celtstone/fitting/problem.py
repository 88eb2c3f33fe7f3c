"""The fitting problem: which numbers are free, where each goes (model, body or initial
state: the names of ``celtstone sweep``), their bounds, and the weighted residuals.

The residual of series s at time t_i is (model − data) / σ_s: each series is weighted by
its own noise scale σ_s, given or estimated from the data (``fitting.noise.noise_scale``).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from celtstone.bodies import Body
from celtstone.errors import CeltstoneError, CeltstoneWarning, ParameterError, did_you_mean
from celtstone.fitting.noise import noise_scale
from celtstone.fitting.nuisance import (
    NUISANCES,
    RELEASE_OFFSET,
    bias_name,
    biased_series,
    gain,
    is_nuisance,
    scaled_series,
    sensor_reading,
)
from celtstone.fitting.record import Record
from celtstone.fitting.series import SERIES
from celtstone.simulation import schema
from celtstone.simulation.integrate import simulate
from celtstone.simulation.models import InitialState, Model
from celtstone.simulation.trajectory import Trajectory
from celtstone.sweep.spec import (
    BODY,
    MODEL,
    PARAMETERS,
    STATE,
    build_body,
    build_model,
    build_state,
)

__all__ = [
    "DEFAULT_BOUNDS",
    "FAILED_RESIDUAL",
    "FIT_ATOL",
    "FIT_RTOL",
    "SLIP_NAMES",
    "FreeParameter",
    "Problem",
    "Settings",
    "current_values",
    "make_problem",
    "parse_bounds",
]

# the runs' tolerances: rtol 1e-8 changes the spin of a 3 s K&L sliding run by 2.5e-9
# rad/s from rtol 1e-10, at half the time (docs/decisions.md); every fit checks it
# again at its optimum against a run at 1/100 of them (``assess.INTEGRATION_ERROR_LIMIT``)
FIT_RTOL = 1e-8
FIT_ATOL = 1e-10
# weighted residual [1] of a sample a run did not reach (it stopped early or raised): large
# and finite, so that the optimiser steps back instead of stopping
FAILED_RESIDUAL = 1e3
# default [LO, HI] of the free numbers that have one (SI units of schema.PARAMETERS)
DEFAULT_BOUNDS: dict[str, tuple[float, float]] = {
    "friction_coefficient": (0.01, 2.0),
    "contact_radius": (1e-5, 1e-2),  # m
    "rolling_resistance": (0.0, 1e-3),  # m
    "damping": (0.0, 1e-3),  # N m s
    "euler_alpha": (-10.0, 10.0),  # deg
    "euler_beta": (-10.0, 10.0),  # deg
    # m/s; a stone's contact slides at centimetres per second
    "slip_velocity1": (-1.0, 1.0),
    "slip_velocity2": (-1.0, 1.0),
}
# the initial sliding velocity of the contact (body axes 1, 2): free by default where the
# run starts mid-motion (the first sample's state read from the record or fitted), zero at
# a release or a state the user gives
SLIP_NAMES = ("slip_velocity1", "slip_velocity2")
# the initial rates [rad/s] are free within this distance of their start by default
DEFAULT_RATE_SPAN = 10.0
_RATES = ("omega1", "omega2", "omega3", "initial_spin")
# the schema entry that checks a bound of each free name (model settings: their own name)
_SCHEMA_NAMES = {**dict.fromkeys(_RATES, "omega"), "euler_alpha": "euler_angles"}
_SCHEMA_NAMES["euler_beta"] = "euler_angles"
_SCHEMA_NAMES.update(dict.fromkeys(SLIP_NAMES, "slip_velocity"))
# a given σ_s, relative to its series' range: smaller would overflow the squares
SIGMA_RANGE = (1e-9, 1e3)


@dataclass(frozen=True)
class FreeParameter:
    """A free number: its name (``sweep`` parameter names), unit, bounds and start.

    ``scale`` [unit] is its typical size, for the optimiser's ``x_scale`` and the
    finite-difference steps: |start|, or a tenth of the bounds' width at a start of 0.
    """

    name: str
    unit: str
    lower: float
    upper: float
    start: float

    @property
    def scale(self) -> float:
        return abs(self.start) if self.start != 0.0 else (self.upper - self.lower) / 10.0

    @property
    def is_log_spaced(self) -> bool:
        """Whether starts are drawn log-uniformly: positive bounds a decade or more apart."""
        return self.lower > 0.0 and self.upper >= 10.0 * self.lower


def parse_bounds(text: str) -> tuple[str, tuple[float, float]]:
    """``NAME=LO:HI`` -> (name, (lo, hi)), numbers checked finite and LO < HI."""
    name, sep, span = text.partition("=")
    lo_text, colon, hi_text = span.partition(":")
    name = name.strip()
    try:
        if not sep or not colon:
            raise ValueError(text)
        lower, upper = float(lo_text), float(hi_text)
    except ValueError:
        raise ParameterError(
            "bounds", text, "NAME=LO:HI", "e.g. contact_radius=1e-4:5e-3"
        ) from None
    if not (math.isfinite(lower) and math.isfinite(upper)) or lower >= upper:
        raise ParameterError(f"bounds of {name}", span, "LO:HI with finite LO < HI")
    return name, (lower, upper)


def _check_free_name(name: str, option: str = "free") -> None:
    if name not in PARAMETERS and not is_nuisance(name):
        raise ParameterError(
            option,
            name,
            "a model setting, initial-state, body or sensor number (see `celtstone fit --help`)",
            did_you_mean(name, [*PARAMETERS, *NUISANCES], cutoff=0.5),
        )


def _bounds(name: str, start: float, given: tuple[float, float] | None) -> tuple[float, float]:
    """The bounds of free ``name``: ``given``, else its default; each bound an allowed value."""
    if given is not None:
        lower, upper = given
    elif is_nuisance(name):
        lower, upper = NUISANCES[name].lower, NUISANCES[name].upper
    elif name in DEFAULT_BOUNDS:
        lower, upper = DEFAULT_BOUNDS[name]
    elif name in _RATES:
        lower, upper = start - DEFAULT_RATE_SPAN, start + DEFAULT_RATE_SPAN
    else:
        raise ParameterError(
            f"bounds of {name}", None, "NAME=LO:HI", f"{name} has no default range: add --bounds"
        )
    schema_name = _SCHEMA_NAMES.get(name, name)
    if schema_name in schema.PARAMETERS:
        for bound in (lower, upper):
            try:
                schema.check(schema_name, bound)
            except ParameterError as error:
                raise ParameterError(
                    f"bounds of {name}", f"{lower:g}:{upper:g}", error.allowed
                ) from None
    return lower, upper


def _starts_mid_motion(read: Mapping[str, float], free: Sequence[str]) -> bool:
    """Whether the run starts at a state of the motion rather than at a release: its rates
    read from the record's first sample or fitted (then the contact may already slide)."""
    return bool(read) or any(name in free for name in _RATES)


def _initial_values(record: Record, given: Mapping[str, float]) -> dict[str, float]:
    """Initial-state numbers read from the record where not ``given``: ω(0) from measured
    omega1..3, else the initial spin from a measured spin (first samples)."""
    values: dict[str, float] = {}
    for k in range(3):
        name = f"omega{k + 1}"
        if name in record.series and name not in given:
            values[name] = float(record.series[name][0])
    if "spin" in record.series and not {"omega3", "initial_spin"} & {*given, *values}:
        values["initial_spin"] = float(record.series["spin"][0])
    return values


@dataclass(frozen=True)
class Problem:
    """A fit: the record, what is fixed, what is free, and how runs are made.

    Parameters
    ----------
    record : the measured motion
    body : the body before any free or fixed body number is applied
    model_name : "rolling" or "sliding"
    choices : fixed named options (``friction_load``, ``contact``, ...)
    fixed : fixed numbers by name (``sweep`` names, SI units)
    free : the free numbers, in the order of the parameter vector
    sigma : series name -> its noise scale σ_s [unit of the series]
    rtol, atol : the runs' tolerances
    method : integrator name, or None for the model's default
    """

    record: Record
    body: Body
    model_name: str
    choices: Mapping[str, str]
    fixed: Mapping[str, float]
    free: tuple[FreeParameter, ...]
    sigma: Mapping[str, float]
    rtol: float
    atol: float
    method: str | None = None
    sigma_source: Mapping[str, str] = field(default_factory=lambda: MappingProxyType({}))
    fixed_source: Mapping[str, str] = field(default_factory=lambda: MappingProxyType({}))

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.free)

    @property
    def start(self) -> np.ndarray:
        return np.array([p.start for p in self.free])

    @property
    def lower(self) -> np.ndarray:
        return np.array([p.lower for p in self.free])

    @property
    def upper(self) -> np.ndarray:
        return np.array([p.upper for p in self.free])

    @property
    def scale(self) -> np.ndarray:
        return np.array([p.scale for p in self.free])

    @property
    def n_residuals(self) -> int:
        return self.record.n_points

    @property
    def degrees_of_freedom(self) -> int:
        """Residuals less free numbers less one offset per offset-free series (yaw)."""
        offsets = sum(SERIES[name].is_angle_offset_free for name in self.record.series)
        return self.n_residuals - len(self.free) - offsets

    @property
    def physical_columns(self) -> list[int]:
        """Columns of the physical numbers: not the sensor's or the record's
        (``fitting.nuisance``), nor the initial slip (it decays within milliseconds)."""
        return [
            j
            for j, name in enumerate(self.names)
            if not is_nuisance(name) and name not in SLIP_NAMES
        ]

    @property
    def is_released(self) -> bool:
        """Whether the run starts at a release ``release_offset`` before the first sample."""
        return RELEASE_OFFSET in self.names or RELEASE_OFFSET in self.fixed

    @property
    def series_rows(self) -> dict[str, slice]:
        """Series name -> its rows in the residual vector (series in the record's order)."""
        rows, start = {}, 0
        for name, measured in self.record.series.items():
            rows[name] = slice(start, start + measured.size)
            start += measured.size
        return rows

    def _acting_columns(self, series_of: Callable[[str], str | None]) -> dict[int, slice]:
        """Column of each free number that ``series_of`` maps to a series of the record
        -> that series' rows."""
        rows = self.series_rows
        return {
            j: rows[series]
            for j, name in enumerate(self.names)
            if (series := series_of(name)) is not None and series in rows
        }

    @property
    def bias_columns(self) -> dict[int, slice]:
        """Column of each free bias -> the rows of the series it shifts: the residuals are
        linear in a bias, so its Jacobian column is 1/σ_s there and needs no run."""
        return self._acting_columns(biased_series)

    @property
    def scale_columns(self) -> dict[int, slice]:
        """Column of each free scale factor -> the rows of the series it multiplies: the
        residuals are linear in it too, with the model's series as its Jacobian column."""
        return self._acting_columns(scaled_series)

    @property
    def linear_columns(self) -> dict[int, slice]:
        """The columns whose Jacobian needs no run (biases and scales) -> their rows."""
        return {**self.bias_columns, **self.scale_columns}

    def bias_jacobian(self, column: int) -> np.ndarray:
        """∂r/∂bias of free ``column`` (a bias) [s/rad], shape (m,)."""
        rows = self.bias_columns[column]
        series = biased_series(self.names[column])
        assert series is not None
        derivative = np.zeros(self.n_residuals)
        derivative[rows] = 1.0 / self.sigma[series]
        return derivative

    def linear_jacobian(self, column: int, x: np.ndarray, residuals: np.ndarray) -> np.ndarray:
        """∂r/∂x of a bias's or a scale's ``column`` at ``x`` [1/its unit], shape (m,),
        exact and without a run: ``residuals`` are those at ``x``.

        Notes
        -----
        r = ((1 + k) ω + b − d) / σ on the series' rows, so ∂r/∂b = 1/σ and
        ∂r/∂k = ω / σ = (r σ + d − b) / ((1 + k) σ): the model's ω from the residuals.
        """
        if column in self.bias_columns:
            return self.bias_jacobian(column)
        rows = self.scale_columns[column]
        series = scaled_series(self.names[column])
        assert series is not None
        values = self.values(x)
        sigma = self.sigma[series]
        measured = self.record.series[series]
        reading = residuals[rows] * sigma + measured - values.get(bias_name(series), 0.0)
        derivative = np.zeros(self.n_residuals)
        derivative[rows] = reading / (gain(series, values) * sigma)
        return derivative

    def values(self, x: np.ndarray) -> dict[str, float]:
        """Every number of a run (sweep names) and of the sensor: the fixed ones and ``x``'s."""
        return {**self.fixed, **dict(zip(self.names, (float(v) for v in x), strict=True))}

    def configuration(self, x: np.ndarray) -> tuple[Model, Body, InitialState]:
        """The validated model, body and initial state of parameter vector ``x``."""
        values = self.values(x)
        groups: dict[str, dict[str, float]] = {BODY: {}, MODEL: {}, STATE: {}}
        for name, value in values.items():
            if not is_nuisance(name):
                groups[PARAMETERS[name].group][name] = value
        model = build_model(self.model_name, self.choices, groups[MODEL])
        return model, build_body(self.body, groups[BODY]), build_state(groups[STATE])

    def sample_times(self, x: np.ndarray) -> np.ndarray:
        """The record's times as times of the run of ``x`` [s from its start]: shifted by
        the release ``release_offset`` before the first sample when there is one."""
        return self.record.times + self.values(x).get(RELEASE_OFFSET, 0.0)

    def run(self, x: np.ndarray, sample_times: np.ndarray | None = None) -> Trajectory:
        """The run of ``x`` sampled at the record's times (may stop early; may raise); from
        the release ``release_offset`` before the first sample when there is one.
        ``sample_times`` [s from the run's start]: other times instead."""
        model, body, state = self.configuration(x)
        times = self.sample_times(x) if sample_times is None else sample_times
        return simulate(
            model,
            body,
            state,
            float(times[-1]),
            sample_times=times,
            method=self.method,
            rtol=self.rtol,
            atol=self.atol,
            progress=_keep_signals_live,
        )

    def run_many(
        self,
        xs: Sequence[np.ndarray],
        device: str,
        sample_times: np.ndarray | None = None,
        workers: int | None = None,
    ) -> list[Trajectory | CeltstoneError]:
        """:meth:`run` of each of ``xs`` as one batch (``simulate_many`` on ``device``,
        on ``workers`` threads on the CPU): each run at its own times (``sample_times``
        [s from its start] for all, or the record's), a run that cannot be made or raises
        its error in its place.

        A batch integrates every run to one end time, so runs whose last sample differs
        (another ``release_offset``) go as one batch per end time: a common, later end
        would change each shorter run's last step, and its samples in the last bits.
        Without a free release offset that is one batch.
        """
        from celtstone.simulation.integrate import simulate_many

        results: list[Trajectory | CeltstoneError | None] = [None] * len(xs)
        by_end: dict[float, list[tuple[int, tuple[Model, Body, InitialState], np.ndarray]]] = {}
        for index, x in enumerate(xs):
            try:
                configuration = self.configuration(x)
            except CeltstoneError as error:  # a number the model refuses
                results[index] = error
                continue
            times = self.sample_times(x) if sample_times is None else sample_times
            by_end.setdefault(float(times[-1]), []).append((index, configuration, times))
        for t_end, members in by_end.items():
            done = simulate_many(
                [configuration for _, configuration, _ in members],
                t_end,
                device=device,
                sample_times=np.array([times for _, _, times in members]),
                method=self.method,
                rtol=self.rtol,
                atol=self.atol,
                workers=workers if device == "cpu" else None,  # threads: the CPU's only
                errors="keep",
            )
            for (index, _, _), result in zip(members, done, strict=True):
                results[index] = result
        made = [result for result in results if result is not None]
        assert len(made) == len(xs)  # every x is in one batch or refused
        return made

    def residuals(self, trajectory: Trajectory | None, x: np.ndarray | None = None) -> np.ndarray:
        """Weighted residuals (sensor reading − data) / σ_s of every series, concatenated,
        shape (m,): the reading (1 + scale) model + bias (``nuisance.sensor_reading``) with
        the biases and scales of ``x`` (or the fixed ones; none without either).

        Samples a run did not reach (and all, for ``None``: a run that raised) get
        ``FAILED_RESIDUAL``; an offset-free series (yaw) has its mean removed.
        """
        values = self.values(x) if x is not None else dict(self.fixed)
        parts = []
        for name, measured in self.record.series.items():
            residual = np.full(measured.size, FAILED_RESIDUAL)
            if trajectory is not None:
                modelled = sensor_reading(name, SERIES[name].model(trajectory.samples), values)
                reached = min(modelled.size, measured.size)
                residual[:reached] = (modelled[:reached] - measured[:reached]) / self.sigma[name]
                if SERIES[name].is_angle_offset_free and reached == measured.size:
                    residual -= residual.mean()
            parts.append(residual)
        return np.concatenate(parts)


@dataclass(frozen=True)
class Settings:
    """What a fit is told beside the record, the body, the model and the free names: the
    keyword arguments of :func:`celtstone.fitting.fit` of the same names (documented
    there), each mapping empty where not given."""

    bounds: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    start: Mapping[str, float] = field(default_factory=dict)
    fixed: Mapping[str, float | str] = field(default_factory=dict)
    sigma: Mapping[str, float] = field(default_factory=dict)
    sensor_bias: bool = True
    initial_slip: bool = True
    rtol: float = FIT_RTOL
    atol: float = FIT_ATOL
    method: str | None = None


def _check_sensor_names(record: Record, names: Sequence[str], numbers: Sequence[str]) -> None:
    """Each bias and scale among the free ``names`` and the held ``numbers`` is of a rate
    series of the record, or ParameterError naming it and those it may be."""
    for name in [*names, *numbers]:
        series = NUISANCES[name].series if is_nuisance(name) else None
        if series is not None and series not in record.series:
            rates = [s for s in record.series if SERIES[s].is_gyroscope_rate]
            raise ParameterError(
                "free" if name in names else "set",
                name,
                "a bias or scale of a rate series of the record: "
                + (
                    ", ".join(n.name for n in NUISANCES.values() if n.series in rates)
                    or "none (no rate series)"
                ),
            )


def make_problem(
    record: Record, body: Body, model_name: str, free: Sequence[str], settings: Settings
) -> Problem:
    """A checked :class:`Problem` (see :func:`celtstone.fitting.fit` for the arguments)."""
    bounds, start, fixed, sigma = (
        dict(settings.bounds),
        dict(settings.start),
        dict(settings.fixed),
        dict(settings.sigma),
    )
    names = list(dict.fromkeys(free))
    for name in names:
        _check_free_name(name)
    choices = {k: str(v) for k, v in fixed.items() if isinstance(v, str)}
    numbers = {k: float(v) for k, v in fixed.items() if not isinstance(v, str)}
    for name in numbers:
        _check_free_name(name, "set")
        if name in names:
            raise ParameterError("set", name, "a parameter that is not free", "it is in --free")
    if model_name == "rolling":
        for name in [n for n in SLIP_NAMES if n in names or numbers.get(n, 0.0) != 0.0]:
            raise ParameterError(
                "free" if name in names else "set",
                name,
                "a number of the rolling model: its contact cannot slip",
                "fit the model 'sliding' to a record that starts sliding",
            )
    _check_sensor_names(record, names, list(numbers))
    if settings.sensor_bias:  # every rate series' bias is free unless held or already free
        names += [
            bias_name(s)
            for s in record.series
            if SERIES[s].is_gyroscope_rate and bias_name(s) not in {*names, *numbers}
        ]
    released = RELEASE_OFFSET in names or RELEASE_OFFSET in numbers
    # the record's first samples set the initial state unless given or released earlier;
    # they start a free one
    read = {} if released else _initial_values(record, numbers)
    if settings.initial_slip and model_name != "rolling" and _starts_mid_motion(read, names):
        names += [n for n in SLIP_NAMES if n not in {*names, *numbers}]
    if not names:
        raise ParameterError("free", "", "at least one parameter name")
    for option, given in (("bounds", bounds), ("start", start)):
        for name in given:
            if name not in names:
                raise ParameterError(option, name, "a free parameter: " + ", ".join(names))
    configured = {**read, **numbers}
    tolerances = (settings.rtol, settings.atol, settings.method)
    base = Problem(record, body, model_name, choices, configured, (), {}, *tolerances)
    model, configured_body, state = base.configuration(np.array([]))  # the fixed part, checked
    current = current_values(model, configured_body, state)
    dropped = {*names, *(("initial_spin",) if "omega3" in names else ())}  # omega3 would lose
    numbers_held = {k: v for k, v in configured.items() if k not in dropped}
    held = {k: v for k, v in numbers_held.items() if k not in fixed}  # the record's, held fixed
    parameters = []
    for name in names:
        default = NUISANCES[name].start if is_nuisance(name) else 0.0
        value = float(start.get(name, current.get(name, configured.get(name, default))))
        lower, upper = _bounds(name, value, bounds.get(name))
        if name not in start and not lower <= value <= upper:  # a default start: moved in
            value = math.sqrt(lower * upper) if lower > 0.0 else 0.5 * (lower + upper)
        if not lower <= value <= upper:
            raise ParameterError(f"start of {name}", value, f"a number in [{lower:g}, {upper:g}]")
        unit = NUISANCES[name].unit if is_nuisance(name) else PARAMETERS[name].unit
        parameters.append(FreeParameter(name, unit, lower, upper, value))
    offsets = sum(SERIES[name].is_angle_offset_free for name in record.series)
    if record.n_points - offsets <= len(parameters):
        needed = f"{len(parameters)} free parameters" + (
            f" and {offsets} yaw offset" if offsets else ""
        )
        raise ParameterError("data", f"{record.n_points} values", f"more values than the {needed}")
    scales, sources = _noise_scales(record, sigma)
    if held:
        warnings.warn(
            "the initial state "
            + ", ".join(f"{k} = {v:.6g} rad/s" for k, v in held.items())
            + " is the record's first sample, its noise included, and is held fixed: add "
            f"{', '.join(held)} to the free parameters, or set it, unless it is known",
            CeltstoneWarning,
            stacklevel=3,
        )
    fixed_source = {k: ("set" if k in fixed else "record's first sample") for k in numbers_held}
    return Problem(
        record,
        body,
        model_name,
        MappingProxyType(choices),
        MappingProxyType(numbers_held),
        tuple(parameters),
        MappingProxyType(scales),
        *tolerances,
        MappingProxyType(sources),
        MappingProxyType(fixed_source),
    )


def _noise_scales(
    record: Record, sigma: Mapping[str, float]
) -> tuple[dict[str, float], dict[str, str]]:
    """σ_s of each series, given or estimated (``noise_scale``), and where each came from."""
    for name in sigma:
        if name not in record.series:
            raise ParameterError(
                "sigma", name, "a series of the record: " + ", ".join(record.series)
            )
    scales, sources = {}, {}
    for name, values in record.series.items():
        if name in sigma:
            size = float(np.ptp(values))
            lower, upper = (factor * size for factor in SIGMA_RANGE)
            value = float(sigma[name])
            if not (math.isfinite(value) and lower <= value <= upper):
                raise ParameterError(
                    f"sigma of {name}",
                    sigma[name],
                    f"a number in [{lower:.3g}, {upper:.3g}] {SERIES[name].unit} "
                    f"({SIGMA_RANGE[0]:g} to {SIGMA_RANGE[1]:g} times the series' range)",
                )
            scales[name], sources[name] = value, "given"
        else:
            scales[name] = noise_scale(record.times, values)
            sources[name] = "estimated from the record's high-frequency part"
    return scales, sources


def current_values(model: Model, body: Body, state: InitialState) -> dict[str, float]:
    """The value each sweep name has in the configured objects (the default starts)."""
    values: dict[str, float] = {}
    for name in PARAMETERS:
        if hasattr(model, name) and isinstance(getattr(model, name), float):
            values[name] = getattr(model, name)
    values.update(zip(("omega1", "omega2", "omega3"), state.omega, strict=True))
    values.update(euler_alpha=state.euler_angles[0], euler_beta=state.euler_angles[1])
    values["initial_spin"] = float(np.dot(state.omega, state.vertical))
    values.update(zip(SLIP_NAMES, state.slip_velocity, strict=True))
    values.update(mass=body.mass, gravity=body.gravity)
    return values


def _keep_signals_live(time: float) -> None:
    """Progress callback of :meth:`Problem.run`: reports nothing; its presence runs the
    compiled loop in a daemon thread, so that Ctrl-C and SIGTERM stop a fit at once even
    while a run goes on in the main thread (``simulate``'s ``progress``)."""
