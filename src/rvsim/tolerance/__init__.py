"""Tolerances: per-part errors drawn from tolerances, Monte Carlo, Sobol indices, allocation.

Names load on first use, see :mod:`lazy_loader`.
"""

import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach(__name__, submod_attrs={
    "spec": ["FEATURES", "Tolerance", "ToleranceStudy", "load_tolerance_study",
             "rv40e_tolerances", "cycloid_drive_tolerances", "BUILT_IN_TOLERANCE_STUDIES",
             "is_tolerance_file"],
    "analysis": ["tolerance_analysis"],
    "engine": ["evaluate_sample", "METRICS"],
    "allocation": ["allocate", "parse_targets", "CostModel"],
})
