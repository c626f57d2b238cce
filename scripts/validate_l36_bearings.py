"""The paper's L36 on RV-40E-bearings (issue 10): K-O as the rolling bearings' radial play.

Runs the study into /tmp/bear/l36b (argument 1 overrides), writes the comparison with Table 3
next to it and prints the figures docs/validation.md reports.

Usage:  python scripts/validate_l36_bearings.py [OUT]
"""
import sys
import dataclasses, json
from scipy.stats import pearsonr, spearmanr
from rvsim.analysis import analyze_table
from rvsim.doe import paper_l36, run
from rvsim.parameters import BUILT_IN_SETS, paper_l36_scheme
OUT = sys.argv[1] if len(sys.argv) > 1 else "/tmp/bear/l36b"
study = dataclasses.replace(paper_l36(), name="paper-l36-bearings", base=BUILT_IN_SETS["RV-40E-bearings"])
res = run(study, OUT, progress=False)
paper = paper_l36_scheme()
t = paper[["run"] + list("ABCDEFGHIJKLMNO") + ["te_arcmin"]].merge(res[["run", "te_mean_arcmin", "te_pp_arcmin", "energy_residual", "status"]], on="run")
t.to_csv(OUT + "/l36_comparison.csv", index=False)
m = analyze_table(t, "te_mean_arcmin", list("ABCDEFGHIJKLMNO"))
print(json.dumps({"status": t.status.value_counts().to_dict(), "range": [t.te_mean_arcmin.min(), t.te_mean_arcmin.max()],
  "pp": [t.te_pp_arcmin.min(), t.te_pp_arcmin.max()],
  "spearman": spearmanr(t.te_arcmin, t.te_mean_arcmin).statistic, "p": spearmanr(t.te_arcmin, t.te_mean_arcmin).pvalue,
  "pearson": pearsonr(t.te_arcmin, t.te_mean_arcmin).statistic, "order": m["order"],
  "E_range": m["range"]["E"]["R"], "max_res": float(t.energy_residual.abs().max())}, default=float))
