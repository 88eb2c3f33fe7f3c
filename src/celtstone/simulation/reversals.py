"""Spin reversals defined with hysteresis on the rocking average of the spin.

Around a reversal the raw spin ω·n can cross zero several times within a second (the
rocking modulates it, by more than any fixed band for a large or slow stone), and a
sliding stone whose spin has died dithers around zero. A *reversal* here is a change of
the sense of spin that is held, read from the spin with the rocking taken out: the
centred running mean of ω·n over one rocking period of the body
(``Body.rocking_period``, the *window*) leaves the band |⟨ω·n⟩| <= ``threshold`` on the
opposite side from the one it last left it on. Its time is the averaged spin's last
zero before it leaves the band. The definition is compiled once
(``kernels.reversal``) and shared by runs, sweeps and the report (docs/decisions.md
§8). A window of 0 gives the raw-spin definition used before (its times the exact
zero crossings): files written before the window was recorded are read with it.

*Resolution.* The averaged spin is the running mean of the samples' linear interpolant,
and its zero is interpolated between samples, so a reversal's time depends on the sample
rate: it converges as the rate grows (O(h²), h the sample spacing), within
:data:`REVERSAL_TIME_RESOLUTION` of a converged run's at the default 200 samples per
second for Kane & Levinson's stone (``tests/test_reversal_resolution.py``). Sweeps
compute the same mean from their own samples in the same compiled kernel, so a run and
a sweep point agree exactly at equal sampling; compare times across sample rates only to
this resolution. The raw spin's zero crossings (``Trajectory.spin_crossings``) are
located by the integrator on its dense output, independent of the sampling.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from celtstone.errors import ParameterError
from celtstone.kernels.reversal import count_reversals, rocking_average_into

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "REVERSAL_BAND_FLOOR",
    "REVERSAL_BAND_FRACTION",
    "REVERSAL_TIME_RESOLUTION",
    "averaged_spin",
    "dataset_reversal_times",
    "reversal_band",
    "reversal_bands",
    "reversal_times",
]


def averaged_spin(time: np.ndarray, spin: np.ndarray, window: float) -> np.ndarray:
    """Average the spin over a centred running window (the rocking average).

    Parameters
    ----------
    time : numpy.ndarray
        Sample times [s], shape (k,), increasing.
    spin : numpy.ndarray
        The spin ω·n to average [rad/s], shape (k,).
    window : float
        Width of the running mean [s], >= 0; 0 returns the spin itself.

    Returns
    -------
    numpy.ndarray
        The averaged spin at the sample times [rad/s], shape (k,).
    """
    time = np.ascontiguousarray(time, dtype=float)
    spin = np.ascontiguousarray(spin, dtype=float)
    if not (window >= 0.0 and np.isfinite(window)):
        raise ParameterError("window", window, "a finite number >= 0 s")
    if time.shape != spin.shape or time.ndim != 1:
        raise ParameterError("spin", spin.shape, f"an array of the shape of time {time.shape}")
    averaged = np.empty_like(spin)
    rocking_average_into(time, spin, spin.size, float(window), averaged, np.zeros(spin.size))
    return averaged


def reversal_times(
    time: np.ndarray,
    spin: np.ndarray,
    threshold: float,
    crossings: np.ndarray | None = None,
    window: float = 0.0,
) -> np.ndarray:
    """Find the times [s] at which the sense of spin reverses (hysteresis ``threshold``).

    Parameters
    ----------
    time : numpy.ndarray
        Sample times [s], shape (k,), increasing.
    spin : numpy.ndarray
        Spin ω·n at those times [rad/s], shape (k,).
    threshold : float
        Half-width of the band around zero [rad/s], > 0.
    crossings : numpy.ndarray, optional
        Exact zero-crossing times of the raw spin [s] (``Trajectory.spin_crossings``);
        used for the times only when ``window`` is 0.
    window : float, optional
        Width of the rocking average [s], >= 0: the body's rocking period
        (``Body.rocking_period``, what runs, sweeps and the report use); 0 judges the
        raw spin.

    Returns
    -------
    numpy.ndarray
        Reversal times [s], shape (r,).
    """
    if not threshold > 0.0:
        raise ParameterError("threshold", threshold, "a number > 0 rad/s")
    averaged = averaged_spin(time, spin, window)
    time = np.ascontiguousarray(time, dtype=float)
    exact = np.zeros(0) if crossings is None or window > 0.0 else np.asarray(crossings, float)
    found = np.empty(averaged.size)
    count = count_reversals(
        time, averaged, averaged.size, float(threshold), exact, exact.size, found
    )
    return found[:count].copy()


REVERSAL_TIME_RESOLUTION = 1e-3
"""Bound [s] on how far a first reversal's time at the default 200 samples per second lies
from a converged run's (tight rtol, 20 000 samples per second), for Kane & Levinson's
stone from ω3 = −5 rad/s: 4e-5 s sliding at f = 0.35 and 3.4e-4 s in rolling, measured
(``tests/test_reversal_resolution.py``). Times read from samples are known to this."""

REVERSAL_BAND_FRACTION = 0.04
"""Default half-width of the hysteresis band, as a fraction of the initial |spin|.

0.2 rad/s for the Kane & Levinson start at 5 rad/s.
"""


def reversal_band(initial_spin: float) -> float:
    """Default band half-width [rad/s]: ``REVERSAL_BAND_FRACTION`` |initial spin|.

    Parameters
    ----------
    initial_spin : float
        Spin ω·n at the start [rad/s], != 0.

    Returns
    -------
    float
        Half-width of the hysteresis band [rad/s].

    Raises
    ------
    ParameterError
        For a start without spin (no sense to reverse).
    """
    band = REVERSAL_BAND_FRACTION * abs(float(initial_spin))
    if not band > 0.0 or not np.isfinite(band):
        raise ParameterError("initial spin", initial_spin, "a finite spin != 0 rad/s")
    return band


REVERSAL_BAND_FLOOR = 0.01
"""Smallest band [rad/s] of :func:`reversal_bands`, for starts with little or no spin."""


def reversal_bands(initial_spins: np.ndarray) -> np.ndarray:
    """Default bands of many starts (sweeps), at least ``REVERSAL_BAND_FLOOR``.

    Parameters
    ----------
    initial_spins : numpy.ndarray
        Spin ω·n at each start [rad/s], shape (p,).

    Returns
    -------
    numpy.ndarray
        ``REVERSAL_BAND_FRACTION`` |spin|, at least ``REVERSAL_BAND_FLOOR`` so that a
        start without spin still has a band [rad/s], shape (p,).
    """
    spins = np.abs(np.asarray(initial_spins, dtype=float))
    return np.maximum(REVERSAL_BAND_FRACTION * spins, REVERSAL_BAND_FLOOR)


def dataset_reversal_times(dataset: xr.Dataset, threshold: float | None = None) -> np.ndarray:
    """Find the reversal times of a run's dataset.

    Parameters
    ----------
    dataset : xarray.Dataset
        A run (``Trajectory.dataset`` or a file read back); its attribute
        ``reversal_window`` is the window (0 in files written before it was recorded).
    threshold : float, optional
        Half-width of the band [rad/s]; by default :func:`reversal_band` of the
        initial spin.

    Returns
    -------
    numpy.ndarray
        Reversal times [s], shape (r,).
    """
    spin = dataset["spin"].values
    band = reversal_band(spin[0]) if threshold is None else threshold
    crossings = dataset["spin_crossings"].values if "spin_crossings" in dataset else None
    window = float(dataset.attrs.get("reversal_window", 0.0))
    return reversal_times(dataset["time"].values, spin, band, crossings, window)
