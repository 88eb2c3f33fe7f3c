"""The right-hand side as the run loop reaches it: compiled once, called at its address.

The run loop ``driver.integrate`` and everything it calls receive the run's *system*,
the pair (kernel parameter record, ``rhs_link``), where the methods' contract says
``params`` (``_methods``, item 2: opaque to them, passed on to :func:`rhs`).
:func:`rhs` calls ``kernels.system.evaluate`` at the address ``rhs_link``
(``_linking``): compiled for the model code and the record's ``RUN_CODES`` (friction
law, pressure, contact and body shape) as constants in a loop compiled for one model
(``driver.integrate_link``: a first run's), for every code in the loop for every code
and a sweep whose points differ in those codes (:func:`rhs_link` makes them, Python
side).

numba links each callee's code into its caller and optimises and generates machine
code for the whole again; with ``kernels.system.rhs`` inlined, the right-hand side of
every model, with its friction laws, contact shapes and the implicit-surface solver,
was compiled again in every step, event and start function of every method and in the
loop itself (docs/decisions.md, "Cold start"). The results are the same to the last
bit: the same function, compiled with the same flags, in a compile unit of its own.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import types

from celtstone.kernels import system as physics
from celtstone.kernels.layout import N_STATE, Y_N, Y_OMEGA, ModelCode
from celtstone.solvers._compile import inlined
from celtstone.solvers._linking import address_call, cached_link_to, link_to, made_link

# ``evaluate``'s return type in numba: (status, normal force, friction power, friction
# force). Given, typing a call compiles nothing: a call site passes the model code as a
# plain int even where it is a constant, and would compile ``evaluate`` for every code.
EVALUATE_RETURNS = types.Tuple((types.int64, types.float64, types.float64, types.float64))
call_evaluate = address_call(physics.evaluate, returns=EVALUATE_RETURNS)


# The parameter record's codes that a run's right-hand side is compiled for as constants
# (``kernels._pruning.CodedRecord``): only the run's friction law, contact pressure,
# contact shape and body shape compile, where the codes as values compiled every law
# (the exact law's series), the elliptic contact (its spline table, the Hertz ellipse)
# and every body shape (the implicit surface's Newton solve). A sweep whose points
# differ in one of them, the stick–slip loop and the loop for every code read them from
# the record.
RUN_CODES = ("friction_law", "contact_pressure", "contact_shape", "shape_code")


def rhs_link(params: Any, model: int | None = None, codes: bool = False) -> tuple[int, int]:
    """The link to ``kernels.system.evaluate`` for the parameter record ``params``, as
    :func:`rhs` calls it: compiled for ``model`` as a constant (a loop compiled for one
    model), or for every model code (None); with ``codes``, ``params``' ``RUN_CODES``
    as constants too (a loop for one model). Python side, compiles it or loads it from
    numba's cache."""
    return link_to(physics.evaluate, *_rhs_version(params, model, codes))


def cached_rhs_link(
    params: Any, model: int | None = None, codes: bool = False
) -> tuple[int, int] | None:
    """:func:`rhs_link` if that version is compiled in this process or in numba's cache,
    else None: nothing is compiled."""
    return cached_link_to(physics.evaluate, *_rhs_version(params, model, codes))


def _rhs_version(
    params: Any, model: int | None, codes: bool
) -> tuple[tuple[Any, ...], tuple[int, ...], tuple[str, ...]]:
    """(arguments, constants, fields) of :func:`rhs_link`'s version of ``evaluate``."""
    state = np.zeros(N_STATE)
    if model is None:
        return (0, state, params, state), (), ()
    return (int(model), state, params, state), (0,), RUN_CODES if codes else ()


def samples_rhs_link(params: Any, model: int) -> tuple[int, int]:
    """The link to ``kernels.system.evaluate`` for a finished run's samples (its derived
    columns and summary): the one a run of ``model`` on ``params`` made in this process
    (:func:`rhs_link` for the model and the record's codes as constants, for the model
    alone, else for every code), which compiles nothing; else :func:`rhs_link` for
    ``model`` and its codes (for every code if it is no model code). Python side."""
    state = np.zeros(N_STATE)
    model = int(model)
    arguments = (model, state, params, state)
    for constants, fields in (((0,), RUN_CODES), ((0,), ()), ((), ())):
        link = made_link(physics.evaluate, arguments, constants, fields)
        if link is not None:
            return link
    known = model in {int(code) for code in ModelCode}
    return rhs_link(params, model, codes=True) if known else rhs_link(params)


@inlined
def parameters(system):
    """The kernel parameter record of the run's ``system``."""
    return system[0]


@inlined
def rhs(model, t, y, system, dy):
    """``kernels.system.rhs`` of the run's ``system`` (at its link): fills ``dy`` with
    dy/dt; returns (right-hand-side status, normal force [N])."""
    status, normal_force, _, _ = call_evaluate(system[1], (model, y, system[0], dy))
    return status, normal_force


@inlined
def spin_and_normal_force(model, y, system, work):
    """``kernels.system.spin_and_normal_force`` of the run's ``system`` (at its link):
    spin ω · n [rad/s], normal force N [N], right-hand-side status; ``work`` is scratch."""
    status, normal_force, _, _ = call_evaluate(system[1], (model, y, system[0], work))
    spin = y[Y_OMEGA] * y[Y_N] + y[Y_OMEGA + 1] * y[Y_N + 1] + y[Y_OMEGA + 2] * y[Y_N + 2]
    return spin, normal_force, status
