"""Analysis: spin reversals of finished runs (defined in ``celtstone.reversals``); linear
stability of steady spin."""

from celtstone.analysis.stability import SpinStability as SpinStability
from celtstone.analysis.stability import spin_stability as spin_stability
from celtstone.reversals import REVERSAL_BAND_FRACTION as REVERSAL_BAND_FRACTION
from celtstone.reversals import dataset_reversal_times as dataset_reversal_times
from celtstone.reversals import reversal_band as reversal_band
from celtstone.reversals import reversal_times as reversal_times

__all__ = [
    "REVERSAL_BAND_FRACTION",
    "SpinStability",
    "dataset_reversal_times",
    "reversal_band",
    "reversal_times",
    "spin_stability",
]
