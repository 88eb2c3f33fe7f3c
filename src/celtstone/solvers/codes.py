"""Integer codes shared by the compiled integrators and their Python wrapper."""

from __future__ import annotations

METHOD_DOP853 = 0
METHOD_RADAU5 = 1

METHODS = {"dop853": METHOD_DOP853, "radau5": METHOD_RADAU5}

# slots of the integrator's int64 statistics array (8 long)
STAT_NFEV = 0
STAT_NJEV = 1
STAT_NLU = 2
STAT_ACCEPTED = 3
STAT_REJECTED = 4
STAT_SAMPLES_WRITTEN = 5  # output samples filled so far, updated after every step
N_STATS = 8

STATUS_SUCCESS = 0
STATUS_LIFT_OFF = 1
STATUS_SINGULAR = 2
STATUS_OFF_SHAPE = 3
STATUS_MAX_STEPS = 4
STATUS_STEP_TOO_SMALL = 5
STATUS_NOT_FINITE = 6
STATUS_PHASE_CHANGE = 7
STATUS_NON_CONVEX = 8

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
}
