"""The study folder: one study at a time, and only the study it was made for.

A running study holds an exclusive ``flock`` on ``folder/study.lock``; the operating system
releases it when the process ends in any way (SIGKILL included), so a stale lock cannot
survive its study.  A folder whose ``study.json`` describes a different study, and whose store
holds results, is refused rather than mixed.
"""

from __future__ import annotations

import contextlib
import json
import os
from pathlib import Path

from ..errors import InputFileError

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX: studies run unlocked
    fcntl = None

__all__ = ["LOCK_NAME", "lock_folder", "held_lock_fds", "check_same_study", "check_not_foreign",
           "STUDY_OUTPUTS"]

LOCK_NAME = "study.lock"

# folder -> [fd, depth]: the lock is re-entrant within one process
_HELD: dict[Path, list[int]] = {}


@contextlib.contextmanager
def lock_folder(folder: str | Path):
    """Hold ``folder``'s study lock (the folder must exist); InputFileError if another holds it."""
    folder = Path(folder)
    where = folder.resolve()
    if where in _HELD:
        _HELD[where][1] += 1
        try:
            yield
        finally:
            _HELD[where][1] -= 1
        return
    fd = os.open(where / LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        if fcntl is not None:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        raise InputFileError(f"{folder}: another rvsim study is running in this folder (wait "
                             "for it to finish, or give another --out folder)") from None
    except OSError:
        pass  # a file system without flock (some network mounts): the study runs unlocked
    os.ftruncate(fd, 0)
    os.write(fd, f"{os.getpid()}\n".encode())
    _HELD[where] = [fd, 1]
    try:
        yield
    finally:
        del _HELD[where]
        os.close(fd)          # closing the last descriptor releases the flock


def held_lock_fds() -> list[int]:
    """Descriptors of the locks this process holds (a forked worker closes its copies)."""
    return [fd for fd, _ in _HELD.values()]


#: files a study writes into its folder besides its store and study.json
STUDY_OUTPUTS = ("results.csv", "analysis.json", "report.html", "main_effects.png",
                 "interactions.png")


def check_not_foreign(folder: Path) -> None:
    """Refuse a folder that holds a study's output names but no study.json: no study wrote
    them, and the study would replace them (a user's own results.csv was overwritten)."""
    if not folder.is_dir() or (folder / "study.json").exists():
        return
    found = [name for name in STUDY_OUTPUTS if (folder / name).exists()]
    if found:
        raise InputFileError(f"{folder}: holds {', '.join(found)} but no study.json, so no "
                             "study wrote them, and this one would replace them; give a new "
                             "--out folder")


def check_same_study(folder: Path, definition: dict, has_results: bool,
                     other_schemes: dict[str, dict] | None = None) -> None:
    """Refuse a folder whose stored results belong to a study other than ``definition``.

    ``other_schemes``: the definitions the same study has with each other integration scheme
    (scheme -> definition); a folder holding one of them is refused with the option that
    resumes it."""
    path = folder / "study.json"
    if not has_results or not path.exists():
        return
    try:
        stored = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, ValueError):
        stored = None
    wanted = json.loads(json.dumps(definition, default=str))
    if stored != wanted:
        name = stored.get("name") if isinstance(stored, dict) else None
        for scheme, other in (other_schemes or {}).items():
            if stored == json.loads(json.dumps(other, default=str)):
                # e.g. a paper-l36 folder of the explicit scheme, from before the study's
                # scheme became implicit-bearings: say how to resume it
                raise InputFileError(
                    f"{folder}: holds the runs of study '{name}' with the {scheme} integration "
                    f"scheme (step {stored.get('time_step')} s), not "
                    f"{_value(definition, 'scheme')}; resume it with --scheme {scheme} "
                    f"(Python: scheme=\"{scheme}\"), or give a new --out folder")
        resume = ""
        if name == definition["name"]:
            keys = _differing_keys(stored, wanted)
            which = (f"a different definition of study '{name}' (study.json differs in "
                     f"{_differences(stored, wanted, keys)})")
            if wanted.get("engine") == "dynamic" and keys == ["time_step"]:
                # the step alone: the option that sets it resumes the folder (a dynamic study's)
                resume = f"resume it with --time-step {stored.get('time_step')}, or "
        else:
            which = f"study '{name}'" if name else "another study"
        raise InputFileError(f"{folder}: holds the results of {which}, not of this "
                             f"'{definition['name']}'; {resume}give a new --out folder")


def _value(definition: dict, key: str):
    """A study definition's ``key``; one without a scheme is the explicit scheme's (the
    runner leaves the default out, as the folders of before the key have it)."""
    return definition.get(key, "explicit" if key == "scheme" else "(none)")


def _differing_keys(stored: dict, wanted: dict) -> list[str]:
    """The keys in which a folder's study.json differs from this study's definition."""
    return sorted(key for key in set(stored) | set(wanted)
                  if _value(stored, key) != _value(wanted, key))


def _differences(stored: dict, wanted: dict, keys: list[str], most: int = 3) -> str:
    """``keys`` (:func:`_differing_keys`) with both values where they are short (a step, a
    seed, a scheme), e.g. "time_step: 2e-05 in the folder, 2.5e-05 here"."""
    parts = []
    for key in keys[:most]:
        old, new = _value(stored, key), _value(wanted, key)
        short = all(isinstance(x, (str, int, float, bool)) and len(str(x)) <= 40
                    for x in (old, new))
        parts.append(f"{key}: {old} in the folder, {new} here" if short else key)
    if len(keys) > most:
        parts.append(f"{len(keys) - most} more")
    return "; ".join(parts)
