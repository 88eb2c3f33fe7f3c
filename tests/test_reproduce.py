"""``celtstone reproduce`` in reduced form: the paper's qualitative findings that our
model reproduces, the files and their provenance, and interruption safety.

Expected behaviour comes from the paper (section 4) and from invariants; the
reduced study keeps the physics (same body, start, ε, f) with shorter runs.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import imageio_ffmpeg
import numpy as np
import pytest
import xarray as xr

import celtstone as cs
from celtstone.cli.main import main
from celtstone.files.export import read_table
from celtstone.reproduce import Study, reduced, threshold
from celtstone.reproduce import cases as reproduce_cases
from celtstone.reproduce.findings import (
    judge_energy_decrease,
    judge_energy_order,
    judge_long_run,
    judge_period_growth,
    judge_threshold,
)
from celtstone.reproduce.progress import progress_bar
from tests.conftest import QUICK_REPRODUCTION, QuickReproduction

KL = Study(body="kane_levinson_1982")
QUICK = pytest.mark.xdist_group(QUICK_REPRODUCTION)  # one worker computes it (conftest)


def _quick_kl(out: Path) -> list[str]:
    """CLI options of a quick, silent reproduction of the K&L body (the paper's contact)
    into ``out``."""
    return [
        *("--quick", "--no-progress", "--out", str(out)),
        *("--body", "kane_levinson_1982", "--contact", "paper"),
    ]


def _quiet(total: int = 0):
    return progress_bar(total, "test", enabled=False)


@pytest.fixture(scope="module")
def fig2_kl(quick_reproduction: QuickReproduction) -> tuple[Path, dict]:
    """Figure 2 of the K&L body from the quick reproduction: runs of 5 s (a quarter of
    the paper's 20 s; the reversals come before 3 s), its directory and its numbers."""
    out = quick_reproduction.out
    assert quick_reproduction.status == 0
    result = json.loads((out / "data" / "fig2_kane_levinson_1982.json").read_text())
    assert result["t_end"] == reduced(KL).fig2_t_end == 5.0
    return out, result


def _static(result: dict) -> dict[float, dict]:
    return {
        c["friction_coefficient"]: c
        for c in result["cases"]
        if c["model"] == "sliding" and c["friction_load"] == "static"
    }


@QUICK
def test_fig2_reversal_order_in_f(fig2_kl: tuple[Path, dict]) -> None:
    """Paper: the period of the Celt effect grows as f falls; K&L reverses at 0.35 and
    0.25 (later at 0.25) and not at 0.15 (below this body's threshold)."""
    cases = _static(fig2_kl[1])
    t35 = cases[0.35]["first_reversal_time"]
    t25 = cases[0.25]["first_reversal_time"]
    assert t35 is not None and t25 is not None
    assert t35 < t25
    assert cases[0.15]["first_reversal_time"] is None
    assert judge_period_growth(fig2_kl[1]).reproduced == "partly"


@QUICK
def test_fig2_energy_falls_monotonically_and_matches_friction_work(
    fig2_kl: tuple[Path, dict],
) -> None:
    """Sliding dissipates: the sampled energy never rises, and E(0) − E = W."""
    for case in fig2_kl[1]["cases"]:
        if case["model"] != "sliding":
            continue
        assert case["energy_monotone"], case["case"]
        assert case["energy_final"] < case["energy_initial"]
        assert case["max_energy_balance_error"] < 1e-9 * case["energy_initial"]
    rolling = next(c for c in fig2_kl[1]["cases"] if c["model"] == "rolling")
    assert (
        abs(rolling["energy_final"] - rolling["energy_initial"]) < 1e-8 * rolling["energy_initial"]
    )
    assert judge_energy_decrease([fig2_kl[1]]).reproduced == "yes"


@QUICK
def test_fig2_energy_falls_with_f(fig2_kl: tuple[Path, dict]) -> None:
    """Paper: as f falls the energy of motion falls (K&L, at the end of the run)."""
    cases = _static(fig2_kl[1])
    energies = [cases[f]["energy_final"] for f in (0.35, 0.25, 0.15)]
    assert energies[0] > energies[1] > energies[2]
    assert judge_energy_order(fig2_kl[1]).reproduced in {"yes", "partly"}


@QUICK
def test_fig2_files_and_provenance(fig2_kl: tuple[Path, dict]) -> None:
    """Figures as PNG and SVG, a CSV with provenance, one NetCDF per run with attrs."""
    out, result = fig2_kl
    for name in ("fig2_kane_levinson_1982", "fig2_kane_levinson_1982_energy"):
        for suffix in (".png", ".svg"):
            assert (out / f"{name}{suffix}").stat().st_size > 1000
    table, header = read_table(out / "fig2_kane_levinson_1982.csv")
    assert len(table) == 7
    for key in ("software", "body", "body_source", "friction_law", "rtol", "atol"):
        assert header[key]
    assert header["software"] == f"celtstone {cs.version()}"
    assert "Kane" in header["body_source"]
    for case in result["cases"]:
        with xr.open_dataset(out / case["file"]) as dataset:
            assert dataset.attrs["celtstone_version"] == cs.version()
            assert dataset.attrs["model"] == case["model"]
            assert float(dataset.attrs["rtol"]) == KL.rtol
            if case["model"] == "sliding":
                assert dataset.attrs["friction_load"] == case["friction_load"]
                assert float(dataset.attrs["contact_radius"]) == 1e-3
    assert json.loads((out / "data" / "fig2_kane_levinson_1982.json").read_text())["cases"]
    # the video: rolling beside sliding at f = 0.35, 5 s in real time at 30 fps
    video = out / result["animation"]
    assert video.name == "fig2_kane_levinson_1982_rolling_vs_sliding.mp4"
    frames, seconds = imageio_ffmpeg.count_frames_and_secs(str(video))
    assert frames == 151
    assert seconds == pytest.approx(151 / 30.0, abs=0.01)


def test_threshold_reduced_kane_levinson(tmp_path: Path) -> None:
    """K&L with ε = 1 mm: no reversal at f = 0.02, reversal at f = 0.5, and one change
    between them, bracketed to the tolerance."""
    study = dataclasses.replace(
        reduced(KL), threshold_t_end=5.0, threshold_grid=(0.02, 0.5, 4), bisection_tolerance=0.04
    )
    result = threshold(study, tmp_path, _quiet())
    assert result["grid_reverses"][0] is False
    assert result["grid_reverses"][-1] is True
    (boundary,) = result["boundaries"]
    low, high = boundary["bracket"]
    assert boundary["kind"] == "appears"
    assert 0.0 < high - low <= 0.04
    table, header = read_table(tmp_path / "threshold_kane_levinson_1982.csv")
    assert set(table["source"]) == {"grid", "bisection"}
    at_low = table[table["friction_coefficient"] == low]["reverses"].item()
    at_high = table[table["friction_coefficient"] == high]["reverses"].item()
    assert (at_low, at_high) == (False, True)
    assert np.all(np.isnan(table[~table["reverses"]]["first_reversal_time"]))
    assert header["bisection_tolerance"] == "0.04"
    assert (tmp_path / "threshold_kane_levinson_1982.svg").exists()


@QUICK
def test_reproduce_all_quick_writes_report(quick_reproduction: QuickReproduction) -> None:
    """The CLI end to end in --quick form for one body: every target, a report with a
    table per finding and a verdict in each; each run computed ahead is asked for."""
    out = quick_reproduction.out
    assert quick_reproduction.argv == ["reproduce", "all", *_quick_kl(out)]
    assert quick_reproduction.status == 0
    # every planned run was asked for; the one-at-a-time rows "paper's contact" and
    # "consistent load" at f = 0.35 (--quick's only f) are Figure 2's sliding runs at
    # 0.35 with N = m g and with the dynamic N: handed over, not computed again
    (runs,) = quick_reproduction.shared
    assert (runs.unclaimed, runs.shared) == (0, 2)
    report = (out / "report.md").read_text()
    assert "--quick" in report
    for heading in ("Figure 2", "threshold", "Figure 3", "energy budget"):
        assert heading in report
    assert report.count("| body and start | our number | reproduced |") == 5
    for figure in (
        "fig2_kane_levinson_1982.png",
        "fig3_kane_levinson_1982.png",
        "threshold_kane_levinson_1982.png",
    ):
        assert f"]({figure})" in report
        assert (out / figure).exists()
    assert "](fig2_kane_levinson_1982_rolling_vs_sliding.mp4)" in report
    assert not list(out.rglob("*.part"))


def test_interrupt_leaves_only_whole_files(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Ctrl-C in the third run: exit 130, no temporary files, nothing of the unfinished
    target (its files reach ``out`` only when it is done)."""
    original = reproduce_cases.simulate
    calls = {"n": 0}

    def interrupted(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 3:
            raise KeyboardInterrupt
        return original(*args, **kwargs)

    monkeypatch.setattr(reproduce_cases, "simulate", interrupted)
    code = main(["reproduce", "fig2", *_quick_kl(tmp_path)])
    assert code == 130
    assert not list(tmp_path.rglob("*.part"))
    assert not (tmp_path / "report.md").exists()
    assert list(tmp_path.iterdir()) == []


def test_bad_targets_and_bodies(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["reproduce", "fig4", "--out", str(tmp_path)]) == 2
    assert "target = 'fig4'" in capsys.readouterr().err
    assert main(["reproduce", "fig2", "--body", "no_such_body", "--out", str(tmp_path)]) == 2
    assert "body" in capsys.readouterr().err
    blocker = tmp_path / "file"
    blocker.write_text("x")
    assert main(["reproduce", "fig2", "--out", str(blocker), "--quick", "--no-progress"]) == 2
    with pytest.raises(cs.ParameterError, match="threshold_grid"):
        Study(body="kane_levinson_1982", threshold_grid=(0.5, 0.1, 10))


# The rules that turn numbers into verdicts, on hand-made numbers.


def _fig2(
    times: dict[float, float | None], energies: dict[float, float], spins: dict[float, float]
):
    cases = [{"model": "rolling", "first_reversal_time": 2.9}]
    for f, t in times.items():
        cases.append(
            {
                "model": "sliding",
                "friction_load": "static",
                "friction_coefficient": f,
                "first_reversal_time": t,
                "energy_final": energies[f],
                "energy_initial": 10.0,
                "energy_rest": 0.0,
                "peak_reversed_spin": spins[f],
                "spin_initial": -5.0,
            }
        )
    return {"cases": cases}


def test_verdict_rules() -> None:
    same = {0.35: 1.0, 0.25: 1.0, 0.15: 1.0}
    assert (
        judge_period_growth(_fig2({0.35: 1.0, 0.25: 2.0, 0.15: 3.0}, same, same)).reproduced
        == "yes"
    )
    assert (
        judge_period_growth(_fig2({0.35: 1.0, 0.25: 2.0, 0.15: None}, same, same)).reproduced
        == "partly"
    )
    assert (
        judge_period_growth(_fig2({0.35: 2.0, 0.25: 1.0, 0.15: 3.0}, same, same)).reproduced == "no"
    )
    falling = {0.35: 3.0, 0.25: 2.0, 0.15: 1.0}
    assert judge_energy_order(_fig2(same, falling, falling)).reproduced == "yes"
    assert judge_energy_order(_fig2(same, falling, same)).reproduced == "partly"
    assert judge_energy_order(_fig2(same, same, same)).reproduced == "no"
    # runs that all end at rest: energies and spins that differ by round-off order nothing
    # (the toy stone's realistic runs: E − m g l = 4.9e-17, 1.5e-17, −1.9e-16 J)
    at_rest = {0.35: 4.9e-17, 0.25: 1.5e-17, 0.15: -1.9e-16}
    assert judge_energy_order(_fig2(same, at_rest, at_rest)).reproduced == "no"
    assert judge_energy_order(_fig2(same, falling, at_rest)).reproduced == "partly"

    def thresh(boundaries, grid_reverses):
        reversing = [b["bracket"][1] for b in boundaries if b["kind"] == "appears"]
        return {
            "grid": [0.02, 0.5],
            "boundaries": boundaries,
            "grid_reverses": grid_reverses,
            "reverses_anywhere": any(grid_reverses) or bool(boundaries),
            "lowest_reversing_f": min(reversing) if reversing else None,
        }

    near = [{"kind": "appears", "bracket": [0.09, 0.095]}]
    far = [{"kind": "appears", "bracket": [0.21, 0.215]}]
    assert judge_threshold(thresh(near, [False, True])).reproduced == "yes"
    assert judge_threshold(thresh(far, [False, True])).reproduced == "partly"
    assert judge_threshold(thresh([], [True, True])).reproduced == "no"

    def long_run(r, s, raw_r, raw_s):
        return {
            "friction": 0.35,
            "band": 0.2,
            "cases": [
                {"reversal_times": r, "spin_crossing_count": raw_r, "spin_final": 1.0},
                {"reversal_times": s, "spin_crossing_count": raw_s, "spin_final": 0.0},
            ],
        }

    assert judge_long_run(long_run([3, 17, 31, 45], [2, 9, 12, 15], 4, 4)).reproduced == "yes"
    assert judge_long_run(long_run([3, 17, 31], [2], 10, 500)).reproduced == "partly"
    assert judge_long_run(long_run([3, 17], [2], 10, 500)).reproduced == "no"
    assert judge_long_run(long_run([3, 17, 31], [], 10, 500)).reproduced == "no"
