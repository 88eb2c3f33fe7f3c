"""Parameter sweeps: grids or lists of points, run in compiled batches, stored in Zarr.

>>> from celtstone.sweep import Sweep
>>> sweep = Sweep({"friction_coefficient": [0.1, 0.35], "initial_spin": [-5.0, 5.0]}, t_end=10.0)
>>> results = sweep.run("sweep.zarr")  # doctest: +SKIP

A sweep is sized from its counts before any point is made (``budget``: limits, and
the estimate of store size and time); ``points.read_points`` reads a CSV of points.
"""

from celtstone.sweep.points import read_points as read_points
from celtstone.sweep.runner import DEFAULT_ATOL as DEFAULT_ATOL
from celtstone.sweep.runner import DEFAULT_RTOL as DEFAULT_RTOL
from celtstone.sweep.runner import SAMPLES_PER_SECOND as SAMPLES_PER_SECOND
from celtstone.sweep.runner import Sweep as Sweep
from celtstone.sweep.spec import PARAMETERS as PARAMETERS
from celtstone.sweep.spec import Axis as Axis
from celtstone.sweep.spec import AxisSpec as AxisSpec
from celtstone.sweep.spec import parse_axis as parse_axis
from celtstone.sweep.spec import parse_axis_spec as parse_axis_spec
from celtstone.sweep.spec import parse_setting as parse_setting
from celtstone.sweep.store import RESULT_FIELDS as RESULT_FIELDS
from celtstone.sweep.store import open_sweep as open_sweep

__all__ = [
    "DEFAULT_ATOL",
    "DEFAULT_RTOL",
    "PARAMETERS",
    "RESULT_FIELDS",
    "SAMPLES_PER_SECOND",
    "Axis",
    "AxisSpec",
    "Sweep",
    "open_sweep",
    "parse_axis",
    "parse_axis_spec",
    "parse_setting",
    "read_points",
]
