"""Pages generated from the code at build time, so that they are never retyped.

* ``api.rst``: one autosummary entry per name of ``celtstone.__all__``, then the
  module pages;
* ``api/MODULE.rst``: one page per public module of :data:`MODULES`, its docstring and
  its public names, each documented once (:func:`documented_at`);
* ``cli.md``: each ``celtstone`` command's ``--help``, from the argument parsers;
* the explorer's screenshots, taken in Chromium when the machine has it;

and docstrings read as the plain text they are written in (bars escaped).
"""

from __future__ import annotations

import argparse
import ast
import importlib
import inspect
import json
import re
from pathlib import Path
from types import ModuleType
from typing import Any

import celtstone
from celtstone.cli.main import build_parser

#: The public modules documented beside ``celtstone.__all__`` (decisions §33): the
#: subpackages and modules a user imports. ``celtstone.kernels`` and ``celtstone.solvers``
#: (the compiled core under the user API), ``celtstone.cli`` (the CLI page) and
#: ``celtstone.files.export`` (the commands' file-writing machinery) are not.
MODULES = (
    "celtstone.atlas",
    "celtstone.bodies",
    "celtstone.contact",
    "celtstone.fitting",
    "celtstone.plotting",
    "celtstone.reproduce",
    "celtstone.simulation.reversals",
    "celtstone.stability",
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
    when another one re-exports it, else ``module.name``."""
    origin = _origin(module, name)
    if name in celtstone.__all__ and _origin("celtstone", name) == origin:
        return f"celtstone.{name}"
    # a documented module above the defining one that lists the name itself
    owners = [
        m
        for m in documented_modules()
        if f"{origin[0]}.".startswith(f"{m}.")
        and name in public_names(importlib.import_module(m))
        and _origin(m, name) == origin
    ]
    return f"{max(owners, key=len) if owners else module}.{name}"


#: the API page's groups of ``celtstone.__all__``, in order, each a test of the value
API_GROUPS: tuple[tuple[str, Any], ...] = (
    ("Functions", inspect.isfunction),
    ("Classes", lambda value: inspect.isclass(value) and not issubclass(value, BaseException)),
    ("Data", lambda value: not (inspect.isfunction(value) or inspect.isclass(value))),
    (
        "Errors and warnings",
        lambda value: inspect.isclass(value) and issubclass(value, BaseException),
    ),
)


def api_groups() -> list[tuple[str, list[str]]]:
    """``celtstone.__all__`` by kind (:data:`API_GROUPS`), each group sorted by name:
    what a user calls first, the exceptions last."""
    groups: list[tuple[str, list[str]]] = []
    for title, belongs in API_GROUPS:
        names = [name for name in celtstone.__all__ if belongs(getattr(celtstone, name))]
        groups.append((title, sorted(names, key=str.lower)))
    return groups


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
        "the :doc:`cli` generated from its parsers.",
        "",
        ".. currentmodule:: celtstone",
        "",
    ]
    for title, names in api_groups():
        if names:
            lines += [title, "-" * len(title), "", ".. autosummary::", "   :toctree: generated"]
            lines += ["", *[f"   {name}" for name in names], ""]
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
    shows the docstring written under it, :func:`_data_docstring`), the constructor
    of a class that has none of its own (``object.__init__``'s docstring is Python's),
    and a Protocol's constructor and parameters (typing's ``*args, **kwargs``)."""
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
        elif inspect.isclass(value) and getattr(value, "_is_protocol", False):
            # a Protocol's constructor is typing's (*args, **kwargs), whose parameters
            # numpydoc would ask the class to document; its members are still checked
            excluded += [full, f"{full}.__init__"]
    patterns = {f"^{re.escape(full)}$" for full in excluded}
    config.numpydoc_validation_exclude = set(config.numpydoc_validation_exclude) | patterns


#: where the executed tutorial is written (Markdown and its figures), beside the sources
TUTORIAL_OUTPUT = "_tutorial"


def _fence(text: str, language: str = "text") -> list[str]:
    """A fenced block longer than any run of backticks in ``text``."""
    longest = max((len(run) for run in re.findall(r"`+", text)), default=0)
    fence = "`" * max(3, longest + 1)
    return [f"{fence}{language}", text.rstrip("\n"), fence, ""]


def _output_markdown(output: Any, figure: Path, link: str) -> list[str]:
    """One output of an executed code cell as Markdown; a PNG is written to ``figure``."""
    import base64

    if output.output_type == "stream":
        if output.name == "stderr":  # a warning or a note: the first examples print none
            raise RuntimeError(f"the tutorial wrote to stderr: {output.text.strip()}")
        return _fence(output.text)
    if output.output_type == "error":
        raise RuntimeError(f"the tutorial failed: {output.ename}: {output.evalue}")
    data = output.get("data", {})
    if "image/png" in data:
        figure.write_bytes(base64.b64decode(data["image/png"]))
        return [f"![a figure of the tutorial]({link})", ""]
    if "text/html" in data:
        return ["```{raw} html", data["text/html"].rstrip("\n"), "```", ""]
    return _fence(data.get("text/plain", "")) if "text/plain" in data else []


def executed_tutorial(notebook_path: Path, out: Path) -> str:
    """Execute the notebook (nbclient, this environment's Python kernel) and give it as
    Markdown: its Markdown cells, each code cell followed by its outputs, each figure a
    PNG in ``out``. An error, or anything written to stderr, stops the build."""
    import os

    import nbformat
    from nbclient import NotebookClient

    os.environ.setdefault("JUPYTER_PREFER_ENV_PATH", "1")  # the venv's kernel, not a user's
    notebook = nbformat.read(notebook_path, as_version=4)
    NotebookClient(
        notebook, timeout=600, kernel_name="python3", resources={"metadata": {"path": out}}
    ).execute()
    lines: list[str] = []
    figures = 0
    for cell in notebook.cells:
        if cell.cell_type == "markdown":
            lines += [cell.source, ""]
            continue
        lines += _fence(cell.source, "python")
        for output in cell.outputs:
            figures += 1
            name = f"figure_{figures:02d}.png"
            lines += _output_markdown(output, out / name, name)
    return "\n".join(lines)


def _tutorial(app: Any) -> None:
    """``_tutorial/tutorial.md``, included by ``tutorial.md``: the notebook, executed."""
    source = Path(app.srcdir)
    out = source / TUTORIAL_OUTPUT
    out.mkdir(exist_ok=True)
    for stale in out.glob("figure_*.png"):
        stale.unlink()
    _write_if_changed(out / "tutorial.md", executed_tutorial(source / "tutorial.ipynb", out))


#: the explorer screenshots' verdicts, ``{picture: verdict}``, written in the build's
#: doctree directory: not published
VERDICTS = "explorer-verdicts.json"


def _explorer_screenshots(app: Any) -> None:
    """Screenshots of the live explorer taken now (``_static/make_explorer_screenshots.py``)
    and published in place of the committed ones in ``_static/explorer``; without
    Chromium, Playwright or Panel the committed ones stay, and the build says so."""
    import importlib.util

    from sphinx.util import logging

    script = Path(app.srcdir) / "_static" / "make_explorer_screenshots.py"
    spec = importlib.util.spec_from_file_location("make_explorer_screenshots", script)
    assert spec is not None and spec.loader is not None
    screenshots = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(screenshots)
    lacking = screenshots.missing()
    if lacking:
        logging.getLogger(__name__).info(f"explorer screenshots: the committed ones ({lacking})")
        return
    taken = Path(app.doctreedir) / "explorer-screenshots"
    verdicts = screenshots.take(taken / "explorer")
    # what each picture shows, for the test that compares it with ``celtstone run``
    # (tests/test_docs.py)
    (Path(app.doctreedir) / VERDICTS).write_text(json.dumps(verdicts, indent=1), encoding="utf-8")
    # copied after the source's _static, so these replace the committed pictures
    app.config.html_static_path = [*app.config.html_static_path, str(taken)]


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


def math_svg(latex: str, display: bool = False) -> str:
    """``latex`` typeset by matplotlib's mathtext as an SVG image, as a data URI: the
    equations need no script and no network in the reader's browser, and the build needs
    no LaTeX (mathtext reads the subset of TeX the pages use)."""
    import base64
    import io

    import matplotlib
    from matplotlib.mathtext import math_to_image

    buffer = io.BytesIO()
    size = 13 if display else 11
    with matplotlib.rc_context({"mathtext.fontset": "cm", "svg.fonttype": "path"}):
        math_to_image(f"${latex}$", buffer, prop=_font(size), format="svg", color="black")
    return "data:image/svg+xml;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def _font(size: float) -> Any:
    from matplotlib.font_manager import FontProperties

    return FontProperties(size=size)


def _math_image(translator: Any, node: Any, display: bool) -> None:
    from docutils import nodes

    latex = node.astext()
    alt = translator.encode(latex)
    image = f'<img class="math" src="{math_svg(latex, display)}" alt="{alt}">'
    if display:
        translator.body.append(f'<div class="math notranslate">{image}</div>')
    else:
        translator.body.append(f'<span class="math notranslate">{image}</span>')
    raise nodes.SkipNode


def _visit_inline_math(translator: Any, node: Any) -> None:
    _math_image(translator, node, display=False)


def _visit_display_math(translator: Any, node: Any) -> None:
    _math_image(translator, node, display=True)


def setup(app: Any) -> dict[str, Any]:
    # equations as SVG made at build time (math_svg): no MathJax from a CDN
    app.add_html_math_renderer("mathtext", (_visit_inline_math, None), (_visit_display_math, None))
    app.connect("config-inited", _generate)  # before autosummary reads api.rst
    app.connect("builder-inited", _tutorial)
    app.connect("builder-inited", _explorer_screenshots)
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
