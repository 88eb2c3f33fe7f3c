"""What a shape declares once, and what is made of it everywhere else.

A shape class (``bodies.shapes``) is a frozen dataclass that says, as class attributes:

* ``kind``: its name in body files, run attributes and messages;
* ``code``: its ``kernels.layout.ShapeCode`` (the kernels' branch);
* ``surface``: its equation in words (documentation, ``celtstone bodies``);
* ``entries``: the keys of its ``[shape]`` table in a body file, with units
  (:class:`Entry`); they are also the keywords of the class, so a table is a shape;
* ``sweep_names``: the numbers a sweep may vary (:class:`SweepName`);
* ``closed``: whether the surface is bounded (drawn through the contact kernel) or
  an open cap (drawn by ``visual.scene``'s own mesh);
* ``stored``: whether the shape is data (rebuilt from its table in a run's file and
  sent to sweep workers) or lives in this process only (a compiled Python function);

and implements ``kernel_parameters`` (four numbers a run records), ``rest_height``,
``radii_of_curvature`` and ``example`` (a Kane & Levinson-sized instance,
symmetric about the plane y = 0, that the registry's tests run). The kernel record's
fields it fills (``kernel_fields``) are its entries, by key, unless it says otherwise.

From these, :class:`DeclaredShape` makes the provenance (``table``, ``attributes``) and
the swept copies (``replaced``); the body-file loader, the sweep's parameter list,
the viewer and the tests read the registry ``bodies.shapes.SHAPES``.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any, ClassVar, Self

from celtstone.errors import ParameterError
from celtstone.kernels.layout import ShapeCode
from celtstone.simulation import schema

__all__ = [
    "INTEGER",
    "KL_COM_OFFSET",
    "KL_SEMI_AXES",
    "NUMBER",
    "DeclaredShape",
    "Entry",
    "SweepName",
]

NUMBER = "number"  # a TOML integer or float (not a boolean, not a string)
INTEGER = "integer"  # a TOML integer

# the Kane & Levinson ellipsoid (references.md) that every shape's ``example()`` builds:
# semi-axes a, b, c [m] and G below the centre h [m]
KL_SEMI_AXES = (0.20, 0.03, 0.02)
KL_COM_OFFSET = 0.01


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
class SweepName:
    """A number of a shape that a sweep may vary: the field it sets (and the index in
    it, for one number of an array field), in the unit of that field's entry."""

    name: str
    field: str
    description: str
    index: int | None = None


def _plain(value: object) -> object:
    """Tuples as lists, NumPy scalars as Python numbers: JSON and TOML values."""
    if isinstance(value, tuple | list):
        return [_plain(item) for item in value]
    if hasattr(value, "item"):
        return value.item()
    return value


class DeclaredShape:
    """Base of every shape: provenance and swept copies from the class's declarations."""

    kind: ClassVar[str]
    code: ClassVar[ShapeCode]
    surface: ClassVar[str]
    entries: ClassVar[tuple[Entry, ...]]
    sweep_names: ClassVar[tuple[SweepName, ...]] = ()
    closed: ClassVar[bool] = True
    stored: ClassVar[bool] = True

    def kernel_fields(self) -> dict[str, Any]:
        """Give the fields of the kernel parameter record this shape sets.

        Its code, and each declared entry under its key: the record's field of that name.
        A shape whose record holds something other than its entries (an implicit
        surface) gives its own.

        Returns
        -------
        dict of str to object
            Field name of ``kernels.layout`` -> value (SI).
        """
        return {"shape_code": self.code, **{e.key: getattr(self, e.key) for e in self.entries}}

    def kernel_parameters(self) -> tuple[float, float, float, float]:
        """Give the four shape numbers a run records (``body_shape_parameters``).

        Returns
        -------
        tuple of 4 float
            The shape's numbers [m].
        """
        raise NotImplementedError

    @property
    def bounding_radius(self) -> float | None:
        """An upper bound of the distance from G to the surface [m]; None for an open cap.

        The plausibility checks of size and density skip what is None.
        """
        return None

    @property
    def volume(self) -> float | None:
        """Volume enclosed by the surface [m³]; None where it has no closed form."""
        return None

    @classmethod
    def example(cls) -> Self:
        """A Kane & Levinson-sized instance, symmetric about y = 0 (tests, docs)."""
        raise NotImplementedError

    def table(self) -> dict[str, object]:
        """Give the ``[shape]`` table of a body file that builds this shape.

        Returns
        -------
        dict of str to object
            ``kind`` first, then the declared entries as JSON and TOML values.

        Raises
        ------
        ParameterError
            For a shape that is not data (``stored`` false: a Python function).
        """
        if not self.stored:
            raise ParameterError(
                "shape",
                self.kind,
                "a shape given as numbers, not as a Python function",
                "a compiled Python function lives in this process only",
            )
        return {"kind": self.kind, **{e.key: _plain(getattr(self, e.key)) for e in self.entries}}

    def attributes(self) -> dict[str, str | float]:
        """Give the shape's provenance for a run's or a sweep's attributes.

        Returns
        -------
        dict of str to str or float
            Its kind, the four recorded numbers and, for a stored shape, the table that
            rebuilds it.
        """
        attrs: dict[str, str | float] = {
            "body_shape": self.kind,
            "body_shape_parameters": str(list(self.kernel_parameters())),
        }
        if self.stored:
            attrs["body_shape_table"] = json.dumps(self.table())
        return attrs

    def replaced(self, values: Mapping[str, float]) -> Self:
        """Copy the shape with some of its numbers set, validated anew.

        Parameters
        ----------
        values : mapping of str to float
            Name of ``sweep_names`` -> value, in the unit of its entry (SI).

        Returns
        -------
        Self
            The new shape (this one when ``values`` is empty).
        """
        if not values:
            return self
        by_name = {sweep.name: sweep for sweep in self.sweep_names}
        keywords = {f.name: getattr(self, f.name) for f in fields(self) if f.init}  # type: ignore[arg-type]
        for name, value in values.items():
            if name not in by_name:
                allowed = ", ".join(by_name) or "none"
                raise ParameterError(
                    "parameter", name, f"a parameter of the body's {self.kind} shape ({allowed})"
                )
            sweep = by_name[name]
            if sweep.index is None:
                keywords[sweep.field] = value
            else:
                numbers = list(keywords[sweep.field])
                numbers[sweep.index] = value
                keywords[sweep.field] = tuple(numbers)
        return type(self)(**keywords)
