"""The documentation site builds with warnings as errors, and lists what the code has.

One build (``sphinx-build -W``, as ``make docs``) into a temporary directory; then, read
from the HTML, not from the sources: every name of ``celtstone.__all__`` has its page
and is listed on the API page; every command of the CLI has its ``--help`` on the CLI
page; every internal link of the site points at a page that exists.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from pathlib import Path

import pytest

import celtstone
from celtstone.cli.main import build_parser

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


def test_the_cli_page_is_every_commands_help(site: Path) -> None:
    cli = (site / "cli.html").read_text(encoding="utf-8")
    commands = _commands()
    assert {"run", "sweep", "reproduce", "fit"} <= set(commands)
    for command in commands:
        assert f"usage: celtstone {command}" in cli, command


def test_internal_links_resolve(site: Path) -> None:
    """Every relative href of every page names a file of the site (anchors aside)."""
    broken = []
    for page in site.rglob("*.html"):
        for target in re.findall(r'href="([^"#:?]+)(?:#[^"]*)?"', page.read_text("utf-8")):
            if not (page.parent / target).resolve().exists():
                broken.append(f"{page.relative_to(site)} -> {target}")
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
