"""The HTML report of a PAC89 fit: statistics, figures, coefficients and the per-sweep table.

Used by :class:`tyrefit.fitting.result.FitResult` (``to_html``, ``report``, ``sweeps_table``) and by
``tyrefit fit --report`` (:func:`report_blocks` appends the fit to a larger report); every function
takes the fit result first.  The report is a :class:`tyrefit.io.report.Report` (one self-contained
HTML file, figures embedded); the figures come from :mod:`tyrefit.fitting.result_figures`.

Sections, in order: the source and cost, what the tyre holds (``FitResult.model_lines``), warnings,
statistics per part (RMSE, R², the within-sweep noise floor :data:`NOISE_FLOOR_DEFINITION`, the
engine's point scatter, the Eq. 5 cost of Komana et al.), the model-over-data panels and the residuals
of each part, the coefficients (with their Eq. 2-4 start values), coefficients held as not
identifiable, constraints, pairs correlated above 0.95, the sweeps, notes.
"""

from __future__ import annotations

import html
import os
from pathlib import Path

import pandas as pd

from . import result_figures
from ..io.outputs import check_output, write_text
from ..io.report import Report

__all__ = ["report_blocks", "to_html", "write_report", "sweeps_table", "stats_rows", "coef_rows",
           "NOISE_FLOOR_DEFINITION"]

#: the one noise-floor definition of fit, diagnose and compare
NOISE_FLOOR_DEFINITION = ("pooled RMSE of a smooth curve (cubic spline, knots every 1.5 deg of slip angle / 0.03 "
                          "slip ratio, plus a load-jitter term) through each sweep on its own "
                          "(tyrefit.fitting.noise.noise_floor)")
_COST_TEXT = {"l2": "least squares on μ", "l1": "sum of absolute μ errors (Komana et al. Eq. 5)",
             "huber": "Huber loss on μ, scale 1.345 × each sweep's noise",
             "soft_l1": "soft-l1 (pseudo-Huber) loss on μ, scale 1.345 × each sweep's noise"}


def _esc(s) -> str:
    return html.escape(str(s))


def stats_rows(result) -> list[dict]:
    """The statistics table: one row per fitted part."""
    rows = []
    for name, s in result.stats.items():
        lo, hi = s["fz_range"]
        ratio = s["rmse"] / s["noise_floor"] if s["noise_floor"] > 0 else float("nan")
        rows.append({"part": name, "points": s["n"], "sweeps": s["sweeps"], "Fz range [N]": f"{lo:.0f}–{hi:.0f}",
                     "RMSE": f"{s['rmse']:.4g} {s['unit']}", "R²": s["r2"],
                     "noise floor (within-sweep)": f"{s['noise_floor']:.4g} {s['unit']}",
                     "RMSE / floor": ratio,
                     "point scatter": f"{s['point_scatter']:.3g} {s['unit']}",
                     "Eq. 5 cost Σ|Δμ|": s["eq5_cost"], "fitted coefficients": s["varied"],
                     "evaluations": s["nfev"], "time [s]": s["seconds"]})
    return rows


def coef_rows(result) -> pd.DataFrame:
    """The coefficient table: value, standard error, Eq. 2-4 start value and status of each coefficient."""
    t = result.coefficients.copy()
    return t[["name", "value", "stderr", "rel_stderr", "initial", "status"]].rename(
        columns={"rel_stderr": "stderr [%]", "initial": "Eq. 2–4 start"})


def sweeps_table(result) -> pd.DataFrame:
    """The per-sweep table in display units with unit headers (kN, deg, kPa, km/h)."""
    t = result.sweeps.copy()
    conv = {"fz": ("Fz [kN]", 1e-3), "camber": ("camber [deg]", 1.0), "slip_angle": ("slip angle [deg]", 1.0),
            "pressure": ("pressure [kPa]", 1e-3), "speed": ("speed [km/h]", 3.6)}
    cols = {}
    for c, (label, f) in conv.items():
        if c in t:
            t[c] = t[c] * f
            cols[c] = label
    for c in ("peak", "rmse", "bias", "noise"):
        if c in t:
            t[c] = t[c].astype(float)
    if "part" in t:
        t["unit"] = t["part"].map({"lateral": "N", "longitudinal": "N", "aligning": "N·m"})
    order = [c for c in ("part", "run", "n", "fz", "camber", "slip_angle", "pressure", "speed", "unit", "peak",
                         "rmse", "rmse_pct", "bias", "bias_pct", "noise") if c in t]
    t = t[order].rename(columns={**cols, "n": "points", "peak": "peak [unit]", "rmse": "RMSE [unit]",
                                 "rmse_pct": "RMSE [% of peak]", "bias": "bias [unit]",
                                 "bias_pct": "bias [% of peak]", "noise": "noise floor [unit]"})
    return t


def to_html(result) -> str:
    """HTML fragment: statistics, coefficient table, not-identifiable list, notes."""
    r = Report("PAC89 fit")
    report_blocks(result, r, figures=False)
    return "\n".join(r.blocks)


def report_blocks(result, r, figures: bool = True) -> None:
    """Append the fit to the :class:`~tyrefit.io.report.Report` ``r``: what the tyre holds, warnings, statistics,
    the figures of every part (``figures``), coefficients, holds, constraints, correlated pairs, sweeps, notes."""
    r.p(f"Source: {result.source or 'data frame'}; cost: {_COST_TEXT.get(result.cost, result.cost)}, "
        "each sweep weighted 1/n.", "note")
    r.h2("What the tyre holds")
    r.bullets(result.model_lines())
    if result.warnings:
        r.raw('<div class="warn"><b>Warnings</b><ul>' + "".join(f"<li>{_esc(w)}</li>" for w in result.warnings)
              + "</ul></div>")
    r.h2("Statistics")
    r.table(stats_rows(result))
    r.p("Noise floor (within-sweep): " + NOISE_FLOOR_DEFINITION + ". Point scatter: the engine's "
        "neighbour-difference estimate, which also counts the hysteresis between up and down branches.", "note")
    if figures:
        for part in result.parts:
            figs = result_figures.facet_figures(result, part)
            for k, fig in enumerate(figs):
                page = f" (page {k + 1} of {len(figs)})" if len(figs) > 1 else ""
                r.figure(fig, f"{part}: {result.figure_title(part)}; dots: data; one panel per condition "
                              f"level{page}")
            r.figure(result_figures.residual_figure(result, part), f"{part}: residuals (model − data) against slip, "
                                                                    "coloured by load, with the ± noise-floor band")
    r.h2("Coefficients")
    r.table(coef_rows(result), digits=6)
    if result.not_identifiable:
        r.h3("Not identifiable from these data (held at neutral values)")
        r.bullets([f"{k}: {v}" for k, v in result.not_identifiable.items()])
    if result.constraints:
        r.h3("Constraints")
        r.bullets(result.constraints)
    for part, c in result.correlations.items():
        if isinstance(c, pd.DataFrame) and not c.empty:
            strong = [(a, b, c.loc[a, b]) for i, a in enumerate(c.index) for b in c.columns[i + 1:]
                      if abs(c.loc[a, b]) > 0.95]
            if strong:
                r.p(f"{part}: strongly correlated pairs: " + ", ".join(f"{a}–{b} {v:+.3f}" for a, b, v in strong))
    r.h2("Sweeps")
    r.table(sweeps_table(result), digits=4)
    if result.notes:
        r.h3("Notes")
        r.bullets(result.notes)


def write_report(result, directory: str | os.PathLike, force: bool = False, title: str | None = None) -> Path:
    """Write ``directory/index.html`` (figures embedded) and ``sweeps.csv``; returns the HTML path."""
    d = Path(directory)
    check_output(d / "index.html", force)
    r = Report(title or f"PAC89 fit — {Path(result.source).name if result.source else 'data'}")
    report_blocks(result, r, figures=True)
    d.mkdir(parents=True, exist_ok=True)
    write_text(d / "sweeps.csv", sweeps_table(result).to_csv(index=False), force=True)
    return r.save(d, force=force)
