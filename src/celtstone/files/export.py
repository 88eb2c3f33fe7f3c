"""Writers that produce a file whole or not at all, and never replace what was not asked for.

Every file is written to a temporary name beside its target and moved into place
only when it is complete. The policy, shared by the CLI and the Python API:

* an existing target is refused (:class:`ParameterError` naming ``out``) unless
  ``overwrite=True`` (``--overwrite``), and ``overwrite`` replaces only a file,
  never a directory, and only one that carries celtstone's mark where its format has
  one (``ownership.is_marked_file``: all but JSON and Markdown); without it the final
  move cannot replace a file that appeared while the output was computed (a hard
  link, which fails if the name is taken);
* a temporary is named ``.NAME.<pid>.<random>.part``: a process killed while writing
  (SIGKILL) leaves one behind, and the next write to the same target removes those
  whose process is gone (:func:`remove_stale_temporaries`), never one of a live
  process and never a file of another naming;
* a failed write (disk full, no permission) raises :class:`OutputError` naming the
  file and the cause, and leaves neither the target nor a temporary;
* an interrupted write (Ctrl-C, SIGTERM: exceptions that unwind) leaves no temporary,
  even when it comes as the temporary is created (its name is chosen first), and an
  earlier output being replaced stays in place until the new one is whole.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import re
import secrets
import shutil
import stat
import sys
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from celtstone._about import version
from celtstone.errors import OutputError, ParameterError
from celtstone.files.ownership import CSV_MARK, SOFTWARE, is_marked_file
from celtstone.files.path_names import check_path_name
from celtstone.simulation.schema import current_attributes

if TYPE_CHECKING:  # imported where used: a JSON-only command needs neither
    import pandas as pd
    import xarray as xr

__all__ = [
    "FORMATS",
    "OVERWRITE_HINT",
    "atomic_path",
    "check_target",
    "output_beside",
    "output_error",
    "read_run",
    "read_table",
    "remove_stale_temporaries",
    "replace_directory",
    "temporary_directory",
    "to_csv",
    "write",
    "write_json",
    "write_table",
]

FORMATS = (".nc", ".csv")
"""The suffixes a run can be written to: NetCDF (the whole run) and CSV (its table)."""
OVERWRITE_HINT = "add --overwrite to replace it"
"""The fix named by the error raised when an output file exists."""
MIN_SAMPLES = 2  # a run to plot or export has a start and an end
_RUN_ALLOWED = "an existing NetCDF file written by `celtstone run --out RUN.nc`"
_TEMPORARY_SUFFIX = ".part"
_RANDOM = r"[a-z0-9_]{8}"  # secrets.token_hex(4) (and tempfile's names, of earlier versions)
# free space [bytes] below which a failed NetCDF write is put down to a full disk
_FULL_DISK_MARGIN = 1 << 20
# file systems without hard links: the no-replace move falls back to check + rename
_NO_HARD_LINKS = {errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EMLINK, errno.ENOSYS}

_UMASK = os.umask(0o022)  # read the process's umask once (os.umask can only set it) ...
os.umask(_UMASK)  # ... and put it back


def _directory(target: Path) -> Path:
    return target.parent if str(target.parent) else Path(".")


def _exists_error(target: Path, parameter: str) -> ParameterError:
    return ParameterError(parameter, str(target), "a file that does not exist yet", OVERWRITE_HINT)


def _refuse_existing(target: Path, *, overwrite: bool, parameter: str) -> None:
    """Raise unless ``target`` is free, or ``overwrite`` and it is a file (or a link)."""
    if not os.path.lexists(target):
        return
    if target.is_dir():
        raise ParameterError(
            parameter,
            str(target),
            "a file name, not a directory",
            "--overwrite replaces only a file" if overwrite else "it is a directory",
        )
    if not overwrite:
        raise _exists_error(target, parameter)
    with contextlib.suppress(OSError):  # a dangling link is replaced like a file
        if not stat.S_ISREG(target.stat().st_mode):
            raise ParameterError(
                parameter,
                str(target),
                "a file name, not a device, pipe or socket",
                "--overwrite replaces only a regular file",
            )
    if is_marked_file(target) is False:
        raise ParameterError(
            parameter,
            str(target),
            "a file celtstone wrote",
            "--overwrite replaces only a file that carries celtstone's mark; this one "
            "does not: move it or choose another name",
        )


def check_target(
    path: str | Path,
    formats: Sequence[str] = FORMATS,
    parameter: str = "out",
    *,
    overwrite: bool = False,
) -> Path:
    """Check that ``path`` can be written before a long computation whose result goes there.

    It needs a suffix in ``formats``, an existing directory, and no file there unless
    ``overwrite`` (never a directory).

    Parameters
    ----------
    path : str or pathlib.Path
        The output file.
    formats : sequence of str, optional
        The suffixes allowed (default :data:`FORMATS`).
    parameter : str, optional
        The option or argument named in errors.
    overwrite : bool, optional
        Whether an existing file may be replaced.

    Returns
    -------
    pathlib.Path
        ``path`` as a :class:`~pathlib.Path`.

    Raises
    ------
    ParameterError
        Naming ``parameter``, for an empty path, another suffix, a directory that does
        not exist, an existing file (without ``overwrite``) or an existing directory.
    """
    allowed = "a file name ending in " + " or ".join(formats)
    if str(path) == "":
        raise ParameterError(parameter, str(path), allowed, "the path is empty")
    check_path_name(path, parameter)
    target = Path(path)
    if target.suffix.lower() not in formats:
        raise ParameterError(parameter, str(path), allowed)
    if not _directory(target).is_dir():
        raise ParameterError(parameter, str(path), "a file in an existing directory")
    _refuse_existing(target, overwrite=overwrite, parameter=parameter)
    return target


def output_beside(run: str | Path, suffix: str) -> Path:
    """Name the default output of a command on the run file ``run``: its name with ``suffix``.

    Parameters
    ----------
    run : str or pathlib.Path
        The run file.
    suffix : str
        The output's suffix (``".png"``).

    Returns
    -------
    pathlib.Path
        The output beside the run.

    Raises
    ------
    ParameterError
        Naming ``run`` when it names no file (empty, ``.``, ``..``, ``/``).
    """
    source = Path(run)
    if str(run) == "" or source.name in ("", ".", ".."):
        raise ParameterError("run", str(run), _RUN_ALLOWED, "the path names no file")
    return source.with_suffix(suffix)


# ---------------------------------------------------------------------------------------
# Temporaries: named after their process, removed when their process is gone
# ---------------------------------------------------------------------------------------


def _temporary_prefix(target: Path) -> str:
    return f".{target.name}.{os.getpid()}."


def _is_alive(pid: int) -> bool:
    """Whether process ``pid`` exists (this PID namespace); in doubt, yes."""
    if pid <= 0 or pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError):
        return True  # another user's process, or not a PID this system can have
    return True


def remove_stale_temporaries(target: str | Path) -> list[Path]:
    """Remove the temporaries of ``target`` left by processes that are gone.

    A temporary of ours is named ``.NAME.<pid>.<random>.part`` beside ``target``
    (a file, or a directory for a sweep store or a staging area). Only names of
    exactly that form whose process no longer exists are removed: never one of a
    live process, never any other file.

    Parameters
    ----------
    target : str or pathlib.Path
        The output whose temporaries are looked for.

    Returns
    -------
    list of pathlib.Path
        The temporaries removed.

    Notes
    -----
    Liveness is that of this PID namespace: a directory shared by machines (NFS)
    holding a temporary of a live process on another machine would lose it, and
    that process's write then fails with a message; none of its output is mixed.
    """
    path = Path(target)
    pattern = re.compile(rf"\.{re.escape(path.name)}\.(\d{{1,10}})\.{_RANDOM}\.part")
    removed = []
    try:
        entries = list(os.scandir(_directory(path)))
    except OSError:
        return []
    for entry in entries:
        match = pattern.fullmatch(entry.name)
        if match is None or _is_alive(int(match.group(1))):
            continue
        try:
            if entry.is_dir(follow_symlinks=False):
                shutil.rmtree(entry.path)
            else:
                os.unlink(entry.path)
        except FileNotFoundError:
            pass  # another process removed it first
        except OSError:
            continue  # not ours to force; left as it is
        removed.append(Path(entry.path))
    return removed


def replace_directory(source: Path, target: Path) -> None:
    """Move the directory ``source`` to ``target`` whole (the same file system).

    An earlier ``target`` is moved aside first (``.NAME.<pid>.<random>.part``) and
    removed after, never mixed with the new one's files. If the move fails or is
    interrupted (Ctrl-C, SIGTERM) before ``source`` is in place, the earlier ``target``
    is put back.

    Parameters
    ----------
    source : pathlib.Path
        The finished directory.
    target : pathlib.Path
        Where it goes.

    Raises
    ------
    OutputError
        If a move fails (``target`` is then the earlier one, or absent if it had none).
    """
    aside = _temporary_name(target)
    try:
        if os.path.lexists(target):
            os.rename(target, aside)
        os.rename(source, target)
    except BaseException as error:
        if os.path.lexists(aside) and not os.path.lexists(target):
            os.rename(aside, target)
        if isinstance(error, OSError):
            raise output_error(target, error) from error
        raise
    finally:
        shutil.rmtree(aside, ignore_errors=True)


def _temporary_name(target: Path) -> Path:
    """A new name ``.NAME.<pid>.<random>.part`` beside ``target``."""
    return target.with_name(f"{_temporary_prefix(target)}{secrets.token_hex(4)}{_TEMPORARY_SUFFIX}")


_TEMPORARY_ATTEMPTS = 100  # names tried before a directory that says every one is taken


@contextlib.contextmanager
def _new_temporary(target: Path, make: Callable[[Path], None]) -> Iterator[Path]:
    """Yield a temporary that ``make`` creates beside ``target``; remove it afterwards if
    it is still there (it is not once moved into place). Stale temporaries of ``target``
    are removed first (:func:`remove_stale_temporaries`).

    The name is chosen before ``make`` creates it (``make`` raises ``FileExistsError``
    for a name taken), so an interruption at any point, even as ``make`` returns,
    leaves nothing: the clean-up always knows the name. Names with this process's PID
    are this process's alone, so nothing else is ever removed.

    Raises
    ------
    OutputError
        Naming ``target``, if the temporary cannot be made.
    """
    remove_stale_temporaries(target)
    temporary: Path | None = None
    try:
        for _ in range(_TEMPORARY_ATTEMPTS):
            temporary = _temporary_name(target)
            try:
                make(temporary)
                break
            except FileExistsError:
                temporary = None
            except OSError as error:
                temporary = None
                raise output_error(target, error) from error
        else:
            cause = f"no free temporary name after {_TEMPORARY_ATTEMPTS} tries"
            raise OutputError(str(target), cause, errno.EEXIST)
        yield temporary
    finally:
        if temporary is not None:
            _remove_temporary(temporary)


def _remove_temporary(temporary: Path) -> None:
    """Remove ``temporary`` (a file or a store's folder), once Zarr's writes under way
    have settled: a write still under way would make it again, even if not there now
    (Zarr empties a store's folder before its first write). A signal that interrupts
    this (one sent as the output is moved into place) still leaves nothing: the removal
    is made again before the interrupt goes on."""
    try:
        settle_zarr_writes()
        _remove_now(temporary)
    except BaseException:
        _remove_now(temporary)
        raise


def _remove_now(temporary: Path) -> None:
    if temporary.is_dir():
        shutil.rmtree(temporary, ignore_errors=True)
    else:
        with contextlib.suppress(OSError):
            temporary.unlink(missing_ok=True)


_SETTLE_TIMEOUT = 30.0  # s: Zarr's writes of one block or of an empty store take far less


def settle_zarr_writes(timeout: float = _SETTLE_TIMEOUT) -> None:
    """Wait until the writes that Zarr still runs on its I/O thread are done.

    Zarr runs each write as a task on its own event loop and waits for it in the calling
    thread; Ctrl-C or SIGTERM ends the wait, not the task, which may then create files
    and their folders after a temporary has been removed (a store built in a temporary
    directory would leave a ``.part`` behind). Nothing is waited for unless Zarr is
    loaded and its loop runs; after ``timeout`` the tasks are left as they are.

    Parameters
    ----------
    timeout : float, optional
        The longest wait [s].
    """
    zarr_sync = sys.modules.get("zarr.core.sync")  # never imports Zarr for this
    loop = getattr(zarr_sync, "loop", [None])[0]
    if loop is None or loop.is_closed() or not loop.is_running():
        return
    import asyncio
    import concurrent.futures

    async def settled() -> None:
        current = asyncio.current_task()
        pending = [task for task in asyncio.all_tasks() if task is not current]
        if pending:
            await asyncio.wait(pending, timeout=timeout)

    try:
        asyncio.run_coroutine_threadsafe(settled(), loop).result(timeout + 1.0)
    except (concurrent.futures.TimeoutError, RuntimeError):
        pass


def _make_private_file(path: Path) -> None:
    os.close(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))


def _make_private_directory(path: Path) -> None:
    path.mkdir(mode=0o700)


@contextlib.contextmanager
def temporary_directory(target: str | Path) -> Iterator[Path]:
    """Yield a new empty directory ``.NAME.<pid>.<random>.part`` beside ``target``.

    Stale temporaries of ``target`` are removed first. The directory is removed when
    the block ends, however it ends (an error, Ctrl-C, SIGTERM), unless the block has
    moved it, e.g. to ``target`` with :func:`replace_directory`.

    Parameters
    ----------
    target : str or pathlib.Path
        The directory it stands in for.

    Yields
    ------
    pathlib.Path
        The new directory.

    Raises
    ------
    OutputError
        If the directory cannot be made.
    """
    with _new_temporary(Path(target), _make_private_directory) as staging:
        yield staging


def output_error(target: str | Path, error: OSError) -> OutputError:
    """Turn ``error`` met while writing ``target`` into an :class:`OutputError`.

    Parameters
    ----------
    target : str or pathlib.Path
        The output being written; the error names it, never the temporary.
    error : OSError
        The cause.

    Returns
    -------
    OutputError
        The error naming ``target`` and the cause.
    """
    if isinstance(error, OutputError):
        return error
    cause = error.strerror or str(error) or type(error).__name__
    return OutputError(str(target), cause, error.errno)


def _move_into_place(temporary: Path, target: Path, overwrite: bool, parameter: str) -> None:
    if overwrite:
        _refuse_existing(target, overwrite=True, parameter=parameter)
        os.replace(temporary, target)
        return
    try:
        os.link(temporary, target)  # fails if the name is taken: never replaces
    except FileExistsError:
        raise _exists_error(target, parameter) from None
    except OSError as error:
        if error.errno not in _NO_HARD_LINKS:
            raise
        if os.path.lexists(target):
            raise _exists_error(target, parameter) from None
        os.rename(temporary, target)


@contextlib.contextmanager
def atomic_path(
    path: str | Path, *, overwrite: bool = False, parameter: str = "out"
) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; move it into place only on success.

    An existing ``path`` is refused unless ``overwrite`` (a directory always is);
    stale temporaries of ``path`` are removed first (:func:`remove_stale_temporaries`).

    Parameters
    ----------
    path : str or pathlib.Path
        The output file.
    overwrite : bool, optional
        Whether an existing file may be replaced.
    parameter : str, optional
        The option or argument named in errors.

    Yields
    ------
    pathlib.Path
        The temporary to write.

    Raises
    ------
    ParameterError
        Naming ``parameter``, for a directory that does not exist or a target in use.
    OutputError
        If writing fails (an ``OSError`` in the ``with`` block or in the final move):
        neither the target nor the temporary is left.
    """
    target = Path(path)
    check_path_name(target, parameter)
    if not _directory(target).is_dir():
        raise ParameterError(parameter, str(path), "a file in an existing directory")
    _refuse_existing(target, overwrite=overwrite, parameter=parameter)
    try:
        with _new_temporary(target, _make_private_file) as temporary:
            yield temporary
            # private (0600) while written; then the mode a plain open() would give it
            os.chmod(temporary, 0o666 & ~_UMASK)
            _move_into_place(temporary, target, overwrite, parameter)
    except OSError as error:
        raise output_error(target, error) from error


# ---------------------------------------------------------------------------------------
# Writers
# ---------------------------------------------------------------------------------------


def to_csv(dataset: xr.Dataset, path: Path) -> None:
    """Write the time series of ``dataset`` as CSV, one column per component.

    Vector variables become ``omega_1``, ``omega_2``, ...; header comments carry
    the units.

    Parameters
    ----------
    dataset : xarray.Dataset
        A run.
    path : pathlib.Path
        The file written (directly: :func:`write` writes it whole or not at all).
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
        stream.write(f"{CSV_MARK} {version()}\n")  # celtstone's: --overwrite may replace it
        stream.write("# units: " + ", ".join(f"{k} [{units[k]}]" for k in names) + "\n")
        stream.write(",".join(names) + "\n")
        count = len(columns["time"])
        for row in range(count):
            stream.write(",".join(repr(float(columns[k][row])) for k in names) + "\n")


def _free_bytes(directory: Path) -> int | None:
    try:
        stats = os.statvfs(directory)
    except (OSError, AttributeError):
        return None
    return stats.f_bavail * stats.f_frsize


def _to_netcdf(dataset: xr.Dataset, temporary: Path, target: Path) -> None:
    """NetCDF-4 to ``temporary``; the library's errors (no errno) become OutputError."""
    try:
        dataset.to_netcdf(temporary, engine="netcdf4")
    except RuntimeError as error:  # e.g. "NetCDF: HDF error" on a full disk
        free = _free_bytes(_directory(target))
        written = temporary.stat().st_size if temporary.exists() else 0
        if free is not None and (free < _FULL_DISK_MARGIN or free < dataset.nbytes - written):
            cause = f"{os.strerror(errno.ENOSPC)} ({free} bytes free)"
            raise OutputError(str(target), cause, errno.ENOSPC) from error
        raise OutputError(str(target), f"the NetCDF library failed: {error}") from error


def write(dataset: xr.Dataset, path: str | Path, *, overwrite: bool = False) -> Path:
    """Write ``dataset`` to ``path`` (.nc NetCDF-4 or .csv), whole or not at all.

    Parameters
    ----------
    dataset : xarray.Dataset
        A run.
    path : str or pathlib.Path
        The file, with a suffix of :data:`FORMATS`.
    overwrite : bool, optional
        Whether an existing file may be replaced (it is refused otherwise).

    Returns
    -------
    pathlib.Path
        The NetCDF or CSV file written.
    """
    target = check_target(path, overwrite=overwrite)
    suffix = target.suffix.lower()
    with atomic_path(target, overwrite=overwrite) as temporary:
        if suffix == ".nc":  # marked as celtstone's (a run already is): --overwrite may replace it
            marked = dataset.assign_attrs(software=dataset.attrs.get("software", SOFTWARE))
            _to_netcdf(marked, temporary, target)
        else:
            to_csv(dataset, temporary)
    return target


def write_table(
    table: pd.DataFrame,
    path: str | Path,
    provenance: Mapping[str, Any],
    *,
    overwrite: bool = False,
) -> Path:
    """Write ``table`` as CSV, whole or not at all, after ``# key: value`` header lines.

    Parameters
    ----------
    table : pandas.DataFrame
        The table.
    path : str or pathlib.Path
        The CSV file; :func:`read_table` reads it back.
    provenance : Mapping
        The header: the body source, model, friction law, tolerances and the celtstone
        version (``software``, added first if it does not name celtstone: the file's
        mark, ``ownership.CSV_MARK``).
    overwrite : bool, optional
        Whether an existing table may be replaced (it is refused otherwise).

    Returns
    -------
    pathlib.Path
        The CSV file written.
    """
    target = Path(path)
    header = dict(provenance)
    if not str(header.get("software", "")).startswith(SOFTWARE):  # the mark (CSV_MARK)
        header = {"software": f"{SOFTWARE} {version()}", **header}
    with atomic_path(target, overwrite=overwrite) as temporary:
        with open(temporary, "w", encoding="utf-8", newline="") as stream:
            for key, value in header.items():
                text = str(value).replace("\n", " ")
                stream.write(f"# {key}: {text}\n")
            table.to_csv(stream, index=False, float_format="%.12g")
    return target


def read_table(path: str | Path) -> tuple[pd.DataFrame, dict[str, str]]:
    """Read a CSV written by :func:`write_table`.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.

    Returns
    -------
    table : pandas.DataFrame
        The table.
    provenance : dict of str to str
        Its ``# key: value`` header.
    """
    provenance: dict[str, str] = {}
    with open(path, encoding="utf-8") as stream:
        for line in stream:
            if not line.startswith("# "):
                break
            key, _, value = line[2:].rstrip("\n").partition(": ")
            provenance[key] = value
    import pandas as pd

    return pd.read_csv(path, skiprows=len(provenance)), provenance


def write_json(data: Any, path: str | Path, *, overwrite: bool = False) -> Path:
    """Write ``data`` as indented JSON, whole or not at all.

    Parameters
    ----------
    data : object
        Anything :func:`json.dumps` writes.
    path : str or pathlib.Path
        The file.
    overwrite : bool, optional
        Whether an existing file may be replaced (it is refused otherwise).

    Returns
    -------
    pathlib.Path
        The JSON file written.
    """
    target = Path(path)
    text = json.dumps(data, indent=2, allow_nan=False) + "\n"
    with atomic_path(target, overwrite=overwrite) as temporary:
        temporary.write_text(text, encoding="utf-8")
    return target


def read_run(path: str | Path) -> xr.Dataset:
    """Read a run written by celtstone (``celtstone run --out RUN.nc``) into memory.

    The attributes of a file written before a rename read under their new names
    (``schema.RENAMED_ATTRIBUTES``).

    Parameters
    ----------
    path : str or pathlib.Path
        The NetCDF file.

    Returns
    -------
    xarray.Dataset
        The run, loaded.

    Raises
    ------
    ParameterError
        If ``path`` is not a readable NetCDF file with a celtstone run of at least
        two samples in it.
    """
    source = Path(path)
    if str(path) == "":
        raise ParameterError("run", str(path), _RUN_ALLOWED, "the path is empty")
    if not source.is_file():
        raise ParameterError("run", str(path), _RUN_ALLOWED)
    import xarray as xr

    try:
        with xr.open_dataset(source, engine="netcdf4") as opened:
            dataset = opened.load()
    except (OSError, ValueError, RuntimeError) as error:
        raise ParameterError("run", str(path), _RUN_ALLOWED, f"cannot read it: {error}") from None
    missing = [name for name in ("spin", "energy", "time") if name not in dataset.variables]
    if dataset.attrs.get("software") != "celtstone" or missing:
        raise ParameterError("run", str(path), _RUN_ALLOWED, "it is not a celtstone run")
    samples = int(dataset.sizes.get("time", 0))
    if samples < MIN_SAMPLES:
        raise ParameterError(
            "run",
            str(path),
            f"a run with at least {MIN_SAMPLES} samples",
            f"it has {samples}; run it again with a later --t-end",
        )
    dataset.attrs = current_attributes(dataset.attrs)
    return dataset
