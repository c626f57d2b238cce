"""The ``rvsim`` process as a shell sees it: exit codes and outputs of whole processes.

``rvsim.cli.run`` ends the commands that start no processes of their own without the
interpreter's teardown, and ends every interrupted command with code 130.  Before, CPython
ended about one Ctrl-C in five with SIGINT (exit code -2) although rvsim had caught it and
printed its line: a KeyboardInterrupt that once passed through an ``exec`` of a string
(dataclasses and numba make functions that way) marks the process as interrupted for good.
"""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from .conftest import SRC, default_signals, interrupted

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")

ENV = {**os.environ, "PYTHONPATH": SRC}


def _rvsim(*args, cwd):
    return subprocess.run([sys.executable, "-m", "rvsim", *args], capture_output=True,
                          cwd=cwd, env=ENV, stdin=subprocess.DEVNULL, timeout=300)


def test_quick_exit_leaves_complete_outputs(tmp_path):
    res = _rvsim("ltca", "--positions", "81", "--json", "--report", "ltca.html", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    data = json.loads(res.stdout)
    assert data["status"] == "ok" and data["positions"] == 81
    page = (tmp_path / "ltca.html").read_text()
    assert page.rstrip().endswith("</html>")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ltca.html"]


#: the command line entered as the executable enters it, with an interpreter-exit hook that
#: says whether the interpreter's teardown ran
_TEARDOWN_WITNESS = """
import atexit, sys
atexit.register(lambda: print("TEARDOWN", file=sys.stderr, flush=True))
from rvsim.__main__ import main
sys.argv = ["rvsim"] + sys.argv[1:]
main()
"""


def test_a_local_study_ends_without_teardown_and_leaves_its_files(tmp_path):
    """A study on the local worker pool ends at once when it has returned (its workers are
    reaped, its store closed, its files renamed into place: the teardown only cost 0.6-0.9 s
    after a paper study), with its summary printed and every file complete.  (Before, the
    interpreter's teardown ran: "TEARDOWN" printed.)  A user error of a local-pool command:
    the next test.  The runs use the implicit-bearings scheme: four times cheaper, the same
    ending."""
    from .conftest import write_study

    path = write_study(tmp_path, extra='scheme = "implicit-bearings"')
    out = tmp_path / "out"
    res = subprocess.run([sys.executable, "-c", _TEARDOWN_WITNESS, "study", str(path), "--out",
                          str(out), "--no-progress"], capture_output=True, cwd=tmp_path,
                         env=ENV, stdin=subprocess.DEVNULL, timeout=300)
    assert res.returncode == 0, res.stderr
    assert b"TEARDOWN" not in res.stderr
    assert res.stdout.decode().startswith("small: 4 runs, 0 failed -> ")
    assert sorted(p.name for p in out.iterdir()) == [
        "analysis.json", "main_effects.png", "report.html", "results.csv", "results.sqlite",
        "study.json", "study.lock"]
    assert (out / "report.html").read_text().rstrip().endswith("</html>")
    assert json.loads((out / "analysis.json").read_text())["runs_ok"] == 4
    # the store is closed: it opens read-only with every run in it
    import sqlite3
    with sqlite3.connect(f"{(out / 'results.sqlite').as_uri()}?mode=ro", uri=True) as db:
        assert db.execute("select count(*) from runs").fetchone()[0] == 4
    # a command with no quick end keeps the teardown (the witness works); a missing folder
    # is enough to show it (it was `analyze`: 3 s of CPU, to the same end)
    res = subprocess.run([sys.executable, "-c", _TEARDOWN_WITNESS, "report",
                          str(tmp_path / "missing")], capture_output=True, cwd=tmp_path,
                         env=ENV, stdin=subprocess.DEVNULL, timeout=300)
    assert res.returncode == 2 and b"TEARDOWN" in res.stderr


def test_local_tolerance_and_allocation_end_without_teardown(tmp_path):
    """``tolerance`` and ``allocate`` on the local pool end at once as ``study`` does (the
    teardown cost 0.57-0.69 s after a small tolerance study), their files complete, and so
    does a user error of such a command.  Two reducers each, the fewest allowed."""
    from .test_tolerance_cli import SMALL

    path = tmp_path / "small.toml"
    path.write_text(SMALL)
    for args, files in (
            (["tolerance", str(path), "--out", "t", "--workers", "2", "--samples", "2"],
             ["report.html", "results.csv", "results.sqlite", "study.json", "study.lock",
              "summary.json"]),
            # one worker: evaluated in the command's process (a pool of two was started for
            # each of the evaluations, 2 s of CPU; the pool's end: the tolerance run above)
            (["allocate", str(path), "--target", "ate_p95=0.5", "--out", "a", "--samples", "2",
              "--workers", "1", "--max-evaluations", "5"],       # the least COBYLA takes
             ["allocation.json", "report.html", "results.sqlite", "study.json", "study.lock"])):
        res = subprocess.run([sys.executable, "-c", _TEARDOWN_WITNESS, *args],
                             capture_output=True, cwd=tmp_path, env=ENV,
                             stdin=subprocess.DEVNULL, timeout=300)
        assert res.returncode == 0, res.stderr
        assert b"TEARDOWN" not in res.stderr and res.stdout.startswith(b"small: ")
        folder = tmp_path / args[args.index("--out") + 1]
        assert sorted(p.name for p in folder.iterdir()) == files
        assert (folder / "report.html").read_text().rstrip().endswith("</html>")
    # a user error found in the command ends at once too, in its one line (a missing file:
    # 0.4 s; it was a study's --time-step 0, 3 s of CPU importing the study runner first)
    res = subprocess.run([sys.executable, "-c", _TEARDOWN_WITNESS, "tolerance",
                          str(tmp_path / "missing.toml"), "--out", "x"], capture_output=True,
                         cwd=tmp_path, env=ENV, stdin=subprocess.DEVNULL, timeout=300)
    assert res.returncode == 2 and res.stderr.decode().startswith("rvsim: error: ")
    assert b"TEARDOWN" not in res.stderr and res.stderr.count(b"\n") == 1
    assert not (tmp_path / "x").exists()


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
def test_standard_output_full_or_closed_is_one_line(tmp_path):
    # found by a hostile review: a traceback ending in OSError ENOSPC, or AttributeError on a
    # closed standard output (Python's sys.stdout is then None).  (A full disk under `params`
    # too: the same flush of the same command path, dropped for its 1.4 s of CPU.)
    with open("/dev/full", "w") as full:
        res = subprocess.run([sys.executable, "-m", "rvsim", "ltca", "--positions", "81",
                              "--json"], stdout=full, stderr=subprocess.PIPE, cwd=tmp_path,
                             env=ENV, timeout=300)
    assert res.returncode == 1 and res.stderr == \
        b"rvsim: error: cannot write the output (No space left on device)\n"
    res = subprocess.run([sys.executable, "-m", "rvsim", "params"], stderr=subprocess.PIPE,
                         cwd=tmp_path, env=ENV, timeout=300, preexec_fn=lambda: os.close(1))
    assert res.returncode == 1 and res.stderr == \
        b"rvsim: error: cannot write the output (standard output is closed)\n"


def test_user_error_exit_code_through_quick_exit(tmp_path):
    res = _rvsim("ltca", "--torque", "abc", cwd=tmp_path)
    assert res.returncode == 2
    assert res.stderr.decode().count("\n") == 1 and b"Traceback" not in res.stderr


@pytest.mark.parametrize("delay", [1.2, 1.7, 2.4])
def test_sigint_at_any_moment_ends_with_130(tmp_path, delay):
    # numba's start, loading the cached engine, the engine: wherever the signal lands, one line
    # and code 130.  (During the first ~0.1 s, while Python imports the rvsim package itself,
    # Ctrl-C still gives Python's own traceback, as for any Python program.)
    result = interrupted(["ltca", "--positions", "100000", "--json"], delay, tmp_path)
    assert result == (130, b"", b"rvsim: interrupted\n")


def test_sigterm_while_writing_a_file_leaves_no_temporary_file(tmp_path):
    """A 10^6-point DXF: its temporary file exists from about 1.2 s to 12 s after the start
    (measured); SIGTERM at 4 s used to end the process there and leave it."""
    result = interrupted(["profile", "--out", "disc.dxf", "--points", "1000000"], 4.0,
                         tmp_path, signal.SIGTERM)
    assert result == (143, b"", b"rvsim: terminated (SIGTERM)\n")
    assert list(tmp_path.iterdir()) == []


def test_sighup_during_a_run_ends_with_143_and_no_output(tmp_path):
    result = interrupted(["simulate", "--duration", "30", "--save", "r.npz", "--report",
                          "r.html"], 3.0, tmp_path, signal.SIGHUP)
    assert result == (143, b"", b"rvsim: terminated (SIGHUP)\n")
    assert list(tmp_path.iterdir()) == []


def test_a_signal_swallowed_on_its_way_still_stops_the_command(tmp_path, cli, monkeypatch):
    """numba's compiler ignores an exception raised in one of its callbacks ("Exception
    ignored in: ..."): a hostile test's SIGTERM during compilation then let `rvsim profile`
    write its file and exit 0 (1 try in 20).  The handler also remembers the signal, and no
    output is moved into place once it came."""
    import rvsim.geometry.export
    from rvsim._stopping import request_stop
    from rvsim.errors import Terminated

    def swallowed(reducer, points):              # the handler ran; its exception was lost
        request_stop(Terminated("SIGTERM"))
        return 0.0

    monkeypatch.setattr(rvsim.geometry.export, "chordal_deviation", swallowed)
    res = cli("profile", "--out", str(tmp_path / "disc.csv"), "--points", "400")
    assert (res.code, res.out, res.err) == (143, "", "rvsim: terminated (SIGTERM)\n")
    assert list(tmp_path.iterdir()) == []
    # the remembered signal ends with the command: the next one runs
    monkeypatch.undo()
    assert cli("profile", "--out", str(tmp_path / "disc.csv"), "--points", "400").code == 0


def test_a_signal_turned_into_another_exception_is_said_as_the_stop(tmp_path, cli,
                                                                   monkeypatch):
    """A SIGHUP during numba's compilation of a cold cache once ended `rvsim simulate` with a
    traceback and exit code 1 (1 try in 10): the compiler let another exception out in the
    interrupt's place.  Any exception after a stop signal is the stop."""
    import rvsim.geometry.export
    from rvsim._stopping import request_stop
    from rvsim.errors import Terminated

    def wrapped(reducer, points):
        request_stop(Terminated("SIGHUP"))
        raise RuntimeError("Failed in nopython mode pipeline (step: native lowering)")

    monkeypatch.setattr(rvsim.geometry.export, "chordal_deviation", wrapped)
    res = cli("profile", "--out", str(tmp_path / "disc.csv"), "--points", "400")
    assert (res.code, res.out, res.err) == (143, "", "rvsim: terminated (SIGHUP)\n")
    assert list(tmp_path.iterdir()) == []


SWALLOWED_IN_A_FINALISER = """
import os, signal, sys
import rvsim.geometry.export
from rvsim.cli import run

class Finalised:                     # a signal that lands in a finaliser (llvmlite's objects)
    def __del__(self):
        os.kill(os.getpid(), signal.SIGHUP)
        for _ in range(1000):        # the handler runs here; its exception cannot leave
            pass

def deviation(reducer, points):
    Finalised()
    return 0.0

rvsim.geometry.export.chordal_deviation = deviation
sys.argv = ["rvsim", "profile", "--out", "disc.csv", "--points", "400"]
run()
"""


def test_a_signal_swallowed_in_a_finaliser_is_one_line(tmp_path):
    """CI, cold numba cache: a SIGHUP that landed in llvmlite's ``ObjectRef.__del__`` while
    numba compiled printed "Exception ignored in: ..." and a 30-line traceback before rvsim's
    own line.  The swallowed stop is said once, by the command."""
    res = subprocess.run([sys.executable, "-c", SWALLOWED_IN_A_FINALISER], capture_output=True,
                         cwd=tmp_path, env=ENV, stdin=subprocess.DEVNULL, timeout=300)
    assert (res.returncode, res.stdout, res.stderr) == (143, b"",
                                                        b"rvsim: terminated (SIGHUP)\n")
    assert list(tmp_path.iterdir()) == []


CTRL_C_WHILE_IMPORTING = """
import sys

class CtrlC:                         # Ctrl-C lands while rvsim.cli is being imported
    def find_spec(self, name, path=None, target=None):
        if name == "rvsim.cli":
            raise KeyboardInterrupt

sys.meta_path.insert(0, CtrlC())
from rvsim.__main__ import main      # the `rvsim` executable's entry point
main()
"""


def test_ctrl_c_while_the_command_line_is_imported_is_one_line():
    """The `rvsim` executable entered at rvsim.cli.run, so a Ctrl-C in its first 0.1 s (while
    Python imported the command line) gave Python's traceback; `python -m rvsim` did not."""
    res = subprocess.run([sys.executable, "-c", CTRL_C_WHILE_IMPORTING], capture_output=True,
                         env=ENV, stdin=subprocess.DEVNULL, timeout=60)
    assert (res.returncode, res.stdout, res.stderr) == (130, b"", b"rvsim: interrupted\n")
    import tomllib

    scripts = tomllib.loads((Path(SRC).parent / "pyproject.toml").read_text())["project"][
        "scripts"]
    assert scripts == {"rvsim": "rvsim.__main__:main"}


def test_an_ignored_signal_stays_ignored(tmp_path):
    """`nohup rvsim simulate ...` must survive the terminal's SIGHUP: the command's handlers
    replaced an ignored signal (a review found it); SIGTERM then ends the run as usual."""
    proc = subprocess.Popen([sys.executable, "-m", "rvsim", "simulate", "--duration", "30",
                             "--save", "r.npz"], stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=tmp_path,
                            env=ENV, preexec_fn=default_signals(ignored=(signal.SIGHUP,)))
    try:
        time.sleep(2.5)
        proc.send_signal(signal.SIGHUP)
        time.sleep(1.0)
        assert proc.poll() is None                       # still running
        proc.send_signal(signal.SIGTERM)
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert (proc.returncode, out, err) == (143, b"", b"rvsim: terminated (SIGTERM)\n")
    assert list(tmp_path.iterdir()) == []


def test_out_of_memory_is_one_line(monkeypatch, capsys):
    # a reviewer's finite-element disc of 0.4 mm elements under a 2.5 GB limit ended in
    # numpy's _ArrayMemoryError traceback after 40 s
    import rvsim.quasistatic
    from rvsim.cli import main

    def exhausted(*args, **kwargs):
        raise MemoryError("Unable to allocate 513. MiB for an array with shape (8400, 8000)")

    monkeypatch.setattr(rvsim.quasistatic, "ltca", exhausted)
    assert main(["ltca", "--positions", "81"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("rvsim: error: out of memory (Unable to allocate 513. MiB")
    assert err.count("\n") == 1 and "flexibility.fe_element_size" in err
