"""Initial estimates of the PAC89 coefficients from each sweep (Komana et al., Eq. 2-4).

For every sweep (one load, camber, pressure) the measured curve gives the
Magic Formula factors directly (Komana et al., section 4.3):

* peak ``D`` and the slip ``x_m`` where it occurs, and the asymptote ``y_a``
  (the force at the largest slips tested);
* shape factor ``C = 1 +/- (1 - (2/pi) asin(y_a / D))``  (Eq. 2), with the
  ``+`` branch when the curve falls after its peak (y_a < 0.98 D: C > 1) and
  the ``-`` branch when it saturates without falling (C <= 1; the peak slip
  is then where the curve first reaches 99.5 % of its plateau);
* cornering stiffness ``BCD`` from the slope over 0-2 deg (0-2 % slip ratio),
  ``B = BCD / (C D)``  (Eq. 3);
* curvature ``E = (B x_m - tan(pi / (2 C))) / (B x_m - atan(B x_m))``  (Eq. 4).

The per-sweep values are then mapped to the PAC89 load laws: ``a0`` from C,
``a1, a2`` from D/Fz vs Fz, ``a3, a4`` from BCD vs Fz, ``a6, a7`` from E vs
Fz (and the ``b`` laws for slip-ratio sweeps).  These values only start the
global fit (:mod:`tyrefit.fitting.engine`).

Everything here works on the friction coefficient mu = F/Fz of each point
(static-rig tests have Fz falling during a sweep) and is sign-agnostic: a
sweep is folded onto positive slip (odd part) and oriented so that its
initial slope is positive, which is PAC89's convention, without assuming
the sign convention of the data.

Fallback when a sweep has no peak inside the tested range
---------------------------------------------------------
Heavy truck tyres often still rise at 12 deg.  When the smoothed curve is
still rising over the last 15 % of the tested slip (or its maximum lies in
that last 15 %), Eq. 2 and Eq. 4 have nothing to work on.  Then C takes the
typical value for the curve (1.3 lateral, 1.65 longitudinal; Pacejka 2006,
section 4.3), E = 0, and D is the value for which the Magic Formula with the
measured BCD passes through the measured force at the largest slip
(a one-dimensional root search); if no such D exists, D = 1.05 x the
largest measured force.  The sweep is flagged ``method='no peak: fallback'``.

References
----------
Komana, Els, Becker, *Cost efficient tyre testing, modelling and validation
for PBS assessments*, Eq. 2-4.  Pacejka, *Tyre and Vehicle
Dynamics*, 2nd ed. (2006), section 4.3.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
import pandas as pd
from scipy.optimize import brentq
from ..models import pac89

__all__ = [
    "SweepEstimate",
    "estimate_sweep",
    "estimate_sweeps",
    "lateral_initial",
    "longitudinal_initial",
    "aligning_initial",
    "load_levels",
    "TYPICAL_C",
]

#: typical shape factors (Pacejka 2006, section 4.3) used when a sweep shows no peak
TYPICAL_C = {"lateral": 1.3, "longitudinal": 1.65, "aligning": 2.3}
#: slope window for BCD [deg or %] (Komana et al.: "the slope between 0 and 2 deg")
SLOPE_WINDOW = 2.0
_E_MIN, _E_MAX = -10.0, 0.95


@dataclass
class SweepEstimate:
    """Magic Formula factors read off one sweep (Eq. 2-4), in mu per PAC89 slip unit.

    Attributes
    ----------
    run : int
    fz : float
        mean load of the sweep [N].
    camber : float
        mean camber [rad].
    n : int
        points in the sweep.
    D : float
        peak friction coefficient [-].
    x_m : float
        slip at the peak [deg or %].
    y_a : float
        asymptote: friction coefficient at the largest slips [-].
    C, B, E : float
        shape, stiffness [1/deg or 1/%] and curvature factors.
    BCD : float
        initial slope of mu [1/deg or 1/%] (Eq. 3).
    falls : bool
        the curve falls after its peak (Eq. 2 '+' branch).
    has_peak : bool
        a peak lies inside the tested range.
    method : str
        how C, D, E were obtained.
    """

    run: int
    fz: float
    camber: float
    n: int
    D: float
    x_m: float
    y_a: float
    C: float
    B: float
    E: float
    BCD: float
    falls: bool
    has_peak: bool
    method: str

    def as_dict(self) -> dict:
        return asdict(self)


def _smooth(y: np.ndarray, k: int) -> np.ndarray:
    if k <= 1 or len(y) < 3:
        return y
    return pd.Series(y).rolling(k, center=True, min_periods=1).mean().to_numpy()


def estimate_sweep(x, mu, *, part: str = "lateral", run: int = 0, fz: float = float("nan"),
                   camber: float = 0.0, window: float = SLOPE_WINDOW) -> SweepEstimate:
    """Eq. 2-4 estimates of one sweep.

    Parameters
    ----------
    x : array_like
        slip in PAC89 units: slip angle [deg] or slip ratio [%], either sign.
    mu : array_like
        friction coefficient F/Fz [-] at each point, either sign convention.
    part : {'lateral', 'longitudinal', 'aligning'}
        chooses the typical C of the fallback.
    window : float
        slope window for BCD [deg or %].

    Returns
    -------
    SweepEstimate
    """
    x = np.asarray(x, float)
    mu = np.asarray(mu, float)
    ok = np.isfinite(x) & np.isfinite(mu)
    x, mu = x[ok], mu[ok]
    n = len(x)
    if n < 4:
        raise ValueError("a sweep needs at least 4 points for Eq. 2-4 estimates")
    # BCD: slope of mu over |x| <= window (Komana et al., "0 to 2 deg"), with intercept
    order = np.argsort(np.abs(x))
    near = np.abs(x) <= window
    if near.sum() < 4 or np.ptp(x[near]) <= 0:
        near = np.zeros(n, bool)
        near[order[: max(4, n // 10)]] = True
    if np.ptp(x[near]) > 0:
        slope = np.polyfit(x[near], mu[near], 1)[0]
    else:  # pragma: no cover - all points at one slip
        slope = 0.0
    orient = 1.0 if slope >= 0 else -1.0
    # fold onto positive slip: odd part, oriented so the initial slope is positive
    z = np.abs(x)
    v = np.sign(x) * mu * orient
    keep = z > 0
    z, v = z[keep], v[keep]
    srt = np.argsort(z, kind="stable")
    z, v = z[srt], v[srt]
    zmax = float(z[-1]) if len(z) else 0.0
    # running mean over ~1/15 of the points, but never wider than 2 % of the slip range
    dz = float(np.median(np.diff(z))) if len(z) > 1 else 0.0
    k_span = int(0.02 * zmax / dz) if dz > 0 else len(v)
    vs = _smooth(v, max(3, min(len(v) // 15, k_span)))
    i_pk = int(np.argmax(vs))
    D, x_m = float(vs[i_pk]), float(z[i_pk])
    tail = z >= 0.9 * zmax
    y_a = float(np.mean(vs[tail])) if tail.any() else float(vs[-1])
    BCD = abs(slope)
    last = z >= 0.85 * zmax
    rising = last.sum() >= 3 and np.ptp(z[last]) > 0 and np.polyfit(z[last], vs[last], 1)[0] > 0.05 * BCD
    falls = bool(y_a < 0.98 * D and x_m < 0.9 * zmax)
    if not falls and D > 0:
        # a plateau: the peak slip is where the curve first reaches 99.5 % of its maximum
        x_m = float(z[np.argmax(vs >= 0.995 * D)])
    has_peak = bool(x_m < 0.85 * zmax and not rising)
    if has_peak and D > 0:
        # Komana et al., Eq. 2: '+' branch if the curve falls after its peak, '-' if it saturates
        s = 1.0 if falls else -1.0
        C = 1.0 + s * (1.0 - 2.0 / math.pi * math.asin(min(max(y_a / D, -1.0), 1.0)))
        C = float(np.clip(C, 0.5, 2.5))
        B = BCD / (C * D)  # Komana et al., Eq. 3
        if C > 1.0 + 1e-6 and B * x_m > 0:
            bx = B * x_m
            den = bx - math.atan(bx)
            E = (bx - math.tan(math.pi / (2.0 * C))) / den if den > 1e-9 else 0.0  # Komana et al., Eq. 4
            method = "Eq. 2-4"
        else:
            E = 0.0
            method = "Eq. 2 '-' branch, Eq. 3 (saturating; C <= 1: Eq. 4 undefined, E = 0)"
        E = float(np.clip(E, _E_MIN, _E_MAX))
    else:
        # documented fallback: no peak inside the tested range
        C = TYPICAL_C.get(part, 1.3)
        E = 0.0
        z_end, y_end = float(z[-1]), float(vs[-1])
        y_max = float(np.max(vs))

        def g(d):
            return d * math.sin(C * math.atan(BCD * z_end / (C * d))) - y_end

        D = 1.05 * y_max
        if y_end > 0 and BCD > 0:
            try:
                if g(y_end) < 0 < g(100.0 * y_end):
                    D = brentq(g, y_end, 100.0 * y_end, xtol=1e-10 * y_end)
            except ValueError:  # pragma: no cover - guarded by the sign check
                pass
        D = float(max(D, y_max))
        B = BCD / (C * D) if D > 0 else 0.0
        x_m = math.tan(math.pi / (2.0 * C)) / B if B > 0 else float("nan")
        method = "no peak: fallback"
    return SweepEstimate(run=int(run), fz=float(fz), camber=float(camber), n=int(n), D=float(D), x_m=float(x_m),
                         y_a=float(y_a), C=float(C), B=float(B), E=float(E), BCD=float(BCD), falls=bool(falls),
                         has_peak=bool(has_peak), method=method)


def estimate_sweeps(df: pd.DataFrame, x_col: str, f_col: str, *, x_scale: float, part: str = "lateral") -> pd.DataFrame:
    """Eq. 2-4 estimates of every run of ``df``.

    ``x_scale`` converts the SI slip column to PAC89 units (180/pi for slip
    angle, 100 for slip ratio).  Returns one row per run (see :class:`SweepEstimate`).
    """
    rows = []
    for run, g in df.groupby("run", sort=True):
        fz = g["fz"].to_numpy(float)
        mu = g[f_col].to_numpy(float) / fz
        cam = float(g["camber"].mean()) if "camber" in g else 0.0
        try:
            est = estimate_sweep(g[x_col].to_numpy(float) * x_scale, mu, part=part, run=run,
                                 fz=float(np.mean(fz)), camber=cam)
        except ValueError:
            continue
        rows.append(est.as_dict())
    return pd.DataFrame(rows)


def load_levels(fz, rel_tol: float = 0.04, abs_tol: float = 100.0) -> np.ndarray:
    """Cluster loads [N] into levels; returns the level index of each value.

    Two loads belong to one level when they differ by less than
    max(abs_tol, rel_tol x the largest load).
    """
    fz = np.asarray(fz, float)
    if fz.size == 0:
        return np.zeros(0, int)
    tol = max(abs_tol, rel_tol * float(np.nanmax(np.abs(fz))))
    order = np.argsort(fz)
    lev = np.zeros(fz.size, int)
    k = 0
    for a, b in zip(order[:-1], order[1:]):
        if fz[b] - fz[a] > tol:
            k += 1
        lev[b] = k
    lev[order[0]] = 0
    return lev


def _per_level(est: pd.DataFrame) -> pd.DataFrame:
    """Median estimates per load level, preferring sweeps near zero camber."""
    e = est.copy()
    if "camber" in e and (np.abs(e["camber"]) < math.radians(0.5)).any():
        e = e[np.abs(e["camber"]) < math.radians(0.5)]
    e = e.assign(level=load_levels(e["fz"].to_numpy()))
    return e.groupby("level").median(numeric_only=True).reset_index(drop=True)


def _fit_bcd_law(fzk: np.ndarray, bcd: np.ndarray, a4_default: float) -> tuple[float, float]:
    """a3, a4 of BCD = a3 sin(2 atan(Fz/a4)) by a grid over a4 with a3 in closed form."""
    if len(fzk) < 2 or np.ptp(fzk) <= 0:
        s = np.sin(2 * np.arctan(fzk / a4_default))
        return float(np.sum(s * bcd) / np.sum(s * s)), a4_default
    a4 = np.geomspace(0.2 * fzk.min(), 20.0 * fzk.max(), 300)[:, None]
    S = np.sin(2 * np.arctan(fzk[None, :] / a4))
    a3 = np.sum(S * bcd, axis=1) / np.sum(S * S, axis=1)
    sse = np.sum((a3[:, None] * S - bcd) ** 2, axis=1)
    i = int(np.argmin(sse))
    return float(a3[i]), float(a4[i, 0])


def lateral_initial(est: pd.DataFrame, *, n_levels: int | None = None) -> dict[str, float]:
    """Map per-sweep estimates to starting values of ``a0``..``a13``.

    a0 = median C of the sweeps with a peak (else the typical 1.3);
    D/Fz = a1 Fz + a2 [N/kN] by regression over load levels (a1 = 0 with one level);
    BCD = a3 sin(2 atan(Fz/a4)) by a grid search over a4 (one level: a4 = 2 x Fz);
    E = a6 Fz + a7 (a6 = 0 with fewer than 3 levels); camber and shift terms 0.
    """
    lv = _per_level(est)
    fzk = lv["fz"].to_numpy() * 1e-3
    nl = len(lv) if n_levels is None else n_levels
    peaked = est[est["has_peak"]]
    c = {f"a{i}": 0.0 for i in range(14)}
    c["a0"] = float(np.median(peaked["C"])) if len(peaked) else TYPICAL_C["lateral"]
    mu_d = lv["D"].to_numpy() * 1e3  # D/Fz in N per kN
    if nl >= 2 and np.ptp(fzk) > 0:
        c["a1"], c["a2"] = (float(v) for v in np.polyfit(fzk, mu_d, 1))
    else:
        c["a2"] = float(np.mean(mu_d))
    bcd = lv["BCD"].to_numpy() * 1e3 * fzk  # N/deg
    c["a3"], c["a4"] = _fit_bcd_law(fzk, bcd, 2.0 * float(np.max(fzk)))
    if c["a3"] < 0:  # only possible with odd data; keep PAC89's sign
        c["a3"] = abs(c["a3"])
    lvp = lv[lv["has_peak"] > 0.5] if "has_peak" in lv else lv
    if len(lvp) >= 3 and np.ptp(lvp["fz"]) > 0:
        c["a6"], c["a7"] = (float(v) for v in np.polyfit(lvp["fz"].to_numpy() * 1e-3, lvp["E"].to_numpy(), 1))
    else:
        c["a7"] = float(np.median(peaked["E"])) if len(peaked) else 0.0
    c["a7"] = min(c["a7"], 0.95 - max(c["a6"] * fzk.min(), c["a6"] * fzk.max(), 0.0))
    return c


def longitudinal_initial(est: pd.DataFrame, *, n_levels: int | None = None) -> dict[str, float]:
    """Starting values of ``b0``..``b10`` from per-sweep estimates.

    b0 = median C; D/Fz = b1 Fz + b2; BCD/Fz = b3 Fz + b4 (b5 = 0);
    E = b8 (b6 = b7 = 0); shifts 0.
    """
    lv = _per_level(est)
    fzk = lv["fz"].to_numpy() * 1e-3
    nl = len(lv) if n_levels is None else n_levels
    peaked = est[est["has_peak"]]
    c = {f"b{i}": 0.0 for i in range(11)}
    c["b0"] = float(np.median(peaked["C"])) if len(peaked) else TYPICAL_C["longitudinal"]
    mu_d = lv["D"].to_numpy() * 1e3
    bcd_per_fz = lv["BCD"].to_numpy() * 1e3  # BCD/Fz [N/% per kN]
    if nl >= 2 and np.ptp(fzk) > 0:
        c["b1"], c["b2"] = (float(v) for v in np.polyfit(fzk, mu_d, 1))
    else:
        c["b2"] = float(np.mean(mu_d))
    if nl >= 3 and np.ptp(fzk) > 0:
        c["b3"], c["b4"] = (float(v) for v in np.polyfit(fzk, bcd_per_fz, 1))
    else:
        c["b4"] = float(np.mean(bcd_per_fz))
    c["b8"] = float(np.clip(np.median(peaked["E"]) if len(peaked) else 0.0, _E_MIN, _E_MAX))
    return c


def aligning_initial(df: pd.DataFrame, x_scale: float) -> dict[str, float]:
    """Starting values of ``c0``..``c17`` from lateral sweeps with ``mz``.

    The aligning moment rises to a peak at a few degrees and falls through zero,
    so Eq. 2-4 (written for forces) do not apply; the start is the typical
    shape C = 2.3, D/Fz = c2 from the peak |Mz|/Fz, |BCD|/Fz = |c4| from the
    0-2 deg slope, E = c9 = -1.  The sign of c4 is chosen by evaluating the
    model (:func:`tyrefit.models.pac89.aligning_moment`) so that its initial
    slope has the sign of the data's; no sign convention is assumed here.
    """
    c = {f"c{i}": 0.0 for i in range(18)}
    peaks, slopes, fzs = [], [], []
    for _, g in df.groupby("run"):
        fz = g["fz"].to_numpy(float)
        x = g["slip_angle"].to_numpy(float) * x_scale
        m = g["mz"].to_numpy(float) / (fz * 1e-3)  # N*m per kN
        near = np.abs(x) <= SLOPE_WINDOW
        if near.sum() >= 3 and np.ptp(x[near]) > 0:
            slopes.append(np.polyfit(x[near], m[near], 1)[0])
        peaks.append(np.max(np.abs(m)))
        fzs.append(float(np.mean(fz)))
    c["c0"] = TYPICAL_C["aligning"]
    c["c2"] = float(np.median(peaks)) if peaks else 1.0
    slope = float(np.median(slopes)) if slopes else -1.0
    c["c4"] = abs(slope) if slope != 0 else 1.0
    c["c9"] = -1.0
    fz0 = float(np.median(fzs)) if fzs else 4000.0
    probe = float(pac89.aligning_moment(c, fz0, 0.5 / x_scale) - pac89.aligning_moment(c, fz0, -0.5 / x_scale))
    if np.sign(probe) != np.sign(slope):
        c["c4"] = -c["c4"]
    return c
