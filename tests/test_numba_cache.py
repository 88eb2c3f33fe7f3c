"""numba's on-disk cache as celtstone uses it: processes that compile at once never mix
entries, and a load does not load numba's compiler (``kernels._cache``)."""

from __future__ import annotations

import importlib
import multiprocessing
import os
import pkgutil
import subprocess
import sys
from pathlib import Path

import pytest
from numba.core.caching import IndexDataCacheFile
from numba.core.registry import CPUDispatcher

import celtstone
from celtstone.kernels._cache import (
    LOCK_NAME,
    LeanFunctionCache,
    LockedCacheFile,
    _locked,
    use_celtstone_cache,
)

WRITERS = 4
ENTRIES = 150  # per writer
STAMP = ("source stamp", 1)


def _save_many(directory: str, writer: int, start: multiprocessing.synchronize.Barrier) -> None:
    """One process saving ``ENTRIES`` new signatures of one function's cache."""
    cache_file = LockedCacheFile(directory, "function-1.py311", STAMP)
    start.wait()
    for entry in range(ENTRIES):
        key = (f"writer {writer}", entry)
        cache_file.save(key, ("machine code of", key))


def test_processes_saving_at_once_keep_every_entry_with_its_own_data(tmp_path: Path) -> None:
    """Four processes save 150 new signatures each into one index at the same time. numba's
    own ``IndexDataCacheFile`` kept 264–364 of the 600 entries, 66–119 of them naming
    another signature's data (three runs on a 2-core machine); this test failed
    three times of three with the lock taken out: every entry is kept here, each naming
    its own data."""
    try:
        context = multiprocessing.get_context("fork")
    except ValueError:  # pragma: no cover - no fork (Windows)
        pytest.skip("needs fork")
    start = context.Barrier(WRITERS)
    writers = [
        context.Process(target=_save_many, args=(str(tmp_path), w, start)) for w in range(WRITERS)
    ]
    for process in writers:
        process.start()
    for process in writers:
        process.join(timeout=120)
        assert process.exitcode == 0
    reader = IndexDataCacheFile(str(tmp_path), "function-1.py311", STAMP)
    index = reader._load_index()
    expected = {(f"writer {w}", e) for w in range(WRITERS) for e in range(ENTRIES)}
    assert set(index) == expected
    assert len(set(index.values())) == len(expected)  # one data file per signature
    assert all(reader.load(key) == ("machine code of", key) for key in expected)
    assert (tmp_path / LOCK_NAME).exists()


def test_an_existing_entry_is_rewritten_in_place(tmp_path: Path) -> None:
    cache_file = LockedCacheFile(str(tmp_path), "function-1.py311", STAMP)
    cache_file.save("a", 1)
    cache_file.save("b", 2)
    cache_file.save("a", 3)
    index = cache_file._load_index()
    assert index == {"a": "function-1.py311.1.nbc", "b": "function-1.py311.2.nbc"}
    assert (cache_file.load("a"), cache_file.load("b")) == (3, 2)


def test_a_lock_file_that_cannot_be_opened_saves_without_the_lock(tmp_path: Path) -> None:
    with _locked(str(tmp_path / "missing directory" / LOCK_NAME)):
        pass  # no error: saved in order, unlocked, as where fcntl is missing


def _celtstone_dispatchers() -> list[CPUDispatcher]:
    found = []
    for module_info in pkgutil.walk_packages(celtstone.__path__, "celtstone."):
        if ".cli" in module_info.name or module_info.name.endswith("__main__"):
            continue
        module = importlib.import_module(module_info.name)
        for value in vars(module).values():
            if isinstance(value, CPUDispatcher) and value.__module__ == module.__name__:
                found.append(value)
    return found


def test_every_cached_celtstone_function_uses_the_celtstone_cache() -> None:
    """A function compiled with ``numba.njit(cache=True)`` directly would save with numba's
    unlocked index and load numba's compiler with its first load: every cached dispatcher
    of the package loads with ``LeanFunctionCache`` and saves with ``LockedCacheFile``."""
    dispatchers = _celtstone_dispatchers()
    cached = [d for d in dispatchers if getattr(d, "_cache", None) is not None]
    cached = [d for d in cached if hasattr(d._cache, "_cache_file")]
    assert len(cached) > 100  # the kernels, the solvers' steps, the drivers
    unlocked = [
        f"{d.py_func.__module__}.{d.py_func.__qualname__}"
        for d in cached
        if type(d._cache) is not LeanFunctionCache
        or type(d._cache._cache_file) is not LockedCacheFile
    ]
    assert unlocked == []


def test_a_cache_numba_no_longer_keeps_as_pinned_fails_at_import() -> None:
    """The celtstone cache swaps the classes of numba's own cache and cache file: a numba
    whose cache is something else (an upgrade) is refused at import, not used unlocked."""

    class Cache:
        _cache_file = object()

    class Dispatcher:
        _cache = Cache()

    with pytest.raises(TypeError, match="FunctionCache"):
        use_celtstone_cache(Dispatcher())

    def plain() -> None:  # NUMBA_DISABLE_JIT=1: njit returns the function itself
        pass

    assert use_celtstone_cache(plain) is plain


# A run loaded from the warm cache, then a compile in the same process, then the run again
LEAN_LOAD_SCRIPT = """
import sys
import numpy as np
from numba import njit
import celtstone as cs

body = cs.load_body("kane_levinson_1982")
state = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
first = cs.simulate(cs.RollingModel(), body, state, 0.05).summary()["spin_final"]
heavy = ("numba.np.arraymath", "numba.typed.typeddict", "scipy.linalg")
print(sorted(name for name in heavy if name in sys.modules))
norm = njit(lambda v: np.linalg.norm(v) + np.sum(np.sort(v)))  # needs those registries
print(norm(np.array([3.0, 4.0, 0.0])))
again = cs.simulate(cs.RollingModel(), body, state, 0.05).summary()["spin_final"]
print(first == again)
"""


def test_a_run_from_the_cache_loads_no_compiler_and_a_later_compile_still_works() -> None:
    """Loading machine code from the cache imports none of numba's lowering registries
    (0.95 s of a 2.45 s ``celtstone run --json``); a compile afterwards in the same process
    loads them and works, and the loaded run still runs alike."""
    command = [sys.executable, "-c", LEAN_LOAD_SCRIPT]
    subprocess.run(command, capture_output=True, text=True, check=True)  # fills the cache
    done = subprocess.run(command, capture_output=True, text=True, check=True)
    assert done.stdout.split("\n")[:3] == ["[]", "12.0", "True"], done.stdout + done.stderr


# A cached kernel loaded, then linked into a new compile (fresh cache: NUMBA_CACHE_DIR)
LAZY_LINK_SCRIPT = """
from numba import njit
from celtstone.kernels.vector import dot

a, b = (1.0, 2.0, 3.0), (4.0, 5.0, 6.0)
value = dot(a, b)
library = dot.overloads[dot.signatures[0]].library
print(type(library).__name__, "_pending_bitcode" in library.__dict__)


@njit
def twice(a, b):
    return 2.0 * dot(a, b)


doubled = twice(a, b)  # compiles twice, linking dot's library in
pending = "_pending_bitcode" in library.__dict__
print(value, doubled, pending, library._shared_module is not None)
"""


def test_a_loaded_kernel_parses_its_linking_bitcode_only_when_a_compile_links_it(
    tmp_path: Path,
) -> None:
    """A kernel loaded from an entry celtstone saved runs with its linking bitcode unparsed
    (the engine knows its symbols from the entry's list); a compile that calls it then
    parses and links it, and both give the same result."""
    command = [sys.executable, "-c", LAZY_LINK_SCRIPT]
    environment = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    compiled = subprocess.run(command, capture_output=True, text=True, env=environment)
    assert compiled.returncode == 0, compiled.stderr
    assert compiled.stdout.splitlines()[0] == "JITCodeLibrary False"  # compiled here, saved
    loaded = subprocess.run(command, capture_output=True, text=True, env=environment)
    assert loaded.returncode == 0, loaded.stderr
    assert loaded.stdout.splitlines() == ["LazyLinkingLibrary True", "32.0 64.0 False True"]


def test_the_symbol_list_is_added_only_to_an_object_entry() -> None:
    import llvmlite.binding as llvm

    from celtstone.kernels._cache import LAZY_KIND, with_symbol_list

    module = llvm.parse_assembly(
        'define double @"f"(double %x) {\n  ret double %x\n}\n'
        "@g = global i32 0\n"
        "declare double @h(double)\n"
    )
    entry = ("library", "object", (b"machine code", module.as_bitcode()))
    payload = with_symbol_list((entry, "the rest"))
    name, kind, (object_code, bitcode, symbols) = payload[0]
    assert (name, kind, object_code, bitcode) == ("library", LAZY_KIND, *entry[2])
    assert symbols == ("f", "g")  # defined ones only: h is a declaration
    assert payload[1:] == ("the rest",)
    other = (("name", "bitcode", b"..."), "the rest")
    assert with_symbol_list(other) is other
    assert with_symbol_list(()) == ()
    assert with_symbol_list(7) == 7
