"""A measured record: times and named series in SI, checked once when it is made.

``make_record`` takes arrays (Python); ``read_record`` reads a CSV file, maps its columns
(``--column NAME=HEADER``) and recognises phyphox's gyroscope export.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from celtstone.errors import ParameterError, did_you_mean
from celtstone.fitting.sensor import parse_sensor_rotation
from celtstone.fitting.series import ANGLE_UNITS, RATE_UNITS, SERIES

__all__ = ["PHYPHOX_GYROSCOPE", "Record", "make_record", "parse_column", "read_record"]

# phyphox's gyroscope export: time and the rates about the phone's axes x, y, z
PHYPHOX_TIME = "Time (s)"
PHYPHOX_GYROSCOPE = ("Gyroscope x (rad/s)", "Gyroscope y (rad/s)", "Gyroscope z (rad/s)")
_HEADER_UNIT = re.compile(r"[(\[]\s*([^)\]]+?)\s*[)\]]\s*$")  # "Tilt (deg)" -> "deg"
_COLUMN = re.compile(r"^\s*(\w+)\s*(?:\[\s*([^\]]+?)\s*\])?\s*=(.*)$")  # NAME[UNIT]=HEADER
_TIME_UNITS = {"s": 1.0}
_SEPARATORS = (",", ";", "\t")
_SNIFF_LINES = 50
# a number with a decimal comma: digits, a comma, digits, not followed by more digit groups
_DECIMAL_COMMA = re.compile(r"(^|;)\s*\"?[-+]?\d+,\d+([eE][-+]?\d+)?\"?\s*(;|$)")
# headers that name the time column
_TIME_NAMES = {"t": "time", "time": "time"}
# units a header may state: another than the one read is a mistake, not a label
_KNOWN_UNITS = {*RATE_UNITS, *ANGLE_UNITS, *_TIME_UNITS, "ms", "min", "h", "rpm", "Hz", "1/s"}


@dataclass(frozen=True)
class Record:
    """A measured motion.

    Parameters
    ----------
    times : numpy.ndarray
        Sample times from the first sample [s], shape (m,), increasing, times[0] = 0.
    series : mapping of str to numpy.ndarray
        Series name (``SERIES``) -> values in its SI unit, shape (m,).
    start_time : float
        Time of the first sample in the file [s].
    source : str
        Where it came from (a file name, or "arrays").
    columns : mapping of str to str
        Series name -> the header it was read from.
    """

    times: np.ndarray
    series: Mapping[str, np.ndarray]
    start_time: float = 0.0
    source: str = "arrays"
    columns: Mapping[str, str] = field(default_factory=lambda: MappingProxyType({}))

    @property
    def n_points(self) -> int:
        """Number of measured values over all series."""
        return sum(values.size for values in self.series.values())

    def describe(self) -> dict[str, Any]:
        """Describe the record for a fit's summary.

        Returns
        -------
        dict
            Source, series with their units and columns, sample count, start time and
            duration [s].
        """
        return {
            "source": self.source,
            "series": {
                name: {"unit": SERIES[name].unit, "column": self.columns.get(name, name)}
                for name in self.series
            },
            "samples": int(self.times.size),
            "start_time": self.start_time,
            "duration": float(self.times[-1]),
        }


def _finite_array(name: str, values: Any) -> np.ndarray:
    """``values`` as a 1-D float array, or ParameterError naming ``name`` and the first bad row."""
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(name, "non-numeric values", "numbers in every row") from None
    if array.ndim != 1:
        raise ParameterError(name, f"shape {array.shape}", "a 1-D series of numbers")
    bad = np.flatnonzero(~np.isfinite(array))
    if bad.size:
        raise ParameterError(
            name, f"{float(array[bad[0]])} in row {bad[0] + 1}", "finite numbers (no NaN or inf)"
        )
    return array


def make_record(
    times: Sequence[float] | np.ndarray,
    series: Mapping[str, Sequence[float] | np.ndarray],
    *,
    source: str = "arrays",
    columns: Mapping[str, str] | None = None,
) -> Record:
    """Make a checked :class:`Record` from arrays in SI (rad/s, rad; ``SERIES``).

    Times are shifted to start at 0 (the model starts at the first sample); a yaw series
    is unwrapped.

    Parameters
    ----------
    times : sequence of float or numpy.ndarray
        Sample times [s], strictly increasing, at least 2.
    series : mapping of str to array_like
        Series name (``SERIES``) -> values in its SI unit, one per time.
    source : str
        Where the data came from, kept in the record.
    columns : mapping of str to str, optional
        Series name -> the header it was read from.

    Returns
    -------
    Record
        The record, times from 0.

    Raises
    ------
    ParameterError
        naming the series for an unknown name, NaN or non-numeric values, a length other
        than that of ``times``, or a series with no variation; naming ``time`` for times
        that do not increase or fewer than 2 samples.
    """
    time = _finite_array("time", times)
    if time.size < 2:
        raise ParameterError("time", f"{time.size} samples", "at least 2 samples")
    steps = np.diff(time)
    if np.any(steps <= 0.0):
        row = int(np.flatnonzero(steps <= 0.0)[0]) + 2
        raise ParameterError(
            "time", f"{time[row - 1]:g} s in row {row}", "strictly increasing times [s]"
        )
    if not series:
        raise ParameterError("series", "none", "at least one of: " + ", ".join(SERIES))
    checked = {}
    for name, values in series.items():
        if name not in SERIES:
            raise ParameterError(
                "column",
                name,
                "a series name, one of: " + ", ".join(SERIES),
                did_you_mean(name, SERIES),
            )
        array = _finite_array(name, values)
        if array.size != time.size:
            raise ParameterError(name, f"{array.size} values", f"{time.size} values, one per time")
        if np.ptp(array) == 0.0:
            raise ParameterError(name, f"constant {array[0]:g}", "a series that varies")
        checked[name] = np.unwrap(array) if SERIES[name].is_angle_offset_free else array
    return Record(
        times=time - time[0],
        series=MappingProxyType(checked),
        start_time=float(time[0]),
        source=source,
        columns=MappingProxyType(dict(columns or {})),
    )


def parse_column(text: str) -> tuple[str, str | None, str]:
    """``NAME[UNIT]=HEADER`` -> (name, unit or None, header): ``tilt[deg]=Tilt``,
    ``spin=w_z``, ``time=t (s)``."""
    match = _COLUMN.match(text)
    if match is None or not match.group(3).strip():
        raise ParameterError("column", text, "NAME=HEADER or NAME[UNIT]=HEADER", "e.g. spin=w_z")
    name, unit, header = match.group(1), match.group(2), match.group(3).strip()
    if name != "time" and name not in SERIES:
        names = ("time", *SERIES)
        raise ParameterError(
            "column", name, "one of: " + ", ".join(names), did_you_mean(name, names)
        )
    return name, unit, header


def _unit(name: str, given: str | None, header: str) -> float:
    """Factor to SI of column ``header`` read as ``name``: the unit ``given`` (``[UNIT]``),
    else the one the header states, else the series' default; a conflict is refused."""
    units = _TIME_UNITS if name == "time" else SERIES[name].units
    match = _HEADER_UNIT.search(header)
    stated = match.group(1) if match and match.group(1) in _KNOWN_UNITS else None
    unit = given or stated or ("s" if name == "time" else SERIES[name].default_unit)
    if unit not in units:
        raise ParameterError(
            f"{name} unit", unit, "one of: " + ", ".join(units), f"column {header!r}"
        )
    if stated is not None and stated != unit:
        raise ParameterError(
            f"{name} unit", unit, f"{stated}, the unit in the header {header!r}", "drop [UNIT]"
        )
    return units[unit]


def _column(table: Any, header: str, name: str) -> np.ndarray:
    """Column ``header`` of ``table`` as numbers; missing or non-numeric columns refused."""
    headers = [str(h) for h in table.columns]
    if header not in headers:
        raise ParameterError(
            f"{name} column",
            header,
            "a header of the file: " + ", ".join(repr(h) for h in headers),
            did_you_mean(header, headers),
        )
    import pandas as pd

    numbers = pd.to_numeric(table[header], errors="coerce").to_numpy(dtype=float)
    unreadable = np.flatnonzero(np.isnan(numbers) & ~table[header].isna().to_numpy())
    if unreadable.size:
        row = int(unreadable[0])
        raise ParameterError(
            f"{name} column {header!r}", f"{table[header].iloc[row]} in row {row + 1}", "numbers"
        )
    return numbers


def _read_table(source: Path, shown: str) -> Any:
    """The file as a table: its separator (comma, semicolon or tab; none: one column) and
    decimal mark (a comma beside semicolons: phyphox's "semicolon, decimal comma") read
    from its first lines, not guessed among all characters."""
    import pandas as pd

    try:
        with source.open(encoding="utf-8-sig") as file:
            lines = [line for _, line in zip(range(_SNIFF_LINES), file, strict=False)]
    except (OSError, UnicodeDecodeError) as error:
        raise ParameterError("data", shown, "a readable UTF-8 CSV file", str(error)) from None
    content = [line for line in lines if line.strip() and not line.lstrip().startswith("#")]
    if len(content) < 2:
        raise ParameterError("data", shown, "a CSV file with a header row and data rows")
    header, first = content[0], content[1]
    separator = max(_SEPARATORS, key=lambda sep: (header.count(sep), -_SEPARATORS.index(sep)))
    if header.count(separator) == 0:
        separator = ","  # one column
    decimal = "," if separator == ";" and _DECIMAL_COMMA.search(first) else "."
    try:
        table = pd.read_csv(
            source,
            sep=separator,
            decimal=decimal,
            comment="#",
            skipinitialspace=True,
            encoding="utf-8-sig",
        )
    except (ValueError, pd.errors.ParserError, UnicodeDecodeError) as error:
        message = " ".join(str(error).split())
        hint = (
            f"{message}; a file separated by semicolons with decimal commas (phyphox's "
            "'semicolon, decimal comma' export) is read as such"
        )
        raise ParameterError("data", shown, "a CSV file with a header row", hint) from None
    table.columns = [str(h).strip() for h in table.columns]
    if len(table.columns) == 0 or len(table) == 0:
        raise ParameterError("data", shown, "a CSV file with a header row and data rows")
    return table


def _named_like_series(headers: Sequence[str]) -> dict[str, tuple[str | None, str]]:
    """Series (and time) whose names the headers are, a unit in brackets allowed:
    ``time (s)``, ``spin``, ``omega1 (rad/s)``; name -> (None, header)."""
    found: dict[str, tuple[str | None, str]] = {}
    for header in headers:
        bare = _HEADER_UNIT.sub("", header).strip().lower()
        name = _TIME_NAMES.get(bare, bare)
        if (name == "time" or name in SERIES) and name not in found:
            found[name] = (None, header)
    return found if set(found) - {"time"} else {}


def read_record(
    path: str | Path,
    columns: Sequence[str] | Mapping[str, str] = (),
    *,
    sensor_rotation: str | Sequence[float] | None = None,
) -> Record:
    """Read a CSV file of measured series (see :func:`make_record` for the checks).

    Parameters
    ----------
    path : str or pathlib.Path
        A CSV file with a header row (comma, semicolon or tab separated; with semicolons,
        decimal commas are read too).
    columns : sequence of str or mapping of str to str
        ``NAME[UNIT]=HEADER`` strings, or a mapping NAME -> HEADER: which column holds
        ``time`` [s] (default: the first column) and each series of ``SERIES``; none
        given, headers named like a series (``spin (rad/s)``, ``omega1``) are read as it; the unit
        is ``[UNIT]``, else the header's own ``(unit)``, else the series' default
        (rad/s for rates, rad for yaw, deg for tilt).
    sensor_rotation : str or sequence of float, optional
        The gyroscope's axes in body axes (``fitting.sensor``), for phyphox's export: its
        ``Gyroscope x/y/z (rad/s)`` columns become omega1..3 when no series is mapped by
        ``columns``; default: the sensor's axes are the body's.

    Returns
    -------
    Record
        The checked record (:func:`make_record`), in SI.
    """
    source = Path(path)
    if not source.is_file():
        raise ParameterError("data", str(path), "an existing CSV file")
    table = _read_table(source, str(path))
    texts = [f"{k}={v}" for k, v in columns.items()] if isinstance(columns, Mapping) else columns
    mapping = {name: (unit, header) for name, unit, header in map(parse_column, texts)}
    if len(table.columns) == 0 or len(table) == 0:
        raise ParameterError("data", str(path), "a CSV file with a header row and data rows")
    if not mapping and not set(PHYPHOX_GYROSCOPE) <= set(table.columns):
        mapping = _named_like_series(table.columns)  # headers that name a series
    time_unit, time_header = mapping.pop("time", (None, table.columns[0]))
    series: dict[str, np.ndarray] = {}
    headers: dict[str, str] = {"time": time_header}
    if not mapping and set(PHYPHOX_GYROSCOPE) <= set(table.columns):
        rotation = parse_sensor_rotation(sensor_rotation)
        sensor = np.column_stack([_column(table, h, "gyroscope") for h in PHYPHOX_GYROSCOPE])
        for k, values in enumerate((sensor @ rotation.T).T):
            series[f"omega{k + 1}"] = values
            headers[f"omega{k + 1}"] = (
                f"Gyroscope x, y, z (rad/s) turned into body axes by R = {rotation.tolist()}"
            )
    elif sensor_rotation is not None:
        raise ParameterError(
            "sensor_rotation",
            sensor_rotation,
            "only with phyphox's gyroscope columns and no --column series",
        )
    for name, (unit, header) in mapping.items():
        series[name] = _column(table, header, name) * _unit(name, unit, header)
        headers[name] = header
    if not series:
        raise ParameterError(
            "column", "none", "at least one NAME=HEADER for a series: " + ", ".join(SERIES)
        )
    times = _column(table, time_header, "time") * _unit("time", time_unit, time_header)
    return make_record(times, series, source=str(path), columns=headers)
