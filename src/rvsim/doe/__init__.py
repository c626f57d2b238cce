"""Designs of experiments on the dynamic model: designs, study definitions, parallel runner.

Names load on first use (pyDOE3 and pandas are slow to import), see :mod:`lazy_loader`.
"""

import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach(__name__, submod_attrs={
    "designs": ["ORTHOGONAL_ARRAYS", "assign_columns", "full_factorial",
                "is_strength2_balanced", "latin_hypercube", "orthogonal_array", "sobol"],
    "outputs": ["write_study_outputs"],
    "result": ["StudyResult", "run_study"],
    "runner": ["evaluate", "run"],
    "store": ["ResultStore", "run_key"],
    "study": ["BUILT_IN_STUDIES", "Study", "StudyFactor", "load_study", "paper_l36"],
})
