"""What a run amounted to, declared once: the outcome record and the run's settings.

Each *outcome* (the first reversal, the final spin, the energy lost, the largest tilt…)
has one name, one SI unit and one meaning here, whoever reports it: ``celtstone run
--json`` and :meth:`Trajectory.summary`, the sweep store, the reproduction's cases and
threshold table, the atlas and the fit. The outcomes marked ``swept`` are computed by
one compiled reduction of a run's samples (``solvers.batch``), applied to every sweep
point and to every single run alike, so a sweep point equals the single run by
construction. The others need a run's whole samples (the list of reversal times, the
largest slip speed…) and are read from them by :meth:`Trajectory.summary`.

*Settings* are not outcomes: what was run (model, body, method, tolerances, the model's
options, solver statistics). ``run --json`` prints them beside the outcomes, and every
key it prints is declared in one of the two tables, with its unit in the JSON's
``units`` map.

Names follow one vocabulary, in SI (angles in rad). Names used before are in
:data:`RENAMED_OUTCOMES`; files written with them read as written now.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from celtstone.simulation.schema import PARAMETERS, VARIABLES, Variable

__all__ = [
    "ENERGY_MONOTONE_TOLERANCE",
    "OUTCOMES",
    "RENAMED_OUTCOMES",
    "SETTINGS",
    "SWEPT",
    "Outcome",
    "Setting",
    "current_outcomes",
    "is_energy_monotone",
    "json_number",
    "units",
    "variable",
]

ENERGY_MONOTONE_TOLERANCE = 1e-9
"""Largest rise of the sampled energy between samples, relative to E(0), still
counted as monotone decrease (the integrator's tolerance, not physics)."""


@dataclass(frozen=True)
class Outcome:
    """One quantity of what a run amounted to.

    Parameters
    ----------
    variable : its unit, meaning (``long_name``), plot label and the meaning of a
        missing value (``schema.Variable``)
    dtype : how it is kept: ``"float64"``, ``"int32"``, ``"str"``, ``"bool"`` (one
        value), ``"list"`` (a list of numbers) or ``"records"`` (a list of records)
    fill : the value of a sweep point not computed yet (swept outcomes)
    swept : computed by the compiled reduction (``solvers.batch``) for sweep points and
        single runs alike, and stored per point by a sweep
    contact : ``"hybrid"`` for an outcome of the stick–slip contact only
    """

    variable: Variable
    dtype: str = "float64"
    fill: float | int | str = math.nan
    swept: bool = False
    contact: str = ""

    @property
    def unit(self) -> str:
        return self.variable.unit


@dataclass(frozen=True)
class Setting:
    """What a run was run with, as ``run --json`` prints it: its unit (``""`` for text,
    ``"1"`` for a number without one) and meaning."""

    unit: str
    meaning: str


def _swept(
    unit: str, long_name: str, label: str = "", dtype: str = "float64", **kwargs: Any
) -> Outcome:
    fill: float | int | str = -1 if dtype == "int32" else "" if dtype == "str" else math.nan
    return Outcome(Variable(unit, long_name, label, **kwargs), dtype, fill, swept=True)


def _run(unit: str, long_name: str, dtype: str = "float64", contact: str = "") -> Outcome:
    return Outcome(Variable(unit, long_name), dtype, swept=False, contact=contact)


_DEG = 180.0 / math.pi

OUTCOMES: dict[str, Outcome] = {
    # computed by the compiled reduction; a sweep stores these, in this order
    "first_reversal_time": _swept(
        "s",
        "first reversal of the sense of spin (hysteresis band), NaN (null) if none",
        "first reversal time",
        missing="no reversal in the run",
    ),
    "reversal_count": _swept(
        "1", "number of spin reversals (hysteresis band)", "number of spin reversals", "int32"
    ),
    "spin_final": _swept(
        "rad/s",
        "spin omega . n at t_end, NaN (null) if the run stopped early",
        r"final spin $\omega\cdot n$",
    ),
    "energy_lost": _swept(
        "J",
        "E(0) - E(t_end), NaN (null) if the run stopped early",
        r"energy lost $E(0)-E(t_\mathrm{end})$",
    ),
    "max_tilt": _swept(
        "rad",
        "largest angle between the vertical and body axis 3 over the samples",
        "largest tilt of body axis 3",
        plot_unit="deg",
        plot_scale=_DEG,
    ),
    "min_normal_force": _swept(
        "N",
        "smallest normal force over the steps and samples (0 at lift-off)",
        "smallest normal force $N$",
    ),
    "t_stop": _swept("s", "time the run stopped (t_end if it finished)", "stop time"),
    "status": _swept("", "success, or why the run stopped early", "status", "str"),
    "message": _swept("", "what happened and what to change", "message", "str"),
    "energy_initial": _swept("J", "energy E(0) at the start", "initial energy $E(0)$"),
    "peak_reversed_spin": _swept(
        "rad/s",
        "largest spin against the initial sense, -sign(spin(0)) spin, over the samples",
        "peak reversed spin",
    ),
    "spin_crossing_count": _swept(
        "1",
        "number of sign changes of the raw spin omega . n (no band)",
        "spin sign changes",
        "int32",
    ),
    "max_energy_balance_error": _swept(
        "J",
        "largest |E(0) - E - W| over the samples, W the dissipated work",
        "energy balance error",
    ),
    "max_energy_rise": _swept(
        "J", "largest rise of the energy between two samples (0: never rises)", "energy rise"
    ),
    "spin_initial": _swept("rad/s", "spin omega . n at the start", r"initial spin $\omega\cdot n$"),
    "energy_final": _swept(
        "J",
        "energy E(t_end), NaN (null) if the run stopped early",
        r"final energy $E(t_\mathrm{end})$",
    ),
    "dissipated_work": _swept(
        "J",
        "work W done by friction and damping until the run stopped",
        "dissipated work $W$",
    ),
    # read from a run's whole samples (Trajectory.summary)
    "reversal_times": _run("s", "times of the spin reversals (hysteresis band)", "list"),
    "spin_crossings": _run("s", "times at which the raw spin omega . n changes sign", "list"),
    "first_spin_crossing_time": _run(
        "s", "first sign change of the raw spin, null if none (a dying spin dithers)"
    ),
    "max_slip_speed": _run("m/s", "largest slip speed |V1| of the contact over the samples"),
    "max_friction_bound_ratio": _run(
        "1", "largest |F| / (f N) for the true N > 0, null without a friction law"
    ),
    "max_relative_energy_drift": _run(
        "1", "largest |E - E(0)| / |E(0)|, for an undamped rolling run only (else null)"
    ),
    "energy_monotone": _run(
        "", "whether the energy never rises between samples beyond rounding", "bool"
    ),
    # the stick–slip contact's phases
    "stick_phases": _run("1", "number of stick phases", "int32", "hybrid"),
    "slip_phases": _run("1", "number of slip phases", "int32", "hybrid"),
    "phases": _run(
        "",
        "each phase: kind (stick or slip), t_start [s], t_end [s], energy_jump [J]",
        "records",
        "hybrid",
    ),
    "max_capture_energy_jump": _run(
        "J", "largest kinetic energy change of a capture impulse", contact="hybrid"
    ),
    "rejected_captures": _run(
        "1", "captures refused (the stick would not hold)", "int32", "hybrid"
    ),
}
"""Every outcome of a run, by name; the ``swept`` ones in the sweep store's order."""

SWEPT = tuple(name for name, outcome in OUTCOMES.items() if outcome.swept)
"""The outcomes of the compiled reduction, as a sweep stores them."""


def _parameter(name: str, meaning: str = "") -> Setting:
    quantity = PARAMETERS[name]
    return Setting(quantity.unit or "1", meaning or quantity.description)


SETTINGS: dict[str, Setting] = {
    "model": Setting("", "rolling or sliding"),
    "contact": Setting("", "rolling, sliding (regularised) or hybrid (stick–slip)"),
    "body": Setting("", "the body's name"),
    "body_shape": Setting("", "the body's shape kind"),
    "t_end": _parameter("t_end"),
    "method": Setting("", "the integrator"),
    "rtol": _parameter("rtol"),
    "atol": Setting("", PARAMETERS["atol"].description),  # each component in its own unit
    "friction_law": Setting("", "the friction law (none for rolling)"),
    "reversal_band": _parameter(
        "reversal_band", "half-width of the spin's hysteresis band of the reversals"
    ),
    "reversal_window": Setting("s", "width of the spin's rocking average (rocking period)"),
    "statistics": Setting("1", "the solver's counts (nfev, njev, nlu, steps, switches)"),
    # the model's options, as set (null: not set)
    "damping": _parameter("damping"),
    "rolling_resistance": _parameter("rolling_resistance"),
    "rolling_resistance_rate": _parameter("rolling_resistance_rate"),
    "friction_coefficient": _parameter("friction_coefficient"),
    "contact_radius": _parameter("contact_radius"),
    "friction_load": Setting("", "normal force in the friction law: static or dynamic"),
    "regularisation_speed": _parameter("regularisation_speed"),
    "contact_pressure": Setting("", "pressure on the contact: hertz or uniform"),
    "contact_shape": Setting("", "shape of the contact: circle or ellipse"),
    "contact_radius_model": Setting("", "fixed contact radius, or hertz from the moduli"),
    "elastic_modulus": _parameter("elastic_modulus"),
    "poisson_ratio": _parameter("poisson_ratio"),
    "effective_modulus": Setting("Pa", "effective modulus E / (1 - nu^2) of the contact"),
    # the stick–slip contact
    "capture_speed": _parameter("capture_speed"),
    "stick_method": Setting("", "the integrator of the stick phases"),
    # the reproduction's cases
    "energy_rest": Setting("J", "energy m g h of the body at rest"),
}
"""What ``run --json`` prints besides the outcomes, by name."""

RENAMED_OUTCOMES: dict[str, str] = {
    "n_reversals": "reversal_count",  # sweep stores, the atlas's cases
    "final_spin": "spin_final",  # sweep stores
    "raw_sign_changes": "spin_crossing_count",  # sweep stores, reproduction cases
    "max_budget_error": "max_energy_balance_error",  # sweep stores, cases, threshold
    "spin_zero_crossings": "spin_crossings",  # run --json
    "first_sign_change_time": "first_spin_crossing_time",  # run --json
    "first_raw_sign_change": "first_spin_crossing_time",  # reproduction cases
}
"""Old name -> name now of an outcome (CHANGELOG.md); ``max_tilt_deg`` [deg] of ``run
--json`` is ``max_tilt`` [rad], a value converted, not only renamed."""


def is_energy_monotone(max_energy_rise: float, energy_initial: float) -> bool:
    """``energy_monotone`` from ``max_energy_rise`` [J] and ``energy_initial`` [J]."""
    return bool(max_energy_rise <= ENERGY_MONOTONE_TOLERANCE * abs(energy_initial))


def variable(name: str) -> Variable:
    """The declaration of ``name``: an outcome's, else a time series' (``schema.VARIABLES``)."""
    return OUTCOMES[name].variable if name in OUTCOMES else VARIABLES[name]


def units(keys: Iterable[str]) -> dict[str, str]:
    """Each of ``keys`` (outcomes or settings) -> its unit, as ``run --json`` states them.

    Raises
    ------
    KeyError
        for a key declared in neither table (a summary that prints an undeclared key).
    """
    found = {}
    for key in keys:
        declared = OUTCOMES.get(key) or SETTINGS.get(key)
        if declared is None:
            raise KeyError(f"{key!r} is declared neither an outcome nor a setting")
        found[key] = declared.unit
    return found


def current_outcomes(record: Mapping[str, Any]) -> dict[str, Any]:
    """``record`` with the old names of :data:`RENAMED_OUTCOMES` under their names now: a
    case or result written before the renames reads as one written now."""
    current = dict(record)
    for old, new in RENAMED_OUTCOMES.items():
        if old in current and new not in current:
            current[new] = current.pop(old)
    return current


def json_number(value: float) -> float | None:
    """``value`` as a float, or None (JSON ``null``) where it is not finite."""
    number = float(value)
    return number if math.isfinite(number) else None
