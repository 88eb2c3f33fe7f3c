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
"""

from __future__ import annotations

import json
import math
import os
import shutil
import tempfile
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
import zarr

from celtstone.errors import CeltstoneError, ParameterError

__all__ = ["RESULT_FIELDS", "Layout", "SweepStore", "open_sweep"]

# name: (dtype, fill value, unit, long name)
RESULT_FIELDS: dict[str, tuple[str, Any, str, str]] = {
    "first_reversal_time": (
        "float64",
        math.nan,
        "s",
        "first reversal of the sense of spin (hysteresis band), NaN if none",
    ),
    "n_reversals": ("int32", -1, "1", "number of spin reversals (hysteresis band)"),
    "final_spin": ("float64", math.nan, "rad/s", "spin omega . n at t_end, NaN if stopped early"),
    "energy_lost": ("float64", math.nan, "J", "E(0) - E(t_end), NaN if stopped early"),
    "max_tilt": ("float64", math.nan, "rad", "largest angle between the vertical and axis 3"),
    "min_normal_force": ("float64", math.nan, "N", "smallest normal force (0 at lift-off)"),
    "t_stop": ("float64", math.nan, "s", "time the run stopped"),
    "status": ("str", "", "", "success, or why the run stopped early"),
    "message": ("str", "", "", "what happened and what to change"),
}
MASK = "completed"
FORMAT = "celtstone-sweep-1"


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
    array = group[name]
    if not isinstance(array, zarr.Array):
        raise CeltstoneError(f"{name} in the sweep store is not an array")
    return array


class SweepStore:
    """An open sweep store (see the module docstring)."""

    def __init__(self, path: Path, group: zarr.Group, layout: Layout) -> None:
        self.path = path
        self.group = group
        self.layout = layout

    @classmethod
    def create(
        cls,
        path: str | Path,
        layout: Layout,
        coords: Mapping[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]],
        attrs: Mapping[str, Any],
        *,
        overwrite: bool = False,
    ) -> SweepStore:
        """Build the empty store in a temporary directory and move it to ``path``."""
        target = Path(path)
        parent = target.parent if str(target.parent) else Path(".")
        if not parent.is_dir():
            raise ParameterError("out", str(path), "a path in an existing directory")
        if target.exists() and not overwrite:
            raise ParameterError(
                "out", str(path), "a path that does not exist yet", "use --resume or --overwrite"
            )
        temporary = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".part", dir=parent))
        try:
            group = zarr.open_group(temporary, mode="w", zarr_format=3)
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
            for name, (dtype, fill, unit, long_name) in RESULT_FIELDS.items():
                group.create_array(
                    name,
                    shape=layout.shape,
                    chunks=layout.chunks,
                    dtype=str if dtype == "str" else dtype,
                    fill_value=fill,
                    dimension_names=layout.dims,
                    attributes={"units": unit, "long_name": long_name}
                    if unit
                    else {"long_name": long_name},
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
            if target.exists():
                shutil.rmtree(target)
            os.rename(temporary, target)
        finally:
            shutil.rmtree(temporary, ignore_errors=True)
        return cls.open(target, expected_spec=attrs["sweep_spec"])

    @classmethod
    def open(cls, path: str | Path, expected_spec: str | None = None) -> SweepStore:
        """Open an existing store for writing; ``expected_spec`` must equal its spec."""
        target = Path(path)
        try:
            group = zarr.open_group(target, mode="r+", zarr_format=3)
            attrs = dict(group.attrs)
            mask = _array(group, MASK)
        except (FileNotFoundError, KeyError, ValueError, zarr.errors.BaseZarrError) as error:
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
        shape = tuple(int(n) for n in mask.shape)
        chunks = tuple(int(c) for c in mask.chunks)
        dims = tuple(str(d) for d in getattr(mask.metadata, "dimension_names", None) or ())
        layout = Layout(dims, shape, chunks)
        return cls(target, group, layout)

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
        for name, values in _encode_results(results, shape).items():
            _array(self.group, name)[region] = values
        _array(self.group, MASK)[region] = np.ones(shape, dtype=bool)

    def mark_complete(self) -> None:
        """Set ``complete`` once every block's mask is set."""
        mask = np.asarray(_array(self.group, MASK)[...])
        if not mask.all():
            raise CeltstoneError(f"{self.path}: {int((~mask).sum())} points are not written yet")
        self.group.attrs["complete"] = True


def open_sweep(path: str | Path, *, allow_incomplete: bool = False) -> xr.Dataset:
    """Open a sweep store as an ``xarray.Dataset`` (loaded into memory).

    Raises
    ------
    CeltstoneError
        if the store is incomplete (a sweep that was stopped) unless
        ``allow_incomplete``: then points not computed hold the fill values (NaN, -1, "").
    """
    store = SweepStore.open(path)
    if not store.complete and not allow_incomplete:
        done = int(np.asarray(_array(store.group, MASK)[...]).sum())
        raise CeltstoneError(
            f"{path}: the sweep is incomplete ({done} of {store.layout.size} points written); "
            "finish it with `celtstone sweep ... --resume`"
        )
    with xr.open_zarr(path, consolidated=False, chunks=None) as dataset:
        loaded = dataset.load()
    for name, (dtype, _, _, _) in RESULT_FIELDS.items():
        if dtype == "str":  # numpy's StringDType as plain unicode, as in memory
            text = [str(v) for v in np.ravel(loaded[name].values)]
            loaded[name] = loaded[name].copy(
                data=np.array(text, dtype=str).reshape(loaded[name].shape)
            )
    extra = [name for name in loaded.data_vars if name not in RESULT_FIELDS and name != MASK]
    loaded = loaded.set_coords(extra)  # the parameters of a list of points
    if store.complete:
        loaded = loaded.drop_vars(MASK)
    return loaded
