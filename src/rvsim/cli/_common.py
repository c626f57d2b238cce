"""Pieces shared by the CLI subcommands: the parser class, reducer options, JSON output."""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import tempfile
from pathlib import Path
from typing import Any

from .._json import to_json_safe
from ..errors import InputFileError, ParameterError, RvsimError, Terminated
from ..parameters import (BUILT_IN_SETS, RV40E, Reducer, load_toml, parse_assignment,
                          plain_number,
                          with_values)

__all__ = ["Parser", "UsageError", "stopped_line", "add_command", "add_reducer_options",
           "reducer_from_args", "print_json", "EXAMPLES", "number", "positive_int", "whole",
           "probability", "path_text", "scheduler_address", "check_output_file",
           "check_output_folder", "warn", "check_load", "flush_warnings"]


class UsageError(RvsimError):
    """A command line that argparse rejected."""


class Parser(argparse.ArgumentParser):
    """ArgumentParser that reports errors as one line (exit code 2 is applied by ``main``)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        # "-1e-5", "-inf" and "-20,40" are values (argparse's own pattern misses exponents,
        # inf and lists and takes them for an option: "expected one argument"); the option's
        # own check then names the reason
        number = r"((\d+\.?\d*|\.\d+)([eE][-+]?\d+)?|inf|nan)"
        self._negative_number_matcher = re.compile(rf"^-{number}(,\s*[-+]?{number})*$")

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(f"{message} (see '{self.prog} --help')")


EXAMPLES = "examples:\n  "


def add_command(sub, name: str, summary: str, description: str, examples: list[str]):
    """A subcommand parser whose --help ends with worked examples."""
    return sub.add_parser(name, help=summary, description=description,
                          epilog=EXAMPLES + "\n  ".join(examples),
                          formatter_class=argparse.RawDescriptionHelpFormatter)


def add_reducer_options(parser: argparse.ArgumentParser, *, paper_run: bool = False) -> None:
    """--params FILE, repeated --set NAME=VALUE and, with ``paper_run``, --paper-run N."""
    if paper_run:
        parser.add_argument("--paper-run", type=int, metavar="N",
                            help="apply row N (1..36) of the paper's L36 scheme (Table 3 with "
                                 "Table 2 levels); --set values override it")
    parser.add_argument("--params", metavar="FILE", type=path_text,
                        help="TOML file describing the reducer (user units, see 'rvsim "
                             "params'), or the name of a built-in set (RV-40E, RV-40E-bearings, "
                             "cycloid-drive)")
    parser.add_argument("--set", metavar="NAME=VALUE", action="append", default=[],
                        dest="assignments",
                        help="override one parameter in its listed unit, e.g. "
                             "errors.pin_circle_radius=0.02 or H=0.02, or with a unit, "
                             "e.g. H=20um or operating.input_speed=1000rpm (repeatable)")


def reducer_from_args(args: argparse.Namespace) -> Reducer:
    """The reducer of --params (a TOML file, or a built-in set's name when no such file
    exists; built-in RV-40E by default) with the --paper-run row (a run of the RV-40E), if
    the command has one, and then the --set values applied (they win), validated."""
    from ..parameters import paper_run_values

    run = getattr(args, "paper_run", None)
    preset = paper_run_values(run) if run is not None else None
    reducer = reducer_of(args.params)
    if preset and reducer.layout.single_stage:
        raise ParameterError("paper-run", f"the paper's runs are runs of the RV-40E; "
                             f"'{reducer.name}' is a single-stage drive")
    values = dict(preset or {})
    values.update(parse_assignment(a) for a in args.assignments)
    from ..friction import check_losses

    return check_losses(with_values(reducer, values))


def reducer_of(params: str | None) -> Reducer:
    """The reducer of a --params value: a TOML file, or a built-in set's name when no such
    file exists; the built-in RV-40E for None."""
    if params is None:
        return RV40E
    if params in BUILT_IN_SETS and not Path(params).exists():
        return BUILT_IN_SETS[params]
    return load_toml(params)


#: warnings of the running command, printed when it ends (rvsim.cli._main)
_WARNINGS: list[str] = []


def warn(text: str) -> None:
    """One ``rvsim: warning: ...`` line on stderr, printed when the command ends (once per
    text), unless the command is refused: a refusal is its one error line."""
    _WARNINGS.append(f"rvsim: warning: {' '.join(text.split())}")


def flush_warnings(show: bool = True) -> None:
    """Print (``show``) or drop the warnings held so far."""
    lines = list(dict.fromkeys(_WARNINGS))
    _WARNINGS.clear()
    if show:
        for line in lines:
            print(line, file=sys.stderr)


def check_load(reducer: Reducer, torque: float, field: str) -> None:
    """An output torque against the reducer's rating (rvsim.parameters.rating.check_torque):
    refused above the momentary maximum, one warning line above the rated torque."""
    from ..parameters.rating import check_torque

    note = check_torque(reducer, torque, field)
    if note:
        warn(note)


def check_input_speeds(reducer: Reducer, speeds_rpm, field: str) -> None:
    """Input speeds [rpm] against the reducer's allowable output speed, converted by the
    ratio (rvsim.parameters.rating.check_output_speed): one warning line above it."""
    from ..parameters.rating import check_output_speed
    from ..units import TO_SI

    fastest = max(speeds_rpm)
    note = check_output_speed(reducer, fastest * TO_SI["rpm"] / abs(reducer.ratio),
                              f"{field} ({fastest:g} rpm at the input, ratio "
                              f"{abs(reducer.ratio):g})", refuse=False)
    if note:
        warn(note)


def print_json(payload: Any) -> None:
    """One JSON object on stdout (NaN/inf become null so any JSON reader accepts it)."""
    json.dump(to_json_safe(payload), sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")


def with_compile_time(summary: dict) -> dict:
    """``summary`` with ``compile_s``: the seconds this process spent compiling the kernels
    (0 with a warm cache); the summary's own ``wall_s`` is the run without them."""
    from .._cache_guard import compile_seconds

    return {**summary, "compile_s": compile_seconds()}


def compile_time_text() -> str:
    """", + 52 s compiling" after a run's wall time when this process compiled, else ""."""
    from .._cache_guard import compile_seconds

    seconds = compile_seconds()
    return f", + {seconds:.0f} s compiling" if seconds > 0 else ""


def number(text: str) -> float:
    """argparse type: a number as float() reads it, but not with digit groups ("1_0", which
    Python reads as 10; --set and parameter files refuse it too)."""
    try:
        return plain_number(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None


def positive_int(text: str) -> int:
    """argparse type: a whole number >= 1."""
    try:
        if "_" in text:
            raise ValueError(text)
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1 (got {value})")
    return value


def whole(text: str) -> int:
    """argparse type: a whole number, its range checked by the command (int() reads "1_0"
    as 10: refused, as ``number`` does)."""
    try:
        if "_" in text:
            raise ValueError(text)
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number") from None


def probability(text: str) -> float:
    """argparse type: a significance level strictly between 0 and 1."""
    try:
        value = number(text)
    except argparse.ArgumentTypeError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not 0.0 < value < 1.0:
        raise argparse.ArgumentTypeError(f"must be between 0 and 1, exclusive (got {text})")
    return value


def path_text(text: str) -> str:
    """argparse type: a non-empty path."""
    if not text.strip():
        raise argparse.ArgumentTypeError("empty path")
    return text


def scheduler_address(text: str) -> str:
    """argparse type: a Dask scheduler address, ``[tcp|tls://]host[:port]``."""
    from urllib.parse import urlparse

    parsed = urlparse(text if "://" in text else f"tcp://{text}")
    if parsed.scheme not in ("tcp", "tls") or not parsed.hostname or parsed.path \
            or parsed.query:
        raise argparse.ArgumentTypeError(f"'{text}' is not a scheduler address "
                                         "(expected tcp://host:port)")
    try:
        port = parsed.port
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}': the port must be a number from 1 to "
                                         "65535") from None
    if port == 0:
        raise argparse.ArgumentTypeError(f"'{text}': the port must be a number from 1 to 65535")
    return text


def _check_writable_folder(folder: Path, option: str, target: Path) -> None:
    try:
        fd, probe = tempfile.mkstemp(dir=folder, prefix=".rvsim-write-check-")
    except OSError as exc:
        raise InputFileError(f"{option} {target}: cannot write in {folder} "
                             f"({exc.strerror or exc})") from None
    os.close(fd)
    os.unlink(probe)


def stopped_line(interrupt: KeyboardInterrupt, folder: Path, what: str) -> tuple[str, int]:
    """The line and exit code of a study stopped by ``interrupt``; it names ``folder`` only
    if the folder's store holds finished ``what`` (a stop before the first result has none)."""
    from ..doe.store import ResultStore

    try:
        store = ResultStore(folder, readonly=True)
        try:
            kept = f"; finished {what} are kept in {folder}" if store.finished() else ""
        finally:
            store.close()
    except RvsimError:                 # no store yet
        kept = ""
    if isinstance(interrupt, Terminated):
        return f"rvsim: terminated ({interrupt}){kept}", 143
    return f"rvsim: interrupted{kept}", 130


def check_output_file(path: str, option: str) -> Path:
    """Fail now, before any long computation, if ``path`` cannot be written as a file."""
    target = Path(path)
    if target.is_dir():
        raise InputFileError(f"{option} {target}: is a folder (give a file name)")
    folder = target.parent
    if not folder.is_dir():
        raise InputFileError(f"{option} {target}: folder {folder} does not exist")
    _check_writable_folder(folder, option, target)
    return target


def check_output_folder(path: str, option: str) -> Path:
    """Fail now if ``path`` cannot be (created and) written as a folder; creates nothing."""
    target = Path(path)
    if target.exists() and not target.is_dir():
        raise InputFileError(f"{option} {target}: exists and is not a folder")
    existing = target
    while not existing.exists():       # the nearest existing ancestor must be writable
        if existing.parent == existing:
            break
        existing = existing.parent
    if not existing.is_dir():
        raise InputFileError(f"{option} {target}: {existing} is not a folder")
    _check_writable_folder(existing, option, target)
    return target
