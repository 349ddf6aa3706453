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

The workflow, design data included, is :func:`tyrefit.workflows.fit.fit_mf_records`; this module
parses, writes and prints.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from ..errors import DataError
from ..io.outputs import write_text
from ..io.report import Report
from ..workflows.fit import _effect_ids, fit

__all__ = ["run_mf", "fit_mf_files", "print_plausibility"]

_PAC89_ONLY = (("patch", "--patch (static-rig tests)"), ("rig", "--rig"), ("vertical", "--vertical"),
               ("by", "--by"), ("json", "--json (Chrono's PAC89 JSON)"))


def print_plausibility(messages) -> None:
    """The mirrored-tyre findings ``--allow-mirrored`` let through, as console warnings."""
    for m in messages:
        print(f"  WARNING (--allow-mirrored): {m}")


def fit_mf_files(args, datas):
    """Read ``datas`` and fit (:func:`tyrefit.workflows.fit.fit`); returns ``(result, start)``."""
    result = fit(list(datas), model=args.model, cost=getattr(args, "cost", "l2") or "l2",
                 effects=_effect_ids(getattr(args, "effects", None)), size=getattr(args, "size", None),
                 rated_load=getattr(args, "rated_load", None),
                 convention=getattr(args, "convention", "iso") or "iso",
                 allow_mirrored=bool(getattr(args, "allow_mirrored", False)))
    print_plausibility(result.plausibility)
    return result, result.start


def _report(result, start, args, out: Path, datas) -> None:
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
