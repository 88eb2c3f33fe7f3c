"""The integrator contract, and the compiled dispatch that routes a method code to its module.

The contract (in the manner of SciPy's ``OdeSolver``)
-----------------------------------------------------
1. **A method is one module** ``solvers/_<name>.py`` and one entry in the registry
   ``codes.METHOD_ENTRIES`` (name, code, words, module, traits). The compiled dispatch on
   a method code, the functions this module hands on, is generated from the registry
   into ``solvers/_dispatch.py`` (``python src/celtstone/solvers/_generate.py``; a test fails
   while the checked-in file is not the registry's). Tests parametrised over
   ``solvers.METHODS`` then run it: convergence slope, agreement with SciPy, events,
   failures. Every function of the dispatch is compiled by numba and takes numbers,
   arrays and NamedTuples of them only (item 11).
2. **The system** is ``_system.rhs(model, t, y, params, out)``: ``model`` a model
   code, ``params`` the run's system (the kernel parameter record and the link to its
   compiled right-hand side, ``solvers._system``; opaque to the methods: they only pass
   it on), ``y`` the state (length n), ``out`` receives dy/dt; it returns the
   right-hand-side status and the normal force [N]. A method calls nothing else of the
   physics.
3. ``ORDER`` (int): the method's order p, global error O(h^p) (the tests check the
   slope); ``ERROR_ORDER`` (int): the order q of its local error estimate, with which
   the driver's first step (Hairer's heuristic, ``_step_control.initial_step``)
   scales as tol^(1/(q+1)).
4. ``workspace(n)`` returns the method's workspace: a ``NamedTuple`` of arrays sized for
   states of length n, created once per run by the driver and passed back to every call.
   It holds the dense-output coefficients and everything one step leaves for the next
   (Radau: Jacobian, LU factors, the last collocation polynomial and the controller's
   memory, a one-element structured array whose record has named fields). Nothing is
   kept anywhere else, so runs on several threads share nothing.
5. ``start(model, params, t, y, f, controls, work, stats)`` is called once, after the
   driver evaluated f = f(t, y) at the first state and before the first ``attempt``
   (Radau evaluates its first Jacobian here). ``auto``'s, which starts the others, takes
   its switching record, the first step size h and every method's workspaces.
6. ``attempt(model, params, t, y, f, h, t_end, controls, work, y_new, f_new, stats)``
   takes one step from (t, y), f = f(t, y), trying the step size h first, and returns
   ``(status, h_taken, h_next)``. **The method owns the step size**: it rejects and
   retries with smaller steps until its error norm (item 8) is at most 1, never steps
   past ``t_end`` (h_taken = min(h, t_end - t)), and proposes h_next for the following
   step. It fills ``y_new`` (the state at t + h_taken) and ``f_new`` = f(t + h_taken,
   y_new). With ``controls.adaptive`` False it takes h as given, once, and h_next = h.
   status is ``STATUS_SUCCESS``, or ``STATUS_STEP_TOO_SMALL`` once h falls below
   ``_step_control.smallest_step(t)``; then y_new is undefined. It also returns what
   ``rhs`` returned for f_new, the right-hand-side status and normal force at y_new:
   ``(status, h_taken, h_next, rhs_status, normal_force)``. The driver checks the
   accepted state with them, without an evaluation of its own.
7. ``dense(model, params, t, y, y_new, h, work, stats)`` is called at most once after
   each accepted step [t, t + h], before anything reads the step's interpolant, and
   stores in ``work.dense`` (every workspace has this 2-D array) the coefficients of
   the interpolant over it (it may evaluate f, as DOP853's three extra stages). The
   driver calls it only for a step in which a sample or an event reads the interpolant,
   unless the method sets ``DENSE_EVERY_STEP`` (Radau, whose next Newton guess is the
   last step's collocation polynomial). ``interpolate(dense, y_old, x, out)`` writes the
   state at t + x h, x in [0, 1], with ``dense`` those coefficients and ``y_old`` the
   state at t; it reads nothing else, so events and samples pass just these. The
   interpolant must be continuous from step to step and pass through y and y_new;
   its order is the method's to state (DOP853: 7, Verner's pair: 8, Radau IIA: 3, the
   collocation polynomial). Sampling and event location use nothing else.
8. **The error norm** is the RMS over the n components of (error estimate) / (atol +
   max(|y|, |y_new|) rtol), as SciPy's (``_step_control.rms_scaled``); a step is
   accepted when it is at most 1.
9. **Counters**: a method adds what it costs to ``stats`` (``codes.STAT_NFEV``,
   ``STAT_NJEV``, ``STAT_NLU``, ``STAT_REJECTED``); the driver counts accepted steps
   (and those Radau took, ``STAT_RADAU_STEPS``), its own evaluations and the samples
   written; a switching method counts its switches (``STAT_SWITCHES``).
10. **What a method does not do**: sampling, events (spin crossings, lift-off, phase
    changes), the step limit, ``max_step``, finiteness checks and stopping belong to the
    driver (``solvers.driver.integrate``), which is the same for every method.
11. **Compiling**: ``start`` is a ``kernels._jit.kernel`` function; ``workspace``,
    ``attempt``, ``dense``, ``interpolate`` and the helpers they call once a step are
    ``_compile.inlined``: numba copies them into the driver (``workspace`` into
    :func:`workspaces`), as a separate function every array they take would cost a
    measurable part of a step (docs/decisions.md §21). Arrays are not sliced per step
    for the same reason. The driver's samples and stop and the events' root search
    interpolate through :func:`interpolate_apart`, every method's interpolant compiled
    once.

Each dispatch has one branch per registered code and no default: an unknown code
returns ``STATUS_UNKNOWN_CODE`` (``attempt``) or NaN, never another method's result.

**Switching** (``auto``, ``solvers._auto``; an entry with ``switches_among``) is a method
code whose steps are taken by the others, one at a time: ``active(method, work.auto)``
names the method that takes the next step (its record's field ``active``), and the
driver passes that code to ``attempt`` (with the run's code), ``dense``,
``dense_every_step`` and ``interpolate`` for the step, with that method's coefficients
(``dense_arrays`` looked up once per run); ``after_step`` takes the run's code, and the
switching module's ``note_explicit_step`` reads each accepted step of the methods its
entry's ``notes_steps_of`` names. Each method's step is compiled once however many codes
route to it.
"""

from __future__ import annotations

from celtstone.kernels._jit import kernel
from celtstone.solvers._compile import inlined
from celtstone.solvers._dispatch import MODULES as MODULES
from celtstone.solvers._dispatch import Workspaces as Workspaces
from celtstone.solvers._dispatch import active as active
from celtstone.solvers._dispatch import after_step as after_step
from celtstone.solvers._dispatch import attempt as attempt
from celtstone.solvers._dispatch import constants
from celtstone.solvers._dispatch import dense as dense
from celtstone.solvers._dispatch import dense_arrays as dense_arrays
from celtstone.solvers._dispatch import interpolate as interpolate
from celtstone.solvers._dispatch import is_known as is_known
from celtstone.solvers._dispatch import start as start
from celtstone.solvers._dispatch import thread_dense_arrays as thread_dense_arrays
from celtstone.solvers._dispatch import thread_workspaces as thread_workspaces
from celtstone.solvers._dispatch import workspaces as workspaces


@kernel
def error_order(method):
    """``ERROR_ORDER`` of the method (contract item 3); -1 for an unknown code."""
    return constants(method)[0]


@inlined
def dense_every_step(method):
    """``DENSE_EVERY_STEP`` of the method (contract item 7); True for an unknown code."""
    return constants(method)[1]


@kernel
def interpolate_apart(method, dense, y_old, x, out):
    """:func:`interpolate` as a function of its own, for the driver's samples and stop and
    the events' root search: inlined, each of them held every method's interpolant
    (which method took a step is known only then), in the run loop too."""
    interpolate(method, dense, y_old, x, out)
