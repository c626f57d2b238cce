import os
import sys

try:
    from .cli import run
except KeyboardInterrupt:  # Ctrl-C while the command line is still being imported
    print("rvsim: interrupted", file=sys.stderr)
    sys.stderr.flush()
    os._exit(130)       # not sys.exit: see rvsim.cli.run

run()
