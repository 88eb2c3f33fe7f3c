"""Analysis of finished runs: spin reversals with a stated definition."""

from celtstone.analysis.reversals import reversal_times as reversal_times

__all__ = ["reversal_times"]
