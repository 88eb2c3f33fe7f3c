"""Spin reversals with the rocking taken out: one compiled definition for runs and sweeps.

The spin ω·n of a rocking stone is modulated at the rocking frequency; for a large or
slow stone the modulation exceeds any fixed hysteresis band around a reversal, and the
raw spin changes sense many times within a second around one real reversal. A
reversal is therefore defined on the *rocking average* of the spin: its centred
running mean over one rocking period (``Body.rocking_period``). A reversal is a change
of the sense of the averaged spin held beyond the band |⟨ω·n⟩| <= band (the spin
leaves the band on the side opposite to the one it last left it on); its time is the
averaged spin's last zero before it leaves the band. With a window of 0 the average is
the raw spin and the time the last exact zero crossing (``crossings``), else the linear
interpolant of the samples: the definition before the rocking average.
"""

from __future__ import annotations

import math

from celtstone.kernels._jit import inlined_kernel, kernel

__all__ = ["count_reversals", "last_zero_before", "rocking_average_into"]


@inlined_kernel
def _integral_at(times, cumulative, values, n, t, start):
    """∫ from times[0] to t of the piecewise-linear interpolant of ``values`` (exact for
    it), searching the segment from index ``start``; returns (integral, segment).
    Inlined, as :func:`last_zero_before`: a compile of their own each cost more than
    their code in their one caller."""
    k = start
    while k < n - 2 and times[k + 1] < t:
        k += 1
    width = times[k + 1] - times[k]
    into = t - times[k]
    slope = (values[k + 1] - values[k]) / width if width > 0.0 else 0.0
    return cumulative[k] + into * (values[k] + 0.5 * slope * into), k


@kernel
def rocking_average_into(times, spins, n, window, averaged, cumulative):
    """Centred running mean of ``spins[:n]`` [rad/s] over ``window`` [s] into ``averaged``.

    The mean of the samples' piecewise-linear interpolant over
    [t − window/2, t + window/2], cut to the samples' span at both ends (so the first
    and last half-window are averaged over a shorter, one-sided window). Times need not
    be uniform. ``window`` <= 0 copies the spin. The spin's running integral [rad] is
    kept in ``cumulative`` (at least n long, overwritten), a buffer the caller provides:
    code that cannot allocate (a CUDA thread) passes its own, and a run's summary and
    its reversal times from Python share one compiled function.
    """
    if window <= 0.0 or n < 2:
        for k in range(n):
            averaged[k] = spins[k]
        return
    cumulative[0] = 0.0
    for k in range(1, n):
        cumulative[k] = cumulative[k - 1] + 0.5 * (spins[k] + spins[k - 1]) * (
            times[k] - times[k - 1]
        )
    half = 0.5 * window
    low_segment = 0
    high_segment = 0
    for k in range(n):
        low = max(times[k] - half, times[0])
        high = min(times[k] + half, times[n - 1])
        if not high > low:
            averaged[k] = spins[k]
            continue
        below, low_segment = _integral_at(times, cumulative, spins, n, low, low_segment)
        above, high_segment = _integral_at(times, cumulative, spins, n, high, high_segment)
        averaged[k] = (above - below) / (high - low)


@inlined_kernel
def last_zero_before(times, spins, index, crossings, n_stored):
    """Last zero of the spin at or before ``times[index]`` [s]: the last of the
    ``n_stored`` exact crossings there, else the linear interpolant of the samples."""
    limit = times[index]
    best = -1.0
    found = False
    for k in range(n_stored):
        if crossings[k] <= limit:
            best = crossings[k]
            found = True
        else:
            break
    if found:
        return best
    k = index - 1
    while k >= 0:
        a = math.copysign(1.0, spins[k]) if spins[k] != 0.0 else 0.0
        b = math.copysign(1.0, spins[k + 1]) if spins[k + 1] != 0.0 else 0.0
        if a * b <= 0.0:
            break
        k -= 1
    if k < 0:
        return times[0]
    if spins[k] == spins[k + 1]:
        return times[k]
    fraction = spins[k] / (spins[k] - spins[k + 1])
    return times[k] + fraction * (times[k + 1] - times[k])


@kernel
def count_reversals(times, averaged, n, band, crossings, n_stored, reversal_times):
    """Number of reversals of the (averaged) spin ``averaged[:n]`` with hysteresis
    ``band`` [rad/s]; the first ``len(reversal_times)`` of their times [s] are written
    into ``reversal_times``. ``crossings[:n_stored]`` are exact zero crossings of the
    same signal (pass ``n_stored = 0`` for an averaged spin)."""
    sense = 0
    count = 0
    for j in range(n):
        if abs(averaged[j]) > band:
            current = 1 if averaged[j] > 0.0 else -1
            if sense != 0 and current != sense:
                if count < reversal_times.shape[0]:
                    reversal_times[count] = last_zero_before(
                        times, averaged, j, crossings, n_stored
                    )
                count += 1
            sense = current
    return count
