"""Compile options shared by the kernel's force elements (docs/decisions.md, "reference
counting")."""

from __future__ import annotations

try:        # Numba's private option that compiles a function without reference counting
    from numba.core.cpu import CPUTargetOptions

    _NRT_OPTION = hasattr(CPUTargetOptions, "_nrt")
except ImportError:        # pragma: no cover - a Numba without that module
    _NRT_OPTION = False

__all__ = ["NO_REFCOUNT", "REFCOUNT"]

#: ``numba.njit`` options of an element that allocates nothing: cached, and compiled without
#: reference counting where this Numba offers the option (about 6 % of a run); a Numba that
#: drops it compiles the same code with reference counting instead of failing
NO_REFCOUNT = {"cache": True, **({"_nrt": False} if _NRT_OPTION else {})}

#: ``numba.njit`` options of a function that allocates and is called from a function compiled
#: with NO_REFCOUNT: Numba's callees inherit the caller's reference counting unless they set
#: it themselves, so it is set explicitly
REFCOUNT = {"cache": True, **({"_nrt": True} if _NRT_OPTION else {})}
