"""numba's compiler with the branches on a constant code removed before typing.

A model, method or other code reaches the kernels as a plain int, and every dispatch on
it is an ``if code == CODE:`` chain. Where a caller passes the code as a constant
(``integrate``'s entries per model and method, ``solvers.driver``), numba types the
callee's argument as a literal (``Literal[int](0)``), but its own branch pruning folds
only comparisons with ``None``: it still types, lowers and optimises every other
model's and method's branch, and compiles every kernel they call: a first rolling run
compiled the sliding and stick models and all four methods (56 s of CPU on the 2-core
machine, against 34 s with this pass; ``benchmarks/bench_cold_start.py``).

:class:`CodePruningCompiler` is numba's nopython pipeline with one more pass,
:class:`FoldCodeComparisons`, before and after numba inlines the ``inline="always"``
helpers: a comparison of two values known at compile time (a literal argument, a
constant, a module-level int, an ``IntEnum`` member) becomes the constant it evaluates
to, and numba's own dead-branch pass then removes the branch it decides. A comparison
with anything else is left as it is, so a call with a runtime code compiles every branch,
as before. Nothing else changes: the same IR minus branches a run can never take.

The inlining itself is numba's ``InlineInlinables`` one call level at a time
(:class:`InlineOnePerLevel`): numba's pass makes each callee's IR anew with every
``inline="always"`` callee of its own already inlined, so the run loop's call to the
method dispatcher (``solvers._methods.attempt``) copied every method's step, Radau's
Newton iteration included, before the loop's constant method code could remove them,
and made the IR of a helper anew at each of its call sites: 9 of the 15 s of CPU that
a first rolling run spent on the run loop itself (29 s in all, then 20 s). One level
at a time, the caller's codes decide each inlined dispatcher's branches before the
calls inside them are inlined, and each callee's IR is made once per process.

A parameter record typed as a :class:`CodedRecord` (a run's right-hand side,
``solvers._system.RUN_CODES``) has some fields known at compile time: each read of one
becomes its constant, and its comparisons fold as a literal argument's do.

The pass uses numba's documented extension points for compiler passes
(``numba.core.compiler_machinery``, ``CompilerBase.define_pipelines``); the pinned
numba's pass names are checked at import.
"""

from __future__ import annotations

import operator
from types import ModuleType
from typing import Any

from numba.core import bytecode, ir, postproc, types
from numba.core.analysis import compute_cfg_from_blocks, dead_branch_prune
from numba.core.compiler import CompilerBase, DefaultPassBuilder
from numba.core.compiler_machinery import FunctionPass, register_pass
from numba.core.datamodel.models import RecordModel
from numba.core.inline_closurecall import InlineWorker, callee_ir_validator
from numba.core.ir_utils import build_definitions, get_definition, guard, simplify_CFG
from numba.core.untyped_passes import InlineClosureLikes, InlineInlinables
from numba.extending import register_model

_COMPARISONS = {
    operator.eq,
    operator.ne,
    operator.lt,
    operator.le,
    operator.gt,
    operator.ge,
}


class _Unknown:
    """A value not known at compile time."""


UNKNOWN = _Unknown()


def _known(value: Any) -> Any:
    """``value`` if it is a compile-time int or bool (an ``IntEnum`` member too)."""
    return value if isinstance(value, int) else UNKNOWN  # bool and IntEnum are ints


def constant_value(func_ir: Any, variable: Any, argument_types: Any) -> Any:
    """The int or bool ``variable`` holds whatever the call, or ``UNKNOWN``.

    Known: a literal argument (``Literal[int]``, ``Literal[bool]``), a constant, a
    global or closure value, an attribute of a global module or class (``codes.X``,
    ``ModelCode.ROLLING``). A variable with several definitions is unknown.
    """
    definition = guard(get_definition, func_ir, variable)
    if isinstance(definition, ir.Arg):
        if argument_types is None or definition.index >= len(argument_types):
            return UNKNOWN
        argument = argument_types[definition.index]
        if isinstance(argument, (types.IntegerLiteral, types.BooleanLiteral)):
            return _known(argument.literal_value)
        return UNKNOWN
    if isinstance(definition, (ir.Const, ir.Global, ir.FreeVar)):
        return _known(definition.value)
    if isinstance(definition, ir.Expr) and definition.op == "getattr":
        owner = guard(get_definition, func_ir, definition.value)
        if isinstance(owner, (ir.Global, ir.FreeVar)) and isinstance(
            owner.value, (ModuleType, type)
        ):
            return _known(getattr(owner.value, definition.attr, UNKNOWN))
    return UNKNOWN


class CodedRecord(types.Record):
    """A parameter record whose fields ``codes`` ((name, value) pairs) are compile-time
    constants: the type of a right-hand side compiled for one run's friction law,
    pressure and shapes (``solvers._system.rhs_link``). Laid out, passed and read as its
    ``record`` is; :func:`fold_record_codes` makes each read of a coded field its
    constant, so that only its branches compile, and callees are compiled for this
    type in turn. Its name holds the codes: numba's cache keeps a version per codes.

    Each coded field carries its value as its title: numba converts a record to
    another whose fields are equal (a "subtype"), and a call with a plain record could
    otherwise take a version compiled for some codes, and the reverse."""

    def __init__(self, record: Any, codes: tuple[tuple[str, int], ...]) -> None:
        self.record = record
        self.codes = codes
        titles = {name: f"{name}={value}" for name, value in codes}
        fields: list[Any] = [
            (
                name,
                {
                    "type": field.type,
                    "offset": field.offset,
                    "alignment": field.alignment,
                    "title": titles.get(name, field.title),
                },
            )
            for name, field in record.fields.items()
        ]
        super().__init__(fields, record.size, record.aligned)
        self.name = f"{record.name}{{{','.join(f'{k}={v}' for k, v in codes)}}}"


register_model(CodedRecord)(RecordModel)


def plain_type(argument: Any) -> Any:
    """``argument``'s numba type without literal values or coded fields, as a caller
    that passes them as values types it."""
    return argument.record if isinstance(argument, CodedRecord) else types.unliteral(argument)


def _assigned(statement: Any, op: str) -> Any:
    """The expression that ``statement`` (numba IR) assigns if it is an ``op`` expression
    ("getattr", "binop", "call"), else None."""
    expression = getattr(statement, "value", None)
    if isinstance(statement, ir.Assign) and isinstance(expression, ir.Expr):
        return expression if expression.op == op else None
    return None


def fold_record_codes(func_ir: Any, argument_types: Any) -> bool:
    """Replace each read of a coded field of a :class:`CodedRecord` argument by its
    value (a constant); whether any was."""
    folded = False
    for block in func_ir.blocks.values():
        for statement in block.body:
            expression = _assigned(statement, "getattr")
            if expression is None:
                continue
            owner = guard(get_definition, func_ir, expression.value)
            if not isinstance(owner, ir.Arg) or argument_types is None:
                continue
            if owner.index >= len(argument_types):
                continue
            record = argument_types[owner.index]
            codes = dict(record.codes) if isinstance(record, CodedRecord) else {}
            if expression.attr not in codes:
                continue
            result = ir.Const(codes[expression.attr], loc=expression.loc)
            statement.value = result
            definitions = func_ir._definitions[statement.target.name]
            definitions[definitions.index(expression)] = result
            folded = True
    return folded


def fold_code_comparisons(func_ir: Any, argument_types: Any) -> bool:
    """Replace each comparison of two compile-time values by its result; whether any was."""
    folded = fold_record_codes(func_ir, argument_types)
    for block in func_ir.blocks.values():
        for statement in block.body:
            expression = _assigned(statement, "binop")
            if expression is None or expression.fn not in _COMPARISONS:
                continue
            left = constant_value(func_ir, expression.lhs, argument_types)
            right = constant_value(func_ir, expression.rhs, argument_types)
            if left is UNKNOWN or right is UNKNOWN:
                continue
            result = ir.Const(bool(expression.fn(int(left), int(right))), loc=expression.loc)
            statement.value = result
            definitions = func_ir._definitions[statement.target.name]
            definitions[definitions.index(expression)] = result
            folded = True
    return folded


@register_pass(mutates_CFG=True, analysis_only=False)
class FoldCodeComparisons(FunctionPass):
    """Fold comparisons of compile-time codes, then let numba prune the branches they
    decide; repeated while something folds (a pruned branch can leave a variable with
    one definition, and so known)."""

    _name = "celtstone_fold_code_comparisons"

    def __init__(self) -> None:
        FunctionPass.__init__(self)

    def run_pass(self, state: Any) -> bool:
        return prune_folded_branches(state.func_ir, state.args)


def prune_folded_branches(func_ir: Any, argument_types: Any) -> bool:
    """Fold comparisons of compile-time codes and remove the branches they decide,
    repeated while something folds (a pruned branch can leave a variable with one
    definition, and so known); whether anything was."""
    changed = False
    while fold_code_comparisons(func_ir, argument_types):
        dead_branch_prune(func_ir, argument_types)
        # the blocks no branch reaches any more, and their definitions: a variable
        # assigned in one live block only is then known (an inlined helper's return)
        for label in compute_cfg_from_blocks(func_ir.blocks).dead_nodes():
            del func_ir.blocks[label]
        func_ir._definitions = build_definitions(func_ir.blocks)
        changed = True
    return changed


def _untyped_pipeline_without_inlining(state: Any, name: str = "untyped") -> Any:
    """numba's untyped pipeline without its ``InlineInlinables``: a callee's own
    ``inline="always"`` calls are left to the caller's pass (:class:`InlineOnePerLevel`)."""
    pipeline = DefaultPassBuilder.define_untyped_pipeline(state, name)
    position = pipeline.passes.index((InlineInlinables, "inline inlinable functions"))
    del pipeline.passes[position]
    return pipeline


# a function's untyped IR, made once per process: every inlining copies it
_CALLEE_IR: dict[Any, Any] = {}


class _OneLevelInliner(InlineWorker):
    """numba's ``InlineWorker`` whose callee IR holds its own inlinable calls uninlined,
    made once per function."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._compiler_pipeline = _untyped_pipeline_without_inlining

    def run_untyped_passes(self, func: Any, enable_ssa: bool = False) -> Any:
        key = (func, enable_ssa)
        cached = _CALLEE_IR.get(key)
        if cached is None:
            cached = _CALLEE_IR[key] = super().run_untyped_passes(func, enable_ssa)
        callee_ir = cached.copy()  # inline_ir copies the blocks, which it mutates
        # a fresh identity per copy: the inlined variables are named after it
        callee_ir.func_id = bytecode.FunctionIdentity.from_function(func)
        return callee_ir


@register_pass(mutates_CFG=True, analysis_only=False)
class InlineOnePerLevel(InlineInlinables):
    """numba's ``InlineInlinables``, one call level at a time: a callee is inlined
    without its own inlinable calls, the caller's codes then decide its branches
    (:func:`prune_folded_branches`), and only the calls left in live blocks are
    inlined in turn. numba's pass inlines each callee with every callee of its own,
    each made anew, before any branch is decided: every method's step for a run that
    takes one."""

    _name = "celtstone_inline_one_per_level"

    def run_pass(self, state: Any) -> bool:
        worker = _OneLevelInliner(
            state.typingctx,
            state.targetctx,
            state.locals,
            state.pipeline,
            state.flags,
            validator=callee_ir_validator,
        )
        func_ir = state.func_ir
        prune_folded_branches(func_ir, state.args)
        modified = False
        work_list = list(func_ir.blocks.items())
        while work_list:
            label, block = work_list.pop()
            if func_ir.blocks.get(label) is not block:
                continue  # pruned since
            for index, statement in enumerate(block.body):
                expression = _assigned(statement, "call")
                if expression is None:
                    continue
                if guard(self._do_work, state, work_list, block, index, expression, worker):
                    modified = True
                    if prune_folded_branches(func_ir, state.args):
                        live = set(func_ir.blocks)
                        work_list = [item for item in work_list if item[0] in live]
                    break  # the block was split
        if modified:
            for dead in compute_cfg_from_blocks(func_ir.blocks).dead_nodes():
                del func_ir.blocks[dead]
            postproc.PostProcessor(func_ir).run()
            func_ir.blocks = simplify_CFG(func_ir.blocks)
        return True


class CodePruningCompiler(CompilerBase):
    """numba's nopython pipeline with :class:`FoldCodeComparisons` after its inlining of
    closures (before the helpers are inlined: none is inlined into a dead branch) and
    after its inlining of ``inline="always"`` functions (their branches on the caller's
    codes)."""

    def define_pipelines(self) -> list[Any]:
        pipeline = DefaultPassBuilder.define_nopython_pipeline(self.state)
        pipeline.add_pass_after(FoldCodeComparisons, InlineClosureLikes)
        position = pipeline.passes.index((InlineInlinables, "inline inlinable functions"))
        pipeline.passes[position] = (InlineOnePerLevel, "inline inlinable functions")
        pipeline.add_pass_after(FoldCodeComparisons, InlineOnePerLevel)
        pipeline.finalize()
        return [pipeline]
