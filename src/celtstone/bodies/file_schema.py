"""What a body file may hold: every table, key, form and unit, declared once.

The loader (``bodies.load_body``), its error messages and the documentation read
these tables; nothing else lists the keys. A body file has

* top-level text ``title`` and ``notes`` (optional),
* ``[source]``: the citation, keys from :data:`SOURCE_KEYS`, each a string or a whole
  number (``year = 1982``); or one string ``source = "..."``,
* ``[body]``: :data:`BODY_ENTRIES` (mass, inertia tensor, gravity),
* ``[shape]``: ``kind`` and the entries of that kind in :data:`SHAPES`,
* or, in place of ``[body]`` and ``[shape]``, ``[design]``: :data:`DESIGN_ENTRIES`, a
  stone given by its outer dimensions, mass or density, misalignment and added masses
  (``bodies.design``), its mass, centre of mass and inertia computed,
* ``[derivation]`` (optional, free keys): the numbers the body was derived from, for the
  reader and the tests (``docs/bodies.md``); the loader does not use them, so their keys
  are free, but each value must be a number, a string or an array of them.

Units are those of ``schema.PARAMETERS`` (SI). Unknown keys, a boolean or a string where
a number belongs, and arrays of the wrong length or nesting are refused, naming the
file and the key (:class:`BodyFileError`, a ``ParameterError``).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any

from celtstone.bodies.declaration import INTEGER, Entry
from celtstone.bodies.design import DESIGN_QUANTITIES
from celtstone.bodies.shapes import SHAPES as SHAPE_CLASSES
from celtstone.bodies.shapes import STORED_SHAPES
from celtstone.errors import BodyFileError, did_you_mean
from celtstone.simulation import schema

__all__ = [
    "BODY_ENTRIES",
    "DESIGN_ENTRIES",
    "SHAPES",
    "SOURCE_KEYS",
    "TOP_LEVEL",
    "BodyFileError",
    "Entry",
    "ShapeFile",
]


@dataclass(frozen=True)
class ShapeFile:
    """A ``[shape]`` kind: the class it builds, the keys it takes (the class's keywords)
    and the surface in words (for documentation and ``celtstone bodies``)."""

    kind: str
    build: Callable[..., Any]
    entries: tuple[Entry, ...]
    surface: str


_Q = schema.PARAMETERS

BODY_ENTRIES: tuple[Entry, ...] = (
    Entry("mass", _Q["mass"]),
    Entry("inertia", _Q["inertia"], (3, 3)),
    Entry("gravity", _Q["gravity"], required=False),  # default: Body's 9.81 m/s^2
)

_D = DESIGN_QUANTITIES
DESIGN_ENTRIES: tuple[Entry, ...] = (
    Entry("length", _D["length"]),
    Entry("width", _D["width"]),
    Entry("height", _D["height"]),
    Entry("misalignment", _D["misalignment"]),
    Entry("mass", _Q["mass"], required=False),  # mass or density
    Entry("density", _D["density"], required=False),
    Entry("added_masses", _D["added_masses"], (None, 4), layout="[μ, x, y, z]", required=False),
    Entry("gravity", _Q["gravity"], required=False),
)
"""The keys of ``[design]`` (``bodies.design.Design``'s keywords): a half-ellipsoid of
length × width × height [m], the misalignment δ [deg], the total mass [kg] or the
density [kg/m³], optional added point masses (rows [μ, x, y, z] in kg and m about the
middle of the flat top) and gravity."""

# the shapes a body file may declare: every stored shape of the registry
SHAPES: dict[str, ShapeFile] = {
    kind: ShapeFile(kind, cls, cls.entries, cls.surface)
    for kind, cls in SHAPE_CLASSES.items()
    if kind in STORED_SHAPES
}

# Bibliographic keys of [source] (BibTeX's names, plus where in the source the numbers are)
SOURCE_KEYS: tuple[str, ...] = (
    "authors",
    "title",
    "journal",
    "booktitle",
    "publisher",
    "institution",
    "volume",
    "issue",
    "pages",
    "year",
    "doi",
    "url",
    "isbn",
    "edition",
    "chapter",
    "section",
    "page",
    "table",
    "figure",
    "equation",
    "note",
)

# top-level key -> meaning; the tables are written [name]
TOP_LEVEL: dict[str, str] = {
    "title": "one line naming the body",
    "notes": "conversions made from the source",
    "source": "the citation: a [source] table or one string",
    "body": "mass, inertia tensor and gravity",
    "shape": "the surface: kind and its entries",
    "design": "a stone by its dimensions, mass, misalignment and added masses, in place "
    "of [body] and [shape]",
    "derivation": "numbers the body was derived from (not read by the loader)",
}
TABLES = frozenset({"source", "body", "shape", "design", "derivation"})


def key_text(key: str) -> str:
    """``key`` as it reads in a message: bare, or quoted when TOML needed quotes."""
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else repr(key)


def closest(key: str, known: list[str]) -> str:
    """``"did you mean 'x'?"`` for the closest of ``known``, or ``""``."""
    return did_you_mean(key, known)


def check_keys(
    file: str,
    table: Mapping[str, Any],
    known: list[str],
    where: str,
    *,
    label: Callable[[str], str] = key_text,
    elsewhere: Callable[[str], str] = lambda key: "",
) -> None:
    """Refuse any key of ``table`` not in ``known``, naming the closest known key.

    ``label`` spells a key in the message (``[shape]`` for a table); ``elsewhere`` says
    where an unknown key does belong (another shape kind), or ``""``.
    """
    for key, value in table.items():
        if key in known:
            continue
        shown = f"[{key_text(key)}]" if isinstance(value, dict) else key_text(key)
        labels = [label(k) for k in known]
        listed = ", ".join(sorted(labels))
        advice = "; ".join(h for h in (closest(shown, labels), elsewhere(key)) if h)
        raise BodyFileError(
            file,
            key,
            value,
            f"one of: {listed}",
            advice,
            problem=(
                f"{shown} is not a known key of {where} "
                f"(expected one of: {listed}" + (f"; {advice}" if advice else "") + ")"
            ),
        )


def check_required(
    file: str, table: Mapping[str, Any], entries: tuple[Entry, ...], where: str
) -> None:
    """Refuse a table that lacks a required entry."""
    for entry in entries:
        if entry.required and entry.key not in table:
            raise BodyFileError(
                file,
                entry.key,
                None,
                entry.form(),
                problem=f"{where} has no {entry.key} (expected {entry.describe()})",
            )


def _is_number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _leaves(value: object) -> Iterator[object]:
    if isinstance(value, list):
        for item in value:
            yield from _leaves(item)
    else:
        yield value


def _wrong_form(file: str, entry: Entry, value: object, why: str) -> BodyFileError:
    return BodyFileError(file, entry.key, value, entry.form(), why)


def check_form(file: str, entry: Entry, value: object) -> None:
    """Refuse ``value`` unless it has the array shape of ``entry`` (lengths and nesting)
    and every integer in it fits a float."""
    if not entry.shape:
        if isinstance(value, list | dict):
            raise _wrong_form(file, entry, value, "one number, not an array or a table")
    elif not isinstance(value, list):
        raise _wrong_form(file, entry, value, "an array in [...], not one value")
    else:
        rows, width = entry.shape[0], entry.shape[-1]
        if rows is not None and len(value) != rows:
            raise _wrong_form(file, entry, value, f"it has {len(value)} entries, not {rows}")
        for row in value:
            if len(entry.shape) == 1:
                if isinstance(row, list | dict):
                    raise _wrong_form(file, entry, value, "it is nested: one [...] of numbers")
            elif not isinstance(row, list) or len(row) != width:
                raise _wrong_form(
                    file, entry, value, f"each row is an array of {width}, not {row!r}"
                )
            elif any(isinstance(item, list | dict) for item in row):
                raise _wrong_form(file, entry, value, f"the row {row!r} is nested")
    for leaf in _leaves(value):
        if isinstance(leaf, int) and not isinstance(leaf, bool):
            try:
                float(leaf)
            except OverflowError:
                raise _wrong_form(file, entry, value, "an integer beyond the float range") from None


def _type_problem(leaf: object) -> str:
    """Why ``leaf`` is not a number, or ``""``."""
    if isinstance(leaf, bool):
        return f"a TOML boolean ({str(leaf).lower()}) is not a number"
    if isinstance(leaf, str):
        return f"a TOML string ({leaf!r}) is not a number: write numbers without quotes"
    if not _is_number(leaf):
        return f"a TOML {type(leaf).__name__} is not a number"
    return ""


def type_problem(value: object) -> str:
    """Why ``value`` (a number or an array of them) holds something that is not a number."""
    for leaf in _leaves(value):
        problem = _type_problem(leaf)
        if problem:
            return problem
    return ""


def check_types(file: str, entry: Entry, value: object) -> None:
    """Refuse a boolean, string or date where ``entry`` takes numbers, and a non-integer
    in an integer column."""
    problem = type_problem(value)
    if problem:
        raise _wrong_form(file, entry, value, problem)
    if entry.columns and isinstance(value, list):
        for row in value:
            for item, form in zip(row, entry.columns, strict=True):
                if form == INTEGER and not isinstance(item, int):
                    raise _wrong_form(
                        file, entry, value, f"{item!r} in {row!r} must be a whole number such as 2"
                    )


def check_text(file: str, key: str, value: object, *, integers: bool = False) -> None:
    """Refuse a text entry that is not a string (or, with ``integers``, a whole number)."""
    if isinstance(value, str):
        return
    if integers and isinstance(value, int) and not isinstance(value, bool):
        return
    allowed = "a string" + (" or a whole number" if integers else "")
    raise BodyFileError(file, key, value, allowed)


def check_derivation(file: str, table: object) -> None:
    """``[derivation]``: free keys, each a number, a string or an array of them."""
    if not isinstance(table, dict):
        raise BodyFileError(file, "derivation", table, "a [derivation] table")
    for key, value in table.items():
        for leaf in _leaves(value):
            if isinstance(leaf, bool) or not isinstance(leaf, int | float | str):
                raise BodyFileError(
                    file, f"derivation.{key}", value, "a number, a string or an array of them"
                )
