"""``python -m rvsim`` and the ``rvsim`` executable (both enter at :func:`main`)."""

import os
import sys


def main() -> None:
    """Import the command line, then run it: a Ctrl-C while it is still being imported ends
    with the command line's own line and code 130, not a traceback."""
    try:
        from .cli import run
    except KeyboardInterrupt:
        print("rvsim: interrupted", file=sys.stderr)
        sys.stderr.flush()
        os._exit(130)       # not sys.exit: see rvsim.cli.run
    run()


if __name__ == "__main__":
    main()
