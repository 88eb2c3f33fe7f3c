"""The installed version, without importing the engine."""

from __future__ import annotations

from importlib import metadata


def version() -> str:
    """The installed celtstone version."""
    try:
        return metadata.version("celtstone")
    except metadata.PackageNotFoundError:  # pragma: no cover - running from a bare tree
        return "unknown"
