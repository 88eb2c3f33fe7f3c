"""The paper's findings, each judged from our numbers (never asserted by hand).

Every ``judge_*`` function takes the numbers a target wrote (``figure2``,
``figure3``, ``threshold``) and returns a :class:`Verdict`: our number in words
and ``yes`` / ``partly`` / ``no`` by a rule stated in its docstring.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

__all__ = [
    "FINDINGS",
    "JUDGES",
    "PAPER_THRESHOLD",
    "THRESHOLD_SLACK",
    "Judge",
    "Verdict",
    "judge_energy_decrease",
    "judge_energy_order",
    "judge_long_run",
    "judge_period_growth",
    "judge_threshold",
]

PAPER_THRESHOLD = 0.1  # "for f < 0.1 the Celt effect does not exist" (section 4)
THRESHOLD_SLACK = 0.05  # |f_c - 0.1| within this counts as "about 0.1"
BUDGET_TOLERANCE = 1e-8  # energy-budget residual relative to E(0) accepted as closed
# differences of the final energy (relative to E(0)) or of the peak reversed spin
# (relative to |spin(0)|) below this are the integrator's, not the physics': runs that
# all end at rest differ by round-off (1e-17 J), which must not order them
ORDER_RESOLUTION = 1e-9

FINDINGS = {
    "period": "If the friction coefficient f decreases (0.35, 0.25, 0.15), the period of "
    "the Celt effect increases (Fig. 2).",
    "energy_order": "If f decreases, the energy of motion (the angular velocity) also "
    "decreases (Fig. 2).",
    "energy_decrease": "With sliding the energy falls (dry friction dissipates).",
    "threshold": "For f < 0.1 the Celt effect does not exist.",
    "long_run": "Over a long run the spin changes sign more than twice; after the second "
    "change the sliding stone (f = 0.35) changes the sign of its spin more quickly than "
    "the rolling one (Fig. 3).",
}


@dataclass(frozen=True)
class Verdict:
    """Our number for a finding, and whether it reproduces the paper's statement."""

    ours: str
    reproduced: str  # "yes", "partly" or "no"
    why: str = ""


def _strictly_increasing(values: Sequence[float], resolution: float = 0.0) -> bool:
    """Whether each value exceeds the one before by more than ``resolution``."""
    return all(b - a > resolution for a, b in itertools.pairwise(values))


def _static_cases(fig2: dict[str, Any], load: str = "static") -> list[dict[str, Any]]:
    """Sliding cases with friction load ``load``, in the order of decreasing f."""
    cases = [c for c in fig2["cases"] if c["model"] == "sliding" and c["friction_load"] == load]
    return sorted(cases, key=lambda c: -c["friction_coefficient"])


def _at_end(case: dict[str, Any], name: str) -> float:
    """A case's value at t_end (``energy_final``, ``spin_final``): NaN where the run
    stopped early (None in its numbers), which no ordering judges as falling."""
    value = case[name]
    return float("nan") if value is None else float(value)


def _time(value: float | None) -> str:
    return "none" if value is None else f"{value:.3g} s"


def judge_period_growth(fig2: dict[str, Any], load: str = "static") -> Verdict:
    """yes: every f reverses and the first reversal comes later as f falls; partly:
    the reversing ones do (at least two), the rest do not reverse; no otherwise."""
    cases = _static_cases(fig2, load)
    rolling = next(c for c in fig2["cases"] if c["model"] == "rolling")
    times = [c["first_reversal_time"] for c in cases]
    ours = ", ".join(
        f"f = {c['friction_coefficient']:g}: {_time(c['first_reversal_time'])}" for c in cases
    )
    ours += f"; rolling: {_time(rolling['first_reversal_time'])}"
    reversing = [t for t in times if t is not None]
    prefix_reverses = times[: len(reversing)] == reversing  # the non-reversing are the lowest f
    if reversing and len(reversing) == len(times) and _strictly_increasing(reversing):
        return Verdict(ours, "yes")
    if len(reversing) >= 2 and prefix_reverses and _strictly_increasing(reversing):
        return Verdict(ours, "partly", "the reversal time grows as f falls until it vanishes")
    if len(reversing) >= 2 and _strictly_increasing(reversing):
        return Verdict(ours, "partly", "where it reverses, later for smaller f")
    return Verdict(ours, "no", "the first reversal does not come later as f falls")


def judge_energy_order(fig2: dict[str, Any], load: str = "static") -> Verdict:
    """yes: the energy at the end and the peak reversed spin both fall with f (by more
    than ``ORDER_RESOLUTION`` of E(0) and of |spin(0)| from one f to the next);
    partly: one of them does; no: neither."""
    cases = _static_cases(fig2, load)
    energies = [_at_end(c, "energy_final") - c["energy_rest"] for c in cases]
    spins = [c["peak_reversed_spin"] for c in cases]
    ours = "; ".join(
        f"f = {c['friction_coefficient']:g}: E − m g l = {e:.3g} J, peak reversed spin "
        f"{s:.3g} rad/s"
        for c, e, s in zip(cases, energies, spins, strict=True)
    )
    energy_scale = max(abs(c["energy_initial"]) for c in cases)
    spin_scale = max(abs(c["spin_initial"]) for c in cases)
    energy_falls = _strictly_increasing(energies[::-1], ORDER_RESOLUTION * energy_scale)
    spin_falls = _strictly_increasing(spins[::-1], ORDER_RESOLUTION * spin_scale)
    if energy_falls and spin_falls:
        return Verdict(ours, "yes")
    if energy_falls or spin_falls:
        which = "energy" if energy_falls else "reversed spin"
        return Verdict(ours, "partly", f"only the {which} falls with f")
    return Verdict(ours, "no", "neither the energy nor the reversed spin falls with f")


def judge_energy_decrease(results: Sequence[dict[str, Any]]) -> Verdict:
    """yes: in every sliding run the sampled energy never rises (beyond 1e-9 E(0))
    and the energy lost equals the friction work within 1e-8 E(0)."""
    cases = [c for r in results for c in r["cases"] if c["model"] == "sliding"]
    if not cases:
        return Verdict("no sliding run", "no")
    worst = max(c["max_energy_balance_error"] / abs(c["energy_initial"]) for c in cases)
    monotone = all(c["energy_monotone"] for c in cases)
    lost = ", ".join(
        f"f = {c['friction_coefficient']:g} ({c['friction_load']}): "
        f"{c['energy_initial'] - _at_end(c, 'energy_final'):.3g} J"
        for c in cases
    )
    ours = (
        f"energy lost {lost}; monotone in all {len(cases)} runs: {monotone}; "
        f"max |E(0) − E − W| / E(0) = {worst:.2g}"
    )
    ok = monotone and worst <= BUDGET_TOLERANCE
    return Verdict(ours, "yes" if ok else "no")


def judge_threshold(result: dict[str, Any]) -> Verdict:
    """yes: no reversal below a bisected f_c with |f_c − 0.1| <= 0.05; partly: a
    lowest reversing f_c exists but elsewhere; no: it reverses down to the grid's start
    or nowhere."""
    grid = result["grid"]
    parts = []
    for boundary in result["boundaries"]:
        low, high = boundary["bracket"]
        parts.append(f"reversal {boundary['kind']} between f = {low:.4g} and {high:.4g}")
    ours = "; ".join(parts) if parts else "no change on the grid"
    if not result["reverses_anywhere"]:
        return Verdict(
            ours + f" (no reversal for f in [{grid[0]:g}, {grid[-1]:g}])",
            "no",
            "no f of the grid reverses",
        )
    if result["grid_reverses"][0]:
        return Verdict(ours, "no", f"it still reverses at the grid's lowest f = {grid[0]:g}")
    f_c = result["lowest_reversing_f"]
    upper = [b["bracket"][0] for b in result["boundaries"] if b["kind"] == "disappears"]
    if abs(f_c - PAPER_THRESHOLD) <= THRESHOLD_SLACK:
        note = (
            f"it also stops reversing above f ≈ {min(upper):.3g}, where the pivoting moment "
            "stops the spin first"
            if upper
            else ""
        )
        return Verdict(ours + f"; lowest reversing f = {f_c:.4g}", "yes", note)
    return Verdict(
        ours + f"; lowest reversing f = {f_c:.4g}",
        "partly",
        f"a threshold exists, at f = {f_c:.3g} instead of about {PAPER_THRESHOLD:g}",
    )


def _intervals(times: Sequence[float]) -> list[float]:
    return [b - a for a, b in itertools.pairwise(times)]


def judge_long_run(fig3: dict[str, Any]) -> Verdict:
    """yes: both runs reverse at least three times and, after the second reversal, the
    sliding one's reversals come at shorter intervals; partly: the sliding spin keeps
    changing sign after rolling's second reversal, more often than rolling's, but without
    leaving the hysteresis band (no held reversal); no otherwise."""
    rolling, sliding = fig3["cases"]
    r_times, s_times = rolling["reversal_times"], sliding["reversal_times"]
    ours = (
        f"rolling: {len(r_times)} reversals ({', '.join(f'{t:.3g}' for t in r_times)} s); "
        f"sliding f = {fig3['friction']:g}: {len(s_times)} reversals"
        + (f" ({', '.join(f'{t:.3g}' for t in s_times)} s)" if s_times else "")
        + f", {sliding['spin_crossing_count']} raw sign changes, final spin "
        f"{_at_end(sliding, 'spin_final'):.2g} rad/s (band {fig3['band']:.2g} rad/s)"
    )
    if len(r_times) < 3:
        return Verdict(ours, "no", "the rolling run has fewer than three reversals: run longer")
    if len(s_times) >= 3:
        faster = max(_intervals(s_times[1:])) < min(_intervals(r_times[1:]))
        return Verdict(
            ours,
            "yes" if faster else "no",
            "" if faster else "sliding reversals are not more frequent",
        )
    if s_times and sliding["spin_crossing_count"] > rolling["spin_crossing_count"]:
        return Verdict(
            ours,
            "partly",
            "the sliding spin dies out and dithers about zero: many sign changes, "
            "but none is a held reversal",
        )
    return Verdict(ours, "no", "the sliding spin stops changing sign")


Judge = Callable[[dict[str, Any]], Verdict | None]


def _judge_energy_decrease_of(fig2: dict[str, Any]) -> Verdict:
    """:func:`judge_energy_decrease` of one Figure 2 result (its sliding runs)."""
    return judge_energy_decrease([fig2])


JUDGES: dict[str, tuple[str, Judge]] = {
    "period": ("fig2", judge_period_growth),
    "energy_order": ("fig2", judge_energy_order),
    "energy_decrease": ("fig2", _judge_energy_decrease_of),
    "threshold": ("threshold", judge_threshold),
    "long_run": ("fig3", judge_long_run),
}
"""Each finding of :data:`FINDINGS`: the target whose numbers judge it, and its judge (the
report's summary and the atlas read this one table)."""
