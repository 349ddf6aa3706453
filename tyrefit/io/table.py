"""Raw tables: parsed columns before unit conversion, shared by every data reader.

:class:`RawTable` holds canonical names, units as written and the file line of
each row; :func:`map_headers` turns headers into glossary names and checked
units; :func:`parse_cells` turns a column of text cells into numbers with a
message naming the first bad cell.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .. import nomenclature as nm
from ..errors import ColumnError, UnitError, ValueRangeError

__all__ = ["RawTable", "map_headers", "parse_cells"]


@dataclass
class RawTable:
    """A parsed table before conversion: canonical names, units, file lines.

    ``values`` maps canonical name -> numpy float array (in the file's units) or
    an object array of text; ``headers`` maps canonical name -> header as
    written; ``units`` canonical name -> unit as written (None if none);
    ``lines`` the 1-based file line of each row (for messages).
    """

    format: str
    values: dict[str, np.ndarray]
    headers: dict[str, str]
    units: dict[str, str | None]
    lines: np.ndarray
    meta: dict[str, Any] = field(default_factory=dict)
    #: columns kept without unit conversion (unknown units in TTC/TDX channels)
    raw_columns: set[str] = field(default_factory=set)
    #: the format reader segments runs itself (TTC)
    segment: bool = False


def map_headers(p: Path, headers: list[str], *, strict_units: bool = True,
                units: list[str | None] | None = None, where: str = "header") -> tuple[list[str], list[str | None], set[str]]:
    """Canonical names and units for a list of headers; errors for duplicates and unknown units.

    ``units`` (TTC, TDX) gives units from a separate line instead of ``name [unit]``.
    With ``strict_units=False`` unknown units on columns outside the glossary are
    kept raw (returned in the third element) instead of raising.
    """
    names: list[str] = []
    out_units: list[str | None] = []
    raw: set[str] = set()
    seen: dict[str, str] = {}
    for i, h in enumerate(headers):
        h = str(h).strip()
        if not h:
            raise ColumnError(f"{p}: {where} column {i + 1} has no name; every column needs a header like 'fz [N]'")
        name, unit = nm.parse_header(h)
        if units is not None:
            unit = units[i]
        if name in seen:
            raise ColumnError(f"{p}: the same quantity is given twice: '{seen[name]}' and '{h}' are both "
                              f"'{name}'; keep one column per quantity")
        seen[name] = h
        if unit is not None and unit.strip() != "":
            try:
                unit = nm.check_unit(name, unit)
            except UnitError as exc:
                if not strict_units and name not in nm.GLOSSARY:
                    raw.add(name)
                else:
                    raise UnitError(f"{p}: column '{h}': {exc}") from None
        elif name in nm.GLOSSARY and nm.GLOSSARY[name].dimension not in ("ratio", "count"):
            q = nm.GLOSSARY[name]
            if units is None:
                raise UnitError(f"{p}: column '{h}' has no unit; write it as '{name} [unit]' with one of "
                                + ", ".join(f"[{u}]" for u in nm.UNITS[q.dimension]))
            raise UnitError(f"{p}: channel '{h}' has no unit; accepted for a {q.dimension}: "
                            + ", ".join(nm.UNITS[q.dimension]))
        else:
            unit = None
        names.append(name)
        out_units.append(unit)
    return names, out_units, raw


def parse_cells(p: Path, name: str, header: str, cells: np.ndarray, lines: np.ndarray,
                text_ok: bool) -> np.ndarray:
    """Turn a column of text cells into floats, or keep it as text when allowed.

    Raises ValueRangeError naming the first bad cell (file line, column, value).
    """
    try:  # fast path: every cell is a plain number (the common case; ~2x faster on large files)
        fast = np.asarray(cells, dtype=object).astype(float)
    except (TypeError, ValueError):
        fast = None
    if fast is not None and not np.any(np.isnan(fast)):
        return fast
    s = pd.Series(cells, dtype=object).astype(str).str.strip()
    num = pd.to_numeric(s, errors="coerce").to_numpy(dtype=float)
    bad = np.isnan(num) & ~s.str.lower().isin(["nan", "inf", "-inf", "+inf", "infinity", "-infinity"]).to_numpy()
    if bad.any():
        if text_ok and bad.mean() > 0.5:
            return s.to_numpy(dtype=object)
        i = int(np.flatnonzero(bad)[0])
        val = s.iloc[i]
        what = "an empty cell" if val == "" else f"non-numeric value {val!r}"
        raise ValueRangeError(f"{p}: line {lines[i]}, column '{header}': {what}; a number is needed"
                              + (f" ({int(bad.sum())} such cells in this column)" if bad.sum() > 1 else ""))
    return num
