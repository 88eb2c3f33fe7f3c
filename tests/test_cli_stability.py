"""``celtstone stability`` in-process: JSON, text, files, and one-line errors.

Expected numbers come from the exact quartic of ../shared/references.md
(``characteristic_roots``) or from the options given, never from an earlier run.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import celtstone as cs
from tests.physics.test_published import characteristic_roots
from tests.test_cli import Result


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory) -> tuple[Result, Path]:
    folder = tmp_path_factory.mktemp("stability")
    result = Result(
        [
            "stability",
            "--body",
            "kane_levinson_1982",
            "--spin",
            "-10:10:21",
            "--damping",
            "0",
            "--json",
            "--csv",
            str(folder / "table.csv"),
            "--netcdf",
            str(folder / "table.nc"),
            "--plot",
            str(folder / "growth.svg"),
        ]
    )
    return result, folder


def test_json_holds_spins_eigenvalues_and_options(written: tuple[Result, Path]) -> None:
    result, folder = written
    assert result.status == 0, result.err
    summary = result.json()
    spins = np.linspace(-10.0, 10.0, 21)
    assert summary["spin"] == list(spins)
    body = cs.load_body("kane_levinson_1982")
    for spin, pairs in zip(spins, summary["eigenvalues"], strict=True):
        values = np.sort_complex(np.array([complex(re, im) for re, im in pairs]))
        roots = np.sort_complex(characteristic_roots(body, spin))
        assert np.allclose(values, roots, rtol=1e-8, atol=0.0)
    for key, value in {
        "body": "kane_levinson_1982",
        "model": "rolling",
        "damping": 0.0,
        "spin_range": "-10:10:21",
        "spin_start": -10.0,
        "spin_stop": 10.0,
        "spin_count": 21,
        "csv": str(folder / "table.csv"),
        "netcdf": str(folder / "table.nc"),
        "plot": str(folder / "growth.svg"),
        "preferred_spin_direction": "positive",
    }.items():
        assert summary[key] == value, key


def test_files_are_written_with_the_options(written: tuple[Result, Path]) -> None:
    result, folder = written
    summary = result.json()
    lines = (folder / "table.csv").read_text().splitlines()
    data = [line.split(",") for line in lines if not line.startswith("#")]
    header, rows = data[0], np.array(data[1:], dtype=float)
    assert rows.shape == (21, len(header))
    assert np.array_equal(rows[:, header.index("spin")], summary["spin"])
    assert np.array_equal(rows[:, header.index("growth_rate_roll")], summary["growth_rate_roll"])
    with xr.open_dataset(folder / "table.nc") as dataset:
        for key in ("body", "model", "damping", "spin_start", "spin_stop", "spin_count"):
            assert dataset.attrs[key] == summary[key], key
        assert dataset.attrs["spin_range"] == "-10:10:21"
        assert np.array_equal(dataset["growth_rate_pitch"].values, summary["growth_rate_pitch"])
    assert (folder / "growth.svg").read_text().lstrip().startswith("<?xml")
    assert not list(folder.glob("*.part"))


def test_text_output_names_the_preference() -> None:
    result = Result(["stability", "--spin", "-1:1:3"])
    assert result.status == 0, result.err
    assert "preferred spin direction: positive" in result.out
    assert len(result.out.splitlines()) == 4 + 3


def test_png_plot_is_written_whole(tmp_path: Path) -> None:
    target = tmp_path / "growth.png"
    result = Result(["stability", "--spin", "-2:2:5", "--plot", str(target)])
    assert result.status == 0, result.err
    assert target.read_bytes().startswith(b"\x89PNG")
    assert [p.name for p in tmp_path.iterdir()] == ["growth.png"]


@pytest.mark.parametrize(
    ("argv", "name"),
    [
        (["--spin", "-10:10"], "spin"),
        (["--spin", "10:-10:5"], "spin"),
        (["--spin", "0:1:x"], "spin"),
        (["--damping", "-1"], "damping"),
        (["--damping", "lots"], "damping"),
        (["--body", "kane_levinsn_1982"], "body"),
        (["--plot", "figure.pdf"], "plot"),
        (["--csv", "table.txt"], "csv"),
        (["--netcdf", "table.csv"], "netcdf"),
        (["--csv", "/no/such/folder/table.csv"], "csv"),
        (["--plot", "/no/such/folder/growth.png"], "plot"),
    ],
)
def test_bad_input_is_one_line(argv: list[str], name: str, tmp_path: Path) -> None:
    result = Result(["stability", *argv])
    assert result.status == 2
    assert result.out == ""
    assert result.err.count("\n") == 1
    assert result.err.startswith(f"celtstone: error: {name} = ")


def test_json_is_valid_for_a_single_spin() -> None:
    result = Result(["stability", "--spin", "5:5:1", "--json"])
    assert result.status == 0, result.err
    summary = json.loads(result.out)
    assert summary["spin"] == [5.0]
    assert len(summary["eigenvalues"]) == 1 and len(summary["eigenvalues"][0]) == 4
