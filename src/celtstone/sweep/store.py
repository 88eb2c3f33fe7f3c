"""The sweep's Zarr store: created whole, filled block by block, marked complete last.

Layout (Zarr v3, readable with ``xarray.open_zarr(path, consolidated=False)``):

* one array per result field with the sweep's dimensions, chunked in *blocks*;
  a block is one Zarr chunk and a contiguous range of the points in C order;
* one coordinate array per grid axis (or, for a list of points, dimension
  ``point`` with one coordinate per parameter);
* ``completed`` (bool, same chunks): a block's mask chunk is written only after
  all of its result chunks, so a block marked done is whole;
* group attributes: provenance (celtstone version, body, model, tolerances, the
  fixed and varied parameters), ``sweep_spec`` (canonical JSON that a resume must
  match) and ``complete``, set to true only after the last block.

Zarr's local store writes every chunk and metadata document to a temporary file and
renames it into place, and the skeleton is built in a temporary directory and renamed
to the target: a store killed at any moment is never corrupt, only unfinished.

An existing path is replaced (``overwrite``) only if it is a celtstone sweep store,
recognised by its own group metadata (``zarr.json`` with ``format`` =
``celtstone-sweep-1``), and only if it holds nothing but the store's own files, its
metadata and the chunks of its arrays (``ownership.check_replaceable``): a notes
file, the ``--points`` file or anything else put into the store keeps it from being
replaced, and so does any other directory or file. The old store is moved aside, the
new one moved in, then the old one deleted. The skeleton and the store moved aside are
named ``.NAME.<pid>.<random>.part``, so that the next store made at the same path
removes those of a killed process (``export.remove_stale_temporaries``).

A store being written (made, filled or resumed) is locked against a second writer:
an exclusive lock on ``.NAME.lock`` beside it (``ownership.WriterLock``), held until
:meth:`SweepStore.close`; a second ``sweep`` on the same store is refused in one line
naming the store and the writing process.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from celtstone.errors import CeltstoneError, ParameterError
from celtstone.files.export import output_error, replace_directory, temporary_directory
from celtstone.files.ownership import LockedOutput, WriterLock, check_replaceable
from celtstone.files.path_names import check_path_name
from celtstone.simulation.outcome import OUTCOMES, RENAMED_OUTCOMES
from celtstone.solvers import batch

if TYPE_CHECKING:
    import xarray as xr
    import zarr


__all__ = [
    "RESULT_FIELDS",
    "Layout",
    "SweepStore",
    "check_store_target",
    "is_sweep_store",
    "open_sweep",
]

# name: (dtype, fill value, unit, long name), from the one declaration of each outcome
# (``simulation.outcome.OUTCOMES``), in the order of ``solvers.batch.RESULT_FIELDS``
RESULT_FIELDS: dict[str, tuple[str, Any, str, str]] = {
    field.name: (
        field.dtype,
        field.fill,
        OUTCOMES[field.name].unit,
        OUTCOMES[field.name].variable.long_name,
    )
    for field in batch.RESULT_FIELDS
}
"""Every result a sweep stores per point -> (dtype, fill value, unit, long name)."""
MASK = "completed"
FORMAT = "celtstone-sweep-1"
_METADATA = "zarr.json"
_METADATA_SIZE_LIMIT = 64 << 20  # bytes; a store's group metadata is far smaller
_COMMAND = "sweep"  # the command named by the store's manifest


def is_sweep_store(path: str | Path) -> bool:
    """Whether ``path`` is a directory (not a link) holding a celtstone sweep store: its
    group metadata ``zarr.json`` has the attribute ``format`` = ``celtstone-sweep-1``."""
    target = Path(path)
    if target.is_symlink() or not target.is_dir():
        return False
    metadata = target / _METADATA
    try:
        if not metadata.is_file() or metadata.stat().st_size > _METADATA_SIZE_LIMIT:
            return False
        document = json.loads(metadata.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    if not isinstance(document, dict) or document.get("node_type") != "group":
        return False
    attributes = document.get("attributes")
    return isinstance(attributes, dict) and attributes.get("format") == FORMAT


def check_store_target(
    path: str | Path,
    *,
    overwrite: bool = False,
    resume: bool = False,
    inputs: Iterable[str | Path] = (),
) -> Path:
    """``path`` as a Path if a sweep store may be made (or resumed) there.

    Free paths are allowed; an existing one only with ``resume`` or ``overwrite``,
    and then only if it is a celtstone sweep store (:func:`is_sweep_store`); with
    ``overwrite``, one that holds nothing but its own files and none of ``inputs``
    (``ownership.check_replaceable``). Call it before any computation;
    :meth:`SweepStore.create` checks again.

    Raises
    ------
    ParameterError
        naming ``out``: a directory that does not exist, or a path in use that may
        not be replaced.
    """
    target = Path(path)
    if str(path) == "":
        raise ParameterError("out", str(path), "a path for the store", "the path is empty")
    check_path_name(target, "out")
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise ParameterError("out", str(path), "a path in an existing directory")
    if not os.path.lexists(target):
        return target
    if not (overwrite or resume):
        raise ParameterError(
            "out", str(path), "a path that does not exist yet", "use --resume or --overwrite"
        )
    if not is_sweep_store(target):
        what = "a directory" if target.is_dir() else "a file"
        raise ParameterError(
            "out",
            str(path),
            "a new path, or an existing celtstone sweep store",
            f"it is {what} but not a celtstone sweep store; "
            + ("--overwrite" if overwrite else "--resume")
            + " never touches anything else",
        )
    if overwrite and not resume:
        check_replaceable(target, _COMMAND, inputs=inputs, zarr=True)
    return target


def _lock(target: Path) -> WriterLock:
    """Hold ``target`` against a second writer (see the module docstring)."""
    try:
        return WriterLock(target.with_name(f".{target.name}.lock"), target)
    except OSError as error:
        raise output_error(target, error) from error


@dataclass(frozen=True)
class Layout:
    """Dimensions, shape and block (chunk) shape of a sweep's arrays."""

    dims: tuple[str, ...]
    shape: tuple[int, ...]
    chunks: tuple[int, ...]

    @staticmethod
    def for_shape(dims: Sequence[str], shape: Sequence[int], target_points: int) -> Layout:
        """Blocks of about ``target_points`` points: trailing axes whole, one axis split."""
        chunks = [1] * len(shape)
        size = 1
        for d in range(len(shape) - 1, -1, -1):
            if size * shape[d] <= target_points:
                chunks[d] = shape[d]
                size *= shape[d]
            else:
                chunks[d] = max(1, target_points // size)
                break
        return Layout(tuple(dims), tuple(int(n) for n in shape), tuple(chunks))

    @property
    def size(self) -> int:
        """Number of points."""
        return int(np.prod(self.shape))

    def blocks(self) -> Iterator[tuple[int, int, tuple[slice, ...]]]:
        """(first flat index, end flat index, region) of every block, in C order."""
        grid = [math.ceil(n / c) for n, c in zip(self.shape, self.chunks, strict=True)]
        for block in np.ndindex(*grid):
            region = tuple(
                slice(b * c, min((b + 1) * c, n))
                for b, c, n in zip(block, self.chunks, self.shape, strict=True)
            )
            starts = tuple(s.start for s in region)
            first = int(np.ravel_multi_index(starts, self.shape)) if self.shape else 0
            count = int(np.prod([s.stop - s.start for s in region]))
            yield first, first + count, region


def _encode_results(results: Mapping[str, np.ndarray], shape: tuple[int, ...]) -> dict:
    out = {}
    for name, (dtype, _, _, _) in RESULT_FIELDS.items():
        values = np.asarray(results[name])
        out[name] = values.astype(str if dtype == "str" else dtype).reshape(shape)
    return out


def _array(group: zarr.Group, name: str) -> zarr.Array:
    import zarr

    array = group[name]
    if not isinstance(array, zarr.Array):
        raise CeltstoneError(f"{name} in the sweep store is not an array")
    return array


def _build(
    directory: Path,
    layout: Layout,
    coords: Mapping[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]],
    attrs: Mapping[str, Any],
) -> None:
    """The empty store's arrays and attributes in ``directory``."""
    import zarr

    group = zarr.open_group(directory, mode="w", zarr_format=3)
    for name, (dims, values, var_attrs) in coords.items():
        array = group.create_array(
            name,
            shape=values.shape,
            chunks=values.shape,
            dtype=values.dtype,
            dimension_names=dims,
            attributes=dict(var_attrs),
        )
        array[...] = values
    for name, (dtype, fill, _, _) in RESULT_FIELDS.items():
        attributes: dict[str, Any] = dict(OUTCOMES[name].variable.attributes)  # units, long name
        group.create_array(
            name,
            shape=layout.shape,
            chunks=layout.chunks,
            dtype=str if dtype == "str" else dtype,
            fill_value=fill,
            dimension_names=layout.dims,
            attributes=attributes,
        )
    group.create_array(
        MASK,
        shape=layout.shape,
        chunks=layout.chunks,
        dtype=bool,
        fill_value=False,
        dimension_names=layout.dims,
        attributes={"long_name": "whether the point has been computed and written"},
    )
    group.attrs.update({**attrs, "format": FORMAT, "complete": False})


class SweepStore(LockedOutput):
    """An open sweep store (see the module docstring)."""

    def __init__(
        self, path: Path, group: zarr.Group, layout: Layout, lock: WriterLock | None = None
    ) -> None:
        self.path = path
        self.group = group
        self.layout = layout
        self._lock = lock

    @classmethod
    def create(
        cls,
        path: str | Path,
        layout: Layout,
        coords: Mapping[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]],
        attrs: Mapping[str, Any],
        *,
        overwrite: bool = False,
        inputs: Iterable[str | Path] = (),
    ) -> SweepStore:
        """Build the empty store in a temporary directory and move it to ``path``.

        With ``overwrite`` an existing celtstone sweep store at ``path`` that holds only
        its own files is replaced; anything else there is refused
        (:func:`check_store_target`). The store returned is locked until
        :meth:`close`.

        Raises
        ------
        ParameterError
            naming ``out`` (see :func:`check_store_target`), or another process is
            writing the store.
        OutputError
            if the store cannot be written (disk full, ...): nothing is left behind.
        """
        target = check_store_target(path, overwrite=overwrite, inputs=inputs)
        lock = _lock(target)
        try:
            check_store_target(target, overwrite=overwrite, inputs=inputs)  # now it is held
            with temporary_directory(target) as temporary:
                try:
                    _build(temporary, layout, coords, attrs)
                except OSError as error:
                    raise output_error(target, error) from error
                if os.path.lexists(target):  # it may have changed since the check
                    check_store_target(target, overwrite=overwrite, inputs=inputs)
                replace_directory(temporary, target)
            return cls.open(target, expected_spec=attrs["sweep_spec"], lock=lock)
        except BaseException:
            lock.release()
            raise

    @classmethod
    def open(
        cls,
        path: str | Path,
        expected_spec: str | None = None,
        *,
        lock: bool | WriterLock = False,
    ) -> SweepStore:
        """Open an existing store for writing; ``expected_spec`` must equal its spec.

        With ``lock`` (True, or a lock already held) no other process may write it
        until :meth:`close`.
        """
        target = Path(path)
        held = _lock(target) if lock is True else lock or None
        try:
            return cls._open(target, path, expected_spec, held)
        except BaseException:
            if held is not None:
                held.release()
            raise

    @classmethod
    def _open(
        cls,
        target: Path,
        path: str | Path,
        expected_spec: str | None,
        lock: WriterLock | None,
    ) -> SweepStore:
        import zarr

        if not is_sweep_store(target):  # never opened for writing unless it is ours
            what = "does not exist" if not os.path.lexists(target) else "is not one"
            raise ParameterError("out", str(path), "a celtstone sweep store", f"it {what}")
        try:
            group = zarr.open_group(target, mode="r+", zarr_format=3)
            attrs = dict(group.attrs)
            mask = _array(group, MASK)
        except (OSError, KeyError, ValueError, zarr.errors.BaseZarrError) as error:
            raise ParameterError(
                "out", str(path), "a celtstone sweep store", f"cannot read it: {error}"
            ) from None
        if attrs.get("format") != FORMAT:
            raise ParameterError("out", str(path), "a celtstone sweep store")
        if expected_spec is not None and attrs.get("sweep_spec") != expected_spec:
            stored = json.loads(str(attrs.get("sweep_spec", "{}")))
            wanted = json.loads(expected_spec)
            differ = sorted(k for k in set(stored) | set(wanted) if stored.get(k) != wanted.get(k))
            raise ParameterError(
                "resume",
                str(path),
                "the store of the same sweep",
                "these settings differ from the stored ones: " + ", ".join(differ),
            )
        # a store written before an outcome was renamed or added reads (``open_sweep``), but
        # a resume could not write its new points
        missing = [name for name in RESULT_FIELDS if name not in group]
        if expected_spec is not None and missing:
            raise ParameterError(
                "resume",
                str(path),
                "a store with every result field of this version",
                f"it has no {', '.join(missing)}; start the sweep anew with --overwrite",
            )
        shape = tuple(int(n) for n in mask.shape)
        chunks = tuple(int(c) for c in mask.chunks)
        dims = tuple(str(d) for d in getattr(mask.metadata, "dimension_names", None) or ())
        layout = Layout(dims, shape, chunks)
        return cls(target, group, layout, lock)

    @property
    def complete(self) -> bool:
        """Whether every block has been written and the store marked complete."""
        return bool(self.group.attrs.get("complete", False))

    def done_blocks(self) -> set[int]:
        """First flat indices of the blocks whose mask says they are written."""
        mask = np.asarray(_array(self.group, MASK)[...]).ravel()
        return {first for first, end, _ in self.layout.blocks() if mask[first:end].all()}

    def write_block(self, region: tuple[slice, ...], results: Mapping[str, np.ndarray]) -> None:
        """Write one block's results, then its mask."""
        shape = tuple(s.stop - s.start for s in region)
        try:
            for name, values in _encode_results(results, shape).items():
                _array(self.group, name)[region] = values
            _array(self.group, MASK)[region] = np.ones(shape, dtype=bool)
        except OSError as error:  # e.g. a full disk: the block stays unmarked, to resume
            raise output_error(self.path, error) from error

    def mark_complete(self) -> None:
        """Set ``complete`` once every block's mask is set."""
        mask = np.asarray(_array(self.group, MASK)[...])
        if not mask.all():
            raise CeltstoneError(f"{self.path}: {int((~mask).sum())} points are not written yet")
        try:
            self.group.attrs["complete"] = True
        except OSError as error:
            raise output_error(self.path, error) from error


def open_sweep(path: str | Path, *, allow_incomplete: bool = False) -> xr.Dataset:
    """Open a sweep store as an ``xarray.Dataset`` (loaded into memory).

    Parameters
    ----------
    path : str or pathlib.Path
        The Zarr store a :class:`Sweep` or ``celtstone sweep`` wrote.
    allow_incomplete : bool, optional
        Open a stopped sweep too: points not computed hold the fill values (NaN, -1,
        "").

    Returns
    -------
    xarray.Dataset
        The result fields on the sweep dimensions, with provenance attributes; a store
        written before the outcomes were renamed (``outcome.RENAMED_OUTCOMES``) reads
        with the names now.

    Raises
    ------
    CeltstoneError
        If the store is incomplete (a sweep that was stopped) and not
        ``allow_incomplete``.
    """
    import xarray as xr

    store = SweepStore.open(path)
    if not store.complete and not allow_incomplete:
        done = int(np.asarray(_array(store.group, MASK)[...]).sum())
        raise CeltstoneError(
            f"{path}: the sweep is incomplete ({done} of {store.layout.size} points written); "
            "finish it with `celtstone sweep ... --resume`"
        )
    with xr.open_zarr(path, consolidated=False, chunks=None) as dataset:
        loaded = dataset.load()
    # a store written before the outcomes' renames reads with their names now
    old = {o: n for o, n in RENAMED_OUTCOMES.items() if o in loaded and n not in loaded}
    loaded = loaded.rename(old)
    for name, (dtype, _, _, _) in RESULT_FIELDS.items():
        if dtype == "str" and name in loaded:  # numpy's StringDType as plain unicode, as in memory
            text = [str(v) for v in np.ravel(loaded[name].values)]
            loaded[name] = loaded[name].copy(
                data=np.array(text, dtype=str).reshape(loaded[name].shape)
            )
    extra = [name for name in loaded.data_vars if name not in RESULT_FIELDS and name != MASK]
    loaded = loaded.set_coords(extra)  # the parameters of a list of points
    if store.complete:
        loaded = loaded.drop_vars(MASK)
    return loaded
