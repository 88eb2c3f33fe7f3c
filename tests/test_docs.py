"""The documentation site builds with warnings as errors, and lists what the code has.

One build (``sphinx-build -W``, as ``make docs``; numpydoc validates the public API's
docstrings in it) into a temporary directory; then, read from the HTML, not from the
sources: every name of ``celtstone.__all__`` has its page and is listed on the API page;
every command of the CLI has its ``--help`` on the CLI page; every internal link of the
site points at a page that exists; external names link to their projects' sites through
the shipped inventories; the explorer's screenshots it took show ``celtstone run``'s
verdicts. Without the build: every snippet of the user guide runs.
"""

from __future__ import annotations

import argparse
import html
import importlib.util
import json
import re
import shlex
import subprocess
import sys
import warnings
from pathlib import Path
from types import ModuleType

import pytest

import celtstone
from celtstone.cli.main import build_parser, main

# one worker builds the site: two builds at once (one per xdist worker) write the same
# gallery files under docs/auto_examples, and one can read a half-written image
pytestmark = pytest.mark.xdist_group("docs-site")

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


def test_the_tutorial_is_on_the_site_executed(site: Path) -> None:
    """The build ran the notebook (``celtstone_docs.executed_tutorial``): the page holds
    its code, its printed outputs and its figures, and the notebook is downloadable."""
    page = (site / "tutorial.html").read_text("utf-8")
    assert "the rattleback, from a first spin to a sweep" in page
    assert "first reversal [s]:" in page  # a printed output, not only the source
    images = re.findall(r'<img[^>]+src="([^"]+)"', page)
    figures = [src for src in images if "figure_" in src]
    assert len(figures) >= 3, images
    for src in figures:
        assert (site / src).resolve().is_file(), src
    assert "# %%" not in page  # the notebook's cells, not its jupytext source
    assert any((site / "_downloads").rglob("tutorial.ipynb"))


FIRST_SLIDING_PAGES = [
    "auto_examples/plot_01_first_run.html",
    "auto_examples/plot_02_rolling_vs_sliding.html",
    "tutorial.html",
]


@pytest.mark.parametrize("page", FIRST_SLIDING_PAGES)
def test_the_first_sliding_examples_print_no_warning(site: Path, page: str) -> None:
    """The gallery's and the tutorial's outputs, as the build captured them."""
    text = (site / page).read_text("utf-8")
    assert "Warning" not in text and "Coulomb&#39;s bound" not in text, page


def test_the_landing_page_has_a_figure_the_install_line_and_an_example(site: Path) -> None:
    page = (site / "index.html").read_text("utf-8")
    (image,) = re.findall(r'<img[^>]+src="([^"]*spin_reversal[^"]*)"', page)
    assert (site / image).is_file()
    text = html.unescape(re.sub(r"<[^>]+>", "", page))  # highlighting splits the code
    assert "pip install ." in text and "cs.simulate(" in text
    assert "On the influence of sliding on the Celt rattleback motion" in text


def test_the_references_are_in_the_top_navigation(site: Path) -> None:
    """API and CLI references are links of the navigation bar, not under "More"."""
    page = (site / "index.html").read_text("utf-8")
    bar = page[page.index("navbar-header-items__center") :]
    bar = bar[: bar.index("</nav>")]
    dropdown = bar.find("dropdown")  # "More": the pages after the first six
    visible = bar if dropdown < 0 else bar[:dropdown]
    for target in ("getting-started.html", "api.html", "cli.html", "tutorial.html"):
        assert f'href="{target}"' in visible, target


def test_the_api_index_is_public_names_exceptions_last(site: Path) -> None:
    api = (site / "api.html").read_text("utf-8")
    headings = re.findall(r"<h2>([^<]+)<a", api)
    assert headings[0] == "Functions", headings
    assert headings.index("Errors and warnings") > headings.index("Classes"), headings
    for internal in ("atomic_path", "LAW_WORDS", "choice_words"):
        assert not list(site.rglob(f"*{internal}*.html")), internal


def test_equations_are_typeset_offline(site: Path) -> None:
    """The equations page shows its equations as SVG images made at build time; no page
    loads a math script (MathJax would come from a CDN, which the build machines and many
    readers cannot reach)."""
    equations = (site / "equations.html").read_text("utf-8")
    assert equations.count('src="data:image/svg+xml;base64,') >= 6
    for page in site.rglob("*.html"):
        scripts = re.findall(r"<script[^>]*>", page.read_text("utf-8"))
        assert not [s for s in scripts if "mathjax" in s.lower()], page.relative_to(site)


PAPER = "On the influence of sliding on the Celt rattleback motion"


def test_the_paper_is_cited_in_the_readme_the_docs_and_the_report(tmp_path: Path) -> None:
    """Its title as the paper's text gives it (it names no authors)."""
    from celtstone.reproduce.report import render_report

    (tmp_path / "data").mkdir()
    assert PAPER in render_report(tmp_path)
    for page in (DOCS.parent / "README.md", DOCS / "index.md", DOCS.parent / "CITATION.cff"):
        assert PAPER in " ".join(page.read_text("utf-8").split()), page


def test_the_readme_is_for_users() -> None:
    """Short, with no decision numbers and no dated measurement."""
    readme = (DOCS.parent / "README.md").read_text("utf-8")
    assert len(readme.splitlines()) <= 150
    assert "§" not in readme
    assert not re.search(r"\b20\d\d-\d\d-\d\d\b", readme)


def test_the_readme_figure_script_draws(tmp_path: Path) -> None:
    """docs/_static/spin_reversal.png is made by its checked-in script, which still runs."""
    script = _docs_module("make_spin_figure", DOCS / "_static" / "make_spin_figure.py")
    path = script.draw(tmp_path / "figure.png", tmp_path / "first_plot.png")
    for made in (path, tmp_path / "first_plot.png"):
        assert made.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "docs/_static/spin_reversal.png" in (DOCS.parent / "README.md").read_text("utf-8")


CHROMIUM = Path("/usr/bin/chromium")


@pytest.mark.skipif(
    not CHROMIUM.exists(),
    reason="browser tests need Chromium at /usr/bin/chromium (apt-get install chromium)",
)
@pytest.mark.parametrize("page", ["index.html", "getting-started.html", "tutorial.html"])
def test_the_front_pages_in_chromium(site: Path, page: str, tmp_path: Path) -> None:
    """Headless Chromium (Playwright, never a browser of its own) opens the page from the
    built site: it loads, shows figures that have pixels, asks nothing of the network and
    logs no error; its screenshot is written beside the test's files."""
    sync_api = pytest.importorskip("playwright.sync_api")
    errors: list[str] = []
    outside: list[str] = []
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(
            executable_path=str(CHROMIUM),
            args=["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run"],
            headless=True,
        )
        try:
            tab = browser.new_page(viewport={"width": 1280, "height": 900})
            tab.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            tab.on("pageerror", lambda error: errors.append(str(error)))
            tab.on(
                "request",
                lambda r: None if r.url.startswith(("file://", "data:")) else outside.append(r.url),
            )
            tab.goto((site / page).as_uri(), wait_until="load")
            widths = tab.eval_on_selector_all(
                "article img", "images => images.map(i => i.complete ? i.naturalWidth : 0)"
            )
            tab.screenshot(path=str(tmp_path / f"{Path(page).stem}.png"), full_page=False)
        finally:
            browser.close()
    assert widths and min(widths) > 0, widths
    assert errors == []
    assert outside == []


def test_the_explorer_screenshots_show_the_runs_of_the_cli(
    site: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The build's screenshots of the live explorer (``celtstone_docs``, with
    ``docs/_static/make_explorer_screenshots.py``) are the pictures the site publishes, whole
    PNGs of the script's size, and the verdict each shows is ``celtstone run``'s."""
    from tests.e2e.test_explore_browser import _cli_words
    from tests.test_explore_docs import _script, png_size

    script = _script()
    lacking = script.missing()
    if lacking:
        pytest.skip(f"the build kept the committed screenshots: {lacking}")
    extension = _docs_module("celtstone_docs", DOCS / "_ext" / "celtstone_docs.py")
    verdicts = json.loads((site / ".doctrees" / extension.VERDICTS).read_text("utf-8"))
    first, compare = script.NAMES
    assert sorted(verdicts) == sorted(script.NAMES)
    assert main(["run", "--json"]) == 0  # the page's first inputs are the CLI's defaults
    reversal = json.loads(capsys.readouterr().out)["first_reversal_time"]
    assert verdicts[first].startswith(f"reverses at {reversal:.3g} s")
    assert _cli_words("0.15", capsys) in verdicts[compare]
    size = (script.VIEWPORT["width"], script.VIEWPORT["height"])
    published = site / "_static" / "explorer"
    assert all(png_size(published / name) == size for name in script.NAMES)
    taken = site / ".doctrees" / "explorer-screenshots" / "explorer"
    for name in script.NAMES:
        assert (published / name).read_bytes() == (taken / name).read_bytes(), name


def test_the_notebook_is_its_paired_script() -> None:
    """docs/tutorial.ipynb holds the cells of docs/tutorial.py (jupytext, percent format):
    the diffable text and the notebook do not drift apart."""
    import jupytext

    script = jupytext.read(DOCS / "tutorial.py")
    notebook = jupytext.read(DOCS / "tutorial.ipynb")
    assert [(c.cell_type, c.source) for c in notebook.cells] == [
        (c.cell_type, c.source) for c in script.cells
    ]


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
    _run_snippets(page, tmp_path, monkeypatch, capsys)


FRONT_DOOR = [DOCS.parent / "README.md", DOCS / "getting-started.md", DOCS / "index.md"]


@pytest.mark.parametrize("page", FRONT_DOOR, ids=lambda p: p.stem)
def test_the_first_examples_run_without_a_warning(
    page: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """The README's and Getting started's commands and Python blocks run, and print no
    warning: a newcomer's first output is the result (FrictionBoundWarning, ignored in the
    rest of the suite, is an error here; the CLI's one-line warnings go to stderr)."""
    assert "python" in {language for language, _ in _snippets(page)}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _run_snippets(page, tmp_path, monkeypatch, capsys)
    assert "warning" not in capsys.readouterr().err


def test_the_warning_check_can_fail(capsys: pytest.CaptureFixture[str]) -> None:
    """The paper's static load on the same start warns, from the CLI (on stderr) and from
    Python (an error under the filter above): the check above is not vacuous."""
    assert main(["run", "--model", "sliding", "--t-end", "1", "--json"]) == 0
    assert "Coulomb's bound" in capsys.readouterr().err
    with warnings.catch_warnings(), pytest.raises(celtstone.FrictionBoundWarning):
        warnings.simplefilter("error")
        exec(
            "import celtstone as cs\n"
            "cs.simulate(cs.SlidingModel(), cs.load_body('kane_levinson_1982'),"
            " cs.InitialState(), t_end=1.0)\n",
            {},
        )


def _run_snippets(
    page: Path, directory: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Run a page's Python blocks and ``$ celtstone`` lines in order, in ``directory``."""
    monkeypatch.chdir(directory)
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
