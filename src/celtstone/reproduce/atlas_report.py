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

__all__ = ["PARAMETER_WORDS", "VERDICTS", "atlas_counts", "atlas_section"]

VERDICTS = ("yes", "partly", "no")
TITLE = "## 7. For which stones does the paper hold?"
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


def atlas_section(result: Mapping[str, Any] | None) -> list[str]:
    """The section's Markdown lines (a line saying it was not run, without ``result``)."""
    lines = [TITLE, ""]
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
    lines += [
        "",
        f"Data: `{result['store']}` (every design's numbers), "
        + ", ".join(f"`{p['table']}`" for p in result["slices"])
        + "; SVG beside each PNG. Each verdict is the judge's of sections 1–5 "
        "(`celtstone.reproduce.findings`) on that design's runs.",
        "",
    ]
    return lines
