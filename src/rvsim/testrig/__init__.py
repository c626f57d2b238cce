"""Test-bench data: import of encoder recordings, the standard analyses (the catalogue's, through
:mod:`rvsim.analysis.catalogue`), the model side by side, calibration of uncertain parameters to
them and to loop curves and efficiency points (:mod:`rvsim.testrig.curves`).

Names load on first use (:mod:`lazy_loader`).
"""

import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach(__name__, submod_attrs={
    "recording": ["Recording", "ColumnMap", "read_recording", "read_column_map"],
    "bench": ["analyse_path", "PointResult", "FileResult"],
    "model": ["point_summary", "compare_point", "simulate_point"],
    "calibration": ["calibrate", "Calibration"],
    "curves": ["read_loop", "read_efficiency", "loop_table", "LoopCurve", "EfficiencyPoints"],
    "synthetic": ["te_recording", "reversal_recording"],
})
