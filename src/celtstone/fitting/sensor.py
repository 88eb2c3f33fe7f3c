"""The orientation of a gyroscope on the body: sensor components -> body components."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from celtstone.errors import ParameterError

__all__ = ["parse_sensor_rotation"]

_AXES = {"x": 0, "y": 1, "z": 2, "1": 0, "2": 1, "3": 2}
_ALLOWED = (
    "the sensor's x, y, z axes as signed body axes (x,-z,y) or 9 numbers R11,...,R33 "
    "(rows of a rotation: omega_body = R omega_sensor)"
)
_ORTHONORMAL_TOLERANCE = 1e-6


def _signed_axis(text: str) -> np.ndarray:
    sign = -1.0 if text.startswith("-") else 1.0
    axis = _AXES.get(text.lstrip("+-"))
    if axis is None:
        raise ValueError(text)
    return sign * np.eye(3)[axis]


def parse_sensor_rotation(value: str | Sequence[float] | None) -> np.ndarray:
    """R [1], shape (3, 3), with ω_body = R ω_sensor: a proper rotation.

    Parameters
    ----------
    value : None (the sensor's axes are the body's); ``"x,-z,y"``: the sensor's x, y and z
        axes along body axis x, along −z and along y (columns of R; ``1,2,3`` also name
        the body axes); or 9 numbers, R row by row (a string "R11,R12,...,R33" or a
        sequence)

    Raises
    ------
    ParameterError
        naming ``sensor_rotation`` unless R is orthonormal with determinant +1 (a
        gyroscope's axes are right-handed) to 1e-6.
    """
    if value is None:
        return np.eye(3)
    parts = [p.strip().lower() for p in value.split(",")] if isinstance(value, str) else value
    try:
        if len(parts) == 3:
            rotation = np.column_stack([_signed_axis(str(p)) for p in parts])
        elif len(parts) == 9:
            rotation = np.array([float(p) for p in parts]).reshape(3, 3)
        else:
            raise ValueError(value)
    except (TypeError, ValueError):
        raise ParameterError("sensor_rotation", value, _ALLOWED) from None
    error = np.max(np.abs(rotation @ rotation.T - np.eye(3)))
    if not (error <= _ORTHONORMAL_TOLERANCE and abs(np.linalg.det(rotation) - 1.0) <= 1e-6):
        raise ParameterError(
            "sensor_rotation", value, _ALLOWED, "a rotation: orthonormal, determinant +1"
        )
    return rotation
