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
from ..tyres.base import Tyre
from ..tyres.mf import REQUIRED_MF, MFTyre
from ..tyres.pac89 import REQUIRED, Pac89Tyre
from .inputs import read_input_bytes
from .outputs import write_text

__all__ = ["PropertyFile", "read_property_file", "read_tir", "read_tyre", "write_tir", "format_tir",
           "pac89_from_property_file", "mf_from_property_file"]

#: characters str.splitlines() breaks lines at, and other control characters (NUL marks a binary file)
_LINE_BREAKS = re.compile("[\n\r\v\f\x1c\x1d\x1e\x85\u2028\u2029]+")
_CONTROL = re.compile("[\x00-\x08\x0e-\x1f\x7f]")
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
            if self.get("A0") is not None or self.get("A3") is not None:
                return "PAC89"
            if any(self.get(k) is not None for k in ("NOMPRES", "PKY4", "PPY1", "PPX1")):
                return "MF61"
            if self.get("PCY1") is not None or self.get("PCX1") is not None:
                return "MF52"
        return ""

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


def _ranges(pf: PropertyFile) -> dict[str, tuple[float, float]]:
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


def pac89_from_property_file(pf: PropertyFile) -> Pac89Tyre:
    """A :class:`Pac89Tyre` from a parsed PAC89 property file (design data in SI).

    The lateral block a0..a13 is required; the longitudinal (b) and aligning
    (c) blocks are optional, but a block the file starts must be complete.
    Missing coefficients are listed in :attr:`Pac89Tyre.missing` (so that
    ``inspect`` can name them) and make :meth:`Pac89Tyre.check` fail.
    """
    path = pf.path
    L, F = pf.unit_factor("LENGTH"), pf.unit_factor("FORCE")
    coeffs, missing = {}, []
    for part, names in REQUIRED.items():
        given = [n for n in names if any(n.upper() in e for e in pf.sections.values())]
        if part != "lateral" and not given:
            continue
        for name in names:
            v = pf.number(name)
            if v is None:
                missing.append(name)
            else:
                coeffs[name] = v
    if not any(k in coeffs for k in pac89.LATERAL) and not any(k in coeffs for k in pac89.LONGITUDINAL):
        raise FormatError(f"{path}: no PAC89 coefficients found (a0..a13, b0..b10); expected "
                          "[LATERAL_COEFFICIENTS] a0 = ...")

    damping = pf.number("VERTICAL_DAMPING", factor=F * pf.unit_factor("TIME") / L)
    mass = pf.number("MASS", section="INERTIA")
    return Pac89Tyre(
        coefficients=coeffs,
        unloaded_radius=pf.number("UNLOADED_RADIUS", factor=L),
        width=pf.number("WIDTH", section="DIMENSION", factor=L),
        aspect_ratio=pf.number("ASPECT_RATIO", section="DIMENSION"),
        fnomin=pf.number("FNOMIN", factor=F),
        lateral_stiffness=pf.number("LATERAL_STIFFNESS", factor=F / L),
        vertical_stiffness=pf.number("VERTICAL_STIFFNESS", factor=F / L),
        vertical_damping=damping,
        mass=mass,
        rolling_resistance=pf.number("ROLLING_RESISTANCE") or 0.0,
        ranges=_ranges(pf),
        header=list(pf.comments),
        name=str(pf.get("NAME", section="MODEL") or Path(path).stem),
        tyreside=str(pf.get("TYRESIDE") or "LEFT").upper(),
        missing=missing,
    )


def read_tir(path: str | os.PathLike) -> Pac89Tyre:
    """Read a PAC89 ``.tir`` into a :class:`Pac89Tyre` (design data in SI)."""
    pf = read_property_file(path)
    if pf.family != "PAC89":
        fmt = pf.format
        raise FormatError(f"{path}: PROPERTY_FILE_FORMAT is {fmt or 'missing'!s}; a PAC89 file is needed here "
                          "(read any tyre file with tyrefit.io.tir.read_tyre)")
    return pac89_from_property_file(pf)


def read_tyre(path: str | os.PathLike) -> Tyre:
    """Read any tyre file the tool knows into the right :class:`~tyrefit.tyres.base.Tyre`.

    PAC89 ``.tir`` -> :class:`Pac89Tyre`; MF 5.x / PAC2002 (``FITTYP`` 5, 6, 21,
    ``PROPERTY_FILE_FORMAT`` 'MF_05', 'PAC2002', 'MF5.2') and MF 6.1 / 6.2
    (``FITTYP`` 61, 62) -> :class:`~tyrefit.tyres.mf.MFTyre`; Chrono PAC89
    ``.json`` -> :class:`Pac89Tyre`.  This is the one public entry point for
    reading a tyre.

    Raises
    ------
    FormatError
        unreadable, or a family the tool does not evaluate.
    """
    if str(path).lower().endswith(".json"):
        from .chrono_json import read_chrono_json

        return read_chrono_json(path)
    pf = read_property_file(path)
    fam = pf.family
    if fam == "PAC89":
        return pac89_from_property_file(pf)
    if fam in ("MF52", "MF61"):
        return mf_from_property_file(pf)
    fmt = pf.format
    raise FormatError(f"{path}: cannot tell the tyre model: PROPERTY_FILE_FORMAT / FITTYP is "
                      f"{fmt[:40] or 'missing'!s}; accepted: PAC89, MF 5.x/PAC2002 (FITTYP 5, 6, 21, 'MF_05', "
                      "'PAC2002'), MF 6.1/6.2 (FITTYP 61, 62)")


#: dimensional MF keys -> unit kind(s) ('LENGTH', 'FORCE', ...; a tuple is a quotient numerator/denominator)
_MF_UNITS = {
    "UNLOADED_RADIUS": "LENGTH", "WIDTH": "LENGTH", "RIM_RADIUS": "LENGTH", "RIM_WIDTH": "LENGTH",
    "BOTTOM_OFFST": "LENGTH", "Q_RA1": None, "FNOMIN": "FORCE", "FZMIN": "FORCE", "FZMAX": "FORCE",
    "NOMPRES": "PRESSURE", "INFLPRES": "PRESSURE", "PRESMIN": "PRESSURE", "PRESMAX": "PRESSURE",
    "IP": "PRESSURE", "IP_NOM": "PRESSURE",
    "ALPMIN": "ANGLE", "ALPMAX": "ANGLE", "CAMMIN": "ANGLE", "CAMMAX": "ANGLE",
    "LONGVL": ("LENGTH", "TIME"), "VXLOW": ("LENGTH", "TIME"),
    "VERTICAL_STIFFNESS": ("FORCE", "LENGTH"), "VERTICAL_DAMPING": ("FORCE", "TIME", "LENGTH"),
    "LATERAL_STIFFNESS": ("FORCE", "LENGTH"), "LONGITUDINAL_STIFFNESS": ("FORCE", "LENGTH"),
    "BOTTOM_STIFF": ("FORCE", "LENGTH"), "MASS": "MASS",
}


def _mf_factor(pf: PropertyFile, kind) -> float:
    if kind is None:
        return 1.0
    if isinstance(kind, str):
        return pf.unit_factor(kind)
    if len(kind) == 2:
        return pf.unit_factor(kind[0]) / pf.unit_factor(kind[1])
    return pf.unit_factor(kind[0]) * pf.unit_factor(kind[1]) / pf.unit_factor(kind[2])


def mf_from_property_file(pf: PropertyFile) -> MFTyre:
    """An :class:`~tyrefit.tyres.mf.MFTyre` from a parsed MF 5.x / 6.x property file.

    Every numeric entry becomes a parameter under its upper-case key; the
    dimensional ones (radius, loads, pressures, speeds, ranges, stiffnesses)
    are converted to SI through the file's ``[UNITS]``.  Empty values in
    coefficient sections have already been refused by :func:`read_property_file`;
    an empty optional entry elsewhere (``WIDTH =``, ``FZMIN =``) is not given,
    and an empty required one (``FNOMIN =``) is an error naming its line.
    Missing required coefficients are listed in
    ``missing`` (not guessed).
    """
    params: dict[str, float] = {}
    for sec, entries in pf.sections.items():
        if sec in ("UNITS", "MDI_HEADER"):
            continue
        for key, v in entries.items():
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                continue
            if not math.isfinite(float(v)):
                raise FormatError(f"{pf.where(key, sec)}: {key} = {v!r} is not a finite number")
            if key in params:  # the same key in two sections: the first one counts, as in Adams
                continue
            params[key] = float(v) * _mf_factor(pf, _MF_UNITS.get(key))
    for req in (k for part in REQUIRED_MF.values() for k in part):
        if req not in params and any(entries.get(req, 0) is None for entries in pf.sections.values()):
            raise FormatError(f"{pf.where(req)}: {req} has no value; a number is required")
    family = pf.family
    fittyp = pf.fittyp
    version = {62: "6.2", 61: "6.1"}.get(fittyp, "6.1" if family == "MF61" else "5.2")
    nom_p = params.get("NOMPRES", params.get("IP_NOM"))
    return MFTyre(
        params=params,
        family=family,
        version=version,
        declared_format=pf.format,
        name=str(pf.get("NAME") or Path(pf.path).stem),
        tyreside=str(pf.get("TYRESIDE") or "LEFT").upper(),
        fnomin=params.get("FNOMIN"),
        unloaded_radius=params.get("UNLOADED_RADIUS"),
        width=params.get("WIDTH"),
        nominal_pressure=nom_p,
        nominal_speed=params.get("LONGVL"),
        ranges=_ranges(pf),
        header=list(pf.comments),
        tables={k: dict(v) for k, v in pf.tables.items()},
        source=pf.path,
    )


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
    """``KEY = value`` padded to a column, then `` $ comment``: a value never runs into the comment."""
    s = f"{key:<21}= {value}"
    return f"{s:<39} $ {comment}" if comment else s


#: coefficient blocks written for a part with no data: finite in Chrono's equations (C = 1, D = Fz [N],
#: a4 = 1 so that sin(2 atan(Fz/a4)) is defined) with zero slip stiffness (a3, b3, b4, c3, c4 = 0), so
#: that B = BCD / (C D) = 0 and the part gives no force: never the all-zero block (B = 0/0 = NaN)
NEUTRAL_BLOCKS = {
    "lateral": {**{k: 0.0 for k in pac89.LATERAL}, "a0": 1.0, "a2": 1.0, "a4": 1.0},
    "longitudinal": {**{k: 0.0 for k in pac89.LONGITUDINAL}, "b0": 1.0, "b2": 1.0},
    "aligning": {**{k: 0.0 for k in pac89.ALIGNING}, "c0": 1.0, "c2": 1.0},
}


def coefficients_for_export(tyre: Pac89Tyre) -> tuple[dict[str, float], list[str]]:
    """The coefficients to write, a part without a model replaced by its :data:`NEUTRAL_BLOCKS`; the parts."""
    c = dict(tyre.coefficients)
    absent = []
    for part, ok in (("lateral", tyre.has_lateral), ("longitudinal", tyre.has_longitudinal),
                     ("aligning", tyre.has_aligning)):
        if not ok:
            c.update(NEUTRAL_BLOCKS[part])
            absent.append(part)
    return c, absent


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
    coeffs, absent = coefficients_for_export(tyre)
    header = list(tyre.header or ["PAC89 tyre written by tyrefit"])
    for part in absent:
        note = (f"{part} part NOT FITTED (no data): neutral coefficients, zero force (C = 1, D = Fz, slip "
                "stiffness 0)")
        if not any(h.startswith(part) and "NOT FITTED" in h for h in header):
            header.append(note)
    for h in header:
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
    if tyre.aspect_ratio is not None:
        dims.append(_line("ASPECT_RATIO", _fc(tyre.aspect_ratio), "-"))
    if dims:
        out += [bar + "dimension", "[DIMENSION]"] + dims
    vert = []
    if tyre.fnomin is not None:
        vert.append(_line("FNOMIN", _f(tyre.fnomin), "N, nominal (rated) load"))
    if tyre.vertical_stiffness is not None:
        vert.append(_line("VERTICAL_STIFFNESS", _fc(tyre.vertical_stiffness * 1e-3), "N/mm"))
    if tyre.vertical_damping is not None:
        vert.append(_line("VERTICAL_DAMPING", _fc(tyre.vertical_damping * 1e-3), "N*s/mm"))
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
        out += [f"{n:<4}= {_f(coeffs[n])}" for n in names]
    return "\n".join(out) + "\n"


def write_tir(tyre: Pac89Tyre, path: str | os.PathLike, force: bool = False, check: bool = True) -> Path:
    """Write ``tyre`` as an Adams-style PAC89 ``.tir`` (atomically).

    With ``check`` (default) the model must be physical over its load range
    (C > 0, D > 0, E <= 1), else :class:`~tyrefit.errors.ModelError`.
    """
    if check:
        tyre.check_physical()
    return write_text(path, format_tir(tyre), force=force)
