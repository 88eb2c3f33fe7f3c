"""The one entry point: ``simulate(model, body, initial_state, t_end, ...)``."""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from celtstone import solvers
from celtstone._about import version as version
from celtstone.bodies import Body
from celtstone.errors import (
    CeltstoneError,
    CeltstoneWarning,
    FrictionBoundWarning,
    ParameterError,
    PlausibilityWarning,
    require_choice,
)
from celtstone.kernels import layout
from celtstone.simulation import plausibility, schema
from celtstone.simulation.models import (
    HybridModel,
    Model,
    RollingModel,
    SlidingModel,
    contact_settings,
    initial_vector,
    kernel_parameters,
)
from celtstone.simulation.models import InitialState as InitialState
from celtstone.simulation.trajectory import RunEnding, Trajectory, sample_run
from celtstone.solvers.devices import DEVICES, resolve_device

__all__ = [
    "DEFAULT_ATOL",
    "DEFAULT_RTOL",
    "SAMPLES_PER_SECOND",
    "STATUS_NAMES",
    "simulate",
    "simulate_many",
    "version",
]

DEFAULT_RTOL = 1e-10
DEFAULT_ATOL = 1e-12
SAMPLES_PER_SECOND = 200  # default output density [1/s]

# solver status code -> its label in results and the CLI (``solvers.Status``)
STATUS_NAMES = {int(status): status.label for status in solvers.Status}


def method_names(
    model: Model, method: str | None, stick_method: str | None = None
) -> tuple[str, str | None]:
    """The integrators of a run of ``model``: (its method, that of its stick phases).

    ``method`` defaults to the model's ``default_method``. The stick phases of the
    stick–slip contact take ``stick_method``, else ``method`` when one is given, else
    DOP853 (they roll, which is not stiff); the other models have none (None), and
    ``stick_method`` given for them is refused.
    """
    name = model.default_method if method is None else method
    require_choice("method", name, solvers.METHODS)
    if not isinstance(model, HybridModel):
        if stick_method is not None:
            raise ParameterError(
                "stick_method",
                stick_method,
                "none for this model",
                "only the stick–slip contact has stick phases: --contact hybrid in run, "
                "contact=hybrid in a sweep, HybridModel in Python",
            )
        return str(name), None
    stick = stick_method if stick_method is not None else method
    stick = STICK_METHOD if stick is None else stick
    require_choice("stick_method", stick, solvers.METHODS)
    return str(name), str(stick)


STICK_METHOD = "dop853"  # the stick phases' default: rolling without sliding is not stiff


def method_words() -> dict[str, str]:
    """The integrators a run may name, with their words for help texts, read from the
    method registry (``solvers.METHOD_ENTRIES``) when asked."""
    return {name: method.words for name, method in solvers.METHOD_ENTRIES.items()}


def _sample_times(t_end: float, n_samples: int | None, sample_times: object) -> np.ndarray:
    if sample_times is not None:
        allowed = "a 1-D array of finite times in s"
        if isinstance(sample_times, str | bytes):
            raise ParameterError("sample_times", sample_times, allowed)
        try:
            given = np.asarray(sample_times)
        except ValueError:  # ragged nested lists
            raise ParameterError("sample_times", sample_times, allowed) from None
        if given.dtype.kind not in ("i", "u", "f"):  # booleans, text, None are not times
            raise ParameterError("sample_times", sample_times, allowed)
        times = given.astype(float)
        if times.ndim != 1 or times.size < 1 or not np.all(np.isfinite(times)):
            raise ParameterError("sample_times", sample_times, allowed)
        if times[0] < 0.0 or times[-1] > t_end or np.any(np.diff(times) <= 0.0):
            raise ParameterError(
                "sample_times", sample_times, f"increasing times in [0, {t_end:g}] s"
            )
        return times
    if n_samples is not None:
        return np.linspace(0.0, t_end, schema.check_count("n_samples", n_samples))
    count = max(201, round(t_end * SAMPLES_PER_SECOND) + 1)
    if count > schema.MAX_SAMPLES:
        count = schema.MAX_SAMPLES
        warnings.warn(
            f"t_end = {t_end:g} s at the default {SAMPLES_PER_SECOND} samples/s would need "
            f"{round(t_end * SAMPLES_PER_SECOND) + 1:.3g} samples; sampling {count} "
            f"({(count - 1) / t_end:.3g} per s, the most) instead: set n_samples to choose",
            CeltstoneWarning,
            stacklevel=3,
        )
    return np.linspace(0.0, t_end, count)


# what each of simulate's three objects must be, and how to make one
_RUN_OBJECTS = (
    ("model", (RollingModel, SlidingModel), "a RollingModel, SlidingModel or HybridModel",
     "e.g. celtstone.model_from_name('sliding', friction_coefficient=0.3)"),
    ("body", (Body,), "a Body", "e.g. celtstone.load_body('kane_levinson_1982')"),
    ("initial_state", (InitialState,), "an InitialState",
     "e.g. celtstone.InitialState(omega=(0, 0, -5), euler_angles=(0.5, 0.5))"),
)  # fmt: skip


def _check_run_objects(model: object, body: object, initial_state: object) -> None:
    """The model, body and initial state are the validated objects, not names, classes
    or tuples: the numbers in them were checked when they were made."""
    for (name, kinds, allowed, hint), value in zip(
        _RUN_OBJECTS, (model, body, initial_state), strict=True
    ):
        if not isinstance(value, kinds):
            if isinstance(value, type) and issubclass(value, kinds):
                hint = f"an instance, e.g. {value.__name__}(), not the class"
            raise ParameterError(name, value, allowed, hint)


def _status_message(status: str, code: int, t_stop: float, final_n: np.ndarray) -> str:
    """``solvers.stop_message``; a non-convex stop also names the last sampled vertical."""
    detail = ""
    if code == solvers.STATUS_NON_CONVEX:
        detail = f" (last sampled vertical n = {np.round(final_n, 4).tolist()} in body axes)"
    return solvers.stop_message(code, t_stop, detail)


def simulate(
    model: Model,
    body: Body,
    initial_state: InitialState,
    t_end: float,
    *,
    method: str | None = None,
    stick_method: str | None = None,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    n_samples: int | None = None,
    sample_times: np.ndarray | None = None,
    max_steps: int = 20_000_000,
    max_crossings: int = 100_000,
    progress: Callable[[float], None] | None = None,
) -> Trajectory:
    """Integrate ``model`` for ``body`` from ``initial_state`` over [0, t_end].

    Parameters
    ----------
    model : RollingModel, SlidingModel or HybridModel
        The equations of motion: paper eq. (3)–(5), eq. (6)–(12), or stick–slip.
    body : Body
        The stone: mass, inertia and surface.
    initial_state : InitialState
        Angular velocity and attitude at t = 0; the contact starts without slip.
    t_end : float
        Duration [s], > 0.
    method : str, optional
        Integrator name from ``solvers.METHODS``: "vern9" (explicit, Verner's 9(8)
        pair), "dop853" (explicit), "radau5" (stiff) or "auto" (each step with DOP853 or
        Radau, whichever is cheaper, switched on the Jacobian's spectral radius;
        ``solvers._auto``). Default: vern9 for rolling, auto for sliding and the slip
        phases of the stick–slip contact.
    stick_method : str, optional
        Integrator of the stick–slip contact's stick phases (``HybridModel`` only):
        default ``method`` when it is given, else dop853.
    rtol, atol : float, optional
        Relative and absolute local error tolerances.
    n_samples : int, optional
        Number of equally spaced output samples (default 200 per second).
    sample_times : numpy.ndarray, optional
        Explicit output times [s], shape (k,), increasing, in [0, t_end].
    max_steps : int, optional
        Largest number of steps before the run stops.
    max_crossings : int, optional
        Largest number of spin zero crossings stored.
    progress : callable, optional
        Called about ten times a second with the time reached [s] while the compiled
        loop runs in another thread (a progress bar); None runs in this thread.

    Returns
    -------
    Trajectory
        Also when the run stopped early (lift-off, singular friction, integrator
        failure): ``status`` says why and the samples reach the stop time. Call
        ``raise_for_status()`` to turn that into an exception.
    """
    _check_run(model, body, initial_state)
    settings = _RunSettings.checked(t_end, rtol, atol, max_steps, max_crossings)
    if progress is not None and not callable(progress):
        raise ParameterError("progress", progress, "None or a function of the time reached [s]")
    methods = (method, stick_method)
    run = _prepared_run(model, body, initial_state, settings, methods, n_samples, sample_times)
    return _run_on_cpu(run, progress)


class _RunSettings(NamedTuple):
    """What every run of a ``simulate_many`` shares, checked: duration [s], tolerances,
    step and crossing limits (:func:`simulate`'s parameters of those names)."""

    t_end: float
    rtol: float
    atol: float
    max_steps: int
    max_crossings: int

    @classmethod
    def checked(
        cls, t_end: object, rtol: object, atol: object, max_steps: object, max_crossings: object
    ) -> _RunSettings:
        """The settings checked (``schema.check``), each raising ``ParameterError``."""
        return cls(
            schema.check("t_end", t_end),
            schema.check("rtol", rtol),
            schema.check("atol", atol),
            schema.check_count("max_steps", max_steps),
            schema.check_count("max_crossings", max_crossings),
        )


@dataclass(frozen=True)
class _PreparedRun:
    """A run checked and turned into what its loop takes (kernel parameter record,
    initial state vector, sample times) and what its ``Trajectory`` records: the one
    preparation of :func:`simulate` and :func:`simulate_many` on either device."""

    model: Model
    settings: _RunSettings
    params: np.record
    initial_vector: np.ndarray
    sample_times: np.ndarray
    concerns: list[plausibility.Concern]
    attrs: dict[str, Any]
    method: str
    stick_method: str | None  # the stick–slip contact's; None for the other models
    capture_speed: float  # v_c of the stick–slip contact [m/s]; 0 for the other models


def _prepared_run(
    model: Model,
    body: Body,
    initial_state: InitialState,
    settings: _RunSettings,
    methods: tuple[str | None, str | None],
    n_samples: int | None,
    sample_times: object,
) -> _PreparedRun:
    """What the loop of a run checked by :func:`_check_run` takes (``methods``: the
    method and the stick method as the user named them, or None); raises
    ``ParameterError`` for what cannot run."""
    method_name, stick_method_name = method_names(model, *methods)
    times = _sample_times(settings.t_end, n_samples, sample_times)
    params = kernel_parameters(model, body)
    y0 = initial_vector(initial_state)
    concerns = plausibility.concerns(body, contact_settings(model))
    attrs = _run_attributes(
        model, body, initial_state, settings.t_end, method_name, settings.rtol, settings.atol
    )
    capture_speed = 0.0
    if isinstance(model, HybridModel):
        capture_speed = model.resolved_capture_speed(settings.atol)
        attrs.update(capture_speed=capture_speed, stick_method=str(stick_method_name))
    return _PreparedRun(
        model,
        settings,
        params,
        y0,
        times,
        concerns,
        attrs,
        method_name,
        stick_method_name,
        capture_speed,
    )


def _check_run(model: object, body: object, initial_state: object) -> None:
    """The objects of a run (:func:`_check_run_objects`), and a rolling model's start
    without slip."""
    _check_run_objects(model, body, initial_state)
    if isinstance(model, RollingModel) and isinstance(initial_state, InitialState):
        if initial_state.is_sliding:
            raise ParameterError(
                "slip_velocity",
                initial_state.slip_velocity,
                "(0, 0) with the rolling model: its contact cannot slip",
                "use the model 'sliding' for a record that starts sliding",
            )


def _warn_concerns(concerns: list[plausibility.Concern], stacklevel: int) -> None:
    """Warn each plausibility concern of a run before it runs (``stacklevel`` as the
    caller would give ``warnings.warn``)."""
    for concern in concerns:
        warnings.warn(str(concern), PlausibilityWarning, stacklevel=stacklevel + 1)


def _run_on_cpu(run: _PreparedRun, progress: Callable[[float], None] | None = None) -> Trajectory:
    """``run`` on the CPU, warned before (its plausibility concerns) and after (the
    friction bound), the warnings pointing at the caller of :func:`simulate` (in
    :func:`simulate_many`, at the thread's call)."""
    _warn_concerns(run.concerns, stacklevel=3)
    trajectory = _trajectory(run, _solve(run, progress))
    _warn_friction_bound(trajectory, stacklevel=4)
    return trajectory


def _solve(
    run: _PreparedRun, progress: Callable[[float], None] | None = None
) -> solvers.RawSolution:
    """The run's compiled loop on the CPU: ``solvers.solve``, or ``solve_phases`` for the
    stick–slip contact."""
    settings = run.settings
    # what the run loop takes alike in one run and in a stick–slip run's phases
    loop_settings: dict[str, Any] = {
        "rtol": settings.rtol,
        "atol": settings.atol,
        "sample_times": run.sample_times,
        "max_crossings": settings.max_crossings,
        "max_steps": settings.max_steps,
        "progress": progress,
    }
    if run.stick_method is not None:
        return solvers.solve_phases(
            run.params,
            run.initial_vector,
            settings.t_end,
            slip_method=run.method,
            stick_method=run.stick_method,
            capture_speed=run.capture_speed,
            **loop_settings,
        )
    return solvers.solve(
        run.model.code, run.method, run.params, run.initial_vector, settings.t_end, **loop_settings
    )


def _trajectory(run: _PreparedRun, raw: solvers.RawSolution) -> Trajectory:
    """The ``Trajectory`` of ``run`` from what its loop returned (``solvers.solve``'s,
    ``solve_phases``' or a GPU thread's, ``batch_cuda.solve_runs``): one code for
    :func:`simulate` and :func:`simulate_many` on either device."""
    model, params, y0 = run.model, run.params, run.initial_vector
    attrs = dict(run.attrs)
    phase_data: dict[str, np.ndarray] = {}
    if isinstance(raw, solvers.RawPhases):
        attrs["rejected_captures"] = raw.rejected_captures
        phase_data = {
            "phase": raw.sample_phase,
            "phase_kind": raw.phase_kind.astype(np.int8),
            "phase_start": raw.phase_start,
            "phase_end": raw.phase_end,
            "phase_energy_jump": raw.phase_energy_jump,
        }
    code, t_stop, min_normal = raw.status, raw.t_stop, raw.min_normal_force
    n_crossings = raw.n_crossings_total
    sample_times_out, samples, crossings = raw.sample_times, raw.samples, raw.crossings
    statistics = {key: int(getattr(raw, key)) for key in solvers.STATISTICS}
    status = STATUS_NAMES.get(code, "failed")
    final_n = (samples if len(samples) else y0[None, :])[-1, layout.Y_N : layout.Y_N + 3]
    message = _status_message(status, code, t_stop, final_n)
    if status != "success" and run.concerns:
        names = ", ".join(dict.fromkeys(concern.parameter for concern in run.concerns))
        message += f"; look first at the implausible {names} (warned before the run)"
    attrs.update(status=status, message=message)
    run_samples = sample_run(
        model.code, params, sample_times_out, samples, crossings, attrs, **phase_data
    )
    return Trajectory(
        samples=run_samples,
        status=status,
        message=message,
        t_stop=t_stop,
        min_normal_force=min_normal,
        ending=RunEnding(model.code, params, y0, samples, int(code), int(n_crossings)),
        statistics=statistics,
    )


def _run_attributes(
    model: Model,
    body: Body,
    initial_state: InitialState,
    t_end: float,
    method_name: str,
    rtol: float,
    atol: float,
) -> dict[str, str | float | int]:
    """The attributes of a run's Dataset: software, body (and the table that rebuilds its
    shape), start, integrator and model settings; :func:`simulate` adds the outcome."""
    return {
        "title": f"celtstone {model.name} run of {body.name}",
        "software": "celtstone",
        "celtstone_version": version(),
        "body": body.name,
        "body_source": body.source,
        "body_notes": body.notes,
        "body_mass": body.mass,
        "body_gravity": body.gravity,
        "body_inertia": str(np.array(body.inertia).tolist()),
        **body.shape.attributes(),  # kind, numbers, and the table that rebuilds it
        "initial_omega": str(list(initial_state.omega)),
        "initial_euler_angles_deg": str(list(initial_state.euler_angles)),
        "initial_slip_velocity": str(list(initial_state.slip_velocity)),
        "t_end": t_end,
        "method": method_name,
        "rtol": rtol,
        "atol": atol,
        "reversal_window": body.rocking_period,  # s, the spin's rocking average
        **model.attributes(),
    }


def friction_bound_warning(trajectory: Trajectory) -> FrictionBoundWarning | None:
    """The ``FrictionBoundWarning`` of a static-load run whose friction exceeded f N for
    the true N (issue 13 item 6; ``Trajectory.max_friction_bound_ratio``), or None; its
    ``command_line`` attribute words the fix as a CLI option."""
    ratio = trajectory.max_friction_bound_ratio
    if trajectory.samples.attrs.get("friction_load") != "static" or ratio is None:
        return None
    if not ratio > 1.0:
        return None
    text = (
        f"the friction force reached {ratio:.3g} f N for the true normal force N, "
        f"{100.0 * (ratio - 1.0):.3g} % above Coulomb's bound: the friction law is "
        "loaded with m g (the paper's first approximation); use {} for the "
        "consistent load"
    )
    warning = FrictionBoundWarning(text.format('friction_load="dynamic"'))
    warning.command_line = text.format("--friction-load dynamic")
    return warning


def _warn_friction_bound(trajectory: Trajectory, stacklevel: int) -> None:
    """Warn :func:`friction_bound_warning`'s warning, if any, from :func:`simulate`
    (``stacklevel`` counted from here)."""
    warning = friction_bound_warning(trajectory)
    if warning is not None:
        warnings.warn(warning, stacklevel=stacklevel)


def simulate_many(
    runs: Sequence[tuple[Model, Body, InitialState]],
    t_end: float,
    *,
    device: str = "cpu",
    sample_times: np.ndarray | None = None,
    method: str | None = None,
    stick_method: str | None = None,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    n_samples: int | None = None,
    max_steps: int = 20_000_000,
    max_crossings: int = 100_000,
    workers: int | None = None,
    errors: str = "raise",
) -> list[Trajectory | CeltstoneError]:
    """:func:`simulate` of each of ``runs`` over [0, t_end], in order.

    Parameters
    ----------
    runs : sequence of (model, body, initial_state)
        The runs, their models of one kind (all rolling, all sliding or all stick–slip);
        each may have its own settings, body and start.
    t_end : float
        Duration of every run [s], > 0.
    device : str, default "cpu"
        "cpu": the runs on ``workers`` threads; "cuda": one GPU thread per run (the
        same loops compiled for CUDA, the same results), refused where no GPU can run
        them; "auto": the GPU where one can run them, else the CPU.
    sample_times : numpy.ndarray, optional
        Output times [s]: shape (m,), the same for every run, or (len(runs), m), each
        run's own.
    method, stick_method : str, optional
        Integrators, as :func:`simulate`'s, for every run.
    rtol, atol : float, optional
        Relative and absolute local error tolerances of every run.
    n_samples : int, optional
        Equally spaced output samples of every run (without ``sample_times``; default
        200 per second).
    max_steps, max_crossings : int, optional
        Largest number of steps, and of spin zero crossings stored, of each run.
    workers : int, optional
        Threads on the CPU (default: one per core).
    errors : str, default "raise"
        "raise": a run that cannot be made (a ``CeltstoneError``: an implausible body or
        contact, a bad setting of its own) raises; "keep": its error takes its place in
        the list, it is not run, and the other runs go on (a fit's batch of trial
        parameters). A setting of every run (``t_end``, ``method``, ``device``...) that
        is bad raises either way.

    Returns
    -------
    list of Trajectory (or CeltstoneError, with ``errors="keep"``)
        One per run, as :func:`simulate` returns it, warnings included.
    """
    require_choice("errors", errors, ("raise", "keep"))
    require_choice("device", device, DEVICES)
    runs = list(runs)
    models = _models_of_one_kind(runs)
    settings = _RunSettings.checked(t_end, rtol, atol, max_steps, max_crossings)
    methods = (method, stick_method)
    names = method_names(models[0], *methods) if models else (str(method), None)
    times = _batch_sample_times(settings.t_end, n_samples, sample_times, len(runs))
    on = "cpu"
    if models:
        model = models[0]
        is_hybrid = isinstance(model, HybridModel)
        on = resolve_device(device, model.name, names[0], is_hybrid)

    def prepared(index: int) -> _PreparedRun | CeltstoneError:
        model, body, state = runs[index]
        try:
            _check_run(model, body, state)
            run_times = times[index] if times.shape[0] > 1 else times[0]
            return _prepared_run(model, body, state, settings, methods, None, run_times)
        except CeltstoneError as error:
            if errors == "raise":
                raise
            return error

    if on == "cuda":
        return _simulate_on_gpu([prepared(index) for index in range(len(runs))])

    from celtstone._threads import map_in_threads

    def one(index: int) -> Trajectory | CeltstoneError:
        run = prepared(index)
        return run if isinstance(run, CeltstoneError) else _run_on_cpu(run)

    return list(map_in_threads(one, range(len(runs)), workers=workers))


def _models_of_one_kind(runs: list[Any]) -> list[Model]:
    """The models of ``runs``, checked to be of one kind (rolling, sliding without stick
    phases, or the stick–slip contact), and each run a (model, body, initial_state);
    a run's model that is no model at all is left to its own run's checks."""
    if not runs:
        raise ParameterError("runs", runs, "one (model, body, initial_state) or more")
    for run in runs:
        if not isinstance(run, tuple | list) or len(run) != 3:
            raise ParameterError("runs", run, "a (model, body, initial_state) for each run")
    models = [run[0] for run in runs if isinstance(run[0], RollingModel | SlidingModel)]
    kinds = dict.fromkeys(_kind(model) for model in models)
    if len(kinds) > 1:
        raise ParameterError(
            "runs",
            f"models of the kinds {', '.join(kinds)}",
            "models of one kind: all rolling, all sliding or all stick–slip",
            "run each kind in a simulate_many of its own",
        )
    return models


def _kind(model: Model) -> str:
    """The kind of ``model`` that a batch of runs shares: its name, or "stick–slip"."""
    return "stick–slip" if isinstance(model, HybridModel) else model.name


def _batch_sample_times(
    t_end: float, n_samples: int | None, sample_times: object, n_runs: int
) -> np.ndarray:
    """The sample times of a batch of ``n_runs`` runs, checked: shape (1, m), every
    run's, or (n_runs, m), each run's own (each row checked as :func:`simulate` checks
    its times, where its run is made)."""
    if sample_times is not None and not isinstance(sample_times, str | bytes):
        given = np.asarray(sample_times, dtype=object)
        if given.ndim == 2:
            if given.shape[0] != n_runs:
                raise ParameterError(
                    "sample_times",
                    f"an array of shape {given.shape}",
                    f"shape (m,) or ({n_runs}, m): a row of times for each run",
                )
            return np.asarray(sample_times)
        if given.ndim != 1:
            raise ParameterError(
                "sample_times",
                f"an array of shape {given.shape}",
                f"shape (m,) or ({n_runs}, m): the times of every run, or of each",
            )
    return _sample_times(t_end, n_samples, sample_times)[None, :]


def _simulate_on_gpu(
    runs: list[_PreparedRun | CeltstoneError],
) -> list[Trajectory | CeltstoneError]:
    """The prepared ``runs`` on the GPU, one thread each (``batch_cuda.solve_runs``),
    each warned as :func:`simulate` warns; an error stays in its place, not launched."""
    from celtstone.solvers import batch_cuda
    from celtstone.solvers.devices import announce_first_launch

    launched = [run for run in runs if isinstance(run, _PreparedRun)]
    for run in launched:
        _warn_concerns(run.concerns, stacklevel=3)
    raws: list[solvers.RawSolution] = []
    if launched:
        first = launched[0]
        times = np.stack([run.sample_times for run in launched])
        if np.all(times == times[0]):
            times = times[:1]
        settings = first.settings
        announce_first_launch("running a batch of runs")
        raws = batch_cuda.solve_runs(
            first.model.code,
            first.method,
            np.array([run.params for run in launched]),
            np.stack([run.initial_vector for run in launched]),
            settings.t_end,
            rtol=settings.rtol,
            atol=settings.atol,
            sample_times=times,
            max_crossings=settings.max_crossings,
            max_steps=settings.max_steps,
            capture_speeds=np.array([run.capture_speed for run in launched]),
            stick_method_name=first.stick_method or STICK_METHOD,
        )
    solved = iter(raws)
    results: list[Trajectory | CeltstoneError] = []
    for prepared in runs:
        if isinstance(prepared, CeltstoneError):
            results.append(prepared)
            continue
        trajectory = _trajectory(prepared, next(solved))
        _warn_friction_bound(trajectory, stacklevel=4)
        results.append(trajectory)
    return results
