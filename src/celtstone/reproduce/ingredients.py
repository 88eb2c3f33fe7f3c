"""What each ingredient of the realistic contact does alone: the one-at-a-time runs.

The realistic contact (``study.REALISTIC_CONTACT``) changes several things against the
paper's idealisation at once. Part of a paper-contact study's Figure 2 target, these
runs change one of them at a time, on the paper's disk, at each f of
``Study.ingredient_frictions``, and the report tabulates their first reversal times
beside the paper's contact and the realistic one (:func:`ingredients_section`): which
ingredient alone removes or moves the reversal is read from the runs, not asserted.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from celtstone.bodies import Body
from celtstone.reproduce.cases import run_cases
from celtstone.reproduce.progress import Progress
from celtstone.reproduce.study import REALISTIC_CONTACT, Study
from celtstone.simulation.models import Model

__all__ = [
    "INGREDIENTS",
    "Ingredient",
    "ingredient_models",
    "ingredients_section",
    "run_ingredients",
]


@dataclass(frozen=True)
class Ingredient:
    """One row of the one-at-a-time table.

    Parameters
    ----------
    name : str
        Its name in file names and the numbers.
    label : str
        Its row label in the report.
    settings : tuple of str
        The :class:`Study` settings it takes from ``REALISTIC_CONTACT`` (none: the
        paper's contact; all: the realistic contact).
    """

    name: str
    label: str
    settings: tuple[str, ...]

    def study(self, study: Study) -> Study:
        """The paper-contact ``study`` with this ingredient's settings."""
        changes: dict[str, Any] = {k: REALISTIC_CONTACT[k] for k in self.settings}
        return dataclasses.replace(study, **changes)


INGREDIENTS: tuple[Ingredient, ...] = (
    Ingredient("paper", "paper's contact (disk ε = 1 mm, Padé law, N = m g)", ()),
    Ingredient("exact_law", "+ exact Coulomb–Contensou law", ("friction_law",)),
    Ingredient(
        "ellipse",
        "+ Hertz ellipse (E = 3 GPa, ν = 0.35)",
        ("contact_shape", "elastic_modulus", "poisson_ratio"),
    ),
    Ingredient("rolling_resistance", "+ rolling resistance λ = 1e-5 m", ("rolling_resistance",)),
    Ingredient("consistent_load", "+ consistent load (the true N)", ("friction_load",)),
    Ingredient("stick_slip", "+ stick–slip contact", ("contact",)),
    Ingredient("realistic", "realistic contact (all of the above)", tuple(REALISTIC_CONTACT)),
)
"""The rows: the paper's contact, each ingredient alone, and all together."""


def ingredient_models(study: Study) -> list[tuple[Ingredient, Model]]:
    """The runs of ``study``'s one-at-a-time table: each ingredient at each f of
    ``ingredient_frictions``; none for a study that is not on the paper's contact."""
    if not study.is_paper_contact:
        return []
    return [
        (ingredient, ingredient.study(study).sliding(friction))
        for ingredient in INGREDIENTS
        for friction in study.ingredient_frictions
    ]


def run_ingredients(
    study: Study, body: Body, out: Path, progress: Progress
) -> dict[str, Any] | None:
    """Run the one-at-a-time table for ``study`` over ``fig2_t_end``; write each run to
    ``out/data/ingredients_KEY_NAME_CASE.nc``.

    Returns
    -------
    dict or None
        ``frictions`` and ``rows`` (each ingredient's ``name``, ``label`` and cases, in
        the order of the frictions); None for a study not on the paper's contact.
    """
    runs = ingredient_models(study)
    if not runs:
        return None
    rows = []
    for ingredient in INGREDIENTS:
        models = [model for owner, model in runs if owner is ingredient]
        stem = f"ingredients_{study.key}_{ingredient.name}"
        ingredient_study = ingredient.study(study)
        _, cases = run_cases(ingredient_study, body, models, study.fig2_t_end, out, stem, progress)
        rows.append({"name": ingredient.name, "label": ingredient.label, "cases": cases})
    return {"frictions": list(study.ingredient_frictions), "rows": rows}


def _time_cell(case: dict[str, Any]) -> str:
    first = case["first_reversal_time"]
    text = "none" if first is None else f"{first:.4g}"
    return text if case["status"] == "success" else f"{text} ({case['status']})"


def ingredients_section(fig2: dict[str, dict[str, Any]], number: int) -> list[str]:
    """The report's one-at-a-time section, numbered ``number`` (a line saying it was not
    run, without Figure 2 numbers of a paper-contact study)."""
    lines = [
        f"## {number}. What each ingredient of the realistic contact does",
        "",
        "Each row adds one ingredient of the realistic contact to the paper's idealisation "
        "(Figure 2's body, start and run length), sliding with the friction load of its "
        "row; the last row has all of them. First reversal time [s], or none within the "
        "run:",
        "",
    ]
    tables = {key: r["ingredients"] for key, r in fig2.items() if r.get("ingredients")}
    if not tables:
        return [*lines, "Not run yet (run `celtstone reproduce fig2`).", ""]
    for key, table in tables.items():
        frictions = table["frictions"]
        t_end = fig2[key]["t_end"]
        lines += [
            f"**{key}**, runs of {t_end:g} s:",
            "",
            "| contact | " + " | ".join(f"f = {f:g}" for f in frictions) + " |",
            "|---|" + "---|" * len(frictions),
        ]
        for row in table["rows"]:
            lines.append(f"| {row['label']} | " + " | ".join(map(_time_cell, row["cases"])) + " |")
        lines += ["", _removed(table), ""]
    return lines


def _removed(table: dict[str, Any]) -> str:
    """In words: which single ingredient removes the paper contact's reversal, at which f."""
    paper = next(row for row in table["rows"] if row["name"] == "paper")
    reversing = [c["first_reversal_time"] is not None for c in paper["cases"]]
    removed = []
    for row in table["rows"]:
        if row["name"] in ("paper", "realistic"):
            continue
        lost = [
            f"{f:g}"
            for f, before, case in zip(table["frictions"], reversing, row["cases"], strict=True)
            if before and case["first_reversal_time"] is None
        ]
        if lost:
            removed.append(f"{row['label'].removeprefix('+ ')} (f = {', '.join(lost)})")
    if not any(reversing):
        return "The paper's contact does not reverse at these f."
    if not removed:
        return "No single ingredient removes the paper contact's reversal at these f."
    return "Alone, these remove the paper contact's reversal: " + "; ".join(removed) + "."
