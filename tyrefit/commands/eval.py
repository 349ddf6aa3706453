"""``tyrefit eval TYRE --points POINTS.csv --out FORCES.csv``: a tyre's forces at given points.

Any tyre file the tool reads (PAC89 ``.tir``, MF 5.x / PAC2002, MF 6.1 / 6.2,
Chrono PAC89 JSON; :func:`tyrefit.io.tir.read_tyre`) is evaluated at the rows
of a CSV with unit headers through the :class:`~tyrefit.tyres.base.Tyre`
interface, in one vectorised call.

Points: ``fz`` (required), ``slip_angle``, ``slip_ratio``, ``camber``,
``pressure``, ``speed``, any units the glossary accepts (``fz [kN]``,
``slip_angle [deg]``, ``pressure [bar]``, ``speed [km/h]``), ISO-W signs.
Every value must be finite and in its domain (slip angle and camber within
+/-90 deg, slip ratio >= -1, pressure > 0, speed >= 0); a load <= 0 is a wheel
off the ground and gives zero forces.  A
missing slip or camber column is 0; a missing pressure or speed is the tyre's
nominal value (INFLPRES / NOMPRES, LONGVL).  The output repeats every input
column as read and adds ``fx [N]``, ``fy [N]``, ``mz [N*m]`` and, where the
model has them, ``mx [N*m]`` and ``my [N*m]`` (ISO-W, combined slip where the
model has it).  A part the tyre does not model (a PAC89 tyre without b0..b10,
say) is left empty, with a note.

A tyre that :meth:`~tyrefit.tyres.base.Tyre.check` finds unphysical over its
declared range is refused unless ``--allow-unphysical``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from .. import nomenclature as nm
from ..errors import ColumnError, DataError
from ..io.inputs import check_input
from ..io.outputs import atomic_write, check_output
from ..io.readers import _decode, _read_bytes, parse_csv
from ..io.table import map_headers
from ..io.tir import read_tyre
from ..tyres.base import require_physical

import orjson as _orjson  # fast shortest round-trip float text for the output CSV (Ryu, as repr)

__all__ = ["run", "read_points", "evaluate_points", "point_notes", "write_forces", "csv_text", "CHUNK"]

#: point columns and their defaults ('nominal': the tyre's nominal value)
POINT_COLUMNS = {"fz": None, "slip_angle": 0.0, "slip_ratio": 0.0, "camber": 0.0, "pressure": "nominal",
                 "speed": "nominal"}
#: output column -> header
OUTPUT_HEADERS = {"fx": "fx [N]", "fy": "fy [N]", "mz": "mz [N*m]", "mx": "mx [N*m]", "my": "my [N*m]"}


def read_points(path: str | Path):
    """The points CSV: (SI arrays of the point columns, the table as read, headers as written).

    Raises
    ------
    DataError
        no ``fz`` column, no slip column, a value that is not a number, an
        unknown unit (named by the readers).
    """
    p = Path(path)
    t = parse_csv(p, _decode(p, _read_bytes(p)))
    return _points_si(p, t.values, t.units, t.headers, t.lines), t


def _points_si(p: Path, values: dict, units: dict, headers: dict, lines) -> dict[str, np.ndarray]:
    """SI arrays of the point columns from the columns as read; DataError naming the line of a bad value."""
    si: dict[str, np.ndarray] = {}
    for name in POINT_COLUMNS:
        col = name
        if name == "fz" and "fz" not in values and "load" in values:
            col = "load"  # a load set point [kg] or [N]
        if col not in values:
            continue
        v = values[col]
        if v.dtype == object:
            raise DataError(f"{p}: column '{headers[col]}' holds text; numbers are needed")
        unit = units.get(col)
        si[name] = np.asarray(nm.to_si(v, unit) if unit else v, dtype=float)
    if "fz" not in si:
        raise ColumnError(f"{p}: no 'fz [N]' column; the points need the normal load (accepted: fz, load with a "
                          "force or mass unit)")
    if "slip_angle" not in si and "slip_ratio" not in si:
        raise ColumnError(f"{p}: no 'slip_angle [deg]' or 'slip_ratio [-]' column; give the slip of each point")
    for name, x in si.items():
        col = "load" if name == "fz" and "fz" not in headers else name
        lo, hi, what = _DOMAIN[name]
        bad = ~(np.isfinite(x) & (x >= lo) & (x <= hi))
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raw = values[col][i]
            raise DataError(f"{p}: line {lines[i]}, column '{headers.get(col, col)}': {float(raw):g} is "
                            f"{'not finite' if not np.isfinite(x[i]) else 'outside ' + what}"
                            + (f" ({int(bad.sum())} such rows)" if bad.sum() > 1 else ""))
    return si


#: the domain of each point column (SI): what a rolling tyre can be asked
_DOMAIN = {"fz": (-np.inf, np.inf, "any load"),
           "slip_angle": (-np.pi / 2, np.pi / 2, "-90..90 deg (a slip angle beyond 90 deg rolls backwards)"),
           "slip_ratio": (-1.0, np.inf, "-1 (locked wheel) and above"),
           "camber": (-np.pi / 2, np.pi / 2, "-90..90 deg"),
           "pressure": (np.finfo(float).tiny, np.inf, "positive pressures"),
           "speed": (0.0, np.inf, "forward speeds >= 0")}


def _forces(tyre, si: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    kw = {k: si.get(k, d if d != "nominal" else None) for k, d in POINT_COLUMNS.items()}
    return tyre.forces(kw["fz"], slip_angle=kw["slip_angle"], slip_ratio=kw["slip_ratio"], camber=kw["camber"],
                       pressure=kw["pressure"], speed=kw["speed"])


def evaluate_points(tyre, si: dict[str, np.ndarray]) -> tuple[dict[str, np.ndarray], list[str]]:
    """Forces at the points (one vectorised call) and notes for the user."""
    return _forces(tyre, si), point_notes(tyre, si)


def point_notes(tyre, si: dict[str, np.ndarray]) -> list[str]:
    """What the user should know about evaluating ``tyre`` at the points ``si`` (no forces computed)."""
    return _notes(tyre, _note_stats(tyre, si))


def _note_stats(tyre, si: dict[str, np.ndarray], stats: dict | None = None) -> dict:
    """Add the counts :func:`_notes` needs for the points ``si`` to ``stats`` (chunk by chunk)."""
    st = stats if stats is not None else {"columns": set(), "n": 0, "combined": False, "outside": {}}
    st["columns"] |= set(si)
    st["n"] += len(si["fz"]) if "fz" in si else 0
    if "slip_angle" in si and "slip_ratio" in si:
        st["combined"] = st["combined"] or bool(np.any((si["slip_angle"] != 0) & (si["slip_ratio"] != 0)))
    v = tyre.validity()
    for k in ("fz", "slip_angle", "slip_ratio", "camber"):
        if k in si and k in v:
            lo, hi = v[k]
            x = si[k]
            tol = 1e-9 * max(abs(lo), abs(hi), 1.0)
            st["outside"][k] = st["outside"].get(k, 0) + int(np.sum((x < lo - tol) | (x > hi + tol)))
    return st


def _notes(tyre, st: dict) -> list[str]:
    notes: list[str] = []
    if tyre.family == "PAC89":
        for k in ("pressure", "speed"):
            if k in st["columns"]:
                notes.append(f"PAC89 has no {k} dependence: the {k} column does not change the forces")
    for part, key in (("longitudinal", "fx"), ("lateral", "fy"), ("aligning", "mz")):
        if not getattr(tyre, f"has_{part}"):
            notes.append(f"the tyre has no {part} model: '{OUTPUT_HEADERS[key]}' is left empty")
    if not tyre.combined and st["combined"]:
        notes.append(f"{tyre.family} has no combined slip: Fx depends on the slip ratio only, Fy and Mz on the slip "
                     "angle only")
    v = tyre.validity()
    for k in ("fz", "slip_angle", "slip_ratio", "camber"):
        out = st["outside"].get(k, 0)
        if out and k in v and (k in getattr(tyre, "ranges", {}) or k == "fz"):
            lo, hi = v[k]
            notes.append(f"{out} of {st['n']} points have {k} outside the tyre's range "
                         f"{_display(k, lo)}..{_display(k, hi)} (extrapolated)")
    return notes


#: points evaluated and written per chunk: the output text of one chunk (a Python string per cell) is
#: what eval holds at once, about 0.15 GB at 5 columns; the forces are elementwise, so the file is the
#: same byte for byte at any chunk size
CHUNK = 100_000


def write_forces(out, tyre, si: dict[str, np.ndarray], table, force: bool = False,
                 chunk: int | None = None) -> list[str]:
    """Evaluate ``tyre`` at the points ``si`` chunk by chunk and write the input columns and the forces to
    ``out`` (atomically); return the output headers written."""
    n = len(next(iter(si.values()))) if si else 0
    chunk = max(int(CHUNK if chunk is None else chunk), 1)
    written: list[str] = []
    with atomic_write(out, "w", force=force, encoding="utf-8", newline="\n") as fh:
        for start in range(0, max(n, 1), chunk):
            sl = slice(start, min(start + chunk, n))
            res = _forces(tyre, {k: v[sl] for k, v in si.items()})
            cols: dict[str, object] = {}
            for name, values in table.values.items():
                cols[table.headers[name]] = values[sl]
            for k in tyre.outputs:
                if k in res:
                    cols[OUTPUT_HEADERS[k]] = np.asarray(res[k], dtype=float)
            if not start:
                written = [OUTPUT_HEADERS[k] for k in tyre.outputs if k in res]
            fh.write(_chunk_text(pd.DataFrame(cols), not start))
            del cols, res
    return written


def csv_text(df: pd.DataFrame) -> str:
    """``df`` as CSV text, every float written as a shortest round-trip decimal.

    ``DataFrame.to_csv`` formats each value in Python (``float_format='%.10g'``
    spent ~90 % of ``eval``'s time at 200k points, and lost digits).  Here a
    float column is turned to text in one C call - ``orjson`` (Ryu: the
    shortest text that reads back to the same double) when installed, else
    ``repr`` of the column's list (``float.__repr__``, same guarantee, about 6x
    slower) - and split; the rows are joined once.  NaN is written empty, as
    pandas does; integer and boolean columns as pandas writes them.  A text
    column or a single column falls back to ``to_csv`` (default float format,
    also round-trip).
    """
    columns = []
    for name in df.columns:
        v = df[name].to_numpy()
        if v.dtype.kind not in "fiub" or df.shape[1] == 1:  # one column: pandas writes NaN as "" (no blank line)
            return df.to_csv(index=False, lineterminator="\n")
        if v.dtype.kind == "f":
            v = v.astype(np.float64, copy=False)
            if not np.isinf(v).any():  # orjson writes inf and NaN both as null
                items = _orjson.dumps(v, option=_orjson.OPT_SERIALIZE_NUMPY).decode()[1:-1].split(",")
                items = ["" if x == "null" else x for x in items]
            else:
                body = repr(v.tolist())[1:-1]
                items = ["" if x == "nan" else x for x in body.split(", ")] if body else []
        else:
            body = repr(v.tolist())[1:-1]
            items = body.split(", ") if body else []
        columns.append(items)
    header = df.head(0).to_csv(index=False, lineterminator="\n")  # pandas' quoting of odd names
    if not columns or len(df) == 0:
        return header
    return header + "\n".join(map(",".join, zip(*columns))) + "\n"


class _NotPlain(Exception):
    """The points file is not a plain numeric CSV: read it whole (its messages name lines and columns)."""


def _chunk_text(df: pd.DataFrame, first: bool) -> str:
    text = csv_text(df)
    if not first:
        header = df.head(0).to_csv(index=False, lineterminator="\n")
        text = text[len(header):] if text.startswith(header) else text
    return text


def stream_forces(out, tyre, points, force: bool = False, chunk: int | None = None) -> tuple[int, list[str], list[str]]:
    """Read a plain numeric points CSV chunk by chunk, evaluate and write each chunk (bounded memory: the
    points file is never held whole).  Returns (points, output headers, notes).  Raises :class:`_NotPlain`
    (nothing written) for anything else - comments or blank lines after the header, quoted or text cells,
    a value outside its domain - which :func:`read_points` then reads whole and names precisely."""
    import csv as _csv
    import io as _io

    p = check_input(points, "a data file (CSV, TYDEX .tdx or FSAE TTC .dat)")
    chunk = max(int(CHUNK if chunk is None else chunk), 1)
    try:
        with open(p, encoding="utf-8-sig", newline="") as fh:
            skip = 0
            header_line = None
            for line in fh:
                skip += 1
                st = line.strip()
                if st and not st.startswith("#"):
                    header_line = line.rstrip("\r\n")
                    break
                if skip > 1000:
                    break
    except (OSError, UnicodeDecodeError, ValueError):
        raise _NotPlain from None
    if header_line is None or '"' in header_line or "'" in header_line or "\x00" in header_line:
        raise _NotPlain
    delim = "\t" if "\t" in header_line else (";" if header_line.count(";") > header_line.count(",") else ",")
    header = [h.strip() for h in header_line.split(delim)]
    try:
        names, units_l, _ = map_headers(p, header)
    except DataError:
        raise _NotPlain from None
    units, headers = dict(zip(names, units_l)), dict(zip(names, header))
    stats = None
    n = 0
    written: list[str] = []
    try:
        with atomic_write(out, "w", force=force, encoding="utf-8", newline="\n") as fh:
            reader = pd.read_csv(p, sep=delim, header=None, skiprows=skip, dtype=float, engine="c",
                                 skip_blank_lines=False, chunksize=chunk, encoding="utf-8-sig")
            for part in reader:
                arr = part.to_numpy()
                if arr.shape[1] != len(names) or np.isnan(arr).any():
                    raise _NotPlain
                values = {name: np.ascontiguousarray(arr[:, j]) for j, name in enumerate(names)}
                try:
                    si = _points_si(p, values, units, headers, np.arange(arr.shape[0]))
                except DataError:
                    raise _NotPlain from None
                stats = _note_stats(tyre, si, stats)
                res = _forces(tyre, si)
                cols: dict[str, object] = {headers[name]: values[name] for name in names}
                for k in tyre.outputs:
                    if k in res:
                        cols[OUTPUT_HEADERS[k]] = np.asarray(res[k], dtype=float)
                if n == 0:
                    written = [OUTPUT_HEADERS[k] for k in tyre.outputs if k in res]
                fh.write(_chunk_text(pd.DataFrame(cols), n == 0))
                n += arr.shape[0]
            if n == 0:
                raise _NotPlain
    except (ValueError, TypeError, UnicodeDecodeError, pd.errors.ParserError, _csv.Error, OverflowError,
            pd.errors.EmptyDataError, _io.UnsupportedOperation):
        raise _NotPlain from None
    return n, written, _notes(tyre, stats)


def _display(k: str, x: float) -> str:
    if k in ("slip_angle", "camber"):
        return f"{np.degrees(x):.3g} deg"
    if k == "fz":
        return f"{x:.0f} N"
    return f"{x:.3g}"


def run(args) -> int:
    """Entry point of ``tyrefit eval``."""
    out = Path(args.out)
    check_output(out, args.force)
    for src in (args.tyre, args.points):
        if out.resolve() == Path(src).resolve():
            raise DataError(f"--out {out}: the output is an input file; choose another name")
    tyre = read_tyre(args.tyre)
    problems = require_physical(tyre, str(args.tyre), allow_unphysical=getattr(args, "allow_unphysical", False))
    try:  # a plain numeric CSV streams through in chunks; anything else is read whole
        n, headers, notes = stream_forces(out, tyre, args.points, force=args.force)
    except _NotPlain:
        si, table = read_points(args.points)
        notes = point_notes(tyre, si)
        headers = write_forces(out, tyre, si, table, force=args.force)
        n = len(si["fz"])
    print(f"wrote {out}: {n} points, {tyre.family} tyre {tyre.name!r} ({', '.join(headers)})")
    for prob in problems:
        print(f"  warning (--allow-unphysical): {prob}")
    for w in [*tyre.file_notes, *tyre.warnings()]:
        print(f"  warning: {w}")
    for n in notes:
        print(f"  note: {n}")
    return 0
