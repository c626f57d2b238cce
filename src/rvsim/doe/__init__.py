"""Designs of experiments on the dynamic model: designs, study definitions, parallel runner."""

from .designs import (ORTHOGONAL_ARRAYS, assign_columns, full_factorial, is_strength2_balanced,
                      latin_hypercube, orthogonal_array, sobol)
from .outputs import write_study_outputs
from .runner import evaluate, run
from .store import ResultStore, run_key
from .study import BUILT_IN_STUDIES, Study, StudyFactor, load_study, paper_l36

__all__ = ["Study", "StudyFactor", "paper_l36", "load_study", "BUILT_IN_STUDIES", "run",
           "evaluate", "write_study_outputs", "ResultStore", "run_key", "ORTHOGONAL_ARRAYS", "orthogonal_array",
           "assign_columns", "is_strength2_balanced", "full_factorial", "latin_hypercube",
           "sobol"]
