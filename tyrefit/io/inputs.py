"""Input files: only regular files of a sane size are read.

Every reader (and the command line, for every input of every command)
calls :func:`check_input` before opening a file, so

* a FIFO, a socket or a device (``/dev/zero``, ``/dev/stdin``) is refused at
  once instead of hanging or filling memory;
* a file larger than the limit is refused with its size and the flag that
  raises the limit (``--max-size MB``, default :data:`DEFAULT_MAX_MB`).

The limit is a process-wide setting (:func:`set_max_size_mb`): the command
line sets it from ``--max-size`` once, before any input is read.  Checking
with :func:`os.stat` never opens the file, so it cannot block on a FIFO.
"""

from __future__ import annotations

import math
import os
import stat
from pathlib import Path

from ..errors import FormatError, InputError, option

__all__ = ["check_input", "read_input_bytes", "set_max_size_mb", "max_size_mb", "DEFAULT_MAX_MB"]

#: default largest input file [MB] (an FSAE TTC run file is 5-60 MB)
DEFAULT_MAX_MB = 256.0
_MAX_MB = DEFAULT_MAX_MB


def set_max_size_mb(mb: float | None) -> None:
    """Set the largest input file tyrefit reads [MB] (None: the default)."""
    global _MAX_MB
    if mb is None:
        _MAX_MB = DEFAULT_MAX_MB
        return
    mb = float(mb)
    if not (math.isfinite(mb) and mb > 0):
        raise InputError(f"{option('max_size', f'{mb:g}')}: the size limit must be a positive number of megabytes")
    _MAX_MB = mb


def max_size_mb() -> float:
    """The largest input file tyrefit reads [MB]."""
    return _MAX_MB


def _kind(mode: int) -> str | None:
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    if not stat.S_ISREG(mode):
        return "not a regular file"
    return None


def check_input(path: str | os.PathLike, what: str = "a data file", folder_ok: bool = False) -> Path:
    """Refuse what is not a readable regular file within the size limit; return the path.

    Raises
    ------
    InputError
        missing file, a folder (unless ``folder_ok``), a FIFO, socket or
        device, or a file over :func:`max_size_mb`.
    """
    p = Path(path)
    try:
        st = os.stat(p)
    except FileNotFoundError:
        raise InputError(f"{p}: no such file (not found)") from None
    except NotADirectoryError:
        raise InputError(f"{p}: no such file (a parent in the path is a file)") from None
    except OSError as exc:
        raise InputError(f"{p}: cannot read ({exc.strerror})") from None
    if stat.S_ISDIR(st.st_mode):
        if folder_ok:
            return p
        raise InputError(f"{p}: is a folder; give {what}")
    kind = _kind(st.st_mode)
    if kind is not None:
        raise InputError(f"{p}: is {kind}, not a regular file; tyrefit reads {what} from a regular file")
    limit = _MAX_MB * 1e6
    if st.st_size > limit:
        raise InputError(f"{p}: {st.st_size / 1e6:.3g} MB is over the input size limit of {_MAX_MB:g} MB; "
                         f"pass {option('max_size', 'MB')} to raise it")
    if not os.access(p, os.R_OK):
        raise InputError(f"{p}: cannot read (permission denied)")
    return p


def read_input_bytes(path: str | os.PathLike, what: str = "a data file") -> bytes:
    """The bytes of an input file after :func:`check_input` (never more than the limit)."""
    p = check_input(path, what)
    limit = int(_MAX_MB * 1e6)
    try:
        with open(p, "rb") as fh:
            data = fh.read(limit + 1)
    except OSError as exc:
        raise FormatError(f"{p}: cannot read ({exc.strerror})") from None
    if len(data) > limit:  # grew while reading
        raise InputError(f"{p}: over the input size limit of {_MAX_MB:g} MB; pass {option('max_size', 'MB')} to "
                         "raise it")
    return data
