"""The sensor's and the record's own unknowns, fitted beside the physics: declared once.

``bias_<series>`` [rad/s]: a gyroscope's constant offset on one measured rate series
(spin, omega1..3), added to the model's value of that series. A phone's gyroscope axes
map one-to-one onto body axes (``fitting.sensor``), so a bias per sensor axis is a bias
per body-axis series. Free by default on every rate series; ``fixed`` (``--set``) holds one.

``release_offset`` [s]: the time from the release to the record's first sample. With it
(free or fixed), the run starts from the release state (the initial state: the model's
defaults or ``--set``, not the record's first sample) and the record's sample times are
shifted by it: a record that starts mid-motion, sliding included, is compared with the
motion from a known release.
"""

from __future__ import annotations

from dataclasses import dataclass

from celtstone.fitting.series import SERIES

__all__ = [
    "BIAS_PREFIX",
    "NUISANCES",
    "RELEASE_OFFSET",
    "Nuisance",
    "bias_name",
    "biased_series",
    "is_nuisance",
]

BIAS_PREFIX = "bias_"
RELEASE_OFFSET = "release_offset"
# a phone gyroscope's zero-rate offset is ~0.01 rad/s, a few degrees per second (0.05 rad/s)
# uncalibrated; a wider bound lets a bias absorb a wrong motion on a spin-only record
BIAS_BOUND = 0.1  # rad/s
RELEASE_OFFSET_BOUNDS = (0.0, 2.0)  # s


@dataclass(frozen=True)
class Nuisance:
    """A number of the sensor or the record: name, unit, meaning, default bounds, start."""

    name: str
    unit: str
    description: str
    lower: float
    upper: float
    start: float = 0.0


NUISANCES: dict[str, Nuisance] = {
    **{
        f"{BIAS_PREFIX}{s.name}": Nuisance(
            f"{BIAS_PREFIX}{s.name}",
            s.unit,
            f"gyroscope bias on {s.name} (added to the model's {s.name})",
            -BIAS_BOUND,
            BIAS_BOUND,
        )
        for s in SERIES.values()
        if s.is_gyroscope_rate
    },
    RELEASE_OFFSET: Nuisance(
        RELEASE_OFFSET,
        "s",
        "time from the release (the initial state) to the record's first sample",
        *RELEASE_OFFSET_BOUNDS,
    ),
}


def bias_name(series: str) -> str:
    """The bias parameter of ``series`` (``bias_spin``)."""
    return f"{BIAS_PREFIX}{series}"


def biased_series(name: str) -> str | None:
    """The series a bias parameter shifts, or None for another name."""
    return name[len(BIAS_PREFIX) :] if name.startswith(BIAS_PREFIX) and name in NUISANCES else None


def is_nuisance(name: str) -> bool:
    """Whether ``name`` is a sensor or record number (not a model, body or state one)."""
    return name in NUISANCES
