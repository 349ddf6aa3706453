"""The tyre contract as constraints of the Magic Formula stages: factors, the friction ceiling, penalty terms.

A Magic Formula set can fit its sweeps well and still be unphysical where the sweeps do not look: a negative
peak friction or slip stiffness at a load or camber between the measured ones, a curvature E > 1 (the curve
turns back), a combined-slip weight that adds force.  A simulator evaluates the tyre everywhere in the
declared range, so the stages of :func:`tyrefit.fitting.mf.fit_mf` hold these conditions over a grid of that
range (:func:`_grid`) as penalty residuals ``10 sqrt(n_sweeps) max(0, margin - c)``, zero wherever the
constraint holds, so a fit that never approaches a boundary is unchanged by them; after the fit every
constraint is checked on the grid (:func:`_check_constraints`) and a violation is reported
(``FitResultMF.constraints``).

Physical constraints, over the fitted range
-------------------------------------------
C > 0 (PCX1, PCY1, QCZ1, RCX1, RCY1 bounded below); E <= 1 (PEX1, PEY1,
REX1, REY1 bounded above).  Over a grid of the fitted load (5 levels),
pressure (3) and camber (3) range and both slip signs, the peak friction
mu_x, mu_y > 0, the curvatures E_x, E_y <= 1 and the slip stiffnesses K_x,
K_y (with the data's sign) > 0, the combined-slip B > 0 and E <= 1, and
one lobe of the kappa-induced side force SV_yk = DV_yk sin(RVY5 atan(RVY6
kappa)) on each side of kappa = 0 over the data's slip-ratio range
(|RVY5 atan(RVY6 kappa_max)| <= pi, :data:`SVYK_LOBE`: slip-ratio samples
0.01 apart do not rule out a phase-wrapped alias that swings through the
opposite lobe between them) are held.  The factor formulas are those of
Pacejka (2012) 4.E11-4.E30, 4.E54-4.E66 (:func:`_factors`).

The pure-slip peak friction is also held below a ceiling the data allow (:func:`_mu_ceiling`, :data:`MU_CAP`):
a sweep that stops short of its peak shows only a lower bound on the friction, and a shape that never peaks
inside the data would otherwise carry any friction at all.

The terms of :mod:`tyrefit.tyres.contract` that need the model itself (:func:`_contract_terms`, on a grid made
once per problem by :func:`_contract_grid`): the aligning moment aligns the wheel at 2-4 deg (Mz Fy < 0), and
the combined-slip weights G_xa (4.E51), G_yk (4.E59) stay >= 0.

References
----------
Pacejka, *Tire and Vehicle Dynamics*, 3rd ed. (2012), equations 4.E11-4.E66.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..tyres.contract import ALIGN_DEG, G_TOL, slip_grid
from . import mf_parts
from .mf_data import condition_levels
from .mf_eval import _mf61
from .mf_stages import Stage

__all__ = ["SVYK_LOBE", "MU_CAP", "MU_CAP_FACTOR", "MuCeiling"]

_DEG = math.pi / 180.0

#: the kappa-induced side force SV_yk = DV_yk sin(RVY5 atan(RVY6 kappa)) (Pacejka 2012, 4.E66) is one lobe on
#: each side of kappa = 0: it rises with |kappa|, may fall past its peak (|RVY5| > 1), but keeps the sign of
#: DV_yk kappa over the fitted slip-ratio range, i.e. the sine's argument stays within +-pi there.  Published
#: sets: RVY5 1.8-2.03, |RVY6| 10-50 (MFeval's MF 6.1 example -1.7992 / -27.5155; others 1.9 / 10, 1.91 / 16.5,
#: 1.89 / 23.8, 2.03 / 15.8, 1.95 / -50), an argument <= 3.03 rad even at |kappa| = 1.  Without the constraint
#: slip-ratio samples 0.01 apart do not rule out a phase-wrapped alias, RVY5 ~ 2 x 1.8 with |RVY6| ~ 150 and DV_yk
#: of the other sign: it meets the generating curve at every sample but swings through the opposite lobe
#: between kappa = 0 and +-0.01 (|RVY5 atan(RVY6 0.2)| = 5.5 rad).  A staged Fy fit can land on that alias:
#: it fits the samples, but between them (near kappa = +-0.005 in the alpha = 0 sweeps) its Fy, and the Mx
#: computed from Fy, are off the true curve.  This constraint bounds |RVY5 atan(RVY6 kappa)| by pi over the
#: fitted slip ratios, which keeps the fit in the published range of RVY5 and RVY6.  Its penalty is zero
#: wherever it holds, so a fit that never approaches the alias is unchanged by it.
SVYK_LOBE = "SV_yk one lobe per kappa sign (|RVY5 atan(RVY6 kappa)| <= pi)"


def _factors(p: Mapping[str, float], stage: str, fz, dpi, gamma, sgn, kappa=None, cap=None):
    """Constraint quantities (Pacejka 2012): (name, value, margin) of stage ``stage`` on a grid.

    Fx0: mu_x (4.E13) > 0, E_x (4.E14) <= 1, K_x/Fz (4.E15) > 0.
    Fy0: mu_y (4.E23) > 0, E_y (4.E24) <= 1, sign * K_y/Fz0 (4.E25) > 0.
    Combined: B_xa (4.E54), B_yk (4.E62) > 0; E_xa (4.E56), E_yk (4.E64) <= 1.
    Fy (combined), given ``kappa`` (the ends of the fitted slip-ratio range, :func:`_grid`): the kappa-induced
    side force SV_yk = DV_yk sin(RVY5 atan(RVY6 kappa)) (4.E66) is one lobe on each side of kappa = 0,
    |RVY5 atan(RVY6 kappa)| <= pi (see :data:`SVYK_LOBE`).
    Fx0, Fy0 given ``cap`` (the peak-friction ceiling at each grid load, :func:`_mu_ceiling`): |mu| <= cap.
    Mz0: the trail curvature E_t (4.E44) <= 1 with its atan term at the bound +-1 (QEZ4, QEZ5).
    Values are dimensionless; a constraint holds when ``value >= margin``.
    """
    g = p.get
    fz0 = float(g("FNOMIN", 1.0)) * float(g("LFZO", 1.0))
    dfz = (fz - fz0) / fz0
    out = []
    if stage == "Fx0":
        mux = (g("PDX1", 1) + g("PDX2", 0) * dfz) * (1 + g("PPX3", 0) * dpi + g("PPX4", 0) * dpi**2) \
            * (1 - g("PDX3", 0) * gamma**2)
        ex = (g("PEX1", 0) + g("PEX2", 0) * dfz + g("PEX3", 0) * dfz**2) * (1 - g("PEX4", 0) * sgn)
        kx = (g("PKX1", 20) + g("PKX2", 0) * dfz) * np.exp(np.clip(g("PKX3", 0) * dfz, -50, 50)) \
            * (1 + g("PPX1", 0) * dpi + g("PPX2", 0) * dpi**2)
        out += [("mu_x > 0", mux, 0.02), ("E_x <= 1", 1.0 - ex, 0.0), ("K_x > 0", kx, 0.1)]
        if cap is not None:
            out.append((MU_CAP.format(axis="x"), cap - np.abs(mux), 0.0))
    elif stage == "Fy0":
        muy = (g("PDY1", 1) + g("PDY2", 0) * dfz) * (1 + g("PPY3", 0) * dpi + g("PPY4", 0) * dpi**2) \
            * (1 - g("PDY3", 0) * gamma**2)
        ey = (g("PEY1", 0) + g("PEY2", 0) * dfz) * (1 + g("PEY5", 0) * gamma**2
                                                   - (g("PEY3", 0) + g("PEY4", 0) * gamma) * sgn)
        den = (g("PKY2", 1) + g("PKY5", 0) * gamma**2) * (1 + g("PPY2", 0) * dpi) * fz0
        ky = g("PKY1", -20) * (1 + g("PPY1", 0) * dpi) * (1 - g("PKY3", 0) * np.abs(gamma)) \
            * np.sin(g("PKY4", 2) * np.arctan(fz / np.where(np.abs(den) > 1e-9, den, 1e-9)))
        s = -1.0 if g("PKY1", -20) < 0 else 1.0  # the data's orientation is fixed by PKY1's sign
        out += [("mu_y > 0", muy, 0.02), ("E_y <= 1", 1.0 - ey, 0.0), ("K_y > 0 (data's sign)", s * ky, 0.1)]
        if cap is not None:
            out.append((MU_CAP.format(axis="y"), cap - np.abs(muy), 0.0))
    elif stage == "Mz0":
        et = g("QEZ1", 0) + g("QEZ2", 0) * dfz + g("QEZ3", 0) * dfz**2
        bound = np.abs(g("QEZ4", 0) + g("QEZ5", 0) * gamma)
        out.append(("E_t <= 1", 1.0 - np.maximum(et * (1 + bound), et * (1 - bound)), 0.01))
    elif stage == "Fx":
        out += [("B_xa > 0", (g("RBX1", 0) + g("RBX3", 0) * gamma**2) + 0 * fz, 0.0),
                ("E_xa <= 1", 1.0 - (g("REX1", 0) + g("REX2", 0) * dfz), 0.0)]
    elif stage == "Fy":
        out += [("B_yk > 0", (g("RBY1", 0) + g("RBY4", 0) * gamma**2) + 0 * fz, 0.0),
                ("E_yk <= 1", 1.0 - (g("REY1", 0) + g("REY2", 0) * dfz), 0.0)]
        if kappa is not None:
            phase = np.abs(g("RVY5", 0) * np.arctan(g("RVY6", 0) * kappa))
            out.append((SVYK_LOBE, (math.pi - phase) + 0 * fz, 0.0))
    return out


#: the peak-friction ceiling (:func:`_mu_ceiling`)
MU_CAP = "mu_{axis} <= 1.15 x the data's peak |F|/Fz"
#: the ceiling's factor over the largest |F|/Fz a sweep through its peak shows
MU_CAP_FACTOR = 1.15


def _mu_ceiling(pts: pd.DataFrame, est: pd.DataFrame, force: str):
    """The largest peak friction the data allow at each load: a function of Fz [N] (None without a peak).

    Every sweep through its peak (``est.has_peak``, Eq. 2-4) shows its friction, the largest |F|/Fz of the
    sweep; the ceiling at a load L is :data:`MU_CAP_FACTOR` x the largest of those at loads up to 1.1 L
    (friction falls with load, Pacejka 2012 4.E13/4.E23: a heavier load never grips more than a lighter
    one did), and unbounded below the lightest sweep through its peak.  A sweep that stops short of its
    peak shows only a lower bound; a shape that never peaks inside the data (C at its bound, D growing
    with the slip) would otherwise carry any friction at all (mu_x 4.6 where the data reach 2.4).
    """
    if est is None or est.empty or "has_peak" not in est or not est["has_peak"].any():
        return None
    d = pts[np.isfinite(pts[force].to_numpy(float))]
    mu = (d[force].abs() / d["fz"].abs()).groupby(d["run"]).quantile(0.995)
    e = est[est["has_peak"].astype(bool)]
    fz_s = e["fz"].to_numpy(float)
    mu_s = e["run"].map(mu).to_numpy(float)
    ok = np.isfinite(fz_s) & np.isfinite(mu_s)
    fz_s, mu_s = fz_s[ok], mu_s[ok]
    if not fz_s.size:
        return None

    return MuCeiling(fz_s, mu_s)


@dataclass(frozen=True)
class MuCeiling:
    """The peak-friction ceiling of :func:`_mu_ceiling`: ``ceiling(fz)`` [-] at loads ``fz`` [N]."""

    fz: np.ndarray  # loads of the sweeps through their peak [N]
    mu: np.ndarray  # their largest |F|/Fz

    def steps(self) -> np.ndarray:
        """The loads where the ceiling steps (each sweep's load / 1.1), and just below them: where a straight
        friction-load law meets it first."""
        s = self.fz / 1.1
        return np.concatenate([s, s * (1 - 1e-6)])

    def __call__(self, fz):
        fz = np.asarray(fz, float)
        seen = self.fz[None, :] <= 1.1 * fz[..., None]
        best = np.max(np.where(seen, self.mu[None, :], -np.inf), axis=-1)
        return np.where(np.isfinite(best), MU_CAP_FACTOR * best, 1e6)


def _grid(pts: pd.DataFrame, nominal: Mapping[str, float], env: Mapping | None = None, loads=()):
    """Grid of the declared range: 5 loads (and ``loads`` inside it) x 3 pressures x 3 cambers x both slip signs.

    ``env`` is the envelope the file will declare (:meth:`MFData.envelope`: every record's loads, cambers
    and pressures), so the stage holds its constraints wherever a simulator may evaluate the tyre, not
    only over its own sweeps' loads (E_x 1.002 at 536 N, a cornering-only load below the drive/brake
    sweeps, had been written); without it the stage's points' range.
    Returns (Fz, dpi, camber, sign, kappa): ``kappa`` is the slip ratio at the end of the data's range on the
    grid point's side (sign x the largest |slip ratio| of the points; 0 for cornering sweeps).
    """
    if env is not None:
        lo, hi = env["fz"]
        prr = env.get("pressure")
        pr = np.asarray(prr if prr is not None else (), float)
        cam = np.asarray(env["camber"], float)
    else:
        fz = pts["fz"].to_numpy(float)
        lo, hi = np.percentile(fz, [1, 99]) if fz.size else (1.0, 1.0)
        pr = pts["pressure"].to_numpy(float)
        pr = pr[np.isfinite(pr)]
        cam = pts["camber"].to_numpy(float)
    extra = np.asarray([x for x in loads if lo <= x <= hi], float)
    fzg = np.unique(np.concatenate([np.linspace(lo, hi, 5), extra]))
    p0 = float(nominal.get("NOMPRES", 0.0)) or 1.0
    dpig = (np.linspace(pr.min(), pr.max(), 3) - p0) / p0 if pr.size and p0 > 0 else np.zeros(1)
    camg = np.linspace(cam.min(), cam.max(), 3) if cam.size else np.zeros(1)
    F, P, G, S = np.meshgrid(fzg, dpig, camg, np.array([-1.0, 1.0]), indexing="ij")
    k = pts["slip_ratio"].to_numpy(float) if "slip_ratio" in pts else np.zeros(0)
    k = k[np.isfinite(k)]
    kmax = float(np.max(np.abs(k))) if k.size else 0.0
    return F.ravel(), P.ravel(), G.ravel(), S.ravel(), kmax * S.ravel()


def _contract_grid(stage: Stage, pts: pd.DataFrame, nominal: Mapping[str, float], version: str,
                   base: Mapping[str, float]):
    """Inputs of the contract terms that need the model itself (:func:`_contract_terms`), made once per problem.

    Mz0: 2, 3, 4 deg of slip angle of both signs at 5 loads x 3 pressures of the fitted range, camber nearest 0.
    Fx, Fy (combined): 3 loads x 3 cambers x the fitted slip-angle range (9 points and the small angles
    within 1 deg) x the slip-ratio range (9 points and those within 0.02), with the model's inputs prepared
    once (:func:`tyrefit.models.mf61._prepare`; the stage varies none of what they depend on).
    """
    if stage.name not in ("Mz0", "Fx", "Fy") or not len(pts):
        return None
    fz = pts["fz"].to_numpy(float)
    fzg = np.linspace(*np.percentile(fz, [1, 99]), 5 if stage.name == "Mz0" else 3)
    if stage.name == "Mz0":
        pr = pts["pressure"].to_numpy(float)
        pr = pr[np.isfinite(pr)]
        prg = np.unique(np.linspace(pr.min(), pr.max(), 3)) if pr.size else np.array([np.nan])
        a = pts["slip_angle"].to_numpy(float)
        amax = float(np.max(np.abs(a))) if a.size else 0.0
        ang = np.array([s * d * _DEG for d in ALIGN_DEG for s in (1.0, -1.0) if d * _DEG <= amax + 1e-9])
        if not ang.size:
            return None
        cam = pts["camber"].to_numpy(float)
        g0 = float(cam[np.argmin(np.abs(cam))]) if cam.size else 0.0
        F, P, A = (x.ravel() for x in np.meshgrid(fzg, prg, ang, indexing="ij"))
        # Fy at a small slip angle has the sign of K_y alpha, K_y of PKY1's sign (4.E25): aligning is Mz Fy < 0
        sign_fy = np.sign(float(base.get("PKY1", -1.0))) * np.sign(A)
        parts = _bound_parts(base, version, F, 0.0 * F, A, np.full_like(F, g0), None if np.all(np.isnan(P)) else P,
                             ("fy0", "mz0"))
        return dict(parts, scale=-sign_fy / (F * float(nominal.get("UNLOADED_RADIUS", 0.3))))
    lv = condition_levels(pts.groupby("run")[["fz", "camber", "pressure", "speed", "slip_angle"]].mean())
    cam = np.unique(np.linspace(min(lv["camber"] or [0.0]), max(lv["camber"] or [0.0]), 3))
    a, k = pts["slip_angle"].to_numpy(float), pts["slip_ratio"].to_numpy(float)
    al = slip_grid(min(np.min(a), 0.0), max(np.max(a), 0.0), 9, 1.0 * _DEG)
    ka = slip_grid(min(np.min(k), 0.0), max(np.max(k), 0.0), 9, 0.02)
    F, G, A, K = (x.ravel() for x in np.meshgrid(fzg, cam, al, ka, indexing="ij"))
    return dict(_bound_parts(base, version, F, K, A, G, None, ("gxa" if stage.name == "Fx" else "gyk",)),
                ones=np.ones_like(F))


def _bound_parts(base, version, fz, kappa, alpha, gamma, pressure, groups) -> dict:
    """The model's inputs at a grid, prepared once (:class:`tyrefit.fitting.mf_parts.Forces`), and the names of
    the coefficients of ``groups`` whose values each evaluation takes from the parameter set."""
    f = mf_parts.Forces(version, fz, kappa, alpha, gamma, pressure, None)
    f.bind(dict(base))
    v52 = f.b0.v52
    return {"forces": f, "names": [k for k in f.c0 if mf_parts.group(k, v52) in groups]}


def _grid_coefficients(cg, p):
    """(c, b) of the grid ``cg`` (:func:`_bound_parts`) at the parameter set ``p``."""
    return cg["forces"].coefficients([(k, p[k]) for k in cg["names"] if k in p])


def _contract_terms(p: Mapping[str, float], stage: str, cg) -> list:
    """The contract's terms that need the model (:mod:`tyrefit.tyres.contract`), as (name, value, margin).

    Mz0: the aligning moment aligns the wheel at 2-4 deg (Mz Fy < 0: value -sign(Fy) Mz / (Fz R0)).
    Fx, Fy: the combined-slip weights G_xa (4.E51), G_yk (4.E59) >= 0 (a shape factor RCX1, RCY1 > 1 can
    carry the cosine past pi/2 at large slip).  G <= 1 is held by the shifts
    (:data:`tyrefit.fitting.mf_identify.COMBINED_SHIFTS`, held at 0).
    """
    if cg is None:
        return []
    mf = _mf61()
    c, b = _grid_coefficients(cg, p)
    if stage == "Mz0":  # Mz0 = -t0 Fy0(gamma = 0) + Mzr0 (4.E31), as tyrefit.models.mf61.mz0
        fyp = mf._fy0_parts(c, b)
        fy_g0 = fyp["fy0"] if not np.any(b.gstar) else mf._fy0_parts(c, b, zero_camber=True)["fy0"]
        mz, _, _ = mf._mz(c, b, mf._mz_parts(c, b, fyp), fy_g0, 0.0, 0.0, fyp["fy0"])
        return [("Mz aligns at 2-4 deg (Mz Fy < 0)", cg["scale"] * mz, 1e-3)]
    if stage in ("Fx", "Fy"):
        if stage == "Fx":
            return [("G_xa >= 0", np.asarray(mf._gxa(c, b), float), 0.0)]
        gyk, _ = mf._gyk(c, b, cg["ones"])
        return [("G_yk >= 0", np.asarray(gyk, float), 0.0)]
    return []


def _check_constraints(stage: Stage, p, grid, cgrid=None) -> list[dict]:
    """Every constraint of ``stage`` (:func:`_factors`, :func:`_contract_terms`) at the parameter set ``p`` on the
    grid the stage held it over: one dict per constraint (stage, constraint, worst value, margin, holds).

    A constraint with a margin m holds when its worst value is >= m/2 (the penalty acts below m, and a fit that
    balances it against the data may stop short of m); one without a margin, when its worst value is >= -G_TOL
    (the contract's tolerance, :mod:`tyrefit.tyres.contract`)."""
    out = []
    for name, v, m in _factors(p, stage.name, *grid) + _contract_terms(p, stage.name, cgrid):
        v = np.asarray(v, float)
        worst = float(np.min(v)) if v.size else float("nan")
        out.append({"stage": stage.name, "constraint": name, "worst": worst, "margin": m,
                    "holds": bool(worst >= 0.5 * m - 1e-9) if m > 0 else bool(worst >= -G_TOL)})
    return out
