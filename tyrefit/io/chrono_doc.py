"""Project Chrono's PAC89 tyre JSON (``Template: Pac89Tire``) as plain data: a tyre's arguments, a document.

Layout of ``shared/reference/chrono/HMMWV_Pac89Tire.json``: SI design
parameters, lowercase coefficients in "Lateral/Longitudinal/Aligning
Coefficients", an optional nonlinear "Vertical Curve Data" table of
(deflection [m], force [N]).  Chrono's files carry ``//`` comments, which are
stripped before parsing; a UTF-8 byte-order mark is accepted.

What Chrono reads unconditionally (projectchrono/chrono @ 17a9098167,
``src/chrono_vehicle/wheeled_vehicle/tire/Pac89Tire.cpp``, ``Pac89Tire::Create``):
``Mass``, ``Inertia`` (3 values), and in "Design Parameters" ``Unloaded Radius``,
``Width``, ``Lateral Stiffness``, ``Vertical Stiffness``, ``Vertical Damping``,
``Rolling Resistance``; each coefficient block present must give every
coefficient (a0..a13, b0..b10, c0..c17).  :func:`chrono_dict` writes all of
them or refuses (:class:`~tyrefit.errors.ModelError` naming what is missing);
a part without a model is written as its neutral block
(:data:`tyrefit.io.pac89_tir.NEUTRAL_BLOCKS`), finite in Chrono's equations, and
said "not fitted" in ``Notes`` with every estimated design value.

This module knows no tyre class (:func:`chrono_dict` reads the attributes of a
:class:`~tyrefit.tyres.pac89.Pac89Tyre`), so that both the tyre's own file
methods and :mod:`tyrefit.io.chrono_json` build on it without an import cycle.
"""

from __future__ import annotations

import json
import math
import os
import re
from pathlib import Path

from ..errors import FormatError, ModelError, option
from ..models import pac89
from .inputs import read_input_bytes
from .outputs import write_text
from .pac89_tir import coefficients_for_export

__all__ = ["chrono_fields", "chrono_dict", "write_chrono_json", "REQUIRED_DESIGN"]

_SECTIONS = (("Lateral Coefficients", pac89.LATERAL), ("Longitudinal Coefficients", pac89.LONGITUDINAL),
             ("Aligning Coefficients", pac89.ALIGNING))


def _strip_comments(text: str) -> str:
    out = []
    for line in text.splitlines():
        # drop // comments that are not inside a string
        in_str, i = False, 0
        while i < len(line):
            ch = line[i]
            if ch == '"' and (i == 0 or line[i - 1] != "\\"):
                in_str = not in_str
            elif not in_str and line.startswith("//", i):
                line = line[:i]
                break
            i += 1
        out.append(line)
    text = "\n".join(out)
    return re.sub(r",(\s*[}\]])", r"\1", text)  # trailing commas


def _finite(v, p: Path, what: str) -> float:
    """``float(v)``, or FormatError unless ``v`` is a finite number."""
    try:
        x = float(v)
    except (TypeError, ValueError, OverflowError):
        x = math.nan
    if isinstance(v, bool) or not math.isfinite(x):
        raise FormatError(f"{p}: {what} = {str(v)[:40]!r} is not a finite number")
    return x


def chrono_fields(path: str | os.PathLike) -> dict:
    """The :class:`~tyrefit.tyres.pac89.Pac89Tyre` arguments of a Chrono PAC89 JSON file."""
    p = Path(path)
    raw = read_input_bytes(p, "a Chrono tyre JSON file")  # no FIFO, device or oversized file
    try:
        doc = json.loads(_strip_comments(raw.decode("utf-8-sig")))
    except (ValueError, RecursionError) as exc:  # bad UTF-8, bad JSON, >4300-digit integers, deep nesting
        raise FormatError(f"{p}: not a Chrono tyre JSON file ({exc.__class__.__name__}: "
                          f"{(str(exc).splitlines() or [''])[0][:80]})") from None
    if not isinstance(doc, dict) or "Lateral Coefficients" not in doc:
        raise FormatError(f"{p}: no 'Lateral Coefficients'; expected Chrono's Pac89Tire JSON")
    coeffs: dict[str, float] = {}
    missing: list[str] = []
    for sec, names in _SECTIONS:
        block = doc.get(sec, {}) or {}
        if not isinstance(block, dict):
            raise FormatError(f"{p}: '{sec}' must be an object of coefficients")
        for k, v in block.items():
            k = str(k).lower()
            if k in names:
                coeffs[k] = _finite(v, p, f"{sec} {k}")
        if sec in doc:  # Chrono reads every coefficient of a block that is present
            missing += [k for k in names if k not in coeffs]
    d = doc.get("Design Parameters", {}) or {}
    if not isinstance(d, dict):
        raise FormatError(f"{p}: 'Design Parameters' must be an object of named values")

    def num(key):
        v = d.get(key)
        return _finite(v, p, f"Design Parameters {key}") if isinstance(v, (int, float)) else None

    curve = d.get("Vertical Curve Data")
    if curve:
        if not isinstance(curve, list) or not all(isinstance(r, list) and len(r) == 2 for r in curve):
            raise FormatError(f"{p}: 'Vertical Curve Data' must be a list of [deflection (m), force (N)] pairs")
        curve = [(_finite(a, p, "Vertical Curve Data"), _finite(b, p, "Vertical Curve Data")) for a, b in curve]
    mass = doc.get("Mass")
    mass = _finite(mass, p, "Mass") if mass is not None else None
    inertia = doc.get("Inertia")
    if inertia is not None:
        if not isinstance(inertia, list) or len(inertia) != 3:
            raise FormatError(f"{p}: 'Inertia' must be a list of 3 numbers [Ixx, Iyy, Izz] (kg m2)")
        inertia = tuple(_finite(v, p, "Inertia") for v in inertia)
    return dict(
        coefficients=coeffs,
        mass=mass,
        inertia=inertia,
        vertical_damping=num("Vertical Damping"),
        unloaded_radius=num("Unloaded Radius"),
        width=num("Width"),
        lateral_stiffness=num("Lateral Stiffness"),
        vertical_stiffness=num("Vertical Stiffness"),
        rolling_resistance=num("Rolling Resistance") or 0.0,
        vertical_curve=curve or None,
        name=str(doc.get("Name", p.stem)),
        missing=missing,
    )


#: the design parameters Pac89Tire::Create reads unconditionally (Pac89Tire.cpp @ 17a9098167)
REQUIRED_DESIGN = ("Unloaded Radius", "Width", "Lateral Stiffness", "Vertical Stiffness", "Vertical Damping",
                   "Rolling Resistance")


def _flags_for(missing: list[str]) -> str:
    """The ``fit`` arguments that give the missing Chrono keys (see :func:`tyrefit.tyres.size.with_design`);
    :func:`tyrefit.errors.option` names them, so the command line reads them as flags."""
    geometry = {"Unloaded Radius", "Width", "Mass", "Inertia"} & set(missing)
    stiffness = {"Vertical Stiffness", "Lateral Stiffness", "Vertical Damping"} & set(missing)
    flags = []
    if geometry:
        flags.append(f"{option('size', 'SIZE')} (e.g. 385/65R22.5: radius and width; mass and inertia estimated "
                     "from them)")
    if stiffness:
        flags.append(f"{option('rated_load', 'NEWTONS')} (vertical stiffness estimated as 15 % deflection of the "
                     f"section height, lateral stiffness and damping from it) or {option('vertical', 'VERTICAL.csv')} "
                     "(measured)")
    if "Rolling Resistance" in missing:
        flags.append("a rolling resistance")
    return "give fit " + " and ".join(flags)


def chrono_dict(tyre, mass: float | None = None, inertia=None) -> dict:
    """The Chrono JSON document of ``tyre`` as a dict, with every key Chrono reads unconditionally.

    Raises
    ------
    ModelError
        a value Chrono needs is unknown (radius, width, stiffnesses, damping,
        mass, inertia); the message names them and the ``fit`` arguments
        (flags on the command line) that give them.
    """
    mass = tyre.mass if mass is None else mass
    inertia = tyre.inertia if inertia is None else inertia
    design: dict[str, object] = {}
    values = {"Unloaded Radius": tyre.unloaded_radius, "Width": tyre.width,
              "Vertical Stiffness": tyre.vertical_stiffness, "Vertical Damping": tyre.vertical_damping,
              "Lateral Stiffness": tyre.lateral_stiffness, "Rolling Resistance": tyre.rolling_resistance}
    missing = [k for k, v in values.items() if v is None]
    missing += [k for k, v in (("Mass", mass), ("Inertia", inertia)) if v is None]
    if missing:
        raise ModelError(f"Chrono's Pac89Tire JSON needs {', '.join(missing)}, which this tyre does not have; "
                         + _flags_for(missing))
    if tyre.lateral_stiffness <= 0:
        raise ModelError(f"Lateral Stiffness = {tyre.lateral_stiffness!r} N/m: Chrono divides Fy by it; it must be "
                         "positive")
    for k in ("Unloaded Radius", "Width", "Vertical Stiffness"):
        design[k] = float(values[k])
    design["Vertical Damping"] = float(tyre.vertical_damping)
    if tyre.vertical_curve:
        design["Vertical Curve Data"] = [[float(a), float(b)] for a, b in tyre.vertical_curve]
    design["Lateral Stiffness"] = float(tyre.lateral_stiffness)
    design["Rolling Resistance"] = float(tyre.rolling_resistance)
    coeffs, absent = coefficients_for_export(tyre)
    notes = [str(h) for h in tyre.header if any(k in str(h) for k in ("ESTIMATED", "NOT FITTED", "WARNING"))]
    for part in absent:
        note = (f"{part} part NOT FITTED (no data): neutral coefficients, zero force (C = 1, D = Fz, slip "
                "stiffness 0)")
        if not any(n.startswith(part) and "NOT FITTED" in n for n in notes):
            notes.append(note)
    doc: dict[str, object] = {"Name": tyre.name, "Type": "Tire", "Template": "Pac89Tire"}
    if notes:
        doc["Notes"] = notes
    doc["Mass"] = float(mass)
    doc["Inertia"] = [float(v) for v in inertia]
    doc["Coefficient of Friction"] = 0.8
    doc["Design Parameters"] = design
    for sec, names in _SECTIONS:
        doc[sec] = {k: coeffs[k] for k in names}
    warns = [h[len("WARNING: "):] for h in tyre.header if h.startswith("WARNING: ")]
    if warns:  # the fit's warnings (tyrefit.fitting.FitResult.warnings); Chrono ignores unknown keys
        doc["warnings"] = warns
    return doc


def write_chrono_json(tyre, path: str | os.PathLike, force: bool = False) -> Path:
    """Write Chrono's PAC89 JSON of ``tyre`` (atomically)."""
    return write_text(path, json.dumps(chrono_dict(tyre), indent=4) + "\n", force=force)
