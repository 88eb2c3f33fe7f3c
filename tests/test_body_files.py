"""Body files: every fault is one line naming the file and the key, never silent physics.

Each case edits one line of a shipped file (so the edit is the only fault, as
``test_every_shipped_file_loads_and_its_copy_too`` shows) and loads it through
``load_body`` and through the CLI (``celtstone run --body FILE``, in-process): exit 2,
exactly one line on standard error naming the file and the key, no traceback.
"""

from __future__ import annotations

import re
import tomllib
from importlib import resources
from pathlib import Path

import pytest

import celtstone as cs
import celtstone.simulation.integrate as integrate_module
from celtstone.bodies import BodyFileError
from celtstone.bodies.file_schema import (
    BODY_ENTRIES,
    DESIGN_ENTRIES,
    SHAPES,
    SOURCE_KEYS,
    TOP_LEVEL,
)
from celtstone.cli.main import main

_DATA = resources.files("celtstone.bodies") / "data"
SHIPPED = sorted(e.name for e in _DATA.iterdir() if e.name.endswith(".toml"))
ELLIPSOID = (_DATA / "kane_levinson_1982.toml").read_text(encoding="utf-8")
PARABOLOID = (_DATA / "kane_levinson_1982_paraboloid.toml").read_text(encoding="utf-8")
TOY = (_DATA / "toy_rattleback_10cm.toml").read_text(encoding="utf-8")
# an egg of docs/bodies.md, with the Kane & Levinson inertia
POLYNOMIAL = re.sub(
    r"\[shape\].*",
    '[shape]\nkind = "implicit_polynomial"\n'
    "terms = [[25.0, 2, 0, 0], [1111.111, 0, 2, 0], [2500.0, 0, 0, 2],\n"
    "         [37500.0, 0, 0, 3], [625000.0, 0, 0, 4]]\n"
    "com_offset = 0.01\n",
    ELLIPSOID,
    flags=re.S,
)
SUPERELLIPSOID = ELLIPSOID.replace('kind = "ellipsoid"', 'kind = "superellipsoid"') + (
    "exponent = 2.0\n"
)


@pytest.fixture(autouse=True)
def no_integration(monkeypatch: pytest.MonkeyPatch) -> None:
    """A refused file never reaches the integrator."""

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("the integrator was called although the body file is invalid")

    monkeypatch.setattr(integrate_module.solvers, "solve", refuse)


def _edit(template: str, key: str, line: str) -> str:
    """The template with its one line ``key = ...`` replaced by ``line`` ("" removes it)."""
    pattern = re.compile(rf"^{re.escape(key)} = .*$\n?", re.MULTILINE)
    assert len(pattern.findall(template)) == 1, key
    return pattern.sub(lambda _: f"{line}\n" if line else "", template)


def _one_line(capsys: pytest.CaptureFixture[str], path: Path) -> str:
    """``celtstone run --body PATH``: exit 2, one stderr line, nothing on stdout."""
    status = main(["run", "--t-end", "1", "--body", str(path)])
    out, err = capsys.readouterr()
    assert status == 2, err
    assert out == ""
    assert "Traceback" not in err and "Warning" not in err
    assert len(err.splitlines()) == 1, err
    return err.strip()


# (id, file text, the key the message names, fragments of the message)
CASES = [
    # unknown keys at every level, with the suggestion
    (
        "typo-in-body",
        _edit(ELLIPSOID, "gravity", "gravty = 1.62"),
        "gravty",
        ("[body]", "did you mean 'gravity'?"),
    ),
    (
        "typo-at-top",
        ELLIPSOID.replace("title = ", "titel = ", 1),
        "titel",
        ("top level", "did you mean 'title'?"),
    ),
    (
        "typo-table-name",
        ELLIPSOID.replace("[shape]", "[shap]"),
        "shap",
        ("[shap]", "did you mean '[shape]'?"),
    ),
    (
        "typo-in-source",
        _edit(ELLIPSOID, "journal", 'jounral = "x"'),
        "jounral",
        ("[source]", "did you mean 'journal'?"),
    ),
    (
        "typo-in-shape",
        _edit(ELLIPSOID, "com_offset", "com_ofset = 0.01"),
        "com_ofset",
        ("[shape]", "ellipsoid", "did you mean 'com_offset'?"),
    ),
    (
        "typo-in-paraboloid",
        _edit(PARABOLOID, "com_height", "com_hieght = 0.01"),
        "com_hieght",
        ("paraboloid", "did you mean 'com_height'?"),
    ),
    (
        "exponent-on-an-ellipsoid",
        ELLIPSOID + "exponent = 3\n",
        "exponent",
        ("ellipsoid", "superellipsoid"),
    ),
    (
        "mass-in-shape",
        ELLIPSOID + "mass = 2.0\n",
        "mass",
        ("[shape]", "[body]"),
    ),
    # booleans, strings and dates where numbers belong
    ("mass-true", _edit(ELLIPSOID, "mass", "mass = true"), "mass", ("boolean",)),
    ("mass-string-number", _edit(ELLIPSOID, "mass", 'mass = "1.0"'), "mass", ("string",)),
    ("gravity-string", _edit(ELLIPSOID, "gravity", 'gravity = "9.81"'), "gravity", ("string",)),
    ("mass-date", _edit(ELLIPSOID, "mass", "mass = 1982-01-01"), "mass", ("date",)),
    (
        "offset-string-number",
        _edit(ELLIPSOID, "com_offset", 'com_offset = "0.01"'),
        "com_offset",
        ("string",),
    ),
    (
        "offset-true",
        _edit(ELLIPSOID, "com_offset", "com_offset = true"),
        "com_offset",
        ("boolean",),
    ),
    (
        "axis-string",
        _edit(ELLIPSOID, "semi_axes", 'semi_axes = [0.20, "0.03", 0.02]'),
        "semi_axes",
        ("string",),
    ),
    (
        "inertia-boolean",
        _edit(
            ELLIPSOID,
            "inertia",
            "inertia = [[2.0e-4, -2.0e-5, false], [-2.0e-5, 1.6e-3, 0.0], [0.0, 0.0, 1.7e-3]]",
        ),
        "inertia",
        ("boolean",),
    ),
    (
        "exponent-string",
        _edit(SUPERELLIPSOID, "exponent", 'exponent = "2"'),
        "exponent",
        ("string",),
    ),
    (
        "mass-beyond-float",
        _edit(ELLIPSOID, "mass", "mass = 1" + "0" * 400),
        "mass",
        ("float range",),
    ),
    # arrays of the wrong length or nesting
    (
        "two-semi-axes",
        _edit(ELLIPSOID, "semi_axes", "semi_axes = [0.20, 0.03]"),
        "semi_axes",
        ("3 numbers", "2 entries"),
    ),
    (
        "nested-semi-axes",
        _edit(ELLIPSOID, "semi_axes", "semi_axes = [[0.20], 0.03, 0.02]"),
        "semi_axes",
        ("nested",),
    ),
    (
        "semi-axes-table",
        _edit(ELLIPSOID, "semi_axes", "semi_axes = {a = 0.2}"),
        "semi_axes",
        ("array",),
    ),
    (
        "inertia-flat-nine",
        _edit(ELLIPSOID, "inertia", "inertia = [2e-4, 0, 0, 0, 1.6e-3, 0, 0, 0, 1.7e-3]"),
        "inertia",
        ("3x3", "9 entries"),
    ),
    (
        "inertia-two-rows",
        _edit(ELLIPSOID, "inertia", "inertia = [[2e-4, 0, 0], [0, 1.6e-3, 0]]"),
        "inertia",
        ("3x3",),
    ),
    (
        "three-radii",
        _edit(PARABOLOID, "radii_of_curvature", "radii_of_curvature = [2.0, 0.045, 1.0]"),
        "radii_of_curvature",
        ("2 numbers",),
    ),
    (
        "mass-array",
        _edit(ELLIPSOID, "mass", "mass = [1.0]"),
        "mass",
        ("one number",),
    ),
    (
        "term-of-three",
        POLYNOMIAL.replace("[25.0, 2, 0, 0]", "[25.0, 2, 0]"),
        "terms",
        ("[c, i, j, k]", "[25.0, 2, 0]"),
    ),
    (
        "term-exponent-float",
        POLYNOMIAL.replace("[25.0, 2, 0, 0]", "[25.0, 2.0, 0, 0]"),
        "terms",
        ("whole number",),
    ),
    (
        "term-exponent-boolean",
        POLYNOMIAL.replace("[25.0, 2, 0, 0]", "[25.0, 2, false, 0]"),
        "terms",
        ("boolean",),
    ),
    (
        "term-coefficient-string",
        POLYNOMIAL.replace("[25.0, 2, 0, 0]", '["25.0", 2, 0, 0]'),
        "terms",
        ("string",),
    ),
    # missing keys, tables and kinds
    ("no-mass", _edit(ELLIPSOID, "mass", ""), "mass", ("[body]", "kg")),
    ("no-inertia", _edit(ELLIPSOID, "inertia", ""), "inertia", ("[body]", "kg m^2")),
    ("no-semi-axes", _edit(ELLIPSOID, "semi_axes", ""), "semi_axes", ("[shape]", "m")),
    ("no-exponent", SUPERELLIPSOID.replace("exponent = 2.0\n", ""), "exponent", ("[shape]",)),
    ("no-kind", _edit(ELLIPSOID, "kind", ""), "kind", ("ellipsoid", "paraboloid")),
    (
        "unknown-kind",
        _edit(ELLIPSOID, "kind", 'kind = "elipsoid"'),
        "elipsoid",
        ("did you mean 'ellipsoid'?", "implicit_polynomial"),
    ),
    ("kind-number", _edit(ELLIPSOID, "kind", "kind = 2"), "kind", ("ellipsoid",)),
    (
        "no-shape-table",
        ELLIPSOID[: ELLIPSOID.index("[shape]")],
        "[shape]",
        ("no [shape] table",),
    ),
    ("body-not-a-table", 'body = "heavy"\n[shape]\nkind = "ellipsoid"\n', "body", ("table",)),
    # text entries
    (
        "title-number",
        re.sub(r"^title = .*$", "title = 3", ELLIPSOID, count=1, flags=re.M),
        "title",
        ("string",),
    ),
    ("source-year-float", _edit(ELLIPSOID, "year", "year = 1982.5"), "year", ("string",)),
    (
        "source-authors-array",
        _edit(ELLIPSOID, "authors", 'authors = ["Kane", "Levinson"]'),
        "authors",
        ("string",),
    ),
    (
        "derivation-boolean",
        TOY.replace("[derivation]\n", "[derivation]\nflag = true\n"),
        "derivation.flag",
        ("number",),
    ),
    # not TOML
    ("bad-toml", ELLIPSOID.replace("[body]", "[body"), "TOML", ("line",)),
]


@pytest.mark.parametrize(
    ("text", "key", "fragments"),
    [case[1:] for case in CASES],
    ids=[case[0] for case in CASES],
)
def test_broken_body_file_is_one_line_naming_file_and_key(
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
    text: str,
    key: str,
    fragments: tuple[str, ...],
) -> None:
    path = tmp_path / "broken.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(BodyFileError) as caught:
        cs.load_body(path)
    assert isinstance(caught.value, cs.ParameterError)
    assert caught.value.file == str(path)
    line = _one_line(capsys, path)
    assert line.startswith(f"celtstone: error: body file {path}: "), line
    assert key in line, line
    for fragment in fragments:
        assert fragment in line, line


def test_a_byte_order_mark_is_allowed(tmp_path: Path) -> None:
    """Spreadsheet and Windows editors write a UTF-8 byte-order mark; the body is the same."""
    path = tmp_path / "kane_levinson_1982.toml"
    path.write_bytes(b"\xef\xbb\xbf" + ELLIPSOID.encode("utf-8"))
    assert cs.load_body(path) == cs.load_body("kane_levinson_1982")


@pytest.mark.parametrize(
    "content",
    [
        bytes(range(256)),  # binary
        ELLIPSOID.encode("latin-1", errors="replace") + "# Müller\n".encode("latin-1"),
        ELLIPSOID.encode("utf-16"),
    ],
    ids=["binary", "latin-1", "utf-16"],
)
def test_bytes_that_are_not_utf8_are_one_line(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, content: bytes
) -> None:
    path = tmp_path / "binary.toml"
    path.write_bytes(content)
    line = _one_line(capsys, path)
    assert f"body file {path}" in line
    assert "UTF-8" in line


@pytest.mark.parametrize("name", SHIPPED)
def test_every_shipped_file_loads_and_its_copy_too(tmp_path: Path, name: str) -> None:
    """Each shipped file passes the checks, by name and as a copy loaded by path."""
    shipped = cs.load_body(name.removesuffix(".toml"))
    copy = tmp_path / name
    copy.write_text((_DATA / name).read_text(encoding="utf-8"), encoding="utf-8")
    assert cs.load_body(copy) == shipped


@pytest.mark.parametrize("text", [POLYNOMIAL, SUPERELLIPSOID], ids=["polynomial", "superellipsoid"])
def test_every_shape_kind_loads_from_a_file(tmp_path: Path, text: str) -> None:
    path = tmp_path / "shape.toml"
    path.write_text(text, encoding="utf-8")
    body = cs.load_body(path)
    assert body.shape.kind in SHAPES


def test_a_source_may_be_one_string_and_a_year_a_number(tmp_path: Path) -> None:
    text = re.sub(
        r"\[source\].*?\n\n", 'source = "Kane and Levinson (1982)"\n\n', ELLIPSOID, flags=re.S
    )
    path = tmp_path / "short.toml"
    path.write_text(text, encoding="utf-8")
    assert cs.load_body(path).source == "Kane and Levinson (1982)"
    path.write_text(_edit(ELLIPSOID, "year", "year = 1982"), encoding="utf-8")
    assert cs.load_body(path).citation["year"] == "1982"


def test_the_declared_keys_are_the_ones_the_loader_accepts(tmp_path: Path) -> None:
    """Every key the tables declare is accepted in its place, and the optional ones
    (gravity) may be left out: the loader reads the declaration, not a list of its own."""
    present = set(tomllib.loads(ELLIPSOID)["source"])
    extra = "".join(f'{key} = "x"\n' for key in SOURCE_KEYS if key not in present)
    path = tmp_path / "all.toml"
    text = _edit(ELLIPSOID, "gravity", "").replace("[source]\n", "[source]\n" + extra)
    path.write_text(text, encoding="utf-8")
    body = cs.load_body(path)
    assert body.gravity == cs.Body.__dataclass_fields__["gravity"].default
    assert set(body.citation) == set(SOURCE_KEYS)
    for kind, shape in SHAPES.items():
        assert shape.kind == kind
        assert {entry.key for entry in shape.entries} <= set(
            shape.build.__dataclass_fields__  # the keys are the shape's own field names
        )
    assert {entry.key for entry in BODY_ENTRIES} <= set(cs.Body.__dataclass_fields__)
    assert {entry.key for entry in DESIGN_ENTRIES} <= set(cs.Design.__dataclass_fields__)
    tables = {"body", "shape", "design", "derivation"}
    assert set(TOP_LEVEL) == {"title", "notes", "source", *tables}
