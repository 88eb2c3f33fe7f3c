"""What a record can measure, declared once: each series' unit, the units a file may give
it in, and how the model's run gives the same quantity.

A series is compared in SI (rad/s, rad); a file may hold it in another unit of the same
kind (deg/s, deg), converted once when it is read (``record.make_record``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from celtstone.simulation.trajectory import RunSamples

__all__ = ["ANGLE_UNITS", "RATE_UNITS", "SERIES", "Series", "yaw_angle"]

# unit -> factor to SI
RATE_UNITS = {"rad/s": 1.0, "deg/s": math.pi / 180.0}
ANGLE_UNITS = {"rad": 1.0, "deg": math.pi / 180.0}


def yaw_angle(quaternion: np.ndarray) -> np.ndarray:
    """Heading ψ of body axis 1 projected on the plane, unwrapped [rad], shape (n,).

    Parameters
    ----------
    quaternion : attitude (w, x, y, z), body to space [1], shape (n, 4)

    Notes
    -----
    ψ = atan2(R21, R11) with R the rotation matrix of the quaternion; axis 1 stays off the
    vertical for a rattleback (tilts of a few degrees), so ψ is defined at every sample.
    """
    w, x, y, z = (quaternion[:, k] for k in range(4))
    r11 = 1.0 - 2.0 * (y * y + z * z)
    r21 = 2.0 * (x * y + w * z)
    return np.unwrap(np.arctan2(r21, r11))


@dataclass(frozen=True)
class Series:
    """A measurable quantity.

    Parameters
    ----------
    name : the series' name in ``--column NAME=HEADER``, the summary and the figure
    description : what it is, in words
    unit : its SI unit, that of the model's variable (``schema.VARIABLES``)
    units : unit -> factor to SI, the units a file may give it in
    default_unit : the unit assumed when neither ``--column`` nor the header says one
    model : the same quantity from a run's samples, shape (n,), in ``unit``
    is_angle_offset_free : whether its zero is arbitrary (a camera's yaw): the offset
        between model and data is removed from the residuals and costs a degree of freedom
    is_gyroscope_rate : whether a gyroscope measures it, with a constant bias of its own
        (``fitting.nuisance``: ``bias_<name>`` is free by default)
    """

    name: str
    description: str
    unit: str
    units: Mapping[str, float]
    default_unit: str
    model: Callable[[RunSamples], np.ndarray]
    plot_scale: float = 1.0
    plot_unit: str = ""
    is_angle_offset_free: bool = False
    is_gyroscope_rate: bool = False


def _omega(axis: int) -> Callable[[RunSamples], np.ndarray]:
    return lambda samples: samples.values("omega")[:, axis]


SERIES: dict[str, Series] = {
    s.name: s
    for s in (
        Series(
            "spin",
            "spin ω·n about the vertical",
            "rad/s",
            RATE_UNITS,
            "rad/s",
            lambda samples: samples.values("spin"),
            is_gyroscope_rate=True,
        ),
        *(
            Series(
                f"omega{k + 1}",
                f"angular velocity component ω{k + 1}, body axis {k + 1}",
                "rad/s",
                RATE_UNITS,
                "rad/s",
                _omega(k),
                is_gyroscope_rate=True,
            )
            for k in range(3)
        ),
        Series(
            "yaw",
            "heading of body axis 1 on the plane, zero arbitrary (video tracking)",
            "rad",
            ANGLE_UNITS,
            "rad",
            lambda samples: yaw_angle(samples.values("quaternion")),
            plot_scale=180.0 / math.pi,
            plot_unit="deg",
            is_angle_offset_free=True,
        ),
        Series(
            "tilt",
            "angle between the vertical and body axis 3",
            "rad",
            ANGLE_UNITS,
            "deg",
            lambda samples: samples.values("tilt"),
            plot_scale=180.0 / math.pi,
            plot_unit="deg",
        ),
    )
}
