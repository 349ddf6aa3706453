"""One glossary for every quantity tyrefit reads, computes or writes.

Each canonical column has a meaning, an SI unit and, where TYDEX defines one,
its TYDEX channel code.  Readers rename foreign channel names through
:data:`ALIASES` and convert units through :func:`to_si`; nothing else in the
package knows about kN, degrees, bar or km/h.

Units are written in CSV headers as ``name [unit]``; see :data:`UNITS` for
what each dimension accepts.  ``load [kg]`` is a set-point *mass*: it is
multiplied by standard gravity g = 9.80665 m/s^2 to give newtons.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import UnitError, close_matches

__all__ = [
    "G0",
    "Quantity",
    "GLOSSARY",
    "UNITS",
    "ALIASES",
    "parse_header",
    "to_si",
    "from_si",
    "dimension_of",
]

#: standard gravity [m/s^2], used for ``[kg]`` loads
G0 = 9.80665


@dataclass(frozen=True)
class Quantity:
    """A glossary entry: canonical name, meaning, dimension, SI unit, TYDEX code."""

    name: str
    meaning: str
    dimension: str
    si_unit: str
    tydex: str = ""


_Q = Quantity
#: canonical columns (DESIGN.md) and the quantities reports use
GLOSSARY: dict[str, Quantity] = {
    q.name: q
    for q in [
        _Q("run", "sweep identifier: one steady condition, one slip sweep", "count", "-"),
        _Q("fz", "vertical (normal) load on the tyre, positive in compression", "force", "N", "FZW"),
        _Q("fx", "longitudinal force, positive driving (ISO-W)", "force", "N", "FX"),
        _Q("fy", "lateral force (ISO-W: negative for positive slip angle)", "force", "N", "FYW"),
        _Q("mz", "aligning moment (ISO-W)", "moment", "N*m", "MZW"),
        _Q("mx", "overturning moment (ISO-W)", "moment", "N*m", "MXW"),
        _Q("slip_angle", "slip angle alpha (ISO-W)", "angle", "rad", "SLIPANGL"),
        _Q("slip_ratio", "longitudinal slip ratio kappa, positive driving", "ratio", "-", "LONGSLIP"),
        _Q("camber", "inclination (camber) angle gamma", "angle", "rad", "INCLANGL"),
        _Q("pressure", "inflation pressure (gauge)", "pressure", "Pa", "INFLPRES"),
        _Q("speed", "longitudinal wheel-centre speed", "speed", "m/s", "LONGVEL"),
        _Q("lateral_displacement", "static-rig lateral displacement of the rim over the plate", "length", "m"),
        _Q("vertical_displacement", "vertical tyre deflection", "length", "m"),
        _Q("load", "nominal load set point", "force", "N"),
        _Q("length", "contact-patch length", "length", "m"),
        _Q("width", "contact-patch width", "length", "m"),
        _Q("area", "contact-patch area", "area", "m2"),
        _Q("treadwear", "UTQG treadwear rating", "ratio", "-"),
        _Q("stopping_distance", "braking distance to standstill", "length", "m"),
        _Q("initial_speed", "speed at the start of braking", "speed", "m/s"),
        _Q("particles", "tyre-wear particle emission rate (per distance in a file: converted with the speed)",
           "rate", "1/s"),
        _Q("time", "time", "time", "s", "RUNTIME"),
        _Q("loaded_radius", "loaded radius", "length", "m", "RIMRADIUS"),
        _Q("rolling_radius", "effective rolling radius", "length", "m"),
        _Q("torque", "wheel torque", "moment", "N*m"),
        _Q("mu", "friction coefficient F/Fz", "ratio", "-"),
        _Q("phase", "load/unload phase of a vertical-stiffness test (+1 load, -1 unload)", "count", "-"),
    ]
}

# unit name -> (dimension, factor to SI, offset) ; SI = value * factor
_U: dict[str, tuple[str, float]] = {
    # force
    "N": ("force", 1.0), "kN": ("force", 1e3), "daN": ("force", 10.0), "lbf": ("force", 4.4482216152605), "kg": ("force", G0),
    # moment
    "N*m": ("moment", 1.0), "Nm": ("moment", 1.0), "N.m": ("moment", 1.0), "daN*m": ("moment", 10.0), "kNm": ("moment", 1e3),
    "lbf*ft": ("moment", 1.3558179483314004), "ft*lbf": ("moment", 1.3558179483314004),
    # angle
    "rad": ("angle", 1.0), "deg": ("angle", math.pi / 180.0),
    # length
    "m": ("length", 1.0), "mm": ("length", 1e-3), "cm": ("length", 1e-2), "in": ("length", 0.0254),
    "ft": ("length", 0.3048),
    # pressure
    "Pa": ("pressure", 1.0), "kPa": ("pressure", 1e3), "bar": ("pressure", 1e5), "psi": ("pressure", 6894.757293168361),
    "MPa": ("pressure", 1e6),
    # speed
    "m/s": ("speed", 1.0), "km/h": ("speed", 1 / 3.6), "kph": ("speed", 1 / 3.6), "mph": ("speed", 0.44704),
    # area
    "m2": ("area", 1.0), "cm2": ("area", 1e-4), "mm2": ("area", 1e-6), "in2": ("area", 0.0254**2),
    # dimensionless
    "-": ("ratio", 1.0), "%": ("ratio", 1e-2), "1": ("ratio", 1.0),
    # time
    "s": ("time", 1.0), "ms": ("time", 1e-3),
    # counts
    "count": ("count", 1.0), "#": ("count", 1.0),
    # emission rates: per second (SI), or per distance (converted with the speed by the readers)
    "#/s": ("rate", 1.0), "1/s": ("rate", 1.0), "#/min": ("rate", 1 / 60), "1/min": ("rate", 1 / 60),
    "#/h": ("rate", 1 / 3600), "1/h": ("rate", 1 / 3600),
    "#/m": ("per_distance", 1.0), "1/m": ("per_distance", 1.0), "#/km": ("per_distance", 1e-3),
    "1/km": ("per_distance", 1e-3), "#/mi": ("per_distance", 1 / 1609.344),
    # stiffness (for tyre files)
    "N/m": ("stiffness", 1.0), "N/mm": ("stiffness", 1e3), "kN/m": ("stiffness", 1e3), "kN/mm": ("stiffness", 1e6),
}

#: accepted units per dimension (for messages and documentation)
UNITS: dict[str, list[str]] = {}
for _name, (_dim, _f) in _U.items():
    UNITS.setdefault(_dim, []).append(_name)

# spelling variants folded to the table's keys
_UNIT_SYNONYMS = {
    "n": "N", "newton": "N", "newtons": "N", "kn": "kN", "lb": "lbf", "lbs": "lbf", "kgf": "kg",
    "nm": "N*m", "n*m": "N*m", "n.m": "N*m", "n m": "N*m", "n-m": "N*m", "knm": "kNm",
    "degree": "deg", "degrees": "deg", "°": "deg", "radian": "rad", "radians": "rad",
    "meter": "m", "metre": "m", "meters": "m", "metres": "m", "inch": "in", "inches": "in", "feet": "ft",
    "pa": "Pa", "kpa": "kPa", "mpa": "MPa", "kph": "kph", "kmh": "km/h", "km/hr": "km/h", "ms": "ms",
    "m/s": "m/s", "mps": "m/s", "m2": "m2", "m^2": "m2", "cm^2": "cm2", "mm^2": "mm2", "in^2": "in2",
    "percent": "%", "": "-", "none": "-", "ratio": "-", "sec": "s", "n/mm": "N/mm", "n/m": "N/m",
    "kn/m": "kN/m", "kn/mm": "kN/mm",
    # the ordinal indicator U+00BA and the ring above U+02DA, typed for a degree on many keyboards
    "º": "deg", "˚": "deg", "deg.": "deg",
    # decanewton (10 N), common on European rigs and load indices
    "dan": "daN", "decanewton": "daN", "decanewtons": "daN", "danm": "daN*m", "dan*m": "daN*m",
    "dan.m": "daN*m", "dan m": "daN*m", "dan-m": "daN*m",
    # US customary spellings of FSAE TTC files
    "ft-lb": "lbf*ft", "lb-ft": "lbf*ft", "ft.lb": "lbf*ft", "ft*lb": "lbf*ft", "lbf-ft": "lbf*ft",
    "ft-lbf": "lbf*ft", "lb*ft": "lbf*ft", "km/hour": "km/h", "mi/h": "mph",
}

#: foreign channel names -> canonical names (case-insensitive)
ALIASES: dict[str, str] = {
    # FSAE TTC
    "sa": "slip_angle", "ia": "camber", "fz": "fz", "fy": "fy", "fx": "fx", "mz": "mz", "mx": "mx",
    "p": "pressure", "v": "speed", "sl": "slip_ratio", "et": "time", "rl": "loaded_radius", "re": "rolling_radius",
    # TYDEX
    "slipangl": "slip_angle", "inclangl": "camber", "fzw": "fz", "fyw": "fy", "mzw": "mz", "mxw": "mx",
    "inflpres": "pressure", "longvel": "speed", "longslip": "slip_ratio", "runtime": "time", "fxw": "fx",
    # common spellings
    "alpha": "slip_angle", "slip angle": "slip_angle", "slipangle": "slip_angle", "sa_deg": "slip_angle",
    "kappa": "slip_ratio", "slip": "slip_ratio", "sr": "slip_ratio", "gamma": "camber", "inclination": "camber",
    "ia_deg": "camber", "fz_n": "fz", "vertical_load": "fz", "normal_load": "fz",
    "dy": "lateral_displacement", "lateral displacement": "lateral_displacement",
    "deflection": "vertical_displacement", "contact_length": "length", "contact_width": "width",
    "contact_area": "area", "tw": "treadwear", "utqg": "treadwear",
}

def _split_header(header: str) -> tuple[str, str | None] | None:
    """``"name [unit]"`` -> (name, unit); ``"name"`` -> (name, None); None if the brackets are malformed.

    Linear in the length of the header: plain string scans, no regular
    expression (a backtracking pattern took minutes on a header cell holding
    a long run of spaces).
    """
    s = header.strip()
    if s.endswith("]"):
        i = s.rfind("[")
        if i < 0:
            return None
        name, unit = s[:i], s[i + 1:-1]
        if "[" in unit or "]" in unit or "[" in name or "]" in name:
            return None
        return name.strip(), unit
    if "[" in s or "]" in s:
        return None
    return s, None


def canonical_unit(unit: str) -> str:
    """Return the table spelling of ``unit`` or raise :class:`UnitError`."""
    u = unit.strip()
    if u in _U:
        return u
    low = u.lower()
    if low in _UNIT_SYNONYMS:
        return _UNIT_SYNONYMS[low]
    for key in _U:
        if key.lower() == low:
            return key
    raise UnitError(f"unknown unit [{unit}]; accepted: " + ", ".join(f"[{k}]" for k in _U) + close_matches(u, _U))


def dimension_of(unit: str) -> str:
    """Dimension (``force``, ``angle``, ...) of a unit."""
    return _U[canonical_unit(unit)][0]


def parse_header(header: str) -> tuple[str, str | None]:
    """Split ``"fz [kN]"`` into the canonical name and the unit (``None`` if absent).

    Foreign channel names are mapped through :data:`ALIASES`; an unknown name is
    returned unchanged (readers decide whether it matters).
    """
    m = _split_header(str(header))
    if m is None:
        return str(header).strip(), None
    name, unit = m
    key = " ".join(name.lower().split())
    name = ALIASES.get(key, key.replace(" ", "_"))
    return name, (unit.strip() if unit is not None else None)


def check_unit(name: str, unit: str) -> str:
    """Check that ``unit`` measures the quantity ``name``; return its table spelling."""
    u = canonical_unit(unit)
    q = GLOSSARY.get(name)
    if q is None:
        return u
    dim = _U[u][0]
    ok = {q.dimension}
    if q.dimension == "ratio":
        ok |= {"ratio"}
    if q.dimension == "count":
        ok |= {"count", "ratio"}
    if q.dimension == "rate":
        ok |= {"per_distance"}  # the readers turn it into a rate with the speed column, or refuse
    if dim not in ok:
        raise UnitError(
            f"unit [{unit}] is a {dim}, but {name!r} is a {q.dimension}; accepted: "
            + ", ".join(f"[{k}]" for k in UNITS[q.dimension])
        )
    return u


def to_si(values, unit: str):
    """Convert ``values`` in ``unit`` to SI (``load [kg]`` -> N via g = 9.80665)."""
    return values * _U[canonical_unit(unit)][1]


def from_si(values, unit: str):
    """Convert SI ``values`` to ``unit`` (for display and file writing)."""
    return values / _U[canonical_unit(unit)][1]
