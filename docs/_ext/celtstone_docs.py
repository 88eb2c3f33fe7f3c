"""Pages generated from the code at build time, so that they are never retyped.

* ``api.rst``: one autosummary entry per name of ``celtstone.__all__``;
* ``cli.md``: each ``celtstone`` command's ``--help``, from the argument parsers;

and docstrings read as the plain text they are written in (bars escaped).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import celtstone
from celtstone.cli.main import build_parser


def _api_page() -> str:
    lines = [
        "API reference",
        "=============",
        "",
        "Every public name of ``celtstone`` (``celtstone.__all__``), generated from the",
        "docstrings. Units are SI throughout.",
        "",
        ".. currentmodule:: celtstone",
        "",
        ".. autosummary::",
        "   :toctree: generated",
        "",
    ]
    lines += [f"   {name}" for name in sorted(celtstone.__all__)]
    return "\n".join(lines) + "\n"


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


def _write_if_changed(path: Path, text: str) -> None:
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def _generate(app: Any, config: Any) -> None:
    source = Path(app.srcdir)
    _write_if_changed(source / "api.rst", _api_page())
    _write_if_changed(source / "cli.md", _cli_page())


def _data_docstring(
    app: Any, what: str, name: str, obj: Any, options: Any, lines: list[str]
) -> None:
    """Data of ``celtstone.__all__`` (``MODELS``) is imported lazily, so autodoc finds no
    docstring in ``celtstone/__init__.py`` and offers the type's (``dict``'s): the
    attribute's docstring is read from the module that defines it (``celtstone._LAZY``)."""
    short = name.removeprefix("celtstone.")
    if what != "data" or short not in celtstone._LAZY:
        return
    from sphinx.pycode import ModuleAnalyzer

    docs = ModuleAnalyzer.for_module(celtstone._LAZY[short]).find_attr_docs()
    if ("", short) in docs:
        lines[:] = list(docs["", short])


def _escape_bars(app: Any, what: str, name: str, obj: Any, options: Any, lines: list[str]) -> None:
    """Docstrings write |x| for a magnitude (plain text, as ``help()`` shows them); in
    reStructuredText a bar starts a substitution, so each is escaped."""
    lines[:] = [line.replace("|", "\\|") for line in lines]


def setup(app: Any) -> dict[str, Any]:
    app.connect("config-inited", _generate)  # before autosummary reads api.rst
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
