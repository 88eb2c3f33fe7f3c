"""Bad sweep invocations: one line, exit 2, and nothing created, before any point is made.

Every case runs ``celtstone sweep ... --out STORE`` in-process
(``celtstone.cli.main.main``): exit status 2, exactly one line on standard error naming
the parameter, nothing on standard output, no numpy warning, and no store (nor
anything else) left in the output directory, so a corrected rerun is never blocked.
The compiled batch driver is replaced by one that fails the test: a refused sweep
computes nothing.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from celtstone import ParameterError
from celtstone.cli.main import main
from celtstone.solvers import batch
from celtstone.sweep import budget, open_sweep, runner, spec

FAST = ["--model", "rolling", "--t-end", "0.05", "--no-progress", "--no-maps"]
GRID = ["--vary", "initial_spin=-5,5"]


@pytest.fixture(autouse=True)
def no_computation(monkeypatch: pytest.MonkeyPatch) -> None:
    """Refused input never reaches the compiled driver."""

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("a point was computed although the sweep is invalid")

    monkeypatch.setattr(batch, "run_batch", refuse)


def _refused(capsys: pytest.CaptureFixture[str], tmp_path: Path, argv: list[str], name: str) -> str:
    """Run the sweep into tmp_path/out.zarr; assert the contract; return the line."""
    before = sorted(p.name for p in tmp_path.iterdir())
    status = main(["sweep", *argv, "--out", str(tmp_path / "out.zarr")])
    out, err = capsys.readouterr()
    assert status == 2, err
    assert out == ""
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("celtstone: error: ")
    assert "Traceback" not in err and "Warning" not in err
    assert name in lines[0], lines[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing created
    return lines[0]


# (id, argv after "sweep", the parameter the line names)
OPTION_CASES = [
    ("workers-negative", [*GRID, *FAST, "--workers", "-1"], "workers"),
    ("workers-zero", [*GRID, *FAST, "--workers", "0"], "workers"),
    ("workers-a-million", [*GRID, *FAST, "--workers", "1000000"], "workers"),
    ("workers-text", [*GRID, *FAST, "--workers", "many"], "workers"),
    ("chunk-zero", [*GRID, *FAST, "--chunk-points", "0"], "chunk"),
    ("chunk-negative", [*GRID, *FAST, "--chunk-points", "-3"], "chunk"),
    ("chunk-huge", [*GRID, *FAST, "--chunk-points", "100000000"], "chunk_points"),
    ("samples-zero", [*GRID, *FAST, "--samples-per-second", "0"], "samples_per_second"),
    ("samples-nan", [*GRID, *FAST, "--samples-per-second", "nan"], "samples_per_second"),
    ("samples-inf", [*GRID, *FAST, "--samples-per-second", "inf"], "samples_per_second"),
    ("samples-text", [*GRID, *FAST, "--samples-per-second", "often"], "samples_per_second"),
    ("samples-too-many", [*GRID, *FAST, "--samples-per-second", "1e9"], "samples_per_second"),
    ("threshold-zero", [*GRID, *FAST, "--reversal-threshold", "0"], "reversal_threshold"),
    ("threshold-negative", [*GRID, *FAST, "--reversal-threshold", "-1"], "reversal_threshold"),
    ("threshold-nan", [*GRID, *FAST, "--reversal-threshold", "nan"], "reversal_threshold"),
    ("t-end-negative", [*GRID, "--t-end", "-1", "--no-maps"], "t_end"),
    ("scheduler-bogus", [*GRID, *FAST, "--scheduler", "bogus"], "scheduler"),
    (
        "scheduler-and-workers",
        [*GRID, *FAST, "--scheduler", "tcp://h:1", "--workers", "2"],
        "workers",
    ),
    ("vary-and-points", [*GRID, *FAST, "--points", "p.csv"], "points"),
    # a body and a model fine alone, not together (models.kernel_parameters): still
    # refused before the store is created
    ("damping-stops-the-body", ["--vary", "damping=0,1e6", *FAST], "damping"),
    ("nothing-varied", FAST, "vary"),
]

# --vary texts: every path of the axis parser, none with a numpy warning
AXIS_CASES = [
    ("stop-inf", "friction_coefficient=0:inf:2", "friction_coefficient"),
    ("start-nan", "friction_coefficient=nan:1:2", "friction_coefficient"),
    ("start-overflow", "initial_spin=-1e400:1:3", "initial_spin"),
    ("span-overflow", "initial_spin=-1e308:1e308:3", "initial_spin"),
    ("all-equal", "initial_spin=1e308:1e308:3", "initial_spin"),
    ("repeated-value", "initial_spin=1,2,1", "initial_spin"),
    ("negative-zero-twice", "initial_spin=-0,0", "initial_spin"),
    ("list-inf", "initial_spin=1,inf", "initial_spin"),
    ("list-overflow", "initial_spin=1,1e999", "initial_spin"),
    ("list-empty-item", "initial_spin=1,,2", "initial_spin"),
    ("count-nan", "initial_spin=0:1:nan", "initial_spin count"),
    ("count-inf", "initial_spin=0:1:inf", "initial_spin count"),
    ("count-overflow", "initial_spin=0:1:1e400", "initial_spin count"),
    ("count-fraction", "initial_spin=0:1:2.5", "initial_spin count"),
    ("count-zero", "initial_spin=0:1:0", "initial_spin count"),
    ("count-negative", "initial_spin=0:1:-4", "initial_spin count"),
    ("count-absurd", "friction_coefficient=0.1:0.3:100000000", "friction_coefficient count"),
    ("count-huge-integer", "initial_spin=0:1:" + "9" * 40, "initial_spin count"),
    ("two-colons", "initial_spin=0:1", "initial_spin"),
    ("unknown-name", "spn=0:1:3", "spn"),
]


@pytest.mark.parametrize(
    ("argv", "name"), [c[1:] for c in OPTION_CASES], ids=[c[0] for c in OPTION_CASES]
)
def test_bad_option_is_one_line_and_creates_nothing(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, argv: list[str], name: str
) -> None:
    _refused(capsys, tmp_path, argv, name)


@pytest.mark.parametrize(
    ("text", "name"), [c[1:] for c in AXIS_CASES], ids=[c[0] for c in AXIS_CASES]
)
def test_bad_axis_is_one_line_without_a_warning(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, text: str, name: str
) -> None:
    """pytest turns warnings into errors, and the line must be the only output."""
    _refused(capsys, tmp_path, ["--vary", text, *FAST], name)


# (id, CSV content, the parameter named, fragments of the line)
POINTS_CASES = [
    (
        "duplicate-column",
        b"initial_spin,initial_spin\n0.1,0.2\n",
        "initial_spin",
        ("columns 1 and 2",),
    ),
    ("duplicate-spelled-twice", b"euler-alpha,euler_alpha\n1,2\n", "euler_alpha", ("named once",)),
    ("empty-header-cell", b"initial_spin,\n1,2\n", "points", ("column 2",)),
    (
        "unknown-column",
        b"initial_spn\n1\n",
        "initial_spn",
        ("line 1", "column 1", "did you mean 'initial_spin'"),
    ),
    ("empty-cell", b"initial_spin,euler_alpha\n1,\n", "euler_alpha", ("line 2", "column 2")),
    (
        "text-cell",
        b"initial_spin,euler_alpha\n1,0.5\nfast,0.5\n",
        "initial_spin",
        ("line 3", "column 1"),
    ),
    ("nan-cell", b"initial_spin\nnan\n", "initial_spin", ("line 2", "finite")),
    ("inf-cell", b"initial_spin\n1\n-inf\n", "initial_spin", ("line 3", "finite")),
    ("overflow-cell", b"initial_spin\n1e999\n", "initial_spin", ("line 2", "finite")),
    ("short-row", b"initial_spin,euler_alpha\n1,0.5\n2\n", "points", ("line 3", "1")),
    ("long-row", b"initial_spin,euler_alpha\n1,0.5,3\n", "points", ("line 2", "3")),
    ("header-only", b"initial_spin,euler_alpha\n", "points", ("no rows",)),
    ("comments-only", b"# nothing here\n\n", "points", ("no header",)),
    ("empty-file", b"", "points", ("no header",)),
    ("binary", bytes(range(256)) * 4, "points", ("UTF-8",)),
    ("latin-1", "initial_spin\n1\n# Müller\n".encode("latin-1"), "points", ("UTF-8",)),
    ("bad-quoting", b'initial_spin\n"1"2\n', "points", ("CSV",)),
    ("nul-byte", b"initial_spin\n1\x00\n", "initial_spin", ("line 2",)),
]


@pytest.mark.parametrize(
    ("content", "name", "fragments"),
    [c[1:] for c in POINTS_CASES],
    ids=[c[0] for c in POINTS_CASES],
)
def test_bad_points_file_is_one_line_naming_file_line_and_column(
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
    content: bytes,
    name: str,
    fragments: tuple[str, ...],
) -> None:
    table = tmp_path / "points.csv"
    table.write_bytes(content)
    line = _refused(capsys, tmp_path, ["--points", str(table), *FAST], name)
    assert str(table) in line
    for fragment in fragments:
        assert fragment in line, line


def test_missing_points_file_is_one_line(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    _refused(capsys, tmp_path, ["--points", str(tmp_path / "none.csv"), *FAST], "points")


def test_a_byte_order_mark_is_allowed_in_the_points_file(tmp_path: Path) -> None:
    """Spreadsheets write a UTF-8 byte-order mark before the header; it is not a name."""
    from celtstone.sweep.points import read_points

    table = tmp_path / "points.csv"
    table.write_bytes(
        b"\xef\xbb\xbfinitial_spin,euler_alpha\r\n-5,0.5\r\n\r\n# a comment\r\n5,1.0\r\n"
    )
    assert read_points(str(table)) == {"initial_spin": [-5.0, 5.0], "euler_alpha": [0.5, 1.0]}


@pytest.mark.parametrize(
    ("options", "name"),
    [
        ({"workers": 0}, "workers"),
        ({"workers": -1}, "workers"),
        ({"workers": runner.MAX_WORKERS + 1}, "workers"),
        ({"workers": True}, "workers"),
        ({"workers": 2.5}, "workers"),
        ({"chunk_points": 0}, "chunk_points"),
        ({"chunk_points": 1.5}, "chunk_points"),
        ({"chunk_points": float("nan")}, "chunk_points"),
        ({"task_points": 0}, "task_points"),
        ({"scheduler": "tcp://h:1", "workers": 1}, "workers"),
        ({"scheduler": ""}, "scheduler"),
    ],
)
def test_run_options_from_python_are_checked_before_the_store(
    tmp_path: Path, options: dict[str, object], name: str
) -> None:
    sweep = runner.Sweep({"initial_spin": [-5.0, 5.0]}, model="rolling", t_end=0.05)
    with pytest.raises(ParameterError) as caught:
        sweep.run(tmp_path / "out.zarr", **options)  # type: ignore[arg-type]
    assert caught.value.name == name
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------- size


@pytest.fixture
def no_point_builder(monkeypatch: pytest.MonkeyPatch) -> None:
    """A sweep refused for its size is refused before any point is made or validated."""

    class Refuse:
        def __init__(self, *args: object, **kwargs: object) -> None:
            raise AssertionError("the points were built although the sweep is too large")

    monkeypatch.setattr(runner, "PointBuilder", Refuse)
    monkeypatch.setattr(spec, "_spaced", Refuse)  # nor an axis spaced


@pytest.mark.usefixtures("no_point_builder")
@pytest.mark.parametrize(
    ("axes", "force", "fragment"),
    [
        (["friction_coefficient=0.1:0.3:1001", "initial_spin=-8:8:1000"], False, "or --force"),
        (
            ["friction_coefficient=0.1:0.3:1000", "initial_spin=-8:8:1000", "damping=0:1e-5:1000"],
            False,
            "even with --force",
        ),
        (
            ["friction_coefficient=0.1:0.3:1000", "initial_spin=-8:8:1000", "damping=0:1e-5:1000"],
            True,
            "even with --force",
        ),
        (
            ["friction_coefficient=0.1:0.3:10000000", "initial_spin=-8:8:2"],
            True,
            "even with --force",
        ),
    ],
    ids=["just-over-the-limit", "billion", "billion-forced", "hard-limit-forced"],
)
def test_huge_grid_is_refused_from_its_counts(
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
    axes: list[str],
    force: bool,
    fragment: str,
) -> None:
    argv = [arg for axis in axes for arg in ("--vary", axis)] + ["--t-end", "10", "--no-maps"]
    line = _refused(capsys, tmp_path, argv + (["--force"] if force else []), "points")
    assert "friction_coefficient" in line
    assert fragment in line


def test_estimate_names_size_and_time() -> None:
    """Above the limit, the line gives the store size and CPU time behind the refusal."""
    with pytest.raises(ParameterError, match=r"store of up to .*B, about .* of CPU") as caught:
        budget.check_size({"initial_spin": 2000, "euler_alpha": 1000}, t_end=10.0, model="sliding")
    assert caught.value.name == "points"
    found = budget.check_size(
        {"initial_spin": 2000, "euler_alpha": 1000}, t_end=10.0, model="sliding", force=True
    )
    assert found.points == 2_000_000
    assert found.store_bytes == 2_000_000 * budget.store_bytes_per_point()


def test_too_many_points_in_a_file_is_refused_before_reading_on(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(budget, "POINT_LIMIT", 3)
    table = tmp_path / "points.csv"
    table.write_text("initial_spin\n1\n2\n3\n4\nnot read\n")
    line = _refused(capsys, tmp_path, ["--points", str(table), *FAST], "points")
    assert "--force" in line and "line 5" in line


def test_force_runs_a_sweep_over_the_limit(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """With a limit of 2 points, 3 points need --force; with it they run."""
    monkeypatch.undo()  # the driver computes here
    monkeypatch.setattr(budget, "POINT_LIMIT", 2)
    argv = ["sweep", "--vary", "initial_spin=-5,0.5,5", *FAST, "--out", str(tmp_path / "s.zarr")]
    assert main(argv) == 2
    assert "--force" in capsys.readouterr().err
    assert not (tmp_path / "s.zarr").exists()
    assert main([*argv, "--force"]) == 0
    assert open_sweep(tmp_path / "s.zarr")["initial_spin"].size == 3


def test_a_long_sweep_states_its_estimate_first(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.undo()
    monkeypatch.setattr("celtstone.cli.sweep.LONG_SWEEP_SECONDS", 0.0)
    argv = ["sweep", "--vary", "initial_spin=-5,5", *FAST, "--workers", "1"]
    assert main([*argv, "--out", str(tmp_path / "s.zarr")]) == 0
    err = capsys.readouterr().err
    assert err.splitlines()[0].startswith("celtstone: sweep of 2 points")
    assert "on 1 threads" in err


def test_validation_builds_each_distinct_object_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """A 300 x 300 grid over a model and a state parameter validates 300 models and
    300 states, not 90 000 of each."""
    built = {"model": 0, "state": 0}
    build_model, build_state = spec.build_model, spec.build_state

    def count_model(*args, **kwargs):  # type: ignore[no-untyped-def]
        built["model"] += 1
        return build_model(*args, **kwargs)

    def count_state(*args, **kwargs):  # type: ignore[no-untyped-def]
        built["state"] += 1
        return build_state(*args, **kwargs)

    monkeypatch.setattr(spec, "build_model", count_model)
    monkeypatch.setattr(spec, "build_state", count_state)
    sweep = runner.Sweep(
        {
            "friction_coefficient": np.linspace(0.1, 0.3, 300),
            "initial_spin": np.linspace(-8, 8, 300),
        },
        t_end=1.0,
    )
    assert sweep.size == 90_000
    assert built == {"model": 300, "state": 300}


def test_the_first_bad_point_is_named_whatever_its_group(monkeypatch: pytest.MonkeyPatch) -> None:
    """Per-group validation still reports the lowest failing point, as point by point."""
    points = {"friction_coefficient": [0.1, 0.1, -0.2, 0.1], "euler_alpha": [1.0, 95.0, 1.0, 1.0]}
    with pytest.raises(ParameterError, match=r"euler_angles.*at sweep point 1 ") as caught:
        runner.Sweep(points=points, t_end=1.0)
    assert "euler_angles" in caught.value.name


# --------------------------------------------------------------------------- scheduler


def test_unreachable_scheduler_leaves_no_store_and_a_rerun_works(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Nothing listens on port 1: the connection fails within the stated timeout, before
    the store is created, and the same command without --scheduler then runs."""
    pytest.importorskip("distributed")
    monkeypatch.setattr(runner, "SCHEDULER_TIMEOUT_SECONDS", 0.5)
    line = _refused(
        capsys, tmp_path, [*GRID, *FAST, "--scheduler", "tcp://127.0.0.1:1"], "scheduler"
    )
    assert "0.5 s" in line
    monkeypatch.undo()
    assert main(["sweep", *GRID, *FAST, "--workers", "1", "--out", str(tmp_path / "out.zarr")]) == 0
