"""Body files: the shipped catalogue (``list_bodies``), reading a TOML file into a
validated :class:`Body` (``load_body``, ``body_from_dict``) or a :class:`Design`
(``load_design``), and shape tables (``shape_from_table``)."""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from importlib import resources
from pathlib import Path
from typing import Any

from celtstone.bodies.body import Body
from celtstone.bodies.design import AddedMass, Design
from celtstone.bodies.file_schema import (
    BODY_ENTRIES,
    DESIGN_ENTRIES,
    SOURCE_KEYS,
    TABLES,
    TOP_LEVEL,
    BodyFileError,
    Entry,
    ShapeFile,
    check_derivation,
    check_form,
    check_keys,
    check_required,
    check_text,
    check_types,
    closest,
    type_problem,
)
from celtstone.bodies.file_schema import (
    SHAPES as SHAPE_FILES,
)
from celtstone.bodies.shapes import (
    Shape,
)
from celtstone.errors import ParameterError, require_choice

_DATA = resources.files("celtstone.bodies") / "data"


def list_bodies() -> dict[str, str]:
    """List the shipped parameter sets (``celtstone bodies``).

    Returns
    -------
    dict of str to str
        Name -> one-line citation of the source.
    """
    found = {}
    for entry in sorted(_DATA.iterdir(), key=lambda e: e.name):
        if entry.name.endswith(".toml"):
            name = entry.name.removesuffix(".toml")
            found[name] = load_body(name).source
    return found


def _citation(source: dict[str, Any]) -> str:
    parts = [str(source.get("authors", "")), f"({source.get('year', '')})"]
    parts.append(f'"{source.get("title", "")}"')
    journal = source.get("journal")
    if journal:
        parts.append(
            f"{journal} {source.get('volume', '')}({source.get('issue', '')}), "
            f"{source.get('pages', '')}"
        )
    return " ".join(p for p in parts if p.strip())


def _table(file: str, data: Mapping[str, Any], key: str) -> dict[str, Any]:
    """The table ``[key]`` of the file, which must be there."""
    if key not in data:
        raise BodyFileError(
            file,
            key,
            None,
            f"a [{key}] table",
            problem=f"no [{key}] table (a body file has [body] and [shape] tables, or [design])",
        )
    table = data[key]
    if not isinstance(table, dict):
        raise BodyFileError(file, key, table, f"a [{key}] table")
    return table


def _top_label(key: str) -> str:
    return f"[{key}]" if key in TABLES else key


def _citation_entries(file: str, source: object) -> dict[str, str]:
    """The ``[source]`` table as strings (a plain ``source = "..."`` has none)."""
    if isinstance(source, str):
        return {}
    if not isinstance(source, dict):
        raise BodyFileError(file, "source", source, "a [source] table or a string")
    check_keys(file, source, list(SOURCE_KEYS), "[source]")
    for key, value in source.items():
        check_text(file, f"source.{key}", value, integers=True)
    return {key: str(value) for key, value in source.items()}


def _shape_file(file: str, table: Mapping[str, Any]) -> ShapeFile:
    """The declared shape kind of a ``[shape]`` table."""
    kinds = ", ".join(SHAPE_FILES)
    if "kind" not in table:
        raise BodyFileError(
            file,
            "shape.kind",
            None,
            f"one of: {kinds}",
            problem=f"[shape] has no kind (expected kind = one of: {kinds})",
        )
    kind = table["kind"]
    if not isinstance(kind, str) or kind not in SHAPE_FILES:
        hint = closest(kind, list(SHAPE_FILES)) if isinstance(kind, str) else "a string in quotes"
        raise BodyFileError(file, "shape.kind", kind, f"one of: {kinds}", hint)
    return SHAPE_FILES[kind]


def _home_of(key: str) -> str:
    """Where a key foreign to the table it is in belongs, for messages."""
    if key in {entry.key for entry in BODY_ENTRIES}:
        return f"{key} is a key of [body]"
    kinds = [kind for kind, shape in SHAPE_FILES.items() if key in {e.key for e in shape.entries}]
    if kinds:
        return f"{key} is a [shape] key of kind = {' or '.join(map(repr, kinds))}"
    return ""


def _frozen(value: object) -> object:
    """Arrays as (nested) tuples, as the frozen shape objects hold them."""
    return tuple(_frozen(item) for item in value) if isinstance(value, list) else value


def _read_entries(
    file: str,
    table: Mapping[str, Any],
    entries: tuple[Entry, ...],
    where: str,
    *,
    also: tuple[str, ...] = (),
) -> dict[str, object]:
    """The entries of ``table``: no unknown key (``also`` names keys read elsewhere),
    the required ones present, arrays of the declared lengths and nesting."""
    known = [*also, *(entry.key for entry in entries)]
    check_keys(file, table, known, where, elsewhere=_home_of)
    check_required(file, table, entries, where)
    values = {}
    for entry in entries:
        if entry.key in table:
            check_form(file, entry, table[entry.key])
            values[entry.key] = table[entry.key]
    return values


def _in_file(file: str, error: ParameterError, raw: Mapping[str, object]) -> BodyFileError:
    """``error`` of a shape or body check, naming the file (and a non-number's TOML type)."""
    problem = type_problem(raw[error.name]) if error.name in raw else ""
    hint = "; ".join(h for h in (error.hint, problem) if h)
    return BodyFileError(file, error.name, error.value, error.allowed, hint)


def _shape_values(file: str, table: Mapping[str, Any]) -> tuple[ShapeFile, dict[str, object]]:
    """The kind of a ``[shape]`` table and its entries' values, their forms checked."""
    shape_file = _shape_file(file, table)
    values = _read_entries(
        file, table, shape_file.entries, f"[shape] with kind = {shape_file.kind!r}", also=("kind",)
    )
    return shape_file, values


def shape_from_table(table: Mapping[str, Any], *, file: str = "the shape table") -> Shape:
    """Build the shape a ``[shape]`` table declares; the inverse of ``shape.table()``.

    Parameters
    ----------
    table : Mapping
        The table: ``kind`` and that kind's entries, validated as in a body file.
    file : str, optional
        Where the table comes from, named in errors.

    Returns
    -------
    Shape
        The validated shape.

    Raises
    ------
    BodyFileError
        (a ``ParameterError``) naming ``file`` and the key.
    """
    if not isinstance(table, Mapping):
        raise BodyFileError(file, "shape", table, "a [shape] table")
    shape_file, values = _shape_values(file, table)
    try:
        shape: Shape = shape_file.build(**{k: _frozen(v) for k, v in values.items()})
    except ParameterError as error:
        raise _in_file(file, error, values) from None
    for entry in shape_file.entries:
        if entry.key in values:
            check_types(file, entry, values[entry.key])
    return shape


def _design_from_table(file: str, data: Mapping[str, Any]) -> Design:
    """The :class:`Design` of a file's ``[design]`` table, which replaces [body] and [shape]."""
    for key in ("body", "shape"):
        if key in data:
            raise BodyFileError(
                file,
                key,
                data[key],
                "no [body] or [shape] table beside [design]",
                problem=f"[{key}] beside [design]: a body file gives either [design] or "
                "[body] and [shape] (the design computes both)",
            )
    table = _table(file, data, "design")
    values = _read_entries(file, table, DESIGN_ENTRIES, "[design]")
    for entry in DESIGN_ENTRIES:
        if entry.key in values:
            check_types(file, entry, values[entry.key])
    added = tuple(
        AddedMass(float(row[0]), (float(row[1]), float(row[2]), float(row[3])))
        for row in values.pop("added_masses", [])  # type: ignore[attr-defined]
    )
    try:
        return Design(**values, added_masses=added)  # type: ignore[arg-type]
    except ParameterError as error:
        raise _in_file(file, error, values) from None


def body_from_dict(name: str, data: Mapping[str, Any], *, file: str | None = None) -> Body:
    """Build a validated :class:`Body` from the parsed TOML structure.

    Every key is checked against ``bodies.file_schema`` first (unknown keys, missing
    keys, array lengths); then the shape and the body check their values, which know
    the ranges in context (``com_offset`` inside the body); last, a value those checks
    took but that is not a TOML number (``true``, ``"1.0"``) is refused.

    Parameters
    ----------
    name : str
        The parameter set's name (``kane_levinson_1982``).
    data : Mapping
        The parsed TOML structure of a body file.
    file : str, optional
        Where it comes from, named in errors; default ``name``.

    Returns
    -------
    Body
        The validated body.

    Raises
    ------
    BodyFileError
        (a ``ParameterError``) naming ``file`` (default ``name``) and the key.
    """
    where = file or name
    check_keys(where, data, list(TOP_LEVEL), "the top level", label=_top_label)
    for key in ("title", "notes"):
        if key in data:
            check_text(where, key, data[key])
    source = data.get("source", {})
    citation = _citation_entries(where, source)
    if "derivation" in data:
        check_derivation(where, data["derivation"])
    provenance = {
        "source": _citation(citation) if citation else str(source) if source else "",
        "notes": str(data.get("notes", "")),
        "citation": citation,
    }
    if "design" in data:
        design = _design_from_table(where, data)
        try:
            return design.body(name, **provenance)
        except ParameterError as error:
            raise _in_file(where, error, {}) from None
    body_table, shape_table = _table(where, data, "body"), _table(where, data, "shape")
    body_values = _read_entries(where, body_table, BODY_ENTRIES, "[body]")
    shape_file, shape_values = _shape_values(where, shape_table)
    raw = {**body_values, **shape_values}
    try:
        shape = shape_file.build(**{k: _frozen(v) for k, v in shape_values.items()})
        body = Body(name=name, shape=shape, **provenance, **body_values)  # type: ignore[arg-type]
    except ParameterError as error:
        raise _in_file(where, error, raw) from None
    for entry in (*BODY_ENTRIES, *shape_file.entries):
        if entry.key in raw:
            check_types(where, entry, raw[entry.key])
    return body


def _decode(file: str, raw: bytes) -> dict[str, Any]:
    """Parse TOML bytes: UTF-8, with or without a byte-order mark."""
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        byte = raw[error.start]
        raise BodyFileError(
            file,
            "body",
            file,
            "a UTF-8 text file",
            problem=f"not UTF-8 text (byte 0x{byte:02x} at offset {error.start}); "
            "a body file is TOML, saved as UTF-8",
        ) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise BodyFileError(
            file, "body", file, "a valid TOML file", problem=f"not valid TOML: {error}"
        ) from None


def _read(name_or_path: str | Path) -> tuple[str, str, dict[str, Any]]:
    """The name, the file (for messages) and the parsed TOML of a body."""
    text = str(name_or_path)
    path = Path(text)
    if text.endswith(".toml") or path.is_file():
        if not path.is_file():
            raise ParameterError("body", text, "a shipped body name or an existing .toml file")
        try:
            raw = path.read_bytes()
        except OSError as error:
            raise BodyFileError(
                text, "body", text, "a readable file", problem=f"cannot read it: {error}"
            ) from None
        name, file = path.stem, text
    else:
        entry = _DATA / f"{text}.toml"
        if not entry.is_file():
            names = [
                e.name.removesuffix(".toml") for e in _DATA.iterdir() if e.name.endswith(".toml")
            ]
            require_choice("body", text, sorted(names))
        raw = entry.read_bytes()
        name, file = text, f"{text}.toml (shipped)"
    return name, file, _decode(file, raw)


def load_body(name_or_path: str | Path) -> Body:
    """Load a shipped parameter set by name, or a TOML file by path.

    The file's keys, forms and units are those of ``bodies.file_schema``; a UTF-8
    byte-order mark is allowed.

    Parameters
    ----------
    name_or_path : str or pathlib.Path
        A name of :func:`list_bodies`, or a path ending in ``.toml``.

    Returns
    -------
    Body
        The body, its ``source`` and ``citation`` read from the file.

    Raises
    ------
    ParameterError
        For an unknown name (with the closest match) or a malformed file
        (:class:`~celtstone.bodies.file_schema.BodyFileError`, naming the file and key).
    """
    name, file, data = _read(name_or_path)
    return body_from_dict(name, data, file=file)


def load_design(name_or_path: str | Path) -> Design | None:
    """Load the ``[design]`` of a body file: what the body was computed from.

    Parameters
    ----------
    name_or_path : str or pathlib.Path
        As for :func:`load_body`.

    Returns
    -------
    Design or None
        The validated design, or None for a file given by ``[body]`` and ``[shape]``.

    Raises
    ------
    ParameterError
        As :func:`load_body`.
    """
    name, file, data = _read(name_or_path)
    body_from_dict(name, data, file=file)  # the whole file checked, as for a run
    return _design_from_table(file, data) if "design" in data else None
