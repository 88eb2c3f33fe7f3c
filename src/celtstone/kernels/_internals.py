"""The parts of numba's private machinery that celtstone's cache and compiler rely on.

``_cache`` subclasses numba's cache classes (a locked save, a load without the
compiler, the linking bitcode parsed when linked), ``_pruning`` adds a compiler pass
that calls numba's branch pruning and replaces numba's inlining pass by one that inlines
a level at a time, and ``_jit`` compiles without C-callable wrappers (an option of
numba's CPU target, ``TARGET_OPTIONS``). All were written against one numba version
(``TESTED_NUMBA``, the one ``pyproject.toml`` pins) and the private functions listed in
``PRIVATE_SIGNATURES``. :func:`internals_changed` names what differs in the numba that
is installed; where anything does, ``_jit.cached_njit`` uses numba's own cache and
compiler instead (slower to load and to compile, the same results), and
``tests/test_numba_internals.py`` fails with the list, so that an upgrade is checked
rather than run on unchecked assumptions.
"""

from __future__ import annotations

import functools
import importlib
import inspect
from typing import Any

import numba

TESTED_NUMBA = "0.68.1"

# "module.Class.function" -> its signature in TESTED_NUMBA (``inspect.signature``)
PRIVATE_SIGNATURES = {
    "numba.core.caching.IndexDataCacheFile.save": "(self, key, data)",
    "numba.core.caching.IndexDataCacheFile._load_index": "(self)",
    "numba.core.caching.IndexDataCacheFile._save_index": "(self, overloads)",
    "numba.core.caching.IndexDataCacheFile._save_data": "(self, name, data)",
    "numba.core.caching.IndexDataCacheFile._data_name": "(self, number)",
    "numba.core.caching.FunctionCache.load_overload": "(self, sig, target_context)",
    "numba.core.caching.FunctionCache._load_overload": "(self, sig, target_context)",
    "numba.core.caching.FunctionCache._guard_against_spurious_io_errors": "(self)",
    "numba.core.codegen.JITCodeLibrary._unserialize": "(codegen, state)",
    "numba.core.codegen.JITCodeLibrary.enable_object_caching": "(self)",
    "numba.core.codegen.JITCodeLibrary._set_compiled_object": "(self, value)",
    "numba.core.codegen.JITCodeLibrary._finalize_final_module": "(self)",
    "numba.core.runtime.rtsys.initialize": "(ctx)",
    "numba.core.analysis.dead_branch_prune": "(func_ir, called_args)",
    "numba.core.analysis.compute_cfg_from_blocks": "(blocks)",
    "numba.core.ir_utils.build_definitions": "(blocks, definitions=None)",
    "numba.core.compiler.DefaultPassBuilder.define_nopython_pipeline": "(state, name='nopython')",
    "numba.core.compiler_machinery.PassManager.add_pass_after": "(self, pass_cls, location)",
    "numba.core.compiler.DefaultPassBuilder.define_untyped_pipeline": "(state, name='untyped')",
    "numba.core.inline_closurecall.InlineWorker.run_untyped_passes": (
        "(self, func, enable_ssa=False)"
    ),
    "numba.core.untyped_passes.InlineInlinables._do_work": (
        "(self, state, work_list, block, i, expr, inline_worker)"
    ),
    "numba.core.ir.FunctionIR.copy": "(self)",
}


# options of numba's CPU target that ``_jit.cached_njit`` passes, private in effect
TARGET_OPTIONS = ("no_cfunc_wrapper",)


def _resolve(dotted: str) -> Any:
    """The object a dotted name names: the longest importable module, then attributes."""
    parts = dotted.split(".")
    for split in range(len(parts) - 1, 0, -1):
        try:
            value: Any = importlib.import_module(".".join(parts[:split]))
        except ImportError:
            continue
        for attribute in parts[split:]:
            value = getattr(value, attribute)
        return value
    raise ImportError(dotted)


def differences(version: str = numba.__version__) -> list[str]:
    """What differs from the numba celtstone's cache and compiler were written for, one
    line each; empty where nothing does."""
    found = []
    if version != TESTED_NUMBA:
        found.append(f"numba {version} is installed; celtstone was checked with {TESTED_NUMBA}")
    for name, expected in PRIVATE_SIGNATURES.items():
        try:
            actual = str(inspect.signature(_resolve(name)))
        except (ImportError, AttributeError, TypeError, ValueError):
            found.append(f"{name} is missing")
            continue
        if actual != expected:
            found.append(f"{name}{actual}, expected {name}{expected}")
    from numba.core.cpu import CPUTargetOptions

    for option in TARGET_OPTIONS:
        if not hasattr(CPUTargetOptions, option):
            found.append(f"numba's CPU target has no option {option}")
    return found


@functools.cache
def internals_changed() -> bool:
    """Whether the installed numba differs (:func:`differences`): then celtstone uses
    numba's own cache and compiler."""
    return bool(differences())
