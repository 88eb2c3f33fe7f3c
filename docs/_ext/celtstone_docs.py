"""Pages generated from the code at build time, so that they are never retyped.

* ``api.rst``: one autosummary entry per name of ``celtstone.__all__``, then the
  module pages;
* ``api/MODULE.rst``: one page per public module of :data:`MODULES`, its docstring and
  its public names, each documented once (:func:`documented_at`);
* ``cli.md``: each ``celtstone`` command's ``--help``, from the argument parsers;

and docstrings read as the plain text they are written in (bars escaped).
"""

from __future__ import annotations

import argparse
import ast
import importlib
import inspect
import re
from pathlib import Path
from types import ModuleType
from typing import Any

import celtstone
from celtstone.cli.main import build_parser

#: The public modules documented beside ``celtstone.__all__`` (decisions §33): the
#: subpackages and modules a user imports. ``celtstone.kernels`` and ``celtstone.solvers``
#: (the compiled core under the user API) and ``celtstone.cli`` (the CLI page) are not.
MODULES = (
    "celtstone.analysis",
    "celtstone.atlas",
    "celtstone.bodies",
    "celtstone.contact",
    "celtstone.export",
    "celtstone.fitting",
    "celtstone.plotting",
    "celtstone.reproduce",
    "celtstone.reversals",
    "celtstone.sweep",
    "celtstone.visual",
)
#: modules of MODULES held back from the API pages while their docstrings are rewritten
#: (none now: fitting and atlas landed validated on 2026-11-25)
NOT_YET: tuple[str, ...] = ()


def documented_modules() -> list[str]:
    """The modules that have an API page, in the order of the API page."""
    return [name for name in MODULES if name not in NOT_YET]


def public_names(module: ModuleType) -> list[str]:
    """A module's public names: its ``__all__``, else the functions and classes it defines
    whose names do not start with an underscore."""
    if hasattr(module, "__all__"):
        return list(module.__all__)
    return [
        name
        for name, value in vars(module).items()
        if not name.startswith("_")
        and (inspect.isfunction(value) or inspect.isclass(value))
        and value.__module__ == module.__name__
    ]


def _origin(module: str, name: str) -> tuple[str, str]:
    """Where ``module.name`` comes from: a function's or class's module and name, the
    module that assigns a datum (:func:`_defined_in`)."""
    value = getattr(importlib.import_module(module), name)
    if inspect.isfunction(value) or inspect.isclass(value):
        return value.__module__, value.__qualname__
    return _defined_in(module, name)


def documented_at(module: str, name: str) -> str:
    """The full name under which ``module.name`` is documented, once: ``celtstone.NAME``
    when ``celtstone`` re-exports the same object, the documented module that defines it
    when another one re-exports it (``celtstone.analysis.reversal_band`` is
    ``celtstone.reversals.reversal_band``), else ``module.name``."""
    origin = _origin(module, name)
    if name in celtstone.__all__ and _origin("celtstone", name) == origin:
        return f"celtstone.{name}"
    owners = [m for m in documented_modules() if f"{origin[0]}.".startswith(f"{m}.")]
    return f"{max(owners, key=len) if owners else module}.{name}"


def _api_page() -> str:
    lines = [
        "API reference",
        "=============",
        "",
        "Every public name of ``celtstone`` (``celtstone.__all__``), generated from the",
        "docstrings, then the public modules a user imports, each with its public names",
        "(its ``__all__``). Units are SI throughout.",
        "",
        "Not here: ``celtstone.kernels`` and ``celtstone.solvers``, the compiled core (numba)",
        "under this API, which takes floats, arrays and typed records with integer codes,",
        "not bodies and models (see :doc:`architecture`); ``celtstone.cli``, documented by",
        "the :doc:`cli` generated from its parsers (decisions §33).",
        "",
        ".. currentmodule:: celtstone",
        "",
        ".. autosummary::",
        "   :toctree: generated",
        "",
    ]
    lines += [f"   {name}" for name in sorted(celtstone.__all__)]
    lines += ["", "Modules", "-------", "", ".. toctree::", "   :maxdepth: 1", ""]
    lines += [f"   api/{module}" for module in documented_modules()]
    return "\n".join(lines) + "\n"


def _module_page(module: str) -> str:
    """A module's page: its docstring, the names documented here, and those it re-exports
    from a page of their own (listed, linked, not documented twice)."""
    names = sorted(public_names(importlib.import_module(module)))
    here = [name for name in names if documented_at(module, name) == f"{module}.{name}"]
    elsewhere = [documented_at(module, name) for name in names if name not in here]
    lines = [module, "=" * len(module), "", f".. automodule:: {module}", ""]
    lines += [f".. currentmodule:: {module}", ""]
    if here:
        lines += [".. autosummary::", "   :toctree: ../generated", ""]
        lines += [f"   {name}" for name in here] + [""]
    if elsewhere:
        lines += ["Also importable from here, each documented on its one page:", ""]
        lines += [".. autosummary::", ""] + [f"   ~{full}" for full in elsewhere] + [""]
    return "\n".join(lines)


def _subcommands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def _cli_page() -> str:
    parser = build_parser()
    parts = [
        "# Command-line reference",
        "",
        "Generated from the argument parsers of `celtstone` (`celtstone COMMAND --help`).",
        "",
        "```text",
        parser.format_help().rstrip(),
        "```",
        "",
    ]
    for name, sub in _subcommands(parser).items():
        parts += [f"## `celtstone {name}`", "", "```text", sub.format_help().rstrip(), "```", ""]
    return "\n".join(parts)


def _exclude_from_validation(app: Any, config: Any) -> None:
    """Left out of numpydoc's validation, computed from the documented names: data, whose
    value's docstring numpydoc checks as a function's (``float``'s, ``dict``'s; the page
    shows the docstring written under it, :func:`_data_docstring`), and the constructor
    of a class that has none of its own (``object.__init__``'s docstring is Python's)."""
    names = [f"celtstone.{name}" for name in celtstone.__all__]
    for module in documented_modules():
        names += [f"{module}.{name}" for name in public_names(importlib.import_module(module))]
    excluded = []
    for full in names:
        module, _, name = full.rpartition(".")
        value = getattr(importlib.import_module(module), name)
        if not (inspect.isfunction(value) or inspect.isclass(value)):
            excluded.append(full)
        elif inspect.isclass(value) and value.__init__ is object.__init__:
            excluded.append(f"{full}.__init__")
    patterns = {f"^{re.escape(full)}$" for full in excluded}
    config.numpydoc_validation_exclude = set(config.numpydoc_validation_exclude) | patterns


def _write_if_changed(path: Path, text: str) -> None:
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def _generate(app: Any, config: Any) -> None:
    source = Path(app.srcdir)
    _write_if_changed(source / "api.rst", _api_page())
    pages = source / "api"
    pages.mkdir(exist_ok=True)
    for module in documented_modules():
        _write_if_changed(pages / f"{module}.rst", _module_page(module))
    # pages and autosummary's stubs of names no longer documented (in no toctree: -W fails)
    stubs = {f"celtstone.{name}" for name in celtstone.__all__}
    for module in documented_modules():
        names = public_names(importlib.import_module(module))
        stubs |= {documented_at(module, name) for name in names}
    for stale in set(pages.glob("*.rst")) - {pages / f"{m}.rst" for m in documented_modules()}:
        stale.unlink()
    for stale in (source / "generated").glob("*.rst"):
        if stale.stem not in stubs:
            stale.unlink()
    _write_if_changed(source / "cli.md", _cli_page())


def _defined_in(module: str, name: str) -> tuple[str, str]:
    """The module and name that assign ``module.name``, following ``from M import N as
    name`` (also under ``if TYPE_CHECKING``: ``celtstone``'s lazy names)."""
    tree = ast.parse(inspect.getsource(importlib.import_module(module)))
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            for alias in node.names:
                if (alias.asname or alias.name) == name:
                    return _defined_in(node.module, alias.name)
    return module, name


def _data_docstring(
    app: Any, what: str, name: str, obj: Any, options: Any, lines: list[str]
) -> None:
    """Data (``celtstone.MODELS``, ``celtstone.sweep.DEFAULT_RTOL``) is mostly imported
    from the module that defines it, where its docstring is written under it: autodoc
    finds none in the importing module and offers the value's type's (``dict``'s,
    ``float``'s). The attribute's docstring is read from the defining module."""
    if what != "data":
        return
    module, _, short = name.rpartition(".")
    from sphinx.pycode import ModuleAnalyzer

    source, attribute = _defined_in(module, short)
    lines[:] = list(ModuleAnalyzer.for_module(source).find_attr_docs().get(("", attribute), []))


def _escape_bars(app: Any, what: str, name: str, obj: Any, options: Any, lines: list[str]) -> None:
    """Docstrings write |x| for a magnitude (plain text, as ``help()`` shows them); in
    reStructuredText a bar starts a substitution, so each is escaped."""
    lines[:] = [line.replace("|", "\\|") for line in lines]


def setup(app: Any) -> dict[str, Any]:
    app.connect("config-inited", _generate)  # before autosummary reads api.rst
    app.connect("config-inited", _exclude_from_validation, priority=400)  # before numpydoc reads it
    app.connect("autodoc-process-docstring", _data_docstring, priority=90)
    app.connect("autodoc-process-docstring", _escape_bars, priority=100)
    return {"parallel_read_safe": True, "version": celtstone.version()}


def figure_scraper(block: Any, block_vars: dict[str, Any], gallery_conf: dict[str, Any]) -> str:
    """sphinx-gallery's scraper of the ``Figure`` objects an example holds.

    celtstone's plotting functions return ``matplotlib.figure.Figure`` objects that
    pyplot does not manage, so the default scraper (``plt.get_fignums()``) misses them:
    each such figure bound to a name of the example is saved once, after the code block
    that made it.
    """
    from matplotlib.figure import Figure
    from sphinx_gallery.scrapers import figure_rst

    paths = []
    for value in list(block_vars["example_globals"].values()):
        if not isinstance(value, Figure) or value.canvas.manager is not None:
            continue  # not a figure, or one of pyplot's (the matplotlib scraper's)
        if getattr(value, "_celtstone_scraped", False):
            continue
        path = next(block_vars["image_path_iterator"])
        value.savefig(path)
        value._celtstone_scraped = True  # type: ignore[attr-defined]
        paths.append(path)
    return figure_rst(paths, gallery_conf["src_dir"])
