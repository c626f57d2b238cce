"""The dynamic virtual prototype: contact dynamics of the whole RV reducer."""

from .result import Result, te_metrics, te_spectrum
from .simulate import DEFAULT_SAMPLE_RATE, DEFAULT_TIME_STEP, decompose_te, simulate

__all__ = ["simulate", "decompose_te", "Result", "te_metrics", "te_spectrum", "DEFAULT_TIME_STEP", "DEFAULT_SAMPLE_RATE"]
