"""The "how far to trust it" figures have one source, src/rvsim/data/trust.csv (issue 34
item 1): README.md and docs/validation.md hold exactly what scripts/trust_box.py renders from
it, and its paper figures are those of the stored L36 comparison (docs/validation_data)."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pandas as pd
from scipy.stats import spearmanr

from rvsim.analysis.trust import catalogue_figure, trust_rows
from rvsim.html import trust_box

ROOT = Path(__file__).resolve().parents[2]


def _script():
    spec = importlib.util.spec_from_file_location("trust_box", ROOT / "scripts/trust_box.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_readme_and_validation_are_generated_from_the_csv():
    script = _script()
    for path, render in script.TARGETS.items():
        text = path.read_text(encoding="utf-8")
        assert script.replaced(text, render()) == text, (
            f"{path.name} disagrees with src/rvsim/data/trust.csv: run "
            "python scripts/trust_box.py (do not edit the generated text by hand)")


def test_paper_rows_are_the_measured_comparison():
    summary = json.loads((ROOT / "docs/validation_data/summary.json").read_text())
    runs = pd.read_csv(ROOT / "docs/validation_data/l36_comparison.csv")
    row = {r["key"]: r for r in trust_rows("paper")}
    lo, hi = summary["model_te_range"]
    assert row["paper_te_mean"]["model"] == f"{lo:.2f}-{hi:.2f} arcmin"
    lo, hi = summary["paper_te_range"]
    assert row["paper_te_mean"]["published"].startswith(f"{lo:.2f}-{hi:.2f} arcmin")
    ratio = runs["te_mean_arcmin"] / runs["te_arcmin"]
    assert row["paper_te_mean"]["ratio"] == (f"{ratio.min():.1f}-{ratio.max():.1f} per run "
                                             f"(median {ratio.median():.1f})")
    assert row["paper_run_order"]["model"] == (f"rho = {summary['spearman']:.2f} "
                                               f"(p = {summary['spearman_p']:.3f})")
    model, paper = summary["model_order"].split(">"), summary["paper_order"].split(">")
    rho = spearmanr([model.index(f) for f in model], [paper.index(f) for f in model])[0]
    assert row["paper_factor_order"]["ratio"].startswith(f"rank correlation {rho:.2f} ")
    assert row["paper_factor_order"]["model"] == " > ".join(model)
    assert row["paper_factor_order"]["published"] == " > ".join(paper)
    signs = summary["main_effects"]
    same = [f for f, s in signs.items() if s["model"] == s["paper"]]
    assert row["paper_signs"]["model"] == f"same sign for {len(same)} of {len(signs)} factors"
    assert row["paper_signs"]["ratio"] == ", ".join(sorted(set(signs) - set(same))) + " differ"
    assert row["paper_significant"]["model"].startswith(
        f"{len(summary['model_significant_0.1'])} of {len(signs)}")
    assert row["paper_significant"]["published"].startswith(
        ", ".join(summary["paper_significant_0.1"]))


def test_catalogue_numbers_and_html_box():
    assert catalogue_figure("rigidity")["low"] == 113.0
    assert catalogue_figure("lost_motion")["limit"] == 1.0
    assert catalogue_figure("efficiency_rated")["low"] is None
    box = trust_box()
    assert box.startswith("<details class='trust'")
    for figure in ("4.5-15.4", "rank correlation 0.71", "5.2 / 9.3 / 5.9", "2.14"):
        assert figure in box
