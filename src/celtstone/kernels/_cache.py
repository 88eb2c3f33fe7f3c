"""numba's on-disk cache as celtstone uses it: saved so that processes compiling at once
never mix its entries, and loaded without loading numba's compiler.

**Saving.**

numba (0.68) keeps, per function, an index (signature key -> data file name) and one
data file per signature. Its ``IndexDataCacheFile.save`` reads the index, names a new
entry's data after the first number the index does not use, writes the index and then
the data, with no lock between processes. Two processes that save new signatures of one
function at once therefore pick the same data file, and the index ends up naming one
signature's machine code for another signature, which a later process loads and runs
with arguments of other types. Measured with ``tests/test_numba_cache.py``'s four
processes saving 150 new signatures each at once: numba's own class kept 264–364 of the
600 entries, 66–119 of them naming another signature's data (three runs, 2-core
machine). Pytest's two workers, Dask workers and a user's parallel jobs all
share one cache.

:class:`LockedCacheFile` saves an entry under an exclusive lock of the cache directory
(``fcntl.flock`` of ``LOCK_NAME``): it reads the index inside the lock, writes the
data file first and then the index that names it, so every name in an index is a whole
data file of that signature, and no process's entry is lost. Loading takes no lock: a
data file named in an index is never rewritten with another signature's data while the
index's source stamp stands (numba starts a new index when the source changes). Where
``fcntl`` is missing (Windows), the lock file cannot be opened or the file system has
no locks, entries are saved in the same order without the lock.

**Loading.** numba's ``Cache.load_overload`` refreshes the target context before it reads
an entry: it imports and installs every lowering registry numba has (NumPy's array
functions, typed containers, random generators, ``scipy.linalg`` for BLAS...), 0.95 s of a
2.45 s ``celtstone run --json`` (cProfile). Loaded machine code needs none of
it: the helper and math symbols are installed when the context is made, and the runtime
(NRT) by ``rtsys.initialize``, which :class:`LeanFunctionCache` calls instead. A compile
later in the process refreshes the context itself (numba's compiler does so first), so
nothing a compile needs is skipped, only put off until one happens.

**The linking module, parsed when linked.** numba saves a function's machine code with
the LLVM bitcode of its module "for linking" (the one a later compile links in when it
calls the function), and on loading parses that bitcode whole only to list the symbols
the library defines: 0.09–0.10 s of a short run's 0.26 s first call (the run loop's
three libraries, 2.2 MB of bitcode). :class:`LockedCacheFile` saves that
list beside the bitcode (the entry kind ``LAZY_KIND``), and :class:`LazyLinkingLibrary`
registers the listed symbols and parses the bitcode only if a compile later in the
process links the function in. Entries saved by plain numba (kind "object") load as
numba loads them.

:func:`use_celtstone_cache` gives a dispatcher made with ``cache=True`` both
(``kernels._jit.cached_njit`` does it for every cached celtstone function).
"""

from __future__ import annotations

import contextlib
import itertools
import os
from collections.abc import Iterator
from typing import Any

import llvmlite.binding as llvm
from numba.core.caching import FunctionCache, IndexDataCacheFile
from numba.core.codegen import JITCodeLibrary
from numba.core.runtime import rtsys

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows: saved in order, without the lock
    fcntl = None  # type: ignore[assignment]

LOCK_NAME = "celtstone-numba-cache.lock"  # one lock file per cache directory
# a library entry (name, kind, data) of numba's kind "object", (machine code, linking
# bitcode), with the names of the symbols that bitcode defines added to its data
LAZY_KIND = "celtstone-object"


def defined_symbols(module: Any) -> tuple[str, ...]:
    """Names of the functions and global variables ``module`` (an LLVM module) defines,
    sorted: what numba's engine records of a library it loads."""
    groups = (module.functions, module.global_variables)
    return tuple(
        sorted({value.name for group in groups for value in group if not value.is_declaration})
    )


def with_symbol_list(payload: Any) -> Any:
    """A compile result's cache payload with its library entry as ``LAZY_KIND``: the
    symbols its linking bitcode defines listed (parsed once, here, at save time). A
    payload of any other form is returned as it is."""
    library = payload[0] if isinstance(payload, tuple) and payload else None
    if not (isinstance(library, tuple) and len(library) == 3 and library[1] == "object"):
        return payload
    name, _, (object_code, bitcode) = library
    symbols = defined_symbols(llvm.parse_bitcode(bitcode))
    return ((name, LAZY_KIND, (object_code, bitcode, symbols)), *payload[1:])


class LazyLinkingLibrary(JITCodeLibrary):
    """numba's JIT code library, unserialised from a ``LAZY_KIND`` entry without parsing
    its linking bitcode: the engine learns the library's symbols from the entry's list,
    and the bitcode becomes an LLVM module the first time a compile links the library in
    (``_shared_module``, which numba reads only for linking)."""

    @property
    def _shared_module(self) -> Any:
        pending = self.__dict__.pop("_pending_bitcode", None)
        if pending is not None:
            self.__dict__["_linking_module"] = llvm.parse_bitcode(pending)
        return self.__dict__.get("_linking_module")

    @_shared_module.setter
    def _shared_module(self, module: Any) -> None:
        self.__dict__.pop("_pending_bitcode", None)
        self.__dict__["_linking_module"] = module

    @classmethod
    def _unserialize(cls, codegen: Any, state: tuple[Any, ...]) -> Any:
        name, kind, data = state
        if kind != LAZY_KIND:
            return super()._unserialize(codegen, state)
        object_code, bitcode, symbols = data
        library = cls(codegen, name)
        library.enable_object_caching()
        library._set_compiled_object(object_code)
        library.__dict__["_pending_bitcode"] = bitcode
        library._finalize_final_module()
        codegen._engine._defined_symbols.update(symbols)  # as _load_defined_symbols does
        return library


class LockedCacheFile(IndexDataCacheFile):
    """numba's index and data files of one function, saved under a lock, data first."""

    def save(self, key: Any, data: Any) -> None:
        """Save the entry ``key`` -> ``data`` (a compiled overload), its library entry as
        ``LAZY_KIND``."""
        data = with_symbol_list(data)
        with _locked(os.path.join(self._cache_path, LOCK_NAME)):
            overloads = self._load_index()
            data_name = overloads.get(key)
            is_new = data_name is None
            if is_new:  # the first number no entry uses, as numba names them
                used = set(overloads.values())
                names = map(self._data_name, itertools.count(1))
                data_name = next(name for name in names if name not in used)
            self._save_data(data_name, data)
            if is_new:
                overloads[key] = data_name
                self._save_index(overloads)


@contextlib.contextmanager
def _locked(path: str) -> Iterator[None]:
    """An exclusive ``flock`` of ``path`` (created if missing) for the block; no lock
    where ``fcntl`` is missing, the file cannot be opened or not locked."""
    if fcntl is None:
        yield
        return
    try:
        descriptor = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
    except OSError:
        yield
        return
    try:
        with contextlib.suppress(OSError):  # a file system without locks: unlocked
            fcntl.flock(descriptor, fcntl.LOCK_EX)
        yield
    finally:
        os.close(descriptor)  # closing releases the lock


class LeanFunctionCache(FunctionCache):
    """numba's cache of compiled functions, loaded without refreshing the target context."""

    def load_overload(self, sig: Any, target_context: Any) -> Any:
        """The compiled overload for ``sig`` from the cache, or None; as numba's, but with
        only the runtime initialised instead of every registry loaded, and the library
        unserialised by :class:`LazyLinkingLibrary` (the caller, ``Dispatcher.compile``,
        holds numba's compiler lock, under which every compile creates its libraries)."""
        rtsys.initialize(target_context)
        codegen = target_context.codegen()
        numba_library = codegen._library_class
        codegen._library_class = LazyLinkingLibrary
        try:
            with self._guard_against_spurious_io_errors():
                return self._load_overload(sig, target_context)
        finally:
            codegen._library_class = numba_library


def use_celtstone_cache(dispatcher: Any) -> Any:
    """``dispatcher`` (``numba.njit(cache=True)``), its cache loaded by
    :class:`LeanFunctionCache` and saved by :class:`LockedCacheFile`; a plain function
    (``NUMBA_DISABLE_JIT=1``) as it is."""
    cache = getattr(dispatcher, "_cache", None)
    if cache is None:
        return dispatcher  # not compiled by numba
    cache_file = getattr(cache, "_cache_file", None)
    if type(cache) is not FunctionCache or type(cache_file) is not IndexDataCacheFile:
        raise TypeError(  # a numba other than the pinned one
            f"numba's cache is not a FunctionCache with an IndexDataCacheFile: {type(cache)}"
        )
    cache.__class__ = LeanFunctionCache  # the same state, loaded and saved by subclasses
    cache_file.__class__ = LockedCacheFile
    return dispatcher
