"""Compile options shared by the kernel's force elements (docs/decisions.md, "reference
counting")."""

from __future__ import annotations

try:        # Numba's private option that compiles a function without reference counting
    from numba.core.cpu import CPUTargetOptions

    _NRT_OPTION = hasattr(CPUTargetOptions, "_nrt")
except ImportError:        # pragma: no cover - a Numba without that module
    _NRT_OPTION = False

__all__ = ["NO_REFCOUNT", "REFCOUNT"]

#: ``numba.njit`` options of an element that allocates nothing: cached, with numpy's error model
#: (a division by zero gives inf or nan instead of a check and an exception: the kernel raises
#: nothing and reports non-finite states by its status), and compiled without reference
#: counting where this Numba offers the option (issue 14: 6 % of a run on AMD EPYC, 21 % on
#: Intel Xeon, where the atomic counts cost more); a Numba that drops the option compiles the
#: same code with reference counting instead of failing.  Numba's callees inherit both options
#: from the function that compiles them unless they set them themselves
NO_REFCOUNT = {"cache": True, "error_model": "numpy",
               **({"_nrt": False} if _NRT_OPTION else {})}

#: ``numba.njit`` options of a function that allocates and is called from a function compiled
#: with NO_REFCOUNT: it would inherit the caller's missing reference counting (and fail to
#: compile), so it sets it explicitly
REFCOUNT = {"cache": True, "error_model": "numpy", **({"_nrt": True} if _NRT_OPTION else {})}
