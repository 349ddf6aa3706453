"""Exception classes of tyrefit.

Every error a user can cause with bad input is a :class:`TyrefitError`.  The
command line turns these into exit code 2 and one line on stderr; anything
else is a bug and keeps its traceback.  Each class also subclasses the
built-in it resembles, so ``except ValueError`` keeps working for callers who
do not know about tyrefit (the python-control / scikit-learn pattern).

Messages name the file, the column or row, the bad value with its unit, and
what is accepted.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable

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
]


class TyrefitError(Exception):
    """Base class of every error tyrefit raises on purpose."""


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
