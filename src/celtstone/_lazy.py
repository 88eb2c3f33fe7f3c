"""Public names of a package imported from their modules on first use (PEP 562).

A package's ``__init__`` lists ``name -> module`` and takes the two functions below as its
``__getattr__`` and ``__dir__``: ``import celtstone`` then costs a few milliseconds and a
command imports only what it runs (no numba, SciPy, xarray, matplotlib, Zarr or Dask
before they are needed).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from importlib import import_module
from typing import Any


def lazy_attributes(
    package: str, names: Mapping[str, str], public: list[str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """``__getattr__`` and ``__dir__`` for ``package``: each of ``names`` (name -> module)
    is imported from its module on first use and kept in the package's namespace."""
    namespace = import_module(package).__dict__

    def __getattr__(name: str) -> Any:
        module = names.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(import_module(module), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(public))

    return __getattr__, __dir__
