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

import json
import os
from pathlib import Path

from ..errors import DataError
from ..tyres.size import complete_mf_design, loaded_radius_law, size_and_rated_load

__all__ = ["run_mf", "fit_mf_files"]

_PAC89_ONLY = (("patch", "--patch (static-rig tests)"), ("rig", "--rig"), ("vertical", "--vertical"),
               ("by", "--by"), ("json", "--json (Chrono's PAC89 JSON)"))


def check_mirror(ds, args) -> None:
    """Refuse a mirrored tyre (camber thrust, pneumatic trail or Fx of the wrong sign) unless
    ``--allow-mirrored``; with it, print the findings as warnings (:mod:`tyrefit.io.plausibility`)."""
    from ..io.plausibility import check_mirrored

    for m in check_mirrored(ds, allow=bool(getattr(args, "allow_mirrored", False))):
        print(f"  WARNING (--allow-mirrored): {m}")


def fit_mf_files(args, datas):
    """Read ``datas`` and fit; returns ``(result, start)`` (``start``: start-model fit with --effects, else None)."""
    from ..fitting.mf import fit_mf, prepare_mf_data
    from ..io.readers import read_data

    conv = getattr(args, "convention", "iso") or "iso"
    sets = []
    for path in datas:  # paths, or records already read (tyrefit.fit with Dataset objects)
        ds = path if hasattr(path, "df") and hasattr(path, "kind") else read_data(path, convention=conv)
        if ds.kind not in ("slip_angle", "slip_ratio"):
            raise DataError(f"{ds.source}: a {ds.kind} table cannot be fitted to a Magic Formula tyre; it needs "
                            "slip-angle or slip-ratio sweeps from a dynamic rig")
        check_mirror(ds, args)
        sets.append(ds)
    data = prepare_mf_data(sets)
    info = {"name": Path(str(getattr(datas[0], "source", datas[0]))).stem}
    size = size_and_rated_load(getattr(args, "size", None), getattr(args, "rated_load", None))
    if getattr(args, "rated_load", None) is not None:
        info["fnomin"] = float(args.rated_load)
    measured = loaded_radius_law(sets)
    if "UNLOADED_RADIUS" in measured:
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
    if measured.get("note"):
        result.notes.append(f"loaded radius: {measured['note']}")
    if "UNLOADED_RADIUS" in getattr(result, "placeholders", []):
        result.warnings.append(f"UNLOADED_RADIUS {result.params['UNLOADED_RADIUS']:g} m is a TEMPLATE value (no "
                               "credible loaded-radius channel in the data and no tyre size given): the Mz and Mx "
                               "coefficients were fitted with it; give the size for the tyre's own radius")
    return result, start


def design_data(result, datasets, size, measured: dict) -> list[str]:
    """Put the design data into ``result.params`` (:func:`tyrefit.tyres.size.complete_mf_design`); the header lines."""
    df = result.data.df
    lines, result.placeholders = complete_mf_design(
        result.params, size=size, measured=measured, rated_load_given=bool(result.tyre_info.get("fnomin")),
        pressure_from_data="pressure" in df.columns and bool(df["pressure"].notna().any()))
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
    write_text(rdir / "fit.json", json.dumps(result.to_dict(), indent=1, default=float), force=True)
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
                      f"{s['noise_floor']:.3g} {s['unit']}{'' if s.get('fitted', True) else '; not fitted'})"
                      for c, s in result.stats.items())
    print(f"wrote {out} (MF {result.version}, {len(result.fitted)} coefficients fitted from {len(datas)} file(s)): "
          f"{parts}")
    if start is not None:
        print(f"  start model Fy RMSE {start.rmse:.4g} N -> with {', '.join(result.effects)}: {result.rmse:.4g} N")
    for name, f in result.stages.items():
        print(f"  stage {name}: {len(f.varied)} coefficients, {f.n_sweeps} sweeps, {f.seconds:.1f} s")
    held = sorted(result.not_identifiable)
    if held:
        print(f"  held (not identifiable from these data, {len(held)}): " + ", ".join(held))
    for w in result.warnings:
        print(f"  warning: {w}")
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
