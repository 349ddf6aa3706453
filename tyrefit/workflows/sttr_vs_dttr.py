"""The STTR-vs-DTTR study of Komana et al.: calibrate on one tyre, predict another from static tests.

Komana, Els and Becker promise a Pacejka tyre from two days of static tests
instead of five days of field tests.  :func:`sttr_vs_dttr` checks that
promise the way it would be used:

1. calibrate Eq. 1 (:func:`tyrefit.rig.calibrate`) on a *reference* tyre
   tested on both rigs;
2. fit the *target* tyre from its static tests only -- with the calibration
   (part 'peak', the default), without it (f = 1), and with the calibration
   but the 'sliding' part -- via :func:`tyrefit.rig.prepare_static_fit` and
   :func:`tyrefit.fitting.fit_pac89`;
3. fit the target's dynamic data too (the DTTR model, what field tests give);
4. score every model against the target's dynamic data with
   :func:`tyrefit.compare.tyres.compare_tyres`: mean |dmu| / mu_peak over 0-12 deg
   per load.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field, replace

import numpy as np
import pandas as pd

from ..nomenclature import G0
from ..compare.tyres import compare_tyres
from ..fitting import fit_pac89
from ..rig import RigCalibration, StaticFitInput, calibrate, prepare_static_fit
from ..io.report import Report

__all__ = ["VARIANTS", "StudyResult", "sttr_vs_dttr"]

#: STTR model variants: name -> (use the calibration, part)
VARIANTS = {
    "sttr_calibrated": (True, "peak"),
    "sttr_uncalibrated": (False, "peak"),
    "sttr_sliding": (True, "sliding"),
}
_LABEL = {"sttr_calibrated": "STTR, calibrated Eq. 1, part 'peak'",
          "sttr_uncalibrated": "STTR, f = 1 (uncalibrated), part 'peak'",
          "sttr_sliding": "STTR, calibrated Eq. 1, part 'sliding'",
          "dttr": "DTTR fit (the target's own dynamic data)"}


@dataclass
class StudyResult:
    """Everything :func:`sttr_vs_dttr` computed.

    Attributes
    ----------
    calibration : RigCalibration
    inputs : dict of str -> StaticFitInput
        per STTR variant.
    fits : dict of str -> FitResult
        per STTR variant and ``'dttr'``.
    comparisons : dict of str -> Comparison
        ``'dttr'`` model (a) against each STTR variant (b), with the dynamic data.
    table : DataFrame
        per dynamic-test load: mean |dmu|/mu_peak [%] of every model against
        the data, and the uncalibrated / calibrated ratio.
    warnings : list of str
        range warnings raised while preparing the target's static data.
    names : dict
        ``reference`` and ``target`` labels.
    """

    calibration: RigCalibration
    inputs: dict
    fits: dict
    comparisons: dict
    table: pd.DataFrame
    warnings: list = field(default_factory=list)
    names: dict = field(default_factory=dict)
    cost: str = "l1"

    # -- verdicts ------------------------------------------------------------------------
    def checks(self, limit_pct: float = 5.0, ratio: float = 2.0) -> dict:
        """The study's acceptance numbers: calibrated STTR within ``limit_pct`` at every load and
        at least ``ratio`` times closer than the uncalibrated conversion."""
        t = self.table
        cal = t["sttr_calibrated vs data [%]"].to_numpy()
        unc = t["sttr_uncalibrated vs data [%]"].to_numpy()
        return {"worst_calibrated_pct": float(cal.max()), "within_limit": bool(np.all(cal < limit_pct)),
                "limit_pct": limit_pct, "min_ratio_uncalibrated_over_calibrated": float(np.min(unc / cal)),
                "mean_ratio": float(np.mean(unc) / np.mean(cal)),
                "at_least_ratio_closer": bool(np.mean(unc) >= ratio * np.mean(cal)), "ratio": ratio,
                "agreement_pct": float(100.0 - cal.max())}

    def summary(self) -> dict:
        c = self.checks()
        per_load = [{"load_kg": round(r["load [kg]"]), **{k: float(r[f"{k} vs data [%]"])
                                                           for k in ("sttr_calibrated", "sttr_uncalibrated",
                                                                     "sttr_sliding", "dttr")}}
                    for _, r in self.table.iterrows()]
        return {"headline": (f"tyre {self.names.get('target', 'B')} from static tests only: within "
                             f"{c['worst_calibrated_pct']:.2f} % of its dynamic data at every load "
                             f"(mean |dmu|/mu_peak, 0-12 deg; uncalibrated Eq. 1: "
                             f"{self.table['sttr_uncalibrated vs data [%]'].max():.1f} %)"),
                "calibration_n": self.calibration.n, "calibration_b": self.calibration.b,
                "per_load": per_load, **c}

    # -- report ------------------------------------------------------------------------------
    def report(self, title: str = "STTR vs DTTR: a tyre from static tests, calibrated on another"):
        """The study as a :class:`tyrefit.io.report.Report`."""
        from matplotlib.figure import Figure


        ref, tgt = self.names.get("reference", "A"), self.names.get("target", "B")
        c = self.checks()
        r = Report(title, f"Eq. 1 calibrated on tyre {ref} (tested on both rigs); tyre {tgt} fitted from its static "
                          f"(STTR) tests only and scored against its own dynamic (DTTR) data. PAC89 fits with cost "
                          f"'{self.cost}'" + (" (Komana et al. Eq. 5)." if self.cost == "l1" else "."))
        r.h2("Result")
        ok = c["within_limit"] and c["at_least_ratio_closer"]
        r.p(f"Tyre {tgt}'s STTR model (calibrated Eq. 1) is within {c['worst_calibrated_pct']:.2f} % of its "
            f"dynamic data at every dynamic-test load (mean |Δμ| / μ_peak over 0-12 deg; limit "
            f"{c['limit_pct']:g} %): it captures the DTTR measurements within {c['agreement_pct']:.1f} % "
            f"(Komana et al.'s 'within 90 %', as a number). The uncalibrated conversion (f = 1) is "
            f"{c['mean_ratio']:.1f} times further off on average (at least "
            f"{c['min_ratio_uncalibrated_over_calibrated']:.1f} times at every load).",
            cls="ok" if ok else "bad")
        tab = self.table.copy()
        r.table(tab, digits=4, caption="Mean |Δμ| / μ_peak [%] of each model against the target's dynamic data, "
                                       "0.5 deg bins over 0-12 deg")
        r.bullets([f"{k}: {_LABEL[k]}" for k in ("sttr_calibrated", "sttr_uncalibrated", "sttr_sliding", "dttr")])
        for w in self.warnings:
            r.p("Range warning (target static data vs the calibration): " + w, cls="warn")
        fig = Figure(figsize=(7, 4))
        ax = fig.subplots()
        x = tab["load [kg]"].to_numpy()
        for k, st in (("sttr_calibrated", "C0o-"), ("sttr_uncalibrated", "C3s--"), ("sttr_sliding", "C2^:"),
                      ("dttr", "k.-")):
            ax.plot(x, tab[f"{k} vs data [%]"], st, label=_LABEL[k])
        ax.axhline(c["limit_pct"], color="0.5", lw=0.8, ls="--")
        ax.set_yscale("log")
        ax.set_xlabel("load [kg]")
        ax.set_ylabel("mean |Δμ| / μ_peak vs DTTR data [%]")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
        r.figure(fig, "Error of each model against the target's dynamic data per load (log scale); dashed: the "
                      "5 % limit.")
        r.h2(f"Calibration on tyre {ref}")
        r.p(self.calibration.summary())
        r.p("Physically: a rolling tyre at slip angle alpha carries its carcass deflected sideways by y with "
            "tan(alpha) = y / sigma, sigma = C_alpha / C_y its relaxation length; n = sigma / L. f = 1 takes "
            f"sigma = L; the calibration finds sigma = {self.calibration.n:.2f} L at small displacement.")
        fig = Figure(figsize=(6.5, 4.2))
        ax = fig.subplots()
        self.calibration.plot(ax)
        r.figure(fig, "Eq. 1 with and without the calibration; shaded: the calibrated range of Delta y / L.")
        r.h2("Effect of the static part used ('peak' vs 'sliding')")
        inp = self.inputs["sttr_calibrated"]
        r.p(f"'peak' (default) fits the rising part of each push with a0, a1, a2 held at what the static test "
            f"measured directly ({', '.join(f'{k} = {v:.4g}' for k, v in inp.anchors.items())}: C from Eq. 2 with "
            "the sliding level, the peak-friction law from the static peaks). 'sliding' feeds the whole push, "
            "plateau included, to a free fit.")
        t = self.table
        r.p(f"Worst load against the dynamic data: 'peak' {t['sttr_calibrated vs data [%]'].max():.2f} %, "
            f"'sliding' {t['sttr_sliding vs data [%]'].max():.2f} %.")
        fig = Figure(figsize=(7, 4.6))
        ax = fig.subplots()
        self.inputs["sttr_sliding"].plot_converted(
            ax, [("part 'peak'", self.fits["sttr_calibrated"].tyre), ("part 'sliding'", self.fits["sttr_sliding"].tyre)])
        r.figure(fig, "Target static data converted with the calibrated Eq. 1 (all samples) and the two fitted models.")
        self.comparisons["sttr_calibrated"].report_section(
            r, title=f"Tyre {tgt}: DTTR fit (a) vs STTR model, calibrated (b), with the dynamic data")
        self.comparisons["sttr_uncalibrated"].report_section(
            r, title=f"Tyre {tgt}: DTTR fit (a) vs STTR model, uncalibrated f = 1 (b), with the dynamic data")
        inp.report_section(r, model=[("STTR calibrated", self.fits["sttr_calibrated"].tyre),
                                     ("DTTR fit", self.fits["dttr"].tyre)])
        r.h2("PAC89 coefficients")
        rows = []
        names = ["a0", "a1", "a2", "a3", "a4", "a6", "a7"]
        for k, f in self.fits.items():
            rows.append({"model": _LABEL[k], **{n: f.tyre.coefficients[n] for n in names},
                         "LATERAL_STIFFNESS [N/mm]": (f.tyre.lateral_stiffness or float("nan")) * 1e-3,
                         "VERTICAL_STIFFNESS [N/mm]": (f.tyre.vertical_stiffness or float("nan")) * 1e-3})
        r.table(rows, digits=5)
        return r


def sttr_vs_dttr(reference_static, reference_dynamic, reference_patch, target_static, target_patch,
                 target_dynamic, *, target_vertical=None, cost: str = "l1", rated_load: float | None = None,
                 names: dict | None = None) -> StudyResult:
    """Calibrate Eq. 1 on a reference tyre, fit a target tyre from static tests, score against its dynamic data.

    Parameters
    ----------
    reference_static, reference_dynamic, reference_patch : Dataset
        the reference tyre, tested on both rigs.
    target_static, target_patch : Dataset
        the target tyre's static tests.
    target_dynamic : Dataset
        the target's dynamic sweeps, used only to score (and for the DTTR fit).
    target_vertical : Dataset, optional
        the target's vertical-stiffness test.
    cost : {'l1', 'l2'}
        PAC89 fit cost ('l1' is Komana et al. Eq. 5).
    rated_load : float, optional
        FNOMIN [N] for the target.
    names : dict, optional
        ``{'reference': 'A', 'target': 'B'}``.

    Returns
    -------
    StudyResult
    """
    names = {"reference": "A", "target": "B", **(names or {})}
    cal = calibrate(reference_static, reference_dynamic, reference_patch)
    inputs: dict[str, StaticFitInput] = {}
    fits = {}
    range_msgs: list[str] = []
    for key, (use_cal, part) in VARIANTS.items():
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            inp = prepare_static_fit(target_static, target_patch, rig=cal if use_cal else None, part=part,
                                     vertical_ds=target_vertical, rated_load=rated_load)
        if key == "sttr_calibrated":
            range_msgs = [str(w.message) for w in caught]
        inputs[key] = inp
        res = fit_pac89(inp.data, cost=cost, **inp.fit_kwargs)
        fits[key] = res.with_tyre(replace(inp.with_static_design(res.tyre), name=f"tyre {names['target']} {key}"))
    dttr = fit_pac89(target_dynamic, cost=cost, tyre_info={"name": f"tyre {names['target']} dttr"})
    cal_inp = inputs["sttr_calibrated"]
    # the static tests give the stiffnesses the field test does not
    dttr = dttr.with_tyre(cal_inp.with_static_design(dttr.tyre))
    fits["dttr"] = dttr
    comparisons = {key: compare_tyres(dttr.tyre, fits[key].tyre, target_dynamic,
                                      names=("DTTR fit", _LABEL[key])) for key in VARIANTS}
    rows = []
    base = comparisons["sttr_calibrated"]
    for j, lc in enumerate(base.loads):
        row = {"load [kg]": lc.fz / G0, "Fz [kN]": lc.fz * 1e-3}
        for key in VARIANTS:
            row[f"{key} vs data [%]"] = 100 * comparisons[key].loads[j].data["mean_abs_dmu_over_peak_vs_data"][1]
        row["dttr vs data [%]"] = 100 * lc.data["mean_abs_dmu_over_peak_vs_data"][0]
        row["uncalibrated / calibrated"] = row["sttr_uncalibrated vs data [%]"] / row["sttr_calibrated vs data [%]"]
        row["C_alpha data [kN/deg]"] = lc.data["cornering_stiffness"] * 1e-3 * math.pi / 180
        row["C_alpha STTR cal [kN/deg]"] = lc.cornering_stiffness[1] * 1e-3 * math.pi / 180
        row["C_alpha STTR f=1 [kN/deg]"] = \
            comparisons["sttr_uncalibrated"].loads[j].cornering_stiffness[1] * 1e-3 * math.pi / 180
        rows.append(row)
    return StudyResult(cal, inputs, fits, comparisons, pd.DataFrame(rows), range_msgs, names, cost)
