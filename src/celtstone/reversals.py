"""Spin reversals defined with hysteresis.

Around a reversal the raw spin ω·n can cross zero several times within a few
hundredths of a second (the rocking modulates it), and a sliding stone whose spin
has died dithers around zero. A *reversal* here is a change of the sense of spin
that is held: the spin leaves the band |ω·n| <= ``threshold`` on the opposite side
from the one it last left it on. Its time is the last zero crossing before the
spin leaves the band.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from celtstone.errors import ParameterError

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "REVERSAL_BAND_FLOOR",
    "REVERSAL_BAND_FRACTION",
    "dataset_reversal_times",
    "reversal_band",
    "reversal_bands",
    "reversal_times",
]


def reversal_times(
    time: np.ndarray,
    spin: np.ndarray,
    threshold: float,
    crossings: np.ndarray | None = None,
) -> np.ndarray:
    """Times [s] at which the sense of spin reverses, with hysteresis band ``threshold``.

    Parameters
    ----------
    time : sample times [s], shape (k,), increasing
    spin : spin ω·n at those times [rad/s], shape (k,)
    threshold : half-width of the band around zero [rad/s], > 0
    crossings : exact zero-crossing times [s] (``Trajectory.spin_crossings``); when
        given, the reversal time is the last of them before the spin leaves the band,
        otherwise the last sign change of the samples, linearly interpolated

    Returns
    -------
    numpy.ndarray
        reversal times [s], shape (r,)
    """
    time = np.asarray(time, dtype=float)
    spin = np.asarray(spin, dtype=float)
    if not threshold > 0.0:
        raise ParameterError("threshold", threshold, "a number > 0 rad/s")
    if time.shape != spin.shape or time.ndim != 1:
        raise ParameterError("spin", spin.shape, f"an array of the shape of time {time.shape}")
    sense = 0
    reversals = []
    for index in np.flatnonzero(np.abs(spin) > threshold):
        current = 1 if spin[index] > 0 else -1
        if sense != 0 and current != sense:
            reversals.append(_last_zero_before(time, spin, int(index), crossings))
        sense = current
    return np.array(reversals)


def _last_zero_before(
    time: np.ndarray, spin: np.ndarray, index: int, crossings: np.ndarray | None
) -> float:
    if crossings is not None:
        earlier = crossings[crossings <= time[index]]
        if earlier.size:
            return float(earlier[-1])
    signs = np.sign(spin[: index + 1])
    changes = np.flatnonzero(signs[:-1] * signs[1:] <= 0)
    k = changes[-1]
    if spin[k] == spin[k + 1]:
        return float(time[k])
    fraction = spin[k] / (spin[k] - spin[k + 1])
    return float(time[k] + fraction * (time[k + 1] - time[k]))


REVERSAL_BAND_FRACTION = 0.04
"""Default half-width of the hysteresis band, as a fraction of the initial |spin|
(0.2 rad/s for the Kane & Levinson start at 5 rad/s)."""


def reversal_band(initial_spin: float) -> float:
    """Default band half-width [rad/s]: ``REVERSAL_BAND_FRACTION`` |initial spin|.

    Raises ParameterError for a start without spin (no sense to reverse).
    """
    band = REVERSAL_BAND_FRACTION * abs(float(initial_spin))
    if not band > 0.0 or not np.isfinite(band):
        raise ParameterError("initial spin", initial_spin, "a finite spin != 0 rad/s")
    return band


REVERSAL_BAND_FLOOR = 0.01
"""Smallest band [rad/s] of :func:`reversal_bands`, for starts with little or no spin."""


def reversal_bands(initial_spins: np.ndarray) -> np.ndarray:
    """Default bands [rad/s] of many starts (sweeps): ``REVERSAL_BAND_FRACTION`` |spin|,
    at least ``REVERSAL_BAND_FLOOR`` so that a start without spin still has a band."""
    spins = np.abs(np.asarray(initial_spins, dtype=float))
    return np.maximum(REVERSAL_BAND_FRACTION * spins, REVERSAL_BAND_FLOOR)


def dataset_reversal_times(dataset: xr.Dataset, threshold: float | None = None) -> np.ndarray:
    """Reversal times [s] of a run's dataset; default band from its initial spin."""
    spin = dataset["spin"].values
    band = reversal_band(spin[0]) if threshold is None else threshold
    crossings = dataset["spin_crossings"].values if "spin_crossings" in dataset else None
    return reversal_times(dataset["time"].values, spin, band, crossings)
