"""Range analysis of an orthogonal-array study (paper Eq. 23, Table 3 bottom rows)."""

from __future__ import annotations

import dataclasses

import pandas as pd

from ._table import check_design_table, factor_columns

__all__ = ["RangeAnalysis", "range_analysis"]


@dataclasses.dataclass(frozen=True)
class RangeAnalysis:
    """Level means k_i, range R, factor order and the smaller-is-better optimum."""

    response: str
    level_means: dict[str, list[float]]
    ranges: dict[str, float]
    grand_mean: float

    @property
    def order(self) -> list[str]:
        """Factors by decreasing range (ties keep column order)."""
        return sorted(self.ranges, key=lambda f: -self.ranges[f])

    @property
    def optimum(self) -> dict[str, int]:
        """Level (1-based) with the smallest mean response, per factor."""
        return {f: int(min(range(len(k)), key=k.__getitem__)) + 1
                for f, k in self.level_means.items()}

    def to_dict(self) -> dict:
        return {"range": {f: {"k": k, "R": self.ranges[f]} for f, k in self.level_means.items()},
                "order": ">".join(self.order), "optimum": self.optimum}

    def to_df(self) -> pd.DataFrame:
        width = max(len(k) for k in self.level_means.values())
        rows = {f"k{i + 1}": [k[i] if i < len(k) else float("nan")
                              for k in self.level_means.values()] for i in range(width)}
        frame = pd.DataFrame(rows, index=list(self.level_means))
        frame["R"] = [self.ranges[f] for f in self.level_means]
        frame["rank"] = [self.order.index(f) + 1 for f in self.level_means]
        frame["optimal_level"] = [self.optimum[f] for f in self.level_means]
        return frame

    def plot(self, ax=None):
        """Main-effect plot (level mean against level per factor, like the paper's Figs. 8-10)."""
        from ..plots import main_effects_plot

        return main_effects_plot(self, ax=ax)


def range_analysis(table: pd.DataFrame, response: str = "te_arcmin", factors=None
                   ) -> RangeAnalysis:
    """Level means and ranges of ``response`` for each factor column of ``table``."""
    factors = factor_columns(table, response, factors)
    data = check_design_table(table, response, factors)
    means = {f: [float(v) for v in data.groupby(f)[response].mean().sort_index()]
             for f in factors}
    ranges = {f: max(k) - min(k) for f, k in means.items()}
    return RangeAnalysis(response, means, ranges, float(data[response].mean()))
