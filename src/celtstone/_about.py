"""The installed version, without importing the engine."""

from __future__ import annotations


def version() -> str:
    """The installed celtstone version."""
    from importlib import metadata  # 50 ms to import: only when asked

    try:
        return metadata.version("celtstone")
    except metadata.PackageNotFoundError:  # pragma: no cover - running from a bare tree
        return "unknown"
