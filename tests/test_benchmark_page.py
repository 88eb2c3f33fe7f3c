"""``make bench`` writes docs/benchmarks.md: each script replaces its own section only."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks import _page  # noqa: E402

MEASURED = {"command": "python benchmarks/bench_x.py", "machine": "a CPU", "date": "a day"}


def test_a_new_section_is_appended_with_its_machine_date_and_command(tmp_path: Path) -> None:
    page = tmp_path / "benchmarks.md"
    _page.write_section("bench_x", "X against SciPy", "ratio 100x\n", page=page, **MEASURED)
    text = page.read_text("utf-8")
    assert text.startswith(_page.HEADER)
    assert "## X against SciPy" in text
    for line in ("- machine: a CPU", "- date: a day", "- command: `python benchmarks/bench_x.py`"):
        assert line in text.splitlines()
    assert "```text\nratio 100x\n```" in text


def test_a_rerun_replaces_its_section_and_keeps_the_others(tmp_path: Path) -> None:
    page = tmp_path / "benchmarks.md"
    _page.write_section("bench_x", "X", "old x\n", page=page, **MEASURED)
    _page.write_section("bench_y", "Y", "y\n", page=page, **MEASURED)
    _page.write_section("bench_x", "X", "new x\n", page=page, **MEASURED)
    text = page.read_text("utf-8")
    assert "old x" not in text and text.count("new x") == 1
    assert text.count("## X") == 1 and text.count("## Y") == 1
    assert text.index("## X") < text.index("## Y")  # in place, not moved to the end
    assert list(tmp_path.iterdir()) == [page]  # no temporary left


def test_recorded_writes_what_was_printed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    page = tmp_path / "benchmarks.md"
    with _page.recorded("bench_z", "Z", page=page):
        print("steps 14007")
    assert "steps 14007" in capsys.readouterr().out  # still shown on the terminal
    text = page.read_text("utf-8")
    assert "```text\nsteps 14007\n```" in text and "- machine: " in text


def test_a_benchmark_that_fails_leaves_the_page_as_it_was(tmp_path: Path) -> None:
    page = tmp_path / "benchmarks.md"
    _page.write_section("bench_z", "Z", "kept\n", page=page, **MEASURED)
    before = page.read_text("utf-8")
    with pytest.raises(KeyboardInterrupt), _page.recorded("bench_z", "Z", page=page):
        print("half a table")
        raise KeyboardInterrupt
    assert page.read_text("utf-8") == before


def test_a_fence_in_the_output_does_not_end_the_block() -> None:
    text = _page.section("b", "B", "a ``` b\n", command="c", machine="m", date="d")
    assert "````text\na ``` b\n````" in text


def test_the_shipped_page_has_the_header_and_the_scripts_of_make_bench_write_it() -> None:
    assert _page.PAGE.read_text("utf-8").startswith(_page.HEADER)
    makefile = (ROOT / "Makefile").read_text("utf-8")
    scripts = {line.split()[1] for line in makefile.splitlines() if "benchmarks/bench_" in line}
    for script in scripts:
        name = Path(script).stem
        source = (ROOT / script).read_text("utf-8")
        assert f'recorded("{name}"' in source, script
