"""Exceptions rvsim raises for problems a user can fix.

Every user-facing error is a :class:`RvsimError`; the CLI prints its message on one line and
exits with code 2.  Messages name the offending field and the reason.
"""

from __future__ import annotations

__all__ = ["RvsimError", "ParameterError", "SimulationError", "InputFileError", "Terminated",
           "check_type"]


class RvsimError(Exception):
    """Base class of errors caused by user input or by a failed computation."""


class ParameterError(RvsimError, ValueError):
    """A parameter is unknown, malformed or physically invalid.

    ``field`` is the dotted parameter name (as listed by ``rvsim params``).
    """

    def __init__(self, field: str, reason: str):
        self.field = field
        self.reason = reason
        super().__init__(f"parameter '{field}': {reason}")


def check_type(value, kind, field: str, what: str):
    """``value`` if it is a ``kind`` (a class or a tuple of classes), else a
    :class:`ParameterError` naming ``field``: "must be ``what`` (got <type>)" (a notebook's
    ``rvsim.ltca("RV-40E")`` was an AttributeError from inside the engine)."""
    if not isinstance(value, kind):
        raise ParameterError(field, f"must be {what} (got {type(value).__name__})")
    return value


class InputFileError(RvsimError):
    """An input file (TOML, CSV) cannot be read or has the wrong structure."""


class SimulationError(RvsimError):
    """The dynamic simulation stopped with a non-success status."""

    def __init__(self, status: str, message: str):
        self.status = status
        super().__init__(message)


class Terminated(KeyboardInterrupt):
    """The process received SIGTERM or SIGHUP: unwinds like Ctrl-C (temporary files removed,
    a study's finished rows kept); the command line ends with exit code 143."""
