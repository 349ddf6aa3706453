"""Signature views: the plot that shows an effect best.

Each sweep is reduced to a few characteristics (cornering stiffness, force at
zero slip, peak friction coefficient, slip at the peak) computed the same way
from the measurements and from a model evaluated at the measured points; a
signature view plots one characteristic against the condition the effect acts
on (load, camber, pressure, speed), data as points, the model before the
effect dashed and after it solid.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from ..io.facets import _decimals, format_condition, format_load
from ..io.levels import group_levels

__all__ = ["sweep_characteristics", "SignatureView", "SIGNATURES", "plot"]

_DEG = np.pi / 180.0


def _smooth(y: np.ndarray, k: int = 5) -> np.ndarray:
    if len(y) < k:
        return y
    kernel = np.ones(k) / k
    pad = k // 2
    yp = np.concatenate([np.full(pad, y[0]), y, np.full(pad, y[-1])])
    return np.convolve(yp, kernel, mode="valid")


def sweep_characteristics(sweep, fz, slip_angle, fy, camber=None, pressure=None, speed=None) -> pd.DataFrame:
    """Per-sweep characteristics of a lateral-force sweep.

    Parameters
    ----------
    sweep : array_like of int
        Sweep id per point.
    fz, fy : array_like
        Normal load and lateral force [N] (ISO-W).
    slip_angle : array_like
        Slip angle [rad] (ISO-W).
    camber, pressure, speed : array_like, optional
        [rad], [Pa], [m/s].

    Returns
    -------
    DataFrame
        One row per sweep: ``sweep``, ``fz`` [N], ``camber`` [rad], ``pressure``
        [Pa], ``speed`` [m/s] (means), ``stiffness`` [N/rad] (-dFy/dalpha within
        +/-1 deg of zero slip where there are 5 points, positive for a normal tyre), ``fy0`` [N] (Fy at zero slip from
        the same local line), ``peak_mu`` [-] (mean over the two sides of the
        largest |Fy|/Fz, smoothed over 5 points), ``slip_at_peak`` [rad],
        ``camber_stiffness`` [N/deg] (-fy0 per degree of sin(camber), NaN
        below 0.5 deg of camber; positive when the tyre pushes towards its lean).
    """
    sweep = np.asarray(sweep)
    cols = {"fz": fz, "slip_angle": slip_angle, "fy": fy, "camber": camber, "pressure": pressure, "speed": speed}
    arrs = {k: (np.asarray(v, dtype=float) if v is not None else np.full(len(sweep), np.nan)) for k, v in cols.items()}
    rows = []
    order = np.argsort(sweep, kind="stable")
    bounds = np.flatnonzero(np.diff(sweep[order])) + 1
    for idx in np.split(order, bounds):
        if len(idx) == 0:
            continue
        a = arrs["slip_angle"][idx]
        y = arrs["fy"][idx]
        z = arrs["fz"][idx]
        srt = np.argsort(a, kind="stable")
        a, y, z = a[srt], y[srt], z[srt]
        row = {"sweep": int(sweep[idx[0]]), "fz": float(np.mean(z)), "camber": float(np.mean(arrs["camber"][idx])),
               "pressure": float(np.mean(arrs["pressure"][idx])), "speed": float(np.mean(arrs["speed"][idx]))}
        stiff = fy0 = np.nan
        for lim in (1.0, 1.5, 3.0):
            m = np.abs(a) <= lim * _DEG
            if m.sum() >= 5 and np.ptp(a[m]) > 0:
                slope, icpt = np.polyfit(a[m], y[m], 1)
                stiff, fy0 = -slope, icpt
                break
        row["stiffness"] = float(stiff)
        row["fy0"] = float(fy0)
        # camber stiffness: zero-slip thrust per degree of inclination, ISO-W sign flipped so a tyre
        # that pushes towards its lean is positive (only for sweeps at |camber| >= 0.5 deg)
        g = row["camber"]
        row["camber_stiffness"] = float(-fy0 / (np.sin(g) / _DEG)) if np.isfinite(g) and abs(g) >= 0.5 * _DEG \
            else np.nan
        mus, slips = [], []
        ys = _smooth(y)
        for side in (1.0, -1.0):
            m = side * a > 0.5 * _DEG
            if m.sum() >= 3:
                mu = -side * ys[m] / z[m]
                j = int(np.argmax(mu))
                mus.append(mu[j])
                slips.append(abs(a[m][j]))
        row["peak_mu"] = float(np.mean(mus)) if mus else np.nan
        row["slip_at_peak"] = float(np.mean(slips)) if slips else np.nan
        # side difference: |Fy| on the positive minus the negative slip side at equal |slip| (3-8 deg, around
        # and past the peak), less the zero-slip force's share (a shift moves both sides by -fy0)
        grid = np.linspace(3.0, 8.0, 11) * _DEG
        if a.min() < -grid[-1] and a.max() > grid[-1]:
            pos = np.interp(grid, a, -ys)
            neg = np.interp(-grid, a, ys)
            row["side_difference"] = float(np.median(pos - neg))
        else:
            row["side_difference"] = np.nan
        rows.append(row)
    return pd.DataFrame(rows)


@dataclass
class SignatureView:
    """Per-sweep characteristics of the data and of two models at the same points.

    ``data``, ``before``, ``after``: DataFrames from :func:`sweep_characteristics`;
    ``rated_load`` [N] (drawn on load views); labels for the legend.
    """

    data: pd.DataFrame
    before: pd.DataFrame
    after: pd.DataFrame
    rated_load: float | None = None
    before_label: str = "before"
    after_label: str = "after"


# characteristic, x condition -> (column, factor to display unit, label)
_Y = {"peak_mu": (1.0, "peak friction coefficient |Fy|/Fz [-]"),
      "stiffness": (_DEG, "cornering stiffness [N/deg]"),
      "fy0": (1.0, "Fy at zero slip angle [N]"),
      "slip_at_peak": (1 / _DEG, "slip angle at the peak [deg]"),
      "camber_stiffness": (1.0, "camber stiffness -Fy(0)/gamma [N/deg]"),
      "side_difference": (1.0, "|Fy(+alpha)| - |Fy(-alpha)| at 3-8 deg [N]")}
_X = {"fz": (1e-3, "normal load Fz [kN]"), "camber": (1 / _DEG, "camber [deg]"),
      "pressure": (1e-3, "inflation pressure [kPa]"), "speed": (3.6, "speed [km/h]")}

#: signature key -> (characteristic, x condition)
SIGNATURES: dict[str, tuple[str, str]] = {
    "peak_mu_vs_fz": ("peak_mu", "fz"),
    "stiffness_vs_fz": ("stiffness", "fz"),
    "slip_at_peak_vs_fz": ("slip_at_peak", "fz"),
    "fy0_vs_camber": ("fy0", "camber"),
    "camber_stiffness_vs_fz": ("camber_stiffness", "fz"),
    "fy0_vs_fz": ("fy0", "fz"),
    "side_difference_vs_fz": ("side_difference", "fz"),
    "stiffness_vs_pressure": ("stiffness", "pressure"),
    "peak_mu_vs_pressure": ("peak_mu", "pressure"),
    "peak_mu_vs_speed": ("peak_mu", "speed"),
}


def _levels(v: pd.Series, tol: float) -> pd.Series:
    """Snap per-sweep condition values to their set-point level (for grouping).

    Levels by :func:`tyrefit.io.levels.group_levels`: sorted values start a new
    level where the gap to the previous value exceeds ``tol`` and 5 % of the
    range; each value maps to its level's mean.  A value not recorded (NaN)
    takes the highest level's mean, as the sorted NaN closed the last group
    before the grouping moved to ``group_levels``.
    """
    if v.isna().all():
        return v
    vals = v.to_numpy(dtype=float)
    _, level = group_levels(vals, tol, 0.05, relative_to="range")
    level = np.where(level < 0, level.max(), level)
    order = np.argsort(vals)  # the mean of each level summed in ascending order, as pandas did before
    means = pd.Series(vals[order]).groupby(level[order]).transform("mean").to_numpy()
    out = np.empty_like(vals)
    out[order] = means
    return pd.Series(out, index=v.index)


_TOL = {"fz": 200.0, "camber": 0.25 * _DEG, "pressure": 5e3, "speed": 1.0}


def _group_label(channel: str, value: float, levels) -> str:
    """Legend label of a condition level in display units, rounded so that levels stay distinct
    ('camber 0.0°', not '-0.000451 deg'; :mod:`tyrefit.io.facets`)."""
    if channel == "fz":
        return format_load(value)
    return format_condition(channel, value, _decimals(channel, levels))


def plot(effect, view: SignatureView, ax=None):
    """Plot ``effect``'s signature view; returns the Axes."""
    import matplotlib
    from matplotlib.figure import Figure

    if ax is None:
        ax = Figure(figsize=(5.5, 3.8)).subplots()
    ych, xc = SIGNATURES[effect.signature]
    yf, ylab = _Y[ych]
    xf, xlab = _X[xc]
    # group by the condition that is not on the x axis and varies most
    candidates = [c for c in ("fz", "camber", "pressure") if c != xc]
    group = None
    for c in candidates:
        if view.data[c].notna().any() and _levels(view.data[c], _TOL[c]).nunique() > 1:
            group = c
            break
    d = view.data.copy()
    d["_x"] = _levels(d[xc], _TOL[xc])
    d["_g"] = _levels(d[group], _TOL[group]) if group else 0.0
    cmap = matplotlib.colormaps["viridis"]
    # groups where the characteristic is defined (camber stiffness has no value at zero camber)
    groups = sorted(g for g in d["_g"].dropna().unique() if d.loc[d["_g"] == g, ych].notna().any())
    for i, g in enumerate(groups):
        col = cmap(i / max(len(groups) - 1, 1))
        m = d["_g"] == g
        glab = "" if group is None else _group_label(group, g, groups)
        ax.plot(d.loc[m, xc] * xf, d.loc[m, ych] * yf, "o", color=col, ms=3.5, alpha=0.6,
                label=f"data {glab}".strip())
        for frame, style, lab in ((view.before, "--", view.before_label), (view.after, "-", view.after_label)):
            f = frame.set_index("sweep").reindex(d["sweep"]).reset_index()
            f["_x"] = d["_x"].to_numpy()
            f["_g"] = d["_g"].to_numpy()
            line = f[f["_g"] == g].groupby("_x")[ych].mean()
            ax.plot(line.index * xf, line.values * yf, style, color=col, lw=1.4,
                    label=lab if i == 0 else None)
    if xc == "fz" and view.rated_load:
        ax.axvline(view.rated_load * xf, color="0.4", lw=0.8, ls=":")
        ax.annotate("rated load", (view.rated_load * xf, ax.get_ylim()[1]), fontsize=7, ha="right", va="top",
                    rotation=90)
    ax.set_xlabel(xlab)
    ax.set_ylabel(ylab)
    ax.set_title(f"{effect.id}: {effect.title}", fontsize=9)
    ax.legend(fontsize=6.5, ncol=2)
    return ax
