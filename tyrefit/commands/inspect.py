"""``tyrefit inspect FILE [--convention iso|sae] [--json OUT.json]``: say what a file holds.

Data files (CSV with unit headers, TYDEX ``.tdx``, FSAE TTC ``.dat``) are read
with :func:`tyrefit.io.readers.read_data`, so inspect shows exactly what every
other command will see: the kind of test, rows, sweeps, the conditions found,
the sign convention read, each column with the unit it was read in, and for
continuous records how they were segmented.  Tyre files (``.tir`` of any
MF/PAC format, Chrono PAC89 ``.json``) give their format, number of model
parameters, sections and dimensions.

JSON keys (``shared/DESIGN.md``): data ``{"kind": "data", "rows", "sweeps",
"conditions": {"fz": [N], "camber": [deg], "pressure": [Pa], "speed": [m/s]},
"convention", "columns", ...}``; tyre ``{"kind": "tyre", "format",
"parameters", ...}``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..errors import FormatError, ModelError
from ..io.chrono_json import read_chrono_json
from ..io.outputs import check_output, write_text
from ..io.plausibility import mirrored_findings
from ..io.readers import (KINDS, Dataset, condition_levels, lateral_slope, plausibility_problems, read_data,
                          sniff_format)
from ..io.tir import read_property_file, read_tyre
from ..tyres.pac89 import CHRONO_LIMITS

__all__ = ["run", "inspect_file", "inspect_data", "inspect_tyre", "format_summary"]


def inspect_file(path: str | Path, convention: str = "iso", allow_mirrored: bool = False) -> dict[str, Any]:
    """Summary dict of a data or tyre file (the ``--json`` document)."""
    p = Path(path)
    fmt = sniff_format(p)
    if fmt in ("tir", "chrono_json"):
        return inspect_tyre(p, fmt)
    return inspect_data(read_data(p, convention=convention, checks=False), allow_mirrored=allow_mirrored)


def inspect_data(ds: Dataset, allow_mirrored: bool = False) -> dict[str, Any]:
    """Summary dict of a read :class:`Dataset`."""
    df = ds.df
    out: dict[str, Any] = {
        "kind": "data",
        "file": ds.source,
        "format": ds.meta.get("format"),
        "data_kind": ds.kind,
        "rows": int(len(df)),
        "sweeps": int(ds.n_runs),
        "conditions": condition_levels(ds),
        "convention": ds.convention,
        "flipped": list(ds.meta.get("flipped", [])),
        "columns": ds.meta.get("columns", {}),
        "runs": ds.meta.get("runs"),
    }
    ranges = {}
    for c in df.columns:
        if c != "run" and pd.api.types.is_numeric_dtype(df[c]) and len(df):
            ranges[c] = [float(np.nanmin(df[c])), float(np.nanmax(df[c]))]
    out["ranges"] = ranges
    # the sign check needs slip-angle sweeps: in drive/brake sweeps the slip angle is held, and the slope of
    # Fy against its noise means nothing
    slope = lateral_slope(ds) if ds.kind == "slip_angle" else None
    if slope is not None:
        out["cornering_slope"] = slope
        out["sign"] = ("positive slip angle gives negative lateral force (ISO-W)" if slope < 0 else
                       "positive slip angle gives POSITIVE lateral force: not ISO-W; " +
                       ("is the file in another sign convention (--convention sae)?" if ds.convention != "sae" else
                        "the file was read as SAE (--convention sae) - is it in fact ISO-W already?"))
    for key in ("info", "header", "constants", "segmentation", "phase", "dropped"):
        if key in ds.meta:
            out[key] = ds.meta[key]
    out["problems"] = plausibility_problems(ds)  # what fit/diagnose would refuse, said instead of refused

    mirrored = [f.message for f in mirrored_findings(ds)]  # fit refuses these unless --allow-mirrored
    out["mirrored"] = mirrored
    if not allow_mirrored:
        out["problems"] = out["problems"] + [m + " (fit refuses this unless --allow-mirrored)" for m in mirrored]
    return out


def _dimensions(pf) -> dict[str, float]:
    L = pf.unit_factor("LENGTH")
    dims = {}
    for key in ("UNLOADED_RADIUS", "WIDTH", "ASPECT_RATIO", "RIM_RADIUS", "RIM_WIDTH"):
        v = pf.get(key, section="DIMENSION")
        if isinstance(v, (int, float)):
            dims[key.lower()] = float(v) * (1.0 if key == "ASPECT_RATIO" else L)
    return dims


#: said of every PAC89 tyre (Chrono's ChPac89Tire limits; see :class:`tyrefit.tyres.pac89.Pac89Tyre`)
CHRONO_NOTE = (f"Chrono's ChPac89Tire clamps camber to +/-{CHRONO_LIMITS['camber_deg']:g} deg (default m_gamma_limit) "
               f"and slip ratio to +/-{CHRONO_LIMITS['slip_ratio']:g}, adds Fx*Fy/k_lat to Mz, sets Mx = -Fz*Fy/k_lat "
               "(k_lat: lateral stiffness) and scales Fx, Fy, Mz by the road's mu/0.8 (ChPac89Tire.cpp, Advance); "
               "tyrefit evaluates PAC89 without those clamps and terms (it shares only the clamp of the shifted slip "
               f"angle to +/-{CHRONO_LIMITS['shifted_slip_angle_deg']:g} deg), so the two agree only inside the clamps, "
               "on a mu = 0.8 road and where Fx*Fy/k_lat is small")


def _tyre_model(tyre) -> dict[str, Any]:
    """Family, completeness and checks of a read :class:`~tyrefit.tyres.base.Tyre`."""
    out: dict[str, Any] = {"family": tyre.family}
    out["missing"] = list(getattr(tyre, "missing", []) or [])
    out["parts"] = [p for p, ok in (("longitudinal", tyre.has_longitudinal), ("lateral", tyre.has_lateral),
                                    ("aligning", tyre.has_aligning)) if ok]
    out["nominal"] = tyre.nominal
    out["validity"] = {k: list(v) for k, v in tyre.validity().items()}
    out["declared_ranges"] = sorted(getattr(tyre, "ranges", {}) or {})
    out["problems"] = tyre.check() if not out["missing"] else [f"required coefficient {k} is missing"
                                                               for k in out["missing"]]
    out["warnings"] = tyre.warnings() if not out["missing"] else []
    out["combined_slip"] = bool(tyre.combined)
    if getattr(tyre, "use_mode", None) is not None:  # MF files: which parts Adams computes (tyrefit.tyres.mf)
        out["use_mode"] = tyre.use_mode
    if getattr(tyre, "not_fitted", None):
        out["not_fitted"] = sorted(tyre.not_fitted)
    if tyre.family == "PAC89":
        out["chrono_limits"] = CHRONO_NOTE
    return out


def inspect_tyre(p: Path, fmt: str | None = None) -> dict[str, Any]:
    """Summary dict of a tyre property file (``.tir``) or a Chrono tyre ``.json``.

    ``format`` is as the file declares it (``PROPERTY_FILE_FORMAT``, or
    ``FITTYP``); ``family`` is the model tyrefit evaluates it as ('PAC89',
    'MF52', 'MF61'); ``missing`` lists required coefficients the file does not
    give, ``problems`` what :meth:`~tyrefit.tyres.base.Tyre.check` finds over
    the declared range and ``warnings`` what is questionable but evaluable.
    ``parameters`` counts the model coefficients: numeric entries of the
    ``[*_COEFFICIENTS]`` sections other than ``[SCALING_COEFFICIENTS]`` (43 for a
    full PAC89 file: a0-a13, b0-b10, c0-c17); ``values`` counts every numeric
    entry of the file.
    """
    fmt = fmt or sniff_format(p)
    if fmt == "tir":
        pf = read_property_file(p)
        coef = {s: sum(isinstance(v, (int, float)) for v in sec.values()) for s, sec in pf.sections.items()
                if s.endswith("_COEFFICIENTS") and s != "SCALING_COEFFICIENTS"}
        out = {"kind": "tyre", "file": str(p), "container": "tir", "format": pf.format or "unknown",
               "parameters": int(sum(coef.values())), "values": int(pf.n_parameters),
               "coefficient_sections": coef, "sections": list(pf.sections), "tables": list(pf.tables),
               "dimensions": _dimensions(pf)}
        units = pf.sections.get("UNITS", {})
        if units:
            out["units"] = {k.lower(): str(v) for k, v in units.items()}
        fnomin = pf.number("FNOMIN")
        if fnomin is not None:
            out["fnomin"] = fnomin * pf.unit_factor("FORCE")
        name = pf.get("NAME") or pf.get("TYRESIDE")
        if name is not None:
            out["name"] = str(name)
        out.update(_tyre_model(read_tyre(p)))
        return out

    text = p.read_text(encoding="utf-8-sig", errors="replace")
    template = None
    for line in text.splitlines():
        if '"Template"' in line:
            template = line.split(":", 1)[1].strip().strip(",").strip().strip('"')
            break
    tyre = read_chrono_json(p)
    declared = {"Pac89Tire": "PAC89", "Pac02Tire": "PAC2002"}.get(template or "", template or "PAC89")
    dims = {k: v for k, v in (("unloaded_radius", tyre.unloaded_radius), ("width", tyre.width)) if v is not None}
    out = {"kind": "tyre", "file": str(p), "container": "chrono_json", "format": declared,
           "template": template, "parameters": len(tyre.coefficients), "name": tyre.name,
           "dimensions": dims}
    for key in ("vertical_stiffness", "lateral_stiffness", "rolling_resistance", "vertical_damping", "mass"):
        v = getattr(tyre, key)
        if v is not None:
            out[key] = v
    if tyre.vertical_curve:
        out["vertical_curve_points"] = len(tyre.vertical_curve)
    out.update(_tyre_model(tyre))
    return out


# --------------------------------------------------------------------------- text

def _num(x: float) -> str:
    return f"{x:.4g}"


def _levels_text(cond: dict[str, list[float]]) -> str:
    parts = []
    if cond.get("fz"):
        big = max(cond["fz"]) >= 10e3
        parts.append("fz " + ", ".join(_num(v / 1e3 if big else v) for v in cond["fz"]) + (" kN" if big else " N"))
    if cond.get("camber"):
        parts.append("camber " + ", ".join(_num(v) for v in cond["camber"]) + " deg")
    if cond.get("pressure"):
        bar = max(cond["pressure"]) >= 2e5
        parts.append("pressure " + ", ".join(_num(v / 1e5 if bar else v / 1e3) for v in cond["pressure"])
                     + (" bar" if bar else " kPa"))
    if cond.get("speed"):
        parts.append("speed " + ", ".join(_num(v * 3.6) for v in cond["speed"]) + " km/h")
    return "; ".join(parts) or "none recorded"


def format_summary(s: dict[str, Any]) -> str:
    """Short human summary of :func:`inspect_file`'s dict."""
    lines = []
    if s["kind"] == "tyre":
        lines.append(f"{s['file']}: tyre property file ({s['container']}), format {s['format']}, "
                     f"{s['parameters']} model parameters; family {s.get('family', '?')}")
        if s.get("parts"):
            lines.append("model parts: " + ", ".join(s["parts"]) + (" (combined slip)" if s.get("combined_slip")
                                                                     else " (pure slip only)")
                         + (f"; USE_MODE {s['use_mode']}" if "use_mode" in s else "")
                         + (f"; not fitted: {', '.join(s['not_fitted'])}" if s.get("not_fitted") else ""))
        if s.get("sections"):
            lines.append("sections: " + ", ".join(s["sections"]))
        d = s.get("dimensions", {})
        if d:
            lines.append("dimensions: " + ", ".join(
                f"{k} {v:.4g}" if k == "aspect_ratio" else f"{k} {v * 1e3:.4g} mm" for k, v in d.items()))
        if s.get("missing"):
            lines.append("MISSING: " + ", ".join(s["missing"]))
        for prob in s.get("problems", []):
            if not prob.startswith("required coefficient"):  # listed once, under MISSING
                lines.append(f"problem: {prob}")
        for w in s.get("warnings", []):
            lines.append(f"warning: {w}")
        if s.get("chrono_limits"):
            lines.append(f"note: {s['chrono_limits']}")
        return "\n".join(lines)
    fmt = {"csv": "CSV", "tdx": "TYDEX", "ttc": "FSAE TTC"}.get(s.get("format"), s.get("format"))
    conv = s["convention"]
    conv_txt = (f"convention {conv} (converted to ISO-W: {', '.join(s['flipped'])} negated)" if conv == "sae"
                else "convention iso (ISO-W, as read)")
    lines.append(f"{s['file']}: {fmt} data, {s['data_kind']} test ({KINDS[s['data_kind']].split(':')[0]}), "
                 f"{conv_txt}")
    seg = s.get("segmentation")
    total = f" (of {seg['n_samples']} samples)" if seg else ""
    lines.append(f"rows {s['rows']}{total}, sweeps {s['sweeps']}; runs {s.get('runs')}")
    lines.append("conditions: " + _levels_text(s["conditions"]))
    if s["data_kind"] in ("patch", "vertical"):
        for c in ("load", "fz"):
            if c in s.get("ranges", {}):
                lo, hi = s["ranges"][c]
                lines.append(f"{c} swept from {lo / 1e3:.4g} to {hi / 1e3:.4g} kN")
                break
    cols = []
    for c, info in s["columns"].items():
        h = info.get("header", c)
        if info.get("converted") is False:
            cols.append(f"{h} -> {c} (kept as read)")
        elif info.get("si_unit") and info.get("unit"):
            cols.append(f"{h} -> {c} [{info['si_unit']}]")
        else:
            cols.append(f"{h} -> {c}")
    lines.append("columns: " + "; ".join(cols))
    if "sign" in s:
        lines.append(f"sign: dFy/dalpha = {s['cornering_slope'] / 1e3:.4g} kN/rad near zero slip: {s['sign']}")
    if seg:
        lines.append(f"segmentation: {seg['n_sweeps']} sweeps; {seg['method']}")
        if seg["dropped"]:
            lines.append("dropped: " + "; ".join(f"{v} {k}" for k, v in seg["dropped"].items()))
    if "info" in s and s["info"]:
        lines.append(f"info: {s['info']}")
    if s.get("dropped"):
        lines.append("dropped: " + "; ".join(f"{v} {k}" for k, v in s["dropped"].items()))
    for problem in s.get("problems", []):
        lines.append(f"PROBLEM (fit and diagnose refuse this file): {problem}")
    if s.get("mirrored") and not any(m in p for m in s["mirrored"] for p in s.get("problems", [])):
        for m in s["mirrored"]:
            lines.append(f"WARNING (--allow-mirrored): {m}")
    return "\n".join(lines)


def run(args) -> int:
    """Entry point of ``tyrefit inspect``."""
    out = getattr(args, "json", None)
    if out:
        check_output(out, args.force)
        if Path(out).resolve() == Path(args.file).resolve():
            raise FormatError(f"{out}: the --json output is the file being inspected; choose another name")
    summary = inspect_file(args.file, convention=getattr(args, "convention", "iso"),
                           allow_mirrored=bool(getattr(args, "allow_mirrored", False)))
    print(format_summary(summary))
    if summary.get("kind") == "tyre" and summary.get("missing"):
        raise ModelError(f"{args.file}: incomplete {summary['family']} tyre: missing "
                         + ", ".join(summary["missing"]))
    if out:
        write_text(out, json.dumps(_jsonable(summary), indent=2) + "\n", force=args.force)
    return 0


def _jsonable(x):
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, (np.floating, float)):
        v = float(x)
        return v if math.isfinite(v) else None
    if isinstance(x, (np.integer,)):
        return int(x)
    return x
