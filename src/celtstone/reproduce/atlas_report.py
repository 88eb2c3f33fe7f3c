"""Section 7 of ``report.md``, "For which stones does the paper hold?", from the atlas's
numbers (``data/atlas_atlas.json``, written by ``celtstone.atlas.target.AtlasTarget``).

Every count is computed here from the verdicts of each design in that file, so the
section states nothing the data do not hold.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from celtstone.reproduce.findings import FINDINGS

__all__ = ["PARAMETER_WORDS", "VERDICTS", "atlas_counts", "atlas_section", "search_lines"]

VERDICTS = ("yes", "partly", "no")
TITLE = "For which stones does the paper hold?"
PARAMETER_WORDS = {
    # a design parameter (a StoneDesign field) in the report and the maps
    "length": "L [m]",
    "width_ratio": "b/a",
    "height_ratio": "c/a",
    "misalignment": "δ [deg]",
    "mass_fraction": "κ",
    "density": "ρ [kg/m³]",
}


def atlas_counts(designs: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """From each design's ``verdicts`` (finding -> "yes" / "partly" / "no"): the number of
    designs, per finding the designs with each verdict, the designs where all five are
    "yes", and per pair of findings (``"A+B"``) the designs where both are "yes"."""
    findings = list(FINDINGS)

    def holds(design: Mapping[str, Any], finding: str) -> bool:
        return bool(design["verdicts"][finding] == "yes")

    return {
        "designs": len(designs),
        "verdicts": {
            f: {v: sum(d["verdicts"][f] == v for d in designs) for v in VERDICTS} for f in findings
        },
        "all_five": sum(all(holds(d, f) for f in findings) for d in designs),
        "pairs": {
            f"{a}+{b}": sum(holds(d, a) and holds(d, b) for d in designs)
            for a, b in itertools.combinations(findings, 2)
        },
    }


def _design_words(parameters: Mapping[str, float], varied: Sequence[str]) -> str:
    return ", ".join(f"{PARAMETER_WORDS[k]} = {parameters[k]:g}" for k in varied)


def _varied(slices: Sequence[Mapping[str, Any]]) -> list[str]:
    """The parameters some slice varies, in the order of ``StoneDesign``'s fields."""
    names = {name for piece in slices for name in (piece["x"], piece["y"])}
    return [name for name in PARAMETER_WORDS if name in names]


def atlas_section(result: Mapping[str, Any] | None, number: int = 7) -> list[str]:
    """The section's Markdown lines, numbered ``number`` (a line saying it was not run,
    without ``result``)."""
    lines = [f"## {number}. {TITLE}", ""]
    if result is None:
        return [*lines, "Not run yet (`celtstone reproduce atlas`).", ""]
    designs = result["designs"]
    counts = atlas_counts(designs)
    findings = list(FINDINGS)
    total = counts["designs"]
    lines += [
        f"Atlas grid **{result['grid']}** (`--atlas-grid {result['grid']}`): {total} designs, "
        "each a PMMA half-ellipsoid with two point masses (docs/bodies.md, docs/decisions.md "
        f"§32), runs: {result['study']}. Slices:",
        "",
    ]
    for piece in result["slices"]:
        lines.append(
            f"* `{piece['name']}`: {piece['words']} ({len(piece['designs'])} designs; "
            f"`{piece['table']}`)"
        )
    lines += [
        "",
        f'**All five findings hold ("yes") for {counts["all_five"]} of {total} designs.**',
        "",
        "| finding | yes | partly | no |",
        "|---|---|---|---|",
    ]
    for finding in findings:
        row = counts["verdicts"][finding]
        lines.append(f"| {finding} | {row['yes']} | {row['partly']} | {row['no']} |")
    lines += [
        "",
        'Designs where both findings of a pair hold ("yes"), of '
        f"{total}; the diagonal: where the finding holds.",
        "",
        "| | " + " | ".join(findings) + " |",
        "|---|" + "---|" * len(findings),
    ]
    for a in findings:
        cells = []
        for b in findings:
            if a == b:
                cells.append(f"*{counts['verdicts'][a]['yes']}*")
            else:
                key = f"{a}+{b}" if findings.index(a) < findings.index(b) else f"{b}+{a}"
                cells.append(str(counts["pairs"][key]))
        lines.append(f"| {a} | " + " | ".join(cells) + " |")
    lines.append("")
    if counts["all_five"] == 0:
        never = [f for f in findings if counts["verdicts"][f]["yes"] == 0]
        exclusive = [
            (a, b)
            for a, b in itertools.combinations(findings, 2)
            if counts["pairs"][f"{a}+{b}"] == 0 and a not in never and b not in never
        ]
        lines += ["No design of this grid satisfies all five findings. Evidence:", ""]
        if never:
            lines.append(
                '* never "yes" on any design: ' + ", ".join(f"**{f}**" for f in never) + ";"
            )
        lines.append(
            "* pairs that each hold somewhere but never together: "
            + (", ".join(f"**{a}** and **{b}**" for a, b in exclusive) if exclusive else "none")
            + "."
        )
        most = max(sum(v == "yes" for v in d["verdicts"].values()) for d in designs)
        best = [d for d in designs if sum(v == "yes" for v in d["verdicts"].values()) == most]
        varied = _varied(result["slices"])
        lines += [
            "",
            f"The most findings that hold together: {most} of {len(findings)}, for "
            + "; ".join(
                _design_words(d["parameters"], varied)
                + " (not: "
                + ", ".join(f for f in findings if d["verdicts"][f] != "yes")
                + ")"
                for d in best
            )
            + ".",
        ]
    else:
        varied = _varied(result["slices"])
        holding = [d for d in designs if all(v == "yes" for v in d["verdicts"].values())]
        lines.append(
            "All five hold for: "
            + "; ".join(_design_words(d["parameters"], varied) for d in holding)
            + "."
        )
    lines.append("")
    for piece in result["slices"]:
        images = [f for f in piece["figures"] if f.endswith(".png")]
        lines += [f"![{Path(f).stem}]({f})" for f in images]
    for search in result.get("searches", []):
        lines += search_lines(search)
    lines += [
        "",
        f"Data: `{result['store']}` (every design's numbers), "
        + ", ".join(f"`{p['table']}`" for p in result["slices"])
        + "; SVG beside each PNG. Each verdict is the judge's of sections 1–5 "
        "(`celtstone.reproduce.findings`) on that design's runs.",
        "",
    ]
    return lines


CONTACT_WORDS = {
    # a contact of the search (celtstone.atlas.search.SEARCH_CONTACTS) in the report
    "eps_1mm": "ε = 1 mm",
    "hertz_pmma_glass": "Hertz, PMMA on glass",
    "hertz_pmma_pmma": "Hertz, PMMA on PMMA",
}
_SHORT_WORDS = {"length": "L", "width_ratio": "b/a", "height_ratio": "c/a", "misalignment": "δ"}


def _axis_words(name: str, axis: Sequence[Any]) -> str:
    low, high, scale = axis
    words = f"{PARAMETER_WORDS[name]} {low:g} … {high:g}"
    return words + (" (log-uniform)" if scale == "log" else "")


def _interval(value: float | None) -> str:
    return "–" if value is None else f"{value:.3g}"


def _short_design(parameters: Mapping[str, float]) -> str:
    words = [f"{_SHORT_WORDS[k]} = {parameters[k]:.3g}" for k in _SHORT_WORDS]
    return ", ".join([*words, f"κ = {parameters['mass_fraction']:.3g}"])


def search_lines(search: Mapping[str, Any]) -> list[str]:
    """The subsection on the search for the long-run finding, from its stored summary
    (``celtstone.atlas.search.search_summary``, written by ``benchmarks/atlas_search.py``):
    its coverage and cost, the verdicts per contact, the closest points and, where they
    were run, all five findings of the best ones."""
    total, verdicts, cost = search["points"], search["verdicts"], search["cost"]
    axes = "; ".join(_axis_words(k, v) for k, v in search["axes"].items())
    lines = [
        "",
        f"### The search for the long-run finding: the {search['box']} box",
        "",
        f"The long run is the finding no grid met, and the cheapest (two 50 s runs a design), "
        f"so it was searched alone over **{total} designs** (`benchmarks/atlas_search.py "
        f"--box {search['box']}`, a Latin hypercube with seed {search['seed']}, run "
        f"{cost['date']}: {cost['wall_s']:g} s "
        f"wall, {cost['cpu_s']:g} s CPU on {cost['workers']} threads, load average "
        f"{cost['load_average_start']:g} at the start, {cost['load_average_1min']:g} at the end; "
        f"{search['software']}). Axes: {axes}; c/a below the rest-stability bound, δ at most "
        "the largest the masses make; the contact a sixth axis, a third of the designs each. "
        "Each long run is judged by the judge of section 5.",
        "",
        f'**The long run holds ("yes") for {verdicts["yes"]} of {total} designs** '
        f"(partly {verdicts['partly']}, no {verdicts['no']}). At least three held reversals: "
        f"rolling {search['rolling_three']}, sliding {search['sliding_three']}, both "
        f"{search['both_three']}. The sliding run has more held reversals than the rolling "
        f"one in {search['sliding_more']} designs, and its mean interval after the second "
        f"reversal is the shorter in {search['sliding_quicker_on_average']} (of the "
        f"{search['both_three']} where both have three). The rolling run's shortest interval "
        "after the second reversal over the sliding run's longest (the judge asks for above 1) "
        f"is at most {_interval(search['largest_interval_ratio'])}; the ratio of their mean "
        f"intervals at most {_interval(search['largest_mean_ratio'])}. Most held sliding "
        "reversals in 50 s: "
        + ", ".join(
            f"{CONTACT_WORDS.get(name, name)} {count}"
            for name, count in search["most_sliding"].items()
        )
        + ".",
        "",
        "| contact | designs | yes | partly | no |",
        "|---|---|---|---|---|",
    ]
    for name, row in search["contacts"].items():
        lines.append(
            f"| {CONTACT_WORDS.get(name, name)} | {row['points']} | {row['yes']} | "
            f"{row['partly']} | {row['no']} |"
        )
    lines += [
        "",
        "The closest designs: the first by verdict (then by the shortest rolling interval "
        "over the longest sliding one after the second reversal, then by the sliding "
        "reversals), and the closest of those with three reversals in both runs (by that "
        "ratio: above 1 every sliding interval is the shorter, as the judge reads the "
        "paper's Figure 3):",
        "",
        "| design | contact | reversals rolling / sliding | shortest rolling interval [s] "
        "| longest sliding interval [s] | mean intervals rolling / sliding [s] | long run |",
        "|---|---|---|---|---|---|---|",
    ]
    for point in search["best"]:
        counts = point["reversals"]
        lines.append(
            f"| {_short_design(point['parameters'])} | "
            f"{CONTACT_WORDS.get(point['contact'], point['contact'])} | "
            f"{counts['rolling']} / {counts['sliding']} | "
            f"{_interval(point['rolling_shortest_interval'])} | "
            f"{_interval(point['sliding_longest_interval'])} | "
            f"{_interval(point['mean_interval']['rolling'])} / "
            f"{_interval(point['mean_interval']['sliding'])} | {point['long_run']} |"
        )
    full = search.get("full", [])
    if full:
        findings = list(FINDINGS)
        holding = sum(all(d["verdicts"][f] == "yes" for f in findings) for d in full)
        lines += [
            "",
            f"All five findings of the {len(full)} closest (`compute_atlas`, the atlas's "
            f"study in each one's contact): all five hold for **{holding}**.",
            "",
            "| design | contact | " + " | ".join(findings) + " |",
            "|---|---|" + "---|" * len(findings),
        ]
        for design in full:
            lines.append(
                f"| {_short_design(design['parameters'])} | "
                f"{CONTACT_WORDS.get(design['contact'], design['contact'])} | "
                + " | ".join(design["verdicts"][f] for f in findings)
                + " |"
            )
    return lines
