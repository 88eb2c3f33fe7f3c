"""Integer codes shared by the compiled integrators and their Python wrapper."""

from __future__ import annotations

import enum
from dataclasses import dataclass

METHOD_DOP853 = 0
METHOD_RADAU5 = 1
METHOD_AUTO = 2  # DOP853 and Radau by turns, switched on stiffness (``solvers._auto``)
METHOD_VERN9 = 3  # Verner's 9(8) pair (``solvers._vern9``)


@dataclass(frozen=True)
class Method:
    """An integration method of the registry :data:`METHOD_ENTRIES`, declared once: the
    compiled dispatch on its code (``solvers._dispatch``) is generated from these entries
    (``python src/celtstone/solvers/_generate.py``), and the help texts, the validation, the
    driver's first-run compile and the GPU sweep read them.

    Parameters
    ----------
    code : the ``METHOD_<NAME>`` the compiled loops branch on, numbered next (the
        interpolants' arrays are indexed by code, ``_methods.dense_arrays``)
    words : what help texts show
    module : the module that follows the method contract (``solvers._methods``), dotted
    own_loop : a first run with it compiles a run loop for its model and this method
        alone (``driver.integrate_link``): worth it for a method that holds little of the
        others' code (the explicit ones), not for one that holds most of it
    gpu : the workspace a sweep's GPU thread gives it (``batch_cuda``): ``"explicit"``
        (shared by the explicit methods, ``batch_cuda.ThreadWorkspace``), ``"radau"`` or
        ``"switching"`` (``auto``'s record); empty where the GPU does not run it
    switches_among : for a method whose steps the others take by turns (``auto``): those
        methods. Its module provides ``workspace()``, ``start`` and ``after_step`` on its
        switching record, whose field ``active`` names the method of the next step (see
        ``solvers._methods``, "Switching")
    notes_steps_of : the methods whose accepted steps a switching method's
        ``note_explicit_step`` reads (``auto``: DOP853's stiffness estimate)
    """

    code: int
    words: str
    module: str
    own_loop: bool = False
    gpu: str = ""
    switches_among: tuple[str, ...] = ()
    notes_steps_of: tuple[str, ...] = ()


# the methods registry, one entry per method: name -> code, words, module and traits
METHOD_ENTRIES = {
    "dop853": Method(
        METHOD_DOP853,
        "Dormand–Prince 8(5,3), explicit",
        "celtstone.solvers._dop853",
        own_loop=True,
        gpu="explicit",
    ),
    "radau5": Method(
        METHOD_RADAU5,
        "Radau IIA of order 5, implicit, for stiff contacts",
        "celtstone.solvers._radau",
        gpu="radau",
    ),
    "auto": Method(
        METHOD_AUTO,
        "DOP853 and Radau IIA by turns, switched on stiffness",
        "celtstone.solvers._auto",
        gpu="switching",
        switches_among=("dop853", "radau5"),
        notes_steps_of=("dop853",),
    ),
    "vern9": Method(
        METHOD_VERN9,
        "Verner's 9(8) pair, explicit",
        "celtstone.solvers._vern9",
        own_loop=True,
        gpu="explicit",
    ),
}
METHODS = {name: method.code for name, method in METHOD_ENTRIES.items()}  # name -> code

# slots of the integrator's int64 statistics array (9 long); the compiled loop adds to
# them, so one array sums the phases of a hybrid run
STAT_NFEV = 0  # right-hand-side evaluations
STAT_NJEV = 1  # Jacobian evaluations
STAT_NLU = 2  # LU factorisations
STAT_ACCEPTED = 3  # accepted steps
STAT_REJECTED = 4  # rejected step attempts
STAT_SAMPLES_WRITTEN = 5  # output samples filled so far, updated after every step
STAT_SWITCHES = 6  # switches between DOP853 and Radau (method auto)
STAT_RADAU_STEPS = 7  # accepted steps that Radau took (all of radau5's, auto's stiff ones)
# not a count: set to 1 from another thread to stop the run at its next step
# (``solvers._stop``); read by the compiled loop before each step
STAT_STOP_REQUESTED = 8
N_STATS = 9

DEFAULT_MAX_PHASES = 100_000  # capacity of a hybrid run's phase log (solvers.phases)


class PhaseKind(enum.IntEnum):
    """A phase of the stick–slip contact, declared once: the code the compiled phase loop
    writes into its log and each sample's ``phase`` (``solvers.phases``), kept as that
    integer in a run's Dataset; its ``label`` is what the summary and the CLI print."""

    SLIP = 0  # sliding (paper eq. 6–12) until the slip–spin speed falls below v_c
    STICK = 1  # rolling without sliding or pivoting until the stick margin falls below 0

    @property
    def label(self) -> str:
        """``"slip"`` or ``"stick"``."""
        return self.name.lower()


class Status(enum.IntEnum):
    """How a run ended, declared once: the code the compiled loops return, the ``label``
    that results, the CLI and the sweep store show, and the ``message`` saying what
    happened and what to change.

    Each member is ``NAME = code, label, message``. The compiled code reads the plain-int
    aliases ``STATUS_<NAME>`` below (an IntEnum *argument* would compile another
    specialisation; a global folds to its integer either way).
    """

    label: str
    message: str

    def __new__(cls, code: int, label: str, message: str) -> Status:
        member = int.__new__(cls, code)
        member._value_ = code
        member.label = label
        member.message = message
        return member

    SUCCESS = 0, "success", "reached t_end"
    LIFT_OFF = (
        1,
        "lift_off",
        "the normal force became negative: the body lifts off the plane "
        "(the contact models do not apply; lower the spin or the tilt)",
    )
    SINGULAR = (
        2,
        "friction_singular",
        "the friction equations have no unique solution (paper eq. 11 or a "
        "Painlevé-type case; lower the friction coefficient or use friction_load='static')",
    )
    OFF_SHAPE = (
        3,
        "off_shape",
        "the contact point left the shape's domain (the paraboloid cap turned "
        "by 90 degrees; use a closed shape)",
    )
    MAX_STEPS = 4, "max_steps", "too many steps: raise max_steps or loosen rtol"
    STEP_TOO_SMALL = (
        5,
        "step_too_small",
        "the step size fell below round-off: loosen rtol or use the stiff method radau5",
    )
    NOT_FINITE = (
        6,
        "not_finite",
        "the state became infinite or NaN: tighten rtol or use radau5",
    )
    PHASE_CHANGE = (
        7,
        "phase_change",
        "the hybrid contact changed phase (stick <-> slip); the phase loop "
        "restarts the integration in the other phase",
    )
    NON_CONVEX = (
        8,
        "non_convex",
        "no contact point found for the implicit shape at this vertical: "
        "the surface is not strictly convex there or the Newton solve failed",
    )
    UNKNOWN_CODE = (
        9,
        "unknown_code",
        "a model, shape, friction-load, friction-law, pressure, method or "
        "right-hand-side status code that no compiled branch handles (a bug in the caller: "
        "please report it)",
    )
    MAX_PHASES = (
        10,
        "max_phases",
        "more stick-slip phases than the phase log holds (max_phases, "
        f"{DEFAULT_MAX_PHASES} unless given): shorten t_end, or raise max_phases "
        "(solvers.solve_phases, solvers.batch.run_batch)",
    )
    CONTACT_RANGE = (
        11,
        "contact_range",
        "the elliptic contact left the range of its law: the Hertz ellipse became more "
        "than 50 times longer than wide (B/A < 0.02), or the surface is flat or "
        "saddle-shaped at the contact; use contact_shape circle",
    )
    STOPPED = (
        12,
        "stopped",
        "stopped on request before t_end (the caller cancelled the run or pressed Ctrl-C)",
    )


# plain ints for the compiled code (numba folds a global to its value)
STATUS_SUCCESS = int(Status.SUCCESS)
STATUS_LIFT_OFF = int(Status.LIFT_OFF)
STATUS_SINGULAR = int(Status.SINGULAR)
STATUS_OFF_SHAPE = int(Status.OFF_SHAPE)
STATUS_MAX_STEPS = int(Status.MAX_STEPS)
STATUS_STEP_TOO_SMALL = int(Status.STEP_TOO_SMALL)
STATUS_NOT_FINITE = int(Status.NOT_FINITE)
STATUS_PHASE_CHANGE = int(Status.PHASE_CHANGE)
STATUS_NON_CONVEX = int(Status.NON_CONVEX)
STATUS_UNKNOWN_CODE = int(Status.UNKNOWN_CODE)
STATUS_MAX_PHASES = int(Status.MAX_PHASES)
STATUS_CONTACT_RANGE = int(Status.CONTACT_RANGE)
STATUS_STOPPED = int(Status.STOPPED)

UNDECLARED_STATUS = "failed"  # the label of a code that no member declares (never returned)

_BY_CODE = {member.value: member for member in Status}
STATUS_MESSAGES = {code: member.message for code, member in _BY_CODE.items()}  # a view of Status


def status_label(code: int) -> str:
    """The label of status ``code`` (``"lift_off"``), ``UNDECLARED_STATUS`` if none has it."""
    member = _BY_CODE.get(int(code))
    return member.label if member is not None else UNDECLARED_STATUS


def stop_message(code: int, t_stop: float, detail: str = "") -> str:
    """How a run ended, in words, for its summary and its sweep point.

    ``"reached t_end"`` for ``Status.SUCCESS``, else ``"stopped at t = <t_stop> s:
    <the status's message><detail>"``; ``t_stop`` [s] is the time the run stopped.
    """
    member = _BY_CODE.get(int(code))
    if member is Status.SUCCESS:
        return member.message
    text = member.message if member is not None else ""
    return f"stopped at t = {t_stop:.6g} s: {text}{detail}"
