"""TYDEX ``.tdx`` measurement files.

TYDEX (TYre Data EXchange format, release 1.3, Unrau & Zamow 1997) is a
keyword file: blocks start with ``**KEYWORD`` lines, ``!`` starts a comment
line.  The blocks read here, all in fixed columns:

``**HEADER``
    name (cols 1-10), description (11-40), value (41-);
``**CONSTANTS``
    name (1-10), description (11-40), unit (41-50), value (51-);
``**MEASURCHANNELS``
    name (1-10), description (11-40), unit (41-50), conversion factor
    (51-60), offset of the measured value (61-70), offset of the physical
    value (71-80);
``**MEASURDATA``
    one row per sample, one field per channel (10 characters each, or
    separated by blanks), ``NOTAVAIL`` for a missing value.

A channel value in its unit is ``(raw - measured offset) * factor + physical
offset`` (factor 1 and offsets 0 when the columns are empty).  Channel
codes map to the glossary through :data:`tyrefit.nomenclature.ALIASES`
(``SLIPANGL INCLANGL FZW FYW FX MZW INFLPRES LONGVEL LONGSLIP``); other
channels are kept under their lower-case code.  Constants that name a
glossary quantity and are not also channels (``INFLPRES``, ``INCLANGL``,
``LONGVEL``, ``FZW``) become constant columns, so the conditions of the
measurement are known.  TYDEX's W-axis system is ISO-W: no sign change.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from .. import nomenclature as nm
from .table import RawTable, map_headers, parse_cells
from ..errors import ColumnError, DataError, FormatError, UnitError

__all__ = ["parse_tydex", "TYDEX_BLOCKS"]

TYDEX_BLOCKS = ("HEADER", "COMMENTS", "CONSTANTS", "MEASURCHANNELS", "MEASURDATA", "MODELDEFINITION",
                "MODELCOEFFICIENTS", "MODELPARAMETERS", "MODELCHANNELS", "MODELOUTPUTS", "MODELEND", "END")

_NUM = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eEdD][+-]?\d+)?$")


def _num(s: str) -> float | None:
    s = s.strip()
    if _NUM.match(s):
        return float(s.replace("D", "E").replace("d", "e"))
    return None


def _blocks(p: Path, text: str) -> dict[str, list[tuple[int, str]]]:
    blocks: dict[str, list[tuple[int, str]]] = {}
    current = None
    for i, line in enumerate(text.splitlines(), 1):
        s = line.rstrip("\r\n")
        if s.lstrip().startswith("**"):
            current = s.strip().lstrip("*").strip().split()[0].upper() if s.strip("* \t") else ""
            blocks.setdefault(current, [])
            continue
        if current is None:
            if s.strip():
                raise FormatError(f"{p}: line {i}: text before the first **KEYWORD; a TYDEX file starts with **HEADER")
            continue
        if not s.strip() or s.lstrip().startswith("!"):
            continue
        blocks[current].append((i, s))
    return blocks


def _channel(p: Path, lineno: int, s: str) -> tuple[str, str, str, float, float, float]:
    """Name, description, unit, factor, measured offset, physical offset of a channel line."""
    name = s[:10].strip()
    if not name:
        raise FormatError(f"{p}: line {lineno}: channel line without a name in columns 1-10")
    desc = s[10:40].strip()
    unit = s[40:50].strip()
    rest = [s[50:60], s[60:70], s[70:80]]
    vals = [_num(x) if x.strip() else None for x in rest]
    fixed_ok = len(name.split()) == 1 and all(v is not None or not x.strip() for v, x in zip(vals, rest))
    if not fixed_ok or len(s) > 80 and s[80:].strip():
        # not in fixed columns: split on blanks from the right (numbers, then the unit)
        tok = s.split()
        nums = []
        while tok and _num(tok[-1]) is not None and len(nums) < 3:
            nums.insert(0, float(_num(tok.pop())))
        if len(tok) < 2:
            raise FormatError(f"{p}: line {lineno}: cannot read channel '{s.strip()[:60]}'; expected name (cols 1-10), "
                              "description (11-40), unit (41-50), factor (51-60), offsets (61-80)")
        name, unit, desc = tok[0], tok[-1], " ".join(tok[1:-1])
        vals = nums + [None] * (3 - len(nums))
    factor = 1.0 if vals[0] is None else vals[0]
    off_meas = 0.0 if vals[1] is None else vals[1]
    off_phys = 0.0 if vals[2] is None else vals[2]
    return name, desc, unit, factor, off_meas, off_phys


def _data_rows(p: Path, rows: list[tuple[int, str]], n: int, names: list[str]) -> tuple[np.ndarray, np.ndarray]:
    lines = np.fromiter((i for i, _ in rows), int, len(rows))
    cells: list[list[str]] = []
    for i, s in rows:
        tok = s.split()
        if len(tok) != n:
            # fixed 10-character fields may touch each other
            w = [s[k:k + 10] for k in range(0, len(s.rstrip()), 10)]
            if len(w) == n and all(x.strip() for x in w):
                tok = [x.strip() for x in w]
            else:
                raise FormatError(f"{p}: line {i}: {len(tok)} values in **MEASURDATA, but {n} channels are declared "
                                  f"in **MEASURCHANNELS ({', '.join(names)})")
        cells.append(tok)
    return np.array(cells, dtype=object).reshape(len(cells), n), lines


def parse_tydex(p: Path, text: str):
    """Parse a TYDEX file into a :class:`~tyrefit.io.readers.RawTable`."""

    blocks = _blocks(p, text)
    if "MEASURCHANNELS" not in blocks:
        raise FormatError(f"{p}: no **MEASURCHANNELS block; a TYDEX measurement file needs **MEASURCHANNELS and "
                          "**MEASURDATA")
    if "MEASURDATA" not in blocks:
        raise FormatError(f"{p}: no **MEASURDATA block; a TYDEX measurement file needs **MEASURCHANNELS and "
                          "**MEASURDATA")
    header = {}
    for _, s in blocks.get("HEADER", []):
        header[s[:10].strip()] = s[40:].strip() or s[10:].strip()
    chans = [_channel(p, i, s) for i, s in blocks["MEASURCHANNELS"]]
    if not chans:
        raise ColumnError(f"{p}: **MEASURCHANNELS declares no channel")
    codes = [c[0] for c in chans]
    units = [c[2] or None for c in chans]
    names, units_ok, raw = map_headers(p, codes, strict_units=False, units=units, where="channel")
    rows = blocks["MEASURDATA"]
    if not rows:
        raise DataError(f"{p}: no data rows in **MEASURDATA")
    cells, lines = _data_rows(p, rows, len(chans), codes)
    cells = np.where(np.char.upper(cells.astype(str)) == "NOTAVAIL", "nan", cells)
    values: dict[str, np.ndarray] = {}
    headers: dict[str, str] = {}
    unit_of: dict[str, str | None] = {}
    for j, (code, desc, unit, factor, off_m, off_p) in enumerate(chans):
        name = names[j]
        v = parse_cells(p, name, code, cells[:, j], lines, text_ok=False)
        values[name] = (v - off_m) * factor + off_p  # TYDEX channel conversion
        headers[name] = f"{code} [{unit}]" if unit else code
        unit_of[name] = units_ok[j]
    constants = {}
    for lineno, s in blocks.get("CONSTANTS", []):
        code, desc, unit, val = s[:10].strip(), s[10:40].strip(), s[40:50].strip(), s[50:].strip()
        num = _num(val.split()[0]) if val else None
        if num is None:  # not in fixed columns: name ... unit value
            tok = s.split()
            if len(tok) >= 2 and _num(tok[-1]) is not None:
                code, val, num = tok[0], tok[-1], _num(tok[-1])
                unit = tok[-2] if len(tok) >= 3 else ""
        constants[code] = {"description": desc, "unit": unit, "value": num if num is not None else val}
        name, _ = nm.parse_header(code)
        if num is not None and name in nm.GLOSSARY and name not in values and name not in ("run",):
            try:
                u = nm.check_unit(name, unit) if unit else None
            except UnitError as exc:
                raise UnitError(f"{p}: line {lineno}, constant {code}: {exc}") from None
            if u is None and nm.GLOSSARY[name].dimension not in ("ratio", "count"):
                continue
            values[name] = np.full(len(lines), float(num))
            headers[name] = f"{code} [{unit}] (constant)"
            unit_of[name] = u
    meta = {"header": header, "constants": constants,
            "channels": {c[0]: {"description": c[1], "unit": c[2], "factor": c[3], "offset_measured": c[4],
                                "offset_physical": c[5]} for c in chans}}
    return RawTable("tdx", values, headers, unit_of, lines, meta=meta, raw_columns=raw)
