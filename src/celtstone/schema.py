"""One entry per user-settable quantity: symbol, SI unit, allowed range, meaning.

This table is the single source of the unit and range of every parameter: the
validators, the CLI help and the ``units`` attributes of exported data read it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from celtstone.errors import ParameterError

__all__ = [
    "PARAMETERS",
    "RENAMED",
    "RENAMED_ATTRIBUTES",
    "VARIABLES",
    "Quantity",
    "Variable",
    "check",
    "current_attributes",
    "renamed",
    "renamed_hint",
]


@dataclass(frozen=True)
class Quantity:
    """A physical quantity: name, the paper's symbol, SI unit and allowed interval.

    ``lower``/``upper`` bound the allowed values; ``lower_open``/``upper_open``
    say whether the bound itself is excluded.
    """

    name: str
    symbol: str
    unit: str
    description: str
    lower: float = -math.inf
    upper: float = math.inf
    lower_open: bool = False
    upper_open: bool = False

    @property
    def allowed(self) -> str:
        """The allowed range in words, e.g. ``"> 0"`` or ``"in [0, 1)"``."""
        has_lower = math.isfinite(self.lower)
        has_upper = math.isfinite(self.upper)
        if has_lower and has_upper:
            left = "(" if self.lower_open else "["
            right = ")" if self.upper_open else "]"
            return f"a number in {left}{self.lower:g}, {self.upper:g}{right}"
        if has_lower:
            return f"a number {'>' if self.lower_open else '>='} {self.lower:g}"
        if has_upper:
            return f"a number {'<' if self.upper_open else '<='} {self.upper:g}"
        return "a finite number"

    def help(self) -> str:
        """One line for CLI help: description, symbol, unit and range."""
        unit = f" [{self.unit}]" if self.unit else ""
        return f"{self.description} ({self.symbol}){unit}, {self.allowed}"


def _q(name: str, symbol: str, unit: str, description: str, **bounds: float | bool) -> Quantity:
    return Quantity(name, symbol, unit, description, **bounds)  # type: ignore[arg-type]


# Bounds beyond which no run means anything or the output cannot be held in memory:
MAX_SAMPLES = 1_000_000  # output samples of one run (about 0.3 GB with derived quantities)
MAX_T_END = 1e6  # s; a rolling K&L run takes ~360 steps/s, so 1e6 s is 3.6e8 steps
MAX_ATOL = 1e-3  # an absolute error above this lets |n| = 1 drift visibly in one step
MAX_ANGULAR_SPEED = 1e4  # rad/s (95 000 rpm); spun faster, every stone lifts off at once
# m; a rolling-friction length is a fraction of the contact size (Cross 2016: ~1e-6 to
# 1e-3 m for balls on hard to soft floors); 1 cm is past any rattleback's contact
MAX_ROLLING_RESISTANCE = 1e-2

_POSITIVE = {"lower": 0.0, "lower_open": True}
_NON_NEGATIVE = {"lower": 0.0}

PARAMETERS: dict[str, Quantity] = {
    q.name: q
    for q in [
        _q("mass", "m", "kg", "mass of the body", **_POSITIVE),
        _q("gravity", "g", "m/s^2", "gravitational acceleration", **_POSITIVE),
        _q("inertia", "A", "kg m^2", "central inertia tensor, body axes"),
        _q("semi_axes", "a, b, c", "m", "ellipsoid semi-axes along body axes 1, 2, 3", **_POSITIVE),
        _q("com_offset", "h", "m", "distance of the centre of mass below the ellipsoid centre"),
        _q("radii_of_curvature", "rho1, rho2", "m", "paraboloid radii of curvature", **_POSITIVE),
        _q(
            "com_height",
            "l",
            "m",
            "height of the centre of mass above the rest contact",
            **_POSITIVE,
        ),
        _q(
            "damping",
            "sigma",
            "N m s",
            "viscous torque coefficient, torque -sigma*omega",
            **_NON_NEGATIVE,
        ),
        _q("friction_coefficient", "f", "", "Coulomb friction coefficient", **_NON_NEGATIVE),
        _q("contact_radius", "epsilon", "m", "radius of the Hertz contact disk", **_POSITIVE),
        _q(
            "regularisation_speed",
            "delta",
            "m/s",
            "slip-speed scale regularising the singular state",
            **_POSITIVE,
        ),
        _q(
            "rolling_resistance",
            "lambda",
            "m",
            "rolling-friction length: shift of the pressure centre, moment lambda*N "
            "against the rolling part of omega",
            lower=0.0,
            upper=MAX_ROLLING_RESISTANCE,
        ),
        _q(
            "rolling_resistance_rate",
            "omega_0",
            "rad/s",
            "rolling rate below which the rolling resistance turns viscous",
            **_POSITIVE,
        ),
        _q(
            "elastic_modulus",
            "E",
            "Pa",
            "Young's modulus of body and plane, for the Hertz contact radius",
            **_POSITIVE,
        ),
        _q(
            "poisson_ratio",
            "nu",
            "",
            "Poisson's ratio of body and plane, for the Hertz contact radius",
            lower=-1.0,
            upper=0.5,
            lower_open=True,
            upper_open=True,
        ),
        _q("load", "N", "N", "normal force pressing the contact", **_POSITIVE),
        _q("equivalent_radius", "R_eq", "m", "equivalent radius sqrt(R1 R2)", **_POSITIVE),
        _q("slip_ratio", "u", "", "slip ratio |V1| / (epsilon |Omega_n|)", **_NON_NEGATIVE),
        _q(
            "capture_speed",
            "v_c",
            "m/s",
            "hybrid contact: slip-spin speed counted as zero, where stick may start",
            **_POSITIVE,
        ),
        _q("t_end", "t_end", "s", "duration of the run", upper=MAX_T_END, **_POSITIVE),
        _q("rtol", "rtol", "", "relative tolerance of the integrator", lower=1e-14, upper=1e-2),
        _q(
            "atol",
            "atol",
            "",
            "absolute tolerance of the integrator on every state component (n [1], "
            "omega [rad/s], slip velocity [m/s])",
            upper=MAX_ATOL,
            **_POSITIVE,
        ),
        _q(
            "omega",
            "omega0",
            "rad/s",
            "initial angular velocity, body axes",
            lower=-MAX_ANGULAR_SPEED,
            upper=MAX_ANGULAR_SPEED,
        ),
        _q(
            "euler_angles",
            "alpha, beta",
            "deg",
            "initial Euler angles of the vertical in body axes",
            lower=-89.0,
            upper=89.0,
        ),
        _q("max_steps", "max_steps", "", "largest number of integrator steps", lower=1.0),
        _q("n_samples", "n_samples", "", "number of output samples", lower=2.0, upper=MAX_SAMPLES),
        _q(
            "reversal_band",
            "band",
            "rad/s",
            "half-width of the hysteresis band that defines a spin reversal",
            **_POSITIVE,
        ),
    ]
}


# Inputs renamed so that each name has one meaning across CLI, JSON, Dataset and docs
# (README, "Renamed in this version"): old name -> new name, as Python and sweeps spell
# them (the CLI with dashes). An old name is refused with the new one (``renamed``).
RENAMED: dict[str, str] = {
    "normal_force": "friction_load",  # the option static|dynamic; normal_force is N [N]
    "tilt": "euler_angles",  # the initial (alpha, beta) [deg]; tilt is an angle [rad]
    "tilt_alpha": "euler_alpha",
    "tilt_beta": "euler_beta",
    "spin": "initial_spin",  # a sweep's omega0 . n0; spin is the time series omega . n
}

# a run's attributes renamed with them: old key -> new key (older files keep the old key)
RENAMED_ATTRIBUTES: dict[str, str] = {
    "normal_force_option": "friction_load",
    "initial_tilt_deg": "initial_euler_angles_deg",
}


def renamed_hint(name: str, spell: Callable[[str], str] = str) -> str:
    """``"renamed friction_load"`` for an old name of :data:`RENAMED`, else ``""``; ``spell``
    writes a name as the user writes it (``--friction-load`` on the command line)."""
    return f"renamed {spell(RENAMED[name])}" if name in RENAMED else ""


def renamed(name: str, value: object = None, spell: Callable[[str], str] = str) -> ParameterError:
    """The error refusing ``name``, an old name of :data:`RENAMED`, with a hint naming the
    new one (``renamed_hint``)."""
    return ParameterError(spell(name), value, "its new name", renamed_hint(name, spell))


def current_attributes(attrs: Mapping[str, Any]) -> dict[str, Any]:
    """A run's ``attrs`` with the old keys of :data:`RENAMED_ATTRIBUTES` under their new
    names: a file written before the rename reads as one written now."""
    current = dict(attrs)
    for old, new in RENAMED_ATTRIBUTES.items():
        if old in current and new not in current:
            current[new] = current.pop(old)
    return current


@dataclass(frozen=True)
class Variable:
    """An output quantity, declared once: what the Dataset, the sweep store, the CSV
    headers, the figures and the viewer say about it.

    ``unit`` and ``long_name`` are the NetCDF attributes of the stored values (SI);
    ``label`` names it on a matplotlib axis (mathtext) and ``text`` in plain text (the
    HTML viewer); plots show ``plot_unit`` = stored value × ``plot_scale``.

    ``source`` makes it a time series of every run's Dataset, read from the sampled
    states (``trajectory.sample_run``): ``"derived"`` is the derived column of the
    same name (``kernels.system.DERIVED``), ``"derived:a,b"`` the consecutive derived
    columns a to b, ``"state:block"`` a block of the state (``kernels.system.STATE_BLOCKS``).
    ``axis`` names the second dimension of a vector (after ``time``). Without a source
    a variable is filled where it is made: the time coordinate, the spin crossings and
    phases of a run, the result fields of a sweep (``solvers.batch.RESULT_FIELDS``),
    or a parameter drawn on an axis.
    """

    unit: str
    long_name: str
    label: str = ""
    text: str = ""
    plot_unit: str = ""
    plot_scale: float = 1.0
    source: str = ""
    axis: str = ""

    @property
    def attributes(self) -> dict[str, str]:
        """``units`` (omitted when empty) and ``long_name``, as NetCDF attributes."""
        return ({"units": self.unit} if self.unit else {}) | {"long_name": self.long_name}

    def axis_label(self) -> str:
        """``"spin $\\omega\\cdot n$ [rad/s]"``: the label and the plotted unit."""
        unit = self.plot_unit or self.unit
        text = self.label or self.long_name
        return f"{text} [{unit}]" if unit not in ("", "1") else text


_DEG = 180.0 / math.pi

VARIABLES: dict[str, Variable] = {
    # the time coordinate, then a run's time series in the Dataset's order
    "time": Variable("s", "time", "time $t$", "time t"),
    "spin": Variable(
        "rad/s",
        "spin omega . n about the vertical",
        r"spin $\omega\cdot n$",
        "spin ω·n",
        source="derived",
    ),
    "tilt": Variable(
        "rad",
        "angle between the vertical and body axis 3",
        "tilt of body axis 3",
        "tilt",
        plot_unit="deg",
        plot_scale=_DEG,
        source="derived",
    ),
    "energy": Variable(
        "J",
        "kinetic plus potential energy, plane as zero",
        "energy $E$",
        "energy",
        source="derived",
    ),
    "dissipated_work": Variable(
        "J",
        "work done by friction and damping since t = 0",
        "friction work",
        "friction work",
        source="state:work",
    ),
    "normal_force": Variable(
        "N", "normal force N of the plane", "normal force $N$", "normal force N", source="derived"
    ),
    "slip_speed": Variable(
        "m/s",
        "sliding speed |V1| of the contact point",
        "slip speed $|V_1|$",
        "slip speed |V1|",
        source="derived",
    ),
    "friction_power": Variable("W", "friction power F . V1 + M Omega_n", source="derived"),
    "friction_force": Variable(
        "N",
        "tangential friction force |F| of the plane (0 in rolling)",
        "friction force $|F|$",
        "friction force |F|",
        source="derived",
    ),
    "com_height": Variable("m", "height of the centre of mass above the plane", source="derived"),
    "omega": Variable("rad/s", "angular velocity, body axes", source="state:omega", axis="axis"),
    "n": Variable("1", "upward vertical unit vector, body axes", source="state:n", axis="axis"),
    "slip_velocity": Variable(
        "m/s",
        "sliding velocity V1 of the contact point, body axes",
        source="state:slip_velocity",
        axis="axis",
    ),
    "quaternion": Variable(
        "1",
        "attitude quaternion (w, x, y, z), body to space",
        source="state:quaternion",
        axis="component",
    ),
    "com_position": Variable(
        "m",
        "horizontal position of the centre of mass, space axes",
        source="state:com_position",
        axis="plane_axis",
    ),
    "contact_position": Variable(
        "m",
        "position of the contact point on the plane, space axes",
        "contact point",
        source="derived:contact_x,contact_y",
        axis="plane_axis",
    ),
    # a run's events and phases (trajectory.sample_run)
    "spin_crossings": Variable("s", "times at which the spin changes sign"),
    "phase": Variable("1", "contact phase of the hybrid contact: 0 slip, 1 stick"),
    "phase_kind": Variable("1", "kind of each contact phase: 0 slip, 1 stick"),
    "phase_start": Variable("s", "start time of each contact phase"),
    "phase_end": Variable("s", "end time of each contact phase"),
    "phase_energy_jump": Variable(
        "J", "kinetic energy change of the capture impulse opening each phase"
    ),
    # a sweep's result fields (solvers.batch.RESULT_FIELDS), in the store's order
    "first_reversal_time": Variable(
        "s",
        "first reversal of the sense of spin (hysteresis band), NaN if none",
        "first reversal time",
    ),
    "n_reversals": Variable(
        "1", "number of spin reversals (hysteresis band)", "number of spin reversals"
    ),
    "final_spin": Variable(
        "rad/s", "spin omega . n at t_end, NaN if stopped early", r"final spin $\omega\cdot n$"
    ),
    "energy_lost": Variable(
        "J", "E(0) - E(t_end), NaN if stopped early", r"energy lost $E(0)-E(t_\mathrm{end})$"
    ),
    "max_tilt": Variable(
        "rad",
        "largest angle between the vertical and axis 3",
        "largest tilt of body axis 3",
        plot_unit="deg",
        plot_scale=_DEG,
    ),
    "min_normal_force": Variable(
        "N", "smallest normal force (0 at lift-off)", "smallest normal force $N$"
    ),
    "t_stop": Variable("s", "time the run stopped", "stop time"),
    "status": Variable("", "success, or why the run stopped early", "status"),
    "message": Variable("", "what happened and what to change", "message"),
    "energy_initial": Variable("J", "energy E(0) at the start", "initial energy $E(0)$"),
    "peak_reversed_spin": Variable(
        "rad/s",
        "largest spin against the initial sense, -sign(spin(0)) spin, over the samples",
        "peak reversed spin",
    ),
    "raw_sign_changes": Variable(
        "1", "zero crossings of the raw spin omega . n (no band)", "raw spin sign changes"
    ),
    "max_budget_error": Variable(
        "J",
        "largest |E(0) - E - W| over the samples, W the dissipated work",
        "energy budget residual",
    ),
    "max_energy_rise": Variable(
        "J", "largest rise of the energy between two samples (0: never rises)", "energy rise"
    ),
    # axis labels of plots
    "contact_x": Variable("m", "contact point x, space axes", "contact point $x$"),
    "contact_y": Variable("m", "contact point y, space axes", "contact point $y$"),
    "friction_coefficient": Variable(
        "1", "Coulomb friction coefficient", "friction coefficient $f$"
    ),
}


def check(name: str, value: float) -> float:
    """Return ``value`` as float if it is finite and inside the range of ``name``.

    Raises
    ------
    ParameterError
        naming the parameter, the value and the allowed range.
    """
    quantity = PARAMETERS[name]
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, value, quantity.allowed) from None
    ok = math.isfinite(number)
    if ok and math.isfinite(quantity.lower):
        ok = number > quantity.lower if quantity.lower_open else number >= quantity.lower
    if ok and math.isfinite(quantity.upper):
        ok = number < quantity.upper if quantity.upper_open else number <= quantity.upper
    if not ok:
        unit = f" {quantity.unit}" if quantity.unit else ""
        raise ParameterError(name, value, quantity.allowed + unit)
    return number
