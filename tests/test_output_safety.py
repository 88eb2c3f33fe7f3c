"""Output files: nothing a user did not ask to replace is replaced; files are whole or absent.

* every writing command refuses an existing ``--out`` (exit 2, one line naming ``out``,
  the path and ``--overwrite``), the file untouched byte for byte;
* ``--overwrite`` replaces a file, never a directory; a sweep replaces only a celtstone
  sweep store, recognised by its own metadata (what else a directory output may hold is
  tested in ``test_output_ownership.py``);
* temporaries are named after their process: those of a process that is gone are
  removed by the next write to the same target, never those of a live process, never
  other files; SIGKILL and SIGTERM during a NetCDF write leave no partial target;
* on a full disk (a 300 kB tmpfs) every writer fails in one line naming the file and
  the cause, and leaves neither the target nor a temporary;
* ``reproduce`` moves a target's files into place only when it finished, records the run
  that made them, and says in the report when results come from different runs;
* a run file with fewer than two samples is refused by name.
"""

from __future__ import annotations

import errno
import json
import os
import shutil
import signal
import subprocess
import sys
import time
import warnings
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from matplotlib.figure import Figure

import celtstone as cs
from celtstone.cli.main import Terminated, build_parser, main
from celtstone.errors import OutputError
from celtstone.files import export, ownership
from celtstone.plotting import save_figure
from celtstone.reproduce import Study, reproduce
from celtstone.reproduce import cases as reproduce_cases
from celtstone.reproduce import targets as reproduce_targets
from celtstone.sweep.store import RESULT_FIELDS as STORE_FIELDS
from celtstone.sweep.store import Layout, SweepStore
from celtstone.visual import write_viewer
from tests.conftest import LITERATURE_EULER_ANGLES

OVERWRITE_HINT = "add --overwrite to replace it"
KL = "kane_levinson_1982"
TOY = "toy_rattleback_10cm"
RANDOM = "abcdefgh"  # the random part of a temporary's name (8 characters)


@pytest.fixture(scope="module")
def run_dataset(kane_levinson: cs.Body) -> xr.Dataset:
    """A 0.5 s rolling run, 51 samples."""
    state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=LITERATURE_EULER_ANGLES)
    return cs.simulate(cs.RollingModel(), kane_levinson, state, 0.5, n_samples=51).dataset


@pytest.fixture
def run_file(run_dataset: xr.Dataset, tmp_path: Path) -> Path:
    return export.write(run_dataset, tmp_path / "run.nc")


def _snapshot(directory: Path) -> dict[str, bytes | None]:
    """Every entry under ``directory`` (hidden ones too): file bytes, None for a directory."""
    return {
        str(p.relative_to(directory)): None if p.is_dir() else p.read_bytes()
        for p in sorted(directory.rglob("*"))
    }


def _one_error_line(
    capsys: pytest.CaptureFixture[str], status: int, expected: int, *, after_warnings: bool = False
) -> str:
    """The one line on stderr; with ``after_warnings``, the last line, after nothing but
    one-line warnings (of runs that finished on other threads before the signal was
    taken: the waiting thread takes it within ``reproduce.parallel.POLL_INTERVAL``)."""
    out, err = capsys.readouterr()
    assert status == expected, (out, err)
    assert "Traceback" not in err and "Exception ignored" not in err, err
    lines = err.splitlines()
    if after_warnings:
        assert all(line.startswith("celtstone: warning: ") for line in lines[:-1]), err
        lines = lines[-1:]
    assert len(lines) == 1, err
    return lines[0]


def _signal_self(sig: signal.Signals) -> None:
    """Send ``sig`` to this process, once celtstone's handler is there to turn it into an
    exception (without one, SIGTERM would end the whole test session)."""
    handler = signal.getsignal(sig)
    assert callable(handler), f"no Python handler for {sig.name}: {handler!r}"
    os.kill(os.getpid(), sig)
    time.sleep(5.0)  # the handler raises here
    raise AssertionError(f"{sig.name} did not interrupt")


def _dead_pid() -> int:
    """The PID of a process that has finished (and been reaped)."""
    process = subprocess.Popen([sys.executable, "-c", ""])
    process.wait()
    return process.pid


# ---------------------------------------------------------------------------------------
# Existing targets: refused, untouched; --overwrite replaces a file, never a directory
# ---------------------------------------------------------------------------------------

# (id, argv with {run} and {target}, target name); {target} absent: the default output
WRITERS = [
    ("run-nc", ["run", "--t-end", "0.1", "--out", "{target}"], "x.nc"),
    ("run-csv", ["run", "--t-end", "0.1", "--out", "{target}"], "x.csv"),
    ("plot-out", ["plot", "{run}", "--out", "{target}"], "figure.svg"),
    ("plot-default", ["plot", "{run}"], "run.png"),
    ("export-out", ["export", "{run}", "--csv", "--out", "{target}"], "table.csv"),
    ("export-default", ["export", "{run}", "--csv"], "run.csv"),
    ("animate-gif", ["animate", "{run}", "--out", "{target}", "--size", "64x48"], "v.gif"),
    ("animate-mp4", ["animate", "{run}", "--out", "{target}", "--size", "64x48"], "v.mp4"),
    ("view", ["view", "{run}", "--out", "{target}"], "page.html"),
]
OVERWRITABLE = [w for w in WRITERS if not w[0].startswith("run")]


def _argv(template: list[str], run: Path, target: Path) -> list[str]:
    return [part.format(run=run, target=target) for part in template]


def _run_has_overwrite() -> bool:
    commands = next(a for a in build_parser()._actions if a.dest == "command")
    run_parser = commands.choices["run"]  # type: ignore[index]
    return any("--overwrite" in action.option_strings for action in run_parser._actions)


@pytest.mark.parametrize(("argv", "name"), [w[1:] for w in WRITERS], ids=[w[0] for w in WRITERS])
def test_existing_file_is_refused_and_untouched(
    capsys: pytest.CaptureFixture[str], run_file: Path, argv: list[str], name: str
) -> None:
    target = run_file.parent / name
    target.write_bytes(b"precious: not celtstone's to replace\n")
    before = _snapshot(run_file.parent)
    line = _one_error_line(capsys, main(_argv(argv, run_file, target)), 2)
    assert line.startswith("celtstone: error: out = "), line
    assert str(target) in line and OVERWRITE_HINT in line, line
    assert _snapshot(run_file.parent) == before


@pytest.mark.parametrize(("argv", "name"), [w[1:] for w in WRITERS], ids=[w[0] for w in WRITERS])
def test_directory_is_refused_even_with_overwrite(
    capsys: pytest.CaptureFixture[str], run_file: Path, argv: list[str], name: str
) -> None:
    target = run_file.parent / name
    target.mkdir()
    (target / "thesis.tex").write_text("years of work\n", encoding="utf-8")
    before = _snapshot(run_file.parent)
    overwrite = ["--overwrite"] if argv[0] != "run" or _run_has_overwrite() else []
    line = _one_error_line(capsys, main([*_argv(argv, run_file, target), *overwrite]), 2)
    assert line.startswith("celtstone: error: out = "), line
    assert str(target) in line and "directory" in line, line
    assert _snapshot(run_file.parent) == before


@pytest.mark.parametrize(
    ("argv", "name"), [w[1:] for w in OVERWRITABLE], ids=[w[0] for w in OVERWRITABLE]
)
def test_overwrite_replaces_a_file(
    capsys: pytest.CaptureFixture[str], run_file: Path, argv: list[str], name: str
) -> None:
    """An earlier output of the command is replaced (a new file moved in); a file
    celtstone did not write is kept where its format carries a mark
    (``test_output_ownership.py``)."""
    target = run_file.parent / name
    assert main(_argv(argv, run_file, target)) == 0, capsys.readouterr()
    earlier = target.stat().st_ino
    assert main([*_argv(argv, run_file, target), "--overwrite"]) == 0, capsys.readouterr()
    assert target.stat().st_ino != earlier
    assert target.stat().st_size > 100
    assert sorted(p.name for p in run_file.parent.iterdir()) == sorted({"run.nc", name})


@pytest.mark.skipif(not _run_has_overwrite(), reason="`celtstone run` has no --overwrite yet")
def test_run_overwrite_replaces_a_file(tmp_path: Path) -> None:
    """An earlier run (celtstone's, by its mark) is replaced; ``test_output_ownership.py``
    has the NetCDF file that is not."""
    target = tmp_path / "x.nc"
    assert main(["run", "--t-end", "0.1", "--out", str(target)]) == 0
    assert main(["run", "--t-end", "0.2", "--out", str(target), "--overwrite"]) == 0
    assert float(export.read_run(target)["time"][-1]) == pytest.approx(0.2)


def test_export_refuses_an_unrelated_csv_beside_the_run(
    capsys: pytest.CaptureFixture[str], run_file: Path
) -> None:
    """``export run.nc --csv`` once replaced an unrelated ``run.csv`` silently."""
    unrelated = run_file.with_suffix(".csv")
    unrelated.write_text("measured,by,hand\n1,2,3\n", encoding="utf-8")
    line = _one_error_line(capsys, main(["export", str(run_file), "--csv"]), 2)
    assert str(unrelated) in line and OVERWRITE_HINT in line
    assert unrelated.read_text(encoding="utf-8") == "measured,by,hand\n1,2,3\n"


@pytest.mark.parametrize(
    ("argv", "name"),
    [
        (["plot", ""], "run"),
        (["export", "", "--csv"], "run"),
        (["plot", "{run}", "--out", ""], "out"),
        (["export", "{run}", "--csv", "--out", ""], "out"),
        (["run", "--t-end", "0.1", "--out", ""], "out"),
        (["view", "{run}", "--out", ""], "out"),
        (["animate", "{run}", "--out", ""], "out"),
    ],
)
def test_empty_paths_are_one_line(
    capsys: pytest.CaptureFixture[str], run_file: Path, argv: list[str], name: str
) -> None:
    before = _snapshot(run_file.parent)
    line = _one_error_line(capsys, main(_argv(argv, run_file, Path())), 2)
    assert line.startswith(f"celtstone: error: {name} = ''"), line
    assert _snapshot(run_file.parent) == before


def test_python_api_has_the_same_policy(run_dataset: xr.Dataset, tmp_path: Path) -> None:
    """Every writer refuses an existing file unless ``overwrite=True``; never a directory;
    a file of a format with a mark (NetCDF, figures) only if celtstone wrote it."""
    figure = Figure()
    writers = {
        "a.nc": lambda path, **kw: export.write(run_dataset, path, **kw),
        "a.json": lambda path, **kw: export.write_json({"a": 1}, path, **kw),
        "a.csv": lambda path, **kw: export.write_table(pd.DataFrame({"a": [1]}), path, {}, **kw),
        "a.svg": lambda path, **kw: save_figure(figure, path, **kw),
        "a.html": lambda path, **kw: write_viewer(run_dataset, path, **kw),
    }
    for name, write in writers.items():
        target = tmp_path / name
        target.write_bytes(b"old")
        with pytest.raises(cs.ParameterError, match="--overwrite") as caught:
            write(target)
        assert caught.value.name == "out"
        assert target.read_bytes() == b"old"
        if ownership.is_marked_file(target) is not None:  # not celtstone's: kept
            with pytest.raises(cs.ParameterError, match="celtstone's mark"):
                write(target, overwrite=True)
            assert target.read_bytes() == b"old"
            target.unlink()
            write(target)
            assert ownership.is_marked_file(target)
        write(target, overwrite=True)
        assert target.read_bytes() != b"old"
        folder = tmp_path / f"folder{Path(name).suffix}"
        folder.mkdir()
        with pytest.raises(cs.ParameterError, match="directory"):
            write(folder, overwrite=True)
        assert folder.is_dir() and not any(folder.iterdir())
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == []


def test_a_file_appearing_during_the_computation_is_not_replaced(tmp_path: Path) -> None:
    """The final move cannot replace a file made after the check (no overwrite)."""
    target = tmp_path / "a.json"
    with pytest.raises(cs.ParameterError, match="--overwrite"):
        with export.atomic_path(target) as temporary:
            temporary.write_text("new\n", encoding="utf-8")
            target.write_text("made meanwhile\n", encoding="utf-8")
    assert target.read_text(encoding="utf-8") == "made meanwhile\n"
    assert [p.name for p in tmp_path.iterdir()] == ["a.json"]


# ---------------------------------------------------------------------------------------
# Sweep stores: --overwrite replaces only a celtstone store
# ---------------------------------------------------------------------------------------

SWEEP = ["sweep", "--vary", "friction_coefficient=0.1,0.3", "--t-end", "0.05"]
SWEEP_OPTIONS = ["--workers", "1", "--no-progress", "--no-maps"]


def _not_a_store(kind: str, path: Path) -> None:
    if kind == "file":
        path.write_text("a plain file\n", encoding="utf-8")
        return
    path.mkdir()
    (path / "thesis").mkdir()
    (path / "thesis" / "chapter1.tex").write_text("years of work\n", encoding="utf-8")
    if kind == "other zarr":  # a Zarr group, but not one of ours
        (path / "zarr.json").write_text(
            json.dumps({"zarr_format": 3, "node_type": "group", "attributes": {"x": 1}}),
            encoding="utf-8",
        )


@pytest.mark.parametrize("kind", ["directory", "other zarr", "file"])
@pytest.mark.parametrize("flag", ["--overwrite", "--resume"])
def test_sweep_never_replaces_what_is_not_a_store(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, kind: str, flag: str
) -> None:
    target = tmp_path / "precious"
    _not_a_store(kind, target)
    before = _snapshot(tmp_path)
    status = main([*SWEEP, "--out", str(target), flag, *SWEEP_OPTIONS])
    line = _one_error_line(capsys, status, 2)
    assert "out = " in line and str(target) in line, line
    assert _snapshot(tmp_path) == before


def test_sweep_overwrite_replaces_a_store_and_its_stale_temporaries(tmp_path: Path) -> None:
    store = tmp_path / "s.zarr"
    assert main([*SWEEP, "--out", str(store), *SWEEP_OPTIONS]) == 0
    dead, live = _dead_pid(), os.getppid()
    stale = tmp_path / f".s.zarr.{dead}.{RANDOM}.part"
    kept = [tmp_path / f".s.zarr.{live}.{RANDOM}.part", tmp_path / f".s.zarr.{RANDOM}.part"]
    for directory in (stale, *kept):
        directory.mkdir()
        (directory / "zarr.json").write_text("{}", encoding="utf-8")
    first = (store / "zarr.json").read_bytes()
    assert main([*SWEEP[:-1], "0.06", "--out", str(store), "--overwrite", *SWEEP_OPTIONS]) == 0
    assert (store / "zarr.json").read_bytes() != first  # the new sweep's spec
    assert cs.open_sweep(store).attrs["t_end"] == 0.06
    assert not stale.exists()
    assert all(path.is_dir() for path in kept)
    names = {p.name for p in tmp_path.iterdir()}
    assert names == {"s.zarr", *(p.name for p in kept)}


# ---------------------------------------------------------------------------------------
# Temporaries of processes that are gone
# ---------------------------------------------------------------------------------------


def test_stale_temporaries_are_removed_only_when_ours_and_dead(
    run_dataset: xr.Dataset, tmp_path: Path
) -> None:
    dead, live = _dead_pid(), os.getppid()
    stale = [tmp_path / f".x.nc.{dead}.{RANDOM}.part", tmp_path / f".x.nc.{dead}.k2_9z0a1.part"]
    kept = [
        tmp_path / f".x.nc.{live}.{RANDOM}.part",  # a live process's write
        tmp_path / f".x.nc.{RANDOM}.part",  # another naming (no PID)
        tmp_path / f".y.nc.{dead}.{RANDOM}.part",  # another target
        tmp_path / f"x.nc.{dead}.{RANDOM}.part",  # not hidden: not ours
        tmp_path / f".x.nc.{dead}.{RANDOM}.part.keep",
    ]
    for path in (*stale, *kept):
        path.write_bytes(b"")
    export.write(run_dataset, tmp_path / "x.nc")
    assert not any(path.exists() for path in stale)
    assert all(path.exists() for path in kept)


def _wait_for_part(process: subprocess.Popen, directory: Path, name: str) -> list[Path]:
    deadline = time.monotonic() + 120.0
    while time.monotonic() < deadline and process.poll() is None:
        parts = list(directory.glob(f".{name}.*.part"))
        if parts:
            return parts
        time.sleep(0.002)
    raise AssertionError(f"no temporary of {name} appeared ({process.poll()=})")


# 300 000 samples: the NetCDF write takes a few tenths of a second
KILLED_RUN = ["run", "--t-end", "0.5", "--samples", "300000", "--out"]


@pytest.mark.parametrize("delay", [0.0, 0.1], ids=["at-start", "later"])
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM], ids=["SIGKILL", "SIGTERM"])
def test_killed_during_a_netcdf_write(tmp_path: Path, sig: signal.Signals, delay: float) -> None:
    target = tmp_path / "x.nc"
    command = [sys.executable, "-m", "celtstone", *KILLED_RUN, str(target)]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _wait_for_part(process, tmp_path, "x.nc")
    time.sleep(delay)
    assert process.poll() is None, "the write ended before the signal"
    process.send_signal(sig)
    _, stderr = process.communicate(timeout=120)
    assert not target.exists()
    if sig == signal.SIGTERM:
        assert process.returncode == 128 + signal.SIGTERM
        assert stderr.decode().splitlines() == [
            "celtstone: terminated; no partial output was written"
        ]
        assert list(tmp_path.iterdir()) == []
        return
    assert process.returncode == -signal.SIGKILL
    (left,) = tmp_path.iterdir()  # what SIGKILL cannot clean up ...
    assert left.name.startswith(".x.nc.") and left.name.endswith(".part")
    assert main(["run", "--t-end", "0.1", "--samples", "11", "--out", str(target)]) == 0
    assert [p.name for p in tmp_path.iterdir()] == ["x.nc"]  # ... the next write does


def test_sigterm_unwinds_like_ctrl_c_in_process(
    capsys: pytest.CaptureFixture[str], run_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """SIGTERM in the middle of a write becomes :class:`Terminated` (a KeyboardInterrupt):
    the temporary is removed, exit 143, one line."""
    previous = signal.getsignal(signal.SIGTERM)

    def terminated_midway(self: xr.Dataset, path: Path, *args: object, **kwargs: object) -> None:
        Path(path).write_bytes(b"CDF half a file")
        _signal_self(signal.SIGTERM)

    monkeypatch.setattr(xr.Dataset, "to_netcdf", terminated_midway)
    before = _snapshot(run_file.parent)
    target = run_file.parent / "x.nc"
    status = main(["run", "--t-end", "0.1", "--out", str(target)])
    line = _one_error_line(capsys, status, 143)
    assert line == "celtstone: terminated; no partial output was written"
    assert _snapshot(run_file.parent) == before
    assert issubclass(Terminated, KeyboardInterrupt)
    assert signal.getsignal(signal.SIGTERM) is previous  # the previous handler is back


# ---------------------------------------------------------------------------------------
# A signal at the worst moments: as a temporary is created, between two moves
# ---------------------------------------------------------------------------------------


def _signal_as_created(monkeypatch: pytest.MonkeyPatch, name: str, sig: signal.Signals) -> None:
    """``os.<name>`` (``open`` or ``mkdir``) sends ``sig`` to this process just after it
    has created a temporary (``*.part``), once: the handler's exception comes as the call
    returns, before the caller has the result (a subprocess once met this by chance)."""
    real = getattr(os, name)

    def creating(path: str | Path, *args: object, **kwargs: object) -> object:
        result = real(path, *args, **kwargs)
        if str(path).endswith(".part"):
            monkeypatch.setattr(os, name, real)
            try:
                _signal_self(sig)
            finally:
                if name == "open":
                    os.close(result)  # the test's own descriptor, not left open
        return result

    monkeypatch.setattr(os, name, creating)


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize(
    ("creation", "command"),
    [
        ("open", ["run", "--t-end", "0.1", "--samples", "11", "--out", "x.nc"]),
        ("mkdir", [*SWEEP, *SWEEP_OPTIONS, "--out", "s.zarr"]),
    ],
    ids=["file", "store"],
)
def test_a_signal_as_the_temporary_is_created_leaves_nothing(
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    sig: signal.Signals,
    creation: str,
    command: list[str],
) -> None:
    """A run's temporary file and a sweep's temporary store: removed, and the one line
    says nothing was written (a sweep stopped before its store exists has nothing to
    resume)."""
    _signal_as_created(monkeypatch, creation, sig)
    status = main([*command[:-1], str(tmp_path / command[-1])])
    line = _one_error_line(capsys, status, 128 + sig)
    assert line == "celtstone: interrupted; no partial output was written" or (
        sig == signal.SIGTERM and line == "celtstone: terminated; no partial output was written"
    )
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("moved", [False, True], ids=["before-the-move", "after-the-move"])
def test_an_interrupted_replace_keeps_one_whole_directory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, moved: bool
) -> None:
    """Ctrl-C between moving the earlier output aside and moving the new one in puts the
    earlier one back; after the new one is in, it stays. Nothing else is left."""
    target = tmp_path / "out"
    target.mkdir()
    (target / "result").write_text("earlier", encoding="utf-8")
    real = os.rename

    def interrupted(source: Path, destination: Path) -> None:
        if Path(destination) == target:
            monkeypatch.setattr(os, "rename", real)
            if moved:
                real(source, destination)
            _signal_self(signal.SIGINT)
        real(source, destination)

    monkeypatch.setattr(os, "rename", interrupted)
    with pytest.raises(KeyboardInterrupt), export.temporary_directory(target) as staging:
        (staging / "result").write_text("new", encoding="utf-8")
        export.replace_directory(staging, target)
    expected = b"new" if moved else b"earlier"
    assert _snapshot(tmp_path) == {"out": None, "out/result": expected}


def test_a_resource_warning_during_a_write_adds_no_line(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Python hides ResourceWarning by default and so does the CLI: a SIGTERM landing in
    an import during the write left the import's file to the collector, and its warning
    came before "terminated" (3 of 36 tries under load)."""
    original = xr.Dataset.to_netcdf

    def leaking(self: xr.Dataset, *args: object, **kwargs: object) -> object:
        warnings.warn(
            "unclosed file <_io.BufferedReader name='x.pyc'>", ResourceWarning, stacklevel=2
        )
        return original(self, *args, **kwargs)  # type: ignore[call-overload]

    monkeypatch.setattr(xr.Dataset, "to_netcdf", leaking)
    status = main(["run", "--t-end", "0.1", "--samples", "11", "--out", str(tmp_path / "x.nc")])
    err = capsys.readouterr().err
    assert status == 0, err
    assert err == ""


# ---------------------------------------------------------------------------------------
# A full disk: a 300 kB tmpfs, filled up to the last page
# ---------------------------------------------------------------------------------------


def _fill(directory: Path, leave: int = 4096) -> None:
    stats = os.statvfs(directory)
    free = stats.f_bavail * stats.f_frsize
    with open(directory.parent / "filler", "wb") as stream:
        stream.write(b"\0" * max(0, free - leave))


@pytest.fixture
def small_disk(tmp_path: Path) -> Iterator[Path]:
    """An empty directory on a fresh 300 kB tmpfs (skipped where none can be mounted)."""
    mount = tmp_path / "disk"
    mount.mkdir()
    if not hasattr(os, "geteuid") or os.geteuid() != 0:
        pytest.skip("mounting a tmpfs needs root")
    if shutil.which("mount") is None:
        pytest.skip("no mount(8) on this system")
    command = ["mount", "-t", "tmpfs", "-o", "size=300k", "tmpfs", str(mount)]
    mounted = subprocess.run(command, capture_output=True, text=True, check=False)
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {mounted.stderr.strip()}")
    try:
        directory = mount / "out"
        directory.mkdir()
        yield directory
    finally:
        if subprocess.run(["umount", str(mount)], check=False).returncode != 0:
            subprocess.run(["umount", "-l", str(mount)], check=False)


@pytest.fixture
def full_disk(small_disk: Path) -> Path:
    _fill(small_disk)
    return small_disk


def _assert_full_disk_line(line: str, target: Path) -> None:
    assert line.startswith("celtstone: error: cannot write output: "), line
    assert str(target) in line and os.strerror(errno.ENOSPC) in line, line
    assert ".part" not in line, line


@pytest.mark.parametrize(
    ("argv", "name"),
    [
        (["run", "--t-end", "0.2", "--samples", "3000", "--out", "{target}"], "x.nc"),
        (["animate", "{run}", "--out", "{target}", "--size", "160x128", "--speed", "4"], "a.mp4"),
        (["animate", "{run}", "--out", "{target}", "--size", "160x128", "--speed", "4"], "a.gif"),
    ],
    ids=["run-nc", "animate-mp4", "animate-gif"],
)
def test_full_disk_cli_in_a_subprocess(
    full_disk: Path, run_file: Path, argv: list[str], name: str
) -> None:
    """Tracebacks and "Exception ignored" reports go to stderr: one line it must be."""
    target = full_disk / name
    command = [sys.executable, "-m", "celtstone", *_argv(argv, run_file, target)]
    result = subprocess.run(command, capture_output=True, text=True, timeout=300, check=False)
    assert result.returncode == 1, result.stderr
    assert "wrote" not in result.stdout
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    _assert_full_disk_line(lines[0], target)
    assert list(full_disk.iterdir()) == []


@pytest.mark.parametrize(
    ("argv", "name"),
    [
        (["export", "{run}", "--csv", "--out", "{target}"], "x.csv"),
        (["plot", "{run}", "--out", "{target}"], "x.png"),
        (["plot", "{run}", "--out", "{target}"], "x.svg"),
        (["view", "{run}", "--out", "{target}"], "x.html"),
    ],
    ids=["export-csv", "plot-png", "plot-svg", "view-html"],
)
def test_full_disk_cli_in_process(
    capfd: pytest.CaptureFixture[str], full_disk: Path, run_file: Path, argv: list[str], name: str
) -> None:
    target = full_disk / name
    line = _one_error_line(capfd, main(_argv(argv, run_file, target)), 1)
    _assert_full_disk_line(line, target)
    assert list(full_disk.iterdir()) == []


def test_full_disk_python_writers(
    capfd: pytest.CaptureFixture[str], full_disk: Path, run_dataset: xr.Dataset
) -> None:
    numbers = {"values": list(np.linspace(0.0, 1.0, 2000))}
    table = pd.DataFrame({"a": np.arange(2000.0)})
    writers = {
        "a.json": lambda path: export.write_json(numbers, path),
        "a.csv": lambda path: export.write_table(table, path, {"software": "test"}),
        "a.nc": lambda path: export.write(run_dataset, path),
    }
    for name, write in writers.items():
        with pytest.raises(OutputError) as caught:
            write(full_disk / name)
        assert caught.value.errno == errno.ENOSPC, name
        assert str(caught.value).startswith(f"{full_disk / name}: "), name
        assert list(full_disk.iterdir()) == [], name
    assert capfd.readouterr().err == ""


def _tiny_layout() -> tuple[Layout, dict, dict]:
    layout = Layout.for_shape(("friction_coefficient",), (4,), 2)
    values = np.array([0.1, 0.2, 0.3, 0.4])
    coords = {"friction_coefficient": (("friction_coefficient",), values, {"units": "1"})}
    return layout, coords, {"sweep_spec": "{}"}


def test_full_disk_sweep_store(small_disk: Path) -> None:
    """The skeleton cannot be written: nothing left; a block cannot be written: one error
    naming the store, the block stays unmarked (to be resumed)."""
    layout, coords, attrs = _tiny_layout()
    store = SweepStore.create(small_disk / "s.zarr", layout, coords, attrs)
    _fill(small_disk, leave=0)
    with pytest.raises(OutputError) as caught:
        SweepStore.create(small_disk / "t.zarr", layout, coords, attrs)
    assert caught.value.errno == errno.ENOSPC
    assert str(caught.value).startswith(f"{small_disk / 't.zarr'}: ")
    # the store still open for writing holds its lock (beside it, until closed)
    assert sorted(p.name for p in small_disk.iterdir()) == [".s.zarr.lock", "s.zarr"]
    results = {name: np.ones(2) for name in STORE_FIELDS}  # every field of a sweep
    results["status"] = np.array(["success"] * 2)
    results["message"] = np.array(["a long message " * 500] * 2)
    with pytest.raises(OutputError) as caught:
        store.write_block((slice(0, 2),), results)
    assert str(caught.value).startswith(f"{small_disk / 's.zarr'}: ")
    assert store.done_blocks() == set()


# ---------------------------------------------------------------------------------------
# Reproduce: staged targets, the run's identity, no staging left
# ---------------------------------------------------------------------------------------


def _tiny_study(body: str) -> Study:
    """Two threshold runs of 0.2 s and no bisection: the cheapest whole target."""
    return Study(
        body=body, threshold_grid=(0.1, 0.5, 2), threshold_t_end=0.2, bisection_tolerance=1.0
    )


def _staging(out: Path) -> list[Path]:
    return sorted(out.glob(".reproduce.*"))


def test_reproduce_records_its_run_and_the_report_tells_runs_apart(tmp_path: Path) -> None:
    reproduce(["threshold"], tmp_path, [_tiny_study(KL)], progress=False)
    reproduce(["threshold"], tmp_path, [_tiny_study(TOY)], progress=False)
    runs = [
        json.loads((tmp_path / "data" / f"threshold_{body}.json").read_text())["run"]
        for body in (KL, TOY)
    ]
    assert runs[0]["id"] != runs[1]["id"]
    for run, body in zip(runs, (KL, TOY), strict=True):
        assert run["celtstone_version"] == cs.version()
        assert run["targets"] == ["threshold"] and run["bodies"] == [body]
        assert run["finished_utc"].endswith("Z")
    report = (tmp_path / "report.md").read_text(encoding="utf-8")
    assert "2 different runs" in report
    for run in runs:
        assert f"`{run['id']}`" in report and run["finished_utc"] in report
    assert _staging(tmp_path) == []
    # one run for both bodies (replacing their earlier results): one identity, no warning
    studies = [_tiny_study(KL), _tiny_study(TOY)]
    reproduce(["threshold"], tmp_path, studies, progress=False, overwrite=True)
    report = (tmp_path / "report.md").read_text(encoding="utf-8")
    assert "different runs" not in report
    assert _staging(tmp_path) == []


def test_reproduce_on_a_full_disk_leaves_nothing(full_disk: Path) -> None:
    with pytest.raises(OutputError) as caught:
        reproduce(["threshold"], full_disk, [_tiny_study(KL)], progress=False)
    assert caught.value.errno == errno.ENOSPC
    assert Path(caught.value.path).parent in (full_disk, full_disk / "data")  # not staging
    assert list(full_disk.iterdir()) == []


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_interrupted_reproduce_leaves_the_old_files_and_no_staging(
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    sig: signal.Signals,
) -> None:
    """A signal in the second run of a target: nothing of that target reaches ``out``,
    the files of an earlier, finished run it was to replace (``--overwrite``) are
    untouched, the staging directory is gone, and a staging directory left by a killed
    process is removed too."""
    reproduce(["threshold"], tmp_path, [_tiny_study(KL)], progress=False)
    earlier = _snapshot(tmp_path)
    assert f"threshold_{KL}.png" in earlier
    live = tmp_path / f".reproduce.{os.getppid()}.{RANDOM}.part"
    stale = tmp_path / f".reproduce.{_dead_pid()}.{RANDOM}.part"
    for staging in (live, stale):
        (staging / "data").mkdir(parents=True)
        (staging / "data" / "threshold_x.json").write_text("{}", encoding="utf-8")
    original = reproduce_cases.simulate
    calls = {"n": 0}

    def signalled(*args: object, **kwargs: object) -> object:
        calls["n"] += 1
        if calls["n"] == 2:
            _signal_self(sig)
        return original(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(reproduce_cases, "simulate", signalled)
    argv = ["reproduce", "threshold", "--quick", "--no-progress", "--out", str(tmp_path)]
    status = main([*argv, "--body", KL, "--overwrite"])
    line = _one_error_line(capsys, status, 128 + sig, after_warnings=True)
    assert "no partial output was written" in line
    assert not stale.exists()
    after = _snapshot(tmp_path)
    assert {k: v for k, v in after.items() if not k.startswith(live.name)} == earlier
    assert live.is_dir()


def test_a_signal_during_the_final_moves_waits_for_them() -> None:
    """reproduce's last renames finish before Ctrl-C acts; both handlers are back after."""
    handlers = (signal.SIGINT, signal.SIGTERM)
    before = {number: signal.getsignal(number) for number in handlers}
    assert callable(before[signal.SIGINT])
    finished = []
    with pytest.raises(KeyboardInterrupt), reproduce_targets._signals_deferred():
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(0.2)  # the handler runs here, and only notes the signal
        finished.append("the moves")
    assert finished == ["the moves"]
    assert {number: signal.getsignal(number) for number in handlers} == before


def test_a_signal_between_the_two_swaps_leaves_no_handler_swapped(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A SIGTERM raising as the deferral swaps its second handler (the first already
    swapped) puts the first one back too."""
    handlers = (signal.SIGINT, signal.SIGTERM)
    before = {number: signal.getsignal(number) for number in handlers}
    real = signal.signal

    def swapped_then_terminated(number: int, handler: object) -> object:
        previous = real(number, handler)  # type: ignore[arg-type]
        if number == signal.SIGINT and callable(handler) and handler is not before[number]:
            raise Terminated  # as the SIGTERM handler would, at the next bytecode
        return previous

    monkeypatch.setattr(signal, "signal", swapped_then_terminated)
    with pytest.raises(Terminated), reproduce_targets._signals_deferred():
        raise AssertionError("the block must not run")
    monkeypatch.setattr(signal, "signal", real)
    assert {number: signal.getsignal(number) for number in handlers} == before


_ENDLESS = """
import importlib, sys
from celtstone.cli.main import main
from celtstone.simulation.models import RollingModel

module = importlib.import_module(sys.argv[1])  # where the command finds simulate
simulate = module.simulate

def endless(model, body, state, t_end, **settings):
    # one write: the threshold's runs start side by side, and print's two writes (the
    # text, then the newline) would interleave into "simulatingsimulating\\n"
    sys.stdout.write("simulating\\n")
    sys.stdout.flush()
    settings["n_samples"] = 1001
    return simulate(RollingModel(), body, state, 1e6, **settings)  # about an hour

module.simulate = endless
sys.exit(main(sys.argv[2:]))
"""


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize(
    ("module", "command"),
    [
        ("celtstone.reproduce.cases", ["reproduce", "threshold", "--quick", "--contact", "paper"]),
        ("celtstone.cli.run", ["run", "--t-end", "1e6", "--out", "run.nc"]),
    ],
    ids=["reproduce", "run"],
)
def test_a_signal_stops_a_command_inside_a_compiled_run(
    tmp_path: Path, sig: signal.Signals, module: str, command: list[str]
) -> None:
    """The signal does not wait for the compiled loop to return (a rolling run of 1e6 s
    here, about an hour): the command stops within seconds, in one line, with the
    signal's exit status, and writes nothing."""
    argv = [*command, "--no-progress", "--body", KL]
    if command[0] == "reproduce":
        argv += ["--out", "results"]
    process = subprocess.Popen(
        [sys.executable, "-c", _ENDLESS, module, *argv],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert process.stdout is not None
        assert process.stdout.readline() == "simulating\n"
        time.sleep(1.0)  # inside the compiled loop
        signalled = time.monotonic()
        process.send_signal(sig)
        _, err = process.communicate(timeout=30)
    finally:
        if process.poll() is None:  # a failed assertion above: stop it and close its pipes
            process.kill()
            process.communicate()
    assert time.monotonic() - signalled < 10.0
    assert process.returncode == 128 + sig, err
    assert "Traceback" not in err and len(err.splitlines()) == 1, err
    assert [p.name for p in tmp_path.iterdir() if p.name != "results"] == []
    assert _staging(tmp_path / "results") == [] and not (tmp_path / "results" / "data").exists()


# ---------------------------------------------------------------------------------------
# Runs with too few samples
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("command", "samples"),
    [("plot", 0), ("plot", 1), ("export", 0), ("export", 1), ("view", 0), ("animate", 0)],
)
def test_run_with_too_few_samples_is_refused(
    capsys: pytest.CaptureFixture[str],
    run_dataset: xr.Dataset,
    tmp_path: Path,
    samples: int,
    command: str,
) -> None:
    path = tmp_path / "short.nc"
    run_dataset.isel(time=slice(0, samples)).to_netcdf(path, unlimited_dims=["time"])
    outputs = {
        "plot": [],
        "export": ["--csv"],
        "view": ["--out", str(tmp_path / "p.html")],
        "animate": ["--out", str(tmp_path / "v.gif")],
    }
    before = _snapshot(tmp_path)
    line = _one_error_line(capsys, main([command, str(path), *outputs[command]]), 2)
    assert line.startswith("celtstone: error: run = "), line
    assert "sample" in line, line
    assert _snapshot(tmp_path) == before
