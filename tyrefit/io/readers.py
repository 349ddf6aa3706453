"""Read rig data files into one validated, tidy :class:`Dataset`.

:func:`read_data` reads

* CSV tables whose headers carry units (``fz [kN]``, ``slip_angle [deg]``;
  lines starting with ``#`` are comments), for every rig the package knows:
  static-rig lateral tests, dynamic-rig slip-angle and slip-ratio tests,
  contact patch, vertical stiffness (load/unload), braking tables, UTQG
  ratings and particle emission vs force;
* TYDEX ``.tdx`` files (:mod:`tyrefit.io.tydex`);
* FSAE TTC ``.dat`` files (:mod:`tyrefit.io.ttc`), whose one continuous
  record is cut into steady-condition sweeps by :mod:`tyrefit.io.segment`.

A slip-angle or slip-ratio CSV without a ``run`` column but with a rising
``time`` column and at least :data:`CONTINUOUS_MIN_ROWS` rows is a logged
record, not a table of sweeps: it is segmented like a TTC file.

Whatever the format, the result holds canonical column names
(:data:`tyrefit.nomenclature.GLOSSARY`), SI units, the ISO-W sign convention
and an integer ``run`` column (the sweep id).

Sign conventions
----------------
Data are held in ISO-W: ``fz > 0`` in compression and, for a normal tyre, a
positive slip angle gives a negative lateral force.  ``convention='sae'`` (the
SAE tyre axis system of the FSAE TTC data, z down, y to the right) is turned
into ISO-W once, here, by a half turn about the x axis, which negates exactly
these columns (:data:`SAE_FLIPPED`)::

    fz, fy, mz, slip_angle, lateral_displacement

and leaves ``fx``, ``mx``, ``camber``, ``slip_ratio``, speeds, pressures,
lengths and the vertical deflection as they are.  In SAE a positive slip
angle also gives a negative lateral force, so the half turn keeps that
relation: after reading, positive ``slip_angle`` goes with negative ``fy``.

Validation
----------
Every problem raises a :mod:`tyrefit.errors` class with a one-line message
that names the file, the column and the row (file line) and says what is
accepted: see :data:`LIMITS` for the plausibility ranges.
"""

from __future__ import annotations

import csv
import io
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .. import nomenclature as nm
from ..errors import ColumnError, DataError, FormatError, UnitError, ValueRangeError, option
from .table import RawTable, map_headers, parse_cells
from .ttc import parse_ttc
from .tydex import parse_tydex
from ..errors import close_matches
from .inputs import read_input_bytes
from .segment import segment_record

__all__ = [
    "Dataset",
    "read_data",
    "check_fittable",
    "require_patch",
    "detect_kind",
    "KINDS",
    "REQUIRED",
    "LIMITS",
    "SAE_FLIPPED",
    "sniff_format",
    "check_plausible",
    "plausibility_problems",
    "condition_levels",
    "lateral_slope",
]

#: data kinds and what each is
KINDS: dict[str, str] = {
    "static": "static-rig (STTR) lateral push: lateral_displacement, fy, fz",
    "slip_angle": "dynamic-rig slip-angle sweeps: slip_angle, fy, fz",
    "slip_ratio": "dynamic-rig slip-ratio sweeps: slip_ratio, fx, fz",
    "patch": "contact patch: length/width/area and load or fz",
    "vertical": "vertical stiffness (load/unload): vertical_displacement and fz or load",
    "braking": "braking tests: stopping_distance, initial_speed",
    "utqg": "UTQG ratings: treadwear",
    "emission": "particle emission vs force: particles, fx",
}

#: required columns per kind: each entry is a tuple of alternatives (one of them is needed)
REQUIRED: dict[str, list[tuple[str, ...]]] = {
    "static": [("lateral_displacement",), ("fy",), ("fz",)],
    "slip_angle": [("slip_angle",), ("fy",), ("fz",)],
    "slip_ratio": [("slip_ratio",), ("fx",), ("fz",)],
    "patch": [("length", "width", "area"), ("load", "fz")],
    "vertical": [("vertical_displacement",), ("fz", "load")],
    "braking": [("stopping_distance",), ("initial_speed",)],
    "utqg": [("treadwear",)],
    "emission": [("particles",), ("fx",)],
}

#: order in which kinds are tried when none is given
_DETECT_ORDER = ("braking", "utqg", "emission", "static", "patch", "vertical", "slip_angle", "slip_ratio")

#: columns negated when converting SAE to ISO-W (a half turn about x)
SAE_FLIPPED = ("fz", "fy", "mz", "slip_angle", "lateral_displacement")

_DEG = math.pi / 180.0

#: plausibility limits in SI: column -> (low, high, low_inclusive, display unit, text)
LIMITS: dict[str, tuple[float, float, bool, str]] = {
    "fz": (0.0, 200e3, False, "kN"),
    "load": (0.0, 200e3, False, "kN"),
    "slip_angle": (-90 * _DEG, 90 * _DEG, True, "deg"),
    "camber": (-30 * _DEG, 30 * _DEG, True, "deg"),
    "pressure": (0.0, 20e5, False, "bar"),
    "slip_ratio": (-1.0, 1.0, True, "-"),
    "length": (0.0, 2.0, False, "mm"),
    "width": (0.0, 2.0, False, "mm"),
    "area": (0.0, 2.0, False, "cm2"),
    "stopping_distance": (0.0, 1000.0, False, "m"),
    "initial_speed": (0.0, 150.0, False, "km/h"),
    "speed": (-150.0, 150.0, True, "km/h"),
    "treadwear": (0.0, 2000.0, False, "-"),
}

#: kinds that are fitted (check_fittable) and their sweep variable
SWEEP_VARIABLE = {"slip_angle": "slip_angle", "slip_ratio": "slip_ratio", "static": "lateral_displacement"}
#: smallest peak-to-peak variation of the sweep variable that counts as a sweep [SI]
MIN_SWEEP_SPAN = {"slip_angle": 0.5 * _DEG, "slip_ratio": 0.01, "lateral_displacement": 2e-3}

#: set-point channels and their step tolerance [SI] for deriving runs
SETPOINT_TOL = {"load": 0.0, "camber": 0.25 * _DEG, "pressure": 0.1e5, "speed": 1.0 / 3.6}


@dataclass
class Dataset:
    """A tidy data set read from one file.

    Attributes
    ----------
    df : pandas.DataFrame
        one row per sample; canonical column names, SI units, ISO-W signs;
        an integer ``run`` column (sweep id).  Numeric columns are float
        (``run`` is int); text columns (tyre names) are kept as text.
    kind : str
        one of :data:`KINDS`.
    source : str
        the file read.
    convention : str
        sign convention of the *file* (``'iso'`` or ``'sae'``); ``df`` is ISO-W.
    meta : dict
        ``format`` (``csv``, ``tdx``, ``ttc``), ``columns`` (canonical name ->
        header and unit read), ``runs`` (how ``run`` was obtained), format
        specifics (``info`` line, TYDEX header/constants) and, for TTC files,
        ``segmentation``.
    """

    df: pd.DataFrame
    kind: str
    source: str = ""
    convention: str = "iso"
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def n_runs(self) -> int:
        """Number of runs (sweeps)."""
        return int(self.df["run"].nunique()) if "run" in self.df else 1

    def runs(self):
        """Iterate over ``(run_id, DataFrame)`` pairs."""
        return iter(self.df.groupby("run", sort=True))

    def conditions(self) -> pd.DataFrame:
        """One row per run: mean set-point conditions and the number of points.

        Columns ``run``, ``n`` and, where the data have them, ``load``, ``fz`` [N],
        ``camber`` [rad], ``pressure`` [Pa], ``speed`` [m/s] (means over the run).
        """
        cols = [c for c in ("load", "fz", "camber", "pressure", "speed") if c in self.df
                and pd.api.types.is_numeric_dtype(self.df[c])]
        g = self.df.groupby("run", sort=True)
        out = g[cols].mean() if cols else pd.DataFrame(index=g.size().index)
        out.insert(0, "n", g.size())
        return out.reset_index()


# --------------------------------------------------------------------------- sniffing

def _read_bytes(p: Path) -> bytes:
    return read_input_bytes(p, "a data file (CSV, TYDEX .tdx or FSAE TTC .dat)")


_MAGIC = {b"PK\x03\x04": "a ZIP/Excel workbook; save it as CSV",
          b"MATLAB 5.0 MAT-file": "a MATLAB .mat file; export the channels to a .dat or CSV",
          b"\x89HDF": "an HDF5 file; export the channels to CSV",
          b"%PDF": "a PDF document",
          b"\xd0\xcf\x11\xe0": "an old Excel/Office file; save it as CSV"}


def _decode(p: Path, raw: bytes) -> str:
    """Text of the file, or FormatError for empty / binary content."""
    if not raw.strip():
        raise FormatError(f"{p}: file is empty; expected a CSV with unit headers, a TYDEX .tdx or an FSAE TTC .dat")
    for magic, what in _MAGIC.items():
        if raw.startswith(magic):
            raise FormatError(f"{p}: binary content ({what}); tyrefit reads text tables: CSV with unit headers, "
                              "TYDEX .tdx, FSAE TTC .dat")
    head = raw[:8192]
    if b"\x00" in head:
        raise FormatError(f"{p}: binary content (NUL bytes); tyrefit reads text tables: CSV with unit headers, "
                          "TYDEX .tdx, FSAE TTC .dat")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    sample = text[:8192]
    bad = sum(1 for ch in sample if (ord(ch) < 32 and ch not in "\t\r\n\f") or 0x7F <= ord(ch) < 0xA0)
    if bad > 0.02 * len(sample):
        raise FormatError(f"{p}: binary content ({bad} control bytes in the first {len(sample)}); tyrefit reads "
                          "text tables: CSV with unit headers, TYDEX .tdx, FSAE TTC .dat")
    return text


def sniff_format(path: str | os.PathLike, text: str | None = None) -> str:
    """Say which format a file is in: ``tir``, ``chrono_json``, ``json``, ``tdx``, ``ttc`` or ``csv``.

    Raises :class:`FormatError` for empty or binary files.
    """
    p = Path(path)
    if text is None:
        text = _decode(p, _read_bytes(p))
    head = text[:8192]
    up = head.upper()
    suffix = p.suffix.lower()
    if suffix == ".tir" or "PROPERTY_FILE_FORMAT" in up or "[MODEL]" in up or (
            "[LATERAL_COEFFICIENTS]" in up):
        return "tir"
    stripped = head.lstrip()
    if suffix == ".json" or stripped.startswith("{") or stripped.startswith("//"):
        return "chrono_json" if ("Lateral Coefficients" in head or "Pac89" in head) else "json"
    if suffix == ".tdx" or "**MEASURCHANNELS" in up or "**HEADER" in up:
        return "tdx"
    if suffix == ".dat" or _looks_ttc(head):
        return "ttc"
    return "csv"


def _looks_ttc(head: str) -> bool:
    lines = [ln for ln in head.splitlines()[:4]]
    if len(lines) < 4:
        return False
    names, units = lines[1].split("\t"), lines[2].split("\t")
    upper = {n.strip().upper() for n in names}
    return len(names) >= 3 and len(names) == len(units) and "FZ" in upper and bool({"SA", "SL"} & upper)


# --------------------------------------------------------------------------- public reader

def read_data(path: str | os.PathLike, convention: str = "iso", kind: str | None = None,
              checks: bool = True) -> Dataset:
    """Read a rig data file into a validated :class:`Dataset`.

    Parameters
    ----------
    path : str or path-like
        CSV with unit headers, TYDEX ``.tdx`` or FSAE TTC ``.dat``.
    convention : {'iso', 'sae'}
        sign convention of the file.  ``'sae'`` negates :data:`SAE_FLIPPED`
        (``fz, fy, mz, slip_angle, lateral_displacement``) to give ISO-W.
    kind : str, optional
        one of :data:`KINDS`; detected from the columns when omitted.
    checks : bool
        run :func:`check_plausible` on sweep data (default); ``False`` leaves
        it to the caller (``inspect`` lists the problems instead).

    Returns
    -------
    Dataset

    Raises
    ------
    FormatError
        empty, binary or unreadable file; a tyre property file given as data.
    ColumnError
        missing required column, a quantity given twice, no header.
    UnitError
        unknown unit or one that does not fit the quantity.
    ValueRangeError
        non-numeric, NaN/inf or implausible values (see :data:`LIMITS`).
    """
    p = Path(path)
    if convention not in ("iso", "sae"):
        raise DataError(f"{p}: unknown sign convention {convention!r}; accepted: 'iso', 'sae'")
    if kind is not None and kind not in KINDS:
        raise DataError(f"{p}: unknown data kind {kind!r}; accepted: " + ", ".join(KINDS)
                        + _close(kind, KINDS))
    text = _decode(p, _read_bytes(p))
    fmt = sniff_format(p, text)
    if fmt in ("tir", "chrono_json"):
        raise FormatError(f"{p}: this is a tyre property file ({'.tir' if fmt == 'tir' else 'Chrono JSON'}), "
                          "not measurement data; use it with compare/sim (or inspect it)")
    if fmt == "json":
        raise FormatError(f"{p}: a JSON file is not measurement data; tyrefit reads CSV with unit headers, "
                          "TYDEX .tdx and FSAE TTC .dat")
    if fmt == "tdx":
        table = parse_tydex(p, text)
    elif fmt == "ttc":

        table = parse_ttc(p, text)
    else:
        table = parse_csv(p, text)
    ds = _finish(table, p, convention, kind)
    if checks and ds.kind in FIT_KINDS:
        check_plausible(ds, {c: v["header"] for c, v in ds.meta["columns"].items()})
    return ds


def _close(word, choices) -> str:
    return close_matches(word, choices)


def _parse_numeric_fast(p: Path, kept: list[str], lines: list[int], delim: str) -> "RawTable | None":
    """pandas' C tokenizer for the common case: every data cell a plain number.

    Returns None (and the careful path below parses the file, with its
    line-and-column messages) unless every row has the header's cell count and
    every cell is a finite-or-inf number; values are exactly Python's float().
    """
    if '"' in kept[0] or "'" in kept[0]:
        return None  # quoted header cells: leave them to the csv module
    header = kept[0].split(delim)
    if len(kept) < 2 or not header:
        return None
    try:
        arr = pd.read_csv(io.StringIO("\n".join(kept[1:])), sep=delim, header=None, dtype=float, engine="c",
                          skip_blank_lines=False).to_numpy()
    except (ValueError, TypeError, pd.errors.ParserError, csv.Error, OverflowError):
        return None
    if arr.shape != (len(kept) - 1, len(header)) or np.isnan(arr).any():
        return None
    header = [h.strip() for h in header]
    names, units, _ = map_headers(p, header)
    line_arr = np.asarray(lines[1:])
    values = {name: np.ascontiguousarray(arr[:, j]) for j, name in enumerate(names)}
    return RawTable("csv", values, dict(zip(names, header)), dict(zip(names, units)), line_arr)


def parse_csv(p: Path, text: str) -> RawTable:
    """Parse a CSV with ``name [unit]`` headers (comma, semicolon or tab)."""
    kept: list[str] = []
    lines: list[int] = []
    for i, line in enumerate(text.splitlines(), 1):
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        kept.append(line)
        lines.append(i)
    if not kept:
        raise FormatError(f"{p}: no header line (only comments); a CSV needs a header like 'fz [N],fy [N],...'")
    first = kept[0]
    delim = "\t" if "\t" in first else (";" if first.count(";") > first.count(",") else ",")
    fast = _parse_numeric_fast(p, kept, lines, delim)
    if fast is not None:
        return fast
    try:
        rows = list(csv.reader(io.StringIO("\n".join(kept)), delimiter=delim))
    except csv.Error as exc:  # e.g. a cell longer than the csv module's field limit
        raise FormatError(f"{p}: cannot split the table into cells ({exc}); expected a CSV with unit headers") from None
    header = [h.strip() for h in rows[0]]
    if len(rows) < 2:
        raise DataError(f"{p}: no data rows after the header (line {lines[0]})")
    ncol = len(header)
    body = rows[1:]
    lens = np.fromiter((len(r) for r in body), int, len(body))
    wrong = np.flatnonzero(lens != ncol)
    if wrong.size:
        i = int(wrong[0])
        raise FormatError(f"{p}: line {lines[i + 1]} has {lens[i]} cells, the header has {ncol}; "
                          f"every row needs one cell per column (delimiter {delim!r})")
    names, units, _ = map_headers(p, header)
    line_arr = np.asarray(lines[1:])
    cells = np.array(body, dtype=object)
    values: dict[str, np.ndarray] = {}
    for j, name in enumerate(names):
        values[name] = parse_cells(p, name, header[j], cells[:, j], line_arr,
                                   text_ok=name not in nm.GLOSSARY)
    return RawTable("csv", values, dict(zip(names, header)), dict(zip(names, units)), line_arr)


# --------------------------------------------------------------------------- conversion and validation

def _fmt(v: float, unit: str) -> str:
    x = nm.from_si(v, unit) if unit != "-" else v
    return f"{x:.6g} {unit}".rstrip()


def detect_kind(columns) -> str | None:
    """The data kind that the columns describe (first match of :data:`REQUIRED`), or None."""
    cols = set(columns)
    for k in _DETECT_ORDER:
        if all(any(a in cols for a in alts) for alts in REQUIRED[k]):
            return k
    return None


def _spread(x: np.ndarray) -> float:
    """Share of 50 equal bins over the range of ``x`` that hold at least 1 % of the samples.

    Near 1 for a swept variable (it passes through its whole range), small
    for a set point that sits at a few levels.
    """
    x = x[np.isfinite(x)]
    if x.size < 10 or np.ptp(x) == 0:
        return 0.0
    counts, _ = np.histogram(x, bins=50)
    return float(np.mean(counts >= 0.01 * x.size))


def _sweep_kind(t: "RawTable") -> str:
    """Slip-angle or slip-ratio test, for files that hold both channels (TTC, combined slip).

    A slip-ratio test when the slip ratio spans more than 0.05 and is more
    evenly swept (:func:`_spread`) than the slip angle, which then sits at
    set-point levels (FSAE TTC drive/brake runs: SA at 0, -3, -6 deg).
    """
    sa, sr = t.values["slip_angle"], t.values["slip_ratio"]
    if sa.dtype == object or sr.dtype == object or not sa.size:
        return "slip_angle"
    sa = np.asarray(nm.to_si(sa.astype(float), t.units["slip_angle"] or "rad"))
    sr = np.asarray(nm.to_si(sr.astype(float), t.units["slip_ratio"] or "-"))
    span_sa = float(np.ptp(sa[np.isfinite(sa)])) if np.isfinite(sa).any() else 0.0
    span_sr = float(np.ptp(sr[np.isfinite(sr)])) if np.isfinite(sr).any() else 0.0
    if span_sr > 0.05 and _spread(sr) >= _spread(sa):
        return "slip_ratio"
    if span_sa < 1 * _DEG and span_sr > 0.02:
        return "slip_ratio"
    return "slip_angle"


def _missing(kind: str, cols) -> list[str]:
    return [" or ".join(alts) for alts in REQUIRED[kind] if not any(a in cols for a in alts)]


def _finish(t: RawTable, p: Path, convention: str, kind: str | None) -> Dataset:
    cols = set(t.values)
    # kind ----------------------------------------------------------------
    if kind is None:
        kind = detect_kind(cols)
        if kind == "slip_angle" and "slip_ratio" in cols and "fx" in cols:
            kind = _sweep_kind(t)
        if kind is None:
            found = ", ".join(f"'{t.headers[c]}'" for c in t.values) or "none"
            raise ColumnError(f"{p}: cannot tell what test this is from its columns ({found}); needed: "
                              + "; ".join(f"{k}: {', '.join(' or '.join(a) for a in REQUIRED[k])}" for k in KINDS))
    else:
        miss = _missing(kind, cols)
        if miss:
            found = ", ".join(f"'{t.headers[c]}'" for c in t.values)
            raise ColumnError(f"{p}: missing required column{'s' if len(miss) > 1 else ''} "
                              f"{', '.join(repr(m) for m in miss)} for a {kind} "
                              f"test ({KINDS[kind]}); found {found}")
    # units -> SI ---------------------------------------------------------
    data: dict[str, np.ndarray] = {}
    for name, v in t.values.items():
        u = t.units.get(name)
        if v.dtype != object and u is not None and name not in t.raw_columns:
            v = np.asarray(nm.to_si(v.astype(float), u), dtype=float)
        data[name] = v
    per_distance = [c for c, u in t.units.items() if u and c in nm.GLOSSARY and nm.GLOSSARY[c].dimension == "rate"
                    and nm.dimension_of(u) == "per_distance"]
    for c in per_distance:  # particles [#/km]: a rate only with the speed it was measured at
        if "speed" not in data or data["speed"].dtype == object:
            raise UnitError(f"{p}: column '{t.headers[c]}' is per distance, but the emission law N(F) (Pham et al. 2025 "
                            "Eq. 14) is particles per second; add a 'speed [km/h]' column to convert, or give the "
                            "rate in [#/s]")
        data[c] = data[c] * np.abs(data["speed"])  # [#/m] * [m/s] = [#/s]
    # convention ----------------------------------------------------------
    flipped = []
    if convention == "sae":
        for c in SAE_FLIPPED:
            if c in data and data[c].dtype != object:
                data[c] = -data[c]
                flipped.append(c)
    df = pd.DataFrame(data)
    df.index = pd.Index(t.lines, name="line")
    meta: dict[str, Any] = {"format": t.format, **t.meta}
    meta["columns"] = {c: {"header": t.headers[c], "unit": t.units.get(c),
                           "si_unit": nm.GLOSSARY[c].si_unit if c in nm.GLOSSARY else None,
                           **({"converted": False} if c in t.raw_columns else {})} for c in t.values}
    meta["flipped"] = flipped
    # finite everywhere ---------------------------------------------------
    for c in df.columns:
        if not pd.api.types.is_numeric_dtype(df[c]):  # text columns (object or pandas str dtype)
            continue
        v = df[c].to_numpy()
        bad = ~np.isfinite(v)
        if c in t.raw_columns or (t.segment and c not in nm.GLOSSARY):
            continue
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise ValueRangeError(f"{p}: line {df.index[i]}, column '{t.headers[c]}': value {v[i]} is not a finite "
                                  f"number; NaN, inf and empty cells are not accepted ({int(bad.sum())} in this column)")
    # sign hint for SAE files read as ISO ----------------------------------
    if "fz" in df and convention == "iso" and _numeric(df["fz"]) and np.nanmedian(df["fz"]) < 0:
        raise ValueRangeError(f"{p}: column '{t.headers['fz']}' is mostly negative (median "
                              f"{np.nanmedian(df['fz']):.4g} N); tyrefit holds loads positive in compression: if the "
                              "file uses the SAE convention (FZ negative, as FSAE TTC) pass "
                              f"{option('convention', 'sae')}")
    # runs ----------------------------------------------------------------
    if not t.segment and _continuous_record(df, kind):
        t.segment = True
        df, note = _time_order(df)
        if note:
            meta["time_order"] = note
    if t.segment:
        df, seg = segment_record(df, kind, source=str(p))
        meta["segmentation"] = seg
        meta["runs"] = "segmented from the continuous record (see segmentation)"
    elif "run" in df:
        r = df["run"].to_numpy()
        if r.dtype == object or not np.all(np.isclose(r, np.round(r))):
            i = int(np.flatnonzero(~np.isclose(np.asarray(r, float), np.round(np.asarray(r, float))))[0]) \
                if r.dtype != object else 0
            raise ValueRangeError(f"{p}: line {df.index[i]}, column '{t.headers['run']}': run ids must be integers "
                                  f"(found {r[i]!r})")
        meta["runs"] = "given in the file"
    else:
        df["run"], how = derive_runs(df, kind)
        meta["runs"] = how
    df["run"] = df["run"].astype(int)
    if kind == "vertical" and "phase" not in df:
        df["phase"] = load_phase(df["vertical_displacement"].to_numpy(), df["run"].to_numpy())
        meta["phase"] = "derived from the sign of the displacement increments (+1 load, -1 unload)"
    # warm-up: samples with fz <= 0 before a sweep's first loaded sample are dropped and counted ----------
    if kind in SWEEP_VARIABLE and "fz" in df and _numeric(df["fz"]) and len(df):
        unloaded = df["fz"].to_numpy(float) <= 0
        if unloaded.any():
            by_run = pd.Series(~unloaded, index=df.index).groupby(df["run"].to_numpy())
            seen = by_run.cummax().to_numpy()  # a loaded sample earlier in the same run
            has_loaded = by_run.transform("any").to_numpy()
            first = int(np.argmax(~unloaded))  # the file's first loaded sample
            # before the file's first loaded sample, or before the first loaded sample of a run that has one;
            # an unloaded stretch after loaded data (lift-off mid-test) is still refused
            warm = unloaded & ((np.arange(len(df)) < first) | (~seen & has_loaded))
            if warm.any() and not warm.all():
                df = df[~warm]
                meta["dropped"] = {"warm-up: fz <= 0 before the sweep's first loaded sample": int(warm.sum())}
    # plausibility --------------------------------------------------------
    _check_ranges(df, kind, p, t.headers, t.units)
    df = df.reset_index(drop=True)
    order = ["run"] + [c for c in df.columns if c != "run"]
    df = df[order]
    if df.empty:
        raise DataError(f"{p}: no data rows left to use")
    return Dataset(df=df, kind=kind, source=str(p), convention=convention, meta=meta)


# --------------------------------------------------------------------------- plausibility of sweep data

#: implied friction coefficient |F|max / Fz of a sweep: above the first is not a tyre on a road (loads in kN
#: labelled [N]?); a whole file below the second is forces in kN labelled [N] (or a stuck channel)
MU_LIMITS = (0.05, 4.0)
#: a file with more distinct load levels than this is a ramp, not sweeps at held loads
MAX_LOAD_LEVELS = 25
#: sweeps with fewer points than this (median over the file) are not sweeps but one condition per sample
MIN_SWEEP_POINTS = 8
#: sweep span from which a tyre builds at least 0.05 Fz (the low-friction check looks only at these)
_WIDE_SPAN = {"slip_angle": 2 * _DEG, "slip_ratio": 0.03}
#: force channel and expected sign of dF/d(sweep variable) in ISO-W, per kind
_FORCE = {"slip_angle": ("fy", -1.0), "slip_ratio": ("fx", 1.0), "static": ("fy", 1.0)}


def _sweep_slopes(df: pd.DataFrame, var: str, force: str) -> pd.DataFrame:
    """Per run: n, correlation and slope sign of force against the sweep variable, max |F|, median fz."""
    g = df.groupby("run", sort=True)
    x, y = df[var], df[force]
    xm, ym = g[var].transform("mean"), g[force].transform("mean")
    dx, dy = x - xm, y - ym
    # max |F| of the 5-sample running median (record order): a few spikes are the fitter's to screen
    # (tyrefit.fitting.engine.screen_sweeps), not a reason to ask whether the loads are in kN
    absf = y.abs().groupby(df["run"]).transform(lambda v: v.rolling(5, center=True, min_periods=1).median())
    tmp = pd.DataFrame({"run": df["run"], "sxy": dx * dy, "sxx": dx * dx, "syy": dy * dy,
                        "absf": absf, "fz": df["fz"] if "fz" in df else np.nan})
    s = tmp.groupby("run", sort=True).agg(n=("sxy", "size"), sxy=("sxy", "sum"), sxx=("sxx", "sum"),
                                          syy=("syy", "sum"), fmax=("absf", "max"), fz=("fz", "median"))
    den = np.sqrt(s["sxx"] * s["syy"])
    s["r"] = np.where(den > 0, s["sxy"] / np.where(den > 0, den, 1.0), 0.0)
    s["span_f"] = g[force].agg(lambda v: float(np.ptp(v.to_numpy())))
    s["span_x"] = g[var].agg(lambda v: float(np.ptp(v.to_numpy())))
    return s


def plausibility_problems(ds: Dataset) -> list[str]:
    """The problem :func:`check_plausible` would raise, as a list (empty when the data pass)."""
    try:
        check_plausible(ds, {c: v.get("header", c) for c, v in ds.meta.get("columns", {}).items()})
    except ValueRangeError as exc:
        return [str(exc)]
    return []


def check_plausible(ds: Dataset, headers: dict[str, str] | None = None) -> None:
    """Refuse sweep data that cannot be a tyre measured as labelled, naming the problem.

    Checks, for slip-angle, slip-ratio and static-rig tests:

    * **too many conditions** - a median of fewer than :data:`MIN_SWEEP_POINTS`
      points per sweep (a run id per sample), or more than
      :data:`MAX_LOAD_LEVELS` distinct loads (a load ramp, not sweeps at held
      loads);
    * **stuck channel** - the force channel constant over a sweep whose slip varies;
    * **implied friction** - a sweep whose |F|max / Fz is over 4 (loads in kN
      labelled [N]?), or a file whose sweeps all stay under 0.05 (forces in kN
      labelled [N]?);
    * **sign** - sweeps whose force falls with slip where others rise (sweeps
      of opposite sign), or every sweep against the ISO-W orientation (a
      positive slip angle gives a negative lateral force; a static push a
      force of the displacement's sign; a driving slip ratio a positive Fx).

    Raises :class:`~tyrefit.errors.ValueRangeError` (one line).
    """
    df, kind, src = ds.df, ds.kind, ds.source
    if kind not in _FORCE:
        return
    force, sign = _FORCE[kind]
    var = SWEEP_VARIABLE[kind]
    if force not in df or var not in df or "fz" not in df or df.empty:
        return
    if not all(_numeric(df[c]) for c in (force, var, "fz")):
        return
    h = headers or {}
    hf, hz = h.get(force, force), h.get("fz", "fz")
    s = _sweep_slopes(df, var, force)
    moving = s[s["span_x"] >= MIN_SWEEP_SPAN[var]]
    # too many conditions -----------------------------------------------------------
    n_runs = len(s)
    if n_runs >= 20 and float(s["n"].median()) < MIN_SWEEP_POINTS:
        raise ValueRangeError(f"{src}: {n_runs} sweeps with a median of {float(s['n'].median()):g} points each: too "
                              "many distinct conditions to be slip sweeps (a run id per sample, or a set point that "
                              f"changes every few samples?); each sweep needs at least {MIN_SWEEP_POINTS} points")
    if kind != "static":
        src_col = "load" if "load" in df and _numeric(df["load"]) else "fz"
        levels = _group_levels(df.groupby("run")[src_col].median().to_numpy(), 100.0, 0.02)
        g = df.groupby("run")["fz"]
        drift = (g.agg(lambda v: float(np.ptp(v.to_numpy()))) / g.median().abs().clip(lower=1.0)).to_numpy()
        if n_runs >= 3 and float(np.median(drift)) > 0.5:
            raise ValueRangeError(f"{src}: the load is not held during the sweeps (it varies by a median "
                                  f"{float(np.median(drift)):.0%} of its value within a sweep, over {n_runs} "
                                  "sweeps): a load ramp is not slip sweeps at held loads")
        if len(levels) > MAX_LOAD_LEVELS and _load_moves_in_sweeps(df, src_col, levels):
            raise ValueRangeError(f"{src}: {len(levels)} distinct loads from {levels[0]:.0f} to {levels[-1]:.0f} N "
                                  f"over {n_runs} sweeps: too many conditions to be sweeps at held loads (a load "
                                  f"ramp?); rig sweeps hold the load at a few levels (at most {MAX_LOAD_LEVELS})")
    if moving.empty:
        return
    # stuck channel -------------------------------------------------------------------
    stuck = moving[moving["span_f"] == 0]
    if len(stuck):
        r = int(stuck.index[0])
        val = float(df.loc[df["run"] == r, force].iloc[0])
        raise ValueRangeError(f"{src}: column '{hf}' is constant ({val:g} N) in sweep {r} while its {var} varies "
                              f"({len(stuck)} of {len(moving)} sweeps): a stuck or disconnected channel")
    # implied friction ------------------------------------------------------------------
    fz = moving["fz"].to_numpy(float)
    mu = np.where(fz > 0, moving["fmax"].to_numpy(float) / np.where(fz > 0, fz, 1.0), np.nan)
    hi = np.flatnonzero(mu > MU_LIMITS[1])
    if hi.size:
        i = int(hi[0])
        raise ValueRangeError(f"{src}: sweep {int(moving.index[i])} implies a friction coefficient |{force}|max/Fz of "
                              f"{mu[i]:.3g} at Fz {fz[i]:.4g} N (accepted {MU_LIMITS[0]:g} to {MU_LIMITS[1]:g}; "
                              f"{hi.size} sweep{'s' if hi.size > 1 else ''} over): are the loads in kN? column "
                              f"'{hz}' is read as given")
    wide = moving["span_x"].to_numpy(float) >= _WIDE_SPAN.get(var, np.inf)  # sweeps long enough to build force
    if kind != "static" and np.isfinite(mu[wide]).any() and np.nanmax(mu[wide]) < MU_LIMITS[0]:
        raise ValueRangeError(f"{src}: every sweep implies a friction coefficient |{force}|max/Fz under "
                              f"{MU_LIMITS[0]:g} (largest {np.nanmax(mu[wide]):.3g}): are the forces in kN? column "
                              f"'{hf}' is read as given (or the '{hz}' load is in the wrong unit)")
    # sign --------------------------------------------------------------------------
    clear = moving[moving["r"].abs() > 0.5]
    if len(clear) and kind != "static":  # static pushes: the rig pipeline takes either orientation
        pos, neg = clear[clear["r"] * sign > 0], clear[clear["r"] * sign < 0]
        if len(pos) and len(neg):
            a, b = (pos, neg) if len(pos) >= len(neg) else (neg, pos)
            raise ValueRangeError(f"{src}: sweeps of opposite sign: '{hf}' {'falls' if (b['r'].iloc[0] < 0) else 'rises'}"
                                  f" with {var} in sweep{'s' if len(b) > 1 else ''} "
                                  f"{', '.join(str(int(x)) for x in b.index[:5])} but "
                                  f"{'rises' if (b['r'].iloc[0] < 0) else 'falls'} in {len(a)} other"
                                  f"{'s' if len(a) > 1 else ''}: a channel inverted part-way, or mixed sign "
                                  "conventions")
        if len(neg) and not len(pos):
            expect = {"slip_angle": "a positive slip angle gives a negative lateral force",
                      "slip_ratio": "a positive (driving) slip ratio gives a positive Fx"}[kind]
            raise ValueRangeError(f"{src}: sign of '{hf}' is reversed in every sweep (ISO-W: {expect}; SAE files "
                                  "keep that relation): the force channel (or the slip channel) is inverted")


def _load_moves_in_sweeps(df: pd.DataFrame, col: str, levels) -> bool:
    """Does the load move within the sweeps by a good part of the step between load levels?

    A load programme of many held levels (40 loads, one sweep each) holds each load through its
    sweep: the load's change from a sweep's start to its end (least-squares line over the sweep's
    samples) is noise, of either sign, with a median near 0.  A load ramp cut into sweeps moves the
    same way in every sweep by about one step.  True when the median signed change is over a quarter
    of the median step between levels.
    """
    lv = np.sort(np.asarray(levels, float))
    if lv.size < 2:
        return False
    step = float(np.median(np.diff(lv)))
    g = df.groupby("run", sort=False)
    x = g.cumcount().to_numpy(float)
    y = df[col].to_numpy(float)
    runs = df["run"].to_numpy()
    t = pd.DataFrame({"run": runs, "x": x, "y": y, "xx": x * x, "xy": x * y})
    a = t.groupby("run", sort=False).agg(n=("x", "size"), sx=("x", "sum"), sy=("y", "sum"), sxx=("xx", "sum"),
                                         sxy=("xy", "sum"))
    a = a[a["n"] >= 3]
    if a.empty:
        return True
    den = a["n"] * a["sxx"] - a["sx"] ** 2
    slope = (a["n"] * a["sxy"] - a["sx"] * a["sy"]) / den.where(den > 0)
    change = (slope * (a["n"] - 1)).dropna().to_numpy(float)
    return bool(change.size == 0 or abs(float(np.median(change))) > 0.25 * step)


#: a CSV without a run column is treated as one continuous record (and segmented) from this many rows on
CONTINUOUS_MIN_ROWS = 1000


#: a logged record's clock may repeat or swap a few samples (an export's rounding, a logger's buffer):
#: at most this share of its steps may fail to rise, each back by at most :data:`_MAX_BACK_STEPS` sample times
_MAX_UNORDERED = 0.01
_MAX_BACK_STEPS = 10.0


def _continuous_record(df: pd.DataFrame, kind: str) -> bool:
    """A logged record rather than a table of sweeps: slip test, no ``run``, a rising ``time``, many rows.

    The clock must rise over the record; a few repeated or swapped samples (at most 1 % of the steps,
    none back by more than 10 sample times) are allowed and put in time order by :func:`_time_order`.
    A clock that restarts (two records joined) is not one record.
    """
    if kind not in ("slip_angle", "slip_ratio") or "run" in df or "time" not in df or len(df) < CONTINUOUS_MIN_ROWS:
        return False
    if not _numeric(df["time"]):
        return False
    t = df["time"].to_numpy(float)
    if not np.all(np.isfinite(t)):
        return False
    d = np.diff(t)
    if np.all(d > 0):
        return True
    rising = d[d > 0]
    if rising.size < (1 - _MAX_UNORDERED) * d.size:
        return False
    dt = float(np.median(rising))
    return bool(t[-1] > t[0] and np.all(d >= -_MAX_BACK_STEPS * dt))


def _time_order(df: pd.DataFrame) -> tuple[pd.DataFrame, str | None]:
    """``df`` in time order (stable: repeated times keep the file's order) and a note, or ``df`` and None."""
    d = np.diff(df["time"].to_numpy(float))
    back, same = int((d < 0).sum()), int((d == 0).sum())
    if not back and not same:
        return df, None
    note = (f"time: {same} repeated and {back} out-of-order sample time{'s' if back + same > 1 else ''}; "
            "samples read in time order")
    return (df.sort_values("time", kind="mergesort") if back else df), note


def _check_ranges(df: pd.DataFrame, kind: str, p: Path, headers: dict[str, str],
                  units: dict[str, str | None] | None = None) -> None:
    for c, (lo, hi, lo_incl, unit) in LIMITS.items():
        if c not in df or not _numeric(df[c]):
            continue
        v = df[c].to_numpy()
        lo_eff = lo
        incl = lo_incl
        if c in ("fz", "load") and kind == "vertical":
            incl = True  # a load/unload cycle starts and ends at zero load
        low_bad = (v < lo_eff) if incl else (v <= lo_eff)
        bad = low_bad | (v > hi)
        if not bad.any():
            continue
        i = int(np.flatnonzero(bad)[0])
        h = headers.get(c, c)
        if c in ("fz", "load"):
            acc = f"{'0 <=' if incl else '0 <'} {c} <= {_fmt(hi, 'kN')}"
            what = "zero or negative load" if v[i] <= 0 else "implausibly large load"
        elif lo < 0:
            acc = f"|{c}| <= {_fmt(hi, unit)}"
            what = "out of range"
        else:
            acc = f"0 < {c} <= {_fmt(hi, unit)}"
            what = "out of range"
        disp = unit if unit != "kN" else "N"
        shown = _fmt(v[i], disp)
        u_file = (units or {}).get(c)
        if u_file and u_file not in (disp, "-"):
            try:
                conv = nm.from_si(v[i], disp) if disp != "-" else v[i]
                shown = f"{nm.from_si(v[i], u_file):.6g} {u_file} = {conv:{'.6g' if disp == 'N' else '.4g'}} {disp}"
            except UnitError:
                pass
        raise ValueRangeError(f"{p}: line {df.index[i]}, column '{h}': {what}, {shown}; accepted "
                              f"{acc} ({int(bad.sum())} value{'s' if bad.sum() > 1 else ''} outside)")


def _numeric(col: pd.Series) -> bool:
    return pd.api.types.is_numeric_dtype(col) and not pd.api.types.is_bool_dtype(col)


def _median(x: np.ndarray, w: int) -> np.ndarray:
    if len(x) < 3 or w <= 1:
        return x
    return pd.Series(x).rolling(w, center=True, min_periods=1).median().to_numpy()


def derive_runs(df: pd.DataFrame, kind: str) -> tuple[np.ndarray, str]:
    """Run ids for a table without a ``run`` column, and how they were found.

    A new run starts where a set-point changes (``load``, ``camber``,
    ``pressure``, ``speed``: step larger than :data:`SETPOINT_TOL`, on a
    5-sample running median; for patch and vertical tests the load is the
    swept variable and does not start a run; tables of braking, UTQG and
    emission results are one run), where the measured ``fz`` of a sweep test steps
    by more than max(150 N, 8 %) on its running median, and where the sweep
    variable jumps back by more than half its span in one sample (a new sweep
    starting again from the same end).
    """
    n = len(df)
    if n == 0:
        return np.zeros(0, int), "none"
    start = np.zeros(n, bool)
    why = []
    w = 5 if n >= 20 else 1
    # patch and vertical tests sweep the load itself: only the other set points start a new run
    setpoints = {c: t for c, t in SETPOINT_TOL.items()
                 if not (kind in ("patch", "vertical") and c == "load")}
    if kind in ("braking", "utqg", "emission"):
        setpoints = {}
    for c, tol in setpoints.items():
        if c not in df or not _numeric(df[c]):
            continue
        x = df[c].to_numpy(float)
        if c == "load":
            tol = max(1e-6 * np.nanmax(np.abs(x)), 1e-9)
            s = x
        else:
            s = _median(x, w)
        step = np.abs(np.diff(s)) > tol
        if step.any():
            start[1:] |= step
            why.append(c)
    if kind in SWEEP_VARIABLE and "fz" in df and "load" not in df:
        fz = df["fz"].to_numpy(float)
        s = _median(fz, w)
        tol = np.maximum(150.0, 0.08 * np.abs(s[:-1]))
        step = np.abs(np.diff(s)) > tol
        # a running median smears one step over a few samples: keep the first of each cluster
        step[1:] &= ~step[:-1]
        if step.any():
            start[1:] |= step
            why.append("fz steps")
    var = SWEEP_VARIABLE.get(kind)
    if var and var in df:
        x = df[var].to_numpy(float)
        span = np.ptp(x) if n else 0.0
        if span > 0:
            d = np.diff(x)
            # direction of the sweep: the sign most increments have
            direction = np.sign(np.median(d[d != 0])) if np.any(d != 0) else 0
            jump = (np.abs(d) > 0.5 * span) & (np.sign(d) == -direction)
            if jump.any():
                start[1:] |= jump
                why.append(f"{var} restarts")
    run = np.cumsum(start)
    how = ("derived from changes in " + ", ".join(why)) if why else "one run (no set-point changes found)"
    return run, how


def load_phase(disp: np.ndarray, run: np.ndarray | None = None) -> np.ndarray:
    """+1 where the deflection grows (loading), -1 where it falls (unloading).

    Zero increments take the phase of the previous sample; the first sample
    of each run takes the phase of the next.
    """
    n = len(disp)
    if n == 0:
        return np.zeros(0)
    d = np.diff(disp, prepend=np.nan)
    if run is not None:
        newrun = np.r_[True, np.diff(run) != 0]
        d[newrun] = np.nan
    s = pd.Series(np.sign(d)).replace(0.0, np.nan)
    s = s.ffill()
    if run is not None:
        s = s.groupby(pd.Series(run)).bfill()
    s = s.bfill().fillna(1.0)
    return s.to_numpy(float)


# --------------------------------------------------------------------------- summaries

#: grouping tolerance of condition levels: absolute [SI] and relative
_LEVEL_TOL = {"fz": (100.0, 0.05), "camber": (0.25 * _DEG, 0.0), "pressure": (5e3, 0.0), "speed": (1.0, 0.0)}


def _group_levels(values: np.ndarray, atol: float, rtol: float) -> list[float]:
    v = np.sort(np.asarray(values, float)[np.isfinite(values)])
    if v.size == 0:
        return []
    gap = np.diff(v) > np.maximum(atol, rtol * np.abs(v[1:]))
    groups = np.split(v, np.flatnonzero(gap) + 1)
    return [float(np.mean(g)) for g in groups]


def condition_levels(ds: Dataset) -> dict[str, list[float]]:
    """Distinct test conditions over the runs of ``ds``.

    Run means are grouped when closer than 100 N or 5 % (load), 0.25 deg
    (camber), 5 kPa (pressure), 1 m/s (speed).  Returns ``{"fz": [N],
    "camber": [deg], "pressure": [Pa], "speed": [m/s]}`` with the keys present
    in the data; ``fz`` uses the ``load`` set point where the file gives one
    (the measured load of a static test falls during the push) and is left
    out for patch and vertical tests, whose load is the swept variable.
    """
    cond = ds.conditions()
    out: dict[str, list[float]] = {}
    src = "load" if "load" in cond else "fz"
    if src in cond and ds.kind not in ("patch", "vertical"):  # those sweep the load itself
        out["fz"] = [round(x, 1) for x in _group_levels(cond[src].to_numpy(), *_LEVEL_TOL["fz"])]
    if "camber" in cond:
        out["camber"] = [round(x / _DEG, 3) for x in _group_levels(cond["camber"].to_numpy(), *_LEVEL_TOL["camber"])]
    if "pressure" in cond:
        out["pressure"] = [round(x, 0) for x in _group_levels(cond["pressure"].to_numpy(), *_LEVEL_TOL["pressure"])]
    if "speed" in cond:
        out["speed"] = [round(x, 3) for x in _group_levels(cond["speed"].to_numpy(), *_LEVEL_TOL["speed"])]
    return out


def lateral_slope(ds: Dataset, max_slip: float = 2 * _DEG) -> float | None:
    """dFy/dalpha [N/rad] near zero slip (least squares on |alpha| <= ``max_slip``, per-run offsets removed).

    Negative in ISO-W for a normal tyre; None when the data have no slip
    angle and lateral force or too few points near zero slip.
    """
    df = ds.df
    if "slip_angle" not in df or "fy" not in df:
        return None
    absa = df["slip_angle"].abs()
    sel = absa <= max(max_slip, float(absa.quantile(0.3)))
    if sel.sum() < 3:
        return None
    d = df.loc[sel, ["run", "slip_angle", "fy"]]
    a = d["slip_angle"] - d.groupby("run")["slip_angle"].transform("mean")
    f = d["fy"] - d.groupby("run")["fy"].transform("mean")
    den = float((a * a).sum())
    return float((a * f).sum() / den) if den > 0 else None


# --------------------------------------------------------------------------- fit checks

FIT_KINDS = ("slip_angle", "slip_ratio", "static")


def _as_dataset(x, **kw) -> Dataset:
    return x if isinstance(x, Dataset) else read_data(x, **kw)


def require_patch(ds: Dataset, patch=None) -> Dataset | None:
    """Check that a static-rig test comes with usable contact-patch data.

    Komana et al. Eq. 1 turns lateral displacement into slip angle through the
    contact-patch length L(Fz, p), so a static test cannot be fitted without it.

    Parameters
    ----------
    ds : Dataset
    patch : Dataset or path, optional

    Returns
    -------
    Dataset or None
        the patch data set (read if a path was given), None for dynamic data.
    """
    if ds.kind != "static":
        return _as_dataset(patch, kind="patch") if patch is not None else None
    if patch is None:
        raise DataError(f"{ds.source}: a static-rig (lateral displacement) test needs contact-patch data to turn "
                        f"displacement into slip angle (Komana et al. Eq. 1); give {option('patch', 'PATCH.csv')} with "
                        "'length [mm]' and 'load [kg]' or 'fz [N]'")
    pds = _as_dataset(patch, kind="patch")
    if pds.kind != "patch":
        raise DataError(f"{pds.source}: is a {pds.kind} test, not contact-patch data; the patch file needs "
                        "'length [mm]' and 'load [kg]' or 'fz [N]'")
    if "length" not in pds.df:
        raise ColumnError(f"{pds.source}: contact-patch data without a 'length' column; Eq. 1 needs the patch "
                          "length L(Fz): add 'length [mm]'")
    lc = "fz" if "fz" in pds.df else "load"
    n_loads = pds.df[lc].round(-1).nunique()
    if n_loads < 2:
        raise DataError(f"{pds.source}: contact-patch length at {n_loads} load only; at least 2 loads are needed "
                        "to interpolate L(Fz)")
    return pds


def check_fittable(ds: Dataset, *, patch=None, min_points: int = 10, min_sweeps: int = 1) -> Dataset | None:
    """Raise a :class:`DataError` if ``ds`` cannot be fitted; return the patch data (or None).

    Checks, in order: the kind is fittable (slip-angle, slip-ratio or static
    tests); a static test has contact-patch data (:func:`require_patch`); at
    least ``min_points`` points and ``min_sweeps`` sweeps; every sweep varies
    its slip (slip angle by 0.5 deg, slip ratio by 0.01, lateral
    displacement by 2 mm).
    """
    src = ds.source
    if ds.kind not in FIT_KINDS:
        raise DataError(f"{src}: a {ds.kind} table cannot be fitted to a tyre model; fit needs slip-angle, "
                        "slip-ratio or static-rig lateral tests")
    pds = require_patch(ds, patch)
    n = len(ds.df)
    if n < min_points:
        raise DataError(f"{src}: too few points to fit: {n}; at least {min_points} are needed")
    if ds.n_runs < min_sweeps:
        raise DataError(f"{src}: too few sweeps to fit: {ds.n_runs}; at least {min_sweeps} are needed")
    var = SWEEP_VARIABLE[ds.kind]
    spans = ds.df.groupby("run")[var].agg(lambda s: float(np.ptp(s.to_numpy())))
    flat = spans[spans < MIN_SWEEP_SPAN[var]]
    if len(flat):
        r = int(flat.index[0])
        cond = ds.conditions().set_index("run").loc[r]
        unit = {"slip_angle": "deg", "slip_ratio": "-", "lateral_displacement": "mm"}[var]
        desc = f"fz {cond['fz']:.0f} N" if "fz" in cond else ""
        raise DataError(f"{src}: sweep {r} ({desc}, {int(cond['n'])} points) has no {var} variation "
                        f"(span {_fmt(flat.iloc[0], unit)}); each sweep needs at least "
                        f"{_fmt(MIN_SWEEP_SPAN[var], unit)} ({len(flat)} such sweep{'s' if len(flat) > 1 else ''})")
    return pds
