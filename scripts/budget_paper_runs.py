"""Measurement (not a test): the compliance budget of the paper's 36 L36 runs on the
quasi-static model, as ``rvsim hysteresis --paper-run N --budget`` computes it; prints each
run's status and shares and how many converged (docs/decisions.md, issue 30/32 fourth
session: 1 of 36 at 1e4 x before the continuation in the factor, 36 of 36 after).

Usage:  python scripts/budget_paper_runs.py [FACTOR [RUN ...]]   (default 1e4, runs 1-36)
"""

from __future__ import annotations

import sys
import time

from rvsim.friction import check_losses
from rvsim.parameters import RV40E, paper_run_values, with_values
from rvsim.quasistatic.budget import compliance_budget


def main(argv: list[str]) -> int:
    factor = float(argv[0]) if argv else 1e4
    runs = [int(a) for a in argv[1:]] or list(range(1, 37))
    converged, start = 0, time.process_time()
    for n in runs:
        budget = compliance_budget(check_losses(with_values(RV40E, paper_run_values(n))),
                                   factor=factor)
        converged += budget.status == "ok"
        shares = " ".join(f"{e}={100 * s:.1f}" for e, s in zip(budget.elements, budget.shares))
        print(f"{n:2d} {budget.status} {shares} residual={100 * budget.residual:.2f}",
              flush=True)
    print(f"converged {converged}/{len(runs)} at {factor:g} x, "
          f"{time.process_time() - start:.1f} s CPU")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
