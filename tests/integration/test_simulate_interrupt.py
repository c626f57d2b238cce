"""Ctrl-C on a long ``rvsim simulate``: a real SIGINT to a real process (issue 8, item 3).

The process runs with its stderr on a pseudo-terminal, as in a shell: it then shows a progress
bar, whose first frame tells the test that the compiled loop is running.  The signal must stop
the run promptly (the compiled driver returns every 5000 steps), with exit code 130, the one
line ``rvsim: interrupted`` and no file written.
"""

import fcntl
import os
import pty
import select
import signal
import struct
import subprocess
import sys
import termios
import time

import pytest

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="needs a POSIX pseudo-terminal")


def _read_until(fd: int, marker: bytes, limit_s: float) -> bytes:
    """Bytes from ``fd`` until ``marker`` appears (or the process ends / ``limit_s`` passes)."""
    data = b""
    end = time.monotonic() + limit_s
    while marker not in data and time.monotonic() < end:
        ready, _, _ = select.select([fd], [], [], 0.2)
        if ready:
            try:
                chunk = os.read(fd, 4096)
            except OSError:   # the other side closed
                break
            if not chunk:
                break
            data += chunk
    return data


def test_sigint_stops_a_long_simulation(tmp_path):
    target = tmp_path / "run.npz"
    master, slave = pty.openpty()
    # a terminal of 24 x 100 characters (a new pseudo-terminal has none; tqdm then hides)
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 100, 0, 0))
    proc = subprocess.Popen([sys.executable, "-m", "rvsim", "simulate", "--duration", "60",
                             "--save", str(target)], stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=slave, cwd=tmp_path)
    os.close(slave)
    try:
        # numba compiles on a cold cache: allow for it before the first progress frame
        started = _read_until(master, b"simulated", 120.0)
        assert b"simulated" in started, started.decode(errors="replace")
        proc.send_signal(signal.SIGINT)
        # a 60 s run takes about 20 s of wall time: finishing within 10 s means it stopped
        code = proc.wait(timeout=10)
        rest = _read_until(master, b"interrupted\r\n", 5.0)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        os.close(master)
    assert code == 130
    text = rest.decode(errors="replace").replace("\r\n", "\n")
    lines = [line for line in text.split("\n") if line.strip(" \r")]
    # the progress bar erases itself ("\r" + blanks); what is left is one line
    assert lines[-1].strip(" \r").endswith("rvsim: interrupted")
    assert "Traceback" not in text and text.count("\n") == 1
    assert proc.stdout.read() == b""
    assert not target.exists() and list(tmp_path.iterdir()) == []
