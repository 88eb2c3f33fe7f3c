"""Bodies: validated parameter sets, loaded from TOML data files.

``list_bodies()`` names the shipped sets; ``load_body(name_or_path)`` reads one.
"""

from __future__ import annotations

import difflib
import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from celtstone.bodies.body import Body
from celtstone.bodies.shapes import (
    Ellipsoid,
    ImplicitFunction,
    ImplicitPolynomial,
    ImplicitSurface,
    Paraboloid,
    Shape,
    Superellipsoid,
)
from celtstone.errors import ParameterError

__all__ = [
    "Body",
    "Ellipsoid",
    "ImplicitFunction",
    "ImplicitPolynomial",
    "ImplicitSurface",
    "Paraboloid",
    "Shape",
    "Superellipsoid",
    "body_from_dict",
    "list_bodies",
    "load_body",
]

_DATA = resources.files("celtstone.bodies") / "data"


def list_bodies() -> dict[str, str]:
    """Shipped parameter sets: name -> one-line citation of the source."""
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


def body_from_dict(name: str, data: dict[str, Any]) -> Body:
    """Build a validated :class:`Body` from the parsed TOML structure."""
    try:
        body = data["body"]
        shape_data = dict(data["shape"])
    except KeyError as missing:
        raise ParameterError(
            "body file", name, f"a [body] and a [shape] table ({missing})"
        ) from None
    kind = shape_data.pop("kind", None)
    shape: Shape
    try:
        if kind == "ellipsoid":
            shape = Ellipsoid(tuple(shape_data["semi_axes"]), shape_data["com_offset"])
        elif kind == "paraboloid":
            shape = Paraboloid(tuple(shape_data["radii_of_curvature"]), shape_data["com_height"])
        elif kind == "superellipsoid":
            shape = Superellipsoid(
                tuple(shape_data["semi_axes"]), shape_data["com_offset"], shape_data["exponent"]
            )
        elif kind == "implicit_polynomial":
            shape = ImplicitPolynomial(
                tuple(tuple(term) for term in shape_data["terms"]), shape_data["com_offset"]
            )
        else:
            raise ParameterError(
                "shape.kind",
                kind,
                "one of: ellipsoid, paraboloid, superellipsoid, implicit_polynomial",
            )
        source = data.get("source", {})
        return Body(
            name=name,
            mass=body["mass"],
            inertia=body["inertia"],
            shape=shape,
            gravity=body.get("gravity", 9.81),
            source=_citation(source) if isinstance(source, dict) else str(source),
            notes=str(data.get("notes", "")),
            citation={k: str(v) for k, v in source.items()} if isinstance(source, dict) else {},
        )
    except KeyError as missing:
        raise ParameterError("body file", name, f"the entry {missing}") from None
    except TypeError as error:
        raise ParameterError(
            "body file", name, f"numbers of the documented form ({error})"
        ) from None


def load_body(name_or_path: str | Path) -> Body:
    """Load a shipped parameter set by name, or a TOML file by path.

    Raises
    ------
    ParameterError
        for an unknown name (with the closest match) or a malformed file.
    """
    text = str(name_or_path)
    path = Path(text)
    if text.endswith(".toml") or path.is_file():
        if not path.is_file():
            raise ParameterError("body", text, "a shipped body name or an existing .toml file")
        raw = path.read_bytes()
        name = path.stem
    else:
        entry = _DATA / f"{text}.toml"
        if not entry.is_file():
            names = [
                e.name.removesuffix(".toml") for e in _DATA.iterdir() if e.name.endswith(".toml")
            ]
            close = difflib.get_close_matches(text, names, n=1)
            hint = f"did you mean {close[0]!r}?" if close else ""
            raise ParameterError("body", text, "one of: " + ", ".join(sorted(names)), hint)
        raw = entry.read_bytes()
        name = text
    try:
        data = tomllib.loads(raw.decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as error:
        raise ParameterError("body", text, f"a valid TOML file ({error})") from None
    return body_from_dict(name, data)
