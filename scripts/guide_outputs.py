"""Re-run the commands whose output docs/user_guide.md shows, at full size, and rewrite the
guide's marked output blocks from those runs (issue 34 item 4).

    python scripts/guide_outputs.py              # run every entry of OUTPUTS, rewrite both
    python scripts/guide_outputs.py KEY ...      # only these entries
    python scripts/guide_outputs.py --check      # exit 1 if a marked block is not the stamp's

A marked block is the fenced block right after a line ``<!-- guide-output: KEY -->``.  The
stamp, docs/validation_data/guide_outputs.json, holds per KEY the command exactly as the guide
shows it, its output, exit code, CPU and wall seconds, the machine's core count and the date of
the run that produced it; the TIMINGS entries have no block, their figures are quoted in the
guide's prose.  Each command runs as a user runs it: a new process (``python -m rvsim``, the
sources of this checkout), in an empty folder where ``docs`` is this checkout's, with the
numba cache as it is (warm: the compile time is measured by the ``compile`` entry alone, in
a cache of its own).  tests/integration/test_guide_commands.py checks the guide against the
stamp and runs every command and code block of the README and the guide at a small size.
"""

from __future__ import annotations

import datetime
import json
import os
import re
import resource
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
GUIDE = ROOT / "docs" / "user_guide.md"
STAMP = ROOT / "docs" / "validation_data" / "guide_outputs.json"
MARK = re.compile(r"^<!-- guide-output: ([\w-]+) -->\n```\w*\n(.*?)^```", re.S | re.M)

#: the Python lines the ``api-ltca`` block shows the console output of (section 16)
API_LTCA = ('import rvsim\nr = rvsim.BUILT_IN_SETS["RV-40E-bearings"]\n'
            'loaded = rvsim.ltca(r, torque=412.0, positions=81)\nprint(repr(loaded))')

#: KEY -> (the command as the guide shows it, or Python code; the stream the block shows)
OUTPUTS: dict[str, tuple[str, str]] = {
    "testrig": ("rvsim testrig docs/examples/testrig", "stdout"),
    "calibrate-bench": ("rvsim calibrate docs/examples/testrig --params "
                        "docs/examples/testrig_start.toml --fit errors.disc_runout,"
                        "clearances.crank_arm_bushing,contact.bushing_stiffness_factor --out fit",
                        "stdout"),
    "budget": ("rvsim hysteresis --budget", "stdout"),
    "calibrate-loop": ("rvsim calibrate --loop docs/examples/hysteresis_loop.csv --fit "
                       "stiffness.pins,stiffness.arm_bearings,clearances.crank_arm_bushing "
                       "--out fit", "stdout"),
    "tolerance": ("rvsim tolerance rv40e-tolerances --out tol --samples 1000", "stdout"),
    "allocate": ("rvsim allocate rv40e-tolerances --target ate_p95=0.30,lost_motion_p95=2.3 "
                 "--out alloc --samples 30", "stdout"),
    "allocate-unreachable": ("rvsim allocate rv40e-tolerances --target lost_motion_p95=1.5 "
                             "--out alloc2 --samples 30", "stderr"),
    "efficiency": ("rvsim efficiency --params RV-40E-bearings --speeds 500,2000 "
                   "--torques 82.4,412", "stdout"),
    "life": ("rvsim life --params RV-40E-bearings", "stdout"),
    "robust": ("rvsim study paper-l36-robust --out rob --workers 2", "stdout"),
    "api-ltca": (API_LTCA, "python"),
}

#: KEY -> command timed for the guide's prose (no block): the paper's study (section 4) and
#: the first simulation's compile time, in an empty numba cache of its own (section 1)
TIMINGS: dict[str, str] = {
    "study": "rvsim study paper-l36 --out study",
    "compile": "rvsim simulate --json",
}


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(command: str, folder: Path, env: dict | None = None) -> dict:
    """Run ``command`` (``rvsim ...`` or Python code) in ``folder`` in a new process."""
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src"), **(env or {})}
    env.pop("RVSIM_PROGRESS", None)
    argv = ([sys.executable, "-m", "rvsim", *shlex.split(command)[1:]]
            if command.startswith("rvsim ") else [sys.executable, "-c", command])
    cpu, wall = _children_cpu(), time.perf_counter()
    proc = subprocess.run(argv, cwd=folder, env=env, capture_output=True, text=True,
                          stdin=subprocess.DEVNULL)
    return {"command": command, "exit_code": proc.returncode, "stdout": proc.stdout,
            "stderr": proc.stderr, "cpu_s": round(_children_cpu() - cpu, 1),
            "wall_s": round(time.perf_counter() - wall, 1)}


def workdir() -> Path:
    """An empty folder whose ``docs`` is this checkout's (the guide's example data)."""
    folder = Path(tempfile.mkdtemp(prefix="rvsim-guide-"))
    (folder / "docs").symlink_to(ROOT / "docs")
    return folder


def entry(key: str, folder: Path) -> dict:
    """Run one entry of OUTPUTS or TIMINGS; its stamp record."""
    if key in OUTPUTS:
        command, stream = OUTPUTS[key]
        result = run(command, folder)
        text = result["stderr" if stream == "stderr" else "stdout"]
    else:
        command, env = TIMINGS[key], None
        if key == "compile":
            env = {"NUMBA_CACHE_DIR": tempfile.mkdtemp(prefix="rvsim-guide-numba-")}
        result = run(command, folder, env)
        if env:
            shutil.rmtree(env["NUMBA_CACHE_DIR"], ignore_errors=True)
        text = result["stdout"] if key != "compile" else result["stderr"]
        if key == "compile":
            summary = json.loads(result["stdout"])
            text = f"compile_s {summary['compile_s']:.1f}, wall_s {summary['wall_s']:.2f}\n"
    if result["exit_code"] not in (0, 2) or (key == "allocate-unreachable") != (
            result["exit_code"] == 2):
        raise SystemExit(f"{key}: exit code {result['exit_code']}\n{result['stderr'][-2000:]}")
    return {"command": command, "output": text.rstrip("\n"), "exit_code": result["exit_code"],
            "cpu_s": result["cpu_s"], "wall_s": result["wall_s"], "cores": os.cpu_count(),
            "date": datetime.date.today().isoformat()}


def blocks(text: str) -> dict[str, str]:
    """KEY -> the text of each marked block of ``text``."""
    return {m.group(1): m.group(2).rstrip("\n") for m in MARK.finditer(text)}


def rewritten(text: str, stamp: dict) -> str:
    """``text`` with each marked block replaced by the stamp's output."""
    def block(match):
        key = match.group(1)
        lang = match.group(0).split("\n")[1]
        if key not in stamp:
            return match.group(0)
        return f"<!-- guide-output: {key} -->\n{lang}\n{stamp[key]['output']}\n```"
    return MARK.sub(block, text)


def main(argv: list[str]) -> int:
    stamp = json.loads(STAMP.read_text()) if STAMP.exists() else {}
    text = GUIDE.read_text(encoding="utf-8")
    if "--check" in argv:
        stale = [k for k, v in blocks(text).items() if stamp.get(k, {}).get("output") != v]
        print(("out of date with the stamp: " + ", ".join(stale)) if stale else "up to date")
        return 1 if stale else 0
    keys = argv or [*OUTPUTS, *TIMINGS]
    folder = workdir()
    for key in keys:
        print(f"{key}: {(OUTPUTS.get(key) or (TIMINGS[key],))[0][:90]}", file=sys.stderr,
              flush=True)
        stamp[key] = entry(key, folder)
        print(f"  {stamp[key]['cpu_s']} s CPU, {stamp[key]['wall_s']} s wall\n"
              f"{stamp[key]['output']}", file=sys.stderr, flush=True)
        STAMP.write_text(json.dumps(stamp, indent=1) + "\n")   # kept as each run ends
    shutil.rmtree(folder, ignore_errors=True)
    text = GUIDE.read_text(encoding="utf-8")      # as it is now: edited while the runs ran
    GUIDE.write_text(rewritten(text, stamp), encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
