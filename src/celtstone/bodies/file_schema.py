"""What a body file may hold: every table, key, form and unit, declared once.

The loader (``bodies.load_body``), its error messages and the documentation read
these tables; nothing else lists the keys. A body file has

* top-level text ``title`` and ``notes`` (optional),
* ``[source]``: the citation, keys from :data:`SOURCE_KEYS`, each a string or a whole
  number (``year = 1982``); or one string ``source = "..."``,
* ``[body]``: :data:`BODY_ENTRIES` (mass, inertia tensor, gravity),
* ``[shape]``: ``kind`` and the entries of that kind in :data:`SHAPES`,
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

from celtstone import schema
from celtstone.bodies.polynomial import ImplicitPolynomial
from celtstone.bodies.shapes import (
    MAX_SUPERELLIPSOID_EXPONENT,
    Ellipsoid,
    Paraboloid,
    Superellipsoid,
)
from celtstone.errors import BodyFileError, did_you_mean

__all__ = [
    "BODY_ENTRIES",
    "SHAPES",
    "SOURCE_KEYS",
    "TOP_LEVEL",
    "BodyFileError",
    "Entry",
    "ShapeFile",
]

NUMBER = "number"  # a TOML integer or float (not a boolean, not a string)
INTEGER = "integer"  # a TOML integer


@dataclass(frozen=True)
class Entry:
    """One key of ``[body]`` or ``[shape]``: its form, its quantity and whether it is required.

    Parameters
    ----------
    key : the key as written in the file, and the keyword of the object it builds
    quantity : its unit, symbol, meaning and range (the ``schema.PARAMETERS`` entry)
    shape : () a number; (3,) three numbers; (3, 3) three rows of three; None in
        place of a length: any number of rows (the object bounds them)
    columns : forms of the entries of each row (``terms``: a number and three integers);
        empty: every entry is a number
    layout : how a row of a list of any length is written, for messages (``"[c, i, j, k]"``)
    required : whether the key must be given (else the object's default applies)
    """

    key: str
    quantity: schema.Quantity
    shape: tuple[int | None, ...] = ()
    columns: tuple[str, ...] = ()
    layout: str = ""
    required: bool = True

    def form(self) -> str:
        """The expected form in words, e.g. ``"3 numbers a, b, c [m]"``."""
        quantity = self.quantity
        unit = f" [{quantity.unit}]" if quantity.unit else ""
        if not self.shape:
            return f"{quantity.allowed}{unit}"
        if len(self.shape) == 1:
            return f"{self.shape[0]} numbers {quantity.symbol}{unit}"
        rows, width = self.shape
        if rows is None:
            return f"a list of rows {self.layout}{unit}"
        return f"a {rows}x{width} array of numbers {quantity.symbol}{unit}"

    def describe(self) -> str:
        """``key``: meaning, unit and form, for messages and documentation."""
        return f"{self.key} ({self.quantity.description}): {self.form()}"


@dataclass(frozen=True)
class ShapeFile:
    """A ``[shape]`` kind: the class it builds, the keys it takes (the class's keywords)
    and the surface in words (for documentation and ``celtstone bodies``)."""

    kind: str
    build: Callable[..., Any]
    entries: tuple[Entry, ...]
    surface: str


_Q = schema.PARAMETERS
# shape quantities that schema does not list: their ranges are checked by the shape class
_EXPONENT = schema.Quantity(
    "exponent",
    "p",
    "1",
    "superellipsoid exponent",
    lower=2.0,
    upper=MAX_SUPERELLIPSOID_EXPONENT,
)
_TERMS = schema.Quantity("terms", "c, i, j, k", "", "implicit polynomial terms, c in m^-(i+j+k)")
SEMI_AXES = Entry("semi_axes", _Q["semi_axes"], (3,))
COM_OFFSET = Entry("com_offset", _Q["com_offset"])

BODY_ENTRIES: tuple[Entry, ...] = (
    Entry("mass", _Q["mass"]),
    Entry("inertia", _Q["inertia"], (3, 3)),
    Entry("gravity", _Q["gravity"], required=False),  # default: Body's 9.81 m/s^2
)

SHAPES: dict[str, ShapeFile] = {
    s.kind: s
    for s in (
        ShapeFile(
            Ellipsoid.kind,
            Ellipsoid,
            (SEMI_AXES, COM_OFFSET),
            "x^2/a^2 + y^2/b^2 + z^2/c^2 = 1, G h below the centre",
        ),
        ShapeFile(
            Paraboloid.kind,
            Paraboloid,
            (
                Entry("radii_of_curvature", _Q["radii_of_curvature"], (2,)),
                Entry("com_height", _Q["com_height"]),
            ),
            "z = x^2/(2 rho1) + y^2/(2 rho2), G l above the rest contact",
        ),
        ShapeFile(
            Superellipsoid.kind,
            Superellipsoid,
            (SEMI_AXES, COM_OFFSET, Entry("exponent", _EXPONENT)),
            "|x/a|^p + |y/b|^p + |z/c|^p = 1, G h below the centre",
        ),
        ShapeFile(
            ImplicitPolynomial.kind,
            ImplicitPolynomial,
            (
                Entry(
                    "terms",
                    _TERMS,
                    (None, 4),
                    (NUMBER, INTEGER, INTEGER, INTEGER),
                    "[c, i, j, k]: coefficient c and whole exponents i, j, k",
                ),
                COM_OFFSET,
            ),
            "sum of c x^i y^j z^k = 1 about O, G = (0, 0, -h)",
        ),
    )
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
    "derivation": "numbers the body was derived from (not read by the loader)",
}
TABLES = frozenset({"source", "body", "shape", "derivation"})


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
