"""The dynamic virtual prototype: contact dynamics of the whole RV reducer.

Names load on first use (the compiled kernel imports numba), see :mod:`lazy_loader`.
"""

import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach(__name__, submod_attrs={
    "result": ["Result", "te_metrics", "te_spectrum"],
    "simulate": ["simulate", "decompose_te", "DEFAULT_TIME_STEP", "DEFAULT_SAMPLE_RATE"],
})
