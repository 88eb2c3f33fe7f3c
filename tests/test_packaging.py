"""celtstone installs with pip into an existing environment.

``pyproject.toml`` declares ranges (lower bounds at the versions of
``requirements.lock``, which ``make`` installs exactly); a fast test reads them. The slow
test builds the wheel as pip does (setuptools from the package index) and reads its
metadata; the slow one installs it into a fresh virtual environment from the package
index and runs ``celtstone run`` there.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tomllib
import venv
import zipfile
from email.parser import Parser
from pathlib import Path

import pytest
from packaging.requirements import Requirement

import celtstone

ROOT = Path(__file__).resolve().parents[1]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text("utf-8"))["project"]


def _pinned(requirements: list[str]) -> list[str]:
    """The requirements that allow one version only (``==`` or ``===``)."""
    return [
        text
        for text in requirements
        if any(spec.operator in ("==", "===") for spec in Requirement(text).specifier)
    ]


def _locked() -> dict[str, str]:
    """requirements.lock as {normalised name: version}."""
    locked = {}
    for line in (ROOT / "requirements.lock").read_text("utf-8").splitlines():
        if line and not line.startswith("#"):
            name, _, version = line.partition("==")
            locked[name.strip().lower().replace("_", "-")] = version.strip()
    return locked


def test_the_pinned_finder_finds_a_pin() -> None:
    """The check below can fail: an exact pin is found, a range is not."""
    assert _pinned(["numpy==2.4.6", "scipy>=1.17.1", "numba>=0.68.1,<0.69"]) == ["numpy==2.4.6"]


def test_no_requirement_is_pinned_exactly() -> None:
    """Runtime and optional requirements are ranges, so that pip can fit celtstone into a
    researcher's environment; the exact versions live in requirements.lock."""
    extras = [text for group in PROJECT["optional-dependencies"].values() for text in group]
    assert _pinned(PROJECT["dependencies"]) == []
    assert _pinned(extras) == []


def test_the_locked_versions_satisfy_the_ranges() -> None:
    """``make`` installs requirements.lock: each locked version lies in its declared range,
    so the test suite, run on the lock, tests the lower bounds."""
    locked = _locked()
    for text in PROJECT["dependencies"]:
        requirement = Requirement(text)
        version = locked[requirement.name.lower().replace("_", "-")]
        assert requirement.specifier.contains(version, prereleases=True), (text, version)


def test_the_version_is_declared_once() -> None:
    assert PROJECT["dynamic"] == ["version"]
    assert "version" not in PROJECT
    citation = (ROOT / "CITATION.cff").read_text("utf-8")
    assert f"\nversion: {celtstone.version()}\n" in citation
    assert f"\n## {celtstone.version()}\n" in (ROOT / "CHANGELOG.md").read_text("utf-8")


def test_the_licence_matches_pyproject() -> None:
    assert PROJECT["license"] == {"text": "MIT"}
    assert (ROOT / "LICENSE").read_text("utf-8").startswith("MIT License\n")


def _pip(python: Path, *args: str, cwd: Path = ROOT) -> None:
    done = subprocess.run(
        [str(python), "-m", "pip", "--disable-pip-version-check", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr[-4000:]


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The wheel pip builds from the source tree (build isolation: setuptools from the
    package index, as a user's ``pip install .`` gets it)."""
    out = tmp_path_factory.mktemp("wheel")
    _pip(Path(sys.executable), "wheel", "--no-deps", "--quiet", "-w", str(out), str(ROOT))
    (path,) = out.glob("celtstone-*.whl")
    return path


def test_the_wheels_metadata_has_no_exact_pin(wheel: Path) -> None:
    with zipfile.ZipFile(wheel) as archive:
        (name,) = [n for n in archive.namelist() if n.endswith(".dist-info/METADATA")]
        metadata = Parser().parsestr(archive.read(name).decode("utf-8"))
    assert metadata["Version"] == celtstone.version()
    requires = metadata.get_all("Requires-Dist") or []
    runtime = [text for text in requires if "extra ==" not in text]
    assert len(runtime) == len(PROJECT["dependencies"])
    assert _pinned([text.split(";")[0] for text in requires]) == []
    with zipfile.ZipFile(wheel) as archive:
        names = archive.namelist()
    assert "celtstone/bodies/data/kane_levinson_1982.toml" in names  # package data shipped


@pytest.mark.slow
def test_the_wheel_installs_into_a_fresh_environment_and_runs(wheel: Path, tmp_path: Path) -> None:
    """pip resolves the ranges from the package index in a new venv; the installed
    command runs a short rolling run (numba compiles it there: minutes, once)."""
    environment = tmp_path / "venv"
    venv.EnvBuilder(with_pip=True).create(environment)
    python = environment / "bin" / "python"
    _pip(python, "install", "--quiet", str(wheel), cwd=tmp_path)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba-cache")}
    command = ["run", "--model", "rolling", "--t-end", "0.05", "--json", "--no-progress"]
    done = subprocess.run(
        [str(environment / "bin" / "celtstone"), *command],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env=env,
    )
    assert done.returncode == 0, done.stderr[-4000:]
    summary = json.loads(done.stdout)
    assert summary["model"] == "rolling" and summary["status"] == "success"
