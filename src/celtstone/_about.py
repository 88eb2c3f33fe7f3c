"""The version, declared once: the package's metadata reads it from here (pyproject.toml)."""

from __future__ import annotations

VERSION = "0.1.0"
"""celtstone's version; ``pyproject.toml`` declares it dynamic, read from this line."""


def version() -> str:
    """Give the celtstone version.

    Returns
    -------
    str
        :data:`VERSION`, which the installed distribution's metadata also carries
        (``importlib.metadata`` took 50-120 ms to import and 2 ms a call to read it, once
        per run).
    """
    return VERSION
