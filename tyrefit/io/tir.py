"""Tyre property files: read any Adams/MF ``.tir`` into its tyre, read and write PAC89.

:func:`read_property_file` (:mod:`tyrefit.io.property_file`) reads the generic
layout shared by PAC89, PAC2002 / MF 5.x and MF 6.x files: ``[SECTION]``
headers, ``KEY = value`` lines, ``$`` and ``!`` comments, quoted strings, curve
tables (a ``{a b}`` line followed by rows of numbers), LF or CRLF, any case.
Nothing is dropped: vendor sections are kept as they are.

:func:`read_tyre` reads any tyre file into the right
:class:`~tyrefit.tyres.base.Tyre`; :func:`read_tir` turns a PAC89 file into a
:class:`~tyrefit.tyres.pac89.Pac89Tyre` (SI design data; coefficients as
written) and :func:`write_tir` writes the Adams-style PAC89 layout of
``shared/reference/adams_pac89_example.tir`` (:mod:`tyrefit.io.pac89_tir`).
Floats are written with ``repr`` so that write -> read is exact.

Layering: :mod:`~tyrefit.io.property_file`, :mod:`~tyrefit.io.pac89_tir` and
:mod:`~tyrefit.io.chrono_doc` know no tyre class; the tyre classes build on
them, and this module (with :mod:`tyrefit.io.chrono_json`) builds on the tyre
classes, so that the import graph has no cycle.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from ..errors import FormatError
from ..tyres.base import Tyre
from ..tyres.mf import REQUIRED_MF, MFTyre
from ..tyres.pac89 import REQUIRED, Pac89Tyre  # noqa: F401  (REQUIRED: public here too)
from .chrono_json import read_chrono_json
from .pac89_tir import (NEUTRAL_BLOCKS, coefficients_for_export, format_tir, pac89_fields,  # noqa: F401
                        read_pac89_fields, write_tir)
from .property_file import PropertyFile, declared_ranges, read_property_file

__all__ = ["PropertyFile", "read_property_file", "read_tir", "read_tyre", "write_tir", "format_tir",
           "pac89_from_property_file", "mf_from_property_file"]


def pac89_from_property_file(pf: PropertyFile, file_notes: list[str] | None = None) -> Pac89Tyre:
    """A :class:`Pac89Tyre` from a parsed PAC89 property file (design data in SI).

    The lateral block a0..a13 is required; the longitudinal (b) and aligning
    (c) blocks are optional, but a block the file starts must be complete.
    Missing coefficients are listed in :attr:`Pac89Tyre.missing` (so that
    ``inspect`` can name them) and make :meth:`Pac89Tyre.check` fail.
    """
    return Pac89Tyre(**pac89_fields(pf), file_notes=list(file_notes or []))


def read_tir(path: str | os.PathLike) -> Pac89Tyre:
    """Read a PAC89 ``.tir`` into a :class:`Pac89Tyre` (design data in SI)."""
    return Pac89Tyre(**read_pac89_fields(path))


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
        return read_chrono_json(path)
    pf = read_property_file(path)
    fam = pf.family
    notes: list[str] = []
    undeclared = pf.undeclared_family()
    if undeclared is not None:
        told, why = undeclared
        if not told or told != fam:
            raise FormatError(f"{path}: no [MODEL] section (PROPERTY_FILE_FORMAT or FITTYP), and the family "
                              f"cannot be told: {why}; add [MODEL] with PROPERTY_FILE_FORMAT = 'PAC89' or "
                              "FITTYP = 61 (MF 6.1) / 6 (MF 5.2)")
        notes.append(f"{path}: no [MODEL] section (PROPERTY_FILE_FORMAT or FITTYP); read as {told} from {why}")
    if fam in ("PAC89", "MF52", "MF61"):
        return (pac89_from_property_file if fam == "PAC89" else mf_from_property_file)(pf, file_notes=notes)
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


def mf_from_property_file(pf: PropertyFile, file_notes: list[str] | None = None) -> MFTyre:
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
        ranges=declared_ranges(pf),
        header=list(pf.comments),
        tables={k: dict(v) for k, v in pf.tables.items()},
        source=pf.path,
        file_notes=list(file_notes or []),
    )
