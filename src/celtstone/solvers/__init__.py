"""Compiled ODE integrators: DOP853 (non-stiff) and Radau IIA order 5 (stiff).

``solve`` allocates the outputs and calls the compiled loop ``driver.integrate``;
``solve_phases`` does the same for the compiled stick–slip loop ``phases.run_phases``
(both in ``solvers.run``; a phase's kind is a ``PhaseKind``).
The methods are the registry ``METHODS`` (name -> code); what a method module must
provide, and what the driver does for all of them, is the contract written in
``solvers._methods``. Events are rows of a table (``solvers._events``). How a run
ends is a member of ``Status`` (code, label, message; ``solvers.codes``), and
``stop_message`` words it for a run's summary and a sweep point alike.
"""

from celtstone.solvers.codes import DEFAULT_MAX_PHASES as DEFAULT_MAX_PHASES
from celtstone.solvers.codes import METHOD_DOP853 as METHOD_DOP853
from celtstone.solvers.codes import METHOD_ENTRIES as METHOD_ENTRIES
from celtstone.solvers.codes import METHOD_RADAU5 as METHOD_RADAU5
from celtstone.solvers.codes import METHOD_VERN9 as METHOD_VERN9
from celtstone.solvers.codes import METHODS as METHODS
from celtstone.solvers.codes import STATUS_LIFT_OFF as STATUS_LIFT_OFF
from celtstone.solvers.codes import STATUS_MAX_PHASES as STATUS_MAX_PHASES
from celtstone.solvers.codes import STATUS_MAX_STEPS as STATUS_MAX_STEPS
from celtstone.solvers.codes import STATUS_MESSAGES as STATUS_MESSAGES
from celtstone.solvers.codes import STATUS_NON_CONVEX as STATUS_NON_CONVEX
from celtstone.solvers.codes import STATUS_NOT_FINITE as STATUS_NOT_FINITE
from celtstone.solvers.codes import STATUS_OFF_SHAPE as STATUS_OFF_SHAPE
from celtstone.solvers.codes import STATUS_PHASE_CHANGE as STATUS_PHASE_CHANGE
from celtstone.solvers.codes import STATUS_SINGULAR as STATUS_SINGULAR
from celtstone.solvers.codes import STATUS_STEP_TOO_SMALL as STATUS_STEP_TOO_SMALL
from celtstone.solvers.codes import STATUS_STOPPED as STATUS_STOPPED
from celtstone.solvers.codes import STATUS_SUCCESS as STATUS_SUCCESS
from celtstone.solvers.codes import STATUS_UNKNOWN_CODE as STATUS_UNKNOWN_CODE
from celtstone.solvers.codes import PhaseKind as PhaseKind
from celtstone.solvers.codes import Status as Status
from celtstone.solvers.codes import status_label as status_label
from celtstone.solvers.codes import stop_message as stop_message
from celtstone.solvers.driver import integrate as integrate
from celtstone.solvers.run import STATISTICS as STATISTICS
from celtstone.solvers.run import RawPhases as RawPhases
from celtstone.solvers.run import RawSolution as RawSolution
from celtstone.solvers.run import capture as capture
from celtstone.solvers.run import solve as solve
from celtstone.solvers.run import solve_phases as solve_phases
