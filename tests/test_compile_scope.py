"""A first run compiles what it needs: the run loop per model and method, with the other
codes' branches removed before typing (``kernels._pruning``, ``solvers.driver``).

Each check runs in a new process with an empty numba cache, as a user's first run does,
and lists what numba compiled there (its "numba:compile" event fires on a cache miss
only)."""

from __future__ import annotations

import io
import json
import os
import sys
from pathlib import Path

import numba
import pytest

from celtstone.kernels import _jit
from celtstone.solvers.codes import METHODS
from celtstone.solvers.driver import MODEL_AND_METHOD
from tests.processes import python_in_new_process

_LISTING = """
import json, sys
from numba.core import event

compiled = []


class Listing(event.Listener):
    def on_start(self, ev):
        function = ev.data["dispatcher"].py_func
        types = [str(t) for t in ev.data["args"]]
        compiled.append([function.__module__ + "." + function.__qualname__, types])

    def on_end(self, ev):
        pass


event.register("numba:compile", Listing())
"""

# kernels only the sliding model, the stick phase, or another method than vern9 calls
SLIDING_OR_STICK = (
    "celtstone.kernels.dynamics.sliding_acceleration",
    "celtstone.kernels.stick.stick_acceleration",
    "celtstone.kernels.friction.contact_friction",
    "celtstone.kernels.friction.pade_disk_friction",
    "celtstone.solvers.phases.run_phases",
)
OTHER_METHODS = ("celtstone.solvers._radau.", "celtstone.solvers._dop853.")
# what only the exact friction law or the elliptic contact compiles
NOT_THE_PADE_DISK = (
    "celtstone.kernels.friction_exact.",
    "celtstone.kernels.friction_ellipse.",
    "celtstone.kernels.hertz_ellipse.",
    "celtstone.kernels.stick_ellipse.",
)
OTHER_SHAPES = (
    "celtstone.kernels.implicit.",
    "celtstone.kernels.geometry.paraboloid_contact",
    "celtstone.kernels.geometry.superellipsoid_contact",
)


def _compiled_in_new_process(code: str, cache: Path) -> list[list[object]]:
    """What numba compiles while ``code`` runs in a new process on the empty cache ``cache``."""
    script = _LISTING + code + "\nprint(json.dumps(compiled))\n"
    environment = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    lines = python_in_new_process(["-c", script], environment, timeout=1800)
    listing: list[list[object]] = json.loads(lines[-1])
    return listing


def test_the_diagnostics_of_a_rolling_run_compile_no_other_model(tmp_path: Path) -> None:
    """The derived columns of a rolling run (``solvers.derived.derived_series``) compile the
    rolling equations and not the sliding or stick ones, which the same kernels hold in
    branches on the model code."""
    code = """
import numpy as np
import celtstone as cs
from celtstone.kernels import layout, system
from celtstone.solvers.derived import derived_series
from celtstone.simulation.models import RollingModel, kernel_parameters

body = cs.load_body("kane_levinson_1982")
params = kernel_parameters(RollingModel(), body)
state = np.zeros(layout.N_STATE)
state[layout.Y_N + 2] = 1.0
state[layout.Y_QUAT] = 1.0
out = np.empty((1, system.N_DIAGNOSTICS))
derived_series(layout.MODEL_ROLLING, state[None, :], params, out)
"""
    names = [name for name, _ in _compiled_in_new_process(code, tmp_path)]
    assert "celtstone.kernels.dynamics.rolling_acceleration" in names
    assert not set(SLIDING_OR_STICK) & set(names), names


@pytest.mark.slow
def test_a_first_rolling_run_compiles_only_the_rolling_model_and_its_method(
    tmp_path: Path,
) -> None:
    """A first rolling run (vern9, its summary) compiles one run loop, for the rolling
    model and vern9 as constants, one right-hand side, for the rolling model, and none of
    the sliding model's, the stick phase's or the other methods' steps."""
    code = """
import celtstone as cs

body = cs.load_body("kane_levinson_1982")
state = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
cs.simulate(cs.RollingModel(), body, state, 0.01, n_samples=3).summary()
"""
    compiled = _compiled_in_new_process(code, tmp_path)
    names = [name for name, _ in compiled]
    loops = [types for name, types in compiled if name == "celtstone.solvers.driver.integrate"]
    assert loops == [["Literal[int](0)", "Literal[int](3)", *loops[0][2:]]], (
        "the run loop compiled once, for the rolling model (0) and vern9 (3)"
    )
    assert not set(SLIDING_OR_STICK) & set(names), names
    # the right-hand side, called at its address (``solvers._system``), compiled once,
    # for the rolling model as a constant: never for every code by a call site's typing
    evaluated = [types for name, types in compiled if name == "celtstone.kernels.system.evaluate"]
    assert [types[0] for types in evaluated] == ["Literal[int](0)"], evaluated
    # nothing of another method, not even its (empty) workspace: the loop for vern9 as a
    # constant holds vern9's workspace alone (``driver.run_workspaces``)
    steps = [name for name in names if name.startswith(OTHER_METHODS)]
    assert not steps, steps
    assert "celtstone.solvers._dispatch.workspaces" not in names, names
    # the summary and the derived columns call the run's right-hand side at its link:
    # nothing of it is compiled again for them
    assert "celtstone.kernels.system.spin_and_normal_force" not in names, names
    # every method's interpolant in one function, compiled once (no copy per call site)
    assert names.count("celtstone.solvers._methods.interpolate_apart") == 1, names


@pytest.mark.slow
def test_a_first_sliding_run_compiles_only_the_sliding_model(tmp_path: Path) -> None:
    """A first sliding run with auto compiles one run loop, for the sliding model as a
    constant and the method a value (``driver.integrate_link``), and one right-hand side,
    for the sliding model, Zhuravlev's Padé law, the disk and the ellipsoid as constants
    (``_system.RUN_CODES``): none of the rolling or stick models' equations, the exact
    law's, the elliptic contact's or another body shape's, and the law's functions
    once."""
    code = """
import celtstone as cs

inside = []  # what compiles while the right-hand side compiles: its callees


class Inside(event.Listener):
    depth = 0

    def on_start(self, ev):
        function = ev.data["dispatcher"].py_func
        name = function.__module__ + "." + function.__qualname__
        if self.depth:
            inside.append(name)
        self.depth += name == "celtstone.kernels.system.evaluate"

    def on_end(self, ev):
        function = ev.data["dispatcher"].py_func
        name = function.__module__ + "." + function.__qualname__
        self.depth -= name == "celtstone.kernels.system.evaluate"


event.register("numba:compile", Inside())
body = cs.load_body("kane_levinson_1982")
state = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
cs.simulate(cs.SlidingModel(0.3, 1e-3), body, state, 0.01, n_samples=3).summary()
compiled.append(["inside evaluate", inside])
"""
    compiled = _compiled_in_new_process(code, tmp_path)
    names = [name for name, _ in compiled]
    loops = [types for name, types in compiled if name == "celtstone.solvers.driver.integrate"]
    assert loops == [["Literal[int](1)", "int64", *loops[0][2:]]], (
        "the run loop compiled once, for the sliding model (1), the method a value"
    )
    evaluated = [types for name, types in compiled if name == "celtstone.kernels.system.evaluate"]
    assert [types[0] for types in evaluated] == ["Literal[int](1)"], evaluated
    assert "celtstone.kernels.dynamics.rolling_acceleration" not in names
    assert "celtstone.kernels.stick.stick_acceleration" not in names
    assert names.count("celtstone.kernels.friction.law_functions") == 1, names
    # the right-hand side for the run's friction law, pressure, contact shape and body
    # shape as constants (``_system.RUN_CODES``): its record type names their values
    codes = "{friction_law=0,contact_pressure=0,contact_shape=0,shape_code=0}"
    assert [types[2].endswith(codes) for types in evaluated] == [True], evaluated
    # neither the exact law nor the elliptic contact is compiled at all
    elsewhere = [name for name in names if name.startswith(NOT_THE_PADE_DISK)]
    assert not elsewhere, elsewhere
    # the right-hand side's compile holds the ellipsoid's contact point and no other
    # shape's (the derived columns' contact point reads the shape code as a value)
    inside = next(types for name, types in compiled if name == "inside evaluate")
    assert "celtstone.kernels.geometry.ellipsoid_contact" in inside, inside
    assert not [name for name in inside if name.startswith(OTHER_SHAPES)], inside


@pytest.mark.slow
@pytest.mark.skipif(not MODEL_AND_METHOD, reason="numba's own compiler: one loop for all")
def test_after_celtstone_compile_a_rolling_run_takes_its_own_loop_or_compiles_nothing(
    tmp_path: Path,
) -> None:
    """On an empty cache, ``celtstone compile`` compiles the loop for every code and the
    rolling model's own loop for vern9. Then a rolling run with vern9 takes its own loop
    (faster warm), and one with dop853, whose own loop is not compiled, takes the loop
    for every code (``driver.integrate_link``): neither compiles anything."""
    code = """
import celtstone as cs
from celtstone.solvers import _linking, driver
from celtstone.solvers import run as solver_run

cs.compile_solvers()
compiled.clear()  # what the runs below compile
taken = []
real = solver_run.integrate_link


def spy(arguments, *rest, **options):
    link, to_rhs = real(arguments, *rest, **options)
    every_code = _linking.cached_link_to(driver.integrate, (*arguments, _linking.NO_LINK))
    own = _linking.made_link(
        driver.integrate, (*arguments, _linking.NO_LINK), driver.MODEL_AND_METHOD
    )
    taken.append([int(arguments[1]), link == own, link == every_code])
    return link, to_rhs


solver_run.integrate_link = spy
body = cs.load_body("kane_levinson_1982")
state = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
for method in ("vern9", "dop853"):
    cs.simulate(cs.RollingModel(), body, state, 0.01, method=method, n_samples=3).summary()
compiled.append(["taken", taken])
"""
    compiled = _compiled_in_new_process(code, tmp_path)
    taken = compiled.pop()
    assert compiled == [], "a run after celtstone compile compiled"
    vern9, dop853 = METHODS["vern9"], METHODS["dop853"]
    assert taken == ["taken", [[vern9, True, False], [dop853, False, True]]]


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_a_compile_inside_a_run_says_what_it_compiles(monkeypatch: pytest.MonkeyPatch) -> None:
    """The run loop's compile names its model and method and about how long, once per
    subject, on a terminal (``kernels._jit.compiling``)."""
    stream = _Terminal()
    monkeypatch.setattr(sys, "stderr", stream)
    monkeypatch.setattr(_jit.COMPILING, "subjects_shown", set())

    def probe(x: float) -> float:
        return 3.0 * x

    probe.__module__ = "celtstone.solvers.probe"
    with _jit.compiling("the rolling model with vern9", 35.0):
        numba.njit(probe)(1.0)
        numba.njit(probe)(2.0)  # the same subject: said once
    line = _jit.compiling_notice("the rolling model with vern9", 35.0)
    assert stream.getvalue() == line + "\n"
    assert line.startswith("celtstone: compiling the rolling model with vern9, about 35 s, once")


def test_a_branch_decided_by_the_callers_code_is_never_inlined() -> None:
    """The inliner goes one call level at a time (``kernels._pruning.InlineOnePerLevel``):
    a dispatcher inlined with a constant code has its other branches removed before the
    calls inside them are inlined, so a callee only a dead branch calls is never made
    into IR, as the run loop's method dispatcher must not copy every method's step."""
    from numba import njit

    from celtstone.kernels import _pruning

    @njit(inline="always")
    def add_one(x):
        return x + 1.0

    @njit(inline="always")
    def double(x):
        return 2.0 * x

    @njit(inline="always")
    def dispatch(code, x):
        if code == 0:
            return add_one(x)
        return double(x)

    @njit(pipeline_class=_pruning.CodePruningCompiler)
    def with_code_zero(x):
        return dispatch(0, x)

    assert with_code_zero(3.0) == 4.0
    made = {function for function, _ in _pruning._CALLEE_IR}
    assert dispatch.py_func in made and add_one.py_func in made
    assert double.py_func not in made, "the dead branch's callee was inlined"
