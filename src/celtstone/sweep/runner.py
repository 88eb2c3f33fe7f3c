"""``Sweep``: a grid or list of points, run in batches on local threads or a Dask cluster.

The points are cut into blocks (one Zarr chunk each) and the blocks into small
tasks. A task is one call of the compiled batch driver ``solvers.batch.run_batch``:
no Python per step. Locally, tasks run on daemon threads of this process (the
compiled driver releases the GIL); with ``scheduler="tcp://HOST:PORT"`` they are
submitted to a ``dask.distributed`` cluster. Either way only this process writes the
store, a block at a time as its tasks come back.
"""

from __future__ import annotations

import json
import math
import os
import queue
import threading
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from celtstone import solvers
from celtstone.bodies import STORED_SHAPES, Body, load_body
from celtstone.errors import CeltstoneError, ParameterError
from celtstone.kernels.layout import Y_N, Y_OMEGA
from celtstone.simulation import schema
from celtstone.simulation.integrate import STICK_METHOD, method_names, version
from celtstone.simulation.models import MODELS, HybridModel
from celtstone.simulation.outcome import OUTCOMES
from celtstone.simulation.reversals import (
    REVERSAL_BAND_FLOOR,
    REVERSAL_BAND_FRACTION,
    reversal_bands,
)
from celtstone.solvers import batch
from celtstone.sweep import budget
from celtstone.sweep.devices import CudaPool, describe_gpu, resolve_device
from celtstone.sweep.spec import PARAMETERS, Axis, AxisSpec, PointBuilder, parse_axis_spec
from celtstone.sweep.store import FORMAT, RESULT_FIELDS, Layout, SweepStore, open_sweep

if TYPE_CHECKING:
    import xarray as xr


__all__ = [
    "DEFAULT_ATOL",
    "DEFAULT_CHUNK_POINTS",
    "DEFAULT_RTOL",
    "MAX_CHUNK_POINTS",
    "MAX_SAMPLES_PER_POINT",
    "MAX_WORKERS",
    "SAMPLES_PER_SECOND",
    "SCHEDULER_TIMEOUT_SECONDS",
    "Sweep",
    "check_run_options",
]

DEFAULT_RTOL = 1e-8  # sliding runs agree with rtol 1e-10 to about 1e-6 rad/s in the final spin
"""A sweep's default relative tolerance of the integrator."""
DEFAULT_ATOL = 1e-12
"""A sweep's default absolute tolerance of the integrator (units of each state component)."""
DEFAULT_CONTACT = "hybrid"  # of the sliding model: faster than "sliding", same results (§28)
SAMPLES_PER_SECOND = 200.0  # as simulate(): max tilt, normal force and the band are sampled
"""Samples per simulated second [1/s] at which a sweep reads each run's results."""
DEFAULT_CHUNK_POINTS = 256  # points per block (Zarr chunk)
DEFAULT_TASK_POINTS = 8  # points per compiled call
MAX_CHUNK_POINTS = 1_000_000  # a block is held in memory and is what an interruption loses
MAX_WORKERS = 1024  # local threads; beyond the number of cores they only share them
# each thread holds every sample of its current point: 16 floats, 128 MB at this bound
MAX_SAMPLES_PER_POINT = 1_000_000
SCHEDULER_TIMEOUT_SECONDS = 10.0  # to connect to a dask scheduler, before anything is created

Progress = Callable[[int, int], None]  # (points written now, failures among them)


AxesInput = Mapping[str, Iterable[float]] | Sequence[Axis | AxisSpec | str] | str | None


def _axes(value: AxesInput) -> tuple[Axis | AxisSpec, ...]:
    """Axes from a mapping name -> values, or a list of axes or of the CLI's
    ``NAME=START:STOP:COUNT`` / ``NAME=V1,V2,...`` texts."""
    if value is None:
        return ()
    if isinstance(value, Mapping):
        return tuple(Axis(str(name), tuple(values)) for name, values in value.items())
    items = [value] if isinstance(value, str) else list(value)
    axes: list[Axis | AxisSpec] = []
    for item in items:
        if isinstance(item, str):
            axes.append(parse_axis_spec(item))
        elif isinstance(item, Axis | AxisSpec):
            axes.append(item)
        else:
            raise ParameterError(
                "vary", item, "a mapping name -> values, or Axis objects or 'NAME=...' texts"
            )
    return tuple(axes)


def _count(axis: Axis | AxisSpec) -> int:
    return axis.count if isinstance(axis, AxisSpec) else len(axis.values)


def _made(axis: Axis | AxisSpec) -> Axis:
    return axis.axis() if isinstance(axis, AxisSpec) else axis


def _samples_per_second(value: float, t_end: float) -> float:
    """The sample density [1/s]: positive, finite, at most ``MAX_SAMPLES_PER_POINT``
    samples in ``t_end``."""
    allowed = "a number > 0 1/s"
    try:
        rate = float(value)
    except (TypeError, ValueError):
        raise ParameterError("samples_per_second", value, allowed) from None
    if not (math.isfinite(rate) and rate > 0.0):
        raise ParameterError("samples_per_second", value, allowed)
    if t_end * rate + 1 > MAX_SAMPLES_PER_POINT:
        raise ParameterError(
            "samples_per_second",
            value,
            f"at most {MAX_SAMPLES_PER_POINT} samples per point",
            f"t_end = {t_end:g} s gives {t_end * rate:.3g}; lower --samples-per-second or --t-end",
        )
    return rate


def _check_as(schema_name: str, name: str, value: float) -> float:
    """``schema.check`` of ``schema_name``, the error naming ``name`` as the user spells it."""
    try:
        return schema.check(schema_name, value)
    except ParameterError as error:
        raise ParameterError(name, value, error.allowed, error.hint) from None


class Sweep:
    """A parameter sweep: every combination of ``vary`` (a grid) or the rows of ``points``.

    The settings and the size (from the number of values alone, ``vary`` may hold
    unspaced :class:`AxisSpec`) are checked first, then every point is validated,
    before anything is computed; ``estimate`` holds the size and expected CPU time.

    Parameters
    ----------
    vary : dict of str to array_like, or sequence of Axis or AxisSpec, optional
        Name -> values, one grid axis each (dimension order as given).
    points : dict of str to array_like, optional
        Name -> values, all of one length: a list of points (dimension ``point``);
        give ``vary`` or ``points``, not both.
    body : Body, str or pathlib.Path, optional
        A body, a shipped body name or a TOML path.
    model : {"sliding", "rolling"}, optional
        The model of every point.
    fixed : dict of str to float or str, optional
        Name -> value held for every point; names as in ``spec.PARAMETERS``, and the
        options of ``spec.CHOICES`` (``friction_load``: "static" or "dynamic",
        ``friction_law``: "pade" or "exact", ``contact_pressure``: "hertz" or
        "uniform", ``contact``: "hybrid" (default), the stick–slip contact of the
        sliding model, whose ``capture_speed`` [m/s] can be fixed or varied, or
        "sliding", the regularised contact that always slides; docs/decisions.md §28:
        the stick–slip contact is the faster of the two for sweeps and agrees with it
        point for point).
    t_end : float, optional
        Duration of each run [s].
    method : str, optional
        Integrator (default: the model's, auto for sliding).
    stick_method : str, optional
        Integrator of the stick–slip contact's stick phases: default ``method`` when
        it is given, else dop853 (as ``simulate``).
    rtol, atol : float, optional
        Local error tolerances (default rtol 1e-8 for sweeps).
    samples_per_second : float, optional
        Density of the samples behind max tilt, the normal force and the hysteresis
        band [1/s].
    reversal_threshold : float, optional
        Half-width of the spin's hysteresis band [rad/s]; default
        ``analysis.reversal_bands``: 4 % of each point's initial |spin| (as
        ``celtstone reproduce``), at least 0.01 rad/s.
    max_steps : int, optional
        Step limit of each run.
    force : bool, optional
        Accept a sweep beyond ``budget.POINT_LIMIT`` points or
        ``budget.STORE_LIMIT_BYTES`` (never beyond ``budget.HARD_POINT_LIMIT``).
    progress : callable, optional
        Called with (objects built, objects to build) while the points are validated.
    device : {"cpu", "cuda", "auto"}, optional
        Where the points run: the CPU's threads (or ``run``'s scheduler), a CUDA GPU
        (one thread per point; the rolling model, and the sliding model with contact
        sliding, so far), or the GPU where it can run the sweep, else the CPU. "cuda"
        where it cannot is an error, never a quiet run on the CPU.
    """

    def __init__(
        self,
        vary: AxesInput = None,
        *,
        points: AxesInput = None,
        body: Body | str | Path = "kane_levinson_1982",
        model: str = "sliding",
        fixed: Mapping[str, float | str] | None = None,
        t_end: float = 10.0,
        method: str | None = None,
        stick_method: str | None = None,
        rtol: float = DEFAULT_RTOL,
        atol: float = DEFAULT_ATOL,
        samples_per_second: float = SAMPLES_PER_SECOND,
        reversal_threshold: float | None = None,
        max_steps: int = 20_000_000,
        force: bool = False,
        progress: Callable[[int, int], None] | None = None,
        device: str = "cpu",
    ) -> None:
        # settings first, then the size from the counts alone, then the points
        if model not in MODELS:
            raise ParameterError("model", model, "one of: " + ", ".join(MODELS))
        self.model_name = model
        self.t_end = schema.check("t_end", t_end)
        self.rtol = schema.check("rtol", rtol)
        self.atol = schema.check("atol", atol)
        self.max_steps = int(schema.check("max_steps", max_steps))
        self.samples_per_second = _samples_per_second(samples_per_second, self.t_end)
        self.reversal_threshold = (
            None
            if reversal_threshold is None
            else _check_as("reversal_band", "reversal_threshold", reversal_threshold)
        )
        self.fixed = dict(fixed or {})
        if model == "sliding":
            self.fixed.setdefault("contact", DEFAULT_CONTACT)
        grid, listed = _axes(vary), _axes(points)
        self.estimate = self._check_axes(grid, listed, force)
        self.axes = tuple(_made(axis) for axis in grid)
        self.point_axes = tuple(_made(axis) for axis in listed)
        for axis in self.axes:
            values, counts = np.unique(axis.values, return_counts=True)
            if counts.max() > 1:
                value, times = values[np.argmax(counts)], counts.max()
                raise ParameterError(
                    axis.name,
                    float(value),
                    "each value of a grid axis once",
                    f"it is {times} times",
                )
        self.base_body = body if isinstance(body, Body) else load_body(body)
        if not self.base_body.shape.stored:
            raise ParameterError(
                "body",
                self.base_body.name,
                f"a body whose shape is data ({', '.join(STORED_SHAPES)})",
                "a Python function's compiled callback lives in this process only; "
                "give the shape as an implicit polynomial to sweep it",
            )
        self.builder = PointBuilder(
            self.base_body, model, self.fixed, self._columns(), progress=progress, atol=self.atol
        )
        # as simulate's: the stick–slip contact's stick phases take stick_method, else
        # the method given, else dop853
        self.method, stick = method_names(self.builder.model, method, stick_method)
        self.is_hybrid = isinstance(self.builder.model, HybridModel)
        self.stick_method = stick if stick is not None else STICK_METHOD
        self.device = resolve_device(device, model, self.method, self.is_hybrid)
        count = max(2, round(self.t_end * self.samples_per_second) + 1)
        self.sample_times = np.linspace(0.0, self.t_end, count)

    def _check_axes(
        self,
        grid: tuple[Axis | AxisSpec, ...],
        listed: tuple[Axis | AxisSpec, ...],
        force: bool,
    ) -> budget.Estimate:
        """Names and counts of the axes, and the sweep's size within ``budget``."""
        if grid and listed:
            raise ParameterError("points", "given with vary", "either a grid or a list of points")
        names = [axis.name for axis in grid + listed]
        duplicates = sorted({n for n in names if names.count(n) > 1})
        if duplicates:
            raise ParameterError("vary", duplicates[0], "each parameter varied once")
        if listed:
            lengths = {_count(axis) for axis in listed}
            if len(lengths) != 1:
                raise ParameterError("points", sorted(lengths), "columns of one length")
            counts = {"points": lengths.pop()}
        else:
            counts = {axis.name: _count(axis) for axis in grid}
        return budget.check_size(counts, t_end=self.t_end, model=self.model_name, force=force)

    # ----------------------------------------------------------------- shape

    @property
    def dims(self) -> tuple[str, ...]:
        """Dimension names: the grid axes, or ``("point",)``."""
        if self.point_axes:
            return ("point",)
        return tuple(a.name for a in self.axes)

    @property
    def shape(self) -> tuple[int, ...]:
        """Number of values along each dimension."""
        if self.point_axes:
            return (len(self.point_axes[0].values),)
        return tuple(len(a.values) for a in self.axes)

    @property
    def size(self) -> int:
        """Number of points."""
        return int(np.prod(self.shape))

    def _columns(self) -> dict[str, np.ndarray]:
        if self.point_axes:
            return {a.name: np.array(a.values) for a in self.point_axes}
        if not self.axes:
            return {}
        grids = np.meshgrid(*[np.array(a.values) for a in self.axes], indexing="ij")
        return {a.name: g.ravel() for a, g in zip(self.axes, grids, strict=True)}

    def _coords(self) -> dict[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]]:
        coords: dict[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]] = {}
        for axis in self.axes + self.point_axes:
            parameter = PARAMETERS[axis.name]
            attrs = {"units": parameter.unit, "long_name": parameter.description}
            dim = "point" if self.point_axes else axis.name
            coords[axis.name] = ((dim,), np.array(axis.values), attrs)
        if self.point_axes:
            coords["point"] = (("point",), np.arange(self.size), {"long_name": "point index"})
        return coords

    # ----------------------------------------------------------------- provenance

    def spec(self, chunk_points: int = DEFAULT_CHUNK_POINTS) -> str:
        """Write everything that determines the results and the store layout as JSON.

        Parameters
        ----------
        chunk_points : int, optional
            Points per block of the store.

        Returns
        -------
        str
            Canonical JSON (sorted keys): a store is resumed only by the same spec.
        """
        body = self.base_body
        document = {
            "body": {
                "name": body.name,
                "mass": body.mass,
                "gravity": body.gravity,
                "inertia": [list(row) for row in body.inertia],
                "shape": body.shape.table(),  # the [shape] table that rebuilds it
            },
            "model": self.model_name,
            "fixed": {k: self.fixed[k] for k in sorted(self.fixed)},
            "vary": [[a.name, list(a.values)] for a in self.axes],
            "points": [[a.name, list(a.values)] for a in self.point_axes],
            "t_end": self.t_end,
            "method": self.method,
            "rtol": self.rtol,
            "atol": self.atol,
            "samples_per_second": self.samples_per_second,
            "reversal_threshold": self.reversal_threshold,
            # the spin's running mean over each body's rocking period (docs/decisions.md §8):
            # a store begun with the raw-spin definition is not resumed with this one
            "reversal_window": "rocking_period",
            "max_steps": self.max_steps,
            "chunk_points": int(chunk_points),
        }
        if self.is_hybrid:  # a key of its own, so that other sweeps' specs are unchanged
            document["stick_method"] = self.stick_method
        return json.dumps(document, sort_keys=True)

    def attrs(self, chunk_points: int = DEFAULT_CHUNK_POINTS) -> dict[str, Any]:
        """Give the provenance attributes of the result Dataset.

        Parameters
        ----------
        chunk_points : int, optional
            As :meth:`spec`, recorded with the spec.

        Returns
        -------
        dict of str to object
            Flat strings and numbers: body, model, fixed and varied names, tolerances,
            celtstone version.
        """
        body = self.base_body
        model = self.builder.model
        return {
            "title": f"celtstone {self.model_name} sweep of {body.name}",
            "software": "celtstone",
            "celtstone_version": version(),
            "body": body.name,
            "body_source": body.source,
            "body_mass": body.mass,
            "body_gravity": body.gravity,
            "body_inertia": str(np.array(body.inertia).tolist()),
            **body.shape.attributes(),
            **{f"model_{k}" if k != "model" else k: v for k, v in model.attributes().items()},
            "fixed_parameters": json.dumps(self.fixed, sort_keys=True),
            "initial_state_default": "omega = (0, 0, -5) rad/s, euler_angles = (0.5, 0.5) deg",
            "varied_parameters": json.dumps([a.name for a in self.axes + self.point_axes]),
            "t_end": self.t_end,
            "method": self.method,
            **({"stick_method": self.stick_method} if self.is_hybrid else {}),
            "rtol": self.rtol,
            "atol": self.atol,
            "samples_per_second": self.samples_per_second,
            "reversal_threshold": (
                "relative" if self.reversal_threshold is None else self.reversal_threshold
            ),
            "reversal_band_rule": self._band_rule(),
            "reversal_window_rule": "the spin's running mean over each point's "
            "Body.rocking_period [s] (celtstone.simulation.reversals)",
            "sweep_spec": self.spec(chunk_points),
            **({"device": describe_gpu()} if self.device == "cuda" else {}),
        }

    # ----------------------------------------------------------------- running

    def _bands(self, y0: np.ndarray) -> np.ndarray:
        """Each point's hysteresis band [rad/s] from its initial state ``y0`` (k, N_STATE)."""
        if self.reversal_threshold is not None:
            return np.full(y0.shape[0], self.reversal_threshold)
        spin = np.einsum("ij,ij->i", y0[:, Y_OMEGA : Y_OMEGA + 3], y0[:, Y_N : Y_N + 3])
        return reversal_bands(spin)

    def _band_rule(self) -> str:
        if self.reversal_threshold is not None:
            return f"|spin| <= {self.reversal_threshold} rad/s"
        return (
            f"|spin| <= max({REVERSAL_BAND_FRACTION} |initial spin|, {REVERSAL_BAND_FLOOR} rad/s)"
        )

    def run(
        self,
        out: str | Path | None = None,
        *,
        resume: bool = False,
        overwrite: bool = False,
        scheduler: str | None = None,
        workers: int | None = None,
        chunk_points: int = DEFAULT_CHUNK_POINTS,
        task_points: int = DEFAULT_TASK_POINTS,
        progress: Progress | None = None,
        on_start: Callable[[int, int], None] | None = None,
    ) -> xr.Dataset:
        """Compute every point (or, with ``resume``, every point not yet in ``out``).

        Every option is checked and the scheduler connected (within
        ``SCHEDULER_TIMEOUT_SECONDS``) before the store is created: a refused run
        leaves nothing at ``out``. Ctrl-C (KeyboardInterrupt) stops after the blocks
        already written; the store can then be resumed.

        Parameters
        ----------
        out : str or pathlib.Path, optional
            Zarr store to write block by block; None keeps the results in memory.
        resume : bool, optional
            Continue the store ``out`` of the same sweep.
        overwrite : bool, optional
            Replace an existing ``out``.
        scheduler : str, optional
            Address of a dask.distributed scheduler ("tcp://HOST:PORT"); None runs on
            threads of this process.
        workers : int, optional
            Number of local threads, 1 to ``MAX_WORKERS`` (default: every core); not
            with ``scheduler``.
        chunk_points : int, optional
            Points per block, the unit of writing and resuming, 1 to
            ``MAX_CHUNK_POINTS``.
        task_points : int, optional
            Points per compiled call.
        progress : callable, optional
            Called with (points written, failures among them) after each block.
        on_start : callable, optional
            Called once with (points already done, points in all).

        Returns
        -------
        xarray.Dataset
            Result fields on the sweep dimensions, with provenance attributes.
        """
        # every option is checked, and a cluster connected, before a store is created
        chunk_points, threads = check_run_options(scheduler, workers, chunk_points)
        task_points = _whole("task_points", task_points, MAX_CHUNK_POINTS)
        if self.device == "cuda":
            _check_gpu_options(scheduler, workers)
            task_points = chunk_points  # a task is a block; a launch gathers many
        if resume and out is None:
            raise ParameterError("resume", True, "a store to resume (out)")
        layout = Layout.for_shape(self.dims, self.shape, chunk_points)
        attrs = self.attrs(chunk_points)
        target = None if out is None else Path(out)
        store: SweepStore | None = None
        if target is not None and resume and target.exists():
            store = SweepStore.open(target, expected_spec=attrs["sweep_spec"], lock=True)
        pool: _Pool | CudaPool
        if self.device == "cuda":
            pool = CudaPool(len(self.sample_times), task_points)
        elif scheduler is not None:
            pool = _DaskPool(scheduler)
        else:
            pool = _ThreadPool(threads)
        try:
            if target is not None and store is None:
                store = SweepStore.create(
                    target, layout, self._coords(), attrs, overwrite=overwrite
                )
            memory = {} if store is not None else _empty_results(layout.size)
            done = store.done_blocks() if store is not None else set()
            blocks = [b for b in layout.blocks() if b[0] not in done]
            if on_start is not None:
                on_start(layout.size - sum(end - first for first, end, _ in blocks), layout.size)

            def write(first: int, end: int, region: tuple[slice, ...], raw: np.ndarray) -> None:
                fields = _fields(raw)
                if store is not None:
                    store.write_block(region, fields)
                else:
                    for name, values in fields.items():
                        memory[name][first:end] = values
                if progress is not None:
                    progress(end - first, int(np.sum(fields["status"] != "success")))

            self._execute(blocks, task_points, pool, write)
            if store is not None:
                store.mark_complete()
        finally:
            pool.close()
            if store is not None:
                store.close()  # another process may write it now
        if store is not None:
            return open_sweep(store.path)
        return self._dataset(layout, memory, attrs)

    def _execute(
        self,
        blocks: list[tuple[int, int, tuple[slice, ...]]],
        task_points: int,
        pool: _Pool | CudaPool,
        write: Callable[[int, int, tuple[slice, ...], np.ndarray], None],
    ) -> None:
        tasks = [
            (block, start, min(start + task_points, end))
            for block, (first, end, _) in enumerate(blocks)
            for start in range(first, end, task_points)
        ]
        pending = {b: end - first for b, (first, end, _) in enumerate(blocks)}
        buffers: dict[int, np.ndarray] = {}
        settings = {
            "rtol": self.rtol,
            "atol": self.atol,
            "sample_times": self.sample_times,
            "max_steps": self.max_steps,
            "stick_method_name": self.stick_method,
        }
        model_code = self.builder.model.code
        next_task = 0
        in_flight = 0
        limit = 4 * pool.slots
        while next_task < len(tasks) or in_flight:
            while next_task < len(tasks) and in_flight < limit:
                block, start, stop = tasks[next_task]
                params, y0 = self.builder.arrays(range(start, stop))
                bands = self._bands(y0)
                captures = self.builder.capture_speeds(range(start, stop))
                pool.submit(
                    next_task,
                    model_code,
                    self.method,
                    params,
                    y0,
                    self.t_end,
                    reversal_bands=bands,
                    reversal_windows=self.builder.rocking_periods(range(start, stop)),
                    capture_speeds=captures if self.is_hybrid else None,
                    **settings,
                )
                next_task += 1
                in_flight += 1
            key, raw = pool.next_done()
            in_flight -= 1
            block, start, stop = tasks[key]
            first, end, region = blocks[block]
            buffer = buffers.setdefault(block, np.empty((end - first, batch.N_FIELDS)))
            buffer[start - first : stop - first] = raw
            pending[block] -= stop - start
            if pending[block] == 0:
                write(first, end, region, buffers.pop(block))

    def _dataset(
        self, layout: Layout, memory: Mapping[str, np.ndarray], attrs: Mapping[str, Any]
    ) -> xr.Dataset:
        import xarray as xr

        variables = {}
        for name, (dtype, _, _, _) in RESULT_FIELDS.items():
            values = memory[name].reshape(layout.shape)
            if dtype == "str":
                values = values.astype(str)
            attributes = OUTCOMES[name].variable.attributes
            variables[name] = xr.Variable(layout.dims, values, attrs=attributes)
        coords = {
            name: xr.Variable(dims, values, attrs=a)
            for name, (dims, values, a) in self._coords().items()
        }
        return xr.Dataset(
            variables, coords=coords, attrs={**attrs, "format": FORMAT, "complete": True}
        )


def _whole(name: str, value: object, largest: int) -> int:
    """``value`` as a whole number from 1 to ``largest``."""
    allowed = f"a whole number from 1 to {largest}"
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise ParameterError(name, value, allowed)
    if not (math.isfinite(value) and value == int(value) and 1 <= value <= largest):
        raise ParameterError(name, value, allowed)
    return int(value)


def check_run_options(
    scheduler: str | None, workers: int | None, chunk_points: int = DEFAULT_CHUNK_POINTS
) -> tuple[int, int]:
    """Check the options of :meth:`Sweep.run` that need no sweep; return the points per
    block and the number of local threads (0 with a scheduler, whose workers run the
    points). Nothing is connected or created.

    Raises
    ------
    ParameterError
        for ``workers`` outside 1..``MAX_WORKERS`` or given with a scheduler, and
        ``chunk_points`` outside 1..``MAX_CHUNK_POINTS``.
    """
    return _whole("chunk_points", chunk_points, MAX_CHUNK_POINTS), _threads(scheduler, workers)


def _check_gpu_options(scheduler: str | None, workers: int | None) -> None:
    """A sweep on the GPU takes neither a scheduler nor local threads."""
    if scheduler is not None:
        raise ParameterError(
            "scheduler", scheduler, "no value with device cuda", "the GPU runs every point"
        )
    if workers is not None:
        raise ParameterError(
            "workers", workers, "no value with device cuda", "the GPU runs every point"
        )


def _threads(scheduler: str | None, workers: int | None) -> int:
    """Local threads to run on: ``workers``, or every core; none with a scheduler."""
    if scheduler is not None:
        if workers is not None:
            raise ParameterError(
                "workers",
                workers,
                "no value with --scheduler",
                "the cluster's workers run the points; --workers sets local threads",
            )
        if not isinstance(scheduler, str) or not scheduler.strip():
            raise ParameterError("scheduler", scheduler, "an address tcp://HOST:PORT")
        return 0
    if workers is None:
        return min(_cores(), MAX_WORKERS)
    return _whole("workers", workers, MAX_WORKERS)


def _empty_results(size: int) -> dict[str, np.ndarray]:
    """Every result field of ``size`` points, holding its fill value."""
    return {
        name: np.full(size, fill, dtype=object if dtype == "str" else dtype)
        for name, (dtype, fill, _, _) in RESULT_FIELDS.items()
    }


def _fields(raw: np.ndarray) -> dict[str, np.ndarray]:
    """Result fields by name (``batch.RESULT_FIELDS``) from the batch driver's columns:
    numbers as their stored type; ``status`` as its label and ``message`` as the run's
    stop message (``solvers.Status``), from the status code and ``t_stop``."""
    codes = raw[:, batch.COLUMN.status].astype(int)
    t_stop = raw[:, batch.COLUMN.t_stop]
    text = {
        "status": np.array([solvers.status_label(c) for c in codes], dtype=object),
        "message": np.array(
            [solvers.stop_message(c, t) for c, t in zip(codes, t_stop, strict=True)],
            dtype=object,
        ),
    }
    return {
        field.name: text[field.name]
        if field.dtype == "str"
        else raw[:, field.column].astype(field.dtype, copy=False)
        for field in batch.RESULT_FIELDS
    }


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


class _Pool:
    """Runs ``batch.run_batch`` calls; ``next_done`` returns (key, result) as they finish."""

    slots = 1

    def submit(self, key: int, *args: Any, **kwargs: Any) -> None:
        raise NotImplementedError

    def next_done(self) -> tuple[int, np.ndarray]:
        raise NotImplementedError

    def close(self) -> None:
        raise NotImplementedError


class _ThreadPool(_Pool):
    """Daemon threads of this process: Ctrl-C returns at once, abandoning running tasks."""

    def __init__(self, threads: int) -> None:
        if threads < 1:
            raise ParameterError("workers", threads, "a whole number >= 1")
        self.slots = threads
        self._tasks: queue.Queue[tuple[int, tuple, dict] | None] = queue.Queue()
        self._done: queue.Queue[tuple[int, np.ndarray | BaseException]] = queue.Queue()
        self._threads: list[threading.Thread] = []
        for k in range(threads):
            thread = threading.Thread(target=self._work, name=f"celtstone-sweep-{k}", daemon=True)
            try:
                thread.start()
            except RuntimeError as error:  # the system's thread limit
                self.close()
                raise ParameterError(
                    "workers", threads, f"at most {k} threads on this system", str(error)
                ) from None
            self._threads.append(thread)

    def _work(self) -> None:
        while True:
            task = self._tasks.get()
            if task is None:
                return
            key, args, kwargs = task
            try:
                self._done.put((key, batch.run_batch(*args, **kwargs)))
            except BaseException as error:  # handed to the main thread
                self._done.put((key, error))

    def submit(self, key: int, *args: Any, **kwargs: Any) -> None:
        self._tasks.put((key, args, kwargs))

    def next_done(self) -> tuple[int, np.ndarray]:
        while True:
            try:
                key, result = self._done.get(timeout=0.1)  # wakes up for Ctrl-C
            except queue.Empty:
                continue
            if isinstance(result, BaseException):
                raise result
            return key, result

    def close(self) -> None:
        while True:
            try:
                self._tasks.get_nowait()
            except queue.Empty:
                break
        for _ in self._threads:
            self._tasks.put(None)


class _DaskPool(_Pool):
    """Tasks submitted to a dask.distributed scheduler; this process writes the results."""

    def __init__(self, address: str) -> None:
        try:
            from distributed import Client, as_completed
        except ImportError as error:  # pragma: no cover - pinned dependency
            raise CeltstoneError(f"dask.distributed is not installed: {error}") from None
        try:
            self._client = Client(address, timeout=f"{SCHEDULER_TIMEOUT_SECONDS:g}s")
        except (OSError, TimeoutError, ValueError, TypeError) as error:
            raise ParameterError(
                "scheduler",
                address,
                "the address tcp://HOST:PORT of a running dask scheduler, "
                f"answering within {SCHEDULER_TIMEOUT_SECONDS:g} s",
                str(error),
            ) from None
        self.slots = max(1, sum(self._client.nthreads().values()))
        self._completed = as_completed()
        self._keys: dict[Any, int] = {}

    def submit(self, key: int, *args: Any, **kwargs: Any) -> None:
        future = self._client.submit(batch.run_batch, *args, pure=False, **kwargs)
        self._keys[future.key] = key
        self._completed.add(future)

    def next_done(self) -> tuple[int, np.ndarray]:
        future = next(self._completed)
        key = self._keys.pop(future.key)
        return key, future.result()

    def close(self) -> None:
        for future in list(self._completed.futures):
            future.cancel()
        self._client.close()
