"""Fitting a measured motion: the friction coefficient, contact size, rolling resistance,
damping or initial state that explain a record, with honest uncertainties.

>>> import celtstone as cs
>>> record = cs.read_record("gyro.csv", sensor_rotation="x,-z,y")  # doctest: +SKIP
>>> free = ["friction_coefficient", "contact_radius"]
>>> result = cs.fit(record, "toy_rattleback_10cm", "sliding", free)  # doctest: +SKIP
>>> result.summary()["parameters"]  # doctest: +SKIP

Named ``fitting``, not ``fit``: a submodule ``celtstone.fit`` would replace the function
``celtstone.fit`` as soon as it was imported.
"""

from celtstone.fitting.record import Record as Record
from celtstone.fitting.record import make_record as make_record
from celtstone.fitting.record import read_record as read_record
from celtstone.fitting.result import FitResult as FitResult
from celtstone.fitting.sample import sample_record_path as sample_record_path
from celtstone.fitting.series import SERIES as SERIES
from celtstone.fitting.solve import fit as fit

__all__ = [
    "SERIES",
    "FitResult",
    "Record",
    "fit",
    "make_record",
    "read_record",
    "sample_record_path",
]
