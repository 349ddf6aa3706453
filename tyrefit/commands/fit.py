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

import math
from pathlib import Path

from ..errors import DataError
from ..io.facets import channel_levels, format_condition, format_levels, sweep_conditions
from ..fitting.result import unfitted_figures
from ..io.chrono_json import chrono_dict
from ..io.outputs import check_output, write_text
from .outputs import check_outputs
from ..io.report import Report
from ..workflows.fit import _effect_ids, fit, fit_pac89_record, read_checked
from .fit_mf import print_plausibility, run_mf

__all__ = ["run", "fit_file", "options"]


def options(args) -> dict:
    """The PAC89 fit's keyword options (:func:`tyrefit.workflows.fit.fit_pac89_record`) from the flags."""
    return {"cost": getattr(args, "cost", "l2") or "l2", "effects": _effect_ids(getattr(args, "effects", None)),
            "size": getattr(args, "size", None), "rated_load": getattr(args, "rated_load", None),
            "patch": getattr(args, "patch", None), "rig": getattr(args, "rig", None),
            "vertical": getattr(args, "vertical", None), "static_part": getattr(args, "static_part", "peak") or "peak"}


def fit_file(args, ds=None):
    """The fit of ``tyrefit fit`` (without writing); returns ``(result, result.extras)``.

    ``ds``: the data already read and checked (a subset for ``--by``); default: read ``args.data``.
    """
    if ds is None:
        result = fit(args.data, convention=getattr(args, "convention", "iso") or "iso",
                     allow_mirrored=bool(getattr(args, "allow_mirrored", False)), **options(args))
        print_plausibility(result.plausibility)
    else:
        result = fit_pac89_record(ds, name=str(args.data), **options(args))
    return result, result.extras


def _report(result, extras, args, out: Path, rdir: Path | None = None, title: str | None = None) -> None:
    rdir = Path(rdir or args.report)
    sub = f"tyrefit fit {args.data} → {out.name}"
    if extras["effects"]:
        sub += f" (effects in the model: {', '.join(extras.get('effects_carried') or []) or 'none'}"
        if extras.get("effects_dropped"):
            sub += f"; requested but not representable in PAC89, so not in the tyre: {', '.join(extras['effects_dropped'])}"
        sub += ")"
    r = Report(title or f"PAC89 fit — {Path(args.data).name}", sub)
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
        from matplotlib.figure import Figure

        fig = Figure(figsize=(12, 4.2))
        axes = fig.subplots(1, 2, sharey=True)
        start.plot(axes[0])
        axes[0].set_title("start model")
        result.plot(axes[1])
        axes[1].set_title("start + " + ", ".join(extras["effects"]))
        fig.tight_layout()
        r.figure(fig, "Both fits over the data (camber level nearest zero)")
    result._report_blocks(r, figures=True)
    _unfitted_section(r, result, extras.get("dataset"))
    if extras.get("static") is not None and hasattr(extras["static"], "report_section"):
        try:
            extras["static"].report_section(r, model=result.tyre)
        except TypeError:
            extras["static"].report_section(r)

    write_text(rdir / "sweeps.csv", result.sweeps_table().to_csv(index=False), force=True)
    r.save(rdir, force=args.force)


def run(args) -> int:
    """Entry point of ``tyrefit fit``."""
    out = Path(args.out)
    if out.suffix.lower() != ".tir":
        raise DataError(f"--out {out}: the tyre file must end in .tir")
    check_outputs(args)
    datas = list(args.data) if isinstance(args.data, (list, tuple)) else [args.data]
    if (getattr(args, "model", None) or "pac89") != "pac89":
        if getattr(args, "by", None):
            raise DataError(f"--by {args.by} writes one PAC89 tyre per level; --model {args.model} carries "
                            "pressure, camber and speed in one tyre - drop --by")
        return run_mf(args, out, datas)
    if len(datas) > 1:
        raise DataError(f"{len(datas)} DATA files: fitting one tyre to several files needs a Magic Formula model "
                        "(--model mf61 or mf52); PAC89 is fitted to one file")
    args.data = datas[0]
    _check_json_flags(args)
    if getattr(args, "by", None):
        return _run_by(args, out)
    result, extras = fit_file(args)
    if getattr(args, "json", None):
        chrono_dict(result.tyre)  # refuses, before anything is written, a JSON Chrono could not load
    result.tyre.to_tir(out, force=args.force)
    if getattr(args, "json", None):
        result.tyre.to_chrono_json(args.json, force=args.force)
    if getattr(args, "report", None):
        _report(result, extras, args, out)
    parts = ", ".join(f"{p} RMSE {s['rmse']:.4g} {s['unit']} (R² {s['r2']:.4f}, noise floor "
                      f"{s['noise_floor']:.4g} {s['unit']})" for p, s in result.stats.items())
    print(f"wrote {out}: {parts}")
    if extras.get("start") is not None:
        print(f"  start model RMSE {extras['start'].rmse:.4g} N -> with {', '.join(extras['effects'])}: "
              f"{result.rmse:.4g} N")
    if result.not_identifiable:
        print("  not identifiable (held): " + ", ".join(result.not_identifiable))
    _print_warnings(result)
    for n in result.notes:
        print(f"  note: {n}")
    if getattr(args, "json", None):
        print(f"wrote {args.json}")
    if getattr(args, "report", None):
        print(f"wrote {Path(args.report) / 'index.html'}")
    return 0


def _check_json_flags(args) -> None:
    """Refuse, before any work, a ``--json`` whose Chrono keys no other flag can give.

    Chrono's Pac89Tire JSON needs radius, width, mass and inertia (only ``--size`` gives width, mass and
    inertia) and the vertical and lateral stiffness and damping (``--rated-load`` estimates them,
    ``--vertical`` measures the vertical one): :func:`tyrefit.io.chrono_doc.chrono_dict`.
    """
    if not getattr(args, "json", None):
        return
    need = []
    if not getattr(args, "size", None):
        need.append("--size (Width, Mass, Inertia)")
    if getattr(args, "rated_load", None) is None and not getattr(args, "vertical", None):
        need.append("--rated-load NEWTONS or --vertical VERTICAL.csv (Vertical Stiffness, Lateral Stiffness, "
                    "Vertical Damping)")
    if need:
        raise DataError(f"--json {args.json}: Chrono's PAC89 JSON needs {' and '.join(need)}; nothing was fitted")


def _print_warnings(result) -> None:
    for c, lv in result.merged.items():
        print(f"  merged: {_merged_line(c, lv)}")
    merged = {f"{c}: not in the model" for c in result.merged}
    for w in result.warnings:
        if not any(w.startswith(m) for m in merged):
            print(f"  WARNING: {w}")


def _merged_line(channel, levels) -> str:
    return (f"{len(levels)} {channel} levels ({format_levels(channel, levels)}) fitted as one "
            f"tyre (PAC89 has no {channel} input); --by {channel} writes one tyre per level")


def _level_tag(channel: str, value: float) -> str:
    """File-name tag of a level: 'pressure83kPa', 'camber-2.0deg', 'speed40kmh'."""
    if channel == "pressure":
        return f"pressure{value / 1e3:.0f}kPa"
    if channel == "camber":
        return f"camber{math.degrees(value):.1f}deg".replace("-0.0deg", "0.0deg")
    return f"speed{value * 3.6:.0f}kmh"


def _run_by(args, out: Path) -> int:
    """``fit --by pressure|camber|speed``: one tyre per level of the condition, and a summary table."""
    from dataclasses import replace

    import pandas as pd

    ch = args.by
    ds, plaus = read_checked(args.data, getattr(args, "convention", "iso") or "iso",
                             bool(getattr(args, "allow_mirrored", False)))
    print_plausibility(plaus)
    if ds.kind not in ("slip_angle", "slip_ratio"):
        raise DataError(f"{ds.source}: --by {ch} splits dynamic-rig sweeps; this file is a {ds.kind} test")
    if ch not in ds.df or not ds.df[ch].notna().any():
        raise DataError(f"{ds.source}: --by {ch}: the data have no '{ch}' channel")
    sc = sweep_conditions(ds.df, (ch,))
    levels, idx = channel_levels(sc[ch].to_numpy(), ch)
    if len(levels) < 2:
        raise DataError(f"{ds.source}: --by {ch}: the data hold one {ch} level "
                        f"({format_condition(ch, float(levels[0]))}); nothing to split - drop --by")
    unassigned = int((idx < 0).sum())
    stem, json_path = out.with_suffix(""), getattr(args, "json", None)
    plan = []
    for k, lv in enumerate(levels):
        tag = _level_tag(ch, float(lv))
        tir = Path(f"{stem}_{tag}.tir")
        js = Path(f"{Path(json_path).with_suffix('')}_{tag}.json") if json_path else None
        for f in (tir, js):
            if f is not None:
                check_output(f, args.force)
        runs = sc.index[idx == k]
        plan.append((lv, tag, tir, js, runs))
    table_path = Path(f"{stem}_by_{ch}.csv")
    check_output(table_path, args.force)
    fits = []
    for lv, tag, tir, js, runs in plan:
        sub = replace(ds, df=ds.df[ds.df["run"].isin(runs)].copy())
        try:
            result, extras = fit_file(args, ds=sub)
        except DataError as e:
            raise DataError(f"--by {ch}, level {format_condition(ch, float(lv))}: {e}") from None
        header = list(result.tyre.header)
        header.insert(1, f"one tyre per {ch} level (tyrefit fit --by {ch}): "
                         f"{format_condition(ch, float(lv))}, {len(runs)} sweeps")
        result = result.with_tyre(replace(result.tyre, header=header))
        fits.append((lv, tag, tir, js, runs, result, extras))
    if json_path:
        for *_, result, extras in fits:
            chrono_dict(result.tyre)  # refuses, before anything is written, a JSON Chrono could not load
    rows = []
    for lv, tag, tir, js, runs, result, extras in fits:
        result.tyre.to_tir(tir, force=args.force)
        if js is not None:
            result.tyre.to_chrono_json(js, force=args.force)
        part = result.parts[0]
        s = result.stats[part]
        rows.append({"level": format_condition(ch, float(lv)), f"{ch} [{_UNIT[ch][1]}]": float(lv) * _UNIT[ch][0],
                     "sweeps": len(runs), "part": part, f"RMSE [{s['unit']}]": s["rmse"],
                     f"noise floor [{s['unit']}]": s["noise_floor"],
                     "RMSE / floor": s["rmse"] / s["noise_floor"] if s["noise_floor"] > 0 else float("nan"),
                     "warnings": len([w for w in result.warnings if "not in the model" not in w]),
                     "file": tir.name})
    table = pd.DataFrame(rows)
    write_text(table_path, table.to_csv(index=False), force=True)
    if getattr(args, "report", None):
        rdir = Path(args.report)
        r = Report(f"PAC89 fit per {ch} level — {Path(args.data).name}",
                   f"tyrefit fit {args.data} --by {ch}: one tyre per {ch} level")
        r.table(table, digits=4)
        r.figure(_by_figure(table, ch), f"Lateral RMSE (bars) and within-sweep noise floor (line) of each {ch} "
                                        "level's tyre")
        for lv, tag, tir, js, runs, result, extras in fits:
            _report(result, extras, args, tir, rdir=rdir / tag,
                    title=f"PAC89 fit — {Path(args.data).name}, {format_condition(ch, float(lv))}")
            r.link(f"{tag}/index.html", f"report of {format_condition(ch, float(lv))}")
        r.save(rdir, force=args.force)
    print(f"fit --by {ch}: {len(fits)} tyres from {Path(args.data).name}")
    print(table.drop(columns=[f"{ch} [{_UNIT[ch][1]}]"]).to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    for lv, tag, tir, js, runs, result, extras in fits:
        print(f"wrote {tir}" + (f" and {js}" if js else ""))
        for w in result.warnings:
            if "not in the model" not in w:
                print(f"  WARNING ({format_condition(ch, float(lv))}): {w}")
    if unassigned:
        print(f"  note: {unassigned} sweeps have no {ch} value and are in none of these tyres")
    print(f"wrote {table_path}")
    if getattr(args, "report", None):
        print(f"wrote {Path(args.report) / 'index.html'}")
    return 0


_UNIT = {"pressure": (1e-3, "kPa"), "camber": (180 / math.pi, "deg"), "speed": (3.6, "km/h")}


def _by_figure(table, channel: str, ax=None):
    """Bar chart of RMSE per level with the noise floor; returns the Figure."""
    from matplotlib.figure import Figure

    if ax is None:
        ax = Figure(figsize=(1.6 * len(table) + 2.4, 3.2)).subplots()
    rm = [c for c in table.columns if c.startswith("RMSE [")][0]
    nf = [c for c in table.columns if c.startswith("noise floor [")][0]
    x = range(len(table))
    ax.bar(x, table[rm], color="#4c78a8", label="RMSE")
    ax.plot(x, table[nf], "k_", ms=30, mew=2, label="noise floor (within-sweep)")
    ax.set_xticks(list(x), [str(v).replace(f"{channel} ", "") for v in table["level"]])
    ax.set_xlabel(channel)
    ax.set_ylabel(rm)
    ax.set_title(f"PAC89, one tyre per {channel} level: lateral RMSE against the noise floor", fontsize=9)
    ax.set_ylim(0, 1.3 * max(float(table[rm].max()), float(table[nf].max())))
    ax.legend(fontsize=8, loc="upper right", ncols=2)
    ax.grid(axis="y", alpha=0.3)
    ax.figure.tight_layout()
    return ax.figure


def _unfitted_section(r, result, ds) -> None:
    """Report section drawing the sweeps of the file that no fitted part used (combined slip for PAC89)."""
    if ds is None or getattr(ds, "kind", "") not in ("slip_angle", "slip_ratio") or "run" not in ds.df:
        return

    used = set()
    for part in result.parts:
        used |= set(result._parts[part].data.df["run"].unique().tolist())
    left = sorted(set(ds.df["run"].unique().tolist()) - used)
    if not left:
        return
    r.h2(f"Sweeps not fitted ({len(left)} of {ds.df['run'].nunique()})")
    r.p(f"{len(left)} sweeps of {Path(str(ds.source)).name or 'the data'} are not in the fit (see the notes: "
        "PAC89 has pure-slip curves only, so combined-slip sweeps are left out). Their data, per condition "
        "level:", "warn")
    for fig in unfitted_figures(ds.df, left):
        r.figure(fig, "Sweeps not fitted: data only, one panel per condition level")
