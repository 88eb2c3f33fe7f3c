"""The one entry point: ``simulate(model, body, initial_state, t_end, ...)``."""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from typing import Any

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
    _check_run_objects(model, body, initial_state)
    if isinstance(model, RollingModel) and initial_state.is_sliding:
        raise ParameterError(
            "slip_velocity",
            initial_state.slip_velocity,
            "(0, 0) with the rolling model: its contact cannot slip",
            "use the model 'sliding' for a record that starts sliding",
        )
    t_end = schema.check("t_end", t_end)
    rtol = schema.check("rtol", rtol)
    atol = schema.check("atol", atol)
    max_steps = schema.check_count("max_steps", max_steps)
    max_crossings = schema.check_count("max_crossings", max_crossings)
    if progress is not None and not callable(progress):
        raise ParameterError("progress", progress, "None or a function of the time reached [s]")
    method_name, stick_method_name = method_names(model, method, stick_method)
    times = _sample_times(t_end, n_samples, sample_times)
    params = kernel_parameters(model, body)
    y0 = initial_vector(initial_state)
    concerns = plausibility.concerns(body, contact_settings(model))
    for concern in concerns:
        warnings.warn(str(concern), PlausibilityWarning, stacklevel=2)
    attrs = _run_attributes(model, body, initial_state, t_end, method_name, rtol, atol)
    phase_data: dict[str, np.ndarray] = {}
    # what the run loop takes alike in one run and in a stick–slip run's phases
    loop_settings: dict[str, Any] = {
        "rtol": rtol,
        "atol": atol,
        "sample_times": times,
        "max_crossings": max_crossings,
        "max_steps": max_steps,
        "progress": progress,
    }
    if isinstance(model, HybridModel):
        capture_speed = model.resolved_capture_speed(atol)
        stick_name = str(stick_method_name)  # a stick–slip run always has one
        solution = solvers.solve_phases(
            params,
            y0,
            t_end,
            slip_method=method_name,
            stick_method=stick_name,
            capture_speed=capture_speed,
            **loop_settings,
        )
        attrs.update(capture_speed=capture_speed, stick_method=stick_name)
        attrs["rejected_captures"] = solution.rejected_captures
        phase_data = {
            "phase": solution.sample_phase,
            "phase_kind": solution.phase_kind.astype(np.int8),
            "phase_start": solution.phase_start,
            "phase_end": solution.phase_end,
            "phase_energy_jump": solution.phase_energy_jump,
        }
        raw: solvers.RawSolution = solution
    else:
        raw = solvers.solve(model.code, method_name, params, y0, t_end, **loop_settings)
    code, t_stop, min_normal = raw.status, raw.t_stop, raw.min_normal_force
    n_crossings = raw.n_crossings_total
    sample_times_out, samples, crossings = raw.sample_times, raw.samples, raw.crossings
    statistics = {key: int(getattr(raw, key)) for key in solvers.STATISTICS}
    status = STATUS_NAMES.get(code, "failed")
    final_n = (samples if len(samples) else y0[None, :])[-1, layout.Y_N : layout.Y_N + 3]
    message = _status_message(status, code, t_stop, final_n)
    if status != "success" and concerns:
        names = ", ".join(dict.fromkeys(concern.parameter for concern in concerns))
        message += f"; look first at the implausible {names} (warned before the run)"
    attrs.update(status=status, message=message)
    run_samples = sample_run(
        model.code, params, sample_times_out, samples, crossings, attrs, **phase_data
    )
    trajectory = Trajectory(
        samples=run_samples,
        status=status,
        message=message,
        t_stop=t_stop,
        min_normal_force=min_normal,
        ending=RunEnding(model.code, params, y0, samples, int(code), int(n_crossings)),
        statistics=statistics,
    )
    _warn_friction_bound(trajectory)
    return trajectory


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


def _warn_friction_bound(trajectory: Trajectory) -> None:
    """Warn :func:`friction_bound_warning`'s warning, if any, from :func:`simulate`."""
    warning = friction_bound_warning(trajectory)
    if warning is not None:
        warnings.warn(warning, stacklevel=3)


def simulate_many(
    runs: Sequence[tuple[Model, Body, InitialState]],
    t_end: float,
    *,
    device: str = "cpu",
    method: str | None = None,
    stick_method: str | None = None,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    n_samples: int | None = None,
    sample_times: np.ndarray | None = None,
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
        same loops compiled for CUDA); "auto": the GPU where one can run them.
    sample_times : numpy.ndarray, optional
        Output times [s]: shape (m,), the same for every run, or (len(runs), m), each
        run's own.
    method, stick_method, rtol, atol, n_samples, max_steps, max_crossings :
        As :func:`simulate`.
    workers : int, optional
        Threads on the CPU (default: one per core).
    errors : str, default "raise"
        "raise": a run that cannot be made (a ``CeltstoneError``: an implausible body or
        contact, a bad setting) raises; "keep": its error takes its place in the list
        and the other runs go on (a fit's batch of trial parameters).

    Returns
    -------
    list of Trajectory (or CeltstoneError, with ``errors="keep"``)
        One per run, as :func:`simulate` returns it.
    """
    from celtstone._threads import map_in_threads

    require_choice("errors", errors, ("raise", "keep"))
    require_choice("device", device, ("cpu", "cuda", "auto"))
    if device == "cuda":  # the GPU's batch of runs is not built yet
        raise ParameterError("device", device, "cpu or auto")
    runs = list(runs)
    if not runs:
        raise ParameterError("runs", runs, "one (model, body, initial_state) or more")
    times = None if sample_times is None else np.asarray(sample_times, dtype=float)
    per_run = times is not None and times.ndim == 2
    if per_run and times is not None and times.shape[0] != len(runs):
        raise ParameterError(
            "sample_times", f"shape {times.shape}", f"(m,) or ({len(runs)}, m): a row per run"
        )

    def one(index: int) -> Trajectory | CeltstoneError:
        model, body, state = runs[index]
        try:
            return run(index, model, body, state)
        except CeltstoneError as error:
            if errors == "raise":
                raise
            return error

    def run(index: int, model: Model, body: Body, state: InitialState) -> Trajectory:
        return simulate(
            model,
            body,
            state,
            t_end,
            method=method,
            stick_method=stick_method,
            rtol=rtol,
            atol=atol,
            n_samples=n_samples,
            sample_times=None if times is None else (times[index] if per_run else times),
            max_steps=max_steps,
            max_crossings=max_crossings,
        )

    return list(map_in_threads(one, range(len(runs)), workers=workers))
