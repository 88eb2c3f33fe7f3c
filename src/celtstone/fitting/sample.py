"""The sample gyroscope record shipped with celtstone, for the fitting guide.

Made by celtstone (``tests/fit_sample.py`` in the source tree): Kane & Levinson's stone,
the sliding model with f = 0.3 and ε = 0.8 mm, released at ω = (0, 0, −5) rad/s with
Euler angles 0.5°, 0.5°; phyphox's gyroscope export of a phone whose x, y, z axes are the
body's −y, x, z, its first sample 0.25 s after the release, 4 s at 100 Hz with ±1 ms
timing jitter, white noise 0.02 rad/s and a bias of (0.01, −0.005, 0.008) rad/s on its
x, y, z axes.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

__all__ = ["SAMPLE_SENSOR_ROTATION", "sample_record_path"]

SAMPLE_SENSOR_ROTATION = "-y,x,z"  # the phone's x, y, z axes in body axes


def sample_record_path() -> Path:
    """The path of the sample record ``sample_phyphox.csv`` (phyphox's gyroscope export).

    Returns
    -------
    pathlib.Path
        The installed file; read it with ``read_record(path, sensor_rotation="-y,x,z")``.
    """
    return Path(str(resources.files("celtstone.fitting") / "data" / "sample_phyphox.csv"))
