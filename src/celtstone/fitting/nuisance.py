"""The sensor's and the record's own unknowns, fitted beside the physics: declared once.

A gyroscope reads (1 + k_s) ω_s + b_s on a rate series s (spin, omega1..3) whose true
value is the model's ω_s (:func:`sensor_reading`):

``bias_<series>`` b_s [rad/s]: a constant offset. A phone's gyroscope axes map one-to-one
onto body axes (``fitting.sensor``), so a bias per sensor axis is a bias per body-axis
series. Free by default on every rate series; ``fixed`` (``--set``) holds one.

``scale_<series>`` k_s [1]: the error of the gyroscope's sensitivity (scale factor), 0
for a calibrated sensor. Held at 0 by default; free it by name (``--free scale_spin``)
or hold it at a calibration's value (``--set scale_omega1=0.012``). With a sensor rotation
of signed axes (phyphox's ``-y,x,z``) each body-axis series is one sensor axis, so its
scale is that axis' scale.

``release_offset`` [s]: the time from the release to the record's first sample. With it
(free or fixed), the run starts from the release state (the initial state: the model's
defaults or ``--set``, not the record's first sample) and the record's sample times are
shifted by it: a record that starts mid-motion, sliding included, is compared with the
motion from a known release.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from celtstone.fitting.series import SERIES

__all__ = [
    "BIAS_PREFIX",
    "NUISANCES",
    "RELEASE_OFFSET",
    "SCALE_PREFIX",
    "Nuisance",
    "bias_name",
    "biased_series",
    "gain",
    "is_nuisance",
    "scale_name",
    "scaled_series",
    "sensor_reading",
]

BIAS_PREFIX = "bias_"
SCALE_PREFIX = "scale_"
RELEASE_OFFSET = "release_offset"
# a phone gyroscope's zero-rate offset is ~0.01 rad/s, a few degrees per second (0.05 rad/s)
# uncalibrated; a wider bound lets a bias absorb a wrong motion on a spin-only record
BIAS_BOUND = 0.1  # rad/s
# a MEMS gyroscope's sensitivity error is within ±3 % (its datasheet's "sensitivity
# tolerance"); ±10 % leaves room for an uncalibrated one
SCALE_BOUND = 0.1
RELEASE_OFFSET_BOUNDS = (0.0, 2.0)  # s


@dataclass(frozen=True)
class Nuisance:
    """A number of the sensor or the record: name, unit, meaning, default bounds, start,
    and the rate series it acts on (a bias or a scale; None for the release offset)."""

    name: str
    unit: str
    description: str
    lower: float
    upper: float
    start: float = 0.0
    series: str | None = None


def bias_name(series: str) -> str:
    """The bias parameter of ``series`` (``bias_spin``)."""
    return f"{BIAS_PREFIX}{series}"


def scale_name(series: str) -> str:
    """The scale-factor parameter of ``series`` (``scale_spin``)."""
    return f"{SCALE_PREFIX}{series}"


_RATES = [s.name for s in SERIES.values() if s.is_gyroscope_rate]
NUISANCES: dict[str, Nuisance] = {
    n.name: n
    for n in (
        *(
            Nuisance(
                bias_name(s),
                SERIES[s].unit,
                f"gyroscope bias on {s} (added to the model's {s})",
                -BIAS_BOUND,
                BIAS_BOUND,
                series=s,
            )
            for s in _RATES
        ),
        *(
            Nuisance(
                scale_name(s),
                "",
                f"gyroscope scale error k on {s}: it reads (1 + k) times the model's {s}",
                -SCALE_BOUND,
                SCALE_BOUND,
                series=s,
            )
            for s in _RATES
        ),
        Nuisance(
            RELEASE_OFFSET,
            "s",
            "time from the release (the initial state) to the record's first sample",
            *RELEASE_OFFSET_BOUNDS,
        ),
    )
}


def _acted_on(name: str, prefix: str) -> str | None:
    nuisance = NUISANCES.get(name)
    return nuisance.series if nuisance is not None and name.startswith(prefix) else None


def biased_series(name: str) -> str | None:
    """The series a bias parameter shifts, or None for another name."""
    return _acted_on(name, BIAS_PREFIX)


def scaled_series(name: str) -> str | None:
    """The series a scale parameter multiplies, or None for another name."""
    return _acted_on(name, SCALE_PREFIX)


def is_nuisance(name: str) -> bool:
    """Whether ``name`` is a sensor or record number (not a model, body or state one)."""
    return name in NUISANCES


def gain(series: str, values: Mapping[str, float]) -> float:
    """1 + k_s [1]: the sensor's reading of a unit rate on ``series`` for the numbers
    ``values`` (1 where its scale is not among them)."""
    return 1.0 + values.get(scale_name(series), 0.0)


def sensor_reading(series: str, modelled: np.ndarray, values: Mapping[str, float]) -> np.ndarray:
    """What the sensor reads, (1 + k_s) ω_s + b_s [unit of the series], shape (n,), for
    the model's ``modelled`` series and the bias and scale among ``values`` (each 0 where
    absent: a series without them, yaw or tilt, is read as modelled)."""
    return gain(series, values) * modelled + values.get(bias_name(series), 0.0)
