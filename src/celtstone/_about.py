"""The installed version, without importing the engine."""

from __future__ import annotations


def version() -> str:
    """Give the installed celtstone version.

    Returns
    -------
    str
        The version of the installed distribution, "unknown" in a bare source tree.
    """
    from importlib import metadata  # 50 ms to import: only when asked

    try:
        return metadata.version("celtstone")
    except metadata.PackageNotFoundError:  # pragma: no cover - running from a bare tree
        return "unknown"
