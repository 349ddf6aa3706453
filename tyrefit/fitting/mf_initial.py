"""Start values of the Magic Formula stages: Eq. 2-4 estimates per sweep mapped to MF coefficients, and the
multi-start.

Each stage of :func:`tyrefit.fitting.mf.fit_mf` is a bounded nonlinear least-squares problem whose cost has
long curved valleys (the shape factor C against the curvature E) and more than one minimum; a start near the
data's own curve is what makes the local solver find the right one, in few iterations.

Eq. 2-4 of Komana, Els and Becker per sweep (:func:`tyrefit.fitting.initial.estimate_sweep`) give C, the
peak friction D, BCD and E of every pure-slip sweep; linear regressions over the sweeps' load, pressure and
camber map them to PCX1, PDX1/PDX2/PPX3, PKX1/PKX2/PPX1, PEX1 (and the Y equivalents; PKY1 and PKY2 from
the cornering stiffness against load, K_y = PKY1 Fz0 sin(PKY4 atan(Fz / (PKY2 Fz0))) with PKY4 = 2,
Pacejka 2012 4.E25; :func:`_initial_pure`).  LMUV from the peak friction against the slip speed at the
peak (mu* = LMU / (1 + LMUV Vs/V0), 4.E7; :func:`_initial_lmuv`).  The aligning moment starts from the
pneumatic trail measured near zero slip (QDZ1, Dt0 = Fz R0/Fz0 QDZ1, 4.E42; :func:`_initial_mz`).

Multi-start as for PAC89 (:func:`_starts`): the Eq. 2-4 start, a typical shape with E = 0, a high-C high-E
start and a low-C low-E start are each run (core first, then the whole stage); the lowest cost wins and is
polished.  The combined stages and Mx start from typical magnitudes of either sign where the model is flat
at zero (SV_y_kappa, 4.E66-4.E67; the Mx sine term).

References
----------
Komana, Els, Becker, *Cost efficient tyre testing...*, Eq. 2-4; Pacejka, *Tire and Vehicle Dynamics*,
3rd ed. (2012), section 4.3.2 (typical shape factors) and equations 4.E7, 4.E25, 4.E42, 4.E66-4.E67.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import pandas as pd

from . import initial as ini
from .mf_stages import Stage

__all__: list[str] = []

_DEG = math.pi / 180.0

#: typical magnitudes of shape, stiffness and combined-slip coefficients: the multi-start's typical shape (C_x 1.6,
#: C_y 1.3, near Pacejka's 1.65 and 1.3, 2012 sec. 4.3.2) and the starts of the combined stages (RBX*, RBY*, RC*)
_TYPICAL = {"PCX1": 1.6, "PCY1": 1.3, "QCZ1": 1.2, "RCX1": 1.0, "RCY1": 1.0, "PKY4": 2.0,
            "QBZ1": 10.0, "QBZ10": 0.0, "RBX1": 12.0, "RBX2": 10.0, "RBY1": 10.0, "RBY2": 8.0}


def _regress(y, cols):
    """Least-squares coefficients of y on the columns (NaN-safe); zeros for missing."""
    X = np.column_stack([np.ones_like(y)] + list(cols))
    ok = np.all(np.isfinite(X), axis=1) & np.isfinite(y)
    if ok.sum() < X.shape[1]:
        c = np.zeros(X.shape[1])
        c[0] = float(np.nanmedian(y)) if np.isfinite(y).any() else 0.0
        return c
    c, *_ = np.linalg.lstsq(X[ok], y[ok], rcond=None)
    return c


def _initial_pure(stage: Stage, pts: pd.DataFrame, nominal: Mapping[str, float], why: dict) -> tuple[dict, pd.DataFrame, bool]:
    """Eq. 2-4 estimates per sweep mapped to the stage's MF coefficients."""
    fz0 = nominal["FNOMIN"]
    p0 = nominal.get("NOMPRES", 0.0) or 1.0
    lateral = stage.name == "Fy0"
    slip, force = ("slip_angle", "fy") if lateral else ("slip_ratio", "fx")
    scale = 180.0 / math.pi if lateral else 100.0
    est = ini.estimate_sweeps(pts, slip, force, x_scale=scale, part="lateral" if lateral else "longitudinal")
    if est.empty:
        return {}, est, False
    conds = pts.groupby("run")[["pressure", "camber"]].mean()
    est = est.drop(columns=[c for c in ("pressure",) if c in est]).join(conds[["pressure"]], on="run")
    dfz = (est["fz"].to_numpy(float) - fz0) / fz0
    pr = est["pressure"].to_numpy(float)
    dpi = np.where(np.isfinite(pr), (pr - p0) / p0, 0.0)
    good = est["has_peak"].to_numpy(bool) if est["has_peak"].any() else np.ones(len(est), bool)
    C = float(np.clip(np.median(est["C"][good]), 0.8, 2.5))
    E = float(np.clip(np.median(est["E"][good]), -3.0, 0.9))
    D = est["D"].to_numpy(float)
    cols = [dfz if np.ptp(dfz) > 0.02 else np.zeros_like(dfz), dpi if np.ptp(dpi) > 0.02 else np.zeros_like(dpi)]
    c_mu = _regress(D, cols)
    mu0 = max(float(c_mu[0]), 0.05)
    slope = est["BCD"].to_numpy(float) * scale  # d(mu)/d(slip) per rad or per unit kappa, >= 0
    out: dict[str, float] = {}
    if "LMUV" not in why:
        lmuv = _initial_lmuv(pts, est, D, cols, nominal, lateral, scale)
        if lmuv is not None:
            out["LMUV"] = lmuv
    if lateral:
        # K_y = PKY1 Fz0 sin(PKY4 atan(Fz / (PKY2 Fz0))) with PKY4 = 2 (4.E25); linear LS in PKY1 per PKY2
        ky = slope * est["fz"].to_numpy(float)
        best = (np.inf, 20.0, 2.0)
        for pky2 in np.geomspace(0.3, 20.0, 60):
            basis = fz0 * np.sin(2.0 * np.arctan(est["fz"].to_numpy(float) / (pky2 * fz0)))
            a = float(basis @ ky / max(basis @ basis, 1e-30))
            res = float(np.sum((a * basis - ky) ** 2))
            if res < best[0]:
                best = (res, pky2, a)
        _, pky2, pky1 = best
        out.update(PCY1=C, PDY1=mu0, PDY2=float(c_mu[1]) if "PDY2" not in why else 0.0,
                   PPY3=float(c_mu[2] / mu0) if "PPY3" not in why else 0.0,
                   PEY1=E, PKY1=-abs(pky1) * _orientation(pts, "slip_angle", "fy"), PKY2=float(pky2), PKY4=2.0)
    else:
        c_k = _regress(slope, cols)
        out.update(PCX1=C, PDX1=mu0, PDX2=float(c_mu[1]) if "PDX2" not in why else 0.0,
                   PPX3=float(c_mu[2] / mu0) if "PPX3" not in why else 0.0, PEX1=E,
                   PKX1=max(float(c_k[0]), 1.0), PKX2=float(c_k[1]) if "PKX2" not in why else 0.0,
                   PPX1=float(c_k[2] / max(c_k[0], 1.0)) if "PPX1" not in why else 0.0)
    return out, est, bool(est["has_peak"].any())


def _initial_lmuv(pts, est, D, cols, nominal, lateral: bool, scale: float) -> float | None:
    """LMUV from the peak friction D of the sweeps through their peak against their slip speed there.

    D = mu(dfz, dpi) / (1 + LMUV Vs/V0) (4.E7) with Vs = V |kappa_m| (drive/brake) or V |tan alpha_m|
    (cornering) at the slip of the peak; to first order D = mu0 + ... - mu0 LMUV Vs/V0, a linear regression
    over the sweeps (the load and pressure columns as for PDX1/PDY1).  None when it cannot be formed.
    """
    v0 = float(nominal.get("LONGVL") or 0.0)
    if not v0 > 0 or "x_m" not in est:
        return None
    sp = pts.groupby("run")["speed"].mean()
    v = est["run"].map(sp).to_numpy(float)
    xm = np.abs(est["x_m"].to_numpy(float)) / scale
    vs = v * (np.tan(xm) if lateral else xm) / v0
    ok = est["has_peak"].to_numpy(bool) & np.isfinite(vs) & np.isfinite(D)
    if ok.sum() < 3 or np.ptp(vs[ok]) <= 1e-3:
        return None
    c = _regress(D[ok], [cc[ok] for cc in cols] + [vs[ok]])
    if not c[0] > 0:
        return None
    return float(np.clip(-c[-1] / c[0], 0.0, 1.5))


def _orientation(pts, slip, force) -> float:
    """+1 when the force falls with slip near zero (ISO-W lateral: Fy < 0 for alpha > 0), -1 otherwise."""
    x, y = pts[slip].to_numpy(float), pts[force].to_numpy(float) / pts["fz"].to_numpy(float)
    near = np.abs(x) <= 2 * _DEG
    if near.sum() < 3 or np.ptp(x[near]) <= 0:
        near = np.abs(x) <= np.percentile(np.abs(x), 30)
    s = np.polyfit(x[near], y[near], 1)[0] if near.sum() >= 3 and np.ptp(x[near]) > 0 else -1.0
    return 1.0 if s < 0 else -1.0


def _initial_mz(pts: pd.DataFrame, nominal: Mapping[str, float]) -> dict[str, float]:
    """QDZ1 from the pneumatic trail t = -Mz/Fy near zero slip: Dt0 = Fz R0/Fz0 QDZ1 (4.E42)."""
    r0, fz0 = nominal["UNLOADED_RADIUS"], nominal["FNOMIN"]
    a = pts["slip_angle"].to_numpy(float)
    near = (np.abs(a) > 0.5 * _DEG) & (np.abs(a) < 3 * _DEG)
    fy, mz, fz = pts["fy"].to_numpy(float), pts["mz"].to_numpy(float), pts["fz"].to_numpy(float)
    ok = near & np.isfinite(fy) & np.isfinite(mz) & (np.abs(fy) > 1e-3 * fz)
    t = float(np.median(-mz[ok] / fy[ok] * fz0 / fz[ok])) if ok.sum() >= 5 else 0.02
    return {"QDZ1": float(np.clip(t / r0, 0.005, 1.0)), "QBZ1": 10.0, "QCZ1": 1.2, "QEZ1": -1.0, "QBZ10": 0.0}


def _starts(stage: Stage, c0: dict[str, float]) -> list[dict[str, float]]:
    """Multi-start points along the C-E valley (as PAC89's :func:`tyrefit.fitting.engine._starts`)."""
    if stage.name in ("Fx0", "Fy0"):
        C, E = ("PCX1", "PEX1") if stage.name == "Fx0" else ("PCY1", "PEY1")
        typ = dict(c0, **{C: _TYPICAL[C], E: 0.0})
        high = dict(c0, **{C: float(min(max(1.3 * c0[C], 1.6), 2.2)), E: 0.8})
        low = dict(c0, **{C: float(max(0.85 * c0[C], 1.05)), E: c0[E] - 1.0})
        return [c0, typ, high, low]
    if stage.name == "Mz0":
        return [c0, dict(c0, QBZ1=6.0, QCZ1=1.5, QEZ1=0.0), dict(c0, QBZ1=15.0, QCZ1=1.1, QEZ1=-3.0)]
    if stage.name == "Fx":
        return [c0, dict(c0, RBX1=25.0, RBX2=20.0, RCX1=1.0, REX1=-1.0), dict(c0, RBX1=6.0, RBX2=5.0, RCX1=1.0)]
    if stage.name == "Mx":
        # the trigonometric terms (MF 6.1 manual Mx, see tyrefit.models.mf61) from a generic shape: with
        # QSX4 = 0 the derivatives of QSX5-QSX9 vanish, so QSX4 starts non-zero (both signs)
        trig = {"QSX4": 0.5, "QSX5": 0.3, "QSX6": 1.0, "QSX7": 0.5, "QSX8": 1.0, "QSX9": 0.5, "QSX10": 0.0,
                "QSX11": 1.0}
        return [c0, dict(c0, **trig), dict(c0, **dict(trig, QSX4=-0.5))]
    if stage.name == "Fy":
        # SVy_kappa = DVy_kappa sin(RVY5 atan(RVY6 kappa)) (4.E66): with RVY1 = RVY5 = RVY6 = 0 every one of
        # their derivatives is 0, so the starts give them typical magnitudes of either sign.  RVY4 enters as
        # cos(atan(RVY4 alpha)) (4.E67), flat at RVY4 = 0 (its derivative is 0 there): from 0 the Fy stage can
        # keep the kappa-induced side force at full size at large slip angles (|RVY4| far below the published
        # values) and move the shift SHy_kappa (RHY1, RHY2) to carry it, a second minimum of higher cost
        # than the true one, which leaves Mz off near kappa = 0 at nonzero slip angle (it goes through Fy).
        # Published magnitudes 15-100: 20 starts at the low end, off the flat point
        sv = {k: v for k, v in (("RVY1", 0.02), ("RVY4", 20.0), ("RVY5", 1.9), ("RVY6", 10.0)) if k in c0}
        sv_neg = dict(sv, RVY1=-0.02) if "RVY1" in sv else sv
        return [dict(c0, **sv), dict(c0, RBY1=20.0, RBY2=15.0, RCY1=1.0, REY1=-1.0, **sv_neg),
                dict(c0, RBY1=5.0, RBY2=4.0, RCY1=1.0, **sv)]
    return [c0]
