"""Small, fast studies for the integration tests (a short schedule: same physics)."""

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

SRC = str(Path(__file__).resolve().parents[2] / "src")

SHORT = """
[set]
"operating.duration" = 0.4
"operating.speed_ramp_time" = 0.1
"operating.load_start" = 0.1
"operating.load_ramp_end" = 0.2
"operating.steady_start" = 0.3
"""


#: a small tolerance study (tests/integration/test_tolerance_cli.py and the browser test)
SMALL = """name = "small"
samples = 6
seed = 3
positions = 81
[set]
"operating.load_torque" = 412
"errors.equidistant_modification" = 0.010
"clearances.crank_arm_bushing" = 0.005
[tolerances.pin_radius]
tolerance = 0.002
distribution = "normal"
[tolerances.disc_holes]
tolerance = 0.004
[tolerances."clearances.crank_arm_bushing"]
tolerance = 0.003
"""


@pytest.fixture(scope="session")
def small_run(tmp_path_factory):
    """One tolerance study of SMALL with Sobol indices and its report, run once for the test
    session (the tolerance tests and the browser test read it): (the command's result, its
    folder); tests work on a copy of the folder."""
    from tests.conftest import run_cli

    root = tmp_path_factory.mktemp("small-run")
    (root / "small.toml").write_text(SMALL)
    res = run_cli("tolerance", str(root / "small.toml"), "--out", str(root / "o"),
                  "--workers", "1", "--sobol", "2")
    return res, root / "o"


def factors(**specs):
    """TOML [factors.X] tables: ``X=(parameter, levels)`` or ``X=(parameter, "range", [lo, hi])``."""
    blocks = []
    for label, spec in specs.items():
        key, values = ("range", spec[2]) if len(spec) == 3 else ("levels", spec[1])
        blocks.append(f'[factors.{label}]\nparameter = "{spec[0]}"\n{key} = {values}\n')
    return "".join(blocks)


def write_study(folder, design="L4", factors=None, extra=""):
    factors = factors or globals()["factors"](H=("errors.pin_circle_radius", [0.0, 0.02]),
                                              I=("I", [0.0, 0.03]),
                                              E=("operating.load_torque", [100, 300]))
    path = folder / "study.toml"
    path.write_text(f'name = "small"\ndesign = "{design}"\n{extra}\n{SHORT}\n'
                    + textwrap.dedent(factors))
    return path


@pytest.fixture
def small_study(tmp_path):
    return write_study(tmp_path)


def default_signals(ignored=()):
    """A ``preexec_fn``: SIGINT, SIGTERM and SIGHUP at their defaults in the child (a test run
    under ``nohup`` or in a background job would otherwise pass on their being ignored),
    those in ``ignored`` ignored."""
    def reset():
        for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
            signal.signal(sig, signal.SIG_IGN if sig in ignored else signal.SIG_DFL)
    return reset


def interrupted(args, delay, cwd, sig=signal.SIGINT, ignored=()):
    """Start ``python -m rvsim ARGS`` in ``cwd`` (``ignored`` signals ignored), send it a real
    ``sig`` (SIGINT) after ``delay`` s and return (exit code, stdout, stderr)."""
    proc = subprocess.Popen([sys.executable, "-m", "rvsim", *args], stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=cwd,
                            env={**os.environ, "PYTHONPATH": SRC},
                            preexec_fn=default_signals(ignored))
    try:
        time.sleep(delay)
        proc.send_signal(sig)
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return proc.returncode, out, err
