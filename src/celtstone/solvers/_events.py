"""Events: what the driver looks for inside every accepted step, as rows of a table.

A row (a record of :data:`EVENT`) names a value kernel g(y) and how its zeros count,
as SciPy's ``solve_ivp`` events carry ``terminal`` and ``direction``:

==============  =====  =========  ========  ====  =======  ============  ============
event           value  direction  terminal  sub.  root     end value     status
==============  =====  =========  ========  ====  =======  ============  ============
lift-off        N      falling    yes       1     nearest  checked       LIFT_OFF
phase change    phase  falling    yes       4     past     interpolated  PHASE_CHANGE
spin crossing   ω · n  either     no        4     nearest  checked       (recorded)
==============  =====  =========  ========  ====  =======  ============  ============

* **value**: ``VALUE_SPIN`` ω · n [rad/s]; ``VALUE_NORMAL_FORCE`` N [N];
  ``VALUE_PHASE`` ``system.phase_value`` with the row's ``parameter`` (the capture
  speed v_c [m/s] of a sliding phase). Each is a function of the state alone.
* **direction**: ``FALLING`` counts a fall from g >= 0 to g < 0 only, so a phase that
  starts below zero (a slip phase just after stick) is not stopped at once; ``EITHER``
  counts any change of sign and an arrival at exactly zero.
* **terminal**: the run stops at the first such root with ``STATUS_<status>``;
  otherwise every root is recorded (the spin crossings) and the run goes on.
* **subdivisions** (sub.): the sign is checked at that many equally spaced points of the
  step, so that two crossings inside one step are both found.
* **root**: Illinois (modified regula falsi) on the interpolant to ``ROOT_TOLERANCE``;
  ``ROOT_NEAREST`` returns the bracket end with the smaller |g|, ``ROOT_PAST`` the end
  already past the crossing (g < 0), so that a run restarted there is in the new phase.
* **end value**: at the end of a step the driver's check of the accepted state gives
  N and ω · n exactly (``END_CHECKED``); the phase value is read from the interpolant
  (``END_INTERPOLATED``).

A step in which every row's roots are decided by the step's ends alone
(:func:`all_decided_by_ends`) is not scanned, so that a step with no sample and no event
inside needs no interpolant (DOP853's costs three evaluations).

Terminal rows are searched first, in table order, each inside the part of the step
left by the ones before; then the others, up to where the run stops.
:func:`event_table` builds a run's table from its model and capture speed.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from celtstone.kernels._jit import kernel
from celtstone.kernels.layout import MODEL_SLIDING, MODEL_STICK, Y_N, Y_OMEGA
from celtstone.kernels.system import phase_value
from celtstone.solvers import _methods as methods
from celtstone.solvers._compile import inlined
from celtstone.solvers._system import parameters, spin_and_normal_force
from celtstone.solvers.codes import STATUS_LIFT_OFF, STATUS_PHASE_CHANGE, STATUS_SUCCESS

ROOT_TOLERANCE = 1e-12  # s, event location
EVENT_SUBDIVISIONS = 4  # sign checks per step, to catch two crossings in one step
MAX_ROOT_ITERATIONS = 200

VALUE_SPIN = 0
VALUE_NORMAL_FORCE = 1
VALUE_PHASE = 2

FALLING = -1
EITHER = 0

ROOT_NEAREST = 0
ROOT_PAST = 1

END_CHECKED = 0
END_INTERPOLATED = 1

EVENT = np.dtype(  # records, so that fields read as attributes in Python too
    (
        np.record,
        np.dtype(
            [
                ("value", "i8"),  # VALUE_*
                ("parameter", "f8"),  # a number the value kernel takes (v_c [m/s] for VALUE_PHASE)
                ("direction", "i8"),  # FALLING or EITHER
                ("terminal", "b1"),  # stops the run at its first root
                ("subdivisions", "i8"),  # sign checks per step
                ("root", "i8"),  # ROOT_NEAREST or ROOT_PAST
                ("end", "i8"),  # END_CHECKED or END_INTERPOLATED
                ("status", "i8"),  # run status of a terminal row
            ],
            align=True,
        ),
    )
)


class Step(NamedTuple):
    """An accepted step [t_old, t_old + h] and its interpolant."""

    method: int  # method code
    dense: np.ndarray  # the interpolant's coefficients (``_methods.dense_arrays``)
    y_old: np.ndarray  # state at t_old
    t_old: float  # [s]
    h: float  # [s]


@inlined
def _set_row(row, value, parameter, direction, terminal, subdivisions, root, end, status):
    row.value = value
    row.parameter = parameter
    row.direction = direction
    row.terminal = terminal
    row.subdivisions = subdivisions
    row.root = root
    row.end = end
    row.status = status


@kernel
def event_table(model, capture_speed):
    """The events of a run of ``model`` (see the module docstring).

    Every run watches lift-off; the stick phase (``MODEL_STICK``) and a sliding run with
    ``capture_speed`` v_c [m/s] > 0 watch the phase value; all but stick record spin
    crossings (in stick ω · n = 0 is held and its sign is round-off).
    """
    has_phase = model == MODEL_STICK or (model == MODEL_SLIDING and capture_speed > 0.0)
    has_spin = model != MODEL_STICK
    rows = 1 + (1 if has_phase else 0) + (1 if has_spin else 0)
    table = np.zeros(rows, dtype=EVENT)
    _set_row(
        table[0],
        VALUE_NORMAL_FORCE,
        0.0,
        FALLING,
        True,
        1,
        ROOT_NEAREST,
        END_CHECKED,
        STATUS_LIFT_OFF,
    )
    k = 1
    if has_phase:
        _set_row(
            table[k],
            VALUE_PHASE,
            capture_speed,
            FALLING,
            True,
            EVENT_SUBDIVISIONS,
            ROOT_PAST,
            END_INTERPOLATED,
            STATUS_PHASE_CHANGE,
        )
        k += 1
    if has_spin:
        _set_row(
            table[k],
            VALUE_SPIN,
            0.0,
            EITHER,
            False,
            EVENT_SUBDIVISIONS,
            ROOT_NEAREST,
            END_CHECKED,
            STATUS_SUCCESS,
        )
    return table


@inlined
def spin_of(y):
    """ω · n of a state [rad/s]."""
    return y[Y_OMEGA] * y[Y_N] + y[Y_OMEGA + 1] * y[Y_N + 1] + y[Y_OMEGA + 2] * y[Y_N + 2]


@inlined
def spin_rate(y, f):
    """d(ω · n)/dt of a state from its derivative f = dy/dt [rad/s²]."""
    return (
        f[Y_OMEGA] * y[Y_N]
        + f[Y_OMEGA + 1] * y[Y_N + 1]
        + f[Y_OMEGA + 2] * y[Y_N + 2]
        + y[Y_OMEGA] * f[Y_N]
        + y[Y_OMEGA + 1] * f[Y_N + 1]
        + y[Y_OMEGA + 2] * f[Y_N + 2]
    )


@inlined
def decided_by_ends(event, start_value, end_value, start_rate, end_rate, h):
    """Whether the row has no root in a whole step, known from its ends alone.

    True for a row checked at the step's end (``END_CHECKED``) without a root between
    its end values, if it is checked once a step (``subdivisions`` 1: what its scan
    would find), or if it is the spin and both end values lie farther from zero than
    h (|g'_a| + |g'_b|), with ``start_rate`` and ``end_rate`` its rates g' [rad/s²] and
    h the step [s]: the spin cannot reach zero inside the step unless its interpolant
    swings by more than the step's own slopes allow, which the step-size control keeps
    out. Otherwise False, and every row of the step is scanned on the interpolant.
    """
    if event.end != END_CHECKED or crosses(event.direction, start_value, end_value):
        return False
    if event.subdivisions <= 1:
        return True
    if event.value != VALUE_SPIN:
        return False
    reach = abs(h) * (abs(start_rate) + abs(end_rate))
    return min(abs(start_value), abs(end_value)) > reach


@inlined
def all_decided_by_ends(table, values, spin, normal_force, start_rate, end_rate, h):
    """Whether every row is ``decided_by_ends`` in a step whose ends have the values
    ``values`` (start) and ``spin`` [rad/s], ``normal_force`` [N] (end): then
    the run takes ``take_ends`` and reads no interpolant in that step."""
    for row in range(table.shape[0]):
        event = table[row]
        end = checked_value(event, spin, normal_force)
        if not decided_by_ends(event, values[row], end, start_rate, end_rate, h):
            return False
    return True


@inlined
def event_value(event, model, params, y, scratch):
    """The row's value kernel at state ``y``; NaN for an unknown value code."""
    if event.value == VALUE_SPIN:
        return spin_of(y)
    if event.value == VALUE_NORMAL_FORCE:
        return spin_and_normal_force(model, y, params, scratch)[1]
    if event.value == VALUE_PHASE:
        return phase_value(model, y, parameters(params), event.parameter)
    return np.nan


@inlined
def checked_value(event, spin, normal_force):
    """The row's value from the driver's check of an accepted state (``END_CHECKED``)."""
    if event.value == VALUE_SPIN:
        return spin
    if event.value == VALUE_NORMAL_FORCE:
        return normal_force
    return np.nan


@inlined
def value_at(event, model, params, step, x, point, scratch):
    """The row's value at the fraction x of the step, from the interpolant."""
    methods.interpolate_apart(step.method, step.dense, step.y_old, x, point)
    return event_value(event, model, params, point, scratch)


@inlined
def crosses(direction, before, after):
    """Whether g going from ``before`` to ``after`` is a root in ``direction``."""
    if direction == FALLING:
        return before >= 0.0 > after
    if direction == EITHER:
        return (before < 0.0 < after) or (after < 0.0 < before) or (after == 0.0 != before)
    return False


@kernel
def locate_root(event, model, params, step, a, b, ga, gb, point, scratch):
    """Illinois root of the row's value on the bracket [a, b] of step fractions, g(a) = ga,
    g(b) = gb, to ``ROOT_TOLERANCE`` in time; the end the row's ``root`` asks for."""
    past = event.root == ROOT_PAST
    if not (past or event.root == ROOT_NEAREST):
        return np.nan
    tolerance = ROOT_TOLERANCE / max(abs(step.h), 1e-300)
    side = 0
    for _ in range(MAX_ROOT_ITERATIONS):
        if abs(b - a) <= tolerance:
            break
        x = (a * gb - b * ga) / (gb - ga)
        if not (a < x < b):
            x = 0.5 * (a + b)
        gx = value_at(event, model, params, step, x, point, scratch)
        if gx == 0.0 and not past:
            return x
        # a ROOT_PAST row falls from ga >= 0 to gb < 0: a zero counts on the side of a
        same_side = (gx >= 0.0) if past else ((gx > 0.0) == (ga > 0.0))
        if same_side:
            a, ga = x, gx
            if side == -1:
                gb *= 0.5
            side = -1
        else:
            b, gb = x, gx
            if side == 1:
                ga *= 0.5
            side = 1
    if past:
        return b
    return b if abs(gb) <= abs(ga) else a


@inlined
def scan(
    event,
    model,
    params,
    step,
    x_limit,
    uncut,
    start_value,
    end_value,
    found,
    n_found,
    point,
    scratch,
):
    """Roots of one row in the step fractions [0, x_limit].

    ``start_value`` is g at the step's start, ``end_value`` the checked g at its end
    (used when ``uncut``: no terminal root cut the step). A terminal row stops at its
    first root; the others write each root's time to ``found`` after the ``n_found``
    there (counted beyond its length, stored up to it). Returns (roots, the new count,
    fraction of the first root (x_limit if none), g at x_limit).
    """
    count = event.subdivisions
    x_a = 0.0
    g_a = start_value
    roots = 0
    first = x_limit
    for k in range(1, count + 1):
        x_b = x_limit * k / count
        if k == count and uncut and event.end == END_CHECKED:
            g_b = end_value
        else:
            g_b = value_at(event, model, params, step, x_b, point, scratch)
        if crosses(event.direction, g_a, g_b):
            if g_b == 0.0:
                root = x_b
            else:
                root = locate_root(event, model, params, step, x_a, x_b, g_a, g_b, point, scratch)
            roots += 1
            if event.terminal:
                return roots, n_found, root, g_a
            if roots == 1:
                first = root
            if n_found < found.shape[0]:
                found[n_found] = step.t_old + root * step.h
            n_found += 1
        x_a = x_b
        g_a = g_b
    return roots, n_found, first, g_a


@kernel
def start_values(table, model, params, y, values, scratch):
    """Each row's value at the run's first state into ``values``."""
    for row in range(table.shape[0]):
        values[row] = event_value(table[row], model, params, y, scratch)


@inlined
def take_ends(table, values, spin, normal_force, step, t_new, n_crossings):
    """The events of an accepted ``step`` (ending at ``t_new`` [s]) whose ends decide every
    row (``all_decided_by_ends``): each row's g at the step's end into ``values``, no root.

    ``spin`` [rad/s] and ``normal_force`` [N] are the driver's check of the accepted state.
    Returns what ``scan_rows`` returns: no stopping row (-1), the whole step, and the
    ``n_crossings`` found before.
    """
    for row in range(table.shape[0]):
        values[row] = checked_value(table[row], spin, normal_force)
    return -1, (t_new - step.t_old) / step.h, t_new, n_crossings


@kernel
def scan_rows(
    table,
    values,
    spin,
    normal_force,
    model,
    params,
    step,
    t_new,
    crossings,
    n_crossings,
    point,
    scratch,
):
    """Every row's roots in the accepted ``step`` (ending at ``t_new`` [s]) whose ends do
    not decide every row: each row scanned on the interpolant.

    ``values`` holds each row's g at the step's start and receives it at the step's end
    (where the run goes on); ``spin`` [rad/s] and ``normal_force`` [N] are the driver's
    check of the accepted state. Non-terminal roots go to ``crossings`` after the
    ``n_crossings`` found before (counted beyond its length, stored up to it).

    Returns (the terminal row that stops the run or -1, step fraction and time [s]
    where the run stops or the step ends, crossings found in all).

    A function of its own, called only then (``take_ends`` serves the other steps), so
    that the run loop does not compile every row's scan and root search into itself.
    """
    t_limit = t_new
    x_limit = (t_new - step.t_old) / step.h
    stop_row = -1
    for terminal in (True, False):  # terminal rows first: a root cuts the step short
        for row in range(table.shape[0]):
            event = table[row]
            if event.terminal != terminal:
                continue
            end = checked_value(event, spin, normal_force)
            roots, n_crossings, first, values[row] = scan(
                event,
                model,
                params,
                step,
                x_limit,
                stop_row < 0,
                values[row],
                end,
                crossings,
                n_crossings,
                point,
                scratch,
            )
            if terminal and roots > 0:
                stop_row = row
                x_limit = first
                t_limit = step.t_old + first * step.h
    return stop_row, x_limit, t_limit, n_crossings
