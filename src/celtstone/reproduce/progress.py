"""Progress bar of a reproduction (tqdm on stderr), or a silent stand-in."""

from __future__ import annotations

from typing import Protocol

from tqdm import tqdm

__all__ = ["Progress", "progress_bar"]


class Progress(Protocol):
    """What the targets need of a progress bar."""

    total: float | None

    def update(self, n: float = 1) -> bool | None: ...

    def set_description(self, desc: str | None = None, refresh: bool = True) -> None: ...

    def refresh(self) -> None: ...

    def close(self) -> None: ...


def progress_bar(total: int, description: str, enabled: bool) -> Progress:
    """A bar of ``total`` runs; disabled bars print nothing."""
    return tqdm(total=total, desc=description, unit="run", disable=not enabled, leave=True)
