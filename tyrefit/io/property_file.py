"""The generic layout of tyre property files (``.tir``): sections, ``KEY = value`` lines, tables, units.

:func:`read_property_file` reads the layout shared by PAC89, PAC2002 / MF 5.x
and MF 6.x files: ``[SECTION]`` headers, ``KEY = value`` lines, ``$`` and ``!``
comments, quoted strings, curve tables (a ``{a b}`` line followed by rows of
numbers), LF or CRLF, any case.  Nothing is dropped: vendor sections are kept
as they are.  It knows no tyre class: the tyre families are built from a
:class:`PropertyFile` by :mod:`tyrefit.io.tir` (and by
:meth:`tyrefit.tyres.pac89.Pac89Tyre.from_file`).
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import FormatError
from .inputs import read_input_bytes

__all__ = ["PropertyFile", "read_property_file", "declared_ranges"]

_INT = re.compile(r"[+-]?[0-9]+")

_LENGTH = {"meter": 1.0, "meters": 1.0, "m": 1.0, "metre": 1.0, "mm": 1e-3, "millimeter": 1e-3,
           "millimetre": 1e-3, "cm": 1e-2, "inch": 0.0254, "in": 0.0254, "ft": 0.3048, "foot": 0.3048}
_FORCE = {"newton": 1.0, "n": 1.0, "kn": 1e3, "kilonewton": 1e3, "lbf": 4.4482216152605,
          "pound_force": 4.4482216152605, "kgf": 9.80665}
_ANGLE = {"radian": 1.0, "radians": 1.0, "rad": 1.0, "degree": math.pi / 180, "degrees": math.pi / 180,
          "deg": math.pi / 180}
_PRESSURE = {"pascal": 1.0, "pa": 1.0, "kpa": 1e3, "kilopascal": 1e3, "mpa": 1e6, "bar": 1e5, "psi": 6894.757293168,
             "n/m2": 1.0, "n/mm2": 1e6}
_TIME = {"second": 1.0, "seconds": 1.0, "sec": 1.0, "s": 1.0, "millisecond": 1e-3, "ms": 1e-3}
_MASS = {"kg": 1.0, "kilogram": 1.0, "gram": 1e-3, "g": 1e-3, "tonne": 1e3, "lbm": 0.45359237, "pound_mass": 0.45359237}
_UNIT_TABLES = {"LENGTH": _LENGTH, "FORCE": _FORCE, "ANGLE": _ANGLE, "PRESSURE": _PRESSURE, "TIME": _TIME,
                "MASS": _MASS}

#: PROPERTY_FILE_FORMAT / FITTYP -> model family (Adams/MF-Tyre conventions: FITTYP 5, 6 and 21 are MF 5.x,
#: 61 and 62 are MF 6.1 and 6.2; MF 6.2 is evaluated as 6.1, turn slip being out of scope)
_FORMAT_FAMILY = {"PAC89": "PAC89", "MF_05": "MF52", "MF05": "MF52", "PAC2002": "MF52", "PAC_2002": "MF52",
                  "MF5.2": "MF52", "MF52": "MF52", "MF_52": "MF52", "MF_5.2": "MF52", "PAC_MF52": "MF52",
                  "MF61": "MF61", "MF_61": "MF61", "MF6.1": "MF61", "MF_6.1": "MF61", "MF62": "MF61",
                  "MF_62": "MF61", "MF6.2": "MF61", "MF_6.2": "MF61", "PAC_MF61": "MF61", "MF_06": "MF61"}
#: 52 is not an MF-Tyre code, but FSAE TTC fits circulate with 'FITTYP = 52' for MF 5.2
_FITTYP_FAMILY = {5: "MF52", 6: "MF52", 21: "MF52", 52: "MF52", 61: "MF61", 62: "MF61"}
#: sections whose entries must all be numbers (an empty or text value there is an error naming the line)
_NUMERIC_SECTION_SUFFIXES = ("_COEFFICIENTS", "_RANGE")
_NUMERIC_SECTIONS = {"DIMENSION", "VERTICAL", "OPERATING_CONDITIONS", "TIRE_CONDITIONS", "STRUCTURAL",
                     "CONTACT_PATCH", "PARAMETER", "INERTIA"}


@dataclass
class PropertyFile:
    """A parsed property file: ordered sections of key -> value, tables, comments.

    ``lines`` gives the file line of each ``(SECTION, KEY)``; a key written
    with no value (``a1 =``) is kept as ``None`` so that the model reader can
    name its line when a number is required.
    """

    path: str
    sections: dict[str, dict[str, object]] = field(default_factory=dict)
    tables: dict[str, dict[str, object]] = field(default_factory=dict)
    comments: list[str] = field(default_factory=list)
    lines: dict[tuple[str, str], int] = field(default_factory=dict)

    @property
    def format(self) -> str:
        """``PROPERTY_FILE_FORMAT`` as the file declares it (upper case), or ''.

        Without one, ``FITTYP`` 61 / 62 read as 'MF61' / 'MF62' and other values
        as 'FITTYP n'; :attr:`family` says what the model is.
        """
        v = self.get("PROPERTY_FILE_FORMAT", section="MODEL")
        if v is None or str(v).strip() == "" or str(v).strip().upper() == "USER":
            f = self.fittyp
            if f is not None:
                return {61: "MF61", 62: "MF62"}.get(f, f"FITTYP {f}")
            raw = self.get("FITTYP")
            if raw is not None and str(raw).strip() != "":
                return f"FITTYP {str(raw)[:20]}"
        return str(v).strip().upper() if v is not None else ""

    @property
    def fittyp(self) -> int | None:
        v = self.get("FITTYP", section="MODEL")
        if v is None:
            v = self.get("FITTYP")
        try:
            return int(float(v)) if v is not None and str(v).strip() != "" else None
        except (TypeError, ValueError, OverflowError):
            return None

    @property
    def family(self) -> str:
        """'PAC89', 'MF52' or 'MF61' (MF 6.2 files read as 'MF61'), or '' when the file does not say.

        ``FITTYP`` decides when given (5, 6, 21: MF 5.2; 61, 62: MF 6.1/6.2),
        else ``PROPERTY_FILE_FORMAT``.  A file that declares neither is told
        by its keys: ``a0..a13`` PAC89; MF 6.1-only keys (``NOMPRES``,
        ``PKY4``, ``PPY1``) MF 6.1; ``PCY1``/``PCX1`` MF 5.2.
        """
        declared = str(self.get("PROPERTY_FILE_FORMAT", section="MODEL") or "").strip().upper()
        if declared == "PAC89":
            return "PAC89"
        f = self.fittyp
        raw = self.get("FITTYP")
        if f is None and raw is not None and str(raw).strip() != "":
            return ""  # FITTYP given but not a number: the file does not say what it is
        if f in _FITTYP_FAMILY:
            return _FITTYP_FAMILY[f]
        if declared in _FORMAT_FAMILY:
            return _FORMAT_FAMILY[declared]
        if f is None and declared in ("", "USER"):
            return self._family_from_keys()[0]
        return ""

    #: coefficient names that tell a family when the file does not declare one
    _PAC89_KEYS = ("A0", "A3")
    _MF_KEYS = ("PCY1", "PCX1", "PKY1", "PDY1", "PDX1", "QBZ1")
    #: MF 6.1 terms the 5.2 equations do not have (non-zero), or NOMPRES; PHY3 (non-zero) is 5.2's camber term
    _MF61_MARKERS = ("PKY4", "PKY6", "PKY7", "PPY5", "QSY5", "QSY6", "QSY7", "QSY8")
    _MF52_MARKERS = ("PHY3",)

    def _nonzero(self, keys) -> list[str]:
        out = []
        for k in keys:
            v = self.get(k)
            try:
                if v is not None and float(v) != 0.0:
                    out.append(k)
            except (TypeError, ValueError):
                out.append(k)
        return out

    def _family_from_keys(self) -> tuple[str, str]:
        """(family, why) told from the coefficient names alone; family '' when they do not tell
        (none of the names, PAC89's a0..a13 beside Magic Formula coefficients, or MF 6.1-only terms
        beside MF 5.2's camber term PHY3)."""
        pac = [k for k in self._PAC89_KEYS if self.get(k) is not None]
        mf = [k for k in self._MF_KEYS if self.get(k) is not None]
        if pac and mf:
            return "", (f"it holds both PAC89 coefficients ({', '.join(pac)}) and Magic Formula ones "
                        f"({', '.join(mf)})")
        if pac:
            return "PAC89", f"its PAC89 coefficients ({', '.join(pac)}, no Magic Formula ones)"
        if not mf:
            return "", "it holds none of PAC89's a0..a13 or the Magic Formula's PCY1, PCX1, PKY1"
        m61 = self._nonzero(self._MF61_MARKERS) + (["NOMPRES"] if self.get("NOMPRES") is not None else [])
        m52 = self._nonzero(self._MF52_MARKERS)
        if m61 and m52:
            return "", (f"it holds MF 6.1-only terms ({', '.join(m61)}) and MF 5.2's camber term PHY3, so it is "
                        "neither MF 5.2 nor MF 6.1")
        if m61:
            return "MF61", f"its MF 6.1-only terms ({', '.join(m61)})"
        if m52:
            return "MF52", "its MF 5.2 camber term PHY3 (non-zero)"
        return "MF52", ("its Magic Formula coefficients (MF 5.2 and 6.1 differ only in terms this file "
                        "leaves out or at zero, so both give the same forces)")

    def undeclared_family(self) -> tuple[str, str] | None:
        """For a file with no ``[MODEL]`` section: (family or '', the one-line reason); else None."""
        if "MODEL" in self.sections:
            return None
        f = self.fittyp
        if f is not None:
            fam = _FITTYP_FAMILY.get(f, "")
            return fam, f"FITTYP = {f} found outside [MODEL]"
        declared = str(self.get("PROPERTY_FILE_FORMAT") or "").strip().upper()
        if declared in _FORMAT_FAMILY:
            return _FORMAT_FAMILY[declared], f"PROPERTY_FILE_FORMAT = '{declared}' found outside [MODEL]"
        if declared == "PAC89":
            return "PAC89", "PROPERTY_FILE_FORMAT = 'PAC89' found outside [MODEL]"
        return self._family_from_keys()

    def get(self, key: str, section: str | None = None, default=None):
        key = key.upper()
        if section is not None:
            return self.sections.get(section.upper(), {}).get(key, default)
        for sec in self.sections.values():
            if key in sec:
                return sec[key]
        return default

    def where(self, key: str, section: str | None = None) -> str:
        """'path:line' of ``key`` (first section holding it unless ``section``)."""
        key = key.upper()
        for sec, entries in self.sections.items():
            if (section is None or sec == section.upper()) and key in entries:
                return f"{self.path}:{self.lines.get((sec, key), '?')}"
        return self.path

    def number(self, key: str, section: str | None = None, factor: float = 1.0) -> float | None:
        """``key`` as a finite float times ``factor``; None when absent.

        Raises
        ------
        FormatError
            present but empty, not a number or not finite (naming the line).
        """
        key = key.upper()
        sec = section
        if sec is None:
            sec = next((s for s, e in self.sections.items() if key in e), None)
            if sec is None:
                return None
        entries = self.sections.get(sec.upper(), {})
        if key not in entries:
            return None
        v = entries[key]
        where = self.where(key, sec)
        if v is None:
            raise FormatError(f"{where}: {key} has no value; a number is required")
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise FormatError(f"{where}: {key} = {str(v)[:40]!r} is not a finite number")
        return float(v) * factor

    def unit_factor(self, kind: str) -> float:
        table = _UNIT_TABLES[kind]
        name = str(self.get(kind, section="UNITS", default="") or "").strip().lower()
        if not name:
            return 1.0
        if name not in table:
            raise FormatError(f"{self.where(kind, 'UNITS')}: [UNITS] {kind} = {name[:40]!r} is not understood; "
                              "accepted: " + ", ".join(sorted(table)))
        return table[name]

    @property
    def n_parameters(self) -> int:
        return sum(1 for sec in self.sections.values() for v in sec.values() if isinstance(v, (int, float)))


def _strip_comment(line: str) -> str:
    """Drop ``$`` / ``!`` comments outside quotes (linear in the line length)."""
    if "'" not in line and '"' not in line:
        cut = min((i for i in (line.find("$"), line.find("!")) if i >= 0), default=-1)
        return (line if cut < 0 else line[:cut]).strip()
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


def _is_separator(s: str) -> bool:
    """A section ruler such as ``$-----------units`` or ``!=====``: layout, not a comment."""
    body = s[1:].lstrip()
    rest = body.lstrip("-=_")
    if len(body) - len(rest) < 4:
        return False
    rest = rest.strip()
    return not rest or all(ch.isalpha() or ch in "_ " for ch in rest)


def _is_key(k: str) -> bool:
    return bool(k) and k.isascii() and (k[0].isalpha() or k[0] == "_") and k.replace("_", "a").isalnum()


def _value(text: str):
    """A value as written: quoted text, int, float (Fortran ``D`` exponents too), None when empty, else text."""
    text = text.strip()
    if not text:
        return None
    if len(text) >= 2 and text[0] == text[-1] and text[0] in "'\"":
        return text[1:-1]
    try:
        if len(text) < 400 and _INT.fullmatch(text):
            v = int(text)
            float(v)  # an integer beyond float range is not a usable number: keep the text
            return v
        return float(text.replace("D", "E").replace("d", "e"))
    except (ValueError, OverflowError):
        return text


def _numbers(s: str) -> list[float] | None:
    """A table row of numbers (whitespace or comma separated), or None."""
    try:
        return [float(x.replace("D", "E").replace("d", "e")) for x in s.replace(",", " ").split()]
    except ValueError:
        return None


def read_property_file(path: str | os.PathLike) -> PropertyFile:
    """Read a ``.tir`` property file of any MF / PAC flavour.

    Reads what vendors ship: ``[SECTION]`` headers, ``KEY = value`` lines
    (comments after values, empty values kept as None), ``{col col}`` curve
    tables and keyless tables (rows of numbers such as ``[SHAPE]``'s
    ``1.00 0.00``), vendor sections, ``$``/``!`` comments, LF or CRLF, a UTF-8
    byte-order mark.  No regular expression with nested repetition is applied
    to a line: the parser is linear in the file size.

    Raises
    ------
    FormatError
        empty, binary, a key given twice in a section, a line that is neither
        ``KEY = value`` nor a table row, or no ``[SECTION]`` at all; each
        names the file line.
    """
    p = Path(path)
    raw = read_input_bytes(p, "a tyre property file (.tir)")  # no FIFO, device or oversized file
    if raw.startswith(b"\xef\xbb\xbf"):
        raw = raw[3:]
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
    quoted: set[tuple[str, str]] = set()  # (section, key) of values written in quotes: text by intent
    for lineno, line in enumerate(text.splitlines(), 1):
        s = line.strip()
        if not s:
            continue
        if s[0] in "$!":
            if not _is_separator(s):
                pf.comments.append(s[1:].strip())
            continue
        if s[0] == "[":
            close = s.find("]")
            name = s[1:close].strip() if close > 0 else ""
            if close > 0 and name and name.isascii() and name.replace("_", "a").isalnum():
                section = name.upper()
                pf.sections.setdefault(section, {})  # a repeated section continues (its keys stay unique)
                continue
            raise FormatError(f"{p}:{lineno}: cannot read section header '{s[:40]}'; expected [NAME]")
        s = _strip_comment(s)
        if not s:
            continue
        if section is None:
            raise FormatError(f"{p}:{lineno}: '{s[:40]}' before any [SECTION]; not a tyre property file")
        if s.startswith("{"):
            pf.tables[section] = {"columns": s.strip("{} ").split(), "rows": [], "line": lineno}
            continue
        eq = s.find("=")
        if eq > 0:
            key = s[:eq].strip()
            if _is_key(key):
                key = key.upper()
                entries = pf.sections[section]
                if key in entries:
                    raise FormatError(f"{p}:{lineno}: {key} is given twice in [{section}] (first at line "
                                      f"{pf.lines[(section, key)]}); keep one")
                raw_value = s[eq + 1:].strip()
                entries[key] = _value(raw_value)
                if raw_value[:1] in ("'", '"'):
                    quoted.add((section, key))
                pf.lines[(section, key)] = lineno
                continue
        row = _numbers(s)
        if row:
            tab = pf.tables.get(section)
            if tab is None:  # a keyless table (vendor [SHAPE]: rows of 'radial width')
                tab = pf.tables[section] = {"columns": None, "rows": [], "line": lineno}
            if tab["rows"] and len(tab["rows"][0]) != len(row):
                raise FormatError(f"{p}:{lineno}: table row '{s[:40]}' in [{section}] has {len(row)} values; the "
                                  f"rows above have {len(tab['rows'][0])}")
            tab["rows"].append(row)
            continue
        raise FormatError(f"{p}:{lineno}: cannot read '{s[:40]}' in [{section}]; expected KEY = value or a "
                          "row of numbers")
    if not pf.sections:
        raise FormatError(f"{p}: no [SECTION] found; not a tyre property file")
    # MF files as vendors and tools export them leave optional entries empty (teasit's library writes
    # 'WIDTH =', 'FZMIN =', 'INFLPRES ='): there an empty value outside the coefficient sections means 'not
    # given' (its default, or no declared range), and a required one is named by the MF reader.  A quoted
    # text in a coefficient section is a setting (Chrono's MAN 5t file has CONTACT_MODEL = '3D_ENVELOPING'
    # under a commented-out section header), not a malformed number.
    mf = pf.family in ("MF52", "MF61")
    for (sec, key), lineno in pf.lines.items():
        if sec.endswith(_NUMERIC_SECTION_SUFFIXES) or sec in _NUMERIC_SECTIONS:
            v = pf.sections[sec][key]
            if v is None and not (mf and not sec.endswith("_COEFFICIENTS")):
                raise FormatError(f"{p}:{lineno}: {key} in [{sec}] has no value; a number is required")
            if isinstance(v, str) and sec.endswith("_COEFFICIENTS") and (sec, key) not in quoted:
                raise FormatError(f"{p}:{lineno}: {key} = {v[:40]!r} in [{sec}] is not a number")
    return pf


def declared_ranges(pf: PropertyFile) -> dict[str, tuple[float, float]]:
    """Declared validity ranges in SI from the ``[*_RANGE]`` sections."""
    F, A = pf.unit_factor("FORCE"), pf.unit_factor("ANGLE")
    P = pf.unit_factor("PRESSURE") if pf.get("PRESSURE", section="UNITS") else 1.0
    ranges = {}
    for key, lo, hi, fac in (("fz", "FZMIN", "FZMAX", F), ("slip_angle", "ALPMIN", "ALPMAX", A),
                             ("camber", "CAMMIN", "CAMMAX", A), ("slip_ratio", "KPUMIN", "KPUMAX", 1.0),
                             ("pressure", "PRESMIN", "PRESMAX", P)):
        if pf.get(lo) is None or pf.get(hi) is None:  # absent, or left empty in an MF file: no declared range
            continue
        a, b = pf.number(lo, factor=fac), pf.number(hi, factor=fac)
        if a is not None and b is not None:
            if not a <= b:
                raise FormatError(f"{pf.where(lo)}: {lo} = {a / fac:g} is above {hi} = {b / fac:g}")
            ranges[key] = (a, b)
    return ranges
