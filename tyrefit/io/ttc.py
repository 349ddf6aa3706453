"""FSAE Tire Test Consortium (TTC) ``.dat`` files.

Layout (Calspan flat-track exports): line 1 an info line (run and tyre
description), line 2 the channel names, line 3 their units, then one
tab-separated row per sample.  Channel names map to the glossary through
:data:`tyrefit.nomenclature.ALIASES` (``ET V N SA IA RL RE P FX FY FZ MX MZ
SL``); units such as ``N lb deg kPa psi kph mph N-m ft-lb cm in none`` are
converted to SI.  Channels with units tyrefit does not convert (``rpm``,
``degC``, ``deg F``) are kept as they are and flagged in ``meta['columns']``.

TTC data are in the SAE tyre axis system (``FZ`` negative): read them with
``convention='sae'``.  ``SL`` (slip ratio from the effective rolling radius)
is the slip ratio; ``SR``, if present as well, is kept as the extra column
``sr_raw``.

One file holds one continuous record of many sweeps; the reader marks the
table for :func:`tyrefit.io.segment.segment_record`, which cuts it into
steady-condition sweeps.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pandas as pd

from .table import RawTable, map_headers, parse_cells
from ..errors import DataError, FormatError

__all__ = ["parse_ttc"]


def parse_ttc(p: Path, text: str):
    """Parse a TTC ``.dat`` into a :class:`~tyrefit.io.readers.RawTable` (to be segmented)."""

    lines = text.splitlines()
    if len(lines) < 3:
        raise FormatError(f"{p}: {len(lines)} line(s); an FSAE TTC .dat needs an info line, a names line and a "
                          "units line before the data")
    info = lines[0].strip()
    sep = "\t" if "\t" in lines[1] else None
    names_raw = [s.strip() for s in (lines[1].split(sep) if sep else lines[1].split())]
    units_raw = [s.strip() for s in (lines[2].split(sep) if sep else lines[2].split())]
    while names_raw and not names_raw[-1]:
        names_raw.pop()
    units_raw = units_raw[:len(names_raw)] + [""] * (len(names_raw) - len(units_raw))
    if len(names_raw) < 2:
        raise FormatError(f"{p}: line 2 should name the channels (tab separated, e.g. 'ET V SA IA P FX FY FZ MZ'); "
                          f"found {lines[1][:60]!r}")
    upper = [n.upper() for n in names_raw]
    if "SR" in upper and "SL" in upper:
        names_raw[upper.index("SR")] = "SR_raw"  # keep SL as the slip ratio (DESIGN)
    units = [("-" if u.lower() in ("none", "-", "") else u) for u in units_raw]
    names, units_ok, raw = map_headers(p, names_raw, strict_units=False, units=units, where="channel")
    if len(lines) < 4 or not any(s.strip() for s in lines[3:]):
        raise DataError(f"{p}: no data rows after the units line (line 3)")
    body = "\n".join(lines[3:])
    ncol = len(names)
    try:
        arr = pd.read_csv(io.StringIO(body), sep=sep or r"\s+", header=None, engine="c" if sep else "python",
                          dtype=float, skip_blank_lines=True, usecols=range(ncol)).to_numpy()
        line_no = np.flatnonzero([bool(s.strip()) for s in lines[3:]]) + 4
        cells = None
    except (ValueError, pd.errors.ParserError):
        arr, cells = None, None
    if arr is None or arr.shape[0] != len(line_no):
        rows = [(i, s) for i, s in enumerate(lines[3:], 4) if s.strip()]
        line_no = np.array([i for i, _ in rows])
        split = [(s.split(sep) if sep else s.split()) for _, s in rows]
        bad = [k for k, r in enumerate(split) if len([c for c in r[:ncol]]) < ncol]
        if bad:
            k = bad[0]
            raise FormatError(f"{p}: line {line_no[k]} has {len(split[k])} values, line 2 names {ncol} channels")
        cells = np.array([r[:ncol] for r in split], dtype=object)
        arr = None
    values, headers, unit_of = {}, {}, {}
    for j, name in enumerate(names):
        if arr is not None:
            v = arr[:, j].astype(float)
        else:
            v = parse_cells(p, name, names_raw[j], cells[:, j], line_no, text_ok=False)
        values[name] = v
        headers[name] = f"{names_raw[j]} [{units_raw[j]}]" if units_raw[j] else names_raw[j]
        unit_of[name] = units_ok[j] if name not in raw else units_raw[j]
    return RawTable("ttc", values, headers, unit_of, line_no, meta={"info": info}, raw_columns=raw, segment=True)
