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
from ..io.outputs import check_output

try:  # fast shortest round-trip float text for the output CSV (optional: repr does the same, slower)
    import orjson as _orjson
except ImportError:  # pragma: no cover - depends on the environment
    _orjson = None

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
    from ..io.readers import _decode, _read_bytes, parse_csv

    p = Path(path)
    t = parse_csv(p, _decode(p, _read_bytes(p)))
    si: dict[str, np.ndarray] = {}
    for name in POINT_COLUMNS:
        col = name
        if name == "fz" and "fz" not in t.values and "load" in t.values:
            col = "load"  # a load set point [kg] or [N]
        if col not in t.values:
            continue
        v = t.values[col]
        if v.dtype == object:
            raise DataError(f"{p}: column '{t.headers[col]}' holds text; numbers are needed")
        unit = t.units.get(col)
        si[name] = np.asarray(nm.to_si(v, unit) if unit else v, dtype=float)
    if "fz" not in si:
        raise ColumnError(f"{p}: no 'fz [N]' column; the points need the normal load (accepted: fz, load with a "
                          "force or mass unit)")
    if "slip_angle" not in si and "slip_ratio" not in si:
        raise ColumnError(f"{p}: no 'slip_angle [deg]' or 'slip_ratio [-]' column; give the slip of each point")
    for name, values in si.items():
        col = "load" if name == "fz" and "fz" not in t.headers else name
        lo, hi, what = _DOMAIN[name]
        bad = ~(np.isfinite(values) & (values >= lo) & (values <= hi))
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raw = t.values[col][i]
            raise DataError(f"{p}: line {t.lines[i]}, column '{t.headers.get(col, col)}': {float(raw):g} is "
                            f"{'not finite' if not np.isfinite(values[i]) else 'outside ' + what}"
                            + (f" ({int(bad.sum())} such rows)" if bad.sum() > 1 else ""))
    return si, t


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
    notes: list[str] = []
    if tyre.family == "PAC89":
        for k in ("pressure", "speed"):
            if k in si:
                notes.append(f"PAC89 has no {k} dependence: the {k} column does not change the forces")
    for part, key in (("longitudinal", "fx"), ("lateral", "fy"), ("aligning", "mz")):
        if not getattr(tyre, f"has_{part}"):
            notes.append(f"the tyre has no {part} model: '{OUTPUT_HEADERS[key]}' is left empty")
    if not tyre.combined and "slip_angle" in si and "slip_ratio" in si and \
            np.any((si["slip_angle"] != 0) & (si["slip_ratio"] != 0)):
        notes.append(f"{tyre.family} has no combined slip: Fx depends on the slip ratio only, Fy and Mz on the slip "
                     "angle only")
    v = tyre.validity()
    for k in ("fz", "slip_angle", "slip_ratio", "camber"):
        if k in si and k in v:
            lo, hi = v[k]
            x = si[k]
            tol = 1e-9 * max(abs(lo), abs(hi), 1.0)
            out = int(np.sum((x < lo - tol) | (x > hi + tol)))
            if out and (k in getattr(tyre, "ranges", {}) or k == "fz"):
                notes.append(f"{out} of {x.size} points have {k} outside the tyre's range "
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
    from ..io.outputs import atomic_write

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
            df = pd.DataFrame(cols)
            text = csv_text(df)
            if start:
                header = df.head(0).to_csv(index=False, lineterminator="\n")
                text = text[len(header):] if text.startswith(header) else text
            else:
                written = [OUTPUT_HEADERS[k] for k in tyre.outputs if k in res]
            fh.write(text)
            del text, df, cols, res
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
            if _orjson is not None and not np.isinf(v).any():  # orjson writes inf and NaN both as null
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


def _display(k: str, x: float) -> str:
    if k in ("slip_angle", "camber"):
        return f"{np.degrees(x):.3g} deg"
    if k == "fz":
        return f"{x:.0f} N"
    return f"{x:.3g}"


def run(args) -> int:
    """Entry point of ``tyrefit eval``."""
    from ..io.tir import read_tyre
    from ..tyres.base import require_physical

    out = Path(args.out)
    check_output(out, args.force)
    for src in (args.tyre, args.points):
        if out.resolve() == Path(src).resolve():
            raise DataError(f"--out {out}: the output is an input file; choose another name")
    tyre = read_tyre(args.tyre)
    problems = require_physical(tyre, str(args.tyre), allow_unphysical=getattr(args, "allow_unphysical", False))
    si, table = read_points(args.points)
    notes = point_notes(tyre, si)
    headers = write_forces(out, tyre, si, table, force=args.force)
    print(f"wrote {out}: {len(si['fz'])} points, {tyre.family} tyre {tyre.name!r} ({', '.join(headers)})")
    for prob in problems:
        print(f"  warning (--allow-unphysical): {prob}")
    for w in getattr(tyre, "file_notes", []) + tyre.warnings():
        print(f"  warning: {w}")
    for n in notes:
        print(f"  note: {n}")
    return 0
