"""``report.md``: one table per finding of the paper, built from the targets' numbers."""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

from celtstone._about import version
from celtstone.bodies import load_body
from celtstone.export import atomic_path
from celtstone.reproduce.findings import (
    FINDINGS,
    PAPER_THRESHOLD,
    Verdict,
    judge_energy_decrease,
    judge_energy_order,
    judge_long_run,
    judge_period_growth,
    judge_threshold,
)

__all__ = ["collect", "render_report", "write_report"]


def collect(out: Path) -> dict[str, dict[str, dict[str, Any]]]:
    """The numbers written by earlier targets in ``out/data``: target -> body -> result
    (a case written before the rename of ``normal_force`` reads as ``friction_load``)."""
    results: dict[str, dict[str, dict[str, Any]]] = {}
    for path in sorted((out / "data").glob("*.json")):
        result = json.loads(path.read_text(encoding="utf-8"))
        for case in result.get("cases", []):
            if "normal_force" in case and "friction_load" not in case:
                case["friction_load"] = case.pop("normal_force")
        results.setdefault(result["target"], {})[result["body"]] = result
    return results


def _table(rows: list[tuple[str, str, Verdict]], paper: str) -> list[str]:
    lines = [
        f"Paper: *{paper}*",
        "",
        "| body and start | our number | reproduced |",
        "|---|---|---|",
    ]
    for study, case, verdict in rows:
        why = f" — {verdict.why}" if verdict.why else ""
        lines.append(f"| {study}{case} | {verdict.ours} | **{verdict.reproduced}**{why} |")
    return lines


def _section(
    title: str,
    key: str,
    results: dict[str, dict[str, Any]],
    judge: Callable[[dict[str, Any]], Verdict],
    figures: Callable[[dict[str, Any]], list[str]],
    variants: tuple[tuple[str, Callable[[dict[str, Any]], Verdict]], ...] = (),
) -> list[str]:
    lines = [f"## {title}", ""]
    if not results:
        return [*lines, "Not run yet (`celtstone reproduce` with this target).", ""]
    rows = []
    for result in results.values():
        where = f"{result['study']}; {result['target']} runs of {result['t_end']:g} s"
        rows.append((where, "", judge(result)))
        for label, variant in variants:
            rows.append((where, f" ({label})", variant(result)))
    lines += _table(rows, FINDINGS[key])
    lines.append("")
    for result in results.values():
        images = [f for f in figures(result) if f.endswith(".png")]
        if not images:
            continue
        lines += [f"![{Path(f).stem}]({f})" for f in images]
        runs = " and NetCDF runs in `data/`" if result["target"] != "threshold" else ""
        lines.append(f"Data: `{result['table']}`{runs}; SVG beside each PNG.")
        if "animation" in result:
            friction = max(result["frictions"])
            lines.append(
                f"Video: [`{result['animation']}`]({result['animation']}), rolling beside "
                f"sliding at f = {friction:g} (N = m g), real time."
            )
        lines.append("")
    return lines


_WHY = """\
## Why our numbers differ from the paper's

The paper gives no body parameters, so no number of ours can be compared with its
figures digit for digit; what can be compared is the direction of each effect. Our
bodies (`docs/bodies.md`) are the Kane & Levinson (1982) ellipsoid, a heavy (1 kg, 40 cm)
benchmark, and a derived 10 cm, 14 g toy. With ε = 1 mm the sliding model has two ways
to lose the reversal:

* **small f**: the contact slides so easily that the tangential friction force cannot
  carry the coupling between rocking and spin that produces the Celt effect (in rolling
  the constraint force does it); the rocking energy is dissipated by slip instead;
* **large f with a light body**: the pivoting moment M0 = 3π f N ε / 16 (eq. 12) brakes
  the spin before the rocking instability has grown. The table gives, for f = 0.35, the
  time C |ω0| / M0 in which M0 alone would stop the initial spin, beside the first
  reversal time in rolling.

{braking}

The window of f in which the stone reverses therefore depends on the mass, the inertia,
the curvatures and ε; the paper's "about 0.1" belongs to its (unpublished) body. A real
toy of 14 g has a Hertz contact radius of order 0.1 mm, not 1 mm: we keep the paper's ε
so that the comparison is with the paper, and leave other ε to parameter sweeps.

Reversal times: a *reversal* here is a change of the sense of spin held beyond a
hysteresis band of 4 % of the initial spin (0.2 rad/s for ω0 = 5 rad/s); the raw spin
crosses zero several times within hundredths of a second around a reversal, and a
sliding stone whose spin has died changes sign many times without reversing
(`celtstone.analysis.reversal_times`).
"""

BRAKING_FRICTION = 0.35
_UNKNOWN_RUN = "unknown (made before runs were recorded)"


def _provenance(results: list[dict[str, Any]]) -> tuple[list[str], list[str]]:
    """A warning when the results come from several runs (or versions), and the table
    of when, by which version and in which run each target was made."""
    table = [
        "## Where each result comes from",
        "",
        "| target | body | finished (UTC) | celtstone | run (targets asked for) |",
        "|---|---|---|---|---|",
    ]
    runs: set[str] = set()
    versions: set[str] = set()
    for result in sorted(results, key=lambda r: (r["target"], r["body"])):
        run = result.get("run")
        if not isinstance(run, dict):
            runs.add(_UNKNOWN_RUN)
            table.append(
                f"| {result['target']} | {result['body']} | unknown | unknown | {_UNKNOWN_RUN} |"
            )
            continue
        runs.add(str(run["id"]))
        versions.add(str(run["celtstone_version"]))
        table.append(
            f"| {result['target']} | {result['body']} | {run['finished_utc']} | "
            f"{run['celtstone_version']} | `{run['id']}` ({', '.join(run['targets'])}) |"
        )
    table.append("")
    warning = []
    if len(runs) > 1:
        warning.append(
            f"**The results below come from {len(runs)} different runs of `celtstone "
            'reproduce`, not from one:** see "Where each result comes from" for which '
            "target was made when. Reproduce into an empty directory for one consistent set."
        )
    if len(versions) > 1:
        warning.append(
            "**They were made by different celtstone versions: "
            + ", ".join(sorted(versions))
            + ".**"
        )
    return ([*warning, ""] if warning else []), table


def _braking_table(fig2: dict[str, dict[str, Any]]) -> str:
    """Pivot braking time C|ω0|/M0 at f = 0.35 against the rolling reversal time."""
    lines = [
        "| body | M0 at f = 0.35 [N m] | C ω0 (magnitude) [N m s] | braking time [s] "
        "| rolling reversal [s] |",
        "|---|---|---|---|---|",
    ]
    for name, result in fig2.items():
        body = load_body(name)
        spin = abs(float(result["cases"][0]["spin_initial"]))
        moment = 3.0 * math.pi * BRAKING_FRICTION * body.mass * body.gravity * 1e-3 / 16.0
        moment *= result["contact_radius"] / 1e-3
        momentum = body.inertia_array[2, 2] * spin
        rolling = next(c for c in result["cases"] if c["model"] == "rolling")
        first = rolling["first_reversal_time"]
        lines.append(
            f"| {name} | {moment:.3g} | {momentum:.3g} | {momentum / moment:.3g} | "
            f"{'none' if first is None else f'{first:.3g}'} |"
        )
    return "\n".join(lines)


def render_report(out: Path) -> str:
    """The report's Markdown from the numbers in ``out/data``."""
    results = collect(out)
    fig2 = results.get("fig2", {})
    fig3 = results.get("fig3", {})
    threshold = results.get("threshold", {})
    lines = [
        "# celtstone reproduction of *On the influence of sliding on the Celt rattleback motion*",
        "",
        f"Generated by celtstone {version()} (`celtstone reproduce`); every number below is read "
        "from the data files beside this report. Model: rolling (paper eq. 3–5) and rolling "
        "with sliding (eq. 6–12) with Zhuravlev's Padé friction law, ε = 1 mm, N = m g unless "
        "said otherwise; integrator tolerances in each file's header.",
        "",
        "| finding | " + " | ".join(sorted({*fig2, *fig3, *threshold})) + " |",
        "|---|" + "---|" * len({*fig2, *fig3, *threshold}),
    ]
    bodies = sorted({*fig2, *fig3, *threshold})
    everything = [r for target in results.values() for r in target.values()]
    warning, provenance = _provenance(everything)
    lines[3:3] = warning
    if any(r["study"].startswith("REDUCED") for r in everything):
        lines[3:3] = [
            "**Some results below come from the shortened `--quick` form: a smoke test, not "
            "the reproduction. Run `celtstone reproduce all` for the real one.**",
            "",
        ]
    summary = [
        ("period grows as f falls", fig2, judge_period_growth),
        ("energy falls with f", fig2, judge_energy_order),
        ("energy falls in sliding", fig2, lambda r: judge_energy_decrease([r])),
        (f"no reversal below f ≈ {PAPER_THRESHOLD:g}", threshold, judge_threshold),
        ("long run: sliding changes sign faster", fig3, judge_long_run),
    ]
    for label, source, judge in summary:
        cells = [judge(source[b]).reproduced if b in source else "not run" for b in bodies]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    lines.append("")
    lines += provenance

    def figs(result: dict[str, Any]) -> list[str]:
        return list(result["figures"])

    lines += _section(
        "1. The period of the Celt effect against f (Figure 2)",
        "period",
        fig2,
        judge_period_growth,
        figs,
        (("dynamic normal force", lambda r: judge_period_growth(r, "dynamic")),),
    )
    lines += _section(
        "2. The energy against f (Figure 2)",
        "energy_order",
        fig2,
        judge_energy_order,
        lambda r: [],
        (("dynamic normal force", lambda r: judge_energy_order(r, "dynamic")),),
    )
    lines += _section(
        "3. Energy and the energy budget",
        "energy_decrease",
        {**{f"fig2 {k}": v for k, v in fig2.items()}, **{f"fig3 {k}": v for k, v in fig3.items()}},
        lambda r: judge_energy_decrease([r]),
        lambda r: [f for f in r["figures"] if "_energy" in f],
    )
    lines += _section(
        "4. The friction threshold",
        "threshold",
        threshold,
        judge_threshold,
        figs,
    )
    lines += _section(
        "5. The long run (Figure 3)",
        "long_run",
        fig3,
        judge_long_run,
        lambda r: [f for f in r["figures"] if "_energy" not in f],
    )
    lines.append(_WHY.format(braking=_braking_table(fig2) if fig2 else "(run fig2 for the table)"))
    return "\n".join(lines)


def write_report(out: Path) -> Path:
    """Write ``out/report.md`` whole or not at all (it replaces the previous report)."""
    target = out / "report.md"
    with atomic_path(target, overwrite=True) as temporary:
        temporary.write_text(render_report(out), encoding="utf-8")
    return target
