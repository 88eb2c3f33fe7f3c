"""Writers that produce a file whole or not at all (temporary file + ``os.replace``)."""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import pandas as pd
import xarray as xr

from celtstone.errors import ParameterError

__all__ = [
    "FORMATS",
    "atomic_path",
    "check_target",
    "read_run",
    "read_table",
    "to_csv",
    "write",
    "write_json",
    "write_table",
]

FORMATS = (".nc", ".csv")

_UMASK = os.umask(0o022)  # read the process's umask once (os.umask can only set it) ...
os.umask(_UMASK)  # ... and put it back


def check_target(
    path: str | Path, formats: Sequence[str] = FORMATS, parameter: str = "out"
) -> Path:
    """``path`` as a :class:`Path` if it can be written: a suffix in ``formats``, an existing
    directory. Call it before a long computation whose result goes to ``path``.

    Raises
    ------
    ParameterError
        naming ``parameter``, for another suffix or a directory that does not exist.
    """
    target = Path(path)
    if target.suffix.lower() not in formats:
        allowed = "a file name ending in " + " or ".join(formats)
        raise ParameterError(parameter, str(path), allowed)
    directory = target.parent if str(target.parent) else Path(".")
    if not directory.is_dir():
        raise ParameterError(parameter, str(path), "a file in an existing directory")
    return target


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; move it into place only on success."""
    target = Path(path)
    directory = target.parent if str(target.parent) else Path(".")
    if not directory.is_dir():
        raise ParameterError("out", str(path), "a file in an existing directory")
    handle, name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".part", dir=directory)
    os.close(handle)
    temporary = Path(name)
    try:
        yield temporary
        # mkstemp makes the file private (0600); give it the mode a plain open() would
        os.chmod(temporary, 0o666 & ~_UMASK)
        os.replace(temporary, target)
    finally:
        temporary.unlink(missing_ok=True)


def to_csv(dataset: xr.Dataset, path: Path) -> None:
    """Write the time series of ``dataset`` as CSV, one column per component.

    Vector variables become ``omega_1``, ``omega_2``, ...; header comments carry
    the units.
    """
    columns = {"time": dataset["time"].values}
    units = {"time": dataset["time"].attrs.get("units", "")}
    for name, variable in dataset.data_vars.items():
        if variable.dims == ("time",):
            columns[str(name)] = variable.values
            units[str(name)] = variable.attrs.get("units", "")
        elif len(variable.dims) == 2 and variable.dims[0] == "time":
            labels = dataset[variable.dims[1]].values
            for index, label in enumerate(labels):
                key = f"{name}_{label}"
                columns[key] = variable.values[:, index]
                units[key] = variable.attrs.get("units", "")
    names = list(columns)
    with open(path, "w", encoding="utf-8", newline="") as stream:
        stream.write(f"# {dataset.attrs.get('title', 'celtstone run')}\n")
        stream.write("# units: " + ", ".join(f"{k} [{units[k]}]" for k in names) + "\n")
        stream.write(",".join(names) + "\n")
        count = len(columns["time"])
        for row in range(count):
            stream.write(",".join(repr(float(columns[k][row])) for k in names) + "\n")


def write(dataset: xr.Dataset, path: str | Path) -> Path:
    """Write ``dataset`` to ``path`` (.nc NetCDF-4 or .csv), whole or not at all."""
    target = check_target(path)
    suffix = target.suffix.lower()
    with atomic_path(target) as temporary:
        if suffix == ".nc":
            dataset.to_netcdf(temporary, engine="netcdf4")
        else:
            to_csv(dataset, temporary)
    return target


def write_table(table: pd.DataFrame, path: str | Path, provenance: Mapping[str, Any]) -> Path:
    """Write ``table`` as CSV, whole or not at all, after ``# key: value`` header lines.

    ``provenance`` names the body source, model, friction law, tolerances and the
    celtstone version; :func:`read_table` reads the file back.
    """
    target = Path(path)
    with atomic_path(target) as temporary:
        with open(temporary, "w", encoding="utf-8", newline="") as stream:
            for key, value in provenance.items():
                text = str(value).replace("\n", " ")
                stream.write(f"# {key}: {text}\n")
            table.to_csv(stream, index=False, float_format="%.12g")
    return target


def read_table(path: str | Path) -> tuple[pd.DataFrame, dict[str, str]]:
    """A CSV written by :func:`write_table`: the table and its provenance header."""
    provenance: dict[str, str] = {}
    with open(path, encoding="utf-8") as stream:
        for line in stream:
            if not line.startswith("# "):
                break
            key, _, value = line[2:].rstrip("\n").partition(": ")
            provenance[key] = value
    return pd.read_csv(path, skiprows=len(provenance)), provenance


def write_json(data: Any, path: str | Path) -> Path:
    """Write ``data`` as indented JSON, whole or not at all."""
    target = Path(path)
    with atomic_path(target) as temporary:
        temporary.write_text(json.dumps(data, indent=2, allow_nan=False) + "\n", encoding="utf-8")
    return target


def read_run(path: str | Path) -> xr.Dataset:
    """A run written by celtstone (``celtstone run --out RUN.nc``), loaded into memory.

    Raises
    ------
    ParameterError
        if ``path`` is not a readable NetCDF file with a celtstone run in it.
    """
    source = Path(path)
    allowed = "an existing NetCDF file written by `celtstone run --out RUN.nc`"
    if not source.is_file():
        raise ParameterError("run", str(path), allowed)
    try:
        with xr.open_dataset(source, engine="netcdf4") as opened:
            dataset = opened.load()
    except (OSError, ValueError) as error:
        raise ParameterError("run", str(path), allowed, f"cannot read it: {error}") from None
    missing = [name for name in ("spin", "energy", "time") if name not in dataset.variables]
    if dataset.attrs.get("software") != "celtstone" or missing:
        raise ParameterError("run", str(path), allowed, "it is not a celtstone run")
    return dataset
