"""Condition levels of a set of sweeps, and the panels (facets) that show every one of them.

A rig record holds sweeps at set points of load, camber, pressure and speed
(and, in drive/brake tests, slip angle).  Views of a fit, a diagnosis or a
comparison draw one panel per combination of the set points other than load
(load is the line colour inside a panel), and every panel must say which
conditions it shows.  This module is the one place where those set points
are found, so that the fit report, the diagnose report and ``compare`` show
the same levels under the same names.

Design choices
--------------
* **The same clustering as segmentation.**  The levels of a channel are the
  histogram peaks of :func:`tyrefit.io.levels.group_levels` with
  ``method="peaks"``, the clustering of segmentation (bins of half the
  step tolerance, :data:`tyrefit.io.segment.DEFAULT_TOLERANCES`: camber
  0.2 deg, pressure 5 kPa, speed 2 km/h, slip angle 0.5 deg), applied to the
  mean value of each sweep (one count per sweep).  Each sweep then belongs to
  its nearest level, so no sweep is ever left out of a view.
* **Every level is shown.**  :func:`facet_sweeps` returns one :class:`Facet`
  per combination present in the data (never the first four, never a
  sample); :func:`pages` cuts a long list into figures of at most
  ``max_rows`` rows, keeping the rows of one pressure together.
* **Titles in display units** (deg, kPa, km/h; loads in kN), rounded to the
  resolution that still tells the levels apart, so a title never reads
  ``-0.000451 deg`` or ``8.3e+04 Pa``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from .levels import group_levels
from .segment import DEFAULT_TOLERANCES

__all__ = ["Facet", "sweep_conditions", "channel_levels", "facet_sweeps", "pages", "format_condition",
           "format_levels", "format_load", "FACET_CHANNELS"]

_DEG = math.pi / 180.0
#: channel -> (display factor from SI, unit, name in titles)
_DISPLAY = {"camber": (1 / _DEG, "°", "camber"), "slip_angle": (1 / _DEG, "°", "slip angle"),
            "pressure": (1e-3, " kPa", "pressure"), "speed": (3.6, " km/h", "speed"),
            "fz": (1e-3, " kN", "Fz")}
#: channels that make panels, outermost first (rows: pressure, speed; columns: camber, slip angle)
FACET_CHANNELS = ("pressure", "speed", "slip_angle", "camber")
_COLUMN_CHANNELS = ("slip_angle", "camber")


def sweep_conditions(df: pd.DataFrame, channels=("fz", "camber", "pressure", "speed", "slip_angle")) -> pd.DataFrame:
    """Mean set-point values of each sweep (SI), one row per ``run``, with ``n`` (samples)."""
    if "run" not in df:
        df = df.assign(run=0)
    cols = [c for c in channels if c in df and pd.api.types.is_numeric_dtype(df[c]) and df[c].notna().any()]
    g = df.groupby("run", sort=True)
    out = g[cols].mean() if cols else pd.DataFrame(index=sorted(df["run"].unique()))
    out["n"] = g.size()
    return out


def channel_levels(values, channel: str, tolerance: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Set-point levels of one channel from per-sweep values, and each value's level index.

    Parameters
    ----------
    values : array_like
        one value per sweep [SI].
    channel : str
        ``camber``, ``pressure``, ``speed``, ``slip_angle`` or ``fz``.
    tolerance : float, optional
        step tolerance [SI]; default that of :data:`tyrefit.io.segment.DEFAULT_TOLERANCES`
        (``fz``: max(150 N, 5 % of the median load), as segmentation).

    Returns
    -------
    levels : ndarray
        sorted levels [SI].
    index : ndarray of int
        nearest level of each value (-1 where the value is NaN: not recorded).
    """
    v = np.asarray(values, float)
    ok = np.isfinite(v)
    if not ok.any():
        return np.array([np.nan]), np.zeros(v.size, int)
    if tolerance is None:
        tolerance = DEFAULT_TOLERANCES[channel]
        if channel == "fz":
            tolerance = max(tolerance, 0.05 * float(np.median(np.abs(v[ok]))))
    return group_levels(v, float(tolerance), method="peaks")  # index -1: not recorded for that sweep


def _decimals(channel: str, levels) -> int:
    """Decimals of the display value that keep distinct levels distinct (at least the usual ones)."""
    base = {"camber": 1, "slip_angle": 1, "pressure": 0, "speed": 0, "fz": 2}[channel]
    f = _DISPLAY[channel][0]
    lv = np.unique(np.asarray([x for x in levels if np.isfinite(x)], float) * f)
    if lv.size > 1:
        gap = float(np.min(np.diff(lv)))
        while base < 4 and gap < 2 * 10.0 ** -base:
            base += 1
    return base


def format_condition(channel: str, value: float, decimals: int | None = None) -> str:
    """``'camber 2.0°'``, ``'pressure 83 kPa'``, ``'speed 40 km/h'``, ``'slip angle -4.0°'`` from SI."""
    f, unit, name = _DISPLAY[channel]
    d = _decimals(channel, [value]) if decimals is None else decimals
    x = round(value * f, d)
    if x == 0:
        x = 0.0  # never '-0.0'
    return f"{name} {x:.{d}f}{unit}"


def format_levels(channel: str, levels) -> str:
    """The levels of one channel in display units, for messages: ``'200, 230, 260 kPa'`` (from SI)."""
    f, unit, _ = _DISPLAY[channel]
    d = _decimals(channel, levels)
    return f"{', '.join(f'{x * f:.{d}f}' for x in levels)}{unit}"


def format_load(fz: float) -> str:
    """A load for legends: ``'1.11 kN'`` (N below 100 N)."""
    return f"{fz:.0f} N" if abs(fz) < 100 else f"{fz / 1e3:.2f} kN"


@dataclass
class Facet:
    """One panel: the sweeps at one combination of condition levels.

    Attributes
    ----------
    conditions : dict
        channel -> level [SI] of the channels that vary in the data.
    runs : list of int
        the sweeps (``run`` ids) in the panel, by increasing load.
    loads : list of float
        mean load of each of those sweeps [N].
    title : str
        the conditions in display units, e.g. ``'pressure 83 kPa, camber 2.0°'``.
    row, col : int
        position in the grid (row: outer channels, column: camber or slip angle).
    """

    conditions: dict
    runs: list
    loads: list
    title: str
    row: int = 0
    col: int = 0
    row_key: tuple = field(default=(), repr=False)

    def mask(self, df: pd.DataFrame) -> np.ndarray:
        """Rows of ``df`` in this panel (by ``run``)."""
        return df["run"].isin(self.runs).to_numpy()


def facet_sweeps(df: pd.DataFrame, channels=FACET_CHANNELS, *, tolerances: dict | None = None
                 ) -> tuple[list[Facet], dict]:
    """Panels covering every sweep of ``df``, one per combination of condition levels present.

    Parameters
    ----------
    df : DataFrame
        canonical SI columns with ``run`` (one sweep per run) and ``fz``.
    channels : sequence of str
        condition channels that may make panels (those present with more than
        one level do); outer channels make rows, ``slip_angle`` and ``camber``
        make columns.  For slip-angle sweeps leave ``slip_angle`` out (it is
        the sweep variable).
    tolerances : dict, optional
        per-channel step tolerances [SI] (default: segmentation's).

    Returns
    -------
    facets : list of Facet
        in row-major order; together they hold every run exactly once.
    info : dict
        ``levels`` (channel -> ndarray [SI], every channel found, varying or
        not), ``varying`` (channels with more than one level), ``constant``
        (channel -> the single level [SI]), ``run_levels`` (DataFrame: run ->
        level of each channel [SI]).
    """
    sc = sweep_conditions(df, ("fz",) + tuple(channels))
    tol = dict(tolerances or {})
    levels, idx = {}, {}
    for c in channels:
        if c in sc:
            levels[c], idx[c] = channel_levels(sc[c].to_numpy(), c, tol.get(c))
    varying = [c for c in channels if c in levels and np.isfinite(levels[c]).all()
               and (len(levels[c]) > 1 or (idx[c] < 0).any())]
    constant = {c: float(levels[c][0]) for c in levels if c not in varying and np.isfinite(levels[c][0])}
    dec = {c: _decimals(c, levels[c]) for c in levels}
    rows_ch = [c for c in varying if c not in _COLUMN_CHANNELS]
    cols_ch = [c for c in varying if c in _COLUMN_CHANNELS]
    key = pd.DataFrame({c: idx[c] for c in varying}, index=sc.index)
    facets: list[Facet] = []
    row_keys = sorted({tuple(int(key.loc[r, c]) for c in rows_ch) for r in sc.index})
    col_keys = sorted({tuple(int(key.loc[r, c]) for c in cols_ch) for r in sc.index})
    for i, rk in enumerate(row_keys):
        for j, ck in enumerate(col_keys):
            m = np.ones(len(sc), bool)
            for c, k in zip(rows_ch + cols_ch, rk + ck):
                m &= key[c].to_numpy() == k
            if not m.any():
                continue
            sub = sc[m].sort_values("fz")
            cond = {c: (float(levels[c][k]) if k >= 0 else float("nan")) for c, k in zip(rows_ch + cols_ch, rk + ck)}
            title = ", ".join(format_condition(c, cond[c], dec[c]) if np.isfinite(cond[c]) else
                              f"{_DISPLAY[c][2]} not recorded" for c in rows_ch + cols_ch) or "all sweeps"
            facets.append(Facet(conditions=cond, runs=[int(r) for r in sub.index],
                                loads=[float(x) for x in sub["fz"]], title=title, row=i, col=j, row_key=rk))
    run_levels = pd.DataFrame({c: np.where(idx[c] >= 0, levels[c][np.maximum(idx[c], 0)], np.nan) for c in levels},
                              index=sc.index)
    return facets, {"levels": levels, "varying": varying, "constant": constant, "run_levels": run_levels,
                    "decimals": dec}


def describe_constant(info: dict) -> str:
    """The conditions common to every sweep, e.g. ``'pressure 83 kPa, speed 40 km/h'`` ('' if none)."""
    return ", ".join(format_condition(c, v, info["decimals"].get(c)) for c, v in info["constant"].items()
                     if c != "fz")


def pages(facets: list[Facet], max_rows: int = 4) -> list[list[Facet]]:
    """Cut facets into figures of at most ``max_rows`` grid rows (whole rows, in order)."""
    rows = sorted({f.row for f in facets})
    out = []
    for k in range(0, len(rows), max_rows):
        keep = set(rows[k:k + max_rows])
        out.append([f for f in facets if f.row in keep])
    return out or [[]]


__all__.append("describe_constant")
