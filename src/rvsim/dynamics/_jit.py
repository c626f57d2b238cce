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
#: same code with reference counting instead of failing.  Numba keys compiled code by argument
#: types only, so a function that set no options would keep those of whichever function
#: compiled it first: every compiled kernel function that is not inlined states NO_REFCOUNT
#: or REFCOUNT (tests/unit/test_jit_options.py)
NO_REFCOUNT = {"cache": True, "error_model": "numpy",
               **({"_nrt": False} if _NRT_OPTION else {})}

#: ``numba.njit`` options of a kernel function that allocates (it may be called from a
#: NO_REFCOUNT one: it counts its own references)
REFCOUNT = {"cache": True, "error_model": "numpy", **({"_nrt": True} if _NRT_OPTION else {})}
