"""A command replaces only what it wrote itself, and only with --overwrite.

Each case of the issue's "Data loss" list, from the command line (``main`` in-process)
and from Python where the writer is public. The oracle is the file system: every file a
user put anywhere is still there, byte for byte (``_snapshot``), and the refusal is one
line, exit status 2, naming the file that stopped it.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import celtstone as cs
from celtstone.cli.main import main
from celtstone.files import ownership
from celtstone.fitting.outputs import write_fit
from celtstone.reproduce import Study, reproduce, write_report
from celtstone.reproduce import report as report_module

KL = "kane_levinson_1982"
TOY = "toy_rattleback_10cm"
SHIPPED_BODIES = Path(cs.__file__).parent / "bodies" / "data"


def _snapshot(directory: Path) -> dict[str, bytes | None]:
    """Every entry under ``directory`` (hidden ones too): file bytes, None for a directory."""
    return {
        str(p.relative_to(directory)): None if p.is_dir() else p.read_bytes()
        for p in sorted(directory.rglob("*"))
    }


def _refusal(capsys: pytest.CaptureFixture[str], status: int) -> str:
    """The one line on stderr of a command refused with exit status 2."""
    out, err = capsys.readouterr()
    assert status == 2, (out, err)
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("celtstone: error: "), err
    return lines[0]


# ---------------------------------------------------------------------------------------
# fit: a former fit with the user's files in it, a copied summary.json
# ---------------------------------------------------------------------------------------


def _gyro_record(path: Path, body: cs.Body) -> Path:
    """A short gyroscope record of the sliding model (f = 0.3) with a little noise."""
    state = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
    times = np.linspace(0.0, 0.5, 51)
    run = cs.simulate(
        cs.SlidingModel(friction_coefficient=0.3), body, state, 0.5, sample_times=times
    )
    rates = run.samples.values("omega") + np.random.default_rng(1).normal(0.0, 0.01, (51, 3))
    header = '"Time (s)","Gyroscope x (rad/s)","Gyroscope y (rad/s)","Gyroscope z (rad/s)"'
    rows = "".join(f"{t},{x},{y},{z}\n" for t, (x, y, z) in zip(times, rates, strict=True))
    path.write_text(header + "\n" + rows, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def fit_run(tmp_path_factory: pytest.TempPathFactory, kane_levinson: cs.Body) -> dict[str, Any]:
    """One fit, written by the CLI into ``fit``: its arguments and the FitResult."""
    root = tmp_path_factory.mktemp("fit")
    data = _gyro_record(root / "gyro.csv", kane_levinson)
    argv = [
        "fit", str(data), "--body", KL, "--free", "friction_coefficient",
        "--start", "friction_coefficient=0.25", "--no-progress",
    ]  # fmt: skip
    record = cs.read_record(data)  # phyphox's columns: omega1..3
    with warnings.catch_warnings():  # the initial state held at the first sample: meant
        warnings.simplefilter("ignore", cs.CeltstoneWarning)
        result = cs.fit(
            record, kane_levinson, "sliding", ["friction_coefficient"],
            start={"friction_coefficient": 0.25},
        )  # fmt: skip
    return {"argv": argv, "data": data, "result": result}


@pytest.fixture(scope="module")
def written_fit(tmp_path_factory: pytest.TempPathFactory, fit_run: dict[str, Any]) -> Path:
    """The fit of ``fit_run`` written by the CLI into a directory of its own, once."""
    out = tmp_path_factory.mktemp("written") / "fit"
    assert main([*fit_run["argv"], "--out", str(out)]) == 0
    assert ownership.MANIFEST in {p.name for p in out.iterdir()}
    return out


def _former_fit(written_fit: Path, tmp_path: Path) -> Path:
    """A copy of ``written_fit`` in ``tmp_path``: the manifest names its files relative
    to the directory, so the copy is celtstone's own fit as much as the original."""
    return Path(shutil.copytree(written_fit, tmp_path / "fit"))


@pytest.mark.parametrize("user_file", ["notes.txt", "input data", "edited summary"])
def test_fit_overwrite_keeps_a_former_fit_with_user_files(
    capsys: pytest.CaptureFixture[str],
    fit_run: dict[str, Any],
    written_fit: Path,
    tmp_path: Path,
    user_file: str,
) -> None:
    out = _former_fit(written_fit, tmp_path)
    capsys.readouterr()
    argv = fit_run["argv"]
    if user_file == "notes.txt":
        (out / "notes.txt").write_text("my notes\n", encoding="utf-8")
        named = out / "notes.txt"
    elif user_file == "input data":  # the record being fitted, moved into the former fit
        named = out / "gyro.csv"
        shutil.copy(fit_run["data"], named)
        argv = [argv[0], str(named), *argv[2:]]
    else:
        named = out / "summary.json"
        named.write_text(named.read_text(encoding="utf-8") + " ", encoding="utf-8")
    before = _snapshot(tmp_path)
    line = _refusal(capsys, main([*argv, "--out", str(out), "--overwrite"]))
    assert line.startswith(f"celtstone: error: out = '{out}'"), line
    assert str(named) in line, line
    assert _snapshot(tmp_path) == before
    with pytest.raises(cs.ParameterError, match="out = ") as caught:
        write_fit(fit_run["result"], out, overwrite=True)
    assert str(named) in str(caught.value)
    assert _snapshot(tmp_path) == before


def test_fit_overwrite_keeps_a_folder_with_only_a_fit_like_summary(
    capsys: pytest.CaptureFixture[str], fit_run: dict[str, Any], written_fit: Path, tmp_path: Path
) -> None:
    out = _former_fit(written_fit, tmp_path)
    copy = tmp_path / "copy"
    copy.mkdir()
    shutil.copy(out / "summary.json", copy / "summary.json")
    assert json.loads((copy / "summary.json").read_text())["format"] == "celtstone-fit-1"
    capsys.readouterr()
    before = _snapshot(tmp_path)
    line = _refusal(capsys, main([*fit_run["argv"], "--out", str(copy), "--overwrite"]))
    assert f"out = '{copy}'" in line and ownership.MANIFEST in line, line
    with pytest.raises(cs.ParameterError, match=ownership.MANIFEST):
        write_fit(fit_run["result"], copy, overwrite=True)
    assert _snapshot(tmp_path) == before


def test_fit_overwrite_replaces_its_own_unchanged_fit(
    capsys: pytest.CaptureFixture[str], fit_run: dict[str, Any], written_fit: Path, tmp_path: Path
) -> None:
    """The control: what the rule allows still works, and the manifest lists the files."""
    out = _former_fit(written_fit, tmp_path)
    manifest = json.loads((out / ownership.MANIFEST).read_text(encoding="utf-8"))
    first_id = manifest["id"]
    assert sorted(manifest["files"]) == sorted(
        p.name for p in out.iterdir() if p.name != ownership.MANIFEST
    )
    assert main([*fit_run["argv"], "--out", str(out), "--overwrite"]) == 0, capsys.readouterr()
    assert json.loads((out / ownership.MANIFEST).read_text(encoding="utf-8"))["id"] != first_id
    write_fit(fit_run["result"], out, overwrite=True)
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".part")]


# ---------------------------------------------------------------------------------------
# sweep: the user's files inside a store; a second writer
# ---------------------------------------------------------------------------------------

SWEEP = ["sweep", "--t-end", "0.05", "--workers", "1", "--no-progress", "--no-maps"]
VARY = ["--vary", "friction_coefficient=0.1,0.3"]


@pytest.fixture(scope="module")
def written_store(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A finished sweep store, written once by the CLI."""
    path = tmp_path_factory.mktemp("written") / "s.zarr"
    assert main([*SWEEP, *VARY, "--out", str(path)]) == 0
    return path


@pytest.fixture
def store(written_store: Path, tmp_path: Path) -> Path:
    """A copy of ``written_store`` in ``tmp_path`` (its manifest is relative, as a fit's)."""
    return Path(shutil.copytree(written_store, tmp_path / "s.zarr"))


@pytest.mark.parametrize("where", ["notes.txt", "status/notes.txt", "status/c/notes"])
def test_sweep_overwrite_keeps_a_store_with_user_files(
    capsys: pytest.CaptureFixture[str], store: Path, tmp_path: Path, where: str
) -> None:
    notes = store / where
    notes.parent.mkdir(parents=True, exist_ok=True)
    notes.write_text("observations\n", encoding="utf-8")
    capsys.readouterr()
    before = _snapshot(tmp_path)
    line = _refusal(capsys, main([*SWEEP, *VARY, "--out", str(store), "--overwrite"]))
    assert f"out = '{store}'" in line and str(notes) in line, line
    assert _snapshot(tmp_path) == before
    sweep = cs.Sweep({"friction_coefficient": [0.1, 0.3]}, t_end=0.05)
    with pytest.raises(cs.ParameterError, match="notes"):
        sweep.run(store, overwrite=True, workers=1)
    assert _snapshot(tmp_path) == before


def test_sweep_overwrite_keeps_the_points_file_it_reads(
    capsys: pytest.CaptureFixture[str], store: Path, tmp_path: Path
) -> None:
    points = store / "points.csv"
    points.write_text("friction_coefficient\n0.2\n", encoding="utf-8")
    capsys.readouterr()
    before = _snapshot(tmp_path)
    argv = [*SWEEP, "--points", str(points), "--out", str(store), "--overwrite"]
    line = _refusal(capsys, main(argv))
    assert f"out = '{store}'" in line and str(points) in line, line
    assert _snapshot(tmp_path) == before


def test_sweep_overwrite_replaces_its_own_store(store: Path) -> None:
    """The control: a store holding only its own files (a finished one) is replaced."""
    argv = [*SWEEP[:2], "0.06", *SWEEP[3:], *VARY, "--out", str(store), "--overwrite"]
    assert main(argv) == 0
    assert cs.open_sweep(store).attrs["t_end"] == 0.06
    assert [p.name for p in store.parent.iterdir()] == ["s.zarr"]  # no lock file left


_HOLD_STORE = """
import sys, time
from celtstone.sweep.store import SweepStore
store = SweepStore.open(sys.argv[1], lock=True)
print("holding", flush=True)
time.sleep(600)
"""


def test_a_store_being_written_is_locked_against_a_second_writer(
    capsys: pytest.CaptureFixture[str], store: Path, tmp_path: Path
) -> None:
    """A second sweep on a store another process is writing is refused, naming the store
    and the process; once that process is killed (SIGKILL), its lock file blocks nothing."""
    writer = subprocess.Popen(
        [sys.executable, "-c", _HOLD_STORE, str(store)], stdout=subprocess.PIPE, text=True
    )
    try:
        assert writer.stdout is not None and writer.stdout.readline() == "holding\n"
        capsys.readouterr()
        before = _snapshot(store)
        for flag in ("--overwrite", "--resume"):
            line = _refusal(capsys, main([*SWEEP, *VARY, "--out", str(store), flag]))
            assert f"out = '{store}'" in line and f"process {writer.pid} " in line, line
        assert _snapshot(store) == before
    finally:
        writer.kill()
        writer.communicate()
    assert (tmp_path / ".s.zarr.lock").exists()  # left by the killed writer
    assert main([*SWEEP, *VARY, "--out", str(store), "--overwrite"]) == 0
    assert not (tmp_path / ".s.zarr.lock").exists()


def test_writer_lock_is_exclusive_and_released(tmp_path: Path) -> None:
    path = tmp_path / ".x.lock"
    with ownership.WriterLock(path, "x"):
        assert path.read_text(encoding="ascii") == f"{os.getpid()}\n"
        with pytest.raises(cs.ParameterError, match=f"process {os.getpid()} is writing it"):
            ownership.WriterLock(path, "x")
    assert not path.exists()
    path.write_text("999999999\n", encoding="ascii")  # a dead writer's file, no lock held
    with ownership.WriterLock(path, "x"):
        assert path.read_text(encoding="ascii") == f"{os.getpid()}\n"


# ---------------------------------------------------------------------------------------
# reproduce: the user's report.md, a file with an output's name, atlas.zarr, --out '',
# two bodies of the same name
# ---------------------------------------------------------------------------------------


def _tiny(body: str) -> Study:
    """Two threshold runs of 0.2 s and no bisection: the cheapest whole target."""
    return Study(
        body=body, threshold_grid=(0.1, 0.5, 2), threshold_t_end=0.2, bisection_tolerance=1.0
    )


QUICK = ["--quick", "--no-progress", "--contact", "paper"]


@pytest.mark.parametrize("overwrite", [[], ["--overwrite"]], ids=["plain", "overwrite"])
@pytest.mark.parametrize(
    "name", ["report.md", f"threshold_{TOY}.png", f"data/threshold_{TOY}.json"]
)
def test_reproduce_keeps_a_user_file_with_an_output_name(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, name: str, overwrite: list[str]
) -> None:
    """Refused before any run (this would take minutes), with or without --overwrite."""
    mine = tmp_path / name
    mine.parent.mkdir(exist_ok=True)
    mine.write_text("my own text\n", encoding="utf-8")
    before = _snapshot(tmp_path)
    argv = ["reproduce", "threshold", *QUICK, "--body", TOY, "--out", str(tmp_path), *overwrite]
    line = _refusal(capsys, main(argv))
    assert f"out = '{tmp_path}'" in line and str(mine) in line, line
    assert _snapshot(tmp_path) == before


def test_reproduce_replaces_its_results_only_with_overwrite(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    reproduce(["threshold"], tmp_path, [_tiny(KL)], progress=False)
    report = tmp_path / "report.md"
    first = _snapshot(tmp_path)
    with pytest.raises(cs.ParameterError, match="--overwrite"):
        reproduce(["threshold"], tmp_path, [_tiny(KL)], progress=False)
    assert _snapshot(tmp_path) == first
    # another body adds its results and rebuilds the report (celtstone's, unchanged)
    reproduce(["threshold"], tmp_path, [_tiny(TOY)], progress=False)
    assert TOY in report.read_text(encoding="utf-8")
    reproduce(["threshold"], tmp_path, [_tiny(KL)], progress=False, overwrite=True)
    # the report edited by its user is theirs now: never replaced
    report.write_text(report.read_text(encoding="utf-8") + "my conclusions\n", encoding="utf-8")
    edited = _snapshot(tmp_path)
    with pytest.raises(cs.ParameterError, match=r"report\.md"):
        reproduce(["threshold"], tmp_path, [_tiny(KL)], progress=False, overwrite=True)
    with pytest.raises(cs.ParameterError, match=r"report\.md"):
        write_report(tmp_path)
    assert _snapshot(tmp_path) == edited


_HOLD_REPRODUCTION = """
import sys, time
from pathlib import Path
from celtstone.reproduce.directory import ReproductionDirectory
held = ReproductionDirectory(Path(sys.argv[1]), overwrite=False)
print("holding", flush=True)
time.sleep(600)
"""


def test_a_reproduction_being_written_is_locked(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    writer = subprocess.Popen(
        [sys.executable, "-c", _HOLD_REPRODUCTION, str(tmp_path)], stdout=subprocess.PIPE, text=True
    )
    try:
        assert writer.stdout is not None and writer.stdout.readline() == "holding\n"
        before = _snapshot(tmp_path)
        argv = ["reproduce", "threshold", *QUICK, "--body", KL, "--out", str(tmp_path)]
        line = _refusal(capsys, main(argv))
        assert f"out = '{tmp_path}'" in line and f"process {writer.pid} " in line, line
        assert _snapshot(tmp_path) == before
    finally:
        writer.kill()
        writer.communicate()


class _AtlasMustNotRun:
    """An atlas target that fails the test if it is run: the refusal comes first."""

    def runs(self) -> int:
        return 1

    def __call__(self, out: Path, progress: object) -> dict[str, Any]:
        raise AssertionError("the atlas ran although its store may not be replaced")


def test_reproduce_atlas_keeps_a_user_directory_named_atlas_zarr(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    mine = tmp_path / "atlas.zarr"
    (mine / "thesis").mkdir(parents=True)
    (mine / "thesis" / "chapter1.tex").write_text("years of work\n", encoding="utf-8")
    before = _snapshot(tmp_path)
    for overwrite in (False, True):
        with pytest.raises(cs.ParameterError, match=r"atlas\.zarr") as caught:
            reproduce(["atlas"], tmp_path, [], progress=False, atlas=_AtlasMustNotRun(),
                      overwrite=overwrite)  # fmt: skip
        assert caught.value.name == "out"
    assert _snapshot(tmp_path) == before
    argv = ["reproduce", "atlas", "--quick", "--no-progress", "--out", str(tmp_path)]
    line = _refusal(capsys, main([*argv, "--overwrite"]))
    assert str(mine) in line, line
    assert _snapshot(tmp_path) == before


def test_reproduce_refuses_an_empty_out(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "report.md").write_text("mine\n", encoding="utf-8")
    before = _snapshot(tmp_path)
    line = _refusal(capsys, main(["reproduce", "threshold", *QUICK, "--body", KL, "--out", ""]))
    assert line.startswith("celtstone: error: out = ''"), line
    with pytest.raises(cs.ParameterError, match="out = ''"):
        reproduce(["threshold"], "", [_tiny(KL)], progress=False)
    assert _snapshot(tmp_path) == before


def _body_file(folder: Path, name: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    return Path(shutil.copy(SHIPPED_BODIES / f"{KL}.toml", folder / name))


def test_reproduce_refuses_two_bodies_of_the_same_name(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    first, second = (
        _body_file(tmp_path / "a", "stone.toml"),
        _body_file(tmp_path / "b", "stone.toml"),
    )
    out = tmp_path / "results"
    argv = ["reproduce", "threshold", *QUICK, "--out", str(out)]
    line = _refusal(capsys, main([*argv, "--body", str(first), "--body", str(second)]))
    assert line.startswith(f"celtstone: error: body = '{second}'"), line
    assert str(first) in line, line
    custom = _body_file(tmp_path / "mine", f"{KL}.toml")  # beside the shipped one
    line = _refusal(capsys, main([*argv, "--body", KL, "--body", str(custom)]))
    assert str(custom) in line and f"{KL} has the same name" in line, line
    assert not out.exists() or not any(p for p in out.iterdir() if p.name != "data")


def test_reproduce_keeps_results_of_another_body_of_the_same_name(tmp_path: Path) -> None:
    """Across calls: the shipped body's results are not replaced by a custom file's of
    the same name, even with overwrite; the refusal names both."""
    reproduce(["threshold"], tmp_path, [_tiny(KL)], progress=False)
    before = _snapshot(tmp_path)
    custom = _body_file(tmp_path.parent / f"{tmp_path.name}-bodies", f"{KL}.toml")
    with pytest.raises(cs.ParameterError) as caught:
        reproduce(["threshold"], tmp_path, [_tiny(str(custom))], progress=False, overwrite=True)
    assert caught.value.name == "body"
    assert str(custom) in str(caught.value) and f"shipped body {KL}" in str(caught.value)
    assert _snapshot(tmp_path) == before


# ---------------------------------------------------------------------------------------
# export: an output is never its input; friction --plot
# ---------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def written_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A short run written once by ``celtstone run``: the input of the commands below."""
    path = tmp_path_factory.mktemp("written") / "run.nc"
    assert main(["run", "--t-end", "0.1", "--out", str(path)]) == 0
    return path


@pytest.fixture
def run_as_csv(written_run: Path, tmp_path: Path) -> Path:
    """A NetCDF run under a .csv name (the issue's R.csv)."""
    return Path(shutil.copy(written_run, tmp_path / "R.csv"))


@pytest.mark.parametrize("spelling", ["same", "dotted", "link", "hard link"])
def test_export_refuses_its_input_as_output(
    capsys: pytest.CaptureFixture[str], run_as_csv: Path, tmp_path: Path, spelling: str
) -> None:
    capsys.readouterr()
    out = str(run_as_csv)
    if spelling == "dotted":
        out = str(tmp_path / "." / "sub" / ".." / "R.csv")
        (tmp_path / "sub").mkdir()
    elif spelling == "link":
        (tmp_path / "L.csv").symlink_to(run_as_csv)
        out = str(tmp_path / "L.csv")
    elif spelling == "hard link":
        os.link(run_as_csv, tmp_path / "H.csv")
        out = str(tmp_path / "H.csv")
    before = _snapshot(tmp_path)
    line = _refusal(capsys, main(["export", str(run_as_csv), "--csv", "--out", out, "--overwrite"]))
    assert line.startswith(f"celtstone: error: out = '{out}'"), line
    assert "not an input" in line, line
    assert _snapshot(tmp_path) == before


def test_friction_plot_keeps_an_existing_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    target = tmp_path / "f.png"
    target.write_bytes(b"my figure")
    line = _refusal(capsys, main(["friction", "--plot", str(target)]))
    assert f"plot = '{target}'" in line and "--overwrite" in line, line
    assert target.read_bytes() == b"my figure"


class _TinyAtlas:
    """An atlas target that writes a small store of its own (a new token each run)."""

    def runs(self) -> int:
        return 1

    def __call__(self, out: Path, progress: object) -> dict[str, Any]:
        store = out / "atlas.zarr"
        (store / "verdicts" / "c").mkdir(parents=True)
        (store / "zarr.json").write_text('{"node_type": "group"}', encoding="utf-8")
        (store / "verdicts" / "c" / "0").write_bytes(os.urandom(16))
        summary = {"target": "atlas", "key": "atlas", "body": "-", "grid": "t", "t_end": 1.0}
        summary["study"] = "a tiny stand-in"
        return {**summary, "designs": [], "slices": [], "figures": [], "store": "atlas.zarr"}


def test_reproduce_atlas_replaces_its_own_store_only_with_overwrite(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(report_module, "atlas_section", lambda *args: [])  # not tested here
    reproduce(["atlas"], tmp_path, [], progress=False, atlas=_TinyAtlas())
    chunk = tmp_path / "atlas.zarr" / "verdicts" / "c" / "0"
    first = _snapshot(tmp_path)
    with pytest.raises(cs.ParameterError, match="--overwrite"):
        reproduce(["atlas"], tmp_path, [], progress=False, atlas=_TinyAtlas())
    assert _snapshot(tmp_path) == first
    reproduce(["atlas"], tmp_path, [], progress=False, atlas=_TinyAtlas(), overwrite=True)
    assert chunk.read_bytes() != first[str(chunk.relative_to(tmp_path))]
    notes = tmp_path / "atlas.zarr" / "notes.txt"
    notes.write_text("mine\n", encoding="utf-8")
    before = _snapshot(tmp_path)
    with pytest.raises(cs.ParameterError) as caught:
        reproduce(["atlas"], tmp_path, [], progress=False, atlas=_TinyAtlas(), overwrite=True)
    assert str(tmp_path / "atlas.zarr") in str(caught.value)
    assert _snapshot(tmp_path) == before


# ---------------------------------------------------------------------------------------
# single files: --overwrite replaces only a file that carries celtstone's mark
# ---------------------------------------------------------------------------------------


def _foreign_file(path: Path) -> None:
    """A file of ``path``'s format written by another program (xarray, matplotlib)."""
    if path.suffix == ".nc":
        import xarray as xr

        xr.Dataset({"spin": ("time", [1.0, 2.0])}, {"time": [0.0, 1.0]}).to_netcdf(path)
        return
    if path.suffix == ".csv":  # a commented table, as a logger writes one
        path.write_text("# measured by hand\n# units: s\ntime,spin\n0,1\n", encoding="utf-8")
        return
    if path.suffix in (".gif", ".mp4"):  # a video of another program (another comment)
        import imageio.v3 as iio

        frames = np.zeros((4, 48, 64, 3), dtype=np.uint8)
        iio.imwrite(
            path, frames, extension=path.suffix, **({"fps": 4} if path.suffix == ".mp4" else {})
        )
        return
    if path.suffix == ".html":
        path.write_text(
            '<!DOCTYPE html><html><head><meta name="generator" content="Jupyter">'
            "<title>celtstone notes</title></head><body>mine</body></html>",
            encoding="utf-8",
        )
        return
    from matplotlib.figure import Figure

    Figure(figsize=(1, 1)).savefig(path)


SINGLE_FILES = [
    (["run", "--t-end", "0.1", "--out", "{target}"], "u.nc"),
    (["plot", "{run}", "--out", "{target}"], "u.png"),
    (["plot", "{run}", "--out", "{target}"], "u.svg"),
    (["friction", "--plot", "{target}"], "u.pdf"),
    (["friction", "--plot", "{target}"], "u.png"),
    (["export", "{run}", "--csv", "--out", "{target}"], "u.csv"),
    (["run", "--t-end", "0.1", "--out", "{target}"], "u.csv"),
    (["stability", "--spin", "-5:-4:3", "--csv", "{target}"], "u.csv"),
    (["view", "{run}", "--out", "{target}"], "u.html"),
    (["animate", "{run}", "--out", "{target}", "--size", "64x48"], "u.gif"),
    (["animate", "{run}", "--out", "{target}", "--size", "64x48"], "u.mp4"),
]
"""Each command that writes one file (its ``--out`` or ``--plot``), and the file's name."""


@pytest.mark.parametrize(("argv", "name"), SINGLE_FILES)
@pytest.mark.parametrize("foreign", ["another program's", "bytes"])
def test_overwrite_keeps_a_file_without_the_mark(
    capsys: pytest.CaptureFixture[str],
    written_run: Path,
    tmp_path: Path,
    argv: list[str],
    name: str,
    foreign: str,
) -> None:
    run = shutil.copy(written_run, tmp_path / "run.nc")
    target = tmp_path / name
    if foreign == "bytes":
        target.write_bytes(b"my data\n")
    else:
        _foreign_file(target)
    assert ownership.is_marked_file(target) is False
    capsys.readouterr()
    before = _snapshot(tmp_path)
    command = [part.format(run=run, target=target) for part in argv]
    line = _refusal(capsys, main([*command, "--overwrite"]))
    assert f"= '{target}'" in line and "celtstone's mark" in line, line
    assert _snapshot(tmp_path) == before


@pytest.mark.parametrize(("argv", "name"), SINGLE_FILES)
def test_overwrite_replaces_a_file_with_the_mark(
    capsys: pytest.CaptureFixture[str],
    written_run: Path,
    tmp_path: Path,
    argv: list[str],
    name: str,
) -> None:
    """The control of the test above, once per command: what celtstone wrote there
    carries its mark and is replaced."""
    run = shutil.copy(written_run, tmp_path / "run.nc")
    target = tmp_path / name
    command = [part.format(run=run, target=target) for part in argv]
    assert main(command) == 0
    assert ownership.is_marked_file(target) is True
    assert main([*command, "--overwrite"]) == 0, capsys.readouterr()


def test_formats_without_a_mark_are_not_judged(tmp_path: Path) -> None:
    for name in ("a.json", "a.md"):
        (tmp_path / name).write_bytes(b"x")
        assert ownership.is_marked_file(tmp_path / name) is None
