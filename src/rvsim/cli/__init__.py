"""The ``rvsim`` command line: each subcommand reads files, calls one public function, writes.

User errors print one line ``rvsim: error: ...`` on stderr and exit with code 2.
"""

from __future__ import annotations

import argparse
import sys

from .. import __version__
from ..errors import RvsimError
from . import _efficiency, _geometry, _quasistatic, _simulate, _study, _testrig, _tolerance
from ._common import EXAMPLES, Parser

__all__ = ["main", "build_parser"]


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog="rvsim", description="Transmission error of RV reducers: geometry, "
                    "analytical error model, contact dynamics, quasi-static loaded contact analysis "
                    "and the catalogue tests, designs of experiments.",
                    epilog=EXAMPLES + "rvsim params\n  rvsim sensitivity --json\n  "
                    "rvsim profile --out disc.dxf\n  rvsim simulate --paper-run 2 --json",
                    formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"rvsim {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    _geometry.register(sub)
    _simulate.register(sub)
    _quasistatic.register(sub)
    _efficiency.register(sub)
    _study.register(sub)
    _testrig.register(sub)
    _tolerance.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if not getattr(args, "func", None):
            parser.print_help()
            return 2
        return int(args.func(args) or 0)
    except RvsimError as exc:
        print(f"rvsim: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("rvsim: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
