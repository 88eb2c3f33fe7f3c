"""Analysis: spin reversals of finished runs; linear stability of steady spin."""

from celtstone.analysis.reversals import reversal_times as reversal_times
from celtstone.analysis.stability import SpinStability as SpinStability
from celtstone.analysis.stability import spin_stability as spin_stability

__all__ = ["SpinStability", "reversal_times", "spin_stability"]
