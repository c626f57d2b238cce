"""rvsim: transmission error of RV (rotate vector) reducers, from geometry to statistics.

The top level imports lazily (``lazy_loader``): parameters and errors are light and load at
once; the dynamic model (numba), the studies and the analysis load on first use, so the
command line starts in a fraction of a second.
"""

from importlib.metadata import PackageNotFoundError, version

import lazy_loader

from .errors import InputFileError, ParameterError, RvsimError, SimulationError
from .parameters import RV40E, Reducer, load_toml, with_values

try:
    __version__ = version("rvsim")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0+unknown"

_lazy_getattr, _lazy_dir, _ = lazy_loader.attach(
    __name__, submod_attrs={"dynamics": ["simulate", "decompose_te", "Result"],
                            "quasistatic": ["ltca", "hysteresis", "life"]})

__all__ = ["Reducer", "RV40E", "load_toml", "with_values", "simulate", "decompose_te", "Result",
           "ltca", "hysteresis", "life", "RvsimError", "ParameterError", "InputFileError", "SimulationError", "__version__"]


def __getattr__(name: str):
    return _lazy_getattr(name)


def __dir__():
    return sorted(set(__all__) | set(_lazy_dir()))
