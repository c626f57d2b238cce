"""matplotlib, set up once for every figure of rvsim (issue 31 step 6: moved out of
:mod:`rvsim.plots` so that the figures of :mod:`rvsim.analysis` and the reports use it without
importing a higher layer).  Foundation layer: imports nothing of rvsim; matplotlib is imported
on the first call only (the command line starts without it, tests/unit/test_lazy_imports.py).
"""

from __future__ import annotations

__all__ = ["pyplot", "plain"]


def pyplot():
    """matplotlib.pyplot, imported on first use, with the non-interactive Agg backend unless
    one is already chosen: pyplot imported before (a notebook's ``import matplotlib.pyplot``)
    or ``MPLBACKEND`` set (Jupyter's kernel sets its inline backend so), so that a notebook's
    ``result.plot()`` shows and its other figures keep showing (issue 34 item 5)."""
    import os
    import sys

    try:
        import matplotlib
    except ValueError:
        # MPLBACKEND names no backend: matplotlib refuses it at import, and a report written
        # after its run ended in that traceback; the files need none, Agg draws them
        os.environ.pop("MPLBACKEND", None)
        for name in [m for m in sys.modules if m.split(".")[0] == "matplotlib"]:
            del sys.modules[name]              # the half-imported package, imported again
        import matplotlib

    if "matplotlib.pyplot" not in sys.modules and not os.environ.get("MPLBACKEND"):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plain(text) -> str:
    """A user's text (a factor label, a column name) as matplotlib draws it literally: a "$"
    would start its mathtext, and a label like "x$_$" failed the whole figure (a reviewer's
    study ended in a traceback after all its runs)."""
    return str(text).replace("$", r"\$")
