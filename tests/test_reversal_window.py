"""Reversals read from the spin with the rocking taken out (issue 15, item 4).

The rocking modulates the spin ω·n; for a stone larger than Kane & Levinson's the
modulation exceeds the fixed band of 4 % of the initial spin, and the raw spin changes
sense many times within a second around one real reversal. A reversal is read from the
spin's running mean over the body's rocking period instead (``Body.rocking_period``,
``kernels.reversal``). Checked here: the rocking periods against the linearised rolling
model's eigenfrequencies; the running mean against closed forms; the K&L body scaled
by 2, 3 and 5 in every length (inertia by the square), rolling for 60 s, against a
running mean and hysteresis written in the test with a different window.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

import celtstone as cs
from celtstone.errors import PlausibilityWarning
from celtstone.simulation.reversals import averaged_spin, reversal_times

KL_INERTIA = np.array([[2.0e-4, -2.0e-5, 0.0], [-2.0e-5, 1.6e-3, 0.0], [0.0, 0.0, 1.7e-3]])
START = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))


def _scaled_kane_levinson(scale: float, directory: Path) -> cs.Body:
    """Kane & Levinson's ellipsoid with every length times ``scale``, same mass."""
    path = directory / f"kane_levinson_x{scale:g}.toml"
    semi_axes = [0.20 * scale, 0.03 * scale, 0.02 * scale]
    path.write_text(
        f"""title = "Kane & Levinson scaled by {scale:g}"
[source]
authors = "test"
title = "every length times {scale:g}, inertia times its square"
year = "2026"
[body]
mass = 1.0
gravity = 9.81
inertia = {(KL_INERTIA * scale**2).tolist()}
[shape]
kind = "ellipsoid"
semi_axes = {semi_axes}
com_offset = {0.01 * scale}
""",
        encoding="utf-8",
    )
    return cs.load_body(path)


@pytest.mark.parametrize("name", ["kane_levinson_1982", "toy_rattleback_10cm"])
def test_rocking_periods_are_the_linearised_models(name: str) -> None:
    """Pitch and roll periods of the body at rest equal 2π/ω of the rolling model's
    linearisation at zero spin (``spin_stability``, from the compiled right-hand side) to
    1 %: the product of inertia the closed form leaves out moves them by less."""
    body = cs.load_body(name)
    stability = cs.spin_stability(body, [0.0])
    pitch, roll = body.rocking_periods
    assert pitch == pytest.approx(2 * math.pi / stability.frequency_pitch[0], rel=1e-2)
    assert roll == pytest.approx(2 * math.pi / stability.frequency_roll[0], rel=1e-2)
    assert body.rocking_period == max(pitch, roll)


def test_running_mean_closed_forms() -> None:
    """Over one period a sinusoid averages to its offset; a straight line is itself away
    from the ends (there the window is cut to the samples, one-sided); the times need not
    be uniform; a window of 0 is the spin itself."""
    rng = np.random.default_rng(7)
    time = np.sort(np.concatenate([[0.0, 10.0], rng.uniform(0.0, 10.0, 20_000)]))
    period = 0.37
    wave = 0.8 + 2.0 * np.sin(2 * np.pi * time / period + 0.3)
    inner = (time > period) & (time < 10.0 - period)
    mean = averaged_spin(time, wave, period)
    assert np.max(np.abs(mean[inner] - 0.8)) < 2e-4  # the interpolant's error, ~(Δt/T)²
    line = 3.0 - 0.5 * time
    assert np.max(np.abs(averaged_spin(time, line, period)[inner] - line[inner])) < 1e-12
    ends = averaged_spin(time, line, period)[[0, -1]]
    assert ends == pytest.approx([3.0 - 0.25 * period / 2, 3.0 - 0.5 * 10.0 + 0.25 * period / 2])
    assert np.array_equal(averaged_spin(time, wave, 0.0), wave)
    with pytest.raises(cs.ParameterError, match="window"):
        averaged_spin(time, wave, -1.0)


def test_a_zero_window_is_the_raw_definition() -> None:
    """Window 0 with exact crossings gives the raw spin's reversals at those crossings."""
    time = np.linspace(0.0, 3.0, 3001)
    spin = -np.cos(np.pi * time / 2.0)  # -1 to +1 and back: zeros at t = 1 and t = 3
    crossings = np.array([1.0 - 1e-9, 1.0])
    assert reversal_times(time, spin, 0.1, crossings, 0.0).tolist() == [1.0]
    assert reversal_times(time, spin, 0.1) == pytest.approx([1.0], abs=1e-9)


def _held_sign_changes(time: np.ndarray, spin: np.ndarray, band: float, window: float) -> list:
    """The test's own rocking average (a centred box filter on a uniform grid) and
    hysteresis: times where the filtered spin leaves the band opposite to its last side."""
    step = time[1] - time[0]
    width = round(float(window / step)) | 1
    padded = np.pad(spin, width // 2, mode="edge")
    mean = np.convolve(padded, np.ones(width) / width, mode="valid")
    changes, side = [], 0
    for k in np.flatnonzero(np.abs(mean) > band):
        now = int(np.sign(mean[k]))
        if side and now != side:
            changes.append(time[k])
        side = now
    return changes


@pytest.mark.parametrize("scale", [2.0, 3.0, 5.0])
def test_scaled_bodies_reverse_once_per_real_reversal(scale: float, tmp_path: Path) -> None:
    """The K&L body scaled by 2, 3, 5, rolling for 60 s: the raw spin shows clusters of
    "reversals" within a second; the rocking average shows one reversal per real one, as
    many as a box filter over two rocking periods written here finds, each within a
    second of it, and none within ten rocking periods of another."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)  # ×5: a 2 m stone
        body = _scaled_kane_levinson(scale, tmp_path)
        run = cs.simulate(cs.RollingModel(), body, START, 60.0, n_samples=60_001)
    time, spin = run.samples.values("time"), run.samples.values("spin")
    band = run.reversal_band
    raw = reversal_times(time, spin, band, run.spin_crossings)
    assert np.min(np.diff(raw)) < 1.0  # the problem: clustered raw "reversals"
    found = run.reversal_times()
    assert run.reversal_window == body.rocking_period > 0.0
    assert found.size >= 1
    if found.size > 1:
        assert np.min(np.diff(found)) > 10 * body.rocking_period
    independent = _held_sign_changes(time, spin, band, 2 * body.rocking_period)
    assert len(independent) == found.size
    assert np.max(np.abs(np.array(independent) - found)) < 1.0
    assert found.size < raw.size


def test_a_flat_pole_has_no_rocking_period() -> None:
    """A superellipsoid of exponent 4 is flat at its pole (radii of curvature infinite):
    no linear rocking, so no window, and reversals are the raw spin's."""
    shape = cs.Superellipsoid((0.2, 0.03, 0.02), 0.01, 4.0)
    body = cs.Body("flat pole", 1.0, tuple(map(tuple, KL_INERTIA)), shape)  # type: ignore[arg-type]
    assert shape.radii_of_curvature == (math.inf, math.inf)
    assert body.rocking_periods == (0.0, 0.0) and body.rocking_period == 0.0
