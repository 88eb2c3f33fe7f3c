"""Trajectory: the sampled run as an ``xarray.Dataset`` plus its outcome and summary.

The samples are kept as NumPy arrays (:class:`RunSamples`); the dataset is built on first
use, so that a run asked only for its summary (``celtstone run --json``) never imports
xarray. The outcome is the record declared in ``simulation.outcome``, reduced from the
sampled states by the sweep's own compiled reduction (``solvers.batch.reduce_run``).
"""

from __future__ import annotations

import html
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from celtstone.errors import (
    CeltstoneError,
    FrictionSingularityError,
    IntegrationError,
    LiftOffError,
)
from celtstone.kernels import layout
from celtstone.kernels import system as kernel_system
from celtstone.simulation.outcome import SETTINGS, is_energy_monotone, json_number, units
from celtstone.simulation.reversals import reversal_bands, reversal_times
from celtstone.simulation.schema import VARIABLES, Variable
from celtstone.solvers.codes import PhaseKind, Status
from celtstone.solvers.derived import derived_series

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["RunEnding", "RunSamples", "Trajectory", "sample_run"]

# the exception of a status label; any other stop raises IntegrationError
_ERRORS: dict[str, type[CeltstoneError]] = {
    Status.LIFT_OFF.label: LiftOffError,
    Status.SINGULAR.label: FrictionSingularityError,
}


def _columns(name: str, variable: Variable) -> tuple[bool, int | slice]:
    """Where the time series ``name`` is read from, by its ``source``: (whether from the
    derived columns, else the states; the column index or slice).

    Raises
    ------
    ValueError
        for a source that names no state block or derived column, or derived columns
        that are not consecutive (a declaration to fix, found on import).
    """
    kind, _, names = variable.source.partition(":")
    if kind == "state" and names in kernel_system.STATE_BLOCKS:
        return False, kernel_system.STATE_BLOCKS[names]
    columns = names.split(",") if names else [name]
    if kind != "derived" or not set(columns) <= set(kernel_system.DERIVED):
        raise ValueError(f"VARIABLES[{name!r}]: source {variable.source!r} names no columns")
    first, last = (kernel_system.DERIVED.index(c) for c in (columns[0], columns[-1]))
    if columns != list(kernel_system.DERIVED[first : last + 1]):
        raise ValueError(f"VARIABLES[{name!r}]: derived columns {columns} are not consecutive")
    return True, first if len(columns) == 1 else slice(first, last + 1)


# name -> (from the derived columns, columns, dimensions): a run's time series, in order
_TIME_SERIES: dict[str, tuple[bool, int | slice, tuple[str, ...]]] = {
    name: (*_columns(name, variable), ("time", variable.axis) if variable.axis else ("time",))
    for name, variable in VARIABLES.items()
    if variable.source
}


@dataclass(frozen=True)
class RunSamples:
    """A run's samples as NumPy arrays: ``variables`` maps each name of ``schema.VARIABLES``
    to its (dimensions, values), ``attrs`` holds the run's attributes."""

    variables: Mapping[str, tuple[tuple[str, ...], np.ndarray]]
    attrs: dict[str, Any]

    def values(self, name: str) -> np.ndarray:
        """The values of the variable ``name`` (its unit in ``schema.VARIABLES``)."""
        return self.variables[name][1]

    def __contains__(self, name: object) -> bool:
        return name in self.variables

    def to_dataset(self) -> xr.Dataset:
        """The samples as a dataset, each variable with its ``schema.VARIABLES`` attributes."""
        import xarray as xr

        # fastpath: the values are NumPy arrays already; without it xarray asks whether
        # each is a Dask array and imports Dask to find out (0.5 s)
        variables = {
            name: xr.Variable(dims, values, VARIABLES[name].attributes, fastpath=True)
            for name, (dims, values) in self.variables.items()
        }
        coords = {"time": variables.pop("time")}
        for name, values, long_name in (
            ("axis", np.array([1, 2, 3]), "body axis"),
            ("component", np.array(["w", "x", "y", "z"]), "quaternion"),
            ("plane_axis", np.array(["x", "y"]), "space axis"),
        ):
            coords[name] = xr.Variable((name,), values, {"long_name": long_name}, fastpath=True)
        return xr.Dataset(variables, coords=coords, attrs=self.attrs)


def sample_run(
    model_code: int,
    params: np.record,
    times: np.ndarray,
    states: np.ndarray,
    crossings: np.ndarray,
    attrs: dict[str, Any],
    phase: np.ndarray | None = None,
    **phase_table: np.ndarray,
) -> RunSamples:
    """Samples of a run from its sampled states (rows of the kernel state layout).

    A hybrid-contact run also gives ``phase`` (per sample, a ``PhaseKind`` code; stick
    rows get the stick diagnostics) and its table of phases ``phase_kind``,
    ``phase_start``, ``phase_end``, ``phase_energy_jump`` (dimension ``contact_phase``).
    """
    derived = np.empty((states.shape[0], kernel_system.N_DIAGNOSTICS))
    if states.shape[0]:
        derived_series(model_code, states, params, derived)
    if phase is not None and np.any(phase == PhaseKind.STICK):
        stick = np.flatnonzero(phase == PhaseKind.STICK)
        stick_derived = np.empty((stick.size, kernel_system.N_DIAGNOSTICS))
        derived_series(
            layout.ModelCode.STICK.value, np.ascontiguousarray(states[stick]), params, stick_derived
        )
        derived[stick] = stick_derived
    time = ("time",)
    variables = {
        name: (dims, derived[:, columns] if is_derived else states[:, columns])
        for name, (is_derived, columns, dims) in _TIME_SERIES.items()
    }
    variables["time"] = (time, times)
    variables["spin_crossings"] = (("crossing",), crossings)
    if phase is not None:
        variables["phase"] = (time, np.asarray(phase, dtype=np.int8))
    for name, values in phase_table.items():
        variables[name] = (("contact_phase",), values)
    return RunSamples(variables, attrs)


@dataclass(frozen=True)
class RunEnding:
    """What the outcome's reduction reads of a run besides its samples and stop.

    Parameters
    ----------
    model_code : kernel model code (``kernels.layout``); the sliding model's for the
        stick–slip contact
    params : the run's kernel parameter record
    initial_state : the state at t = 0, shape (N_STATE,)
    states : the sampled states (rows of the kernel state layout), shape (s, N_STATE)
    status_code : how the run ended (``solvers.Status``)
    n_crossings : spin zero crossings found (more than stored if the buffer was full)
    """

    model_code: int
    params: np.record
    initial_state: np.ndarray
    states: np.ndarray
    status_code: int
    n_crossings: int


def _phase_summary(ds: RunSamples) -> dict[str, Any]:
    """Stick and slip phases of a hybrid-contact run, and its options, for the summary."""
    kinds = ds.values("phase_kind")
    phases = [
        {
            "kind": PhaseKind(int(kind)).label,
            "t_start": float(start),
            "t_end": float(end),
            "energy_jump": float(jump),
        }
        for kind, start, end, jump in zip(
            kinds,
            ds.values("phase_start"),
            ds.values("phase_end"),
            ds.values("phase_energy_jump"),
            strict=True,
        )
    ]
    jumps = ds.values("phase_energy_jump")
    return {
        "stick_phases": int(np.sum(kinds == PhaseKind.STICK)),
        "slip_phases": int(np.sum(kinds == PhaseKind.SLIP)),
        "phases": phases,
        "max_capture_energy_jump": float(np.max(np.abs(jumps))) if jumps.size else 0.0,
        "rejected_captures": int(ds.attrs["rejected_captures"]),
        "capture_speed": float(ds.attrs["capture_speed"]),
        "regularisation_speed": float(ds.attrs["regularisation_speed"]),
        "stick_method": ds.attrs["stick_method"],
    }


@dataclass(frozen=True)
class Trajectory:
    """A finished run: the sampled ``dataset`` and the run's ``summary``.

    Made by :func:`simulate`, not by hand.

    Parameters
    ----------
    samples : RunSamples
        The sampled time series and the run's attributes, as NumPy arrays.
    status : str
        ``"success"`` or why the run stopped early (``"lift_off"``,
        ``"friction_singular"``, ``"off_shape"``, ``"max_steps"``,
        ``"step_too_small"``, ``"not_finite"``); the samples reach ``t_stop``.
    message : str
        What stopped the run and what to change, or "".
    t_stop : float
        Time the run reached [s].
    min_normal_force : float
        Smallest normal force N at the integrator's steps [N].
    ending : RunEnding
        What the outcome's reduction reads besides the samples.
    statistics : dict of str to int
        Solver counts (``solvers.STATISTICS``): ``nfev``, ``njev``, ``nlu``,
        ``n_accepted``, ``n_rejected``, ``n_switches`` (between DOP853 and Radau, method
        ``auto``).
    """

    samples: RunSamples
    status: str
    message: str
    t_stop: float
    min_normal_force: float
    ending: RunEnding
    statistics: dict[str, int] = field(default_factory=dict)

    @cached_property
    def dataset(self) -> xr.Dataset:
        """The samples as an ``xarray.Dataset``, built on first use.

        Time series, spin crossings, phases, and the run's attributes.
        """
        return self.samples.to_dataset()

    @property
    def ok(self) -> bool:
        """Whether the run reached ``t_end``."""
        return self.status == "success"

    def raise_for_status(self) -> Trajectory:
        """Raise the matching :class:`CeltstoneError` unless the run succeeded.

        Returns
        -------
        Trajectory
            This run, when it succeeded.
        """
        if not self.ok:
            raise _ERRORS.get(self.status, IntegrationError)(self.message)
        return self

    @property
    def spin_crossings(self) -> np.ndarray:
        """Times at which the spin ω · n changes sign [s]."""
        return np.asarray(self.samples.values("spin_crossings"))

    @property
    def first_spin_crossing_time(self) -> float | None:
        """First sign change of the spin ω · n [s], None if it never changes.

        Raw: around a reversal the spin can cross zero several times, and a dying spin
        dithers about zero.
        """
        crossings = self.spin_crossings
        return float(crossings[0]) if crossings.size else None

    @property
    def reversal_band(self) -> float:
        """Default half-width of the reversal's hysteresis band [rad/s].

        4 % of the initial |spin|, at least 0.01 rad/s
        (``celtstone.simulation.reversals.reversal_bands``), as in sweeps and the reproduction.
        """
        return float(reversal_bands(np.array([self.samples.values("spin")[0]]))[0])

    @property
    def reversal_window(self) -> float:
        """Width of the rocking average of the spin that reversals are read from [s].

        The body's rocking period (``Body.rocking_period``); 0 (the raw spin) in files
        written before it was recorded.
        """
        return float(self.samples.attrs.get("reversal_window", 0.0))

    def reversal_times(self, band: float | None = None) -> np.ndarray:
        """Find the reversals of the sense of spin.

        A reversal is a change of sign of the spin's rocking average
        (:attr:`reversal_window`) held beyond the hysteresis band
        (``celtstone.simulation.reversals``).

        Parameters
        ----------
        band : float, optional
            Half-width of the band [rad/s]; default :attr:`reversal_band`.

        Returns
        -------
        numpy.ndarray
            Reversal times [s], shape (r,).
        """
        ds = self.samples
        threshold = self.reversal_band if band is None else band
        return reversal_times(
            ds.values("time"),
            ds.values("spin"),
            threshold,
            self.spin_crossings,
            self.reversal_window,
        )

    @property
    def first_reversal_time(self) -> float | None:
        """First reversal of the sense of spin [s], None if the spin never reverses.

        With the default hysteresis band: the reversal of sweeps and the report.
        """
        return json_number(self.outcome()["first_reversal_time"])

    def outcome(self, band: float | None = None) -> dict[str, Any]:
        """Give the run's outcome record, as a sweep stores it for the same point.

        Parameters
        ----------
        band : float, optional
            Half-width of the spin's hysteresis band of the reversals [rad/s]; default
            :attr:`reversal_band`.

        Returns
        -------
        dict of str to object
            Each swept outcome of ``simulation.outcome.OUTCOMES`` by name, in its unit
            (NaN where the declaration says; counts as int, ``status`` and ``message``
            as text).
        """
        return dict(self._outcome) if band is None else self._reduce(band)

    @cached_property
    def _outcome(self) -> dict[str, Any]:
        return self._reduce(self.reversal_band)

    def _reduce(self, band: float) -> dict[str, Any]:
        """The outcome record by the sweep's compiled reduction (``batch.reduce_run``)."""
        from celtstone.solvers import batch

        ending = self.ending
        raw = batch.reduce_run(
            ending.model_code,
            ending.params,
            ending.initial_state,
            (ending.status_code, self.t_stop, self.min_normal_force, ending.n_crossings),
            self.samples.values("time"),
            ending.states,
            self.spin_crossings,
            band,
            self.reversal_window,
        )
        text = {"status": self.status, "message": self.message}
        return {
            f.name: text[f.name]
            if f.column is None or f.dtype == "str"
            else (int(raw[f.column]) if f.dtype == "int32" else float(raw[f.column]))
            for f in batch.RESULT_FIELDS
        }

    @property
    def max_friction_bound_ratio(self) -> float | None:
        """Largest |F| / (f N) over the samples with N > 0, N the true normal force [1].

        Above 1 the friction exceeds Coulomb's bound, as the paper's first approximation
        (``friction_load`` static, the law loaded with m g) allows. None for rolling (no
        friction law), f = 0 or no sample with N > 0.
        """
        ds = self.samples
        coefficient = ds.attrs.get("friction_coefficient")
        if ds.attrs["model"] == "rolling" or not isinstance(coefficient, (int, float)):
            return None
        normal = ds.values("normal_force")
        loaded = normal > 0.0
        if not coefficient > 0.0 or not np.any(loaded):
            return None
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # f N may underflow
            ratios = ds.values("friction_force")[loaded] / (coefficient * normal[loaded])
        return json_number(float(np.nanmax(ratios))) if np.any(np.isfinite(ratios)) else None

    def plot(self) -> Figure:
        """Draw the run (``celtstone.plotting.plot_run``).

        Spin with its reversals, tilt, energy and its budget, slip, normal force and
        contact path against time.

        Returns
        -------
        matplotlib.figure.Figure
            The figure, outside pyplot.
        """
        from celtstone.plotting.run import plot_run

        return plot_run(self.dataset)

    def _repr_html_(self) -> str:
        """A short table for Jupyter: body, model and contact, duration, status, first
        reversal and energy lost."""
        attrs = self.samples.attrs
        energy = self.samples.values("energy")
        first = self.first_reversal_time
        model = str(attrs["model"])
        if model == "sliding":
            model += f", f = {float(attrs['friction_coefficient']):g}"
            model += f", {attrs.get('contact', 'sliding')} contact"
        rows = {
            "body": str(attrs["body"]),
            "model": model,
            "t_end": f"{float(attrs['t_end']):g} s",
            "status": self.status if self.ok else f"{self.status} at {self.t_stop:.6g} s",
            "first reversal": "none" if first is None else f"{first:.6g} s",
            "energy lost": f"{float(energy[0] - energy[-1]):.6g} J",
        }
        cells = "".join(
            f"<tr><th style='text-align:left'>{html.escape(name)}</th>"
            f"<td style='text-align:left'>{html.escape(value)}</td></tr>"
            for name, value in rows.items()
        )
        return f"<table><caption>celtstone Trajectory</caption>{cells}</table>"

    def summary(self) -> dict[str, Any]:
        """Summarise the run as ``celtstone run --json`` prints it.

        Returns
        -------
        dict of str to object
            The outcomes (``simulation.outcome.OUTCOMES``, the stick–slip ones for that
            contact only) and the settings the run was run with (``SETTINGS``), JSON-safe
            (a NaN as None), and ``units``: each key's unit.
        """
        ds = self.samples
        attrs = ds.attrs
        outcome = self.outcome()
        summary: dict[str, Any] = {
            "model": attrs["model"],
            "contact": attrs.get("contact", attrs["model"]),
            "body": attrs["body"],
            "body_shape": attrs.get("body_shape", ""),
            "t_end": float(attrs["t_end"]),
        }
        for name, value in outcome.items():
            summary[name] = json_number(value) if isinstance(value, float) else value
        summary.update(self._sample_outcomes(outcome))
        if "phase_start" in ds:
            summary.update(_phase_summary(ds))
        summary["reversal_band"] = self.reversal_band
        summary["reversal_window"] = self.reversal_window
        summary.update({key: attrs[key] for key in ("method", "rtol", "atol", "friction_law")})
        for key in SETTINGS:  # the other settings the run records; "none" (not set): null
            if key in attrs and key not in summary:
                summary[key] = None if str(attrs[key]) == "none" else attrs[key]
        summary["statistics"] = dict(self.statistics)
        summary["units"] = units(summary)
        return summary

    def _sample_outcomes(self, outcome: Mapping[str, Any]) -> dict[str, Any]:
        """The outcomes that are not swept, read from the whole samples (reversal and
        crossing times, energy drift, slip speed, friction bound) or from the swept
        ``outcome`` (whether the energy is monotone)."""
        ds = self.samples
        energy = ds.values("energy")
        drift = None
        if ds.attrs["model"] == "rolling" and ds.attrs["damping"] == 0.0:
            drift = float(np.max(np.abs(energy - energy[0])) / abs(energy[0]))
        return {
            "reversal_times": [float(t) for t in self.reversal_times()],
            "spin_crossings": [float(t) for t in self.spin_crossings],
            "first_spin_crossing_time": self.first_spin_crossing_time,
            "max_slip_speed": float(np.max(ds.values("slip_speed"))),
            "max_friction_bound_ratio": self.max_friction_bound_ratio,
            "max_relative_energy_drift": drift,
            "energy_monotone": is_energy_monotone(
                outcome["max_energy_rise"], outcome["energy_initial"]
            ),
        }
