"""celtstone's cache and compiler rely on private parts of numba (``kernels._internals``):
an upgrade that changes them is named here, and celtstone then runs on numba's own cache
and compiler instead of on unchecked assumptions."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numba

from celtstone.kernels import _internals


def test_the_installed_numba_is_the_one_celtstone_was_checked_with() -> None:
    """Fails on a numba upgrade, listing what changed; check ``kernels._cache`` and
    ``kernels._pruning`` against the new numba, then update ``_internals``."""
    changed = _internals.differences()
    assert changed == [], "numba's private machinery changed:\n" + "\n".join(changed)
    assert not _internals.internals_changed()


def test_another_version_or_signature_is_named() -> None:
    """The check can fail: another version, a changed and a missing function."""
    assert _internals.differences(numba.__version__ + ".post1")[0].startswith(
        f"numba {numba.__version__}.post1 is installed"
    )
    signatures = dict(_internals.PRIVATE_SIGNATURES)
    name = "numba.core.caching.IndexDataCacheFile.save"
    signatures[name] = "(self, key)"
    signatures["numba.core.caching.NoSuchClass.save"] = "(self)"
    original = _internals.PRIVATE_SIGNATURES
    try:
        _internals.PRIVATE_SIGNATURES = signatures
        changed = _internals.differences()
    finally:
        _internals.PRIVATE_SIGNATURES = original
    assert changed == [
        f"{name}(self, key, data), expected {name}(self, key)",
        "numba.core.caching.NoSuchClass.save is missing",
    ]


_FALLBACK = """
import numba
from numba.core.caching import FunctionCache

from celtstone.kernels import _internals

_internals.TESTED_NUMBA = "0.0"  # as if another numba were installed
from celtstone.kernels import _cache, vector  # noqa: E402
from celtstone.solvers import driver  # noqa: E402

assert type(vector.dot._cache) is FunctionCache, type(vector.dot._cache)
assert "pipeline_class" not in vector.dot.targetoptions
assert driver.MODEL_AND_METHOD == ()
assert vector.dot((1.0, 2.0, 3.0), (4.0, 5.0, 6.0)) == 32.0
print("fallback")
"""


def test_another_numba_runs_on_numbas_own_cache_and_compiler(tmp_path: Path) -> None:
    """With another numba, the kernels use numba's own cache classes and compiler (no
    lock, no lean load, every branch compiled) and still compute."""
    completed = subprocess.run(
        [sys.executable, "-c", _FALLBACK],
        capture_output=True,
        text=True,
        check=False,
        timeout=600,
        env=dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path)),
    )
    assert completed.returncode == 0, completed.stderr[-3000:]
    assert completed.stdout.strip() == "fallback"
