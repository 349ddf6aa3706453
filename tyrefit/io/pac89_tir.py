"""PAC89's Adams ``.tir`` layout as plain data: the tyre's arguments from a parsed file, and the file's text.

The Adams-style PAC89 layout of ``shared/reference/adams_pac89_example.tir``.
Floats are written with ``repr`` so that write -> read is exact.  This module
knows no tyre class (the writer reads the attributes of a
:class:`~tyrefit.tyres.pac89.Pac89Tyre`), so that both the tyre's own file
methods and :mod:`tyrefit.io.tir` build on it without an import cycle.
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

from ..errors import FormatError
from ..models import pac89
from .outputs import write_text
from .property_file import PropertyFile, declared_ranges, read_property_file

__all__ = ["pac89_fields", "read_pac89_fields", "format_tir", "write_tir", "coefficients_for_export", "NEUTRAL_BLOCKS"]

#: characters str.splitlines() breaks lines at, and other control characters (NUL marks a binary file)
_LINE_BREAKS = re.compile("[\n\r\v\f\x1c\x1d\x1e\x85\u2028\u2029]+")
_CONTROL = re.compile("[\x00-\x08\x0e-\x1f\x7f]")


def pac89_fields(pf: PropertyFile) -> dict:
    """The :class:`~tyrefit.tyres.pac89.Pac89Tyre` arguments of a parsed PAC89 property file (design data in SI).

    The lateral block a0..a13 is required; the longitudinal (b) and aligning
    (c) blocks are optional, but a block the file starts must be complete.
    Missing coefficients are listed in :attr:`~tyrefit.tyres.pac89.Pac89Tyre.missing` (so that
    ``inspect`` can name them) and make :meth:`~tyrefit.tyres.pac89.Pac89Tyre.check` fail.
    """
    path = pf.path
    L, F = pf.unit_factor("LENGTH"), pf.unit_factor("FORCE")
    coeffs, missing = {}, []
    for part, names in pac89.PARTS.items():
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
    return dict(
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
        ranges=declared_ranges(pf),
        header=list(pf.comments),
        name=str(pf.get("NAME", section="MODEL") or Path(path).stem),
        tyreside=str(pf.get("TYRESIDE") or "LEFT").upper(),
        missing=missing,
    )


def read_pac89_fields(path: str | os.PathLike) -> dict:
    """:func:`pac89_fields` of the PAC89 ``.tir`` at ``path``.

    Raises
    ------
    FormatError
        unreadable, or not a PAC89 file (:func:`tyrefit.io.tir.read_tyre` reads every family).
    """
    pf = read_property_file(path)
    if pf.family != "PAC89":
        fmt = pf.format
        raise FormatError(f"{path}: PROPERTY_FILE_FORMAT is {fmt or 'missing'!s}; a PAC89 file is needed here "
                          "(read any tyre file with tyrefit.io.tir.read_tyre)")
    return pac89_fields(pf)


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


def coefficients_for_export(tyre) -> tuple[dict[str, float], list[str]]:
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


def format_tir(tyre) -> str:
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


def write_tir(tyre, path: str | os.PathLike, force: bool = False, check: bool = True) -> Path:
    """Write ``tyre`` as an Adams-style PAC89 ``.tir`` (atomically).

    With ``check`` (default) the model must be physical over its load range
    (C > 0, D > 0, E <= 1), else :class:`~tyrefit.errors.ModelError`.
    """
    if check:
        tyre.check_physical()
    return write_text(path, format_tir(tyre), force=force)
