"""``tyrefit fit DATA --out TYRE.tir``: fit a PAC89 tyre and write it.

Dynamic-rig slip-angle and slip-ratio data (or a file with both) go straight
to :func:`tyrefit.fitting.fit_pac89`.  Static-rig (STTR) tests are first
turned into slip-angle data by :func:`tyrefit.rig.prepare_static_fit`
(Komana et al. Eq. 1, needs ``--patch``; ``--rig`` for the calibrated
f(dy/L), ``--vertical`` for VERTICAL_STIFFNESS).  With ``--effects E1,E2``
the diagnose start model and the start model plus those effects
(:func:`tyrefit.effects.resolve_pac89`) are both fitted; the ``.tir`` holds
the latter and the report shows both.
"""

from __future__ import annotations

import inspect
import warnings
from pathlib import Path

from ..errors import DataError
from ..io.outputs import check_outputs

__all__ = ["run", "fit_file"]


def _read(path, convention, kind=None):
    from ..io.readers import read_data

    return read_data(path, convention=convention, kind=kind) if kind else read_data(path, convention=convention)


def _resolver():
    try:
        from ..effects import resolve_pac89
    except ImportError:
        raise DataError("--effects: the effects catalogue (tyrefit.effects) is not available in this "
                        "installation") from None
    return resolve_pac89


def _static_input(ds, args, notes):
    if not getattr(args, "patch", None):
        raise DataError(f"{ds.source}: a static test needs --patch PATCH.csv for Eq. 1 (contact-patch length)")
    from ..rig import prepare_static_fit

    patch = _read(args.patch, "iso", "patch")
    rig = None
    if getattr(args, "rig", None):
        from ..rig import RigCalibration

        rig = RigCalibration.from_json(args.rig)
    vertical = _read(args.vertical, "iso", "vertical") if getattr(args, "vertical", None) else None
    kw = {"rig": rig, "part": getattr(args, "static_part", "peak") or "peak", "vertical_ds": vertical}
    if getattr(args, "rated_load", None) is not None and \
            "rated_load" in inspect.signature(prepare_static_fit).parameters:
        kw["rated_load"] = args.rated_load
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sfi = prepare_static_fit(ds, patch, **kw)
    for w in caught:
        notes.append(f"warning: {w.message}")
    return sfi


def _tyre_info(sfi, args, data_path) -> dict:
    info: dict = {"name": Path(data_path).stem}
    if sfi is not None:
        ti = getattr(sfi, "tyre_info", None)
        if isinstance(ti, dict):
            info.update(ti)
        else:
            for k in ("lateral_stiffness", "vertical_stiffness", "fnomin", "vertical_curve"):
                v = getattr(sfi, k, None)
                if v is not None:
                    info[k] = v
            info["header"] = list(getattr(sfi, "notes", []))
    if getattr(args, "rated_load", None) is not None:
        info["fnomin"] = float(args.rated_load)
    return info


def fit_file(args):
    """Do the work of ``tyrefit fit`` (without writing); returns (result, extras).

    ``extras``: ``static`` (StaticFitInput or None), ``start`` (FitResult of the
    start model when ``--effects``), ``effects`` (ids), ``notes``.
    """
    from ..fitting import fit_pac89
    from ..io.readers import check_fittable

    notes: list[str] = []
    ds = _read(args.data, getattr(args, "convention", "iso") or "iso")
    sfi = None
    if ds.kind == "static":
        sfi = _static_input(ds, args, notes)
        data = sfi.data
    elif ds.kind in ("slip_angle", "slip_ratio"):
        if not {"slip_angle", "slip_ratio"} <= set(ds.df.columns):
            check_fittable(ds)
        # a file with both slip-angle and slip-ratio sweeps: each sweep is classified and
        # checked by tyrefit.fitting.prepare_data (combined-slip sweeps are left out, with a note)
        data = ds
    else:
        raise DataError(f"{ds.source}: a {ds.kind} table cannot be fitted to a tyre model; fit needs slip-angle, "
                        "slip-ratio or static-rig lateral tests")
    info = _tyre_info(sfi, args, args.data)
    # static 'peak' part: C (Eq. 2) and the peak-friction law measured by the static test itself
    fixed = (getattr(sfi, "anchors", None) or None) if sfi is not None else None
    extras = {"static": sfi, "start": None, "effects": [], "notes": notes, "dataset": ds}
    effects = [e.strip() for e in (getattr(args, "effects", None) or "").split(",") if e.strip()]
    if effects:
        resolve = _resolver()
        vary0, _ = resolve([])
        vary1, enotes = resolve(effects)
        notes += list(enotes)
        extras["start"] = fit_pac89(data, cost=args.cost, vary=vary0, tyre_info=info, fixed=fixed)
        extras["effects"] = effects
        # the effects' model starts from the start model's solution
        result = fit_pac89(data, cost=args.cost, vary=vary1, tyre_info=info, fixed=fixed,
                           initial={k: v for k, v in extras["start"].values.items() if k.startswith("a")})
        result.notes.append(f"effects {', '.join(effects)}: start-model RMSE {extras['start'].rmse:.4g} N -> "
                            f"{result.rmse:.4g} N with the effects")
    else:
        result = fit_pac89(data, cost=args.cost, tyre_info=info, fixed=fixed)
    if sfi is not None and hasattr(sfi, "apply_to"):
        sfi.apply_to(result.tyre)
    result.notes.extend(n for n in notes if n not in result.notes)
    return result, extras


def _report(result, extras, args, out: Path) -> None:
    from ..io.report import Report

    rdir = Path(args.report)
    r = Report(f"PAC89 fit — {Path(args.data).name}",
               f"tyrefit fit {args.data} → {out.name}" + (f" (effects: {', '.join(extras['effects'])})"
                                                          if extras["effects"] else ""))
    try:
        import os

        rel = os.path.relpath(out.resolve(), rdir.resolve())
    except ValueError:  # pragma: no cover - other drive on Windows
        rel = str(out)
    r.link(rel, f"tyre file: {out.name}")
    start = extras.get("start")
    if start is not None:
        r.h2("Start model and start model + effects")
        rows = [{"model": "start (a0, a2, a3, a4, a7)", "fitted coefficients": start.stats[start.parts[0]]["varied"],
                 "RMSE [N]": start.rmse, "R²": start.stats[start.parts[0]]["r2"]},
                {"model": "start + " + ", ".join(extras["effects"]),
                 "fitted coefficients": result.stats[result.parts[0]]["varied"],
                 "RMSE [N]": result.rmse, "R²": result.stats[result.parts[0]]["r2"]}]
        r.table(rows)
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, 2, figsize=(12, 4.2), sharey=True)
        start.plot(axes[0])
        axes[0].set_title("start model")
        result.plot(axes[1])
        axes[1].set_title("start + " + ", ".join(extras["effects"]))
        fig.tight_layout()
        r.figure(fig, "Both fits over the data (camber level nearest zero)")
    result._report_blocks(r, figures=True)
    if extras.get("static") is not None and hasattr(extras["static"], "report_section"):
        try:
            extras["static"].report_section(r, model=result.tyre)
        except TypeError:
            extras["static"].report_section(r)
    rdir.mkdir(parents=True, exist_ok=True)
    from ..io.outputs import write_text

    write_text(rdir / "sweeps.csv", result.sweeps.to_csv(index=False), force=True)
    r.save(rdir, force=args.force)


def run(args) -> int:
    """Entry point of ``tyrefit fit``."""
    out = Path(args.out)
    if out.suffix.lower() != ".tir":
        raise DataError(f"--out {out}: the tyre file must end in .tir")
    check_outputs(args)
    result, extras = fit_file(args)
    result.tyre.to_tir(out, force=args.force)
    if getattr(args, "json", None):
        result.tyre.to_chrono_json(args.json, force=args.force)
    if getattr(args, "report", None):
        _report(result, extras, args, out)
    parts = ", ".join(f"{p} RMSE {s['rmse']:.4g} {s['unit']} (R² {s['r2']:.4f}, noise floor "
                      f"{s['noise_floor']:.3g} {s['unit']})" for p, s in result.stats.items())
    print(f"wrote {out}: {parts}")
    if extras.get("start") is not None:
        print(f"  start model RMSE {extras['start'].rmse:.4g} N -> with {', '.join(extras['effects'])}: "
              f"{result.rmse:.4g} N")
    if result.not_identifiable:
        print("  not identifiable (held): " + ", ".join(result.not_identifiable))
    for n in result.notes:
        print(f"  note: {n}")
    if getattr(args, "json", None):
        print(f"wrote {args.json}")
    if getattr(args, "report", None):
        print(f"wrote {Path(args.report) / 'index.html'}")
    return 0
