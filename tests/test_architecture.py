"""docs/architecture.md's picture of the layers is the import contract that `make lint`
checks (pyproject.toml), layer for layer and in order."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _contract_layers() -> list[set[str]]:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    (layers,) = (
        c["layers"] for c in config["tool"]["importlinter"]["contracts"] if c["type"] == "layers"
    )
    return [
        {name.strip().strip("()").removeprefix("celtstone.") for name in layer.split("|")}
        for layer in layers
    ]


def _pictured_layers() -> list[set[str]]:
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    picture = text.split("```", 2)[1]
    rows = [line for line in picture.splitlines()[1:] if line and not line.startswith(" ")]
    return [{name.strip() for name in re.split(r"\s{2,}", row)[0].split("|")} for row in rows]


def test_the_pictured_layers_are_the_contract_s() -> None:
    assert _pictured_layers() == _contract_layers()


def test_no_contract_keeps_an_exception() -> None:
    """The contracts describe the real floors: no import is ignored for convenience."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    for contract in config["tool"]["importlinter"]["contracts"]:
        assert not contract.get("ignore_imports"), contract["name"]


def test_every_package_init_only_hands_names_on() -> None:
    """No function or class is defined in a package's ``__init__.py``."""
    offenders = [
        str(init.relative_to(ROOT))
        for init in sorted((ROOT / "src" / "celtstone").rglob("__init__.py"))
        if re.search(r"^\s*(async\s+)?(def|class)\s", init.read_text(encoding="utf-8"), re.M)
    ]
    assert offenders == []


# a file docs/architecture.md names: a path with a folder and a file ending, below the
# repository or the package (``solvers/_<name>.py``: any module of that form)
_NAMED_FILE = re.compile(r"`([\w./<>-]+/[\w.<>-]+\.(?:py|json|md|npz|toml))`")
# a recipe: its heading "Adding ... (N files...)" and what follows, to the next section
_RECIPE = re.compile(r"^(?:## )?Adding (.+?) \((\d+) files\b.*?\n(.*?)(?=^## |\Z)", re.M | re.S)
# a numbered step of a recipe, to the next step or the first blank line
_STEP = re.compile(r"^\d+\. (.*?)(?=^\d+\. |^\s*$|\Z)", re.M | re.S)


def _exists(name: str) -> bool:
    pattern = name.replace("<name>", "*")
    return any(any(base.glob(pattern)) for base in (ROOT, ROOT / "src" / "celtstone"))


def _recipes(text: str) -> dict[str, tuple[int, list[list[str]]]]:
    """Each recipe's subject -> the file count its heading states and, per numbered
    step, the files the step names."""
    return {
        match.group(1): (
            int(match.group(2)),
            [_NAMED_FILE.findall(step) for step in _STEP.findall(match.group(3))],
        )
        for match in _RECIPE.finditer(text)
    }


def test_every_file_the_architecture_names_exists() -> None:
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    named = sorted(set(_NAMED_FILE.findall(text)))
    assert len(named) > 20, named  # the pattern still finds the document's paths
    assert [name for name in named if not _exists(name)] == []


def test_each_recipe_counts_the_files_its_steps_name() -> None:
    """A recipe's heading says how many files it takes; its numbered steps name one
    file each (the first path of a step), all different, all there."""
    recipes = _recipes((ROOT / "docs" / "architecture.md").read_text(encoding="utf-8"))
    assert {"a shape", "a friction law", "an integration method", "an outcome"} <= set(recipes)
    for subject, (count, steps) in recipes.items():
        files = [named[0] for named in steps if named]
        assert len(files) == len(steps), f"adding {subject}: a step names no file"
        assert count == len(files) == len(set(files)), f"adding {subject}: {files}"
        assert all(_exists(name) for name in files), f"adding {subject}: {files}"
