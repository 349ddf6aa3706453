"""Exception classes of tyrefit.

Every error a user can cause with bad input is a :class:`TyrefitError`.  The
command line turns these into exit code 2 and one line on stderr; anything
else is a bug and keeps its traceback.  Each class also subclasses the
built-in it resembles, so ``except ValueError`` keeps working for callers who
do not know about tyrefit (the python-control / scikit-learn pattern).

Messages name the file, the column or row, the bad value with its unit, and
what is accepted.  An option a message names is written with :func:`option`,
so the same message reads ``rated_load=-5`` to a Python caller and
``--rated-load -5`` on the command line (:func:`cli_style`, which the command
line enters around each command).
"""

from __future__ import annotations

import contextlib
import contextvars
import difflib
import re
from collections.abc import Iterable, Iterator

__all__ = [
    "TyrefitError",
    "DataError",
    "FormatError",
    "ColumnError",
    "UnitError",
    "ValueRangeError",
    "OutputExistsError",
    "OutputError",
    "InputError",
    "FitError",
    "ModelError",
    "close_matches",
    "option",
    "cli_style",
]

_STYLE: contextvars.ContextVar[str] = contextvars.ContextVar("tyrefit_option_style", default="api")
_TOKEN = re.compile("\x1f([A-Za-z_][A-Za-z0-9_]*)(?:\x1c([A-Za-z0-9-]+))?(?:\x1e(.*?))?\x1d(b?)\x1f", re.S)


def option(name: str, value=None, *, flag: bool = False, cli: str | None = None) -> str:
    """An option named in a message: ``name=value`` for Python callers, ``--name value`` on the command line.

    ``flag=True`` for a switch (``force``): ``force=True`` / ``--force``.  ``value`` is put in as it is
    given (format it first, e.g. ``repr(s)``).  ``cli``: the flag's name where it is not the keyword's
    (``option("out_dir", cli="out")``).
    """
    c = "" if cli is None else "\x1c" + cli
    v = "" if value is None else "\x1e" + str(value)
    return f"\x1f{name}{c}{v}\x1d{'b' if flag else ''}\x1f"


def render(text: str, style: str | None = None) -> str:
    """``text`` with its :func:`option` tokens written for ``style`` ('api' or 'cli'; default: the current one)."""
    st = style or _STYLE.get()

    def one(m: re.Match) -> str:
        name, cli, value, flag = m.group(1), m.group(2), m.group(3), bool(m.group(4))
        if st == "cli":
            return "--" + (cli or name.replace("_", "-")) + ("" if value is None else " " + value)
        return name + "=" + ("True" if flag else (value if value is not None else ""))

    return _TOKEN.sub(one, text)


@contextlib.contextmanager
def cli_style() -> Iterator[None]:
    """Within this block, messages name options as command-line flags (``--rated-load``)."""
    token = _STYLE.set("cli")
    try:
        yield
    finally:
        _STYLE.reset(token)


class TyrefitError(Exception):
    """Base class of every error tyrefit raises on purpose."""

    def __str__(self) -> str:
        return render(super().__str__())


class DataError(TyrefitError, ValueError):
    """Input data that cannot be used (bad values, too few points, ...)."""


class FormatError(DataError):
    """A file that is not in a format tyrefit reads (binary, empty, wrong kind)."""


class ColumnError(DataError):
    """A required column is missing, unknown or given twice."""


class UnitError(DataError):
    """A unit tyrefit does not know, or one that does not fit the quantity."""


class ValueRangeError(DataError):
    """Values outside the physically plausible range (negative load, |slip| > 90 deg)."""


class OutputExistsError(TyrefitError, FileExistsError):
    """An output exists and ``--force`` was not given."""


class OutputError(TyrefitError, OSError):
    """An output that cannot be written: an input of the run, a folder, a read-only place, a full disk."""


class InputError(FormatError):
    """An input that is not a regular file tyrefit may read (a FIFO, a device, too large)."""


class FitError(TyrefitError, RuntimeError):
    """A fit that cannot be done with these data or did not converge."""


class ModelError(TyrefitError, ValueError):
    """A model or parameter set that is not physical (C <= 0, D <= 0, E > 1, ...)."""


def close_matches(word: str, choices: Iterable[str], n: int = 3) -> str:
    """Return ``" (did you mean 'x'?)"`` for the closest choices, or ``""``."""
    found = difflib.get_close_matches(str(word), [str(c) for c in choices], n=n, cutoff=0.6)
    if not found:
        return ""
    return " (did you mean " + " or ".join(repr(f) for f in found) + "?)"
