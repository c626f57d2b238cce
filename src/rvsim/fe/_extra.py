"""The finite-element extra (``pip install 'rvsim[fe]'``): one check, one message, on every
path that meshes or assembles a body (issue 30: the crank's path imported scikit-fem before
the mesher's check and ended in a traceback)."""

from __future__ import annotations

import importlib

from ..errors import RvsimError

__all__ = ["require"]

#: the extra's modules (pyproject.toml, ``fe``), in the order they are first needed
MODULES = ("gmsh", "skfem", "cholespy")


def require() -> None:
    """Import the extra's modules, or raise one RvsimError saying what to install.  gmsh's
    wheel loads X and GL libraries when imported: a missing one is an OSError."""
    for name in MODULES:
        try:
            importlib.import_module(name)
        except (ImportError, OSError) as exc:
            raise RvsimError(f"flexibility.model: the finite-element route needs gmsh, "
                             f"scikit-fem and cholespy (pip install 'rvsim[fe]'; gmsh needs "
                             f"the Debian libraries libglu1-mesa libxcursor1 libxft2 "
                             f"libxinerama1): {exc}") from None
