"""Integer codes shared by the compiled integrators and their Python wrapper."""

from __future__ import annotations

METHOD_DOP853 = 0
METHOD_RADAU5 = 1

# the methods registry: name -> code; each code has its module (``solvers._methods``)
METHODS = {"dop853": METHOD_DOP853, "radau5": METHOD_RADAU5}

# slots of the integrator's int64 statistics array (8 long); the compiled loop adds to
# them, so one array sums the phases of a hybrid run
STAT_NFEV = 0  # right-hand-side evaluations
STAT_NJEV = 1  # Jacobian evaluations
STAT_NLU = 2  # LU factorisations
STAT_ACCEPTED = 3  # accepted steps
STAT_REJECTED = 4  # rejected step attempts
STAT_SAMPLES_WRITTEN = 5  # output samples filled so far, updated after every step
N_STATS = 8

DEFAULT_MAX_PHASES = 100_000  # capacity of a hybrid run's phase log (solvers.phases)

STATUS_SUCCESS = 0
STATUS_LIFT_OFF = 1
STATUS_SINGULAR = 2
STATUS_OFF_SHAPE = 3
STATUS_MAX_STEPS = 4
STATUS_STEP_TOO_SMALL = 5
STATUS_NOT_FINITE = 6
STATUS_PHASE_CHANGE = 7
STATUS_NON_CONVEX = 8
STATUS_UNKNOWN_CODE = 9
STATUS_MAX_PHASES = 10

STATUS_MESSAGES = {
    STATUS_SUCCESS: "reached t_end",
    STATUS_LIFT_OFF: "the normal force became negative: the body lifts off the plane "
    "(the contact models do not apply; lower the spin or the tilt)",
    STATUS_SINGULAR: "the friction equations have no unique solution (paper eq. 11 or a "
    "Painlevé-type case; lower the friction coefficient or use normal_force='static')",
    STATUS_OFF_SHAPE: "the contact point left the shape's domain (the paraboloid cap turned "
    "by 90 degrees; use a closed shape)",
    STATUS_MAX_STEPS: "too many steps: raise max_steps or loosen rtol",
    STATUS_STEP_TOO_SMALL: "the step size fell below round-off: loosen rtol or use the "
    "stiff method radau5",
    STATUS_NOT_FINITE: "the state became infinite or NaN: tighten rtol or use radau5",
    STATUS_PHASE_CHANGE: "the hybrid contact changed phase (stick <-> slip); the phase loop "
    "restarts the integration in the other phase",
    STATUS_NON_CONVEX: "no contact point found for the implicit shape at this vertical: "
    "the surface is not strictly convex there or the Newton solve failed",
    STATUS_UNKNOWN_CODE: "a model, shape, normal-force, friction-law, pressure, method or "
    "right-hand-side status code that no compiled branch handles (a bug in the caller: "
    "please report it)",
    STATUS_MAX_PHASES: "more stick-slip phases than the phase log holds (max_phases, "
    f"{DEFAULT_MAX_PHASES} unless given): shorten t_end, or raise max_phases "
    "(hybrid.solve_phases, solvers.batch.run_batch)",
}
