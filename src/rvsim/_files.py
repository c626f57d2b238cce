"""Files: atomic writing (a finished file or none, never a partial one) and TOML reading with
one-line errors."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path
from typing import Callable, Iterator

from ._stopping import check_stop

__all__ = ["atomic_write", "atomic_write_text", "atomic_outputs", "read_toml",
           "read_study_toml"]


def atomic_write(path: str | Path, write: Callable[[Path], None]) -> Path:
    """Call ``write(tmp)`` on a temporary file beside ``path``, then rename it into place.

    The file gets the permissions a plain ``open`` would give (0666 less the umask).
    """
    path = Path(path)
    tmp = _temporary_beside(path)
    try:
        write(tmp)
        check_stop()
        _move_into_place(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def _temporary_beside(path: Path) -> Path:
    """A new empty hidden file ``.NAME.xxxx.SUFFIX`` in ``path``'s folder."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=path.suffix)
    os.close(fd)
    return Path(tmp)


def _move_into_place(tmp: Path, path: Path) -> None:
    """Give ``tmp`` the permissions a plain ``open`` would (0666 less the umask; mkstemp
    makes 0600) and rename it to ``path``."""
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    os.replace(tmp, path)


@contextlib.contextmanager
def atomic_outputs(*paths: str | Path | None) -> Iterator[list[Path | None]]:
    """Temporary paths beside ``paths`` (None stays None) for a command's several outputs,
    renamed into place one after the other (microseconds) only when the block ends without
    an exception and every one is written, all removed when it raises: an interrupted
    command leaves the outputs as they were, not one of a pair.  The files get the
    permissions a plain ``open`` would give, as with :func:`atomic_write`."""
    temps: list[Path | None] = []
    try:
        for path in paths:
            temps.append(None if path is None else _temporary_beside(Path(path)))
        yield temps
        check_stop()
        for tmp, path in zip(temps, paths):
            if tmp is not None:
                try:
                    _move_into_place(tmp, Path(path))
                except OSError as exc:
                    from .errors import InputFileError

                    raise InputFileError(f"{path}: cannot write ({exc.strerror or exc})") \
                        from None
    finally:
        for tmp in temps:
            if tmp is not None:
                tmp.unlink(missing_ok=True)


def atomic_write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    return atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))


#: the largest TOML file read (parameter sets, studies and maps are a few kilobytes)
MAX_TOML_BYTES = 16 * 2 ** 20


def read_toml(path: str | Path, what: str = "TOML file") -> dict:
    """The TOML table of ``path``; every way of failing is one :class:`InputFileError` line."""
    import tomllib

    from .errors import InputFileError

    path = Path(path)
    try:
        with open(path, "rb") as handle:      # bounded: a device or a pipe may never end
            data = handle.read(MAX_TOML_BYTES + 1)
        if len(data) > MAX_TOML_BYTES:
            raise InputFileError(f"{path}: larger than {MAX_TOML_BYTES // 2 ** 20} MiB: not a "
                                 f"{what}")
        # a UTF-8 byte-order mark (Windows editors, Excel) is not part of the text
        return tomllib.loads(data.decode("utf-8-sig"))
    except FileNotFoundError:
        raise InputFileError(f"{path}: file not found") from None
    except IsADirectoryError:
        raise InputFileError(f"{path}: is a folder, not a {what}") from None
    except UnicodeDecodeError:
        raise InputFileError(f"{path}: not a text file (expected a {what})") from None
    except OSError as exc:
        raise InputFileError(f"{path}: cannot read ({exc.strerror or exc})") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputFileError(f"{path}: not valid TOML ({exc})") from None


def read_study_toml(path: str | Path) -> dict:
    """The TOML table of a study file (a design study or a tolerance study): the one reader
    of both, so that their messages name the file alike (issue 31 step 7)."""
    return read_toml(path, "TOML study file")
