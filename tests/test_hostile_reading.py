"""Files a user may have edited, and names a file system refuses: one line, exit 2, never
a traceback (issue 37, "Tracebacks and unclear exits").

The oracle of each case is the file's own content: the test breaks a valid run in one
known way and the message must name that way (the attribute, the sample) and the option.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import celtstone as cs
from celtstone.cli.main import main
from celtstone.errors import CeltstoneWarning
from celtstone.files.path_names import TEMPORARY_NAME_EXTRA
from celtstone.reproduce.report import collect
from celtstone.visual.runs import check_run

CELTSTONE = Path(sys.executable).with_name("celtstone")
COMMANDS = ("plot", "view", "animate")
SUFFIX = {"plot": ".png", "view": ".html", "animate": ".gif"}


@pytest.fixture(scope="module")
def sliding_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A short sliding run saved as `celtstone run --out` saves it."""
    path = tmp_path_factory.mktemp("runs") / "sliding.nc"
    arguments = ["run", "--model", "sliding", "--t-end", "0.5", "--out", str(path)]
    assert main(arguments) == 0
    return path


def _drop_attribute(name: str) -> Callable[[xr.Dataset], xr.Dataset]:
    def edit(dataset: xr.Dataset) -> xr.Dataset:
        del dataset.attrs[name]
        return dataset

    return edit


def _set_attribute(name: str, value: object) -> Callable[[xr.Dataset], xr.Dataset]:
    def edit(dataset: xr.Dataset) -> xr.Dataset:
        dataset.attrs[name] = value
        return dataset

    return edit


def _set_value(variable: str, sample: int, value: float) -> Callable[[xr.Dataset], xr.Dataset]:
    def edit(dataset: xr.Dataset) -> xr.Dataset:
        values = dataset[variable].values.copy()
        values[sample] = value
        dataset[variable] = (dataset[variable].dims, values, dataset[variable].attrs)
        return dataset

    return edit


def _retime(change: Callable[[np.ndarray], np.ndarray]) -> Callable[[xr.Dataset], xr.Dataset]:
    def edit(dataset: xr.Dataset) -> xr.Dataset:
        return dataset.assign_coords(time=change(dataset["time"].values.copy()))

    return edit


def _repeat_sample_10(times: np.ndarray) -> np.ndarray:
    times[10] = times[9]
    return times


def _nan_at_3(times: np.ndarray) -> np.ndarray:
    times[3] = np.nan
    return times


# edit -> words the one-line message must hold (what is wrong, where)
EDITS: dict[str, tuple[Callable[[xr.Dataset], xr.Dataset], tuple[str, ...]]] = {
    "no friction coefficient": (_drop_attribute("friction_coefficient"), ("friction_coefficient",)),
    "friction coefficient as text": (
        _set_attribute("friction_coefficient", "abc"),
        ("friction_coefficient = 'abc'",),
    ),
    "negative friction coefficient": (
        _set_attribute("friction_coefficient", -1.0),
        ("friction_coefficient = -1.0",),
    ),
    "unknown friction load": (_set_attribute("friction_load", "psychic"), ("friction_load",)),
    "no model": (_drop_attribute("model"), ("lacks model",)),
    "unknown model": (_set_attribute("model", "quantum"), ("'quantum'",)),
    "no body": (_drop_attribute("body"), ("lacks body",)),
    "initial omega NaN": (_set_attribute("initial_omega", "[0, 0, nan]"), ("initial_omega",)),
    "reversal window text": (_set_attribute("reversal_window", "x"), ("reversal_window",)),
    "NaN quaternion": (_set_value("quaternion", 5, np.nan), ("quaternion", "sample 5")),
    "zero quaternion": (_set_value("quaternion", 7, 0.0), ("quaternion at sample 7",)),
    "infinite spin": (_set_value("spin", 2, np.inf), ("spin", "sample 2")),
    "reversed times": (_retime(lambda t: t[::-1]), ("strictly increasing", "sample 1")),
    "repeated time": (_retime(_repeat_sample_10), ("strictly increasing", "sample 10")),
    "NaN time": (_retime(_nan_at_3), ("finite sample times", "sample 3")),
    "no normal force": (lambda d: d.drop_vars("normal_force"), ("lacks normal_force",)),
}


@pytest.fixture(scope="module")
def edited_files(sliding_file: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("edited")
    files = {}
    for number, (name, (edit, _)) in enumerate(EDITS.items()):
        with xr.open_dataset(sliding_file) as opened:
            dataset = edit(opened.load())
        files[name] = folder / f"edit{number}.nc"
        dataset.to_netcdf(files[name])
    return files


def _one_line(capsys: pytest.CaptureFixture[str]) -> str:
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and "Traceback" not in error, error
    return error.strip()


@pytest.mark.parametrize("command", COMMANDS)
@pytest.mark.parametrize("edit", list(EDITS))
def test_an_edited_run_file_is_one_line_exit_2(
    command: str,
    edit: str,
    edited_files: dict[str, Path],
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    path = edited_files[edit]
    out = tmp_path / f"drawn{SUFFIX[command]}"
    assert main([command, str(path), "--out", str(out)]) == 2
    line = _one_line(capsys)
    assert line.startswith(f"celtstone: error: run = {str(path)!r} is not allowed")
    for words in EDITS[edit][1]:
        assert words in line, line
    assert list(tmp_path.iterdir()) == []


def test_the_unedited_file_is_drawn_by_all_three(sliding_file: Path, tmp_path: Path) -> None:
    """The control: the checks refuse only what the edits broke."""
    for command in COMMANDS:
        out = tmp_path / f"drawn{SUFFIX[command]}"
        assert main([command, str(sliding_file), "--out", str(out)]) == 0
        assert out.stat().st_size > 0


def test_a_file_of_a_newer_celtstone_is_drawn_if_it_reads_and_named_if_not(
    sliding_file: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    with xr.open_dataset(sliding_file) as opened:
        dataset = opened.load()
    dataset.attrs.update(celtstone_version="99.0", format_version=99)
    future = tmp_path / "future.nc"
    dataset.to_netcdf(future)
    assert main(["plot", str(future), "--out", str(tmp_path / "f.png")]) == 0
    capsys.readouterr()
    del dataset.attrs["friction_coefficient"]
    dataset.to_netcdf(broken := tmp_path / "future_broken.nc")
    assert main(["plot", str(broken), "--out", str(tmp_path / "g.png")]) == 2
    line = _one_line(capsys)
    assert "written by celtstone 99.0, newer than this" in line


def test_a_simulated_run_passes_the_check_in_memory() -> None:
    """``check_run`` takes what ``simulate`` gives, rolling and sliding alike."""
    body = cs.load_body("kane_levinson_1982")
    state = cs.InitialState(omega=(0.0, 0.0, -5.0))
    for model in (cs.RollingModel(), cs.SlidingModel()):
        dataset = cs.simulate(model, body, state, 0.2).dataset
        assert check_run(dataset) is dataset


# ---- reproduce --out DIR with files of the user's own in DIR/data ------------------------

UNRELATED_JSON = {
    "list": "[1, 2, 3]",
    "number": "3",
    "text": '"notes"',
    "empty object": "{}",
    "a target without its numbers": '{"target": "fig2"}',
    "t_end as text": '{"target": "fig2", "body": "b", "study": "s", "t_end": "x"}',
    "not JSON": "my notes about the stone",
    "deep nesting": "[" * 100_000,
}


def test_unrelated_json_in_the_data_folder_is_left_out_with_a_warning(tmp_path: Path) -> None:
    data = tmp_path / "data"
    data.mkdir()
    for number, content in enumerate(UNRELATED_JSON.values()):
        (data / f"user{number}.json").write_text(content, encoding="utf-8")
    (data / "latin1.json").write_bytes(b'{"note": "\xe9t\xe9"}')
    (data / "folder.json").mkdir()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert collect(tmp_path) == {}
    left_out = sorted(str(w.message).split(" is left out")[0] for w in caught)
    assert left_out == sorted(str(p) for p in data.iterdir())
    assert all(issubclass(w.category, CeltstoneWarning) for w in caught)


@pytest.mark.slow
def test_reproduce_with_a_users_json_in_data_writes_the_report(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "paper"
    (out / "data").mkdir(parents=True)
    notes = out / "data" / "notes.json"
    notes.write_text(json.dumps({"measured": [1, 2, 3]}), encoding="utf-8")
    status = main(["reproduce", "threshold", "--quick", "--no-progress", "--out", str(out)])
    error = capsys.readouterr().err
    assert status == 0, error
    assert "Traceback" not in error
    assert f"{notes} is left out of the report" in error
    assert json.loads(notes.read_text(encoding="utf-8")) == {"measured": [1, 2, 3]}
    assert (out / "report.md").is_file()


# ---- output names the file system cannot take ---------------------------------------------


def _name_max(folder: Path) -> int:
    return int(os.pathconf(folder, "PC_NAME_MAX"))


def _outputs(folder: Path, name: Callable[[str], str], run: Path) -> dict[str, list[str]]:
    """Each command that writes a file, its output named ``name(suffix)`` in ``folder``."""

    def out(suffix: str) -> str:
        return str(folder / name(suffix))

    return {
        "run": ["run", "--t-end", "0.05", "--out", out(".nc")],
        "export": ["export", str(run), "--csv", "--out", out(".csv")],
        "plot": ["plot", str(run), "--out", out(".png")],
        "view": ["view", str(run), "--out", out(".html")],
        "animate": ["animate", str(run), "--out", out(".gif")],
        "stability": ["stability", "--spin", "-1:1:3", "--csv", out(".csv")],
        "friction": ["friction", "--plot", out(".png")],
        "sweep": [
            "sweep", "--vary", "friction_coefficient=0.1,0.2", "--t-end", "0.05",
            "--out", out(".zarr"),
        ],
        "reproduce": ["reproduce", "fig2", "--quick", "--out", out("")],
    }  # fmt: skip


WRITING_COMMANDS = list(_outputs(Path("."), lambda suffix: "x" + suffix, Path("r")))


@pytest.mark.parametrize("command", WRITING_COMMANDS)
def test_a_name_over_the_file_systems_limit_is_bad_input(
    command: str, sliding_file: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A name the temporary cannot take, even if the final name could: exit 2, named."""
    length = _name_max(tmp_path) - TEMPORARY_NAME_EXTRA + 1

    def too_long(suffix: str) -> str:
        return "n" * (length - len(suffix)) + suffix

    assert main(_outputs(tmp_path, too_long, sliding_file)[command]) == 2
    line = _one_line(capsys)
    assert "is not allowed: expected a file name of at most" in line
    assert list(tmp_path.iterdir()) == []


def test_a_name_at_the_limit_is_written(sliding_file: Path, tmp_path: Path) -> None:
    """The control: the longest allowed name is written, temporary and all."""
    length = _name_max(tmp_path) - TEMPORARY_NAME_EXTRA
    out = tmp_path / ("n" * (length - 3) + ".nc")
    assert len(out.name) == length
    assert main(["run", "--t-end", "0.05", "--out", str(out)]) == 0
    assert [p.name for p in tmp_path.iterdir()] == [out.name]


@pytest.mark.skipif(sys.platform == "darwin", reason="macOS refuses non-UTF-8 names itself")
def test_a_name_that_is_not_utf8_is_bad_input_in_every_command(tmp_path: Path) -> None:
    """Bytes of Latin-1 in a name, as a shell passes them: exit 2 naming the option."""
    run = tmp_path / "run.nc"
    assert main(["run", "--t-end", "0.05", "--out", str(run)]) == 0
    folder = tmp_path / "out"
    folder.mkdir()
    latin1 = os.fsdecode(b"\xe9t\xe9")  # "été" in Latin-1

    def name(suffix: str) -> str:
        return latin1 + suffix

    for command, arguments in _outputs(folder, name, run).items():
        done = subprocess.run(
            [str(CELTSTONE), *arguments], capture_output=True, text=True, errors="replace"
        )
        assert done.returncode == 2, (command, done.stderr)
        assert "Traceback" not in done.stderr
        assert done.stderr.count("\n") == 1, (command, done.stderr)
        assert "expected a path in UTF-8 text" in done.stderr, (command, done.stderr)
        assert list(folder.iterdir()) == [], command


def test_an_error_with_a_full_standard_error_is_still_exit_2() -> None:
    """`celtstone run --t-end -1 2>/dev/full`: the message cannot be written; the status
    still says bad input."""
    if not Path("/dev/full").exists():
        pytest.skip("no /dev/full")
    with open("/dev/full", "w") as full:
        done = subprocess.run([str(CELTSTONE), "run", "--t-end", "-1"], stderr=full)
    assert done.returncode == 2


def test_a_closed_standard_output_ends_quietly() -> None:
    """`celtstone stability ... | head -1`: the reader has gone; no traceback, exit 1
    (output could not be written)."""
    with subprocess.Popen(
        [str(CELTSTONE), "stability", "--spin", "-10:10:2001"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    ) as process:
        assert process.stdout is not None and process.stderr is not None
        first = process.stdout.readline()
        process.stdout.close()  # as `head -1` does
        error = process.stderr.read().decode()
        process.wait()
    assert first.startswith(b"linear stability of steady spin")
    assert "Traceback" not in error and "BrokenPipe" not in error, error
    assert process.returncode == 1
