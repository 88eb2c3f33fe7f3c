"""How big and how long a sweep is, known from its counts before any point is made.

A sweep is sized from the number of values of each axis (or the rows of a points
file) alone, before the values are spaced, the points validated or the store
created, so an absurd request is refused at once:

* more than :data:`POINT_LIMIT` points, or a store estimated above
  :data:`STORE_LIMIT_BYTES`, needs ``force`` (``--force``);
* more than :data:`HARD_POINT_LIMIT` points is refused even then: this process holds
  every point's parameters and bookkeeping in memory (split such a sweep in parts).

The run time is estimated from :data:`CPU_SECONDS_PER_SIMULATED_SECOND`, measured
per model; the CLI prints the estimate before a sweep expected to take longer
than :data:`LONG_SWEEP_SECONDS`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from celtstone.errors import ParameterError
from celtstone.sweep.store import RESULT_FIELDS

__all__ = [
    "CPU_SECONDS_PER_SIMULATED_SECOND",
    "HARD_POINT_LIMIT",
    "LONG_SWEEP_SECONDS",
    "POINT_LIMIT",
    "STORE_LIMIT_BYTES",
    "Estimate",
    "check_size",
    "estimate",
]

POINT_LIMIT = 1_000_000  # more needs force: about 3.5 days of CPU for 10 s sliding runs
STORE_LIMIT_BYTES = 1_000_000_000  # more needs force
HARD_POINT_LIMIT = 10_000_000  # not even with force
LONG_SWEEP_SECONDS = 10.0  # the CLI prints the estimate before a longer sweep

# CPU time of one point per simulated second [s/s], default tolerances (rtol 1e-8,
# atol 1e-12), Kane & Levinson's body, measured on the 2-core development machine
# (Python 3.11.7) on 16-point sweeps of 5 s runs, spin -8..8 rad/s: sliding (radau5,
# f = 0.1 and 0.35, eps = 1 mm) 0.028 s/s, as the 64 x 64 benchmark's 0.262 s per 10 s
# point (docs/benchmarks.md); rolling (dop853, damping 0 and 1e-5) 0.0012 s/s. Rounded
# up; a point's cost varies about twofold over a grid. Kept as the bound for the method
# auto that sliding runs take, which costs 0.1-1.1 times radau5 (decisions §34).
CPU_SECONDS_PER_SIMULATED_SECOND: dict[str, float] = {"sliding": 0.03, "rolling": 0.002}

# Stored bytes per point of the string fields, before compression: a status name
# (at most about 20 characters) and a message (at most about 200: "stopped at
# t = ... s: " and the longest solver message, 146 characters), with a 4-byte length.
STRING_FIELD_BYTES = {"status": 24, "message": 204}
MASK_BYTES = 1  # the "completed" flag of each point


def store_bytes_per_point() -> int:
    """Upper bound of a point's stored bytes before compression, from ``RESULT_FIELDS``.

    Zarr's compression makes the store smaller: a 64 x 64 rolling sweep (56 % of its
    points stopped early, with long messages) took 178 bytes per point on disk.
    """
    total = MASK_BYTES
    for name, (dtype, _, _, _) in RESULT_FIELDS.items():
        total += STRING_FIELD_BYTES.get(name, 0) if dtype == "str" else np.dtype(dtype).itemsize
    return total


@dataclass(frozen=True)
class Estimate:
    """A sweep's size and expected cost.

    Parameters
    ----------
    points : number of points
    store_bytes : upper bound of the store's size before compression [bytes]
    cpu_seconds : expected CPU time of all points [s]
    seconds_per_point : the CPU time per point behind ``cpu_seconds`` [s]
    """

    points: int
    store_bytes: int
    cpu_seconds: float
    seconds_per_point: float

    def wall_seconds(self, threads: int) -> float:
        """Expected wall time on ``threads`` busy threads [s]."""
        return self.cpu_seconds / max(1, threads)

    def describe(self, threads: int | None = None) -> str:
        """One line: points, store size and time (on ``threads``, if given)."""
        text = (
            f"{self.points} points, a store of up to {_bytes(self.store_bytes)}, "
            f"about {_duration(self.cpu_seconds)} of CPU "
            f"({self.seconds_per_point:.2g} s per point, estimated)"
        )
        if threads is not None:
            text += f", about {_duration(self.wall_seconds(threads))} on {threads} threads"
        return text


def _bytes(count: float) -> str:
    for unit in ("B", "kB", "MB", "GB", "TB"):
        if count < 1000 or unit == "TB":
            return f"{count:.3g} {unit}"
        count /= 1000
    raise AssertionError  # pragma: no cover


def _duration(seconds: float) -> str:
    for unit, length in (("days", 86400.0), ("h", 3600.0), ("min", 60.0)):
        if seconds >= length:
            return f"{seconds / length:.2g} {unit}"
    return f"{seconds:.2g} s"


def estimate(points: int, t_end: float, model: str) -> Estimate:
    """The size and CPU time of ``points`` runs of ``t_end`` seconds of ``model``
    (an unknown model is costed as the dearest known one)."""
    rate = CPU_SECONDS_PER_SIMULATED_SECOND.get(
        model, max(CPU_SECONDS_PER_SIMULATED_SECOND.values())
    )
    per_point = rate * t_end
    return Estimate(points, points * store_bytes_per_point(), points * per_point, per_point)


def check_size(
    counts: Mapping[str, int], *, t_end: float, model: str, force: bool = False
) -> Estimate:
    """Refuse a sweep of more points than the limits allow; return its estimate.

    Parameters
    ----------
    counts : number of values of each grid axis, or ``{"points": rows}`` for a list
    t_end : duration of each run [s]
    model : model name, for the time estimate
    force : accept more than ``POINT_LIMIT`` points or ``STORE_LIMIT_BYTES``

    Raises
    ------
    ParameterError
        naming the axes and their counts, the estimate and the limit.
    """
    points = math.prod(counts.values())  # Python integers: no overflow
    axes = " x ".join(f"{name} {count}" for name, count in counts.items())
    if points > HARD_POINT_LIMIT:
        raise ParameterError(
            "points",
            points,
            f"at most {HARD_POINT_LIMIT} points (even with --force)",
            f"{axes}; split the sweep into parts of fewer points",
        )
    found = estimate(points, t_end, model)
    if force:
        return found
    if points > POINT_LIMIT or found.store_bytes > STORE_LIMIT_BYTES:
        raise ParameterError(
            "points",
            points,
            f"at most {POINT_LIMIT} points and a store of at most "
            f"{_bytes(STORE_LIMIT_BYTES)} without --force",
            f"{axes}: {found.describe()}; use fewer values, or --force to run it",
        )
    return found
