"""Quasi-static loaded contact analysis (LTCA) of the whole reducer: the dynamic model's force
elements at zero speed, solved for static equilibrium.

Names load on first use (the compiled solver imports numba), see :mod:`lazy_loader`.
"""

import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach(__name__, submod_attrs={
    "transmission": ["ltca", "LtcaResult", "solve_path"],
    "torque_reversal": ["hysteresis", "HysteresisResult"],
    "efficiency": ["efficiency", "EfficiencyResult"],
    "budget": ["compliance_budget", "ComplianceBudget"],
    "bearing_life": ["life", "LifeResult"],
})
