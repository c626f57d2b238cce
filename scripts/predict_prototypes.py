"""Predict the ATE bands of the paper's three test prototypes (issue 33, item 3).

Runs the tolerance Monte Carlo of docs/examples/table1_errors.toml (the paper's Table 1 part
errors) on each prototype file, with the paper's bushings (docs/examples/prototype_N.toml)
and with rolling bearings (prototype_N_bearings.toml, built-in RV-40E-bearings), and writes
DIR/predictions.md (the table of docs/validation.md, "Prototype predictions (made before any
comparison)") and DIR/predictions.json, with the bands of the first n reducers of each run
for every n of --subsets (the sample-size convergence: sample i does not depend on how many
are drawn, docs/tolerances.md section 2).  Each run is a folder DIR/tpN_VARIANT of
`rvsim tolerance`: re-running resumes.  The same as, per band:

    rvsim tolerance docs/examples/table1_errors.toml \
        --params docs/examples/prototype_1.toml --out tp1 --samples 400

Usage: python scripts/predict_prototypes.py --samples 400 --out prototypes [--workers 2]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "docs" / "examples"
ERRORS = EXAMPLES / "table1_errors.toml"
VARIANTS = {"bushings": "prototype_{}.toml", "bearings": "prototype_{}_bearings.toml"}
METRICS = ("ate_arcmin", "te_mean_arcmin")


def run_band(prototype: int, variant: str, out: Path, samples: int, workers: int | None,
             errors: Path = ERRORS) -> pd.DataFrame:
    """One prototype and bearing variant through `rvsim tolerance`'s own loader and
    analysis; its results.csv (one row per reducer)."""
    from rvsim.cli._tolerance import load_any_tolerance_study
    from rvsim.tolerance.analysis import tolerance_analysis

    params = EXAMPLES / VARIANTS[variant].format(prototype)
    study = load_any_tolerance_study(str(errors), str(params))
    folder = out / f"tp{prototype}_{variant}"
    tolerance_analysis(study, folder, samples=samples, workers=workers, report=False)
    return pd.read_csv(folder / "results.csv")


def dynamic_ate(prototype: int, variant: str, rows: pd.DataFrame, count: int,
                errors: Path = ERRORS) -> list[dict]:
    """The first ``count`` reducers of a band that assemble, each simulated on the dynamic
    engine at the prototype file's input speed (the bench's 1200 r/min) and load until its
    steady window covers one output revolution: their dynamic ATE beside the quasi-static
    one (the explicit scheme, the default of `rvsim simulate`)."""
    import math

    from rvsim import simulate
    from rvsim.cli._tolerance import load_any_tolerance_study

    params = EXAMPLES / VARIANTS[variant].format(prototype)
    study = load_any_tolerance_study(str(errors), str(params))
    out = []
    for _, row in rows[rows["status"] == "ok"].head(count).iterrows():
        reducer = study.realise(study.unit_sample(int(row["sample"])))
        op = reducer.operating
        revolution = 2.0 * math.pi * abs(reducer.ratio) / op.input_speed   # s per output rev
        result = simulate(reducer, duration=op.steady_start + 1.02 * revolution,
                          raise_on_failure=False)
        summary = result.summary()
        out.append({"sample": int(row["sample"]), "status": summary["status"],
                    "ate_arcmin": summary["ate_arcmin"],
                    "quasi_static_ate_arcmin": float(row["ate_arcmin"]),
                    "te_mean_arcmin": summary["te_mean_arcmin"],
                    "quasi_static_te_mean_arcmin": float(row["te_mean_arcmin"])})
    return out


def band(rows: pd.DataFrame, n: int) -> dict:
    """Statistics of the first ``n`` reducers (the tolerance summary's own)."""
    from rvsim.tolerance.montecarlo import summarise

    first = rows[rows["sample"] < n]
    summary = summarise(first["status"].to_numpy(),
                        {m: first[m].to_numpy(dtype=float) for m in METRICS})
    return {"samples": n, "ok": summary["ok"], "binds": summary["binds"],
            "failed": summary["failed"], "binding_share": summary["binding_share"],
            **{m: summary["metrics"][m] for m in METRICS}}


def _cell(stats: dict, digits: int = 2) -> str:
    if not stats["n"]:
        return "n/a"
    return " / ".join(f"{stats[k]:.{digits}f}" for k in ("p5", "p50", "p95"))


def table(results: dict, samples: int) -> str:
    """The markdown table of the bands at ``samples`` reducers."""
    lines = ["| prototype | bearings | load [N*m] | ATE p5 / p50 / p95 [arcmin] | mean TE "
             "p5 / p50 / p95 [arcmin] | analysed / bind |", "|---|---|---|---|---|---|"]
    for key, entry in results.items():
        b = entry["bands"][str(samples)]
        lines.append(f"| TP {entry['prototype']} | {entry['variant']} | {entry['load_nm']:g} | "
                     f"{_cell(b['ate_arcmin'], 3)} | {_cell(b['te_mean_arcmin'])} | "
                     f"{b['ok']} / {b['binds']} |")
    return "\n".join(lines) + "\n"


def convergence(results: dict, subsets: list[int]) -> str:
    """ATE p5 / p50 / p95 of the first n reducers, each n of ``subsets``."""
    head = " | ".join(f"n = {n}" for n in subsets)
    lines = [f"| prototype | bearings | {head} |", "|---|---|" + "---|" * len(subsets)]
    for entry in results.values():
        cells = " | ".join(f"{_cell(entry['bands'][str(n)]['ate_arcmin'], 3)} "
                           f"({entry['bands'][str(n)]['ok']})" for n in subsets)
        lines.append(f"| TP {entry['prototype']} | {entry['variant']} | {cells} |")
    return "\n".join(lines) + "\n"


def dynamic_table(results: dict) -> str:
    """Dynamic against quasi-static ATE of the reducers simulated (--dynamic)."""
    lines = ["| prototype | bearings | sample | dynamic ATE [arcmin] | quasi-static ATE "
             "[arcmin] | status |", "|---|---|---|---|---|---|"]
    for entry in results.values():
        for d in entry.get("dynamic", []):
            ate = "n/a" if d["ate_arcmin"] is None else f"{d['ate_arcmin']:.3f}"
            lines.append(f"| TP {entry['prototype']} | {entry['variant']} | {d['sample']} | "
                         f"{ate} | {d['quasi_static_ate_arcmin']:.3f} | {d['status']} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--samples", type=int, default=400, help="reducers per band (default 400)")
    p.add_argument("--subsets", default=None,
                   help="also give the bands of the first n reducers (comma list; default "
                        "those of 100,200 below --samples)")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.add_argument("--workers", type=int, default=None, help="worker processes")
    p.add_argument("--prototypes", default="1,2,3", help="which prototypes (comma list)")
    p.add_argument("--dynamic", type=int, default=0, metavar="K",
                   help="also simulate the first K assembling reducers of each band on the "
                        "dynamic engine over one output revolution (about 20 s CPU each)")
    args = p.parse_args(argv)
    given = ([int(n) for n in args.subsets.split(",") if n] if args.subsets is not None
             else [n for n in (100, 200) if n < args.samples])
    subsets = sorted(set(given) | {args.samples})
    if subsets[0] < 2 or subsets[-1] > args.samples:
        p.error(f"--subsets: each n from 2 to --samples ({args.samples})")
    from rvsim.parameters import load_toml

    results = {}
    for prototype in (int(x) for x in args.prototypes.split(",")):
        for variant in VARIANTS:
            rows = run_band(prototype, variant, args.out, args.samples, args.workers)
            reducer = load_toml(EXAMPLES / VARIANTS[variant].format(prototype))
            results[f"tp{prototype}_{variant}"] = {
                "prototype": prototype, "variant": variant,
                "params": VARIANTS[variant].format(prototype),
                "load_nm": reducer.operating.load_torque,
                "bands": {str(n): band(rows, n) for n in subsets}}
            if args.dynamic:
                results[f"tp{prototype}_{variant}"]["dynamic"] = dynamic_ate(
                    prototype, variant, rows, args.dynamic)
            last = results[f"tp{prototype}_{variant}"]["bands"][str(args.samples)]
            print(f"TP {prototype} {variant}: ATE {_cell(last['ate_arcmin'], 3)} arcmin",
                  file=sys.stderr)
    out = {"errors": "docs/examples/table1_errors.toml", "samples": args.samples,
           "subsets": subsets, "results": results}
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "predictions.json").write_text(json.dumps(out, indent=2) + "\n")
    text = (f"Bands at {args.samples} reducers per prototype and variant:\n\n"
            + table(results, args.samples)
            + "\nATE p5 / p50 / p95 [arcmin] of the first n reducers (analysed):\n\n"
            + convergence(results, subsets))
    if args.dynamic:
        text += "\n" + dynamic_table(results)
    (args.out / "predictions.md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
