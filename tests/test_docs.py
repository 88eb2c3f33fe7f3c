"""The documentation site builds with warnings as errors, and lists what the code has.

One build (``sphinx-build -W``, as ``make docs``; numpydoc validates the public API's
docstrings in it) into a temporary directory; then, read from the HTML, not from the
sources: every name of ``celtstone.__all__`` has its page and is listed on the API page;
every command of the CLI has its ``--help`` on the CLI page; every internal link of the
site points at a page that exists; external names link to their projects' sites through
the shipped inventories. Without the build: every snippet of the user guide runs.
"""

from __future__ import annotations

import argparse
import importlib.util
import re
import shlex
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest

import celtstone
from celtstone.cli.main import build_parser, main

DOCS = Path(__file__).resolve().parents[1] / "docs"
SPHINX = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html"]


def _commands() -> list[str]:
    """The CLI's commands, read from its parser."""
    actions = build_parser()._actions
    (commands,) = [a for a in actions if isinstance(a, argparse._SubParsersAction)]
    return list(commands.choices)


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("site")
    build = subprocess.run(
        # every example runs, not only those changed since the last build in the tree
        [*SPHINX, "-D", "sphinx_gallery_conf.run_stale_examples=True", DOCS, out],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert build.returncode == 0, build.stderr[-4000:]
    return out


def test_the_api_page_lists_every_public_name(site: Path) -> None:
    api = (site / "api.html").read_text(encoding="utf-8")
    for name in celtstone.__all__:
        page = f"generated/celtstone.{name}.html"
        assert f'href="{page}' in api, name
        assert (site / page).is_file(), name


def test_the_module_pages_list_every_public_name(site: Path) -> None:
    """Each public module the API page links has a page that links every public name of
    the module (its ``__all__``) to the page documenting that very object: the link's
    title, imported, is the module's attribute (a re-exported name links the one page
    of its object)."""
    extension = _docs_module("celtstone_docs", DOCS / "_ext" / "celtstone_docs.py")
    modules = extension.documented_modules()
    assert {"celtstone.bodies", "celtstone.sweep", "celtstone.visual"} <= set(modules)
    api = (site / "api.html").read_text(encoding="utf-8")
    for name in modules:
        assert f'href="api/{name}.html"' in api, name
        page = site / "api" / f"{name}.html"
        links = re.findall(r'href="([^"#]+)#[^"]*" title="([^"]+)"', page.read_text("utf-8"))
        module = importlib.import_module(name)
        public = module.__all__ if hasattr(module, "__all__") else extension.public_names(module)
        for short in public:
            value = getattr(module, short)
            targets = [
                href
                for href, title in links
                if title.rpartition(".")[2] == short
                and getattr(importlib.import_module(title.rpartition(".")[0]), short) is value
            ]
            assert targets, f"{name}.{short}"
            assert (page.parent / targets[0]).is_file(), f"{name}.{short}"


def test_the_cli_page_is_every_commands_help(site: Path) -> None:
    cli = (site / "cli.html").read_text(encoding="utf-8")
    commands = _commands()
    assert {"run", "sweep", "reproduce", "fit"} <= set(commands)
    for command in commands:
        assert f"usage: celtstone {command}" in cli, command


def test_internal_links_resolve(site: Path) -> None:
    """Every relative href of every page names a file of the site, and its anchor (the
    guide's links into the decisions and the equations) an id on that page."""
    broken = []
    pages: dict[Path, str] = {}
    for page in site.rglob("*.html"):
        text = pages.setdefault(page.resolve(), page.read_text("utf-8"))
        for target, anchor in re.findall(r'href="([^"#:?]*)(?:#([^"]*))?"', text):
            path = (page.parent / target).resolve() if target else page.resolve()
            if not path.exists():
                broken.append(f"{page.relative_to(site)} -> {target}")
            elif anchor and path.suffix == ".html":
                if f'id="{anchor}"' not in pages.setdefault(path, path.read_text("utf-8")):
                    broken.append(f"{page.relative_to(site)} -> {target}#{anchor}")
    assert broken == []


EXAMPLES = sorted((DOCS / "examples").glob("plot_*.py"))


def test_the_gallery_has_its_examples() -> None:
    assert len(EXAMPLES) >= 8


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda path: path.stem)
def test_every_example_made_its_figure(site: Path, example: Path) -> None:
    """Each example's page exists, is on the gallery's index and embeds a figure the
    build made (sphinx-gallery names them ``sphx_glr_<example>_NNN.png``)."""
    page = site / "auto_examples" / f"{example.stem}.html"
    assert page.is_file()
    assert f'href="{example.stem}.html' in (site / "auto_examples" / "index.html").read_text(
        "utf-8"
    )
    images = re.findall(r'<img[^>]+src="([^"]+)"', page.read_text("utf-8"))
    figures = [src for src in images if f"sphx_glr_{example.stem}_" in src]
    assert figures, images
    for src in figures:
        assert (page.parent / src).resolve().is_file(), src


def test_the_tutorial_is_on_the_site(site: Path) -> None:
    page = (site / "tutorial.html").read_text("utf-8")
    assert "Tutorial notebook" in page
    assert any((site / "_downloads").rglob("tutorial.ipynb"))


def test_the_notebook_is_its_paired_script() -> None:
    """docs/tutorial.ipynb holds the cells of docs/tutorial.py (jupytext, percent format):
    the diffable text and the notebook do not drift apart."""
    import jupytext

    script = jupytext.read(DOCS / "tutorial.py")
    notebook = jupytext.read(DOCS / "tutorial.ipynb")
    assert [(c.cell_type, c.source) for c in notebook.cells] == [
        (c.cell_type, c.source) for c in script.cells
    ]


def test_the_tutorial_notebook_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Every cell of the notebook runs without error (nbclient, a fresh kernel of this
    environment's Python, not one a user installed) and the figures render."""
    import nbformat
    from jupyter_client.kernelspec import KernelSpecManager
    from nbclient import NotebookClient

    monkeypatch.setenv("JUPYTER_PREFER_ENV_PATH", "1")
    spec = KernelSpecManager().get_kernel_spec("python3")
    assert Path(spec.resource_dir).is_relative_to(sys.prefix), spec.resource_dir
    assert spec.argv[0] == "python", spec.argv  # jupyter_client runs sys.executable

    notebook = nbformat.read(DOCS / "tutorial.ipynb", as_version=4)
    NotebookClient(
        notebook, timeout=300, kernel_name="python3", resources={"metadata": {"path": tmp_path}}
    ).execute()
    outputs = [o for c in notebook.cells if c.cell_type == "code" for o in c.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    assert sum("image/png" in o.get("data", {}) for o in outputs) >= 3


def _docs_module(name: str, path: Path) -> ModuleType:
    """A script of docs/ (the inventories' writer, the extension), imported by path."""
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _inventories() -> ModuleType:
    return _docs_module("inventories", DOCS / "_inventories" / "make.py")


def test_the_shipped_inventories_are_what_make_py_writes() -> None:
    """docs/_inventories/*.inv are the declared names, and Sphinx reads them."""
    from sphinx.util.inventory import InventoryFile

    inventories = _inventories()
    assert {"numpy", "scipy", "xarray", "matplotlib"} <= set(inventories.PROJECTS)
    for key, project in inventories.PROJECTS.items():
        shipped = (DOCS / "_inventories" / f"{key}.inv").read_bytes()
        assert shipped == inventories.inventory(project), f"rerun docs/_inventories/make.py ({key})"
        loaded = InventoryFile.loads(shipped, uri=project.base_url)
        names = {name for items in loaded.data.values() for name in items}
        assert names == {name for name, _, _ in project.objects}


@pytest.mark.parametrize(
    ("page", "url"),
    [
        (
            "generated/celtstone.simulate.html",
            "https://numpy.org/doc/stable/reference/generated/numpy.ndarray.html#numpy.ndarray",
        ),
        (
            "generated/celtstone.open_sweep.html",
            "https://docs.xarray.dev/en/stable/generated/xarray.Dataset.html#xarray.Dataset",
        ),
        (
            "guide/visuals.html",
            "https://matplotlib.org/stable/api/_as_gen/matplotlib.figure.Figure.html#matplotlib.figure.Figure",
        ),
        (
            "guide/models.html",
            "https://docs.scipy.org/doc/scipy/reference/generated/scipy.integrate.Radau.html#scipy.integrate.Radau",
        ),
    ],
)
def test_external_names_link_to_their_projects(site: Path, page: str, url: str) -> None:
    """intersphinx, offline: a type in a docstring or a role in a page links to the page
    of its project (numpy.ndarray to numpy.org, ...)."""
    assert f'href="{url}"' in (site / page).read_text("utf-8")


GUIDE = sorted((DOCS / "guide").glob("*.md"))
# minutes each (make run): their command lines are parsed here, not run
PARSE_ONLY = {"reproduce"}


def _snippets(page: Path) -> list[tuple[str, str]]:
    """The ``python`` and ``console`` blocks of a guide page, in order."""
    text = page.read_text("utf-8")
    return re.findall(r"^```(python|console)\n(.*?)^```", text, flags=re.MULTILINE | re.DOTALL)


@pytest.mark.parametrize("page", [p for p in GUIDE if _snippets(p)], ids=lambda p: p.stem)
def test_the_guide_runs(
    page: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Every Python block of a guide page runs, in order, in one namespace, and every
    ``$ celtstone ...`` line exits 0 (in-process, in the same directory: a file one
    line writes, the next reads)."""
    monkeypatch.chdir(tmp_path)
    namespace: dict[str, object] = {"__name__": f"guide_{page.stem}"}
    for language, code in _snippets(page):
        if language == "python":
            exec(compile(code, str(page), "exec"), namespace)
            continue
        for line in code.splitlines():
            assert line.startswith("$ celtstone "), line
            argv = shlex.split(line.removeprefix("$ celtstone "))
            if argv[0] in PARSE_ONLY:
                build_parser().parse_args(argv)  # a wrong option exits 2
            else:
                assert main(argv) == 0, (line, capsys.readouterr().err[-2000:])
