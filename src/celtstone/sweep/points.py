"""A list of sweep points from a CSV file: a header of parameter names, a row per point.

The file is UTF-8 text (a byte-order mark, as spreadsheet programs write, is
allowed); lines whose first cell starts with ``#`` and blank rows are skipped. Every
fault is one :class:`ParameterError` naming the file, the line and the column:
a name that is not a sweep parameter, a name given twice or left empty, a cell that
is empty, not a number, NaN or infinite, a row of another length than the header,
a file with no header or no row, a file that is not UTF-8 text.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Iterator

from celtstone.errors import ParameterError
from celtstone.sweep import budget
from celtstone.sweep.spec import check_name

__all__ = ["read_points"]


def _rows(path: str) -> Iterator[tuple[int, list[str]]]:
    """(line number, cells) of every row that is not blank or a comment."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as stream:
            reader = csv.reader(stream, strict=True)
            for row in reader:
                if not any(cell.strip() for cell in row) or row[0].lstrip().startswith("#"):
                    continue
                yield reader.line_num, row
    except OSError as error:
        raise ParameterError("points", path, "a readable CSV file", str(error)) from None
    except UnicodeDecodeError as error:
        raise ParameterError(
            "points",
            path,
            "a CSV text file in UTF-8",
            f"byte 0x{error.object[error.start]:02x} at offset {error.start} is not UTF-8 text",
        ) from None
    except csv.Error as error:
        raise ParameterError("points", path, "a CSV file", str(error)) from None


def _header(path: str, line: int, cells: list[str]) -> list[str]:
    """Column names: sweep parameters, each once."""
    names = [cell.strip().replace("-", "_") for cell in cells]
    where = f"points file {path}, line {line}"
    for column, name in enumerate(names, start=1):
        if not name:
            raise ParameterError(
                "points", path, "a name in every header cell", f"{where}, column {column} is empty"
            )
        try:
            check_name(name)
        except ParameterError as error:
            raise ParameterError(
                error.name, error.value, error.allowed, f"{error.hint}; {where}, column {column}"
            ) from None
        if names.index(name) != column - 1:
            raise ParameterError(
                "points",
                path,
                "each column named once",
                f"{where}: {name} names columns {names.index(name) + 1} and {column}",
            )
    return names


def _value(path: str, line: int, column: int, name: str, text: str) -> float:
    """The number in one cell: finite."""
    where = f"points file {path}, line {line}, column {column}"
    if not text.strip():
        raise ParameterError(name, text, "a finite number", f"{where} is empty")
    try:
        value = float(text)
    except ValueError:
        raise ParameterError(name, text, "a finite number", where) from None
    if not math.isfinite(value):
        raise ParameterError(name, text, "a finite number", where)
    return value


def read_points(path: str, *, force: bool = False) -> dict[str, list[float]]:
    """Read the points of a sweep from the columns of a CSV file.

    Parameters
    ----------
    path : str
        The CSV file, one column per parameter name.
    force : bool, optional
        Accept more rows than ``budget.POINT_LIMIT`` (never more than
        ``budget.HARD_POINT_LIMIT``); reading stops at the first row beyond the limit.

    Returns
    -------
    dict of str to list of float
        Parameter name -> one value per point.

    Raises
    ------
    ParameterError
        Naming the file, the line and the column of the first fault.
    """
    rows = _rows(path)
    first = next(rows, None)
    if first is None:
        raise ParameterError(
            "points", path, "a header of names and at least one row", "the file has no header"
        )
    names = _header(path, *first)
    columns: dict[str, list[float]] = {name: [] for name in names}
    limit = budget.HARD_POINT_LIMIT if force else budget.POINT_LIMIT
    count = 0
    for line, row in rows:
        if len(row) != len(names):
            raise ParameterError(
                "points",
                path,
                f"rows of {len(names)} values, as the header",
                f"line {line} has {len(row)}",
            )
        count += 1
        if count > limit:
            raise ParameterError(
                "points",
                path,
                f"at most {limit} rows" + ("" if force else " without --force"),
                f"line {line} is row {count}; "
                + ("split the sweep into parts" if force else "use fewer points, or --force"),
            )
        for column, (name, text) in enumerate(zip(names, row, strict=True), start=1):
            columns[name].append(_value(path, line, column, name, text))
    if not count:
        raise ParameterError(
            "points", path, "a header of names and at least one row", "the file has no rows"
        )
    return columns
