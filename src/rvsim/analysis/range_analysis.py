"""Range analysis of an orthogonal-array study (paper Eq. 23, Table 3 bottom rows)."""

from __future__ import annotations

import dataclasses

import pandas as pd

from ._table import UNBALANCED_NOTE, check_design_table, factor_columns, is_balanced

__all__ = ["RangeAnalysis", "range_analysis", "larger_is_better"]

#: a robust study's S/N columns (rvsim.analysis.signal_noise): larger is better
_SN_SUFFIXES = ("_sn", "_sn_smaller", "_sn_nominal", "_sn_larger")


def larger_is_better(response: str) -> bool:
    """Whether a larger ``response`` is the better: a Taguchi S/N ratio column (a robust
    study's ``..._sn``, ``..._sn_smaller``, ...); every other response is smaller-is-better
    (the paper's TE)."""
    return str(response).endswith(_SN_SUFFIXES)


@dataclasses.dataclass(frozen=True)
class RangeAnalysis:
    """Level means k_i, range R, factor order and the smaller-is-better optimum (larger for
    an S/N ratio column).

    ``levels[f]`` holds the level numbers that occur in column ``f`` (ascending) and
    ``level_means[f]`` the mean response at each of them, in the same order.
    """

    response: str
    level_means: dict[str, list[float]]
    ranges: dict[str, float]
    grand_mean: float
    levels: dict[str, list[int]]
    notes: tuple[str, ...] = ()
    #: whether the optimum is the largest level mean (None: :func:`larger_is_better`)
    larger: bool | None = None

    @property
    def order(self) -> list[str]:
        """Factors by decreasing range (ties keep column order)."""
        return sorted(self.ranges, key=lambda f: -self.ranges[f])

    @property
    def optimum(self) -> dict[str, int]:
        """The level number (as written in the table) with the smallest mean, per factor (the
        largest for an S/N ratio, :func:`larger_is_better`, or when ``larger``)."""
        larger = larger_is_better(self.response) if self.larger is None else self.larger
        best = max if larger else min
        return {f: self.levels[f][best(range(len(k)), key=k.__getitem__)]
                for f, k in self.level_means.items()}

    def mean_at(self, factor: str, level: int) -> float:
        """Mean response of ``factor`` at level number ``level``."""
        return self.level_means[factor][self.levels[factor].index(level)]

    def to_dict(self) -> dict:
        out = {"range": {f: {"k": k, "levels": self.levels[f], "R": self.ranges[f]}
                         for f, k in self.level_means.items()},
               "order": ">".join(self.order), "optimum": self.optimum}
        if self.notes:
            out["notes"] = list(self.notes)
        return out

    def to_df(self) -> pd.DataFrame:
        """One row per factor: k<level> for every level number present, R, rank, optimum."""
        every = sorted({lv for lvs in self.levels.values() for lv in lvs})
        rows = {f"k{lv}": [self.mean_at(f, lv) if lv in self.levels[f] else float("nan")
                           for f in self.level_means] for lv in every}
        frame = pd.DataFrame(rows, index=list(self.level_means))
        frame["R"] = [self.ranges[f] for f in self.level_means]
        frame["rank"] = [self.order.index(f) + 1 for f in self.level_means]
        frame["optimal_level"] = [self.optimum[f] for f in self.level_means]
        return frame

    def plot(self, ax=None):
        """Main-effect plot (level mean against level per factor, like the paper's Figs. 8-10)."""
        from .figures import main_effects_plot

        return main_effects_plot(self, ax=ax)


def range_analysis(table: pd.DataFrame, response: str = "te_arcmin", factors=None,
                   larger: bool | None = None) -> RangeAnalysis:
    """Level means and ranges of ``response`` for each factor column of ``table`` (the optimum
    the largest level mean when ``larger``; None: :func:`larger_is_better`)."""
    factors = factor_columns(table, response, factors)
    data = check_design_table(table, response, factors)
    groups = {f: data.groupby(f)[response].mean().sort_index() for f in factors}
    means = {f: [float(v) for v in g] for f, g in groups.items()}
    levels = {f: [int(lv) for lv in g.index] for f, g in groups.items()}
    ranges = {f: max(k) - min(k) for f, k in means.items()}
    notes = () if is_balanced(data, factors) else (UNBALANCED_NOTE,)
    return RangeAnalysis(response, means, ranges, float(data[response].mean()), levels, notes,
                         larger)
