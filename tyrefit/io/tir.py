"""Tyre property files: read any Adams/MF ``.tir``, read and write PAC89.

:func:`read_property_file` reads the generic layout shared by PAC89,
PAC2002 / MF 5.x and MF 6.x files: ``[SECTION]`` headers, ``KEY = value``
lines, ``$`` and ``!`` comments, quoted strings, curve tables (a ``{a b}``
line followed by rows of numbers), LF or CRLF, any case.  Nothing is dropped:
vendor sections are kept as they are.

:func:`read_tir` turns a PAC89 file into a :class:`~tyrefit.tyres.pac89.Pac89Tyre`
(SI design data; coefficients as written) and :func:`write_tir` writes the
Adams-style PAC89 layout of ``shared/reference/adams_pac89_example.tir``.
Floats are written with ``repr`` so that write -> read is exact.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import FormatError
from ..models import pac89
from ..tyres.pac89 import Pac89Tyre
from .outputs import write_text

__all__ = ["PropertyFile", "read_property_file", "read_tir", "read_tyre", "write_tir", "format_tir"]

_SECTION = re.compile(r"^\[\s*([A-Za-z0-9_]+)\s*\]")
_KEYVAL = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)\s*=\s*(.*)$")
#: section rulers such as ``$-----------units`` or ``!=====``: layout, not comments
_SEPARATOR = re.compile(r"^[$!]\s*[-=_]{4,}\s*[A-Za-z_ ]*$")
#: characters str.splitlines() breaks lines at, and other control characters (NUL marks a binary file)
_LINE_BREAKS = re.compile("[\n\r\v\f\x1c\x1d\x1e\x85\u2028\u2029]+")
_CONTROL = re.compile("[\x00-\x08\x0e-\x1f\x7f]")

_LENGTH = {"meter": 1.0, "meters": 1.0, "m": 1.0, "metre": 1.0, "mm": 1e-3, "millimeter": 1e-3,
           "millimetre": 1e-3, "cm": 1e-2, "inch": 0.0254, "in": 0.0254, "ft": 0.3048, "foot": 0.3048}
_FORCE = {"newton": 1.0, "n": 1.0, "kn": 1e3, "kilonewton": 1e3, "lbf": 4.4482216152605,
          "pound_force": 4.4482216152605, "kgf": 9.80665}
_ANGLE = {"radian": 1.0, "radians": 1.0, "rad": 1.0, "degree": math.pi / 180, "degrees": math.pi / 180,
          "deg": math.pi / 180}


@dataclass
class PropertyFile:
    """A parsed property file: ordered sections of key -> value, tables, comments."""

    path: str
    sections: dict[str, dict[str, object]] = field(default_factory=dict)
    tables: dict[str, dict[str, object]] = field(default_factory=dict)
    comments: list[str] = field(default_factory=list)

    @property
    def format(self) -> str:
        """``PROPERTY_FILE_FORMAT`` as the file declares it (upper case), or ''."""
        v = self.get("PROPERTY_FILE_FORMAT", section="MODEL")
        if v is None:
            v = self.get("FITTYP", section="MODEL")
            if v is not None:  # MF 6.x files often give only FITTYP (61, 62)
                return {"61": "MF61", "62": "MF62", "6": "MF6"}.get(str(v).split(".")[0], f"FITTYP {v}")
        return str(v).upper() if v is not None else ""

    def get(self, key: str, section: str | None = None, default=None):
        key = key.upper()
        if section is not None:
            return self.sections.get(section.upper(), {}).get(key, default)
        for sec in self.sections.values():
            if key in sec:
                return sec[key]
        return default

    def unit_factor(self, kind: str) -> float:
        table = {"LENGTH": _LENGTH, "FORCE": _FORCE, "ANGLE": _ANGLE}[kind]
        name = str(self.get(kind, section="UNITS", default="")).strip().lower()
        if not name:
            return 1.0
        if name not in table:
            raise FormatError(f"{self.path}: [UNITS] {kind} = {name!r} is not understood; accepted: "
                              + ", ".join(sorted(table)))
        return table[name]

    @property
    def n_parameters(self) -> int:
        return sum(1 for sec in self.sections.values() for v in sec.values() if isinstance(v, (int, float)))


def _strip_comment(line: str) -> str:
    """Drop ``$`` / ``!`` comments outside quotes."""
    out, quote = [], None
    for ch in line:
        if quote:
            out.append(ch)
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
            out.append(ch)
        elif ch in "$!":
            break
        else:
            out.append(ch)
    return "".join(out).strip()


def _value(text: str):
    text = text.strip()
    if len(text) >= 2 and text[0] == text[-1] and text[0] in "'\"":
        return text[1:-1]
    try:
        if re.fullmatch(r"[+-]?\d+", text):
            v = int(text)
            float(v)  # an integer beyond float range is not a usable number: keep the text
            return v
        return float(text.replace("D", "E").replace("d", "e"))
    except (ValueError, OverflowError):
        return text


def read_property_file(path: str | os.PathLike) -> PropertyFile:
    """Read a ``.tir`` property file of any MF / PAC flavour.

    Raises
    ------
    FormatError
        empty, binary, or with no ``[SECTION]`` at all.
    """
    p = Path(path)
    try:
        raw = p.read_bytes()
    except OSError as exc:
        raise FormatError(f"{p}: cannot read ({exc.strerror})") from None
    if not raw.strip():
        raise FormatError(f"{p}: file is empty; expected a tyre property file with [SECTION] blocks")
    if b"\x00" in raw[:4096]:
        raise FormatError(f"{p}: binary content; expected a text tyre property file (.tir)")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    pf = PropertyFile(path=str(p))
    section = None
    table_cols: list[str] | None = None
    for lineno, line in enumerate(text.splitlines(), 1):
        s = line.strip()
        if not s:
            continue
        if s[0] in "$!":
            if not _SEPARATOR.match(s):
                pf.comments.append(s[1:].strip())
            continue
        m = _SECTION.match(s)
        if m:
            section = m.group(1).upper()
            pf.sections.setdefault(section, {})
            table_cols = None
            continue
        s = _strip_comment(s)
        if not s:
            continue
        if section is None:
            raise FormatError(f"{p}:{lineno}: '{s[:40]}' before any [SECTION]; not a tyre property file")
        if s.startswith("{"):
            table_cols = s.strip("{} ").split()
            pf.tables[section] = {"columns": table_cols, "rows": []}
            continue
        kv = _KEYVAL.match(s)
        if kv:
            pf.sections[section][kv.group(1).upper()] = _value(kv.group(2))
            continue
        if table_cols is not None:
            try:
                pf.tables[section]["rows"].append([float(x) for x in s.split()])
                continue
            except ValueError:
                pass
        raise FormatError(f"{p}:{lineno}: cannot read '{s[:40]}' in [{section}]; expected KEY = value")
    if not pf.sections:
        raise FormatError(f"{p}: no [SECTION] found; not a tyre property file")
    return pf


def read_tir(path: str | os.PathLike) -> Pac89Tyre:
    """Read a PAC89 ``.tir`` into a :class:`Pac89Tyre` (design data in SI)."""
    pf = read_property_file(path)
    fmt = pf.format
    if fmt != "PAC89":
        raise FormatError(f"{path}: PROPERTY_FILE_FORMAT is {fmt or 'missing'!s}; a PAC89 file is needed here "
                          "(other formats can be inspected with 'tyrefit inspect')")
    L, F, A = pf.unit_factor("LENGTH"), pf.unit_factor("FORCE"), pf.unit_factor("ANGLE")
    coeffs = {}
    for name in pac89.ALL:
        v = pf.get(name)
        if v is None:
            continue
        if not isinstance(v, (int, float)) or not math.isfinite(v):
            raise FormatError(f"{path}: coefficient {name} = {str(v)[:40]!r} is not a finite number")
        coeffs[name] = float(v)
    if not any(k in coeffs for k in pac89.LATERAL):
        raise FormatError(f"{path}: no lateral coefficients a0..a13 found")

    def num(key, factor=1.0, section=None):
        v = pf.get(key, section=section)
        return float(v) * factor if isinstance(v, (int, float)) else None

    ranges = {}
    for key, lo, hi, fac in (("fz", "FZMIN", "FZMAX", F), ("slip_angle", "ALPMIN", "ALPMAX", A),
                             ("camber", "CAMMIN", "CAMMAX", A), ("slip_ratio", "KPUMIN", "KPUMAX", 1.0)):
        a, b = num(lo, fac), num(hi, fac)
        if a is not None and b is not None:
            ranges[key] = (a, b)
    header = [c for c in pf.comments]
    return Pac89Tyre(
        coefficients=coeffs,
        unloaded_radius=num("UNLOADED_RADIUS", L),
        width=num("WIDTH", L, section="DIMENSION"),
        fnomin=num("FNOMIN", F),
        lateral_stiffness=num("LATERAL_STIFFNESS", F / L),
        vertical_stiffness=num("VERTICAL_STIFFNESS", F / L),
        rolling_resistance=num("ROLLING_RESISTANCE") or 0.0,
        ranges=ranges,
        header=header,
        name=str(pf.get("NAME", section="MODEL") or Path(path).stem),
        tyreside=str(pf.get("TYRESIDE", default="LEFT")).upper(),
    )


def read_tyre(path: str | os.PathLike) -> Pac89Tyre:
    """Read a PAC89 tyre from ``.tir`` or Chrono ``.json``."""
    if str(path).lower().endswith(".json"):
        from .chrono_json import read_chrono_json

        return read_chrono_json(path)
    return read_tir(path)


def _f(v: float) -> str:
    return repr(float(v))


def _fc(v: float) -> str:
    """A value converted from SI to file units (mm, deg, N/mm), to 15 significant digits.

    The conversion back on reading (x 1e-3, x pi/180) is within a few ulp of the
    inverse, so 15 digits make write -> read -> write give the same text and
    read -> write -> read the same floats.
    """
    return repr(float(f"{float(v):.15g}"))


def _line(key: str, value: str, comment: str = "") -> str:
    s = f"{key:<21}= {value}"
    return f"{s:<40}$ {comment}" if comment else s


def _quoted(text: str) -> str:
    """Quote a string value so the reader gets it back (no '$'/'!' comment cut inside quotes)."""
    if "'" not in text:
        return f"'{text}'"
    if '"' not in text:
        return f'"{text}"'
    return "'" + text.replace("'", "\u2019") + "'"


def format_tir(tyre: Pac89Tyre) -> str:
    """The PAC89 ``.tir`` text of ``tyre`` (dimensions in mm, stiffness in N/mm)."""
    bar = "$" + "-" * 70
    out = [bar + "info"]
    for h in tyre.header or ["PAC89 tyre written by tyrefit"]:
        for part in str(h).splitlines() or [""]:
            out.append(f"! {_CONTROL.sub('?', part)}")
    name = _CONTROL.sub("?", _LINE_BREAKS.sub(" ", str(tyre.name)))  # a line break would end the quoted value
    out += [bar + "units", "[MDI_HEADER]", "FILE_TYPE     = 'tir'", "FILE_VERSION  = 2.0",
            "FILE_FORMAT   = 'ASCII'", "[UNITS]", "LENGTH        = 'mm'", "FORCE         = 'newton'",
            "ANGLE         = 'degrees'", "MASS          = 'kg'", "TIME          = 'sec'",
            bar + "model", "[MODEL]", _line("PROPERTY_FILE_FORMAT", "'PAC89'"),
            _line("TYRESIDE", f"'{tyre.tyreside}'"), _line("NAME", _quoted(name))]
    dims = []
    if tyre.unloaded_radius is not None:
        dims.append(_line("UNLOADED_RADIUS", _fc(tyre.unloaded_radius * 1e3), "mm"))
    if tyre.width is not None:
        dims.append(_line("WIDTH", _fc(tyre.width * 1e3), "mm"))
    if dims:
        out += [bar + "dimension", "[DIMENSION]"] + dims
    vert = []
    if tyre.fnomin is not None:
        vert.append(_line("FNOMIN", _f(tyre.fnomin), "N, nominal (rated) load"))
    if tyre.vertical_stiffness is not None:
        vert.append(_line("VERTICAL_STIFFNESS", _fc(tyre.vertical_stiffness * 1e-3), "N/mm"))
    if vert:
        out += [bar + "vertical", "[VERTICAL]"] + vert
    out += [bar + "parameter", "[PARAMETER]"]
    if tyre.lateral_stiffness is not None:
        out.append(_line("LATERAL_STIFFNESS", _fc(tyre.lateral_stiffness * 1e-3), "N/mm"))
    out.append(_line("ROLLING_RESISTANCE", _f(tyre.rolling_resistance)))
    rng = tyre.ranges
    deg = 180.0 / math.pi
    for key, sec, lo, hi, fac, unit in (("fz", "VERTICAL_FORCE_RANGE", "FZMIN", "FZMAX", 1.0, "N"),
                                        ("slip_angle", "SLIP_ANGLE_RANGE", "ALPMIN", "ALPMAX", deg, "deg"),
                                        ("camber", "INCLINATION_ANGLE_RANGE", "CAMMIN", "CAMMAX", deg, "deg"),
                                        ("slip_ratio", "LONG_SLIP_RANGE", "KPUMIN", "KPUMAX", 1.0, "-")):
        if key in rng:
            a, b = rng[key]
            out += [bar + sec.lower(), f"[{sec}]", _line(lo, _fc(a * fac), f"{unit}, fitted range"),
                    _line(hi, _fc(b * fac), f"{unit}, fitted range")]
    for sec, names in (("LATERAL_COEFFICIENTS", pac89.LATERAL), ("LONGITUDINAL_COEFFICIENTS", pac89.LONGITUDINAL),
                       ("ALIGNING_COEFFICIENTS", pac89.ALIGNING)):
        out += [bar + sec.split("_")[0].lower(), f"[{sec}]"]
        out += [f"{n:<4}= {_f(tyre.coefficients[n])}" for n in names]
    return "\n".join(out) + "\n"


def write_tir(tyre: Pac89Tyre, path: str | os.PathLike, force: bool = False, check: bool = True) -> Path:
    """Write ``tyre`` as an Adams-style PAC89 ``.tir`` (atomically).

    With ``check`` (default) the model must be physical over its load range
    (C > 0, D > 0, E <= 1), else :class:`~tyrefit.errors.ModelError`.
    """
    if check:
        tyre.check_physical()
    return write_text(path, format_tir(tyre), force=force)
