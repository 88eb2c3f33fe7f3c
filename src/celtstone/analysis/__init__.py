"""Analysis of finished runs: spin reversals with a stated definition."""

from celtstone.analysis.reversals import REVERSAL_BAND_FRACTION as REVERSAL_BAND_FRACTION
from celtstone.analysis.reversals import dataset_reversal_times as dataset_reversal_times
from celtstone.analysis.reversals import reversal_band as reversal_band
from celtstone.analysis.reversals import reversal_times as reversal_times

__all__ = ["REVERSAL_BAND_FRACTION", "dataset_reversal_times", "reversal_band", "reversal_times"]
