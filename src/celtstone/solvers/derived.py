"""The derived columns of a run's samples (``kernels.system.DERIVED``), with the run's
right-hand side.

Each sample's right-hand side is evaluated at the run's link to it (``_system``), as
the run loop calls it: ``kernels.system.evaluate`` linked into the function that fills
the columns was compiled and optimised once more there (docs/decisions.md, "Cold
start"). So what depends on the model here is small (the energy's velocity, the slip
speed), and the columns are compiled once for every model code, the model a value:
a version per model, the code a constant, compiled the right-hand side's branches of
that model alone but linked and optimised them again, once for each model of a run
(a stick–slip run's slip and stick rows).
"""

from __future__ import annotations

from typing import Any

from celtstone.kernels._jit import kernel
from celtstone.kernels.system import derived_columns
from celtstone.solvers._system import call_evaluate, samples_rhs_link


@kernel
def derived_rows(model, ys, system, out):
    """The derived columns of every row of ``ys`` (shape (k, N_STATE)) into ``out`` (k,
    N_DIAGNOSTICS) on the run's ``system`` (``_system``: the parameter record and the
    link to its right-hand side)."""
    params = system[0]
    work = ys[0].copy() if ys.shape[0] > 0 else ys.ravel().copy()
    for i in range(ys.shape[0]):
        evaluated = call_evaluate(system[1], (model, ys[i], params, work))
        derived_columns(model, ys[i], params, evaluated, out[i])


def derived_series(model: int, ys: Any, params: Any, out: Any) -> None:
    """The derived columns (``kernels.system.DERIVED``) of every row of ``ys`` (shape (k,
    N_STATE)) into ``out`` (k, N_DIAGNOSTICS).

    Parameters
    ----------
    model : kernel model code (``kernels.layout``); an unknown code gives NaN rows and
        ``evaluate``'s status
    ys : states, shape (k, N_STATE)
    params : the kernel parameter record
    out : filled, shape (k, N_DIAGNOSTICS)
    """
    derived_rows(int(model), ys, (params, samples_rhs_link(params, model)), out)
