"""Tyre size designations and the design data a simulator needs that a rig test does not give.

:func:`parse_size` reads ISO metric sizes (``385/65R22.5``, ``205/55 R16 91V``,
``P215/60R16``, ``LT265/75R16``, ``205/55ZR16``) and flotation sizes
(``37x12.5R16.5``, ``37X12.50R16.5LT``) into section width, aspect ratio, rim
diameter and unloaded radius.

:func:`design_estimates` fills what Chrono's ``Pac89Tire`` JSON and an Adams
``.tir`` require but tyrefit cannot measure from force data alone -- mass,
inertia, vertical damping, and (without a vertical or static test) the
vertical and lateral stiffness -- with documented rules of thumb.  Every
value it returns comes with a sentence saying how it was estimated, which the
writers put in the file's header (``.tir``) or its ``"Notes"`` (JSON).  They
are estimates, good to tens of percent, for a simulator to run, not
measurements:

* **mass** m = 0.015 x rated load / g.  Tyre mass is close to 1.5 % of the
  load the tyre is rated for across sizes: 205/55R16 91 (615 kg) about 9 kg,
  385/65R22.5 160 (4500 kg) about 68 kg (manufacturers' data sheets).
  Without a rated load: 15 kg/m^2 of outer surface (two sidewall annuli and
  the tread band).
* **inertia** (Chrono's [Ixx, Iyy, Izz], y the spin axis): the tread band
  (its share of the surface area of the mass) as a thin ring at the unloaded
  radius R and the sidewalls as annuli between the rim radius r and R:
  Iyy = m_t R^2 + m_s (R^2 + r^2)/2, Ixx = Izz = Iyy/2 + m w^2/12.  For
  Chrono's HMMWV tyre (37.6 kg, R 0.464 m, r 0.2096 m, w 0.318 m) this gives
  Iyy = 6.36 kg m^2 against the file's 6.69.
* **vertical damping** c = 2 zeta sqrt(k m) with zeta = 0.5 on the tyre's own
  mass: Chrono's HMMWV Pac89 JSON (k = 326332 N/m, m = 37.6 kg) has
  c = 3484 N s/m, this rule 3503.
* **vertical stiffness** (only without a vertical test) k = F / (0.15 H): a
  15 % deflection of the section height H at the rated load F.
* **lateral stiffness** (only without a static lateral test) 0.8 x vertical
  stiffness, the ratio of Chrono's HMMWV Pac89 tyre (261065 / 326332 N/m).
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, replace

import numpy as np

from ..errors import DataError, option
from ..models import mf61

__all__ = ["TyreSize", "parse_size", "size_and_rated_load", "design_estimates", "with_design", "G0", "loaded_radius_law",
           "complete_mf_design", "MF_DESIGN_SECTIONS"]

G0 = 9.80665
_INCH = 0.0254

# One pass over the designation, no nested repetition (linear time)
_METRIC = re.compile(r"(?:P|LT|T|ST|C)?(\d{3})\s?/\s?(\d{2,3})\s?(?:Z?R|-|D|B)\s?(\d{2}(?:\.\d)?)", re.I)
_FLOTATION = re.compile(r"(\d{2}(?:\.\d{1,2})?)\s?X\s?(\d{1,2}(?:\.\d{1,2})?)\s?(?:Z?R|-|D|B)\s?(\d{2}(?:\.\d)?)",
                        re.I)


@dataclass(frozen=True)
class TyreSize:
    """A tyre size.

    Attributes
    ----------
    text : str
        the designation as given.
    width : float
        nominal section width [m].
    aspect_ratio : float
        section height / width [-].
    rim_diameter : float
        [m].
    """

    text: str
    width: float
    aspect_ratio: float
    rim_diameter: float

    @property
    def section_height(self) -> float:
        """[m]"""
        return self.width * self.aspect_ratio

    @property
    def rim_radius(self) -> float:
        """[m]"""
        return 0.5 * self.rim_diameter

    @property
    def unloaded_radius(self) -> float:
        """Rim radius plus section height [m] (ISO 4000-1 / ETRTO design diameter / 2)."""
        return self.rim_radius + self.section_height


def parse_size(text: str) -> TyreSize:
    """Parse an ISO metric (``385/65R22.5``) or flotation (``37x12.5R16.5``) size.

    Raises
    ------
    DataError
        not a size, or numbers outside any tyre made (width 100-1000 mm,
        aspect 20-120 %, rim 8-63 in).
    """
    s = str(text).strip()
    if len(s) > 60:
        raise DataError(f"{option('size', repr(s[:40]))}...: not a tyre size; expected e.g. 385/65R22.5 or 205/55R16")
    m = _METRIC.fullmatch(s.split()[0]) if s else None
    if m is None and s:
        m = _METRIC.match(s)
    if m is not None:
        width, aspect, rim = float(m.group(1)) * 1e-3, float(m.group(2)) / 100.0, float(m.group(3)) * _INCH
    else:
        f = _FLOTATION.match(s) if s else None
        if f is None:
            raise DataError(f"{option('size', repr(s))}: not a tyre size; expected an ISO metric size such as 385/65R22.5 or "
                            "205/55R16, or a flotation size such as 37x12.5R16.5")
        diameter, width, rim = (float(f.group(i)) * _INCH for i in (1, 2, 3))
        if not diameter > rim:
            raise DataError(f"{option('size', repr(s))}: the overall diameter is not larger than the rim")
        aspect = 0.5 * (diameter - rim) / width
    if not (0.1 <= width <= 1.0 and 0.2 <= aspect <= 1.2 and 8 * _INCH <= rim <= 63 * _INCH):
        raise DataError(f"{option('size', repr(s))}: width {width * 1e3:.0f} mm, aspect ratio {aspect * 100:.0f} %, rim "
                        f"{rim / _INCH:g} in is not a tyre; expected e.g. 385/65R22.5")
    return TyreSize(s, width, aspect, rim)


def size_and_rated_load(size: str | None, rated_load: float | None) -> TyreSize | None:
    """``--size`` parsed (None when not given) after ``--rated-load`` is checked to be finite and > 0.

    The one check of the two flags for every ``fit`` model (PAC89 and Magic Formula).

    Raises
    ------
    DataError
        the rated load is not a positive, finite force, or the size is not a tyre size (:func:`parse_size`).
    """
    if rated_load is not None and not (math.isfinite(rated_load) and rated_load > 0):
        raise DataError(f"{option('rated_load', repr(rated_load))}: the rated load must be a positive, finite force in N")
    return parse_size(size) if size else None


def design_estimates(*, unloaded_radius: float, width: float, rim_radius: float | None = None,
                     rated_load: float | None = None, vertical_stiffness: float | None = None,
                     lateral_stiffness: float | None = None, mass: float | None = None,
                     aspect_ratio: float | None = None,
                     vertical_damping: float | None = None, inertia=None) -> dict[str, tuple[object, str]]:
    """Estimates of the design values not given (see the module notes), each with its sentence.

    Parameters are SI; a value given is kept and not estimated.  Returns
    ``{name: (value, note)}`` for ``mass`` [kg], ``inertia`` [kg m^2] x 3,
    ``vertical_stiffness`` [N/m], ``lateral_stiffness`` [N/m],
    ``vertical_damping`` [N s/m] -- only those that were missing.  Without a
    stiffness and without a rated load, the stiffnesses and the damping cannot
    be estimated: mass and inertia are returned with a ``not_estimated`` entry
    ``(None, sentence)``.
    """
    R, w = float(unloaded_radius), float(width)
    r = rim_radius if rim_radius else (R - w * aspect_ratio if aspect_ratio else 0.55 * R)
    r = min(max(r, 0.2 * R), 0.95 * R)
    out: dict[str, tuple[object, str]] = {}
    side, tread = 2 * math.pi * (R**2 - r**2), 2 * math.pi * R * w
    if mass is None:
        if rated_load:
            mass = 0.015 * rated_load / G0
            out["mass"] = (mass, f"mass {mass:.3g} kg ESTIMATED as 1.5 % of the rated load {rated_load:.0f} N / g")
        else:
            mass = 15.0 * (side + tread)
            out["mass"] = (mass, f"mass {mass:.3g} kg ESTIMATED as 15 kg/m2 of outer surface (no rated load given)")
    share = tread / (side + tread)
    iyy = mass * (share * R**2 + (1 - share) * 0.5 * (R**2 + r**2))
    ixx = 0.5 * iyy + mass * w**2 / 12.0
    if inertia is None:
        out["inertia"] = ((ixx, iyy, ixx), f"inertia [Ixx, Iyy, Izz] = [{ixx:.3g}, {iyy:.3g}, {ixx:.3g}] kg m2 "
                                           f"ESTIMATED: tread ring at R = {R:.3f} m, sidewall annuli from r = {r:.3f} m")
    k = vertical_stiffness
    if k is None:
        if not rated_load:  # mass and inertia stand; stiffness and damping need a load or a vertical test
            out["not_estimated"] = (None, "VERTICAL_STIFFNESS, LATERAL_STIFFNESS, VERTICAL_DAMPING not estimated: "
                                          "give a vertical test (vertical=) or the rated load (rated_load=)")
            return out
        height = max(R - r, 1e-3)
        k = rated_load / (0.15 * height)
        out["vertical_stiffness"] = (k, f"VERTICAL_STIFFNESS {k / 1e3:.4g} N/mm ESTIMATED as 15 % deflection of the "
                                        f"section height {height * 1e3:.0f} mm at the rated load {rated_load:.0f} N")
    if lateral_stiffness is None:
        out["lateral_stiffness"] = (0.8 * k, f"LATERAL_STIFFNESS {0.8 * k / 1e3:.4g} N/mm ESTIMATED as 0.8 x vertical "
                                             "stiffness (ratio of Chrono's HMMWV Pac89 tyre)")
    if vertical_damping is not None:
        return out
    c = 2 * 0.5 * math.sqrt(k * mass)
    out["vertical_damping"] = (c, f"VERTICAL_DAMPING {c:.4g} N s/m ESTIMATED as 2 x 0.5 x sqrt(k m) (zeta 0.5 on "
                                  "the tyre mass; Chrono's HMMWV tyre: 3484 against 3503 by this rule)")
    return out


def with_design(tyre, size: TyreSize | None = None, rated_load: float | None = None):
    """A copy of a :class:`~tyrefit.tyres.pac89.Pac89Tyre` with what Adams and Chrono require, and the notes.

    The size sets UNLOADED_RADIUS, WIDTH and ASPECT_RATIO (replacing none that
    the data gave); ``rated_load`` sets FNOMIN.  Then :func:`design_estimates`
    fills mass, inertia, vertical damping and any stiffness still missing;
    each estimate is said in a header line of the new tyre.  Without a radius
    and width (no size) nothing is estimated, and the notes say what is missing.
    ``tyre`` itself is not changed.

    Returns
    -------
    (tyre, notes)
        the completed tyre and the notes, one sentence each.
    """
    notes: list[str] = []
    design: dict[str, object] = {"header": list(tyre.header)}  # the copy shares no list with ``tyre``
    if size is not None:
        for attr, value in (("unloaded_radius", size.unloaded_radius), ("width", size.width),
                            ("aspect_ratio", size.aspect_ratio)):
            if getattr(tyre, attr) is None:
                design[attr] = value
        notes.append(f"size {size.text}: unloaded radius {size.unloaded_radius * 1e3:.1f} mm (rim radius + section "
                     f"height), width {size.width * 1e3:.0f} mm, aspect ratio {size.aspect_ratio:.3g}")
    if rated_load is not None:
        design["fnomin"] = float(rated_load)

    def now(attr):
        return design.get(attr, getattr(tyre, attr))

    if now("unloaded_radius") is None or now("width") is None:
        notes.append("no tyre size (--size): UNLOADED_RADIUS, WIDTH, ASPECT_RATIO, mass, inertia and vertical "
                     "damping are not written; Adams and Chrono need them")
        return replace(tyre, **design), notes
    try:
        est = design_estimates(unloaded_radius=now("unloaded_radius"), width=now("width"),
                               rim_radius=size.rim_radius if size is not None else None, rated_load=now("fnomin"),
                               vertical_stiffness=now("vertical_stiffness"),
                               lateral_stiffness=now("lateral_stiffness"), mass=now("mass"),
                               aspect_ratio=now("aspect_ratio"), vertical_damping=now("vertical_damping"),
                               inertia=now("inertia"))
    except DataError as exc:
        notes.append(f"not estimated: {exc}")
        return replace(tyre, **design), notes
    for key, (value, note) in est.items():
        if value is not None:
            design[key] = value
        notes.append(note)
    design["header"] += [n for n in notes if n not in tyre.header]
    return replace(tyre, **design), notes


#: the sections whose values a force fit does not give (their keys in :data:`tyrefit.models.mf61.COEFFICIENTS`)
MF_DESIGN_SECTIONS = ("DIMENSION", "OPERATING_CONDITIONS", "INERTIA", "VERTICAL", "STRUCTURAL", "CONTACT_PATCH")


def _radius_line(f: np.ndarray, r: np.ndarray) -> dict | None:
    """R_l = R0 - Fz / c_z by least squares, when the line is credible (else None)."""
    if f.size < 50 or not np.percentile(f, 95) > 1.5 * np.percentile(f, 5):
        return None
    slope, r0 = np.polyfit(f, r, 1)
    if not (slope < 0 and 0.1 < r0 < 2.0 and r0 > r.max()):
        return None
    return {"UNLOADED_RADIUS": float(r0), "VERTICAL_STIFFNESS": float(-1.0 / slope), "n": int(f.size),
            "fz": (float(f.min()), float(f.max())), "rl": (float(r.min()), float(r.max()))}


#: records whose laws differ by more than this in R0 (relative) or 25 % in c_z are said to disagree
RADIUS_AGREE = 0.01


def loaded_radius_law(datasets) -> dict:
    """UNLOADED_RADIUS [m] and VERTICAL_STIFFNESS [N/m] from a loaded-radius channel (empty dict if none).

    Least squares R_l = R0 - Fz / c_z over the samples with Fz > 0 and a finite
    loaded radius (MF 6.1's vertical model with Q_FZ2 = 0: Fz = c_z (R0 - R_l),
    Pacejka (2012) (A3.4)), per record.  A line is used only when credible: at
    least 50 samples, loads spanning a factor of 1.5, c_z > 0, and 0.1 m < R0 <
    2 m with R0 above every loaded radius seen.  Records whose lines agree
    (R0 within :data:`RADIUS_AGREE`, c_z within 25 %) are pooled; records that
    disagree (a rig's radius channel is often offset between test set-ups: TTC
    cornering 0.186-0.206 m against drive/brake 0.210-0.229 m of the same tyre)
    are not averaged: the free-rolling record's law is used (the cornering
    record, slip angle at zero slip ratio: its radius is the tyre's free-rolling
    loaded radius), and ``note`` says so.  ``note`` also names records whose
    radius line is not credible.
    """
    per = []
    for ds in datasets:
        df = ds.df
        if "loaded_radius" not in df.columns or "fz" not in df.columns:
            continue
        f, r = df["fz"].to_numpy(float), df["loaded_radius"].to_numpy(float)
        ok = np.isfinite(f) & np.isfinite(r) & (f > 0) & (r > 0)
        name = os.path.basename(str(getattr(ds, "source", "") or "record"))
        per.append((name, getattr(ds, "kind", ""), f[ok], r[ok], _radius_line(f[ok], r[ok])))
    if not per:
        return {}
    good = [x for x in per if x[4] is not None]
    notes = [f"{n}: its loaded-radius channel gives no credible R_l = R0 - Fz/c_z line (not used)"
             for n, _, _, _, law in per if law is None]
    if not good:
        return {"note": "; ".join(notes)} if notes else {}
    laws = [x[4] for x in good]
    r0s = np.array([w["UNLOADED_RADIUS"] for w in laws])
    czs = np.array([w["VERTICAL_STIFFNESS"] for w in laws])
    agree = np.ptp(r0s) <= RADIUS_AGREE * r0s.mean() and np.ptp(czs) <= 0.25 * czs.mean()
    if agree:
        out = _radius_line(np.concatenate([x[2] for x in good]), np.concatenate([x[3] for x in good]))
        out = out or laws[0]
        out["source"] = ", ".join(x[0] for x in good)
    else:
        free = [x for x in good if x[1] == "slip_angle"] or good
        pick = free[0]
        out = dict(pick[4], source=pick[0])
        said = "; ".join(f"{n}: R0 {w['UNLOADED_RADIUS'] * 1e3:.1f} mm, c_z {w['VERTICAL_STIFFNESS'] / 1e3:.0f} N/mm "
                         f"(loaded radius {w['rl'][0] * 1e3:.1f}-{w['rl'][1] * 1e3:.1f} mm)"
                         for n, _, _, _, w in good)
        notes.insert(0, f"the records' loaded radii disagree ({said}); used {pick[0]}"
                        + (" (free-rolling: slip-angle sweeps at zero slip ratio)" if pick[1] == "slip_angle" else ""))
    if notes:
        out["note"] = "; ".join(notes)
    return out


def complete_mf_design(p: dict, *, size: TyreSize | None = None, measured: dict | None = None,
                       rated_load_given: bool = False, pressure_from_data: bool = False) -> tuple[list[str], list[str]]:
    """Fill the design data of a Magic Formula parameter set ``p`` (in place); say where each value came from.

    Four origins, in order: the data (``measured`` from :func:`loaded_radius_law`:
    UNLOADED_RADIUS, VERTICAL_STIFFNESS; NOMPRES / INFLPRES when
    ``pressure_from_data``), the size (UNLOADED_RADIUS when the data give none,
    WIDTH, ASPECT_RATIO, RIM_RADIUS) and the rated load (FNOMIN, already in
    ``p``), :func:`design_estimates` from the size (MASS, IXX, IYY,
    VERTICAL_STIFFNESS, LATERAL_STIFFNESS, VERTICAL_DAMPING), and otherwise
    the 205/60R15 template of :func:`tyrefit.models.mf61.neutral`, each listed
    as a PLACEHOLDER.

    Returns
    -------
    lines : list of str
        header lines (``.tir`` ``$`` comments).
    placeholders : list of str
        the keys still at template values.
    """
    measured = measured or {}
    template = mf61.neutral()
    origin: dict[str, str] = {}
    lines: list[str] = []
    if "UNLOADED_RADIUS" in measured:
        p["UNLOADED_RADIUS"] = measured["UNLOADED_RADIUS"]
        p["VERTICAL_STIFFNESS"] = measured["VERTICAL_STIFFNESS"]
        origin["UNLOADED_RADIUS"] = origin["VERTICAL_STIFFNESS"] = "data"
        lines.append(f"UNLOADED_RADIUS {p['UNLOADED_RADIUS']:.4f} m and VERTICAL_STIFFNESS "
                     f"{p['VERTICAL_STIFFNESS'] / 1e3:.4g} N/mm FROM THE DATA: loaded radius = R0 - Fz/cz fitted to "
                     f"{measured['n']} samples, Fz {measured['fz'][0]:.0f}-{measured['fz'][1]:.0f} N"
                     + (f" ({measured['source']})" if measured.get("source") else ""))
    if measured.get("note"):
        lines.append(f"loaded radius: {measured['note']}")
    if pressure_from_data:
        origin["NOMPRES"] = origin["INFLPRES"] = "data"
    if size is not None:
        sz = {"WIDTH": size.width, "ASPECT_RATIO": size.aspect_ratio, "RIM_RADIUS": size.rim_radius}
        if "UNLOADED_RADIUS" not in origin:
            sz["UNLOADED_RADIUS"] = size.unloaded_radius
        for k, v in sz.items():
            p[k] = float(v)
            origin[k] = "size"
        lines.append(f"size {size.text}: " + ", ".join(f"{k} {v:.4g}" for k, v in sz.items())
                     + " (m; radius = rim radius + section height)")
    rated = rated_load_given
    if rated:
        origin["FNOMIN"] = "rated load"
        lines.append(f"FNOMIN {p['FNOMIN']:.0f} N = the rated load (--rated-load)")
    else:
        origin["FNOMIN"] = "data"
    if size is not None:
        try:
            est = design_estimates(unloaded_radius=p["UNLOADED_RADIUS"], width=size.width,
                                   rim_radius=size.rim_radius, rated_load=p["FNOMIN"],
                                   vertical_stiffness=p["VERTICAL_STIFFNESS"] if "UNLOADED_RADIUS" in measured else None,
                                   aspect_ratio=size.aspect_ratio)
        except DataError as exc:  # pragma: no cover - rated_load is FNOMIN > 0
            est = {}
            lines.append(f"not estimated: {exc}")
        keys = {"mass": ("MASS",), "inertia": ("IXX", "IYY"), "vertical_stiffness": ("VERTICAL_STIFFNESS",),
                "lateral_stiffness": ("LATERAL_STIFFNESS",), "vertical_damping": ("VERTICAL_DAMPING",)}
        for name, (value, note) in est.items():
            if value is None:  # not_estimated: said, nothing set
                lines.append(note)
                continue
            vals = value[:2] if name == "inertia" else (value,)
            for k, v in zip(keys[name], vals):
                p[k] = float(v)
                origin[k] = "estimate"
            lines.append(note + ("" if rated else " (FNOMIN from the data as the rated load)"))
    placeholders: list[str] = []
    for sec in MF_DESIGN_SECTIONS:
        keys = [k for k in mf61.COEFFICIENTS.get(sec, []) if k not in origin and k in p]
        if not keys:
            continue
        placeholders += keys
        shown = ", ".join(f"{k} {p[k]:g}" for k in keys)
        lines.append(f"PLACEHOLDER [{sec}] (template values of a 205/60R15, not from these data): {shown}")
    if "UNLOADED_RADIUS" in placeholders:
        lines.append(f"the Mz, Mx and My coefficients were fitted with UNLOADED_RADIUS {p['UNLOADED_RADIUS']:g} m "
                     "(a placeholder); keep them with it, or refit with --size")
    if "NOMPRES" in placeholders:
        lines.append(f"no pressure column: NOMPRES = INFLPRES {p['NOMPRES'] / 1e3:g} kPa is a placeholder; the "
                     "pressure terms are not fitted (PPX, PPY, PPZ = 0), so the forces do not depend on it")
    return lines, placeholders
