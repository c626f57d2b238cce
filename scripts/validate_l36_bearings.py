"""The paper's L36 on RV-40E-bearings (issue 10): K-O act as the rolling bearings' radial play.

Runs the study on the dynamic model into OUT/study, writes OUT/l36_comparison.csv (each run's
factors, the paper's Table 3 TE and the model's) and prints the figures docs/validation.md
reports (range, correlation with Table 3, factor order, range of E, largest energy residual).

Usage:  python scripts/validate_l36_bearings.py [--out bearings_l36]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

from scipy.stats import pearsonr, spearmanr

from rvsim.analysis import analyze_table
from rvsim.doe import paper_l36, run
from rvsim.parameters import BUILT_IN_SETS, paper_l36_scheme

LETTERS = list("ABCDEFGHIJKLMNO")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="bearings_l36")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    study = dataclasses.replace(paper_l36(), name="paper-l36-bearings", scheme="explicit",
                                base=BUILT_IN_SETS["RV-40E-bearings"])
    results = run(study, out / "study", progress=False)
    table = paper_l36_scheme()[["run"] + LETTERS + ["te_arcmin"]].merge(
        results[["run", "te_mean_arcmin", "te_pp_arcmin", "energy_residual", "status"]],
        on="run")
    table.to_csv(out / "l36_comparison.csv", index=False)
    model = analyze_table(table, "te_mean_arcmin", LETTERS)
    print(json.dumps({
        "status": table["status"].value_counts().to_dict(),
        "te_mean_range": [table["te_mean_arcmin"].min(), table["te_mean_arcmin"].max()],
        "te_pp_range": [table["te_pp_arcmin"].min(), table["te_pp_arcmin"].max()],
        "spearman": spearmanr(table["te_arcmin"], table["te_mean_arcmin"]).statistic,
        "spearman_p": spearmanr(table["te_arcmin"], table["te_mean_arcmin"]).pvalue,
        "pearson": pearsonr(table["te_arcmin"], table["te_mean_arcmin"]).statistic,
        "model_order": model["order"], "range_E": model["range"]["E"]["R"],
        "max_abs_energy_residual": table["energy_residual"].abs().max()},
        indent=2, default=float))


if __name__ == "__main__":
    main()
