"""The camber brush model (Zhang et al. 2024) against PAC89: where the Magic Formula cannot follow.

:func:`compare_brush_pac89` evaluates the lateral force Fy(alpha, gamma, Fz)
of the improved camber brush model (2N strips, :func:`tyrefit.models.brush.camber_brush_forces`)
and of the original, symmetric brush (:func:`tyrefit.models.brush.brush_forces`)
on a rig-like grid (loads x cambers -6..6 deg x slip angles -12..12 deg,
free rolling, no noise), fits PAC89 to each with :func:`tyrefit.fitting.fit_pac89`
and measures where PAC89 cannot follow the brush physics:

* the error of the fit per load and camber [N and % of the sweep's peak],
  and the error of a PAC89 fitted to one load alone (the curve *shape*,
  without the load laws);
* the camber thrust at zero slip, brush against PAC89, with the brush's
  linear-limit value ``-K_yg sin(gamma)`` from Eq. 20 summed over the strips;
* the cornering stiffness against camber: the brush's (strip loads move to
  the leaning shoulder, strip lengths change) against PAC89's ``BCD (1 - a5 |gamma|)``;
* the camber stiffness against load: Eq. 20, ``K_yg = 2 a^3 k / (3 R_e)``
  (rising like ``Fz^(3 a2)`` as the half-length grows, ``a ~ q^a2``), against
  PAC89's ``BCD a8 + a11 Fz`` (the horizontal shift a8 gamma and the vertical
  shift a11 Fz gamma);
* the camber effect at the largest slip, where the brush slides over (nearly)
  the whole patch and its camber term has faded (Eq. 22) while a11 Fz gamma has not.

Everything here is computed from the models; the grid is synthetic.  Figures
are functions of a :class:`BrushComparison` that take ``ax=None`` and return
the Axes; :meth:`BrushComparison.report_section` writes the whole comparison
into a :class:`tyrefit.io.report.Report`.

References
----------
Zhang, Zhu, Zhou, Chen, Liu (2024), *Estimation of road adhesion coefficient
based on camber brush model*, World Electr. Veh. J. 15, 263,
Eq. 1-30 (Eq. 20 camber and cornering stiffness, Eq. 22 the camber term).
Bakker, Nyborg, Pacejka (1989), the PAC89 lateral force (a5, a8, a11).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..models import brush as bm, pac89
from ..fitting import fit_pac89

__all__ = ["ModelComparison", "BrushComparison", "compare_brush_pac89", "LATERAL_VARY",
           "plot_sweeps", "plot_rmse", "plot_camber_thrust", "plot_cornering_stiffness", "plot_camber_stiffness"]

_DEG = np.pi / 180.0
#: PAC89 lateral coefficients fitted to the brush forces (the brush is mirror symmetric: no ply-steer or
#: conicity shifts a9, a10, a12, a13)
LATERAL_VARY = ("a0", "a1", "a2", "a3", "a4", "a5", "a6", "a7", "a8", "a11")
_H_ALPHA = 1e-4  # rad, central differences of the cornering stiffness
_H_GAMMA = 1e-4  # rad, central differences of the camber stiffness
_MODELS = {"improved": "improved camber brush (2N strips)", "original": "original brush (symmetric)"}


@dataclass
class ModelComparison:
    """One brush model against its PAC89 fit.

    Attributes
    ----------
    model : str
        ``'improved'`` (2N-strip camber brush) or ``'original'`` (one symmetric brush).
    data : DataFrame
        The grid: ``run``, ``fz`` [N], ``camber`` [rad], ``slip_angle`` [rad],
        ``fy`` [N] (brush, ISO-W), ``fy_pac89`` [N] (the fitted PAC89).
    coefficients : dict
        PAC89 a0..a13 of the global fit (PAC89 units).
    cells : DataFrame
        One row per load x camber: ``fz`` [N], ``camber_deg``, ``peak_N`` (largest
        |Fy| of the brush sweep), ``rmse_N``, ``rmse_pct`` (of the peak),
        ``max_err_N`` and ``slip_at_max_err_deg``; ``fy0_brush_N``, ``fy0_pac89_N``
        (force at zero slip, the camber thrust), ``fy0_eq20_N`` (``-sum K_yg,i
        sin(gamma)`` of the strips at this camber: the brush's linear limit);
        ``ky_brush``, ``ky_pac89`` [N/deg] (-dFy/dalpha at zero slip) and
        ``ky_pac89_formula`` (BCD (1 - a5 |gamma|)); ``dfy_sat_brush_N``,
        ``dfy_sat_pac89_N`` (Fy at the largest slip minus Fy there at zero camber:
        what is left of the camber effect where the brush (nearly) all slides).
    loads : DataFrame
        One row per load: ``fz`` [N]; ``kyg_eq20`` [N/rad] (Eq. 20 summed over
        the strips at zero camber), ``kyg_brush`` [N/rad] (-dFy/d sin(gamma) of the
        brush at zero slip and camber, numerically), ``kyg_pac89`` [N/rad]
        (``(BCD a8 + a11 Fz) 180/pi``), ``kyg_pac89_a11_share`` (the part PAC89
        puts in the vertical shift that never fades); ``ky0_brush``,
        ``ky0_pac89`` [N/deg] at zero camber; ``rmse_N``, ``rmse_pct`` of the
        global fit at this load; ``rmse_single_N``, ``rmse_single_pct`` of a
        PAC89 fitted to this load alone (shape and camber terms, no load law).
    fit : FitResult
        The global PAC89 fit (coefficients, notes, statistics).
    single : dict
        Load [N] -> PAC89 coefficients fitted to that load alone.
    """

    model: str
    data: pd.DataFrame
    coefficients: dict
    cells: pd.DataFrame
    loads: pd.DataFrame
    fit: object
    single: dict = field(default_factory=dict)

    @property
    def label(self) -> str:
        return _MODELS[self.model]

    @property
    def rmse(self) -> float:
        """RMSE of the global PAC89 fit over the grid [N]."""
        r = self.data["fy_pac89"] - self.data["fy"]
        return float(np.sqrt(np.mean(r**2)))

    @property
    def rmse_pct(self) -> float:
        """RMSE of the global fit as % of the largest peak force of the grid."""
        return 100.0 * self.rmse / float(self.cells["peak_N"].max())

    def exponent(self, column: str) -> float:
        """Power-law exponent of a per-load column against load (least squares in log-log)."""
        t = self.loads
        y = np.abs(t[column].to_numpy(float))
        return float(np.polyfit(np.log(t["fz"].to_numpy(float)), np.log(y), 1)[0])


@dataclass
class BrushComparison:
    """The camber brush model and the original brush against PAC89 (see :func:`compare_brush_pac89`).

    Attributes
    ----------
    params : BrushParams
        Brush parameters of the improved model (and of the original, unless
        ``original_params`` was given).
    improved, original : ModelComparison
        ``original`` is None when not asked for.
    pressure : float
        Inflation pressure [Pa].
    mu : float
        Road friction coefficient [-].
    n : int
        Half the number of strips.
    """

    params: bm.BrushParams
    improved: ModelComparison
    original: ModelComparison | None
    pressure: float
    mu: float
    n: int
    seconds: float = 0.0

    @property
    def models(self) -> list[ModelComparison]:
        return [m for m in (self.improved, self.original) if m is not None]

    def findings(self) -> list[str]:
        """Where PAC89 cannot follow the camber brush model, in words, with the measured numbers."""
        m = self.improved
        c, L = m.cells, m.loads
        out = []
        p_ky, p_kyg = m.exponent("ky0_brush"), m.exponent("kyg_eq20")
        notes = " ".join(m.fit.notes)
        bound = "a4 ended at its upper bound" in notes
        lo, hi = L.iloc[0], L.iloc[-1]
        out.append(
            f"Cornering-stiffness load law: the brush's K_y = 2 a^2 k grows like Fz^{p_ky:.2f} (the half-length "
            f"grows with the line load, a ~ q^{self.params.a2:g}); PAC89's a3 sin(2 atan(Fz/a4)) is concave and "
            f"at most linear in Fz"
            + (" (the fit drives a4 to its upper bound: a straight line)" if bound else "")
            + f". At {lo.fz / 1e3:.1f} kN PAC89 has {lo.ky0_pac89:.0f} N/deg against {lo.ky0_brush:.0f}, at "
            f"{hi.fz / 1e3:.1f} kN {hi.ky0_pac89:.0f} against {hi.ky0_brush:.0f} N/deg.")
        z = c[c["camber_deg"].abs() < 1e-9]
        out.append(
            f"Curve shape: fitted to one load at a time PAC89 stays within {L['rmse_single_pct'].max():.1f} % of "
            f"the peak (zero-camber sweeps of the global fit: {z['rmse_pct'].min():.1f}-{z['rmse_pct'].max():.1f} %); "
            f"the global fit's larger errors ({L['rmse_pct'].min():.1f}-{L['rmse_pct'].max():.1f} % per load) "
            "come from the load laws. The brush saturates at mu Fz where the whole patch slides (no peak, no "
            "fall-off), which the Magic Formula only approaches"
            + (" (E held at 0: the fitter sees no peak)" if "no sweep reaches its peak" in notes else "") + ".")
        out.append(
            f"Camber stiffness (Eq. 20): K_yg = 2 a^3 k/(3 R_e) grows like Fz^{p_kyg:.2f} "
            f"({lo.kyg_eq20 * _DEG:.0f} N/deg at {lo.fz / 1e3:.1f} kN, {hi.kyg_eq20 * _DEG:.0f} at "
            f"{hi.fz / 1e3:.1f} kN); PAC89's BCD a8 + a11 Fz gives {lo.kyg_pac89 * _DEG:.0f} and "
            f"{hi.kyg_pac89 * _DEG:.0f} N/deg (a8 = {m.coefficients['a8']:.3g} deg/deg, "
            f"a11 = {m.coefficients['a11']:.3g} N/(kN deg)).")
        gmax = float(c["camber_deg"].abs().max())
        g6 = c[np.isclose(c["camber_deg"].abs(), gmax)]
        g0 = c[c["camber_deg"].abs() < 1e-9].set_index("fz")
        gain_b = 100 * (g6.groupby("fz")["ky_brush"].mean() / g0["ky_brush"] - 1)
        gain_p = 100 * (g6.groupby("fz")["ky_pac89"].mean() / g0["ky_pac89"] - 1)
        a5 = m.coefficients["a5"]
        out.append(
            f"Cornering stiffness against camber: at {gmax:.0f} deg the brush's K_y changes by "
            f"{gain_b.iloc[0]:+.1f} % at {lo.fz / 1e3:.1f} kN and {gain_b.iloc[-1]:+.1f} % at {hi.fz / 1e3:.1f} kN "
            f"(the patch narrows and the load moves to the leaning shoulder, whose strips get longer), smoothly "
            f"and evenly in "
            f"gamma; PAC89 has one factor 1 - a5 |gamma| = {100 * (-a5 * gmax):+.1f} % for every load "
            f"(a5 = {a5:.3g}/deg), with a kink at zero camber, and with the shift a8 gamma moving the curve its "
            f"slope at zero slip changes by {gain_p.min():+.1f} to {gain_p.max():+.1f} %.")
        top = c[c["fz"] == c["fz"].max()]
        same = top[np.isclose(top["camber_deg"], gmax)].iloc[0]
        opp = top[np.isclose(top["camber_deg"], -gmax)].iloc[0]
        out.append(
            f"Camber at the largest slip ({np.degrees(m.data['slip_angle'].max()):.0f} deg, where the patch of "
            f"the heaviest load has (nearly) all slid), {hi.fz / 1e3:.1f} kN: the brush keeps "
            f"{abs(same.dfy_sat_brush_N):.0f} N of its {abs(same.fy0_brush_N):.0f} N camber thrust where camber "
            f"and slip push the same way ({gmax:+.0f} deg) and {abs(opp.dfy_sat_brush_N):.0f} N where they oppose "
            f"({-gmax:+.0f} deg, the camber deflection delays full sliding): Eq. 22, only the adhering part keeps "
            f"its camber deflection. PAC89 keeps {abs(same.dfy_sat_pac89_N):.0f} N and "
            f"{abs(opp.dfy_sat_pac89_N):.0f} N (a11 Fz gamma is a vertical shift that never fades; "
            f"{100 * lo.kyg_pac89_a11_share:.0f} % of its camber stiffness is in a11).")
        if self.original is not None:
            o = self.original
            dky = o.cells.groupby("fz")["ky_brush"].agg(lambda v: 100 * (v.max() / v.min() - 1)).max()
            out.append(
                f"Original brush (one symmetric brush, same parameters): no width effects, so its K_y changes "
                f"by {dky:.2f} % at most with camber and its K_yg = 2 a^3 k/(3 R_e) from the mean line load grows "
                f"like Fz^{o.exponent('kyg_eq20'):.2f}; PAC89 follows it with RMSE {o.rmse:.0f} N "
                f"({o.rmse_pct:.1f} % of the largest peak) against {m.rmse:.0f} N ({m.rmse_pct:.1f} %) for the "
                "improved model.")
        return out

    def to_dict(self) -> dict:
        """JSON-ready summary."""
        out = {"pressure": self.pressure, "mu": self.mu, "strips": 2 * self.n, "params": self.params.as_dict(),
               "findings": self.findings()}
        for m in self.models:
            out[m.model] = {"rmse_N": m.rmse, "rmse_pct_of_peak": m.rmse_pct,
                            "coefficients": {k: float(v) for k, v in m.coefficients.items()},
                            "ky_exponent": m.exponent("ky0_brush"), "kyg_exponent": m.exponent("kyg_eq20"),
                            "loads": m.loads.to_dict("records"), "cells": m.cells.to_dict("records"),
                            "notes": list(m.fit.notes)}
        return out

    # -- figures --------------------------------------------------------------------------------
    def plot_sweeps(self, fz: float | None = None, model: str = "improved", ax=None):
        return plot_sweeps(self, fz, model, ax=ax)

    def plot_rmse(self, ax=None):
        return plot_rmse(self, ax=ax)

    def plot_camber_thrust(self, ax=None):
        return plot_camber_thrust(self, ax=ax)

    def plot_cornering_stiffness(self, ax=None):
        return plot_cornering_stiffness(self, ax=ax)

    def plot_camber_stiffness(self, ax=None):
        return plot_camber_stiffness(self, ax=ax)

    # -- report ---------------------------------------------------------------------------------
    def report_section(self, report, figures: bool = True):
        """Add the comparison to a :class:`tyrefit.io.report.Report` (heading, findings, tables, figures).

        Returns the report.
        """
        from matplotlib.figure import Figure

        m = self.improved
        r = report
        r.h2("Camber brush model vs PAC89")
        r.p(f"Fy(alpha, gamma, Fz) of the improved camber brush model (Zhang et al. 2024, {2 * self.n} strips, "
            f"tyrefit.models.brush defaults unless stated) at {len(m.loads)} loads "
            f"({', '.join(f'{v / 1e3:.1f}' for v in m.loads['fz'])} kN), cambers "
            f"{', '.join(f'{v:g}' for v in sorted(m.cells['camber_deg'].unique()))} deg and slip angles to "
            f"+/-{np.degrees(m.data['slip_angle'].abs().max()):.0f} deg, {self.pressure / 1e3:.0f} kPa, "
            f"mu = {self.mu:g}, no noise; PAC89 fitted with tyrefit.fitting.fit_pac89 "
            f"({', '.join(LATERAL_VARY)}). Global fit: RMSE {m.rmse:.0f} N ({m.rmse_pct:.1f} % of the largest "
            "peak)." + (f" The original brush model (one symmetric brush, same parameters): RMSE "
                        f"{self.original.rmse:.0f} N ({self.original.rmse_pct:.1f} %)." if self.original else ""))
        r.h3("Where PAC89 cannot follow")
        r.bullets(self.findings())
        r.h3("Per load")
        rows = []
        for mc in self.models:
            for _, t in mc.loads.iterrows():
                rows.append({"model": mc.model, "Fz [kN]": t.fz / 1e3, "K_y brush [N/deg]": t.ky0_brush,
                             "K_y PAC89 [N/deg]": t.ky0_pac89, "K_yg Eq. 20 [N/deg]": t.kyg_eq20 * _DEG,
                             "K_yg brush [N/deg]": t.kyg_brush * _DEG, "K_yg PAC89 [N/deg]": t.kyg_pac89 * _DEG,
                             "a11 share [%]": 100 * t.kyg_pac89_a11_share, "RMSE [N]": t.rmse_N,
                             "RMSE [% peak]": t.rmse_pct, "one-load fit RMSE [% peak]": t.rmse_single_pct})
        r.table(rows, digits=4, caption="K_y: cornering stiffness at zero camber; K_yg: camber stiffness at zero "
                                        "slip and camber (Eq. 20 summed over the strips; the brush numerically; "
                                        "PAC89 BCD a8 + a11 Fz); a11 share: part of PAC89's K_yg in the vertical "
                                        "shift a11 Fz gamma, which does not fade with sliding.")
        r.h3("Per load and camber (improved model)")
        cols = {"fz": "Fz [N]", "camber_deg": "camber [deg]", "rmse_N": "RMSE [N]", "rmse_pct": "RMSE [% peak]",
                "max_err_N": "max |error| [N]", "slip_at_max_err_deg": "at slip [deg]",
                "fy0_brush_N": "Fy(0) brush [N]", "fy0_eq20_N": "Fy(0) Eq. 20 [N]", "fy0_pac89_N": "Fy(0) PAC89 [N]",
                "ky_brush": "K_y brush [N/deg]", "ky_pac89": "K_y PAC89 [N/deg]",
                "dfy_sat_brush_N": "camber at max slip, brush [N]", "dfy_sat_pac89_N": "camber at max slip, PAC89 [N]"}
        r.table(m.cells[list(cols)].rename(columns=cols), digits=4)
        if figures:
            fig = Figure(figsize=(11, 3.8))
            axes = fig.subplots(1, 2)
            loads = m.loads["fz"].to_numpy()
            self.plot_sweeps(loads[0], ax=axes[0])
            self.plot_sweeps(loads[-1], ax=axes[1])
            fig.tight_layout()
            r.figure(fig, "Brush lateral force (points) and the PAC89 fit (lines) at the lowest and highest load, "
                          "one colour per camber.")
            fig = Figure(figsize=(11, 3.8))
            axes = fig.subplots(1, 2)
            self.plot_rmse(ax=axes[0])
            self.plot_camber_thrust(ax=axes[1])
            fig.tight_layout()
            r.figure(fig, "Left: RMSE of the PAC89 fit per sweep, % of the sweep's peak (solid improved model, "
                          "dashed original). Right: camber thrust at zero slip: brush (points), Eq. 20 linear "
                          "limit (dotted), PAC89 (lines).")
            fig = Figure(figsize=(11, 3.8))
            axes = fig.subplots(1, 2)
            self.plot_cornering_stiffness(ax=axes[0])
            self.plot_camber_stiffness(ax=axes[1])
            fig.tight_layout()
            r.figure(fig, "Left: cornering stiffness against camber, brush (points) and PAC89 (lines). Right: "
                          "camber stiffness against load: Eq. 20 for both brush models and what PAC89 makes of "
                          "it (BCD a8 + a11 Fz, and its a11 part).")
        r.h3("PAC89 coefficients of the fits")
        r.table([{"coefficient": k, **{mc.model: mc.coefficients.get(k, 0.0) for mc in self.models}}
                 for k in LATERAL_VARY], digits=5)
        notes = [f"{mc.model}: {n}" for mc in self.models for n in mc.fit.notes]
        if notes:
            r.bullets(notes)
        return r


# --- evaluation ----------------------------------------------------------------------------------
def _brush_fy(model: str, p: bm.BrushParams, fz, alpha, gamma, pressure, mu, n):
    if model == "improved":
        return bm.camber_brush_forces(p, fz, 0.0, alpha, gamma, pressure, mu, n=n).fy
    return bm.brush_forces(p, fz, 0.0, alpha, gamma, pressure, mu).fy


def _eq20(model: str, p: bm.BrushParams, fz, gamma, pressure, n):
    st = bm.strip_states(p, fz, pressure, gamma, n) if model == "improved" else bm.original_state(p, fz, pressure)
    return bm.camber_stiffness(st)  # Zhang et al., Eq. 20, summed over the strips


def _compare_model(model, p, loads, cambers, slips, pressure, mu, n, vary, single_fits) -> ModelComparison:
    F, G, A = np.meshgrid(loads, cambers, slips, indexing="ij")
    run = np.broadcast_to(np.arange(F.shape[0] * F.shape[1]).reshape(F.shape[:2])[..., None], F.shape)
    fy = _brush_fy(model, p, F, A, G, pressure, mu, n)
    df = pd.DataFrame({"run": run.ravel() + 1, "fz": F.ravel(), "camber": G.ravel(), "slip_angle": A.ravel(),
                       "fy": fy.ravel()})
    res = fit_pac89(df[["run", "fz", "camber", "slip_angle", "fy"]], vary=list(vary))
    coef = dict(res.tyre.coefficients)
    df["fy_pac89"] = pac89.lateral_force(coef, df["fz"], df["slip_angle"], df["camber"])
    single = {}
    if single_fits:
        for L in loads:
            sub = df[df["fz"] == L]
            single[float(L)] = dict(fit_pac89(sub[["run", "fz", "camber", "slip_angle", "fy"]],
                                              vary=list(vary)).tyre.coefficients)

    # per cell
    fz_c, g_c = F[:, :, 0], G[:, :, 0]
    err = (df["fy_pac89"] - df["fy"]).to_numpy().reshape(F.shape)
    peak = np.abs(fy).max(-1)
    imax = np.abs(err).argmax(-1)

    def brush(alpha, gamma):
        return _brush_fy(model, p, fz_c, alpha, gamma, pressure, mu, n)

    def pac(alpha, gamma):
        return pac89.lateral_force(coef, fz_c, alpha, gamma)

    fy0_b, fy0_p = brush(0.0, g_c), pac(0.0, g_c)
    ky_b = -(brush(_H_ALPHA, g_c) - brush(-_H_ALPHA, g_c)) / (2 * _H_ALPHA) * _DEG
    ky_p = -(pac(_H_ALPHA, g_c) - pac(-_H_ALPHA, g_c)) / (2 * _H_ALPHA) * _DEG
    _, fac = pac89.lateral_force(coef, fz_c, 0.0, g_c, return_factors=True)
    B, C, D = fac.B, fac.C, fac.D
    amax = float(np.abs(slips).max())
    sat_b = brush(amax, g_c) - brush(amax, 0.0 * g_c)
    sat_p = pac(amax, g_c) - pac(amax, 0.0 * g_c)
    cells = pd.DataFrame({
        "fz": fz_c.ravel(), "camber_deg": np.round(np.degrees(g_c.ravel()), 6),
        "peak_N": peak.ravel(), "rmse_N": np.sqrt(np.mean(err**2, -1)).ravel(),
        "rmse_pct": (100 * np.sqrt(np.mean(err**2, -1)) / peak).ravel(),
        "max_err_N": np.take_along_axis(err, imax[..., None], -1)[..., 0].ravel(),
        "slip_at_max_err_deg": np.degrees(slips[imax]).ravel(),
        "fy0_brush_N": fy0_b.ravel(), "fy0_eq20_N": (-_eq20(model, p, fz_c, g_c, pressure, n) * np.sin(g_c)).ravel(),
        "fy0_pac89_N": fy0_p.ravel(), "ky_brush": ky_b.ravel(), "ky_pac89": ky_p.ravel(),
        "ky_pac89_formula": (B * C * D).ravel(),
        "dfy_sat_brush_N": sat_b.ravel(), "dfy_sat_pac89_N": sat_p.ravel()})

    # per load
    L = np.asarray(loads, float)
    z = np.zeros_like(L)
    kyg_b = -(_brush_fy(model, p, L, 0.0, _H_GAMMA, pressure, mu, n)
              - _brush_fy(model, p, L, 0.0, -_H_GAMMA, pressure, mu, n)) / (2 * np.sin(_H_GAMMA))
    _, f0 = pac89.lateral_force(coef, L, 0.0, z, return_factors=True)
    bcd0 = f0.B * f0.C * f0.D  # N/deg
    a8_part, a11_part = bcd0 * coef["a8"], coef["a11"] * L * 1e-3  # N/deg per deg of camber
    ky0_b = -(_brush_fy(model, p, L, _H_ALPHA, z, pressure, mu, n)
              - _brush_fy(model, p, L, -_H_ALPHA, z, pressure, mu, n)) / (2 * _H_ALPHA) * _DEG
    ky0_p = -(pac89.lateral_force(coef, L, _H_ALPHA, z) - pac89.lateral_force(coef, L, -_H_ALPHA, z)) \
        / (2 * _H_ALPHA) * _DEG
    rm = np.sqrt(np.mean(err**2, axis=(1, 2)))
    rows = []
    for i, load in enumerate(L):
        single_rmse = np.nan
        if single:
            sub = df[df["fz"] == load]
            r1 = pac89.lateral_force(single[float(load)], sub["fz"], sub["slip_angle"], sub["camber"]) - sub["fy"]
            single_rmse = float(np.sqrt(np.mean(r1**2)))
        tot = a8_part[i] + a11_part[i]
        rows.append({"fz": float(load), "kyg_eq20": float(_eq20(model, p, load, 0.0, pressure, n)),
                     "kyg_brush": float(kyg_b[i]), "kyg_pac89": float(tot / _DEG),
                     "kyg_pac89_a11_share": float(a11_part[i] / tot) if tot != 0 else np.nan,
                     "ky0_brush": float(ky0_b[i]), "ky0_pac89": float(ky0_p[i]), "rmse_N": float(rm[i]),
                     "rmse_pct": float(100 * rm[i] / peak[i].max()), "rmse_single_N": single_rmse,
                     "rmse_single_pct": float(100 * single_rmse / peak[i].max())})
    return ModelComparison(model=model, data=df, coefficients=coef, cells=cells, loads=pd.DataFrame(rows), fit=res,
                           single=single)


def compare_brush_pac89(params: bm.BrushParams = bm.DEFAULT_PARAMS,
                        loads=(2000.0, 3500.0, 5000.0, 6500.0, 8000.0),
                        camber_deg=(-6.0, -4.0, -2.0, 0.0, 2.0, 4.0, 6.0),
                        slip_max_deg: float = 12.0, n_slip: int = 49, pressure: float | None = None,
                        mu: float = 1.0, n: int = 10, original: bool = True,
                        original_params: bm.BrushParams | None = None, single_fits: bool = True,
                        vary=LATERAL_VARY) -> BrushComparison:
    """Fit PAC89 to the camber brush model (and the original brush) and measure where it cannot follow.

    Parameters
    ----------
    params : BrushParams
        Brush parameters [SI] (default :data:`tyrefit.models.brush.DEFAULT_PARAMS`,
        a plausible 205/55R16 chosen by tyrefit).
    loads : sequence of float
        Normal loads [N] (one set of sweeps each).
    camber_deg : sequence of float
        Inclination angles [deg], ISO-W.
    slip_max_deg : float
        Sweeps run from -slip_max_deg to +slip_max_deg [deg].
    n_slip : int
        Points per sweep.
    pressure : float, optional
        Inflation pressure [Pa]; default ``params.p_ref``.
    mu : float
        Road friction coefficient [-].
    n : int
        Half the number of strips of the improved model.
    original : bool
        Also compare the original (symmetric, one-brush) model.
    original_params : BrushParams, optional
        Parameters of the original model (default ``params``: the same tyre
        without the width effects; :func:`tyrefit.fitting.brush.calibrate_original`
        gives one calibrated on the improved model).
    single_fits : bool
        Also fit PAC89 to each load alone (separates the curve shape from the load laws).
    vary : sequence of str
        PAC89 coefficients fitted (default :data:`LATERAL_VARY`).

    Returns
    -------
    BrushComparison

    Examples
    --------
    >>> cmp = compare_brush_pac89(loads=(3000.0, 6000.0), camber_deg=(0.0, 4.0), original=False)
    >>> bool(cmp.improved.rmse_pct < 10)
    True
    """
    import time

    t0 = time.perf_counter()
    pressure = params.p_ref if pressure is None else float(pressure)
    loads = np.asarray(loads, float)
    cambers = np.radians(np.asarray(camber_deg, float))
    slips = np.radians(np.linspace(-slip_max_deg, slip_max_deg, n_slip))
    imp = _compare_model("improved", params, loads, cambers, slips, pressure, mu, n, vary, single_fits)
    orig = (_compare_model("original", original_params or params, loads, cambers, slips, pressure, mu, n, vary,
                           single_fits) if original else None)
    return BrushComparison(params=params, improved=imp, original=orig, pressure=pressure, mu=float(mu), n=int(n),
                           seconds=time.perf_counter() - t0)


# --- figures --------------------------------------------------------------------------------------
def _ax(ax, size=(5.5, 3.8)):
    from matplotlib.figure import Figure

    if ax is None:
        ax = Figure(figsize=size).subplots()
    return ax


def _colours(k):
    import matplotlib

    cmap = matplotlib.colormaps["viridis"]
    return [cmap(i / max(k - 1, 1)) for i in range(k)]


def plot_sweeps(cmp: BrushComparison, fz: float | None = None, model: str = "improved", ax=None):
    """Brush Fy against slip angle (points) and the PAC89 fit (lines) at one load, per camber; returns the Axes."""
    ax = _ax(ax)
    m = cmp.improved if model == "improved" else cmp.original
    d = m.data
    loads = np.unique(d["fz"])
    fz = loads[len(loads) // 2] if fz is None else loads[np.argmin(np.abs(loads - fz))]
    d = d[d["fz"] == fz]
    cams = np.unique(d["camber"])
    for col, g in zip(_colours(len(cams)), cams):
        s = d[d["camber"] == g]
        ax.plot(np.degrees(s["slip_angle"]), s["fy"], "o", ms=2.5, color=col, label=f"{np.degrees(g):+.0f} deg")
        ax.plot(np.degrees(s["slip_angle"]), s["fy_pac89"], "-", lw=1.0, color=col)
    ax.set_xlabel("slip angle [deg]")
    ax.set_ylabel("Fy [N] (ISO-W)")
    ax.set_title(f"{m.label}, Fz {fz / 1e3:.1f} kN: brush (points), PAC89 (lines)", fontsize=9)
    ax.legend(fontsize=6.5, ncol=2, title="camber", title_fontsize=7)
    return ax


def plot_rmse(cmp: BrushComparison, ax=None):
    """RMSE of the PAC89 fit, % of each sweep's peak, against camber per load; returns the Axes."""
    ax = _ax(ax)
    loads = cmp.improved.loads["fz"].to_numpy()
    cols = _colours(len(loads))
    for m, style in zip(cmp.models, ("-o", "--s")):
        for col, L in zip(cols, loads):
            c = m.cells[m.cells["fz"] == L]
            ax.plot(c["camber_deg"], c["rmse_pct"], style, ms=3, color=col,
                    label=f"{L / 1e3:.1f} kN" if m.model == "improved" else None)
    ax.set_xlabel("camber [deg]")
    ax.set_ylabel("RMSE [% of peak]")
    ax.set_title("PAC89 fit error per sweep (solid improved, dashed original)", fontsize=9)
    ax.legend(fontsize=6.5, ncol=2)
    return ax


def plot_camber_thrust(cmp: BrushComparison, ax=None):
    """Fy at zero slip against camber per load: brush, Eq. 20 linear limit, PAC89; returns the Axes."""
    ax = _ax(ax)
    m = cmp.improved
    loads = m.loads["fz"].to_numpy()
    for col, L in zip(_colours(len(loads)), loads):
        c = m.cells[m.cells["fz"] == L]
        ax.plot(c["camber_deg"], c["fy0_brush_N"], "o", ms=3.5, color=col, label=f"{L / 1e3:.1f} kN")
        ax.plot(c["camber_deg"], c["fy0_eq20_N"], ":", color=col)
        ax.plot(c["camber_deg"], c["fy0_pac89_N"], "-", lw=1.0, color=col)
    ax.set_xlabel("camber [deg]")
    ax.set_ylabel("Fy at zero slip [N]")
    ax.set_title("camber thrust: brush (points), Eq. 20 (dotted), PAC89 (lines)", fontsize=9)
    ax.legend(fontsize=6.5)
    return ax


def plot_cornering_stiffness(cmp: BrushComparison, ax=None):
    """Cornering stiffness against camber per load, brush vs PAC89; returns the Axes."""
    ax = _ax(ax)
    m = cmp.improved
    loads = m.loads["fz"].to_numpy()
    for col, L in zip(_colours(len(loads)), loads):
        c = m.cells[m.cells["fz"] == L]
        ax.plot(c["camber_deg"], c["ky_brush"], "o", ms=3.5, color=col, label=f"{L / 1e3:.1f} kN")
        ax.plot(c["camber_deg"], c["ky_pac89"], "-", lw=1.0, color=col)
    ax.set_xlabel("camber [deg]")
    ax.set_ylabel("cornering stiffness [N/deg]")
    ax.set_yscale("log")
    ax.set_title("K_y vs camber: brush (points), PAC89 (lines)", fontsize=9)
    ax.legend(fontsize=6.5)
    return ax


def plot_camber_stiffness(cmp: BrushComparison, ax=None):
    """Camber stiffness against load: Eq. 20 (both brush models) vs PAC89 (BCD a8 + a11 Fz); returns the Axes."""
    ax = _ax(ax)
    for m, mk in zip(cmp.models, ("o", "s")):
        t = m.loads
        kn = t["fz"] / 1e3
        ax.plot(kn, t["kyg_eq20"] * _DEG, mk + "-", ms=4, color="C0" if m.model == "improved" else "C2",
                label=f"Eq. 20, {m.model} (Fz^{m.exponent('kyg_eq20'):.2f})")
        if m.model == "improved":
            ax.plot(kn, t["kyg_pac89"] * _DEG, "-", color="C3", label="PAC89 BCD a8 + a11 Fz")
            ax.plot(kn, t["kyg_pac89"] * _DEG * t["kyg_pac89_a11_share"], "--", color="C3", lw=0.9,
                    label="PAC89 a11 Fz part (never fades)")
    ax.set_xlabel("normal load Fz [kN]")
    ax.set_ylabel("camber stiffness K_yg [N/deg]")
    ax.set_title("camber stiffness at zero slip and camber", fontsize=9)
    ax.legend(fontsize=6.5)
    return ax
