"""Pieces shared by the CLI subcommands: the parser class, reducer options, JSON output."""

from __future__ import annotations

import argparse
import json
import math
import sys
from typing import Any

from ..errors import RvsimError
from ..parameters import RV40E, Reducer, load_toml, parse_assignment, with_values

__all__ = ["Parser", "UsageError", "add_command", "add_reducer_options", "reducer_from_args",
           "print_json", "EXAMPLES"]


class UsageError(RvsimError):
    """A command line that argparse rejected."""


class Parser(argparse.ArgumentParser):
    """ArgumentParser that reports errors as one line (exit code 2 is applied by ``main``)."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(f"{message} (see '{self.prog} --help')")


EXAMPLES = "examples:\n  "


def add_command(sub, name: str, summary: str, description: str, examples: list[str]):
    """A subcommand parser whose --help ends with worked examples."""
    return sub.add_parser(name, help=summary, description=description,
                          epilog=EXAMPLES + "\n  ".join(examples),
                          formatter_class=argparse.RawDescriptionHelpFormatter)


def add_reducer_options(parser: argparse.ArgumentParser) -> None:
    """--params FILE and repeated --set NAME=VALUE."""
    parser.add_argument("--params", metavar="FILE",
                        help="TOML file describing the reducer (user units, see 'rvsim params')")
    parser.add_argument("--set", metavar="NAME=VALUE", action="append", default=[],
                        dest="assignments",
                        help="override one parameter in its listed unit, e.g. "
                             "errors.pin_circle_radius=0.02 or H=0.02 (repeatable)")


def reducer_from_args(args: argparse.Namespace, preset: dict | None = None) -> Reducer:
    """The reducer of --params (built-in RV-40E by default) with ``preset`` values (e.g. a
    paper run) and then the --set values applied, validated."""
    reducer = load_toml(args.params) if args.params else RV40E
    values = dict(preset or {})
    values.update(parse_assignment(a) for a in args.assignments)
    return with_values(reducer, values)


def _clean(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if hasattr(value, "item") and callable(value.item):  # numpy scalar
        return _clean(value.item())
    return value


def print_json(payload: Any) -> None:
    """One JSON object on stdout (NaN/inf become null so any JSON reader accepts it)."""
    json.dump(_clean(payload), sys.stdout, indent=2)
    sys.stdout.write("\n")
