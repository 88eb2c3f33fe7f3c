"""Writers that produce a file whole or not at all (temporary file + ``os.replace``)."""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

import xarray as xr

from celtstone.errors import ParameterError

__all__ = ["FORMATS", "atomic_path", "check_target", "to_csv", "write"]

FORMATS = (".nc", ".csv")


def check_target(path: str | Path) -> Path:
    """``path`` as a :class:`Path` if it can be written: a known suffix, an existing directory.

    Call it before a long computation whose result goes to ``path``.

    Raises
    ------
    ParameterError
        for an unknown suffix or a directory that does not exist.
    """
    target = Path(path)
    if target.suffix.lower() not in FORMATS:
        raise ParameterError("out", str(path), "a file name ending in " + " or ".join(FORMATS))
    directory = target.parent if str(target.parent) else Path(".")
    if not directory.is_dir():
        raise ParameterError("out", str(path), "a file in an existing directory")
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
