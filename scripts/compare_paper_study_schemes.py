"""The paper's L36 study under both integration schemes: does the study's analysis change?

Runs ``paper_l36()`` with the explicit scheme (5e-6 s) and with ``implicit-bearings`` (2e-5 s,
the study's scheme since 2026-11-26) into ``OUT/explicit`` and ``OUT/implicit-bearings``
(resumable: finished runs are kept), analyses both on the mean TE as ``rvsim study`` does and
prints what docs/decisions.md ("The paper's study runs implicit-bearings") reports: factor
order, significant factors, optimum, S/N ranks, the largest change of a range R, a level
mean and an ANOVA p-value, the predicted optimum, and per run the relative change of the
mean TE, the peak-to-peak TE and the largest pin force (median, largest, which run).

Usage:  python scripts/compare_paper_study_schemes.py [--out schemes_l36] [--workers N]
(about a minute on 2 cores with a warm cache)
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

from rvsim.analysis import analyze_table
from rvsim.doe import paper_l36, run

LETTERS = list("ABCDEFGHIJKLMNO")
SCHEMES = ("explicit", "implicit-bearings")
PER_RUN = ("te_mean_arcmin", "te_pp_arcmin", "max_pin_force_n")


def _largest(changes: dict) -> tuple[str, float]:
    key = max(changes, key=lambda k: abs(changes[k]))
    return key, changes[key]


def compare(reference: dict, other: dict) -> dict:
    """The changes from ``reference`` to ``other`` (two :func:`analyze_table` results)."""
    ranges_r = {f: other["range"][f]["R"] - reference["range"][f]["R"] for f in LETTERS}
    level_means = {f"{f}{i + 1}": (b - a) / a for f in LETTERS for i, (a, b) in
                   enumerate(zip(reference["range"][f]["k"], other["range"][f]["k"]))}
    p_values = {f: other["anova"][f]["p"] - reference["anova"][f]["p"] for f in LETTERS}
    return {
        "order": [reference["order"], other["order"]],
        "same_order": reference["order"] == other["order"],
        "same_significant": reference["significant"] == other["significant"],
        "significant": other["significant"],
        "same_optimum": reference["optimum"] == other["optimum"],
        "same_sn_ranks": all(reference["sn_response"][f]["rank"] ==
                             other["sn_response"][f]["rank"] for f in LETTERS),
        "largest_range_change_arcmin": _largest(ranges_r),
        "largest_range_R_arcmin": max(reference["range"][f]["R"] for f in LETTERS),
        "largest_level_mean_change_rel": _largest(level_means),
        "largest_p_change": _largest(p_values),
        "predicted_optimum_arcmin": [reference["prediction"]["predicted"],
                                     other["prediction"]["predicted"]],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="schemes_l36")
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args()
    tables, analyses = {}, {}
    for scheme in SCHEMES:
        study = dataclasses.replace(paper_l36(), scheme=scheme)
        tables[scheme] = run(study, Path(args.out) / scheme, workers=args.workers,
                             progress=False)
        analyses[scheme] = analyze_table(tables[scheme], "te_mean_arcmin", LETTERS)
    summary = compare(*analyses.values())
    ref, other = tables.values()
    summary["status"] = {s: t["status"].value_counts().to_dict() for s, t in tables.items()}
    for column in PER_RUN:
        change = ((other[column] - ref[column]) / ref[column]).abs()
        summary[f"{column}_change_rel"] = {
            "median": change.median(), "largest": change.max(),
            "run": int(ref["run"][change.idxmax()]), "runs_within_1e-3": int((change < 1e-3).sum())}
    print(json.dumps(summary, indent=2, default=float))


if __name__ == "__main__":
    main()
