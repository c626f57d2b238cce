"""Every command and code block of README.md and docs/user_guide.md runs (issue 34 item 4).

The fenced blocks of both files are read and sorted: command blocks (every line, continuations
joined, starting with ``rvsim``, ``python``, ``pip`` or the README's test command), Python
blocks, TOML blocks (the files the commands read: a first line ``# NAME.toml``, or a fragment of
:data:`TOML_FRAGMENTS`) and output blocks (each marked ``<!-- guide-output: KEY -->``: the
output of a full-size run by scripts/guide_outputs.py, kept in its stamp
docs/validation_data/guide_outputs.json).  A block of any other kind fails the test.

Every command runs in order, in-process through the command line's entry :func:`rvsim.cli.main`,
in one temporary folder whose ``docs`` is the checkout's (the example data where the guide says
it lives), at the sizes of :data:`REDUCED`, :data:`LINE_REDUCED`, :data:`PATCHED` and
:data:`REDUCED_PYTHON` (each entry with its reason); the lines of :data:`SKIPPED` are parsed,
those of :data:`CHECKED_ONLY` checked (shell syntax, the extras they install, their rvsim part
parsed), those of :data:`PENDING_README` wait for a README edit.  The test fails on a command
that fails or exits with another code than the guide gives (a trailing ``# exit code N``; else
0), on an output block that is not the stamp's or whose small run prints another shape, and on
a list entry whose line is gone.  ``RVSIM_GUIDE_TIMES=1`` prints each command's CPU time.

Figures are built but neither laid out nor rasterised (:func:`_no_png`: 60-80 % of a report's
time; each report's images are checked by tests/unit/test_plots_show_data.py and the browser
test), and study runs are evaluated in this process (:func:`_runs_in_process`).
"""

from __future__ import annotations

import dataclasses
import importlib.util
import io
import json
import os
import re
import shlex
import subprocess
import sys
import tomllib
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

from rvsim._matplotlib import pyplot
from rvsim.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[2]
DOCS = ("README.md", "docs/user_guide.md")

#: a short schedule of the dynamic model: 0.2 s simulated instead of 4 s, long enough for the
#: paper's 36 runs all to end ok (at tests/_warmup.py's 0.05 s, 26 of them end
#: energy_imbalance; measured 2026-11-28)
SHORT = {"operating.duration": 0.2, "operating.speed_ramp_time": 0.05,
         "operating.load_start": 0.05, "operating.load_ramp_end": 0.1,
         "operating.steady_start": 0.15}
SHORT_SET = " ".join(f"--set {k}={v}" for k, v in SHORT.items())
#: tests/_warmup.py's shorter schedule (0.05 s simulated), for single runs that end ok with it
SHORTEST = {"operating.duration": 0.05, "operating.speed_ramp_time": 0.01,
            "operating.load_start": 0.01, "operating.load_ramp_end": 0.02,
            "operating.steady_start": 0.03}
SHORTEST_SET = " ".join(f"--set {k}={v}" for k, v in SHORTEST.items())

#: lines checked, not run: line -> reason
CHECKED_ONLY = {
    "pip install . && rvsim study paper-l36 --out rv40e_study":
        "installs the package under test; its study is the guide's 'rvsim study paper-l36', run",
    "pip install .": "installs the package under test",
    'pip install ".[fe]"': "installs the finite-element extra (present in the test environment)",
    "(dpkg -s chromium libglu1-mesa libxcursor1 libxft2 libxinerama1 >/dev/null 2>&1 || "
    "(apt-get update -qq && apt-get install -y -qq chromium libglu1-mesa libxcursor1 libxft2 "
    "libxinerama1 >/dev/null)) && pip install --upgrade --upgrade-strategy eager -e \".[test]\" "
    "&& python -m pytest -q":
        "installs system packages and runs the whole suite, this test among it",
}

#: README lines that wait for the README edit of issue 34 item 4 (the coordinator's; the
#: example recordings live in docs/examples/testrig, and the default reducer's fit ends
#: model_fails): line -> reason.  An entry whose line is gone from the README fails the test.
PENDING_README: dict[str, str] = {}

#: size reductions, per command (the first word after rvsim, or the script):
#: (pattern, replacement) applied to the line with re.sub, and the reason
REDUCED: dict[str, list[tuple[str, str, str]]] = {
    "simulate": [(r"$", " " + SHORTEST_SET, "4 s simulated -> 0.05 s (SHORTEST)")],
    "tolerance": [(r"--samples \d+|$", " --samples 4", "1000 reducers -> 4")],
    "allocate": [(r"--samples \d+|$", " --samples 2", "30 reducers (README: 200) -> 2"),
                 (r"$", " --max-evaluations 12",
                  "60 evaluations -> 12, the least for 10 tolerances (stopped, as the guide's)")],
    "calibrate": [(r"^(?!.*--loop)(.*)$", r"\1 --positions 256",
                   "recordings: 1024 model positions per output revolution -> 256 (at 81, the "
                   "least for the RV-40E's 40 pins, the model's own discretisation leaves a "
                   "systematic residual that the runs test calls lack_of_fit)")],
    "testrig": [(r"--compare", "--compare --points 1024", "model nodes 4096 -> 1024")],
    "grid": [(r"--speeds [\d,]+", "--speeds 8000", "speeds -> one, 8000 rpm: the shortest "
                                                   "revolution below the RV-40E's allowable "
                                                   "output speed (70 rpm)"),
             (r"--torques [\d.,]+", "--torques 200", "torques -> one"),
             (r"--temperatures [\d,]+", "--temperatures 20", "temperatures -> one"),
             (r"$", " --scheme implicit-bearings --set operating.steady_start=0.03 "
                    "--set operating.load_start=0.01 --set operating.load_ramp_end=0.02 "
                    "--set operating.speed_ramp_time=0.01",
              "the short start-up; the implicit scheme where the reducer has one")],
    "scripts/predict_prototypes.py": [
        (r"--samples \d+", "--samples 2 --prototypes 1", "400 reducers -> 2; prototype 1 only")],
}

#: the built-in studies at a small size (patched by _small_built_ins): name -> reason
PATCHED = {
    "paper-l36": "36 runs of 0.2 s simulated instead of 4 s (SHORT)",
    "paper-l36-robust": "2 noise replicates per run instead of 20, at 81 positions per output "
                        "revolution instead of 360",
    "rv40e-tolerances": "81 positions per output revolution instead of 360 (the least for the "
                        "RV-40E's 40 pins)",
}

#: lines parsed by the command line's parser, not run: line -> reason
SKIPPED = {
    "rvsim study paper-l36 --out ref --scheme explicit":
        "the study above in the reference scheme, at 4 times its steps; --scheme explicit on a "
        "study is run by tests/integration/test_study_engines.py",
    "rvsim tolerance rv40e-tolerances --out tol --samples 1000 --sobol 64":
        "the tolerance run above plus Sobol indices (22 more reducers per base sample); "
        "--sobol is run by tests/integration/test_tolerance_cli.py",
    "rvsim allocate rv40e-tolerances --target ate_p95=0.3 --out alloc":
        "the guide's allocation (section 11), which is run, with one of its two targets",
}

#: lines reduced otherwise than their command's rule: line -> (line run, reason)
LINE_REDUCED = {
    "rvsim simulate --paper-run 3 --scheme implicit-bearings --json":
        ("rvsim simulate --paper-run 3 --scheme implicit-bearings --json " + SHORT_SET,
         "4 s simulated -> 0.2 s (SHORT): at 0.05 s this run ends energy_imbalance"),
}

#: substitutions in the Python blocks: (text, replacement, reason)
REDUCED_PYTHON = [
    ('{"H": 0.02, "I": 0.016}', '{"H": 0.02, "I": 0.016, **SHORTEST}',
     "4 s simulated -> 0.05 s (SHORTEST is put in the block's namespace)"),
]

#: TOML blocks that are no file of their own: first line -> how they are checked
TOML_FRAGMENTS = {
    'engine = "quasi-static"': "the two lines that make a study quasi-static: my_qs_study.toml",
}
#: files the guide's commands read that no block spells out (_write_files): name -> what
MADE_FILES = {
    "my_qs_study.toml": "tolerances.toml (section 6) with the quasi-static fragment (section 7), "
                        "as section 5 says",
}

COMMAND = re.compile(r"^(rvsim |python |pip |\(dpkg )")
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)
NUMBER = re.compile(r"[-+]?(?:\d{1,3}(?:,\d{3})+|\d+)(?:\.\d+)?(?:e[-+]?\d+)?")
ORDER = re.compile(r"\b[A-Z](?:>[A-Z])+\b")
SECONDS = re.compile(r"[\d.]+ s\b")
#: the compile time a command adds to its timing when it compiled (a cold numba cache: CI's
#: first run of a kernel this test reaches first), absent from the stamp's warm runs
COMPILING = re.compile(r", \+ [\d.]+ s compiling")


def _script():
    spec = importlib.util.spec_from_file_location("guide_outputs",
                                                  ROOT / "scripts/guide_outputs.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


GUIDE = _script()


@dataclasses.dataclass
class Block:
    doc: str
    line: int
    lang: str
    text: str
    marker: str | None      # the guide-output key of a marked output block

    @property
    def kind(self) -> str:
        if self.lang in ("python", "toml"):
            return self.lang
        if self.lang == "" and self.marker is None and all(
                COMMAND.match(line) for line in self.text.replace("\\\n", " ").splitlines()):
            return "commands"
        return "output" if self.marker else "unknown"


def blocks() -> list[Block]:
    found = []
    for doc in DOCS:
        text = (ROOT / doc).read_text(encoding="utf-8")
        for m in FENCE.finditer(text):
            before = text[:m.start()].rstrip("\n").rsplit("\n", 1)[-1]
            marker = re.fullmatch(r"<!-- guide-output: ([\w-]+) -->", before)
            found.append(Block(doc, text[:m.start()].count("\n") + 1, m.group(1), m.group(2),
                               marker and marker.group(1)))
    return found


def command_lines(block: Block) -> list[tuple[str, int]]:
    """(command, expected exit code) of a command block: continuations joined, the comment
    (from a '#' after a space) dropped; a comment '# exit code N' gives the code (else 0)."""
    out = []
    for line in block.text.replace("\\\n", " ").splitlines():
        command, _, comment = line.partition(" #")
        code = re.search(r"exit code (\d+)", comment)
        out.append((" ".join(command.split()), int(code.group(1)) if code else 0))
    return out


def _reduced(line: str) -> tuple[str, list[str]]:
    """The line run for ``line`` and the reasons of its reductions."""
    if line in LINE_REDUCED:
        return LINE_REDUCED[line][0], [LINE_REDUCED[line][1]]
    words = line.split()
    key = words[1] if words[0] == "rvsim" else words[1] if words[0] == "python" else ""
    reasons = []
    for pattern, replacement, reason in REDUCED.get(key, ()):
        new = re.sub(pattern, replacement, line, count=1)
        if new != line:
            reasons.append(reason)
        line = new
    return line, reasons


def _shape(text: str) -> list[str]:
    """The lines of ``text`` with every number replaced by '#', every factor order (K>M>...)
    by '>', and spaces collapsed."""
    return [" ".join(NUMBER.sub("#", ORDER.sub(">", COMPILING.sub("", line))).split())
            for line in text.strip().splitlines()]


def _numbers(text: str) -> list[float]:
    return [float(n.replace(",", "")) for n in NUMBER.findall(SECONDS.sub("", text))]


@pytest.fixture
def _no_png(monkeypatch):
    """Figures built (every plotting call runs) but neither laid out nor rasterised: a
    1-pixel PNG."""
    import base64

    import matplotlib.figure

    import rvsim.plots

    monkeypatch.setattr(matplotlib.figure.Figure, "tight_layout", lambda self, **kw: None)
    pixel = base64.b64decode("iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAAAAAA6fptVAAAACklEQVR4nGNgAAAA"
                             "AgABSK+kcQAAAABJRU5ErkJggg==")

    def no_png(fig, path=None):
        rvsim.plots.pyplot().close(fig)
        if path is not None:
            Path(path).write_bytes(pixel)
        return pixel
    monkeypatch.setattr(rvsim.plots, "figure_to_png", no_png)


@pytest.fixture
def _runs_in_process(monkeypatch):
    """The runs of studies, tolerance runs and grids evaluated in this process, one after
    another, by the task a worker would call: forking the workers cost 3 s of CPU here, and
    the worker pool is tested by tests/integration/test_study_faults.py and
    test_worker_signals.py."""
    import rvsim.doe.runner as runner

    def in_process(tasks, workers, on_result, inherited_fds=(), on_idle=None, *, task,
                   first_alone=False):
        for key, args in tasks.items():
            on_result(*task(key, *args))
    monkeypatch.setattr(runner, "run_workers", in_process)


@pytest.fixture
def _small_built_ins(monkeypatch):
    """The built-in studies at a small size (PATCHED)."""
    from rvsim.doe import study as doe_study
    from rvsim.tolerance import robust, spec as tolerance_spec

    def paper_l36():
        return dataclasses.replace(doe_study.paper_l36(), fixed=tuple(SHORT.items()))

    def paper_l36_robust():
        full = robust.paper_l36_robust()
        noise = dataclasses.replace(full.noise.spec, samples=2, positions=81)
        return dataclasses.replace(full, noise=dataclasses.replace(full.noise, spec=noise))

    def rv40e_tolerances():
        return dataclasses.replace(tolerance_spec.rv40e_tolerances(), positions=81)
    monkeypatch.setitem(doe_study.BUILT_IN_STUDIES, "paper-l36", paper_l36)
    monkeypatch.setitem(tolerance_spec.BUILT_IN_TOLERANCE_STUDIES, "rv40e-tolerances",
                        rv40e_tolerances)
    monkeypatch.setitem(robust.BUILT_IN_ROBUST_STUDIES, "paper-l36-robust", paper_l36_robust)


def _check_only(line: str) -> None:
    """Shell syntax, the extras a pip line installs, the rvsim parts parsed."""
    assert subprocess.run(["bash", "-n", "-c", line]).returncode == 0, line
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"][
        "optional-dependencies"]
    for extra in re.findall(r"\.\[(\w+)\]", line):
        assert extra in extras, f"{line}: no extra [{extra}] in pyproject.toml"
    for part in line.split("&&"):
        words = shlex.split(part)
        if words and words[0] == "rvsim":
            build_parser().parse_args(words[1:])


def _write_files(folder: Path, found: list[Block]) -> None:
    """The named TOML blocks (first line '# NAME.toml') as files; the fragments checked."""
    named = {}
    for block in found:
        if block.kind != "toml":
            continue
        first = block.text.splitlines()[0]
        tomllib.loads(block.text)
        name = re.fullmatch(r"# ([\w.-]+\.toml)", first)
        if name:
            named[name.group(1)] = block.text
        else:
            assert first in TOML_FRAGMENTS, (
                f"{block.doc}:{block.line}: a TOML block with no '# NAME.toml' first line and "
                "not in TOML_FRAGMENTS")
    for name, text in named.items():
        (folder / name).write_text(text)
    fragment = next(b.text for b in found if b.text.startswith('engine = "quasi-static"'))
    (folder / "my_qs_study.toml").write_text(fragment + named["tolerances.toml"])


def _run(line: str) -> tuple[int, str, str]:
    """One command line in-process: (exit code, stdout, stderr)."""
    words = shlex.split(line)
    target = None
    if ">" in words:
        target = words[words.index(">") + 1]
        words = words[:words.index(">")]
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        try:
            if words[0] == "rvsim":
                code = main(words[1:])
            else:
                code = _script_main(words[1], words[2:])
        except SystemExit as exc:
            code = int(exc.code or 0)
    if target:
        Path(target).write_text(out.getvalue())
    return code, out.getvalue(), err.getvalue()


def _cpu() -> float:
    """CPU seconds of this process and its finished children."""
    import resource

    own, children = (resource.getrusage(who) for who in (resource.RUSAGE_SELF,
                                                           resource.RUSAGE_CHILDREN))
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def _script_main(path: str, argv: list[str]) -> int:
    spec = importlib.util.spec_from_file_location(Path(path).stem, ROOT / path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.main(argv)


def test_every_block_is_known():
    """Each block is a command, Python, TOML or marked output block; each command is run,
    checked or pending; each output block is the stamp's; every list entry is still used."""
    found = blocks()
    unknown = [f"{b.doc}:{b.line}" for b in found if b.kind == "unknown"]
    assert not unknown, f"blocks that are no command, code, TOML or marked output: {unknown}"
    lines = {line for b in found if b.kind == "commands" for line, _ in command_lines(b)}
    for table in (CHECKED_ONLY, PENDING_README, SKIPPED, LINE_REDUCED):
        stale = set(table) - lines
        assert not stale, f"entries whose line is no longer in the guide: {stale}"
    stamp = json.loads(GUIDE.STAMP.read_text())
    marked = {b.marker: b for b in found if b.kind == "output"}
    assert set(marked) == set(GUIDE.OUTPUTS), "marked blocks and scripts/guide_outputs.py differ"
    for key, block in marked.items():
        assert block.text.rstrip("\n") == stamp[key]["output"], (
            f"{block.doc}:{block.line}: the '{key}' block is not the output of "
            "scripts/guide_outputs.py's run: re-run it (do not edit the block by hand)")
        command = stamp[key]["command"]
        if GUIDE.OUTPUTS[key][1] == "python":
            code = "\n".join(b.text for b in found if b.kind == "python")
            assert all(line in code for line in command.splitlines()[:-1]), key
        else:
            assert command in lines, f"'{key}': the guide does not show {command!r}"
        assert command == GUIDE.OUTPUTS[key][0], f"'{key}': the stamp's command is stale"


@pytest.mark.usefixtures("_no_png", "_small_built_ins", "_runs_in_process")
def test_guide_runs(tmp_path, monkeypatch):
    """Every command and code block, in order, at the sizes of REDUCED."""
    found = blocks()
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("RVSIM_CACHE_DIR", os.environ.get("RVSIM_CACHE_DIR", str(tmp_path)))
    (tmp_path / "docs").symlink_to(ROOT / "docs")
    _write_files(tmp_path, found)
    done: dict[str, tuple[int, str, str]] = {}
    failures = []
    namespace: dict = {}
    for block in found:
        if block.kind == "python":
            start, code = _cpu(), block.text
            for text, replacement, _ in REDUCED_PYTHON:
                code = code.replace(text, replacement)
            namespace.update(SHORTEST=SHORTEST)
            with redirect_stdout(io.StringIO()):
                exec(compile(code, f"{block.doc}:{block.line}", "exec"), namespace)
            pyplot().close("all")
            if os.environ.get("RVSIM_GUIDE_TIMES"):
                print(f"{_cpu() - start:6.2f} s CPU  {block.doc}:{block.line}", file=sys.__stderr__)
            continue
        if block.kind != "commands":
            continue
        for line, expected in command_lines(block):
            if line in CHECKED_ONLY:
                _check_only(line)
                continue
            if line in SKIPPED:
                build_parser().parse_args(shlex.split(line)[1:])
                continue
            if line in PENDING_README or line in done:
                continue
            small, _ = _reduced(line)
            start = _cpu()
            done[line] = result = _run(small)
            if os.environ.get("RVSIM_GUIDE_TIMES"):     # where the test's CPU time goes
                print(f"{_cpu() - start:6.2f} s CPU  {small}", file=sys.__stderr__)
            if result[0] != expected:
                failures.append(f"{block.doc}:{block.line}: {small}: exit {result[0]} "
                                f"(expected {expected}): {result[2].strip()[-300:]}")
    assert not failures, "\n".join(failures)
    _outputs_have_the_stamp_shape(done, namespace)


def _outputs_have_the_stamp_shape(done, namespace) -> None:
    """Each output block's command, run here: the same lines with the same words as the full
    run; where it ran at full size, the same numbers (timings left out) to 1e-4."""
    stamp = json.loads(GUIDE.STAMP.read_text())
    for key, (command, stream) in GUIDE.OUTPUTS.items():
        if stream == "python":
            text, full = repr(namespace["loaded"]), True
        else:
            code, out, err = done[command]
            text = err if stream == "stderr" else out
            full = _reduced(command)[0] == command and not set(PATCHED) & set(command.split())
        assert _shape(text) == _shape(stamp[key]["output"]), (key, text)
        if full:
            assert _numbers(text) == pytest.approx(_numbers(stamp[key]["output"]), rel=1e-4), key
