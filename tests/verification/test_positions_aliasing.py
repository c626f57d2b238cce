"""The positions floor (rvsim.analysis.sampling, issue 30) is where the pin order stops
aliasing: paper run 2's peak-to-peak TE collapses one position below it and is within 1.4 %
of the value at 4 zp (0.2613 arcmin, as at 1440 positions) at it (docs/decisions.md)."""

from __future__ import annotations

import pytest

from rvsim.parameters import RV40E, paper_run_values, with_values
from rvsim.quasistatic import ltca


def test_the_floor_resolves_the_pin_order_of_paper_run_2():
    from rvsim.analysis.sampling import minimum_positions

    run2 = with_values(RV40E, paper_run_values(2))
    floor = minimum_positions(run2)
    assert floor == 2 * run2.cycloid.pin_count + 1 == 81

    def pp(n):
        return ltca(run2, positions=n, allow_aliasing=True).summary()["te_pp_arcmin"]

    resolved = pp(4 * run2.cycloid.pin_count)          # samples on the peaks: 0.26132
    assert resolved == pytest.approx(0.26132, rel=1e-4)
    assert pp(floor) == pytest.approx(resolved, rel=0.02)              # 0.25755: -1.4 %
    assert pp(floor - 1) < 0.02 * resolved                             # 0.00387: aliased
