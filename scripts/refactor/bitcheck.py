"""Bit-for-bit fingerprint of rvsim's numbers, for checking each refactoring step of issue 31.

    cd TREE && PYTHONPATH=src NUMBA_CACHE_DIR=/tmp/numba-TREE \
        python scripts/refactor/bitcheck.py record /tmp/before.json [--quick]
    ... apply a step ...
    cd TREE && PYTHONPATH=src ... scripts/refactor/bitcheck.py compare /tmp/before.json [--quick]

Hashes (sha256 of the raw float64 bytes, so a single last-bit change shows) of:
* the assembled model (P vector and every array of build_model) for the built-in sets, paper
  runs 1-3, both schemes, the bearing variants: catches any change of the constants, free of
  compiling (seconds);
* short dynamic runs (explicit, implicit-bearings, the step guard, the cycloid drive, needle and
  roller bearings, friction on): every channel, pin force and the energy record;
* short quasi-static runs (ltca, hysteresis, efficiency): every array of the results.
``--quick`` does the model part only.  The model entry points are looked up by both their old
and their new homes, so the same script runs before and after a move.
"""
from __future__ import annotations

import hashlib
import importlib
import json
import os
import tempfile
import sys
import time

# the FE tables of the model part are cached: in a folder of this check's own, never the user's
os.environ.setdefault("RVSIM_CACHE_DIR",
                      os.path.join(tempfile.gettempdir(), "rvsim-bitcheck-fe-cache"))

import numpy as np

SHORT = {"operating.duration": 0.05, "operating.speed_ramp_time": 0.01,
         "operating.load_start": 0.01, "operating.load_ramp_end": 0.02,
         "operating.steady_start": 0.03}


def _h(a) -> str:
    a = np.ascontiguousarray(np.asarray(a))
    return hashlib.sha256(str(a.dtype).encode() + str(a.shape).encode() + a.tobytes()).hexdigest()[:16]


def _first(*dotted):
    """The first importable of several 'module:attribute' homes (before / after a move)."""
    for d in dotted:
        mod, _, attr = d.partition(":")
        try:
            return getattr(importlib.import_module(mod), attr)
        except (ImportError, AttributeError):
            continue
    raise ImportError(dotted)


def reducers():
    from rvsim.parameters import BUILT_IN_SETS, RV40E, paper_run_values, with_values
    out = {name: r for name, r in BUILT_IN_SETS.items()}
    for run in (1, 2, 3):
        out[f"paper{run}"] = with_values(RV40E, paper_run_values(run))
    out["needles+rollers"] = with_values(RV40E, {"bearings.arm_needles": True,
                                                 "bearings.support_rollers": True})
    out["friction"] = with_values(RV40E, {"friction.mesh_coefficient": 0.05,
                                          "contact.friction_coefficient": 0.05,
                                          "friction.arm_bearing_f0": 1.5})
    return out


def model_part(out):
    build_model = _first("rvsim.dynamics.model:build_model")
    for name, r in reducers().items():
        for scheme, dt in (("explicit", 5e-6), ("explicit", 1e-5), ("implicit-bearings", 2e-5)):
            try:
                m = build_model(r, dt, scheme)
            except Exception as exc:              # a set a scheme refuses: record the refusal
                out[f"model/{name}/{scheme}/{dt}"] = f"{type(exc).__name__}: {exc}"
                continue
            for field in ("P", "pins", "holes", "crank_angles", "mesh_phase", "q0", "fe"):
                out[f"model/{name}/{scheme}/{dt}/{field}"] = _h(getattr(m, field))


def dynamic_part(out):
    from rvsim.dynamics import simulate
    from rvsim.parameters import BUILT_IN_SETS, RV40E, with_values
    short = with_values(RV40E, SHORT)
    runs = {"explicit": (short, {}),
            "implicit": (short, {"scheme": "implicit-bearings"}),
            "guard7e-6": (short, {"time_step": 7e-6}),
            "cycloid-drive": (with_values(BUILT_IN_SETS["cycloid-drive"], SHORT), {}),
            "needles": (with_values(RV40E, {**SHORT, "bearings.arm_needles": True,
                                            "bearings.support_rollers": True}), {}),
            "friction": (with_values(RV40E, {**SHORT, "friction.mesh_coefficient": 0.05,
                                             "contact.friction_coefficient": 0.05}), {})}
    for name, (r, kw) in runs.items():
        res = simulate(r, raise_on_failure=False, **kw)
        out[f"sim/{name}/status"] = f"{res.status} {res.steps}"
        for field in ("channels", "pin_forces"):
            out[f"sim/{name}/{field}"] = _h(getattr(res, field))
        out[f"sim/{name}/energy"] = json.dumps(res.energy, sort_keys=True, default=repr)
        out[f"sim/{name}/metrics"] = json.dumps(res.metrics, sort_keys=True, default=repr)


def _result_arrays(prefix, res, out):
    for key, value in sorted(vars(res).items()):
        if isinstance(value, np.ndarray):
            out[f"{prefix}/{key}"] = _h(value)
        elif isinstance(value, (int, float, str)) and key != "wall_s":
            out[f"{prefix}/{key}"] = repr(value)


def quasistatic_part(out):
    from rvsim.parameters import BUILT_IN_SETS, RV40E, with_values
    from rvsim.quasistatic import efficiency, hysteresis, ltca
    _result_arrays("ltca/rv40e", ltca(RV40E, positions=16, raise_on_failure=False,
                                      allow_aliasing=True), out)
    _result_arrays("ltca/cycloid", ltca(BUILT_IN_SETS["cycloid-drive"], positions=16,
                                        raise_on_failure=False, allow_aliasing=True), out)
    _result_arrays("hyst/rv40e", hysteresis(RV40E, points_per_branch=6,
                                            raise_on_failure=False), out)
    bearings = with_values(RV40E, {"bearings.arm_needles": True,
                                   "bearings.support_rollers": True})
    _result_arrays("hyst/bearings", hysteresis(bearings, points_per_branch=6,
                                               raise_on_failure=False), out)
    friction = with_values(RV40E, {"friction.mesh_coefficient": 0.05,
                                   "contact.friction_coefficient": 0.05})
    eff = efficiency(friction, speeds_rpm=[500.0], torques=[200.0], positions=8)
    out["eff"] = _h(np.asarray(eff.to_numpy(dtype=float) if hasattr(eff, "to_numpy")
                               else getattr(eff, "efficiency", np.nan), dtype=float)) \
        if not isinstance(eff, dict) else json.dumps(eff, sort_keys=True, default=repr)


def collect(quick: bool) -> dict:
    out: dict = {}
    t = time.perf_counter()
    model_part(out)
    print(f"model part {time.perf_counter() - t:.1f} s", file=sys.stderr)
    if not quick:
        t = time.perf_counter()
        dynamic_part(out)
        print(f"dynamic part {time.perf_counter() - t:.1f} s", file=sys.stderr)
        t = time.perf_counter()
        quasistatic_part(out)
        print(f"quasi-static part {time.perf_counter() - t:.1f} s", file=sys.stderr)
    return out


if __name__ == "__main__":
    mode, path = sys.argv[1], sys.argv[2]
    quick = "--quick" in sys.argv
    now = collect(quick)
    if mode == "record":
        with open(path, "w") as f:
            json.dump(now, f, indent=0, sort_keys=True)
        print(f"recorded {len(now)} fingerprints to {path}")
    else:
        with open(path) as f:
            before = json.load(f)
        keys = sorted(set(now) | (set(before) if not quick else
                                  {k for k in before if k.startswith("model/")}))
        diff = [k for k in keys if before.get(k) != now.get(k)]
        for k in diff:
            print(f"DIFF {k}: {before.get(k)} -> {now.get(k)}")
        print(f"{len(keys) - len(diff)} of {len(keys)} fingerprints identical")
        sys.exit(1 if diff else 0)
