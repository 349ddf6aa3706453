"""The HTML report of a diagnosis: the whole loop on one page.

Fit-vs-data views, where the start model fails (cells, residual maps, even and
odd parts), the evidence table with a status for every catalogue effect, the
error waterfall against the noise floor, a signature plot and physics card per
accepted effect, what it means for an exported PAC89 ``.tir``, and the check
for structure still unexplained.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from matplotlib import cm as plt_cm
from matplotlib.figure import Figure
import pandas as pd

from ..effects import EFFECTS, get_effect
from ..io.outputs import staged_dir, write_text
from ..io.report import Report, esc
from . import views
from .channel_report import add_channel_sections
from .advice import PEAK_SEARCH_DEG, level_curve, needs_model

__all__ = ["write_report", "build_report"]

_STATUS_TEXT = {
    "accepted": "the data need it: significant, confirmed on held-out sweeps and levels, stable",
    "in start model": "given with --start",
    "not significant": "the data show no evidence for it (which is not evidence that the tyre lacks it)",
    "not testable with these data": "the data cannot show it either way; the reason says what test is missing",
    "significant but not confirmed": "the screening test found something, but the held-out check did not confirm it",
    "variant not distinguishable": "fits as well as the accepted variant of its family; the data cannot tell them apart",
    "covered": "its terms are already part of an effect in the model",
    "confirmed, not added": "confirmed, but another effect explained more in that round",
    "significant, not refitted": "significant, ranked below the refitted candidates",
}


def _fmt(v, d=3):
    if v is None or (isinstance(v, float) and not np.isfinite(v)):
        return "–"
    if isinstance(v, float):
        return f"{v:.{d}g}"
    return str(v)


def build_report(dg) -> tuple[Report, dict[str, str]]:
    """Build the report of ``dg``; returns the Report and CSV tables (name -> text)."""
    d = dg.data
    x = d.inputs
    first, last = dg.steps[0], dg.steps[-1]
    title = f"tyrefit diagnose — {Path(d.source).name if d.source else 'data'}"
    r = Report(title)
    cond = [f"loads {', '.join(f'{v / 1e3:.2f}' for v in d.levels['fz'])} kN",
            f"cambers {', '.join(f'{np.degrees(v):.1f}' for v in d.levels['camber'])} deg"]
    if "pressure" in d.levels:
        cond.append(f"pressures {', '.join(f'{v / 1e3:.0f}' for v in d.levels['pressure'])} kPa")
    if "speed" in d.levels:
        cond.append(f"speeds {', '.join(f'{v * 3.6:.0f}' for v in d.levels['speed'])} km/h")
    r.p(f"Data: {d.n} points in {d.n_sweeps} sweeps; " + "; ".join(cond)
        + (f"; rated load {x.rated_load / 1e3:.2f} kN" if x.rated_load else "; rated load not given")
        + ". " + " ".join(d.notes))
    acc = ", ".join(dg.accepted) if dg.accepted else "nothing beyond the start model"
    r.raw(
        "<div class='note'><b>Result.</b> Start model: base PAC89"
        + (esc(" + " + ", ".join(dg.start)) if dg.start else "")
        + f". Accepted, in order: <b>{esc(acc)}</b>. "
        f"Lateral-force RMSE {first.rmse:.1f} N → {last.rmse:.1f} N "
        f"(held-out sweeps {first.rmse_heldout:.1f} N → {last.rmse_heldout:.1f} N); "
        f"within-sweep noise floor {dg.noise_floor:.1f} N. {esc(dg.unexplained.get('summary', ''))}"
        + "".join(f" <b>{esc(a)}: {esc(needs_model(a))}.</b>" for a in dg.accepted if needs_model(a)) + "</div>")

    # -- the loop ----------------------------------------------------------------------
    r.h2("1. The loop: error from the start model to the final model")
    fig = Figure(figsize=(7, 3.8))
    ax = fig.subplots()
    views.plot_waterfall(dg, ax=ax)
    r.figure(fig, "Error waterfall: each bar pair is one model; held-out RMSE predicts whole sweeps the fit "
                  "never saw. The dashed line is the within-sweep noise floor (a separate smooth curve through "
                  "every sweep); a model cannot do better than it on average.")
    r.table([{"step": i, "added": s.added or "(start)", "effects": ", ".join(s.effects) or "base PAC89",
              "RMSE [N]": s.rmse, "held-out RMSE [N]": s.rmse_heldout,
              "held-out levels RMSE [N]": s.rmse_levelout,
              "extrapolated sweeps RMSE [N]": s.rmse_extrapolated} for i, s in enumerate(dg.steps)], digits=4)

    # -- evidence ------------------------------------------------------------------------
    r.h2("2. Evidence for every catalogue effect")
    scr = dg.screening or {}
    few = d.n_sweeps <= dg.settings.loso_max_sweeps
    nm = scr.get("noise_model")
    r.p("Each testable effect is screened with a score test at its neutral value; all candidates of a round are "
        "tested together and their p-values adjusted by min-p over the same bootstrap draws (family-wise level "
        f"{dg.settings.level(scr.get('method') or ''):g}"
        + ("" if scr.get("method") == "sweep flips" else
           f", below the diagnosis' {dg.settings.alpha:g}: the noise model is estimated from the same few sweeps")
        + "). The null distribution comes from "
        + ("flips of whole sweeps (residuals along a sweep are correlated, so point-wise tests find effects in "
           "pure noise)" if scr.get("method") == "sweep flips" else
           "a noise model estimated from the residuals: AR(1) noise along each sweep plus a random offset per "
           "sweep, re-estimated in every bootstrap draw"
           + (f" (here: sd {nm['sd_N']:.1f} N, lag-one correlation {nm['rho']:.2f}, sweep offsets "
              f"{nm['tau_N']:.1f} N)" if nm else ""))
        + f". Significant candidates are refitted and must lower the RMSE on held-out sweeps by at least "
        f"{100 * dg.settings.margin:.0f} % of the noise floor ({dg.settings.margin * dg.noise_floor:.2f} N) and "
        "not worsen held-out interior load/camber/pressure levels"
        + (f"; with {d.n_sweeps} sweeps every sweep is held out in turn (with one sweep per load: one load level "
           "at a time), and a held-out sweep outside the training levels (the lowest or highest load) counts as "
           "an extrapolation, reported apart." if few else
           f", improve >= {100 * dg.settings.min_folds_improved:.0f} % of the sweep folds and keep a positive gain "
           f"in >= {100 * dg.settings.min_boot_prob:.0f} % of sweep resamples."))
    rows = []
    for eid in EFFECTS:
        c = dg.candidates[eid]
        rows.append({"effect": eid, "family": c.family, "status": c.status, "round": _fmt(c.round),
                     "adjusted p": _fmt(c.p_adjusted), "held-out gain [N]": _fmt(c.delta_heldout),
                     "levels gain [N]": _fmt(c.delta_levelout), "stability": _fmt(c.boot_prob),
                     "why": c.reason})
    r.table(rows)
    r.bullets([f"{k}: {v}" for k, v in _STATUS_TEXT.items() if any(c.status == k for c in dg.candidates.values())])

    # -- where it fails --------------------------------------------------------------------
    r.h2("3. Where the start model fails, and where the final model still does")
    fig = views.plot_residual_maps(dg)
    r.figure(fig, "Mean residual (model − data) over slip angle and load, one panel per camber/pressure facet "
                  "(columns: camber, rows: pressure); the start model's panels first, then the final model's, "
                  "one colour scale for all panels.")
    fig = Figure(figsize=(7.5, 3.4))
    ax = fig.subplots()
    views.plot_even_odd(dg, ax=ax)
    r.figure(fig, "Even and odd residual parts per sweep. Lateral force is odd in slip angle, so a missing "
                  "shift (offsets, camber thrust) leaves an even residual; a missing stiffness, friction or "
                  "shape term leaves an odd one.")
    cells0 = dg.cell_table(0)
    cells1 = dg.cell_table(-1)
    cells = cells0.rename(columns={"rmse_N": "start RMSE [N]", "bias_N": "start bias [N]"})
    cells["final RMSE [N]"] = cells1["rmse_N"].to_numpy()
    cells["final bias [N]"] = cells1["bias_N"].to_numpy()
    r.h3("RMSE and bias per condition cell (bias = mean of model − data)")
    r.table(cells, digits=4)

    # -- fit vs data -----------------------------------------------------------------------
    r.h2("4. Fit against the data")
    fc = views.facets(d)
    ncol = min(3, len(fc))
    nrow = int(np.ceil(len(fc) / ncol))
    fig = Figure(figsize=(4.3 * ncol, 3.3 * nrow))
    axes = fig.subplots(nrow, ncol, squeeze=False)
    for k, f in enumerate(fc):
        views.plot_fit(dg, f, ax=axes[k // ncol, k % ncol])
    for k in range(len(fc), nrow * ncol):
        axes[k // ncol, k % ncol].set_visible(False)
    fig.tight_layout()
    r.figure(fig, "Measured lateral force (dots) with the start model (dotted) and the final model (solid), "
                  "one colour per load.")

    # -- advice ---------------------------------------------------------------------------------
    r.h2("Advice: what these data leave open, and the test that would decide it")
    if dg.advice:
        r.p("For every effect family the data could not test, could not settle, or did not show: the extra test "
            "that would decide it, and the smallest effect the present data detect (80 % power at the "
            f"{100 * dg.advice[0].get('level', dg.settings.alpha):g} % level of the screening, in the parameter's "
            "unit and as the largest change of "
            "lateral force the start model cannot mimic).")
        rows = []
        for a in dg.advice:
            det = "; ".join(f"{x['parameter']} {x['value']:.3g} {x['unit']} (~{x['force_N']:.0f} N)"
                            for x in (a.get("detectable") or []) if x["value"] is not None)
            rows.append({"family": a["family"], "status": a["status"], "why": a["why"], "test that decides it": a["test"],
                         "smallest detectable": det or "–", "model": a.get("needs_model") or ""})
        r.table(rows)
    else:
        r.p("Nothing left open: every family was testable and settled.")
    missed = [p for p in dg.peaks if p.get("model_misses_peak")]
    if missed:
        r.p("The measured sweeps peak where the model does not: "
            + "; ".join(f"at {p['fz_N'] / 1e3:.2f} kN the data peak near {p['data_peak_deg']:.1f} deg and fall "
                        f"{100 * p['data_drop']:.0f} % by the sweeps' end ({p['reach_deg']:.1f} deg), the model "
                        + (f"peaks at {p['peak_deg']:.1f} deg" if p["peak_deg"] is not None else
                           f"still rises at {PEAK_SEARCH_DEG:.0f} deg") for p in missed)
            + ". The peak is in the data: this is the model's error (its friction or curvature law), not a "
              "test to add.", "warn")
    if any(not p["reached"] or p.get("model_misses_peak") for p in dg.peaks):
        fig = Figure(figsize=(6.4, 3.8))
        _peak_figure(fig.subplots(), dg)
        r.figure(fig, "Where the sweeps stop against the force peak: the final model per load (lines) extended to "
                 "30 deg, the measured points (dots), the end of the sweeps (dashed) and the model's peak (circle; "
                 "none where it still rises at 30 deg). Where the peak is beyond the sweeps, the peak force is an "
                 "extrapolation of the curve's shape, and friction and curvature laws in load are hard to tell apart.")

    # -- accepted effects ------------------------------------------------------------------------
    r.h2("5. The effects that were added")
    if not dg.accepted:
        r.p("None: the data show nothing the start model misses at the practical margin. Effects reported "
            "'not testable' above may still be present in the tyre; the test that would show them is named "
            "in their row.")
    for eid in dg.accepted:
        e = get_effect(eid)
        r.h3(f"{eid} — {e.title}")
        fig = Figure(figsize=(6, 3.9))
        ax = fig.subplots()
        e.plot_signature(views.signature_view(dg, eid), ax=ax)
        r.figure(fig, f"Signature of {eid}: per-sweep characteristic of the data (points), the model without "
                      "the effect (dashed) and with it (solid).")
        r.table(e.card.as_rows())
        vals = dg.final.fit.values
        r.table([{"parameter": p.name, "fitted": vals.get(p.name, float("nan")), "unit": p.unit,
                  "plausible range": f"{p.plausible[0]:g} … {p.plausible[1]:g}",
                  "in range": "yes" if p.plausible[0] <= vals.get(p.name, np.nan) <= p.plausible[1] else "no",
                  "meaning": p.meaning} for p in e.params], digits=4)
        r.p(f"PAC89: {e.pac89_note}", cls=None if e.representable else "warn")
        if needs_model(eid):
            r.p(f"{eid}: {needs_model(eid)}: PAC89 has no input for it.", cls="warn")

    # -- .tir ----------------------------------------------------------------------------------
    r.h2("6. What it means for the exported .tir")
    vary, notes = dg.pac89()
    ex = dg.export
    r.p(f"A PAC89 .tir of the final model frees {', '.join(vary)}. "
        + ("Every accepted effect is a PAC89 term, so the .tir reproduces the final model "
           f"(RMSE {ex['rmse']:.1f} N)." if ex.get("same_as_final") else
           f"Not every accepted effect fits in PAC89: refitted with only PAC89 terms "
           f"({', '.join(ex['effects']) or 'base'}), the .tir has RMSE {ex['rmse']:.1f} N against "
           f"{last.rmse:.1f} N for the final model."))
    if notes:
        r.bullets(notes)
    if ex.get("fit_rmse") is not None:
        r.p("To export: " + export_command(dg) + f" - it gives lateral RMSE {ex['fit_rmse']:.1f} N (diagnose ran "
            f"it; the {ex['rmse']:.1f} N above is diagnose's own refit on its sampled points)")
    else:
        r.p("To export: " + export_command(dg) + f" (tyrefit fit refits these terms on every point and prints its "
            f"own RMSE; diagnose's {ex['rmse']:.1f} N is on its sampled points)")
    coef = ex.get("coefficients", {})
    r.table([{"coefficient": k, "value": v, "freed by": next((e for e in dg.effects
                                                             if k in get_effect(e).pac89 + get_effect(e).pac89_approx),
                                                            "start model" if k in ("a0", "a2", "a3", "a4", "a7") else "–")}
             for k, v in coef.items()], digits=5)

    # -- unexplained -----------------------------------------------------------------------------
    r.h2("7. Structure still unexplained")
    u = dg.unexplained
    r.p(u.get("summary", ""), cls="warn" if u.get("structure_found") else "note")
    mf = u.get("misfit") or {}
    if mf:
        r.p(f"How far the final model ends above the noise: held-out RMSE {mf['rmse_heldout_N']:.1f} N is "
            f"{mf['ratio']:.2f} x the within-sweep noise floor {mf['noise_floor_N']:.1f} N. Above "
            f"{mf['threshold_ratio']:g} x (a model with nothing missing ends near 1.0 x with independent noise and "
            "about 1.25 x with sweep-to-sweep offsets) a smooth surface over slip and conditions is fitted to the "
            "final residuals of some sweeps and asked to predict the others: a systematic misfit carries over "
            f"(at least {100 * mf['threshold_share']:.0f} % of the residual variance predicted), noise correlated "
            "along a sweep does not."
            + (f" Here it predicts {100 * mf['predictable_share']:.0f} % "
               f"({mf['predictable_rmse_N']:.0f} N RMSE)." if mf.get("checked") else ""),
            cls="warn" if mf.get("systematic") else None)
        if mf.get("systematic"):
            r.table([{"part of the systematic error": k, "share [%]": 100 * v} for k, v in mf["components"].items()]
                    + [{"part of the systematic error": "odd in slip (stiffness, friction, shape)",
                        "share [%]": 100 * mf["odd_share"]}], digits=3,
                    caption="what the predictable part of the residual depends on (variance shares)")
            r.table(pd.DataFrame(mf["cells"]), digits=3, caption="cells with the largest systematic error")
    if u.get("omnibus_groups"):
        r.table([{"directions": k, "number": v["directions"], "p (alone)": v["p_value"]}
                 for k, v in u["omnibus_groups"].items()], digits=3,
                caption=f"omnibus score test by group of smooth directions (combined by min-p: "
                        f"p = {_fmt(u.get('p_value'))})")
    if u.get("cells"):
        r.table(pd.DataFrame(u["cells"][:6]), digits=3, caption="cells with the largest error (final model)")
    if u.get("slip_bins"):
        r.table([{"slip range [deg]": f"{b['slip_deg'][0]:.1f} … {b['slip_deg'][1]:.1f}",
                  "mean residual [N]": b["mean_N"], "sweep-robust SE [N]": b["se_N"]} for b in u["slip_bins"]],
                digits=3, caption="final residual by slip range (mean over sweeps)")
    add_channel_sections(r, dg)
    r.json_block(dg.to_dict(), "diagnosis JSON")
    tables = {"cells.csv": cells.to_csv(index=False),
              "candidates.csv": pd.DataFrame([dg.candidates[e].to_dict() for e in EFFECTS])
              .drop(columns=["parameters"], errors="ignore").to_csv(index=False),
              "steps.csv": pd.DataFrame([{"effects": "+".join(s.effects), "added": s.added, "rmse_N": s.rmse,
                                          "rmse_heldout_N": s.rmse_heldout} for s in dg.steps]).to_csv(index=False)}
    return r, tables


def _peak_figure(ax, dg) -> None:
    """|Fy| of the final model per load level over 0..30 deg of slip, with the data and the fitted peaks."""
    d, st = dg.data, dg.final
    li = np.asarray(d.level_index["fz"])
    grid = np.linspace(0.0, PEAK_SEARCH_DEG, 301)
    colours = plt_cm.viridis(np.linspace(0.0, 0.9, max(len(d.levels["fz"]), 1)))
    for p in dg.peaks:
        k = int(np.argmin(np.abs(np.asarray(d.levels["fz"]) - p["fz_N"])))
        f, side, _ = level_curve(st.spec, st.fit.theta, d, k, np.radians(grid))
        c = colours[k]
        ax.plot(grid, f / 1e3, color=c, lw=1.2, label=f"{p['fz_N'] / 1e3:.1f} kN")
        m = li == k
        sa = d.inputs.slip_angle[m]
        on = np.sign(sa) == side
        ax.plot(np.degrees(np.abs(sa[on])), np.abs(d.fy[m][on]) / 1e3, ".", color=c, ms=2.5, alpha=0.6)
        ax.axvline(p["reach_deg"], color=c, ls="--", lw=0.6)
        if p["peak_deg"] is not None:
            ax.plot(p["peak_deg"], np.interp(p["peak_deg"], grid, f) / 1e3, "o", mfc="none", color=c, ms=7)
    ax.set_xlabel("|slip angle| [deg]")
    ax.set_ylabel("|Fy| [kN]")
    ax.legend(fontsize=7, ncol=2, loc="lower right")


def write_report(dg, directory: str | os.PathLike, force: bool = False) -> Path:
    """Write ``directory/index.html`` and CSV tables atomically; return the index path."""
    report, tables = build_report(dg)
    with staged_dir(directory, force=force) as tmp:
        write_text(tmp / "index.html", report.html(), force=True)
        for name, text in tables.items():
            write_text(tmp / name, text, force=True)
    return Path(directory) / "index.html"


def export_command(dg) -> str:
    """The complete ``tyrefit fit`` command that writes the PAC89 .tir of this diagnosis.

    The data as given to diagnose (path and sign convention), the PAC89 effects of the export
    (``dg.export['effects']``, the ones the reported .tir RMSE is for) and the rated load when an effect
    uses it.
    """
    import shlex

    d = dg.data
    eff = list(dg.export.get("effects", dg.effects))
    cmd = ["tyrefit", "fit", d.source or "DATA"]
    if getattr(d, "convention", "iso") == "sae":
        cmd += ["--convention", "sae"]
    if eff:
        cmd += ["--effects", ",".join(eff)]
    rated = getattr(d.inputs, "rated_load", None)
    if rated and any(e.startswith("overload") for e in eff):
        cmd += ["--rated-load", f"{float(rated):.6g}"]
    return shlex.join(cmd + ["--out", "tyre.tir"])
