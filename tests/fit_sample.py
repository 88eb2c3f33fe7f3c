"""The sample gyroscope record shipped with celtstone (``celtstone.fitting.sample_record``):
how it is made, so that a test can check the file against celtstone's own run.

Run ``python tests/fit_sample.py`` to write it again (the same bytes: seeded).

The motion: Kane & Levinson's stone (``kane_levinson_1982``), the sliding model with
f = 0.3 and ε = 0.8 mm (N = m g, Padé law), released at ω = (0, 0, −5) rad/s with Euler
angles 0.5°, 0.5°. The phone: first sample 0.25 s after the release, 4 s at 100 Hz with
±1 ms timing jitter (the true times written), white noise 0.02 rad/s and a bias of
(0.01, −0.005, 0.008) rad/s on its x, y, z axes, lying so that its x, y, z axes are the
body's −y, x, z (``--sensor-rotation -y,x,z``); phyphox's "comma" gyroscope export.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np

SAMPLE = Path(__file__).parents[1] / "src" / "celtstone" / "fitting" / "data" / "sample_phyphox.csv"
FRICTION_COEFFICIENT = 0.3
CONTACT_RADIUS = 8e-4  # m
RELEASE_OFFSET = 0.25  # s
DURATION = 4.0  # s
RATE = 100.0  # Hz
JITTER = 1e-3  # s
NOISE = 0.02  # rad/s
SENSOR_BIAS = (0.01, -0.005, 0.008)  # rad/s, sensor x, y, z
SENSOR_ROTATION = "-y,x,z"
SEED = 2026
HEADER = (
    '"Time (s)","Gyroscope x (rad/s)","Gyroscope y (rad/s)","Gyroscope z (rad/s)",'
    '"Absolute (rad/s)"'
)


def clean_sensor_rates(times: np.ndarray) -> np.ndarray:
    """The noise-free, bias-free sensor rates [rad/s] at ``times`` [s from the first
    sample], shape (n, 3): celtstone's run in body axes turned into the sensor's."""
    import celtstone as cs
    from celtstone.fitting.sensor import parse_sensor_rotation

    body = cs.load_body("kane_levinson_1982")
    model = cs.SlidingModel(
        friction_coefficient=FRICTION_COEFFICIENT, contact_radius=CONTACT_RADIUS
    )
    sampled = RELEASE_OFFSET + times
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cs.FrictionBoundWarning)
        run = cs.simulate(model, body, cs.InitialState(), float(sampled[-1]), sample_times=sampled)
    rotation = parse_sensor_rotation(SENSOR_ROTATION)  # omega_body = R omega_sensor
    return run.samples.values("omega") @ rotation  # rows: (R.T omega_body).T


def sample_times() -> np.ndarray:
    rng = np.random.default_rng(SEED)
    count = round(DURATION * RATE)
    times = np.arange(count) / RATE + rng.uniform(-JITTER, JITTER, count)
    times[0] = 0.0
    return times


def write_sample(path: Path = SAMPLE) -> None:
    times = sample_times()
    rng = np.random.default_rng(SEED + 1)
    rates = (
        clean_sensor_rates(times) + np.array(SENSOR_BIAS) + rng.normal(0.0, NOISE, (times.size, 3))
    )
    lines = [HEADER]
    for t, (x, y, z) in zip(times, rates, strict=True):
        lines.append(f"{t:.9E},{x:.9E},{y:.9E},{z:.9E},{math.sqrt(x * x + y * y + z * z):.9E}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    write_sample()
