"""The compiled drivers call one another at an address (``solvers._linking``): none holds
a copy of another's machine code, and a link to the wrong compiled version is an error,
never a call."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from numba import types as numba_types
from numba.core import event

import celtstone as cs
from celtstone.kernels import layout
from celtstone.simulation import models
from celtstone.solvers import _linking, _system, batch, driver, phases
from celtstone.solvers import _structures as structures
from celtstone.solvers import run as solver_run
from celtstone.solvers.codes import METHODS
from celtstone.sweep import Sweep

KL_START = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))


def _defined_functions(dispatcher: Any) -> set[str]:
    """Names of the functions each compiled version defines (numba's module for linking,
    from its cache or compiled now)."""
    names: set[str] = set()
    for overload in dispatcher.overloads.values():
        module = overload.library._get_module_for_linking()
        names |= {function.name for function in module.functions if not function.is_declaration}
    return names


def test_the_stick_slip_and_sweep_loops_hold_no_copy_of_the_run_loop() -> None:
    """Linked in, the run loop's code was in each of them (2.4–3.1 MB of machine code)."""
    cs.compile_solvers()
    run_loop = "6driver9integrate"  # in numba's mangled names of driver.integrate
    assert any(run_loop in name for name in _defined_functions(driver.integrate))
    for caller in (phases.run_phases, batch._batch):
        defined = _defined_functions(caller)
        assert defined and not any(run_loop in name for name in defined), caller
    assert not any("6phases10run_phases" in name for name in _defined_functions(batch._batch))


def test_the_loop_for_every_code_holds_no_copy_of_the_right_hand_side() -> None:
    """It calls ``kernels.system.evaluate`` at an address (``solvers._system``); linked
    in, every model's equations were compiled again in each method's step, event and
    start function and in the loop."""
    cs.compile_solvers()
    right_hand_side = "6system8evaluate"  # in numba's mangled names of system.evaluate
    every_code = [
        overload
        for types, overload in driver.integrate.overloads.items()
        if not any(isinstance(argument, numba_types.Literal) for argument in types)
    ]
    assert every_code, "compile_solvers compiles the loop for every code"
    for overload in every_code:
        module = overload.library._get_module_for_linking()
        defined = {function.name for function in module.functions if not function.is_declaration}
        assert defined and not any(right_hand_side in name for name in defined)


def _off_by_one(link: tuple[int, int]) -> tuple[int, int]:
    return link[0], link[1] + 1


def _none(link: tuple[int, int]) -> tuple[int, int]:
    return _linking.NO_LINK


@pytest.mark.parametrize("spoil", [_off_by_one, _none], ids=["another-version", "no-link"])
def test_a_stick_slip_run_with_a_wrong_link_raises(
    monkeypatch: pytest.MonkeyPatch, spoil: Callable[[tuple[int, int]], tuple[int, int]]
) -> None:
    real = phases.integrate_links

    def spoiled(*args: Any) -> tuple[tuple[int, int], ...]:
        slip, stick, to_rhs = real(*args)
        return spoil(slip), spoil(stick), to_rhs

    monkeypatch.setattr(solver_run, "integrate_links", spoiled)
    body = cs.load_body("kane_levinson_1982")
    with pytest.raises(RuntimeError, match="integrate: a link to another compiled version"):
        cs.simulate(cs.HybridModel(), body, KL_START, 0.01)


@pytest.mark.parametrize("spoil", [_off_by_one, _none], ids=["another-version", "no-link"])
def test_a_run_with_a_wrong_link_raises(
    monkeypatch: pytest.MonkeyPatch, spoil: Callable[[tuple[int, int]], tuple[int, int]]
) -> None:
    real = driver.integrate_link

    def spoiled(*args: Any) -> tuple[tuple[int, int], tuple[int, int]]:
        link, to_rhs = real(*args)
        return spoil(link), to_rhs

    monkeypatch.setattr(solver_run, "integrate_link", spoiled)
    body = cs.load_body("kane_levinson_1982")
    with pytest.raises(RuntimeError, match="integrate: a link to another compiled version"):
        cs.simulate(cs.RollingModel(), body, KL_START, 0.01)


@pytest.mark.parametrize("spoil", [_off_by_one, _none], ids=["another-version", "no-link"])
def test_a_run_with_a_wrong_link_to_its_right_hand_side_raises(
    monkeypatch: pytest.MonkeyPatch, spoil: Callable[[tuple[int, int]], tuple[int, int]]
) -> None:
    real = driver.integrate_link

    def spoiled(*args: Any) -> tuple[tuple[int, int], tuple[int, int]]:
        link, to_rhs = real(*args)
        return link, spoil(to_rhs)

    monkeypatch.setattr(solver_run, "integrate_link", spoiled)
    body = cs.load_body("kane_levinson_1982")
    with pytest.raises(RuntimeError, match="evaluate: a link to another compiled version"):
        cs.simulate(cs.SlidingModel(), body, KL_START, 0.01)


@pytest.mark.parametrize("hybrid", [True, False], ids=["hybrid", "sliding"])
def test_a_sweep_with_a_wrong_link_raises(monkeypatch: pytest.MonkeyPatch, hybrid: bool) -> None:
    real = batch._links

    def spoiled(*args: Any) -> tuple[Any, ...]:
        to_integrate, to_phases, phase_links = real(*args)
        if hybrid:
            return to_integrate, _off_by_one(to_phases), phase_links
        return (_off_by_one(to_integrate[0]), to_integrate[1]), to_phases, phase_links

    monkeypatch.setattr(batch, "_links", spoiled)
    fixed = {} if hybrid else {"contact": "sliding"}
    sweep = Sweep({"initial_spin": [-5.0]}, fixed=fixed, t_end=0.01)
    assert sweep.is_hybrid is hybrid
    name = "run_phases" if hybrid else "integrate"
    with pytest.raises(RuntimeError, match=f"{name}: a link to another compiled version"):
        sweep.run()


def test_a_batch_without_hybrid_points_links_no_phase_loop() -> None:
    """``_links`` leaves the phase loop unlinked (and so uncompiled) when no point needs
    it, and links it when one does (and the run loop only where a point runs one model)."""
    body = cs.load_body("kane_levinson_1982")
    params = np.array([models.kernel_parameters(cs.SlidingModel(), body)])
    state = models.initial_vector(KL_START)[np.newaxis, :]
    output = structures.new_output(np.linspace(0.0, 0.01, 3), layout.N_STATE, 10)
    log = structures.new_phase_log(3, 10)
    controls = structures.Controls(1e-8, 1e-12, 0.0, 0.0, 1000, True)
    for speed, linked in ((0.0, False), (1e-3, True)):
        speeds = np.full(1, speed)
        points = batch.Points(params, state, np.zeros(1), np.zeros(1), speeds)
        links = batch._links(layout.MODEL_SLIDING, (0, 0), points, 0.01, controls, output, log)
        to_integrate, to_phases, phase_links = links
        assert (to_integrate[0] != _linking.NO_LINK) is not linked  # every point is hybrid
        assert (to_phases != _linking.NO_LINK) is linked
        assert all((link != _linking.NO_LINK) is linked for link in phase_links)


def test_links_are_kept_per_argument_types(monkeypatch: pytest.MonkeyPatch) -> None:
    """``link_to`` types a run's arguments once (a parameter record takes ~0.5 ms to
    type): a second run with arguments of the same types reuses the link."""
    body = cs.load_body("kane_levinson_1982")
    params = models.kernel_parameters(cs.SlidingModel(), body)
    controls = structures.Controls(1e-8, 1e-12, 0.0, 0.0, 1000, True)
    hybrid = structures.HybridSettings(0, 0, 1.0)
    first = phases.integrate_links(
        params,
        hybrid,
        controls,
        structures.new_output(np.linspace(0.0, 0.01, 3), layout.N_STATE, 10),
    )
    made: list[tuple[Any, ...]] = []
    real = _linking._new_link

    def counted(*args: Any) -> tuple[int, int]:
        made.append(args)
        return real(*args)

    monkeypatch.setattr(_linking, "_new_link", counted)
    other_body = models.kernel_parameters(cs.SlidingModel(), cs.load_body("toy_rattleback_10cm"))
    output = structures.new_output(np.linspace(0.0, 2.0, 50), layout.N_STATE, 99)
    assert phases.integrate_links(other_body, hybrid, controls._replace(rtol=1e-6), output) == first
    assert made == []


def test_a_record_and_its_coded_version_never_convert() -> None:
    """numba converts a record to another with equal fields; a right-hand side compiled
    for one run's codes (``kernels._pruning.CodedRecord``) must never serve a call with
    a plain record, nor the reverse: its coded fields carry their values as titles."""
    import numba
    from numba.core.registry import cpu_target

    from celtstone.kernels._pruning import CodedRecord, plain_type

    record = numba.typeof(layout.parameter_record())
    coded = CodedRecord(record, (("friction_law", 0), ("shape_code", 0)))
    other = CodedRecord(record, (("friction_law", 1), ("shape_code", 0)))
    typing = cpu_target.typing_context
    for source, target in ((record, coded), (coded, record), (coded, other)):
        assert typing.can_convert(source, target) is None, (source, target)
    assert coded != other and coded.fields.keys() == record.fields.keys()
    assert plain_type(coded) == record  # a link's key: the same at both ends


class _Compiles(event.Listener):
    """The functions numba compiles (its "numba:compile" event fires on a cache miss only)."""

    def __init__(self) -> None:
        self.names: list[str] = []

    def on_start(self, event: event.Event) -> None:
        self.names.append(event.data["dispatcher"].py_func.__qualname__)

    def on_end(self, event: event.Event) -> None:
        pass


def _rolling_run_arguments(monkeypatch: pytest.MonkeyPatch) -> tuple[Any, ...]:
    """``integrate``'s arguments (without ``rhs_link``) of a short rolling vern9 run of
    Kane & Levinson's stone, as ``solvers.run.solve`` makes them."""
    captured: list[tuple[Any, ...]] = []
    real = driver.integrate_link

    def spy(arguments: tuple[Any, ...], *rest: Any, **options: Any) -> Any:
        captured.append(arguments)
        return real(arguments, *rest, **options)

    with monkeypatch.context() as patch:
        patch.setattr(solver_run, "integrate_link", spy)
        cs.simulate(cs.RollingModel(), cs.load_body("kane_levinson_1982"), KL_START, 0.01)
    assert [int(arguments[1]) for arguments in captured] == [METHODS["vern9"]]
    return captured[0]


@pytest.mark.skipif(not driver.MODEL_AND_METHOD, reason="numba's own compiler: one loop")
def test_a_run_takes_its_own_loop_where_it_is_compiled_beside_the_loop_for_every_code(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Where the loop for every code is compiled (``celtstone compile``, a stick–slip
    run), a rolling run still takes the loop compiled for its model and method, and its
    right-hand side for the record's codes, where those are compiled too: it runs
    faster (``driver.integrate_link``)."""
    cs.compile_solvers()
    arguments = _rolling_run_arguments(monkeypatch)
    placeholder = (*arguments, _linking.NO_LINK)
    every_code = _linking.cached_link_to(driver.integrate, placeholder)
    assert every_code is not None, "compile_solvers compiles the loop for every code"
    own = _linking.link_to(driver.integrate, placeholder, driver.MODEL_AND_METHOD)
    own_rhs = _system.rhs_link(arguments[2], layout.MODEL_ROLLING, codes=True)
    assert own != every_code
    assert driver.integrate_link(arguments) == (own, own_rhs)


@pytest.mark.skipif(not driver.MODEL_AND_METHOD, reason="numba's own compiler: one loop")
def test_a_run_whose_own_right_hand_side_is_not_compiled_takes_the_loop_for_every_code(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The run's own loop is compiled but not its right-hand side for the record's codes
    (a body shape no run had: here a code no run can have, so that no cache holds it):
    the run takes the loop for every code, which is compiled, and compiles nothing."""
    cs.compile_solvers()
    arguments = _rolling_run_arguments(monkeypatch)
    placeholder = (*arguments, _linking.NO_LINK)
    _linking.link_to(driver.integrate, placeholder, driver.MODEL_AND_METHOD)  # compiled
    params = arguments[2].copy()
    params["shape_code"] = 99  # in no ShapeCode
    other = (*arguments[:2], params, *arguments[3:])
    every_code = _linking.cached_link_to(driver.integrate, (*other, _linking.NO_LINK))
    assert every_code is not None, "compile_solvers compiles the loop for every code"
    compiles = _Compiles()
    with event.install_listener("numba:compile", compiles):
        links = driver.integrate_link(other)
        assert _system.cached_rhs_link(params, layout.MODEL_ROLLING, codes=True) is None
    assert compiles.names == []
    assert links == (every_code, _system.rhs_link(params))


def test_a_link_to_a_version_in_no_cache_is_none_and_compiles_nothing() -> None:
    """``cached_link_to`` with constants and coded record fields finds the version that
    ``link_to`` made for them, and None for one that no cache holds, compiling nothing."""
    params = models.kernel_parameters(cs.RollingModel(), cs.load_body("kane_levinson_1982"))
    made = _system.rhs_link(params, layout.MODEL_ROLLING, codes=True)
    assert _system.cached_rhs_link(params, layout.MODEL_ROLLING, codes=True) == made
    unknown = params.copy()
    unknown["friction_law"] = 99  # in no FrictionLaw: no cache holds its version
    compiles = _Compiles()
    with event.install_listener("numba:compile", compiles):
        assert _system.cached_rhs_link(unknown, layout.MODEL_ROLLING, codes=True) is None
        assert _system.cached_rhs_link(unknown, layout.MODEL_ROLLING, codes=True) is None
    assert compiles.names == []
