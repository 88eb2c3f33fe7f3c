"""The compiled dispatch from a method code to its module: GENERATED from the method
registry ``solvers.codes.METHOD_ENTRIES`` by ``solvers._generate``. Do not edit; after
changing the registry, run ``python src/celtstone/solvers/_generate.py``.

The contract each function serves is written in ``solvers._methods``, which hands these
names on. One branch per registered code and no default: an unknown code returns
``STATUS_UNKNOWN_CODE`` (``attempt``) or NaN, never another method's result.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from celtstone.kernels._jit import kernel
from celtstone.kernels.layout import RHS_UNKNOWN_CODE
from celtstone.solvers import _auto as auto
from celtstone.solvers import _dop853 as dop853
from celtstone.solvers import _radau as radau5
from celtstone.solvers import _vern9 as vern9
from celtstone.solvers._compile import inlined
from celtstone.solvers.codes import (
    STATUS_SUCCESS,
    STATUS_UNKNOWN_CODE,
)

# the registered codes (``codes.METHOD_ENTRIES``)
METHOD_DOP853 = 0
METHOD_RADAU5 = 1
METHOD_AUTO = 2
METHOD_VERN9 = 3

# for Python: code -> the method's module
MODULES = {
    METHOD_DOP853: dop853,
    METHOD_RADAU5: radau5,
    METHOD_AUTO: auto,
    METHOD_VERN9: vern9,
}


class Workspaces(NamedTuple):
    """One workspace per registered method, in code order; only those the run uses are
    sized to the state (a switching method's too); a switching method's is its
    switching record."""

    dop853: dop853.Workspace
    radau5: radau5.Workspace
    auto: np.ndarray
    vern9: vern9.Workspace


@kernel
def is_known(method):
    """Whether ``method`` is a registered method code."""
    return (
        method == METHOD_DOP853
        or method == METHOD_RADAU5
        or method == METHOD_AUTO
        or method == METHOD_VERN9
    )


@kernel
def workspaces(method, n):
    """Workspaces for a run of ``method`` on states of length n (the others empty)."""
    switching = method == METHOD_AUTO
    return Workspaces(
        dop853.workspace(n if method == METHOD_DOP853 or switching else 0),
        radau5.workspace(n if method == METHOD_RADAU5 or switching else 0),
        auto.workspace(),
        vern9.workspace(n if method == METHOD_VERN9 else 0),
    )


@inlined
def constants(method):
    """(``ERROR_ORDER``, ``DENSE_EVERY_STEP``) of the method (contract items 3 and 7);
    (-1, True) for an unknown code."""
    if method == METHOD_DOP853:
        return dop853.ERROR_ORDER, dop853.DENSE_EVERY_STEP
    if method == METHOD_RADAU5:
        return radau5.ERROR_ORDER, radau5.DENSE_EVERY_STEP
    if method == METHOD_AUTO:
        return auto.ERROR_ORDER, auto.DENSE_EVERY_STEP
    if method == METHOD_VERN9:
        return vern9.ERROR_ORDER, vern9.DENSE_EVERY_STEP
    return -1, True


@inlined
def active(method, switching):
    """The code of the method that takes the next step: ``method`` itself, or for a
    switching method the one its switching record ``switching`` names."""
    if method == METHOD_AUTO:
        return switching[0].active
    return method


@inlined
def start(method, model, params, t, y, f, h, controls, work, stats):
    """The method's ``start`` (contract item 5); a switching method's also checks its
    choice against the first step h [s] (``auto``: a run that starts stiff starts with
    Radau)."""
    if method == METHOD_DOP853:
        dop853.start(model, params, t, y, f, controls, work.dop853, stats)
    elif method == METHOD_RADAU5:
        radau5.start(model, params, t, y, f, controls, work.radau5, stats)
    elif method == METHOD_AUTO:
        auto.start(work.auto, model, params, t, y, f, h, controls, work, stats)
    elif method == METHOD_VERN9:
        vern9.start(model, params, t, y, f, controls, work.vern9, stats)


@inlined
def attempt(method, stepper, model, params, t, y, f, h, t_end, controls, work, y_new, f_new, stats):
    """The ``attempt`` (contract item 6) of ``stepper``, the method that takes the step
    (``active``): (status, h_taken, h_next, rhs status, normal force [N]); a switching
    ``method`` notes the steps of the methods its ``notes_steps_of`` names."""
    if stepper == METHOD_DOP853:
        result = dop853.attempt(
            model, params, t, y, f, h, t_end, controls, work.dop853, y_new, f_new, stats
        )
        if method == METHOD_AUTO and result[0] == STATUS_SUCCESS:
            auto.note_explicit_step(work.auto, work.dop853, y_new, result[1])
        return result
    if stepper == METHOD_RADAU5:
        return radau5.attempt(
            model, params, t, y, f, h, t_end, controls, work.radau5, y_new, f_new, stats
        )
    if stepper == METHOD_VERN9:
        return vern9.attempt(
            model, params, t, y, f, h, t_end, controls, work.vern9, y_new, f_new, stats
        )
    return STATUS_UNKNOWN_CODE, h, h, RHS_UNKNOWN_CODE, np.nan


@inlined
def after_step(method, model, params, t, y, f, h_next, controls, work, stats):
    """Between accepted steps, at the new (t, y) with f = f(t, y) and the next step size
    h_next [s]: a switching method may switch the method that takes it; the others do
    nothing."""
    if method == METHOD_AUTO:
        auto.after_step(work.auto, model, params, t, y, f, h_next, controls, work, stats)


@inlined
def dense(method, model, params, t, y, y_new, h, work, stats):
    """The method's ``dense`` (contract item 7)."""
    if method == METHOD_DOP853:
        dop853.dense(model, params, t, y, y_new, h, work.dop853, stats)
    elif method == METHOD_RADAU5:
        radau5.dense(model, params, t, y, y_new, h, work.radau5, stats)
    elif method == METHOD_VERN9:
        vern9.dense(model, params, t, y, y_new, h, work.vern9, stats)


@inlined
def dense_arrays(work):
    """Every method's interpolant coefficients ``work.<method>.dense`` (contract item 7),
    indexed by method code; an empty array at a code that takes no steps itself."""
    return (work.dop853.dense, work.radau5.dense, np.zeros((0, 0)), work.vern9.dense)


@inlined
def interpolate(method, dense, y_old, x, out):
    """The method's ``interpolate`` (contract item 7); NaN for an unknown code."""
    if method == METHOD_DOP853:
        dop853.interpolate(dense, y_old, x, out)
    elif method == METHOD_RADAU5:
        radau5.interpolate(dense, y_old, x, out)
    elif method == METHOD_VERN9:
        vern9.interpolate(dense, y_old, x, out)
    else:
        out[:] = np.nan


@inlined
def thread_workspaces(explicit, radau, switching):
    """A sweep's GPU thread's :class:`Workspaces` (``batch_cuda``) from its three: the
    explicit methods' shared one, Radau's and the switching record, as each entry's
    ``gpu`` says; a method the GPU does not run holds the explicit one, never read."""
    return Workspaces(explicit, radau, switching, explicit)


@inlined
def thread_dense_arrays(explicit_dense, radau_dense):
    """A GPU thread's interpolant arrays by method code, as :func:`dense_arrays`."""
    return (explicit_dense, radau_dense, explicit_dense, explicit_dense)
