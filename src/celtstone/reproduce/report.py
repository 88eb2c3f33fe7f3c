"""``report.md``: one table per finding of the paper, built from the targets' numbers."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

from celtstone._about import version
from celtstone.bodies import load_body
from celtstone.files.export import atomic_path
from celtstone.reproduce.atlas_report import atlas_section
from celtstone.reproduce.directory import REPORT, ReproductionDirectory
from celtstone.reproduce.findings import (
    FINDINGS,
    JUDGES,
    PAPER_THRESHOLD,
    Judge,
    Verdict,
    judge_energy_decrease,
    judge_energy_order,
    judge_long_run,
    judge_period_growth,
    judge_threshold,
)
from celtstone.reproduce.ingredients import ingredients_section
from celtstone.reproduce.results import read_result
from celtstone.simulation.reversals import REVERSAL_TIME_RESOLUTION

__all__ = ["collect", "render_report", "write_report"]


def collect(out: Path) -> dict[str, dict[str, dict[str, Any]]]:
    """The numbers written by earlier targets in ``out/data``: target -> study key ->
    result. The key is the body's name for the paper's contact, ``BODY+VARIANT`` for a
    variant (``Study.key``); numbers written before variants have no ``key`` and are
    keyed by their body, and a case written before the rename of ``normal_force`` reads
    as ``friction_load``."""
    results: dict[str, dict[str, dict[str, Any]]] = {}
    for path in sorted((out / "data").glob("*.json")):
        result = read_result(path)  # a user's own JSON file there: left out, with a warning
        if result is None:
            continue
        for case in result.get("cases", []):
            if "normal_force" in case and "friction_load" not in case:
                case["friction_load"] = case.pop("normal_force")
        result.setdefault("key", result["body"])
        results.setdefault(result["target"], {})[result["key"]] = result
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
    variants: tuple[tuple[str, Judge], ...] = (),
) -> list[str]:
    lines = [f"## {title}", ""]
    if not results:
        return [*lines, "Not run yet (`celtstone reproduce` with this target).", ""]
    rows = []
    for result in results.values():
        where = f"{result['study']}; {result['target']} runs of {result['t_end']:g} s"
        rows.append((where, "", judge(result)))
        for label, variant in variants:
            verdict = variant(result)
            if verdict is not None:
                rows.append((where, f" ({label})", verdict))
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
            load = result.get("contact", {}).get("friction_load", "static")
            words = "N = m g" if load == "static" else "the dynamic N"
            lines.append(
                f"Video: [`{result['animation']}`]({result['animation']}), rolling beside "
                f"sliding at f = {friction:g} ({words}), real time."
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
(`celtstone.reversal_times`). The band is applied to the spin's running mean
over one rocking period, read from the runs' samples (200 per second): a reversal's
time is known to the samples' resolution, within {resolution:g} s of a converged run's
for Kane & Levinson's stone (`celtstone.simulation.reversals.REVERSAL_TIME_RESOLUTION`); the
table's four significant digits are within it.
"""

BRAKING_FRICTION = 0.35
_UNKNOWN_RUN = "unknown (made before runs were recorded)"


def _provenance(results: list[dict[str, Any]]) -> tuple[list[str], list[str]]:
    """A warning when the results come from several runs (or versions), and the table
    of when, by which version and in which run each target was made."""
    table = [
        "## Where each result comes from",
        "",
        "| target | study | finished (UTC) | celtstone | run (targets asked for) |",
        "|---|---|---|---|---|",
    ]
    runs: set[str] = set()
    versions: set[str] = set()
    for result in sorted(results, key=lambda r: (r["target"], r["key"])):
        run = result.get("run")
        if not isinstance(run, dict):
            runs.add(_UNKNOWN_RUN)
            table.append(
                f"| {result['target']} | {result['key']} | unknown | unknown | {_UNKNOWN_RUN} |"
            )
            continue
        runs.add(str(run["id"]))
        versions.add(str(run["celtstone_version"]))
        table.append(
            f"| {result['target']} | {result['key']} | {run['finished_utc']} | "
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
    """Pivot braking time C|ω0|/M0 at f = 0.35 against the rolling reversal time, for
    the paper's contact (the disk's M0; a variant's contact has its own)."""
    lines = [
        "| body | M0 at f = 0.35 [N m] | C ω0 (magnitude) [N m s] | braking time [s] "
        "| rolling reversal [s] |",
        "|---|---|---|---|---|",
    ]
    for name, result in fig2.items():
        if "variant" in result:
            continue
        body = load_body(result["body"])
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


_LABELS = {
    "period": "period grows as f falls",
    "energy_order": "energy falls with f",
    "energy_decrease": "energy falls in sliding",
    "threshold": f"no reversal below f ≈ {PAPER_THRESHOLD:g}",
    "long_run": "long run: sliding changes sign faster",
}
_SUMMARY: tuple[tuple[str, str, Judge], ...] = tuple(
    (label, *JUDGES[key]) for key, label in _LABELS.items()
)
"""One row of the summary table per finding: its label, the target judged, the judge."""


def _with_load(judge: Callable[[dict[str, Any], str], Verdict], load: str) -> Judge:
    """``judge`` on the Figure 2 runs with friction load ``load``; ``None`` (not run)
    where the study ran no such runs (a variant's Figure 2 may run one load only)."""

    def judged(result: dict[str, Any]) -> Verdict | None:
        if not any(c.get("friction_load") == load for c in result["cases"]):
            return None
        return judge(result, load)

    return judged


_DYNAMIC: tuple[tuple[str, str, Judge], ...] = (
    ("period grows as f falls (dynamic N)", "fig2", _with_load(judge_period_growth, "dynamic")),
    ("energy falls with f (dynamic N)", "fig2", _with_load(judge_energy_order, "dynamic")),
)
"""The Figure 2 findings judged on the dynamic-load runs too (the comparison's table)."""


def _cell(verdict: Verdict | None, short: bool = False) -> str:
    """A verdict in a table's cell (``short``: the word alone); "not run" for none."""
    if verdict is None:
        return "not run"
    if short:
        return verdict.reproduced
    why = f" ({verdict.why})" if verdict.why else ""
    return f"**{verdict.reproduced}**{why}: {verdict.ours}"


_VARIANT_WHY = """The realistic contact changes five things against the paper's idealisation (each
study's settings are in its rows above and in each table's header): the disk of fixed
radius ε becomes the Hertz ellipse at the current contact point of a polymer stone on a
polymer plate (E = 3 GPa, ν = 0.35, chosen so that Kane & Levinson's *circular* Hertz
radius is 1.09 mm, the paper's ε: the contact changes its shape, not its size), Zhuravlev's
Padé law becomes the exact Coulomb–Contensou law, a rolling-friction length λ (Coulomb's
law of rolling friction) resists the rocking, and the contact sticks when the friction
it needs lies inside the Coulomb–Contensou limit set (the stick–slip contact) instead of
creeping under a regularised law. The fifth, the friction law loaded with the true normal
force N (the consistent load) instead of the paper's m g, is run in Figure 2 and in the
one-at-a-time table; the threshold and Figure 3 runs keep the paper's m g, because with
the consistent load and the stick–slip contact some of the threshold's runs take tens of
minutes each. What each does alone is measured in the one-at-a-time table
("What each ingredient of the realistic contact does"); in words:

* **the ellipse pivots harder.** A rattleback's contact ellipse is long and thin (Kane &
  Levinson at rest: 3.14 mm × 0.28 mm); its pivoting moment at zero slip,
  (3/8) E(e) f N A, is 1.86 times the disk's of the same E, ν (docs/decisions.md §24, §29).
  The spin about the vertical is braked harder, so a stone whose rocking instability
  grows slowly against that braking (the heavy Kane & Levinson body: see the braking
  times of the disk under "Why our numbers differ from the paper's") can lose its spin
  before it reverses; a light stone with a small contact (the toy's is 0.14 mm) is
  braked far less;
* **the exact law slides harder than Padé's** near the crossover of slip and pivoting
  (at u = 1 the disk's |F| is 0.88 f N exact, 0.54 f N Padé; decisions §29): on the
  paper's own disk it alone can remove a reversal, as the one-at-a-time table shows;
* **rolling resistance takes energy from the rocking**, at the rate λ N |ω_t|, and none
  from the spin about the vertical (ω_t = 0 there, decisions §25). With λ = 1e-5 m a
  rocking Kane & Levinson stone alone would stop in about 93 s (1e-4 m: 9 s).
  λ = 1e-5 m is an order-of-magnitude estimate for a hard polymer pair (Cross 2016 gives
  1e-6 m to 1e-3 m from hard to soft floors), not a measurement. Where a stone comes to
  rest within a run at every f (E − m g l of round-off size), its final energies cannot
  order f, and "energy falls with f" is judged on the reversed spin alone;
* **the consistent load** keeps the friction within Coulomb's bound: with N = m g the
  friction force of a rocking stone exceeds f N of the true normal force (each case's
  `max_friction_bound_ratio`);
* **the stone sticks.** Once the spin has died, the stick–slip contact holds the
  contact point still and the stone rocks, rolling, until rolling resistance and the
  friction of each short slip have taken its energy; the regularised contact would
  creep instead, and at rest it is so stiff that one Kane & Levinson run of 20 s did
  not end within 150 s (decisions §30).

Every verdict is the same judge's (`celtstone.reproduce.findings`) on the numbers of the
runs with that contact; a finding that holds for the paper's idealisation and not here
rests on the idealisation.
"""

_VARIANT_EXPLANATIONS = {"realistic": _VARIANT_WHY}
"""The explanation of a variant's differences, by variant name (none for the others)."""


def _variant_rows(
    results: dict[str, dict[str, dict[str, Any]]], variant: str
) -> tuple[list[str], list[str]]:
    """The variant's table of verdicts beside the paper's, and the bodies compared."""
    ran = {  # (body, target) -> the variant's result
        (r["body"], target): r
        for target, by_key in results.items()
        for r in by_key.values()
        if r.get("variant") == variant
    }
    bodies = sorted({body for body, _ in ran})
    rows = []
    changes = []
    compared = set()
    for label, target, judge in (*_SUMMARY, *_DYNAMIC):
        for body in bodies:
            paper = results.get(target, {}).get(body)
            ours = ran.get((body, target))
            before = judge(paper) if paper is not None else None
            after = judge(ours) if ours is not None else None
            rows.append(f"| {label} | {body} | {_cell(before)} | {_cell(after)} |")
            if before is not None and after is not None:
                compared.add(body)
                if before.reproduced != after.reproduced:
                    changes.append(f"{label}, {body}: {before.reproduced} → {after.reproduced}")
    verdict = (
        "Verdicts that change with the contact: "
        + ("; ".join(changes) if changes else "none")
        + f" (compared for {', '.join(sorted(compared))})."
        if compared
        else "Not compared: no body of this contact was also run with the paper's "
        "idealisation, so no verdict can change; the table gives this contact's own."
    )
    return rows, [verdict]


def _comparison(results: dict[str, dict[str, dict[str, Any]]], number: int = 7) -> list[str]:
    """Per contact variant, one section numbered from ``number``: each finding for each
    body, the paper's contact beside it where that was run too."""
    variants = sorted(
        {r["variant"] for by_key in results.values() for r in by_key.values() if "variant" in r}
    )
    lines = []
    for offset, variant in enumerate(variants):
        rows, verdict = _variant_rows(results, variant)
        lines += [
            f"## {number + offset}. The paper's idealisation beside the {variant} contact",
            "",
            "| finding | body | paper's idealisation (disk ε = 1 mm, Padé law, no rolling "
            f"resistance) | {variant} contact |",
            "|---|---|---|---|",
            *rows,
            "",
            *verdict,
            "",
        ]
        if variant in _VARIANT_EXPLANATIONS:
            lines += [_VARIANT_EXPLANATIONS[variant], ""]
    return lines


def _variant_count(results: dict[str, dict[str, dict[str, Any]]]) -> int:
    return len({r["variant"] for t in results.values() for r in t.values() if "variant" in r})


def render_report(out: Path) -> str:
    """Render the report's Markdown from the numbers in ``out/data``.

    Parameters
    ----------
    out : pathlib.Path
        The reproduction's directory; the numbers are read from its ``data``.

    Returns
    -------
    str
        The report.
    """
    results = collect(out)
    fig2 = results.get("fig2", {})
    fig3 = results.get("fig3", {})
    threshold = results.get("threshold", {})
    keys = sorted({*fig2, *fig3, *threshold})
    lines = [
        "# celtstone reproduction of *On the influence of sliding on the Celt rattleback motion*",
        "",
        f"Generated by celtstone {version()} (`celtstone reproduce`); every number below is read "
        "from the data files beside this report. Model: rolling (paper eq. 3–5) and rolling "
        "with sliding (eq. 6–12) with Zhuravlev's Padé friction law, ε = 1 mm, N = m g unless "
        "said otherwise; integrator tolerances in each file's header. A column `BODY+VARIANT` "
        "is the same body with another contact (its settings in its rows below; the sections "
        "after the one-at-a-time table set it beside the paper's). To cite: the paper, "
        "*On the influence of sliding on the Celt rattleback motion*, for the models, and "
        "celtstone as its `CITATION.cff` says.",
        "",
        "| finding | " + " | ".join(keys) + " |",
        "|---|" + "---|" * len(keys),
    ]
    everything = [r for target in results.values() for r in target.values()]
    warning, provenance = _provenance(everything)
    lines[3:3] = warning
    if any(r["study"].startswith("REDUCED") for r in everything):
        lines[3:3] = [
            "**Some results below come from the shortened `--quick` form: a smoke test, not "
            "the reproduction. Run `celtstone reproduce all` for the real one.**",
            "",
        ]
    for label, target, judge in _SUMMARY:
        source = results.get(target, {})
        cells = [_cell(judge(source[k]) if k in source else None, short=True) for k in keys]
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
        (("dynamic normal force", _with_load(judge_period_growth, "dynamic")),),
    )
    lines += _section(
        "2. The energy against f (Figure 2)",
        "energy_order",
        fig2,
        judge_energy_order,
        lambda r: [],
        (("dynamic normal force", _with_load(judge_energy_order, "dynamic")),),
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
    lines += ingredients_section(fig2, 6)
    number = 7
    lines += _comparison(results, number)
    number += _variant_count(results)
    lines += atlas_section(results.get("atlas", {}).get("atlas"), number)
    braking = _braking_table(fig2) if fig2 else "(run fig2 for the table)"
    lines.append(_WHY.format(braking=braking, resolution=REVERSAL_TIME_RESOLUTION))
    return "\n".join(lines)


def write_report(out: Path, directory: ReproductionDirectory | None = None) -> Path:
    """Write ``out/report.md`` whole or not at all, and list it in ``out``'s manifest.

    It replaces a previous report only if a reproduction wrote it and it is unchanged
    since (``reproduce.directory``); a user's ``report.md`` is refused.

    Parameters
    ----------
    out : pathlib.Path
        The reproduction's directory, where ``report.md`` is written.
    directory : ReproductionDirectory, optional
        ``out`` as a reproduction holds it (locked); by default it is opened here.

    Returns
    -------
    pathlib.Path
        The report's path.

    Raises
    ------
    ParameterError
        Naming ``out`` and the report, if it is not celtstone's to replace.
    """
    if directory is None:
        with ReproductionDirectory(Path(out), overwrite=False) as opened:
            return write_report(out, opened)
    directory.check_replaceable(REPORT, None)
    target = Path(out) / REPORT
    with atomic_path(target, overwrite=True) as temporary:
        temporary.write_text(render_report(Path(out)), encoding="utf-8")
    directory.record_report()
    return target
