"""Issue 35 item 1: is a faster integration scheme as accurate as the explicit reference?

For each paper L36 run asked for (default all 36, full 4 s), runs the explicit reference
(5e-6 s), the reference with its step x (1 + 1e-12) (the run's chaotic spread) and each
candidate (default every scheme the package offers besides the reference, at its own step;
``scheme@step`` for another step), in parallel processes, and applies the criterion of
:mod:`rvsim.dynamics.accuracy` (mean TE within 1e-4 relative, energy residual within 1e-3 of
the input work, each peak metric's differences no larger than the chaotic spread, median and
maximum over the runs).  Prints a table per run and candidate, then the medians, maxima and
the verdict of each criterion; ``--json FILE`` writes every figure.

Usage:  python benchmarks/bench_scheme_accuracy.py [--runs 1-36] [--workers 2]
            [--candidates implicit-bearings implicit-bearings@2.5e-5] [--duration 4]
            [--json accuracy.json]
(on a loaded 2-core host, 2026-11-28: about 6 s of CPU per run with the default candidate,
4 minutes for the 36; 330 s with three candidates; docs/benchmarks.md)
"""

from __future__ import annotations

import argparse
import json
import os
import time
from concurrent.futures import ProcessPoolExecutor

from _timing import machine, one_thread, run_numbers

one_thread()


def _measure(run: int, candidates: tuple, duration: float | None) -> tuple[int, dict]:
    from rvsim.dynamics.accuracy import measure_run
    from rvsim.parameters import RV40E, paper_run_values, with_values

    reducer = with_values(RV40E, paper_run_values(run))
    return run, measure_run(reducer, candidates, duration=duration)


def _table(candidate: str, rows: dict) -> None:
    from rvsim.dynamics.accuracy import PEAK_METRICS

    peaks = [m for m in PEAK_METRICS
             if any(row[f"{m}_spread"] == row[f"{m}_spread"] for row in rows.values())]
    head = ["run", "status", "mean TE diff / spread", "energy"]
    head += [f"{m} diff / spread" for m in peaks] + ["CPU ref/cand s"]
    print(f"\n{candidate} against the explicit reference (relative differences)")
    print(" | ".join(head))
    for run, row in rows.items():
        status = "ok" if (row["status_reference"], row["status_perturbed"],
                          row["status_candidate"]) == ("ok",) * 3 else (
            f"{row['status_reference']}/{row['status_perturbed']}/{row['status_candidate']}")
        cells = [f"{run:3d}", status,
                 f"{row['mean_te_difference']:.2e} / {row['mean_te_spread']:.2e}",
                 f"{row['energy_residual']:+.2e}"]
        cells += [f"{row[f'{m}_difference']:.2e} / {row[f'{m}_spread']:.2e}" for m in peaks]
        cells.append(f"{row['cpu_reference_s']:.2f}/{row['cpu_candidate_s']:.2f}")
        print(" | ".join(cells))


def _ratio(difference: dict, spread: dict, key: str) -> float:
    return difference[key] / spread[key] if spread[key] else float("inf")


def _verdict(candidate: str, verdict: dict) -> None:
    print(f"\nverdict for {candidate}: {'MEETS' if verdict['passed'] else 'FAILS'} the criterion")
    status = verdict["status"]
    print(f"  status: {status['runs']} runs, not ok: {status['not_ok'] or 'none'}"
          f" -> {'pass' if status['passed'] else 'FAIL'}")
    for key in ("mean_te", "energy"):
        part = verdict[key]
        print(f"  {key}: median {part['median']:.2e}, max {part['max']:.2e} (limit "
              f"{part['limit']:g}) -> {'pass' if part['passed'] else 'FAIL'}"
              + (f"; the reference's own spread median {part['spread']['median']:.2e}, max "
                 f"{part['spread']['max']:.2e}" if "spread" in part else ""))
    for key, part in verdict.items():
        if isinstance(part, dict) and "difference" in part:
            d, s = part["difference"], part["spread"]
            print(f"  {key}: difference median {d['median']:.2e} max {d['max']:.2e}; "
                  f"spread median {s['median']:.2e} max {s['max']:.2e} -> "
                  f"{'pass' if part['passed'] else 'FAIL'} (median x{_ratio(d, s, 'median'):.3g},"
                  f" max x{_ratio(d, s, 'max'):.3g} of the spread; {part['runs_within_spread']}"
                  f" of {part['runs']} runs within their own spread)")


def _collect(args) -> tuple[dict, tuple, float, dict]:
    """(measured figures by run, candidates, wall time, the loaded report or {}): the runs
    simulated in parallel, or read from a --json file (``--load``)."""
    from rvsim.dynamics.accuracy import REFERENCE
    from rvsim.dynamics.model import SCHEMES

    if args.load:
        with open(args.load) as handle:
            loaded = json.load(handle)
        measured = {int(run): value for run, value in loaded["measured"].items()}
        names = [n for n in measured[min(measured)] if not n.startswith(REFERENCE + "+")]
        candidates = tuple(args.candidates or [n for n in names if n != REFERENCE])
        args.duration, args.workers = loaded["duration"], loaded["workers"]
        return measured, candidates, loaded["wall_s"], loaded
    candidates = tuple(args.candidates or [s for s in SCHEMES if s != REFERENCE])
    start = time.perf_counter()
    measured = {}
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        futures = [pool.submit(_measure, run, candidates, args.duration)
                   for run in run_numbers(args.runs)]
        for future in futures:
            run, result = future.result()
            measured[run] = result
    return measured, candidates, time.perf_counter() - start, {}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", default="1-36", help="paper L36 runs, e.g. 1-36 or 3,34")
    parser.add_argument("--candidates", nargs="+", default=None,
                        help="schemes to judge, 'scheme' or 'scheme@step' (default: every "
                             "scheme but the reference, at its own step)")
    parser.add_argument("--duration", type=float, default=None,
                        help="simulated time [s] (default: the run's own, 4 s)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--json", default=None, help="write every figure to this file")
    parser.add_argument("--load", default=None,
                        help="judge the runs of a --json file again instead of running them")
    args = parser.parse_args()

    from rvsim.dynamics.accuracy import differences, judge

    measured, candidates, wall, loaded = _collect(args)
    runs = sorted(measured)
    report = {"machine": machine(), "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
              **({"measured_on": {k: loaded[k] for k in ("machine", "date")}}
                 if loaded else {}),
              "runs": runs, "duration": args.duration, "workers": args.workers,
              "wall_s": round(wall, 1),
              "cpu_of_runs_s": round(sum(m["cpu_s"] for r in measured.values()
                                         for m in r.values()), 1),
              "load_average_1min": round(os.getloadavg()[0], 2),
              "measured": measured, "verdicts": {}}
    for candidate in candidates:
        rows = {run: differences(measured[run], candidate) for run in runs}
        _table(candidate, rows)
        verdict = judge(list(rows.values()))
        verdict["status"]["not_ok"] = [runs[i] for i in verdict["status"]["not_ok"]]
        cpu_ref = sum(measured[r]["explicit"]["cpu_s"] for r in runs)
        cpu_cand = sum(measured[r][candidate]["cpu_s"] for r in runs)
        verdict["cpu_share_of_reference"] = cpu_cand / cpu_ref
        _verdict(candidate, verdict)
        print(f"  CPU: {cpu_cand:.1f} s against the reference's {cpu_ref:.1f} s "
              f"({100 * cpu_cand / cpu_ref:.0f} %)")
        report["verdicts"][candidate] = verdict
    print(f"\n{machine()}; {len(runs)} runs in {wall:.0f} s wall, "
          f"{report['cpu_of_runs_s']} s CPU in the runs, {args.workers} workers")
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(report, handle, indent=1, default=float)


if __name__ == "__main__":
    main()
