"""Transmission error of RV (rotate vector) reducers and cycloid drives, geometry to statistics.

Quick start (in a notebook every result shows its headline figures; SI inside)::

    import rvsim
    r = rvsim.with_values(rvsim.RV40E, {"H": 0.02})   # a built-in set, factor H changed
    run = rvsim.simulate(r)             # dynamic run: TE over time (Result)
    rvsim.ltca(r, torque=412.0)         # loaded TE over an output revolution, contact stress
    rvsim.hysteresis(r)                 # torque reversal: rigidity, lost motion, backlash
    rvsim.efficiency(r)                 # efficiency map, running and starting torque
    rvsim.life(rvsim.BUILT_IN_SETS["RV-40E-bearings"])   # rolling bearings' life (ISO 281)
    study = rvsim.run_study(rvsim.paper_l36(), "study")   # a design of experiments
    study.analysis()                    # range analysis, ANOVA, S/N ratios (DataFrames)

Results have ``.summary()`` (the command line's JSON keys), ``.to_frame()`` (a DataFrame,
units in the column names) and ``.plot(ax=None)`` (matplotlib; returns the Axes).

Also here: the sets ``CYCLOID_DRIVE``, ``BUILT_IN_SETS`` (by name), ``load_toml``,
``Reducer``; ``decompose_te``, ``compliance_budget``; studies ``load_study``,
``BUILT_IN_STUDIES``; tolerances ``load_tolerance_study``, ``BUILT_IN_TOLERANCE_STUDIES``,
``tolerance_analysis``, ``allocate``; bench data ``read_recording``, ``analyse_path``,
``calibrate``; errors ``RvsimError``, ``ParameterError``, ``SimulationError``.

Docs: ``help(rvsim.simulate)`` etc.; docs/user_guide.md (the same from a shell: ``rvsim
--help``), docs/parameters.md (every parameter, unit, source), docs/model.md (the physics).
"""

from importlib import import_module
from importlib.metadata import PackageNotFoundError, version

from .errors import InputFileError, ParameterError, RvsimError, SimulationError
from .parameters import BUILT_IN_SETS, RV40E, Reducer, load_toml, with_values
from .parameters.cycloid_drive import CYCLOID_DRIVE

try:
    __version__ = version("rvsim")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0+unknown"

#: names loaded on first use: top-level name -> (module, name there)
_LAZY = {
    "simulate": ("dynamics.simulate", "simulate"),
    "decompose_te": ("dynamics.simulate", "decompose_te"),
    "Result": ("dynamics.result", "Result"),
    "ltca": ("quasistatic.transmission", "ltca"),
    "hysteresis": ("quasistatic.torque_reversal", "hysteresis"),
    "efficiency": ("quasistatic.efficiency", "efficiency"),
    "life": ("quasistatic.bearing_life", "life"),
    "compliance_budget": ("quasistatic.budget", "compliance_budget"),
    "analyze_table": ("analysis", "analyze_table"),
    "load_study": ("doe.study", "load_study"),
    "paper_l36": ("doe.study", "paper_l36"),
    "BUILT_IN_STUDIES": ("doe.study", "BUILT_IN_STUDIES"),
    "run_study": ("doe.result", "run_study"),
    "load_tolerance_study": ("tolerance.spec", "load_tolerance_study"),
    "BUILT_IN_TOLERANCE_STUDIES": ("tolerance.spec", "BUILT_IN_TOLERANCE_STUDIES"),
    "tolerance_analysis": ("tolerance.analysis", "tolerance_analysis"),
    "allocate": ("tolerance.allocation", "allocate"),
    "read_recording": ("testrig.recording", "read_recording"),
    "analyse_path": ("testrig.bench", "analyse_path"),
    "calibrate": ("testrig.calibration", "calibrate"),
}

# What ``help(rvsim)`` lists besides the docstring (pydoc shows the names of __all__ only, a
# class with every method: the errors were 450 of its 596 lines): the paper's set.  The calls
# are in the docstring, each with its own help; every name of _LAZY, the other sets and the
# errors import by name (``from rvsim import simulate, ParameterError``).
__all__ = ["RV40E", "__version__"]


def __getattr__(name: str):
    if name not in _LAZY:
        raise AttributeError(f"module 'rvsim' has no attribute {name!r}")
    module, attribute = _LAZY[name]
    value = getattr(import_module(f"{__name__}.{module}"), attribute)
    globals()[name] = value                 # once: the next access is a plain lookup
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
