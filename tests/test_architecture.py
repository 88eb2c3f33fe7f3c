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


def test_every_package_init_only_hands_names_on() -> None:
    """No function or class is defined in a package's ``__init__.py``."""
    offenders = [
        str(init.relative_to(ROOT))
        for init in sorted((ROOT / "src" / "celtstone").rglob("__init__.py"))
        if re.search(r"^\s*(async\s+)?(def|class)\s", init.read_text(encoding="utf-8"), re.M)
    ]
    assert offenders == []
