"""Reversal times with hysteresis: exact synthetic cases and the Kane & Levinson run."""

from __future__ import annotations

import numpy as np
import pytest

import celtstone as cs
from celtstone.simulation.reversals import reversal_times
from tests.conftest import LITERATURE_EULER_ANGLES


def test_dither_inside_the_band_is_not_a_reversal() -> None:
    time = np.linspace(0.0, 10.0, 10001)
    spin = -5.0 * np.exp(-time) + 0.01 * np.sin(40.0 * time)  # dies, then dithers around 0
    assert reversal_times(time, spin, threshold=0.1).size == 0


def test_modulated_reversal_counts_once_at_its_last_zero() -> None:
    """spin = t - 2 + 0.3 sin(20 t) crosses zero three times near t = 2; one reversal,
    timed at the last crossing before the band is left."""
    time = np.linspace(0.0, 4.0, 400001)
    spin = time - 2.0 + 0.3 * np.sin(20.0 * time)
    reversals = reversal_times(time, spin, threshold=0.5)
    assert reversals.size == 1
    signs = np.sign(spin)
    raw = time[np.flatnonzero(signs[:-1] != signs[1:])]
    assert raw.size == 3
    assert reversals[0] == pytest.approx(raw[-1], abs=1e-5)


def test_two_reversals_of_a_cosine() -> None:
    time = np.linspace(0.0, 2 * np.pi, 100001)
    reversals = reversal_times(time, np.cos(time), threshold=0.2)
    np.testing.assert_allclose(reversals, [np.pi / 2, 3 * np.pi / 2], atol=1e-6)


def test_kane_levinson_rolling_reverses_once_in_ten_seconds() -> None:
    """The raw spin crosses zero 7 times around 2.7-2.9 s; it is one reversal."""
    body = cs.load_body("kane_levinson_1982")
    run = cs.simulate(
        cs.RollingModel(), body, cs.InitialState((0.0, 0.0, -5.0), LITERATURE_EULER_ANGLES), 10.0
    )
    ds = run.dataset
    reversals = reversal_times(
        ds["time"].values, ds["spin"].values, 0.5, crossings=run.spin_crossings
    )
    assert run.spin_crossings.size > 1
    assert reversals.size == 1
    assert reversals[0] in run.spin_crossings
    assert ds["spin"].sel(time=reversals[0] + 0.5, method="nearest").item() > 0.5


def test_threshold_must_be_positive() -> None:
    with pytest.raises(cs.ParameterError, match="threshold"):
        reversal_times(np.zeros(3), np.zeros(3), threshold=0.0)


def test_sweep_bands_scale_with_the_spin_and_keep_a_floor() -> None:
    from celtstone.simulation.reversals import REVERSAL_BAND_FLOOR, reversal_band, reversal_bands

    np.testing.assert_allclose(reversal_bands([-5.0, 3.0, 0.0, 0.1]), [0.2, 0.12, 0.01, 0.01])
    assert REVERSAL_BAND_FLOOR == 0.01
    assert reversal_bands([-5.0])[0] == reversal_band(-5.0)
