"""One entry per user-settable quantity: symbol, SI unit, allowed range, meaning.

This table is the single source of the unit and range of every parameter: the
validators, the CLI help and the ``units`` attributes of exported data read it.
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Callable, Mapping, Sequence
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
    "check_components",
    "check_count",
    "current_attributes",
    "parse_count",
    "parse_number",
    "real_number",
    "renamed",
    "renamed_hint",
]


@dataclass(frozen=True)
class Quantity:
    """A physical quantity: name, the paper's symbol, SI unit and allowed interval.

    ``lower``/``upper`` bound the allowed values; ``lower_open``/``upper_open``
    say whether the bound itself is excluded; ``integer`` makes it a count, whose
    values are integers (:func:`check_count`).
    """

    name: str
    symbol: str
    unit: str
    description: str
    lower: float = -math.inf
    upper: float = math.inf
    lower_open: bool = False
    upper_open: bool = False
    integer: bool = False

    @property
    def allowed(self) -> str:
        """The allowed range in words, e.g. ``"a number > 0"`` or ``"an integer in [2, 1e+06]"``."""
        kind = "an integer" if self.integer else "a number"
        has_lower = math.isfinite(self.lower)
        has_upper = math.isfinite(self.upper)
        if has_lower and has_upper:
            left = "(" if self.lower_open else "["
            right = ")" if self.upper_open else "]"
            return f"{kind} in {left}{self.lower:g}, {self.upper:g}{right}"
        if has_lower:
            return f"{kind} {'>' if self.lower_open else '>='} {self.lower:g}"
        if has_upper:
            return f"{kind} {'<' if self.upper_open else '<='} {self.upper:g}"
        return "an integer" if self.integer else "a finite number"

    def contains(self, number: float) -> bool:
        """Whether ``number`` is finite and inside the allowed interval."""
        if not math.isfinite(number):
            return False
        if math.isfinite(self.lower) and not (
            number > self.lower if self.lower_open else number >= self.lower
        ):
            return False
        return not math.isfinite(self.upper) or (
            number < self.upper if self.upper_open else number <= self.upper
        )

    def help(self) -> str:
        """One line for CLI help: description, symbol, unit and range."""
        unit = f" [{self.unit}]" if self.unit else ""
        return f"{self.description} ({self.symbol}){unit}, {self.allowed}"


def _q(name: str, symbol: str, unit: str, description: str, **bounds: float | bool) -> Quantity:
    return Quantity(name, symbol, unit, description, **bounds)  # type: ignore[arg-type]


def _count(name: str, description: str, lower: float, upper: float = math.inf) -> Quantity:
    return Quantity(name, name, "", description, lower=lower, upper=upper, integer=True)


# Bounds beyond which no run means anything or the output cannot be held in memory:
MAX_SAMPLES = 1_000_000  # output samples of one run (about 0.3 GB with derived quantities)
MAX_T_END = 1e6  # s; a rolling K&L run takes ~360 steps/s, so 1e6 s is 3.6e8 steps
MAX_ATOL = 1e-3  # an absolute error above this lets |n| = 1 drift visibly in one step
MAX_ANGULAR_SPEED = 1e4  # rad/s (95 000 rpm); spun faster, every stone lifts off at once
# m/s; a contact point sliding faster than a thrown stone moves is no rattleback's
MAX_SLIP_SPEED = 10.0
# m; a rolling-friction length is a fraction of the contact size (Cross 2016: ~1e-6 to
# 1e-3 m for balls on hard to soft floors); 1 cm is past any rattleback's contact
MAX_ROLLING_RESISTANCE = 1e-2
# spin zero crossings one run stores: 8 bytes each, allocated before the run starts
MAX_CROSSINGS = 10_000_000

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
        _q(
            "slip_velocity",
            "V0",
            "m/s",
            "initial sliding velocity of the contact point along body axes 1 and 2 (its "
            "axis-3 part keeps it in the table plane)",
            lower=-MAX_SLIP_SPEED,
            upper=MAX_SLIP_SPEED,
        ),
        _count("max_steps", "largest number of integrator steps", lower=1),
        _count("n_samples", "number of output samples", lower=2, upper=MAX_SAMPLES),
        _count("max_crossings", "largest number of spin zero crossings stored", 1, MAX_CROSSINGS),
        _count("workers", "number of threads running the runs", lower=1),
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
# (CHANGELOG.md, "Renamed"): old name -> new name, as Python and sweeps spell
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
    phases of a run, or a parameter drawn on an axis (a run's outcomes, what a sweep
    stores per point, are declared in ``simulation.outcome``). ``missing`` says in words
    what a NaN of a finished run means (a map's legend names such cells).
    """

    unit: str
    long_name: str
    label: str = ""
    text: str = ""
    plot_unit: str = ""
    plot_scale: float = 1.0
    source: str = ""
    axis: str = ""
    missing: str = ""

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
    # axis labels of plots
    "contact_x": Variable("m", "contact point x, space axes", "contact point $x$"),
    "contact_y": Variable("m", "contact point y, space axes", "contact point $y$"),
    "friction_coefficient": Variable(
        "1", "Coulomb friction coefficient", "friction coefficient $f$"
    ),
}


def real_number(value: object) -> float | None:
    """``value`` as a float if it is a real number, else None.

    Real numbers are Python's ``int`` and ``float``, NumPy's integer and floating scalars
    and 0-d arrays of them. Booleans, text, None and sequences are not: a string is
    turned into a number only where the command line reads it (:func:`parse_number`).
    """
    if isinstance(value, bool) or type(value).__name__ in ("bool_", "bool"):  # NumPy's too
        return None
    if isinstance(value, numbers.Real):
        return float(value)
    dtype = getattr(value, "dtype", None)
    if getattr(value, "ndim", None) == 0 and getattr(dtype, "kind", "") in ("i", "u", "f"):
        return float(value)  # type: ignore[arg-type]
    return None


def _kind_hint(value: object) -> str:
    """``"a str, not a number"``: why a value of the wrong type is refused."""
    if value is None:
        return "None, not a number"
    return f"a {type(value).__name__}, not a number"


def check(name: str, value: object) -> float:
    """Return ``value`` as float if it is a real number, finite and inside the range of ``name``.

    The one check of every number a user gives, from Python and from the command line
    alike: text, booleans and None are refused (:func:`real_number`), and a count (a
    quantity with ``integer``) must also be an integer (:func:`check_count`).

    Raises
    ------
    ParameterError
        naming the parameter, the value and the allowed range.
    """
    quantity = PARAMETERS[name]
    if quantity.integer:
        return float(check_count(name, value))
    number = real_number(value)
    if number is None:
        raise ParameterError(name, value, quantity.allowed, _kind_hint(value))
    if not quantity.contains(number):
        unit = f" {quantity.unit}" if quantity.unit else ""
        raise ParameterError(name, value, quantity.allowed + unit)
    return number


def check_count(name: str, value: object) -> int:
    """Return ``value`` as int if it is an integer inside the range of the count ``name``.

    Integers are Python's ``int``, NumPy's integer scalars and 0-d integer arrays; a
    float is refused even when it is whole (``2.5`` and ``10.0`` alike: counts are
    integers), as are booleans and text.

    Parameters
    ----------
    name : str
        A count of :data:`PARAMETERS` (``n_samples``, ``max_steps``, ``max_crossings``,
        ``workers``).
    value : object
        The value given.

    Raises
    ------
    ParameterError
        naming the parameter, the value and the allowed range.
    """
    quantity = PARAMETERS[name]
    dtype = getattr(value, "dtype", None)
    is_integer = isinstance(value, numbers.Integral) or getattr(dtype, "kind", "") in ("i", "u")
    if real_number(value) is None or not is_integer:
        kind = "None" if value is None else f"a {type(value).__name__}"
        raise ParameterError(name, value, quantity.allowed, f"{kind}, not an integer")
    count = int(value)  # type: ignore[call-overload]
    if not quantity.contains(count):
        raise ParameterError(name, value, quantity.allowed)
    return count


def check_components(name: str, value: object, count: int, allowed: str) -> tuple[float, ...]:
    """``value`` as a tuple of ``count`` floats, each checked as ``name`` (:func:`check`).

    A list, tuple or 1-D array of that length is accepted; text, a mapping, a set, a
    scalar, None or another length is refused with ``allowed`` (``"three numbers
    W1,W2,W3 in rad/s"``).

    Raises
    ------
    ParameterError
        naming the parameter, the value and what is allowed.
    """
    is_array = getattr(value, "ndim", None) == 1
    if isinstance(value, str | bytes) or not (isinstance(value, Sequence) or is_array):
        raise ParameterError(name, value, allowed)
    items: tuple[object, ...] = tuple(value)  # type: ignore[arg-type]
    if len(items) != count:
        raise ParameterError(name, value, allowed)
    return tuple(check(name, item) for item in items)


# a decimal number as the command line reads it: no underscores ("1_0"), no other digits
# than 0-9, no hexadecimal; inf and nan are read, and refused by the range check
_NUMBER = re.compile(
    r"[+-]?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|inf|infinity|nan)", re.I
)
_INTEGER = re.compile(r"[+-]?[0-9]+")


def _allowed(name: str) -> str:
    return PARAMETERS[name].allowed if name in PARAMETERS else "a number"


def parse_number(name: str, text: str, allowed: str | None = None) -> float:
    """The number written as ``text`` on the command line, checked for form only.

    Python's ``float`` also reads ``"1_0"`` as 10 and digits of other scripts; a
    command line takes a plain decimal (``5``, ``-0.5``, ``1e-3``, ``.5``), with
    spaces around it ignored. The range is checked where the number is used.

    Parameters
    ----------
    name : str
        The parameter, as its error names it.
    text : str
        What was typed.
    allowed : str, optional
        What is allowed, in words; default the range of ``PARAMETERS[name]``.

    Raises
    ------
    ParameterError
        for anything but a decimal number.
    """
    words = allowed if allowed is not None else _allowed(name)
    if not isinstance(text, str) or not _NUMBER.fullmatch(text.strip()):
        raise ParameterError(name, text, words, "written as a plain decimal such as 0.5 or 1e-3")
    return float(text)


def parse_count(name: str, text: str) -> int:
    """The integer written as ``text`` on the command line (``200``, ``1e3``), in the range
    of the count ``name`` when it is one of :data:`PARAMETERS` (:func:`check_count`).

    A decimal that is not a whole number (``2.5``), an underscore or any other
    character is refused; the error shows ``text`` as it was typed.

    Raises
    ------
    ParameterError
        for anything but a whole decimal number in the count's range.
    """
    allowed = _allowed(name)
    if isinstance(text, str) and _INTEGER.fullmatch(text.strip()):
        try:
            count = int(text)
        except ValueError:  # more digits than Python converts
            raise ParameterError(name, text, allowed) from None
    else:
        number = parse_number(name, text, allowed)
        if not (math.isfinite(number) and number == int(number)):
            raise ParameterError(name, text, allowed, "a count is a whole number")
        count = int(number)
    if name in PARAMETERS:
        try:
            check_count(name, count)
        except ParameterError as error:
            raise ParameterError(name, text, error.allowed, error.hint) from None
    return count
