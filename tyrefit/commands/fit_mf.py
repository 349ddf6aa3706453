"""``tyrefit fit DATA [DATA ...] --model mf61|mf52 --out TYRE.tir``: one Magic Formula tyre from every file.

The records (a cornering and a drive/brake record of the same tyre, say) are
read with the same ``--convention``, gathered and fitted in stages by
:func:`tyrefit.fitting.mf.fit_mf`; the tyre is written as a complete
``FITTYP = 61`` property file (:func:`tyrefit.io.mf_tir.write_mf_tir`) with
the data sources and the RMSE per channel in its header.  ``--effects``
fits diagnose's start model (PCY1, PDY1, PKY1, PKY2, PEY1) and then the
start model plus the MF 6.1 coefficients that carry those effects
(:data:`tyrefit.fitting.mf.EFFECT_COEFFICIENTS`), so the error waterfall of
``tyrefit diagnose`` continues in the exported tyre; both RMSEs are printed.

Design data (:func:`design_data`).  A Magic Formula file carries geometry,
pressure, inertia and stiffness that force data rarely give.  Each written
value has one of four origins, said in the header and on the console:

1. **the data**: NOMPRES = INFLPRES is the middle pressure level of a
   ``pressure`` column; a ``loaded_radius`` channel (TTC's RL) gives
   UNLOADED_RADIUS and VERTICAL_STIFFNESS as the intercept and the inverse
   slope of a straight line R_l = R0 - Fz / c_z over the loaded samples (the
   linear part of MF 6.1's vertical model, Pacejka (2012) (A3.4), with
   Q_FZ2 = 0);
2. **``--size``** (``385/65R22.5``): UNLOADED_RADIUS (when the data give none),
   WIDTH, ASPECT_RATIO, RIM_RADIUS; **``--rated-load``**: FNOMIN;
3. **documented estimates** from the size (:func:`tyrefit.tyres.size.design_estimates`,
   the same rules as the PAC89 and Chrono writers): MASS, IXX, IYY,
   VERTICAL_STIFFNESS, LATERAL_STIFFNESS, VERTICAL_DAMPING, each line marked
   ESTIMATED;
4. otherwise **placeholders**: the 205/60R15 template of
   :func:`tyrefit.models.mf61.neutral`, listed per section under
   ``PLACEHOLDER`` in the header and summarised on the console -- never
   written silently.  UNLOADED_RADIUS enters the Mz, Mx and My equations, so
   the fitted aligning and moment coefficients belong with the radius written
   beside them.
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import DataError

__all__ = ["run_mf", "fit_mf_files"]

_PAC89_ONLY = (("patch", "--patch (static-rig tests)"), ("rig", "--rig"), ("vertical", "--vertical"),
               ("by", "--by"), ("json", "--json (Chrono's PAC89 JSON)"))


def fit_mf_files(args, datas):
    """Read ``datas`` and fit; returns ``(result, start)`` (``start``: start-model fit with --effects, else None)."""
    from ..fitting.mf import fit_mf, prepare_mf_data
    from ..io.readers import read_data

    conv = getattr(args, "convention", "iso") or "iso"
    sets = []
    for path in datas:
        ds = read_data(path, convention=conv)
        if ds.kind not in ("slip_angle", "slip_ratio"):
            raise DataError(f"{ds.source}: a {ds.kind} table cannot be fitted to a Magic Formula tyre; it needs "
                            "slip-angle or slip-ratio sweeps from a dynamic rig")
        sets.append(ds)
    data = prepare_mf_data(sets)
    info = {"name": Path(datas[0]).stem}
    from .fit import _size_and_load

    size = _size_and_load(args)
    if getattr(args, "rated_load", None) is not None:
        info["fnomin"] = float(args.rated_load)
    measured = loaded_radius_law(sets)
    if measured:
        info["unloaded_radius"] = measured["UNLOADED_RADIUS"]
    elif size is not None:
        info["unloaded_radius"] = size.unloaded_radius
    if size is not None:
        info["width"] = size.width
    effects = [e.strip() for e in (getattr(args, "effects", None) or "").split(",") if e.strip()]
    kw = {"model": args.model, "cost": getattr(args, "cost", "l2") or "l2", "tyre_info": info}
    start = None
    if effects:
        start = fit_mf(data, effects=[], **kw)
        result = fit_mf(data, effects=effects, **kw)
        result.notes.append(f"effects {', '.join(effects)}: start-model Fy RMSE {start.rmse:.4g} N -> "
                            f"{result.rmse:.4g} N with the effects")
    else:
        result = fit_mf(data, **kw)
    notes = design_data(result, sets, size, measured)
    result.tyre_info["header"] = list(result.tyre_info.get("header", [])) + notes
    return result, start


#: the sections whose values a force fit does not give (their keys in :data:`tyrefit.models.mf61.COEFFICIENTS`)
DESIGN_SECTIONS = ("DIMENSION", "OPERATING_CONDITIONS", "INERTIA", "VERTICAL", "STRUCTURAL", "CONTACT_PATCH")


def loaded_radius_law(datasets) -> dict[str, float]:
    """UNLOADED_RADIUS [m] and VERTICAL_STIFFNESS [N/m] from a loaded-radius channel (empty dict if none).

    Least squares R_l = R0 - Fz / c_z over the samples with Fz > 0 and a finite
    loaded radius (MF 6.1's vertical model with Q_FZ2 = 0: Fz = c_z (R0 - R_l),
    Pacejka (2012) (A3.4)).  Used only when the line is credible: at least 50
    samples, loads spanning a factor of 1.5, c_z > 0, and 0.1 m < R0 < 2 m with
    R0 above every loaded radius seen.
    """
    import numpy as np

    fz, rl = [], []
    for ds in datasets:
        df = ds.df
        if "loaded_radius" not in df.columns or "fz" not in df.columns:
            continue
        f, r = df["fz"].to_numpy(float), df["loaded_radius"].to_numpy(float)
        ok = np.isfinite(f) & np.isfinite(r) & (f > 0) & (r > 0)
        fz.append(f[ok])
        rl.append(r[ok])
    if not fz:
        return {}
    fz, rl = np.concatenate(fz), np.concatenate(rl)
    if fz.size < 50 or not np.percentile(fz, 95) > 1.5 * np.percentile(fz, 5):
        return {}
    slope, r0 = np.polyfit(fz, rl, 1)
    if not (slope < 0 and 0.1 < r0 < 2.0 and r0 > rl.max()):
        return {}
    return {"UNLOADED_RADIUS": float(r0), "VERTICAL_STIFFNESS": float(-1.0 / slope), "n": int(fz.size),
            "fz": (float(fz.min()), float(fz.max()))}


def design_data(result, datasets, size, measured: dict) -> list[str]:
    """Put the design data into ``result.params``; the header lines saying where each value came from.

    See the module notes for the four origins (data, ``--size`` /
    ``--rated-load``, estimates, placeholders).
    """
    from ..models import mf61
    from ..tyres.size import design_estimates

    p = result.params
    template = mf61.neutral()
    origin: dict[str, str] = {}
    lines: list[str] = []
    if measured:
        p["UNLOADED_RADIUS"] = measured["UNLOADED_RADIUS"]
        p["VERTICAL_STIFFNESS"] = measured["VERTICAL_STIFFNESS"]
        origin["UNLOADED_RADIUS"] = origin["VERTICAL_STIFFNESS"] = "data"
        lines.append(f"UNLOADED_RADIUS {p['UNLOADED_RADIUS']:.4f} m and VERTICAL_STIFFNESS "
                     f"{p['VERTICAL_STIFFNESS'] / 1e3:.4g} N/mm FROM THE DATA: loaded radius = R0 - Fz/cz fitted to "
                     f"{measured['n']} samples, Fz {measured['fz'][0]:.0f}-{measured['fz'][1]:.0f} N")
    levels = result.data.df["pressure"] if "pressure" in result.data.df.columns else None
    if levels is not None and levels.notna().any():
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
    rated = getattr(result, "tyre_info", {}).get("fnomin")
    if rated:
        origin["FNOMIN"] = "rated load"
        lines.append(f"FNOMIN {p['FNOMIN']:.0f} N = the rated load (--rated-load)")
    else:
        origin["FNOMIN"] = "data"
    if size is not None:
        try:
            est = design_estimates(unloaded_radius=p["UNLOADED_RADIUS"], width=size.width,
                                   rim_radius=size.rim_radius, rated_load=p["FNOMIN"],
                                   vertical_stiffness=p["VERTICAL_STIFFNESS"] if measured else None,
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
    for sec in DESIGN_SECTIONS:
        keys = [k for k in mf61.COEFFICIENTS.get(sec, []) if k not in origin and k in p]
        if not keys:
            continue
        placeholders += keys
        shown = ", ".join(f"{k} {p[k]:g}" for k in keys)
        lines.append(f"PLACEHOLDER [{sec}] (template values of a 205/60R15, not from these data): {shown}")
    result.placeholders = placeholders
    if "UNLOADED_RADIUS" in placeholders:
        lines.append(f"the Mz, Mx and My coefficients were fitted with UNLOADED_RADIUS {p['UNLOADED_RADIUS']:g} m "
                     "(a placeholder); keep them with it, or refit with --size")
    if "NOMPRES" in placeholders:
        lines.append(f"no pressure column: NOMPRES = INFLPRES {p['NOMPRES'] / 1e3:g} kPa is a placeholder; the "
                     "pressure terms are not fitted (PPX, PPY, PPZ = 0), so the forces do not depend on it")
    return lines


def _report(result, start, args, out: Path, datas) -> None:
    from ..io.outputs import write_text
    from ..io.report import Report

    rdir = Path(args.report)
    names = ", ".join(Path(d).name for d in datas)
    r = Report(f"Magic Formula {result.version} fit — {names}",
               f"tyrefit fit {' '.join(map(str, datas))} --model {result.model} → {out.name}"
               + (f" (effects: {', '.join(result.effects)})" if result.effects else ""))
    try:
        rel = os.path.relpath(out.resolve(), rdir.resolve())
    except ValueError:  # pragma: no cover - other drive on Windows
        rel = str(out)
    r.link(rel, f"tyre file: {out.name}")
    if start is not None:
        r.h2("Diagnose's start model and start model + effects, in MF 6.1")
        r.table([{"model": "start (PCY1, PDY1, PKY1, PKY2, PEY1)", "Fy RMSE [N]": start.rmse},
                 {"model": "start + " + ", ".join(result.effects), "Fy RMSE [N]": result.rmse}])
    result.report_blocks(r)
    rdir.mkdir(parents=True, exist_ok=True)
    if not result.cells.empty:
        write_text(rdir / "cells.csv", result.cells.to_csv(index=False), force=True)
    r.save(rdir, force=args.force)


def run_mf(args, out: Path, datas) -> int:
    """``tyrefit fit`` with ``--model mf61`` or ``mf52``."""
    for attr, flag in _PAC89_ONLY:
        if getattr(args, attr, None):
            raise DataError(f"{flag} is for --model pac89; a Magic Formula fit takes dynamic-rig slip sweeps only")
    result, start = fit_mf_files(args, datas)
    result.write_tir(out, force=args.force)
    if getattr(args, "report", None):
        _report(result, start, args, out, datas)
    parts = ", ".join(f"{c.upper()} RMSE {s['rmse']:.4g} {s['unit']} (R² {s['r2']:.4f}, noise floor "
                      f"{s['noise_floor']:.3g} {s['unit']})" for c, s in result.stats.items())
    print(f"wrote {out} (MF {result.version}, {len(result.fitted)} coefficients fitted from {len(datas)} file(s)): "
          f"{parts}")
    if start is not None:
        print(f"  start model Fy RMSE {start.rmse:.4g} N -> with {', '.join(result.effects)}: {result.rmse:.4g} N")
    for name, f in result.stages.items():
        print(f"  stage {name}: {len(f.varied)} coefficients, {f.n_sweeps} sweeps, {f.seconds:.1f} s")
    held = sorted(result.not_identifiable)
    if held:
        print(f"  held (not identifiable from these data, {len(held)}): " + ", ".join(held))
    for n in result.notes:
        print(f"  note: {n}")
    ph = getattr(result, "placeholders", [])
    main_ph = [k for k in ("UNLOADED_RADIUS", "WIDTH", "NOMPRES", "INFLPRES", "MASS", "VERTICAL_STIFFNESS",
                           "VERTICAL_DAMPING") if k in ph]
    if ph:
        print(f"  note: {len(ph)} design values are PLACEHOLDERS (template, not data), listed in the file's header"
              + (f", among them {', '.join(main_ph)}" if main_ph else "")
              + ("; give --size (and --rated-load) for the geometry and estimates" if "WIDTH" in ph else ""))
    if getattr(args, "report", None):
        print(f"wrote {Path(args.report) / 'index.html'}")
    return 0
