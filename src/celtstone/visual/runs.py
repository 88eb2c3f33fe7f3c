"""Reading a run file back for drawing, with a clear error for anything else.

:func:`check_run` is the one check of a run that ``plot``, ``view`` and ``animate`` draw
(a file a user may have edited, or one from another version of celtstone): every
variable they read, its times, its numbers and the model settings its attributes
record are checked here, so that a bad file is one line naming what is wrong instead
of a traceback, a NaN on the page or a silently reversed clock.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from celtstone._about import version
from celtstone.errors import ParameterError
from celtstone.files.export import MIN_SAMPLES, read_run
from celtstone.simulation.models import MODEL_KINDS, MODELS, SETTINGS, settings_of

if TYPE_CHECKING:
    import xarray as xr


__all__ = ["REQUIRED_VARIABLES", "check_run", "default_label", "load_run"]

# what the scene, the viewer and the plots read (schema.VARIABLES names)
REQUIRED_VARIABLES = (
    "spin",
    "tilt",
    "energy",
    "dissipated_work",
    "slip_speed",
    "normal_force",
    "n",
    "quaternion",
    "com_position",
    "com_height",
    "contact_position",
)
REQUIRED_ATTRIBUTES = ("model", "body", "initial_omega", "body_shape", "body_shape_parameters")
# the settings the labels read (``default_label``, ``plotting.labels``); any other setting
# may be absent (a file written before it existed) but is checked when present
LABELLED_SETTINGS = {"sliding": ("friction_coefficient", "contact_radius", "friction_load")}
# a stored attitude is a unit quaternion to the integrator's tolerance; far off it, the
# file was edited (a rotation drawn from it would shear the body)
QUATERNION_NORM_TOLERANCE = 1e-3
_ALLOWED = "a NetCDF file written by `celtstone run --out RUN.nc`"


def check_run(dataset: xr.Dataset, name: str = "run") -> xr.Dataset:
    """``dataset`` if it is a run that can be drawn, else ParameterError naming ``name``.

    Checked: the variables drawn (:data:`REQUIRED_VARIABLES`), each finite and over
    ``time``; at least ``MIN_SAMPLES`` times, finite and strictly increasing; unit
    quaternions; the model (``MODELS``) and each of its settings in its range, as
    ``simulate`` would check them (``models.SETTINGS``). A file written by a newer
    celtstone that fails says so.
    """
    try:
        _check_variables(dataset, name)
        _check_times(dataset, name)
        _check_attributes(dataset, name)
    except ParameterError as error:
        newer = _newer_writer(dataset)
        if newer is None:
            raise
        raise ParameterError(
            error.name,
            error.value,
            error.allowed,
            "; ".join(
                part
                for part in (
                    error.hint,
                    f"written by celtstone {newer}, newer than this {version()}",
                )
                if part
            ),
        ) from None
    return dataset


def _title(dataset: xr.Dataset) -> str:
    return str(dataset.attrs.get("title", "dataset"))


def _check_variables(dataset: xr.Dataset, name: str) -> None:
    missing = [v for v in REQUIRED_VARIABLES if v not in dataset.variables]
    missing += [a for a in REQUIRED_ATTRIBUTES if a not in dataset.attrs]
    if "time" not in dataset.variables:
        missing.insert(0, "time")
    if missing:
        raise ParameterError(name, _title(dataset), _ALLOWED, f"it lacks {', '.join(missing)}")
    for variable in REQUIRED_VARIABLES:
        values = dataset[variable]
        if values.dims[:1] != ("time",) or not np.issubdtype(values.dtype, np.number):
            raise ParameterError(
                name, _title(dataset), _ALLOWED, f"its {variable} is not numbers over time"
            )
        finite = np.isfinite(np.asarray(values.values, dtype=float))
        if not finite.all():
            first = int(np.argwhere(~finite.reshape(finite.shape[0], -1).all(axis=1))[0, 0])
            raise ParameterError(
                name,
                _title(dataset),
                "a run with finite values",
                f"its {variable} is not finite at sample {first}",
            )
    norm = np.linalg.norm(np.asarray(dataset["quaternion"].values, dtype=float), axis=-1)
    off = np.abs(norm - 1.0) > QUATERNION_NORM_TOLERANCE
    if off.any():
        raise ParameterError(
            name,
            _title(dataset),
            f"unit quaternions (norm 1 within {QUATERNION_NORM_TOLERANCE:g})",
            f"the quaternion at sample {int(np.argmax(off))} has norm {norm[np.argmax(off)]:.6g}",
        )


def _check_times(dataset: xr.Dataset, name: str) -> None:
    times = np.asarray(dataset["time"].values)
    if times.ndim != 1 or not np.issubdtype(times.dtype, np.number):
        raise ParameterError(name, _title(dataset), _ALLOWED, "its time is not a list of numbers")
    if times.size < MIN_SAMPLES:
        raise ParameterError(name, _title(dataset), f"a run with at least {MIN_SAMPLES} samples")
    times = times.astype(float)
    if not np.isfinite(times).all():
        first = int(np.argmax(~np.isfinite(times)))
        raise ParameterError(
            name,
            _title(dataset),
            "finite sample times",
            f"time at sample {first} is {times[first]}",
        )
    steps = np.diff(times)
    if not (steps > 0).all():
        first = int(np.argmax(steps <= 0))
        raise ParameterError(
            name,
            _title(dataset),
            "strictly increasing sample times [s]",
            f"sample {first + 1} is at {float(times[first + 1])!r} s "
            f"after {float(times[first])!r} s",
        )


def _attribute(value: Any) -> Any:
    """A stored setting as the model takes it: "none" is not set; NumPy scalars as Python."""
    if isinstance(value, str) and value == "none":
        return None
    return value.item() if isinstance(value, np.generic) else value


def _check_attributes(dataset: xr.Dataset, name: str) -> None:
    """The model and its settings, checked as ``simulate`` checks them (``SETTINGS``)."""
    attrs = dataset.attrs
    model = attrs["model"]
    if model not in MODELS:
        raise ParameterError(
            name, _title(dataset), f"a run of the {' or '.join(MODELS)} model", f"model = {model!r}"
        )
    kind = attrs.get("contact", model)
    if kind not in MODEL_KINDS:
        raise ParameterError(
            name,
            _title(dataset),
            f"a run with contact {', '.join(MODEL_KINDS)}",
            f"contact = {kind!r}",
        )
    for setting in LABELLED_SETTINGS.get(str(model), ()):
        if setting not in attrs:
            raise ParameterError(
                name, _title(dataset), _ALLOWED, f"it lacks the {model} model's {setting}"
            )
    for setting in settings_of(str(kind)):
        if setting not in attrs:
            continue
        try:
            SETTINGS[setting].check(_attribute(attrs[setting]))
        except ParameterError as error:
            raise _bad_attribute(
                dataset, name, setting, _attribute(attrs[setting]), error.allowed
            ) from None
    # as `run` writes it: "[ω1, ω2, ω3]" [rad/s]; the plot's title shows it
    _check_attribute(
        dataset,
        name,
        "initial_omega",
        attrs["initial_omega"],
        _is_rates,
        "three finite numbers [rad/s]",
    )
    window = attrs.get("reversal_window", 0.0)
    _check_attribute(dataset, name, "reversal_window", window, _is_duration, "a duration >= 0 s")


def _is_rates(text: object) -> bool:
    """Whether ``text`` reads as three finite numbers, "[ω1, ω2, ω3]"."""
    omega = np.asarray(ast.literal_eval(str(text)), dtype=float)
    return omega.shape == (3,) and bool(np.isfinite(omega).all())


def _is_duration(value: Any) -> bool:
    """Whether ``value`` is a finite number >= 0."""
    return bool(np.isfinite(float(value)) and float(value) >= 0.0)


def _check_attribute(
    dataset: xr.Dataset,
    name: str,
    attribute: str,
    value: Any,
    test: Callable[[Any], bool],
    expected: str,
) -> None:
    """Refuse the run unless ``test(value)`` holds for its attribute (a value that does not
    parse fails it)."""
    try:
        ok = test(value)
    except (ValueError, TypeError, SyntaxError, MemoryError, RecursionError):
        ok = False
    if not ok:
        raise _bad_attribute(dataset, name, attribute, value, expected)


def _bad_attribute(
    dataset: xr.Dataset, name: str, attribute: str, value: Any, expected: str
) -> ParameterError:
    """The error of a run whose attribute ``attribute`` is ``value``, not ``expected``."""
    return ParameterError(
        name,
        _title(dataset),
        _ALLOWED,
        f"its attribute {attribute} = {value!r}: expected {expected}",
    )


def _version_numbers(text: object) -> tuple[int, ...] | None:
    found = re.match(r"\s*(\d+)\.(\d+)(?:\.(\d+))?", str(text))
    return None if found is None else tuple(int(part or 0) for part in found.groups())


def _newer_writer(dataset: xr.Dataset) -> str | None:
    """The version of celtstone that wrote ``dataset`` if it is newer than this one."""
    written = dataset.attrs.get("celtstone_version")
    theirs, ours = _version_numbers(written), _version_numbers(version())
    if theirs is None or ours is None or theirs <= ours:
        return None
    return str(written)


def load_run(path: str | Path) -> xr.Dataset:
    """Load the run saved at ``path`` (NetCDF) and check it holds what drawing needs.

    Parameters
    ----------
    path : str or pathlib.Path
        The NetCDF file (``celtstone run --out RUN.nc``).

    Returns
    -------
    xarray.Dataset
        The run, loaded into memory (:func:`celtstone.files.export.read_run`), checked by
        :func:`check_run`.

    Raises
    ------
    ParameterError
        Naming ``run`` and what is wrong with the file.
    """
    dataset = read_run(path)
    try:
        return check_run(dataset)
    except ParameterError as error:  # the path says which file better than its title
        raise ParameterError("run", str(path), error.allowed, error.hint) from None


def default_label(dataset: xr.Dataset) -> str:
    """A title from the run's attributes.

    E.g. ``"sliding — kane_levinson_1982, f = 0.35, ε = 1 mm"``.
    """
    attrs = dataset.attrs
    label = f"{attrs.get('model', 'run')} — {attrs.get('body', '')}"
    if attrs.get("model") == "sliding":
        label += (
            f", f = {float(attrs['friction_coefficient']):g},"
            f" ε = {1e3 * float(attrs['contact_radius']):g} mm"
        )
    return label
