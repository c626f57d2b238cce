"""rvsim: transmission error of RV (rotate vector) reducers, from geometry to statistics."""

from importlib.metadata import PackageNotFoundError, version

from .errors import InputFileError, ParameterError, RvsimError, SimulationError
from .dynamics import Result, decompose_te, simulate
from .parameters import RV40E, Reducer, load_toml, with_values

try:
    __version__ = version("rvsim")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0+unknown"

__all__ = ["Reducer", "RV40E", "load_toml", "with_values", "simulate", "decompose_te", "Result", "RvsimError", "ParameterError",
           "InputFileError", "SimulationError", "__version__"]
