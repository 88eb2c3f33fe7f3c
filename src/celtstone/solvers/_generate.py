"""Writes ``solvers/_dispatch.py``, the compiled dispatch on a method code, from the method
registry ``codes.METHOD_ENTRIES``.

numba compiles a branch per code, not a loop over a registry, and caches only functions
that live in a file: the dispatch is therefore Python source, generated from the entries
and checked in. After adding or changing an entry, run from the repository's root::

    python src/celtstone/solvers/_generate.py

``tests/test_method_registry.py`` fails, naming that command, while the checked-in file
differs from what the registry gives. Run as a script, it reads ``codes.py`` as a file
of its own and imports nothing of celtstone, so it also mends a dispatch that no longer
imports (a method module renamed); nothing here runs when celtstone is imported.

Each generated function has one branch per registered code and no default branch: an
unknown code returns ``STATUS_UNKNOWN_CODE`` (``attempt``), -1 (``error_order``) or NaN
(``interpolate``), never another method's result. A method whose steps the others take
(``Method.switches_among``, ``auto``) gets the switching forms of ``start``, ``active``
and ``after_step``; the driver hands it one switching record, so at most one method of
the registry switches.
"""

from __future__ import annotations

import importlib.util
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

if TYPE_CHECKING:
    from celtstone.solvers.codes import Method

TARGET = Path(__file__).with_name("_dispatch.py")
COMMAND = "python src/celtstone/solvers/_generate.py"

_HEADER = f'''"""The compiled dispatch from a method code to its module: GENERATED from the method
registry ``solvers.codes.METHOD_ENTRIES`` by ``solvers._generate``. Do not edit; after
changing the registry, run ``{COMMAND}``.

The contract each function serves is written in ``solvers._methods``, which hands these
names on. One branch per registered code and no default: an unknown code returns
``STATUS_UNKNOWN_CODE`` (``attempt``) or NaN, never another method's result.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from celtstone.kernels._jit import kernel
from celtstone.kernels.layout import RHS_UNKNOWN_CODE
'''

# a GPU thread's workspaces (``batch_cuda._thread_arrays``) -> the workspace and the
# interpolant's array each ``Method.gpu`` takes; a method the GPU does not run ("") holds
# the explicit one, never read: a thread's method code is a constant of its kernel, so
# no branch of that method is compiled there
_GPU_WORKSPACES = {
    "explicit": ("explicit", "explicit_dense"),
    "radau": ("radau", "radau_dense"),
    "switching": ("switching", "explicit_dense"),
    "": ("explicit", "explicit_dense"),
}

_PASS = "    pass\n"  # the body of a dispatch with no branch
_STEP_ARGUMENTS = "model, params, t, y, f, h, t_end, controls, work.{alias}, y_new, f_new, stats"


def _constant(name: str) -> str:
    return f"METHOD_{name.upper()}"


def _check(entries: Mapping[str, Method]) -> None:
    """Refuse a registry the dispatch cannot serve, naming what is wrong."""
    codes = sorted(entry.code for entry in entries.values())
    if codes != list(range(len(entries))):
        raise ValueError(f"method codes must be 0 .. {len(entries) - 1}, each once: {codes}")
    for name, entry in entries.items():
        if not name.isidentifier():
            raise ValueError(f"method name {name!r} is not a Python identifier")
        for other in (*entry.switches_among, *entry.notes_steps_of):
            if other not in entries or entries[other].switches_among:
                raise ValueError(f"{name}: {other!r} is not a registered stepping method")
        if entry.gpu not in _GPU_WORKSPACES:
            raise ValueError(f"{name}: gpu {entry.gpu!r} is not one of {sorted(_GPU_WORKSPACES)}")
        if entry.gpu and (entry.gpu == "switching") != bool(entry.switches_among):
            raise ValueError(f"{name}: gpu 'switching' is a switching method's, and only its")
    switching = [name for name, entry in entries.items() if entry.switches_among]
    if len(switching) > 1:
        raise ValueError(f"the driver hands one switching record; switching methods: {switching}")


class _Registry(NamedTuple):
    """The entries as the generated functions need them, in code order."""

    ordered: list[tuple[str, Method]]
    steppers: list[tuple[str, Method]]  # the methods that take steps themselves
    switchers: list[tuple[str, Method]]  # those whose steps the others take (auto)
    covered: set[str]  # the steppers a switching method takes steps with


def _branches(lines: list[str], keyword_chain: bool) -> str:
    """``lines`` joined; with ``keyword_chain`` every ``if`` but the first an ``elif``."""
    if keyword_chain:
        lines = [lines[0]] + [line.replace("    if ", "    elif ", 1) for line in lines[1:]]
    return "".join(lines)


def _preamble(entries: Mapping[str, Method], r: _Registry) -> str:
    """The imports (each method's module under its name: ``dop853.attempt``), the codes
    and ``MODULES``."""
    lines = [_HEADER]
    for name, entry in sorted(entries.items(), key=lambda item: item[1].module):
        package, module = entry.module.rsplit(".", 1)
        lines.append(f"from {package} import {module} as {name}\n")
    lines.append("from celtstone.solvers._compile import inlined\n")
    lines.append("from celtstone.solvers.codes import (\n")
    lines.append("    STATUS_SUCCESS,\n    STATUS_UNKNOWN_CODE,\n)\n\n")
    lines.append("# the registered codes (``codes.METHOD_ENTRIES``)\n")
    lines += [f"{_constant(name)} = {entry.code}\n" for name, entry in r.ordered]
    lines.append("\n# for Python: code -> the method's module\nMODULES = {\n")
    lines += [f"    {_constant(name)}: {name},\n" for name, _ in r.ordered]
    lines.append("}\n")
    return "".join(lines)


def _workspaces(r: _Registry) -> str:
    """``Workspaces``, ``is_known`` and ``workspaces``."""
    fields = "".join(
        f"    {name}: {'np.ndarray' if entry.switches_among else name + '.Workspace'}\n"
        for name, entry in r.ordered
    )
    known = "".join(f"        or method == {_constant(name)}\n" for name, _ in r.ordered)
    sizes = []
    for name, entry in r.ordered:
        if entry.switches_among:
            sizes.append(f"        {name}.workspace(),\n")
        else:
            switched = " or switching" if name in r.covered else ""
            sizes.append(
                f"        {name}.workspace(n if method == {_constant(name)}{switched} else 0),\n"
            )
    switching = "".join(f"    switching = method == {_constant(name)}\n" for name, _ in r.switchers)
    return f'''

class Workspaces(NamedTuple):
    """One workspace per registered method, in code order; only those the run uses are
    sized to the state (a switching method's too); a switching method's is its
    switching record."""

{fields}

@kernel
def is_known(method):
    """Whether ``method`` is a registered method code."""
    return (
        {known[11:]}    )


@kernel
def workspaces(method, n):
    """Workspaces for a run of ``method`` on states of length n (the others empty)."""
{switching}    return Workspaces(
{"".join(sizes)}    )
'''


def _constants(r: _Registry) -> str:
    """``constants``: each method's ``ERROR_ORDER`` and ``DENSE_EVERY_STEP``."""
    returns = "".join(
        f"    if method == {_constant(name)}:\n"
        f"        return {name}.ERROR_ORDER, {name}.DENSE_EVERY_STEP\n"
        for name, _ in r.ordered
    )
    return f'''

@inlined
def constants(method):
    """(``ERROR_ORDER``, ``DENSE_EVERY_STEP``) of the method (contract items 3 and 7);
    (-1, True) for an unknown code."""
{returns}    return -1, True
'''


def _switching(r: _Registry) -> str:
    """``active`` and ``start``."""
    active = "".join(
        f"    if method == {_constant(name)}:\n        return switching[0].active\n"
        for name, _ in r.switchers
    )
    starts = []
    for name, entry in r.ordered:
        if entry.switches_among:
            call = f"{name}.start(work.{name}, model, params, t, y, f, h, controls, work, stats)"
        else:
            call = f"{name}.start(model, params, t, y, f, controls, work.{name}, stats)"
        starts.append(f"    if method == {_constant(name)}:\n        {call}\n")
    return f'''

@inlined
def active(method, switching):
    """The code of the method that takes the next step: ``method`` itself, or for a
    switching method the one its switching record ``switching`` names."""
{active}    return method


@inlined
def start(method, model, params, t, y, f, h, controls, work, stats):
    """The method's ``start`` (contract item 5); a switching method's also checks its
    choice against the first step h [s] (``auto``: a run that starts stiff starts with
    Radau)."""
{_branches(starts, keyword_chain=True)}'''


def _attempt(r: _Registry) -> str:
    """``attempt`` and ``after_step``."""
    attempts = []
    for name, _ in r.steppers:
        call = f"{name}.attempt(\n            {_STEP_ARGUMENTS.format(alias=name)}\n        )\n"
        noting = [switcher for switcher, entry in r.switchers if name in entry.notes_steps_of]
        if not noting:
            attempts.append(f"    if stepper == {_constant(name)}:\n        return {call}")
            continue
        text = f"    if stepper == {_constant(name)}:\n        result = {call}"
        for switcher in noting:
            text += (
                f"        if method == {_constant(switcher)} and result[0] == STATUS_SUCCESS:\n"
                f"            {switcher}.note_explicit_step(work.{switcher}, work.{name}, "
                "y_new, result[1])\n"
            )
        attempts.append(text + "        return result\n")
    after = "".join(
        f"    if method == {_constant(name)}:\n"
        f"        {name}.after_step(work.{name}, model, params, t, y, f, h_next, controls, "
        "work, stats)\n"
        for name, _ in r.switchers
    )
    return f'''

@inlined
def attempt(method, stepper, model, params, t, y, f, h, t_end, controls, work, y_new, f_new, stats):
    """The ``attempt`` (contract item 6) of ``stepper``, the method that takes the step
    (``active``): (status, h_taken, h_next, rhs status, normal force [N]); a switching
    ``method`` notes the steps of the methods its ``notes_steps_of`` names."""
{"".join(attempts)}    return STATUS_UNKNOWN_CODE, h, h, RHS_UNKNOWN_CODE, np.nan


@inlined
def after_step(method, model, params, t, y, f, h_next, controls, work, stats):
    """Between accepted steps, at the new (t, y) with f = f(t, y) and the next step size
    h_next [s]: a switching method may switch the method that takes it; the others do
    nothing."""
{after or _PASS}'''


def _dense(r: _Registry) -> str:
    """``dense``, ``dense_arrays`` and ``interpolate``."""
    denses = [
        f"    if method == {_constant(name)}:\n"
        f"        {name}.dense(model, params, t, y, y_new, h, work.{name}, stats)\n"
        for name, _ in r.steppers
    ]
    arrays = ", ".join(
        "np.zeros((0, 0))" if entry.switches_among else f"work.{name}.dense"
        for name, entry in r.ordered
    )
    interpolants = [
        f"    if method == {_constant(name)}:\n        {name}.interpolate(dense, y_old, x, out)\n"
        for name, _ in r.steppers
    ]
    return f'''

@inlined
def dense(method, model, params, t, y, y_new, h, work, stats):
    """The method's ``dense`` (contract item 7)."""
{_branches(denses, keyword_chain=True)}

@inlined
def dense_arrays(work):
    """Every method's interpolant coefficients ``work.<method>.dense`` (contract item 7),
    indexed by method code; an empty array at a code that takes no steps itself."""
    return ({arrays})


@inlined
def interpolate(method, dense, y_old, x, out):
    """The method's ``interpolate`` (contract item 7); NaN for an unknown code."""
{_branches(interpolants, keyword_chain=True)}    else:
        out[:] = np.nan
'''


def _gpu(r: _Registry) -> str:
    """``thread_workspaces`` and ``thread_dense_arrays``, for a GPU thread."""
    thread_work = ", ".join(_GPU_WORKSPACES[entry.gpu][0] for _, entry in r.ordered)
    thread_dense = ", ".join(_GPU_WORKSPACES[entry.gpu][1] for _, entry in r.ordered)
    return f'''

@inlined
def thread_workspaces(explicit, radau, switching):
    """A sweep's GPU thread's :class:`Workspaces` (``batch_cuda``) from its three: the
    explicit methods' shared one, Radau's and the switching record, as each entry's
    ``gpu`` says; a method the GPU does not run holds the explicit one, never read."""
    return Workspaces({thread_work})


@inlined
def thread_dense_arrays(explicit_dense, radau_dense):
    """A GPU thread's interpolant arrays by method code, as :func:`dense_arrays`."""
    return ({thread_dense})
'''


def dispatch_source(entries: Mapping[str, Method]) -> str:
    """The source of ``solvers/_dispatch.py`` for the registry ``entries``."""
    _check(entries)
    ordered = sorted(entries.items(), key=lambda item: item[1].code)
    r = _Registry(
        ordered,
        [(name, entry) for name, entry in ordered if not entry.switches_among],
        [(name, entry) for name, entry in ordered if entry.switches_among],
        {stepper for entry in entries.values() for stepper in entry.switches_among},
    )
    sections = (_workspaces, _constants, _switching, _attempt, _dense, _gpu)
    return _preamble(entries, r) + "".join(section(r) for section in sections)


def registry() -> Mapping[str, Method]:
    """``codes.METHOD_ENTRIES``, read from ``codes.py`` beside this file without importing
    celtstone (whose import needs a dispatch that imports)."""
    name = "_celtstone_method_registry"
    spec = importlib.util.spec_from_file_location(name, Path(__file__).with_name("codes.py"))
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses read the module of a class's annotations
    spec.loader.exec_module(module)
    entries: Mapping[str, Method] = module.METHOD_ENTRIES
    return entries


def main(arguments: list[str]) -> int:
    """Write ``TARGET`` from the registry (``--check``: only say whether it is current)."""
    source = dispatch_source(registry())
    current = TARGET.read_text(encoding="utf-8") if TARGET.exists() else ""
    if "--check" in arguments:
        if source != current:
            print(f"{TARGET} is not the registry's; run: {COMMAND}", file=sys.stderr)
            return 1
        return 0
    if source != current:
        TARGET.write_text(source, encoding="utf-8")
        print(f"wrote {TARGET}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
