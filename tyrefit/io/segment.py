"""Cut one continuous rig record into steady-condition slip sweeps.

FSAE TTC files (and many in-house flat-track logs) hold a whole test
programme in one record: warm-up, load steps, camber steps, pressure changes,
speed changes, and between them the slip sweeps that a fit needs.  The steps
here are vectorised (pandas rolling medians, histogram levels, a
zig-zag over slope changes)
so records of 10^5 samples are cut in well under a second.

Algorithm (every threshold is recorded in the returned ``meta``)
-----------------------------------------------------------------
1. **Unloaded** samples (``fz`` below max(100 N, 5 % of the 95th percentile))
   are dropped: the tyre is lifted off the belt between tests.
2. Each **set-point channel** (``fz``, ``camber``, ``pressure``, ``speed``; and
   ``slip_angle`` for slip-ratio tests) is smoothed by a running median over
   ``window`` samples (0.5 s when a ``time`` channel exists, else 25 samples).
   Its **set-point levels** are the peaks of a histogram of the smoothed
   values (bins of half the tolerance; a level must hold at least
   max(2 windows, 20) samples and stand out by half that from the valley
   towards any higher peak), so slow ramps between levels do not make levels.
   Tolerances: ``fz`` max(150 N, 5 % of the median load); camber 0.2 deg;
   pressure 5 kPa; speed 2 km/h; slip angle 0.5 deg.  A sample farther than
   the tolerance from every level of a channel is *in transition*.
3. The samples left fall into **steady stretches**: runs in which every
   channel stays at one level; a stretch ends where any level changes.
   Stretches shorter than max(2 windows, 20 samples) are dropped.
4. In each stretch the sweep variable (slip angle or slip ratio) is lightly
   smoothed; a stretch whose slip spans less than 0.5 deg (0.01 slip ratio)
   is dropped (*no slip variation*), and the constant-slip **dwell** before
   the sweep starts and after it ends is trimmed.
5. The stretch is cut into **full slip cycles**: interior extremes of the
   slip (peaks with a prominence of a quarter of the span) are taken in
   pairs (one maximum, one minimum: 0 -> +12 -> -12 -> 0 is one sweep), and
   the cut is placed where the slip crosses the middle of its range between
   pairs.  A monotone ramp or a single out-and-back is one sweep.
6. Sweeps whose slip span is below half of the median span are dropped as
   **warm-up or partial** sweeps; so are sweeps with fewer than 20 samples.

Each kept sweep becomes one ``run``.
"""

from __future__ import annotations

import math
from collections import Counter
from typing import Any

import numpy as np
import pandas as pd

from ..errors import ColumnError, DataError

__all__ = ["segment_record", "DEFAULT_TOLERANCES"]

_DEG = math.pi / 180.0

#: step tolerances [SI]; fz is max(this, 5 % of the median load)
DEFAULT_TOLERANCES = {"fz": 150.0, "camber": 0.2 * _DEG, "pressure": 5e3, "speed": 2.0 / 3.6,
                      "slip_angle": 0.5 * _DEG}
_MIN_SPAN = {"slip_angle": 0.5 * _DEG, "slip_ratio": 0.01}
_SWEEP = {"slip_angle": "slip_angle", "slip_ratio": "slip_ratio"}


def _odd(n: int) -> int:
    n = max(3, int(n))
    return n if n % 2 else n + 1


def _rolling_median(x: np.ndarray, w: int) -> np.ndarray:
    return pd.Series(x).rolling(w, center=True, min_periods=1).median().to_numpy()


def _runs_of(mask: np.ndarray) -> list[tuple[int, int]]:
    """(start, stop) index pairs of the True stretches of ``mask``."""
    m = np.r_[False, mask, False].astype(np.int8)
    d = np.diff(m)
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1)))


def _levels(v: np.ndarray, tol: float, min_count: int) -> list[float]:
    """Set-point levels of a smoothed channel: histogram peaks (bins of tol/2) held by >= min_count samples."""
    if v.size == 0:
        return []
    lo, hi = float(v.min()), float(v.max())
    if hi - lo <= tol:
        return [float(np.median(v))]
    bw = tol / 2
    edges = np.arange(lo - bw, hi + 2 * bw, bw)
    counts, _ = np.histogram(v, edges)
    levels = []
    for k in _local_maxima(counts, min_count):
        centre = 0.5 * (edges[k] + edges[k + 1])
        sel = np.abs(v - centre) <= tol
        lv = float(np.median(v[sel]))
        if not levels or abs(lv - levels[-1]) > tol:
            levels.append(lv)
    return sorted(levels)


def _local_maxima(c: np.ndarray, min_height: float) -> np.ndarray:
    """Histogram peaks: local maxima at least ``min_height`` high and standing at least
    ``min_height / 2`` above the valley towards any higher peak (a topographic prominence)."""
    c = np.asarray(c, dtype=float)
    p = np.r_[-1.0, c, -1.0]
    # a plateau counts once: compare with the next different value on the right
    nxt = pd.Series(np.where(np.diff(p[1:]) != 0, p[2:], np.nan)).bfill().to_numpy()
    pk = np.flatnonzero((p[1:-1] > p[:-2]) & (c > nxt) & (c >= min_height))
    keep = []
    for k in pk:
        higher_left = np.flatnonzero(c[:k] > c[k])
        higher_right = np.flatnonzero(c[k + 1:] > c[k]) + k + 1
        lo_l = c[higher_left[-1]:k + 1].min() if higher_left.size else c[:k + 1].min()
        # no higher peak to the right: the valley is the empty histogram beyond the last bin
        lo_r = c[k:higher_right[0] + 1].min() if higher_right.size else 0.0
        if c[k] - max(lo_l, lo_r) >= min_height / 2:
            keep.append(int(k))
    return np.asarray(keep, dtype=int)


def _turning_points(x: np.ndarray, thr: float) -> np.ndarray:
    """Interior extremes of ``x`` that it leaves again by at least ``thr`` (zig-zag with hysteresis).

    Candidates are the sign changes of the slope (vectorised); only those are
    visited by the hysteresis loop.
    """
    if x.size < 3:
        return np.zeros(0, int)
    d = np.sign(np.diff(x))
    d = pd.Series(np.where(d == 0, np.nan, d)).ffill().bfill().fillna(0).to_numpy()
    cand = np.r_[0, np.flatnonzero(d[1:] != d[:-1]) + 1, x.size - 1]
    ext: list[int] = []
    imax = imin = int(cand[0])
    direction = 0
    for i in cand[1:]:
        v = x[i]
        if direction >= 0 and v > x[imax]:
            imax = int(i)
        if direction <= 0 and v < x[imin]:
            imin = int(i)
        if direction == 0:
            if x[imax] - x[imin] >= thr:
                direction = 1 if imax > imin else -1
        elif direction == 1 and x[imax] - v >= thr:
            ext.append(imax)
            direction, imin = -1, int(i)
        elif direction == -1 and v - x[imin] >= thr:
            ext.append(imin)
            direction, imax = 1, int(i)
    return np.asarray(ext, dtype=int)


def _assign(s: np.ndarray, levels: list[float], tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Index of the nearest level and whether it is within ``tol``."""
    if not levels:
        return np.zeros(s.size, int), np.zeros(s.size, bool)
    lv = np.asarray(levels)
    j = np.clip(np.searchsorted(lv, s), 1, max(1, lv.size - 1)) if lv.size > 1 else np.zeros(s.size, int)
    if lv.size > 1:
        j = np.where(np.abs(s - lv[j - 1]) <= np.abs(s - lv[j]), j - 1, j)
    return j, np.abs(s - lv[j]) <= tol


def segment_record(df: pd.DataFrame, kind: str, source: str = "", *, window: int | None = None,
                   tolerances: dict[str, float] | None = None,
                   min_span_fraction: float = 0.5) -> tuple[pd.DataFrame, dict[str, Any]]:
    """Split a continuous record into steady-condition sweeps.

    Parameters
    ----------
    df : DataFrame
        SI, ISO-W columns (``fz``, the sweep variable, optional ``camber``,
        ``pressure``, ``speed``, ``time``); the index holds file line numbers.
    kind : {'slip_angle', 'slip_ratio'}
    source : str
        file name for messages.
    window : int, optional
        running-median window [samples]; default 0.5 s of ``time`` or 25.
    tolerances : dict, optional
        step tolerances per channel [SI], updating :data:`DEFAULT_TOLERANCES`.
    min_span_fraction : float
        sweeps spanning less than this fraction of the median span are dropped.

    Returns
    -------
    (DataFrame, dict)
        the kept samples with an integer ``run`` column, and what was found:
        ``n_sweeps``, ``sweeps`` (one dict per run), ``dropped`` (reason ->
        samples), ``window``, ``tolerances``, ``method``.
    """
    var = _SWEEP.get(kind)
    if var is None:
        raise DataError(f"{source}: a continuous record can be segmented for slip-angle or slip-ratio tests, "
                        f"not for {kind} data")
    if var not in df or "fz" not in df:
        raise ColumnError(f"{source}: segmenting needs the channels '{var}' and 'fz'")
    n = len(df)
    tol = dict(DEFAULT_TOLERANCES)
    tol.update(tolerances or {})
    fz = df["fz"].to_numpy(float)
    if window is None:
        if "time" in df and n > 10:
            dt = np.median(np.diff(df["time"].to_numpy(float)))
            window = _odd(round(0.5 / dt)) if dt > 0 else 25
        else:
            window = 25
    w = _odd(window)
    h = w // 2
    dropped: Counter[str] = Counter()
    label = np.full(n, "", dtype=object)

    # 1. unloaded
    fz_min = max(100.0, 0.05 * float(np.percentile(fz, 95))) if n else 100.0
    loaded = fz > fz_min
    label[~loaded] = f"tyre unloaded (fz < {fz_min:.0f} N)"

    # 2. set-point levels and transitions
    fz_med = float(np.median(fz[loaded])) if loaded.any() else 0.0
    tol["fz"] = max(tol["fz"], 0.05 * fz_med)
    channels = [c for c in ("fz", "camber", "pressure", "speed") if c in df]
    if kind == "slip_ratio" and "slip_angle" in df:
        channels.append("slip_angle")
    min_len = max(2 * w, 20)
    level_id = np.zeros(n, dtype=np.int64)
    off_level = np.zeros(n, bool)
    levels_found: dict[str, list[float]] = {}
    for c in channels:
        s = _rolling_median(df[c].to_numpy(float), w)
        lv = _levels(s[loaded], tol[c], min_len)
        levels_found[c] = lv
        idx, ok = _assign(s, lv, tol[c])
        bad = ~ok & loaded & ~off_level
        label[bad] = f"set-point transition ({c})"
        off_level |= ~ok
        level_id = level_id * (len(lv) + 1) + np.where(ok, idx + 1, 0)
    # 3.-5. steady stretches, dwell, cycles
    steady = loaded & ~off_level
    slip = df[var].to_numpy(float)
    sweeps: list[tuple[int, int]] = []
    change = np.r_[False, level_id[1:] != level_id[:-1]]
    stretches = []
    for a, b in _runs_of(steady):
        cut = a + np.flatnonzero(change[a + 1:b]) + 1
        edges = np.r_[a, cut, b]
        stretches.extend(zip(edges[:-1], edges[1:]))
    for a, b in stretches:
        if b - a < min_len:
            label[a:b] = f"steady stretch too short (< {min_len} samples)"
            continue
        xs = _rolling_median(slip[a:b], _odd(max(3, w // 3)))
        span = float(np.ptp(xs))
        if span < _MIN_SPAN[var]:
            label[a:b] = "no slip variation"
            continue
        band = 0.02 * span
        x0, x1 = np.median(xs[:max(3, h)]), np.median(xs[-max(3, h):])
        out0 = np.flatnonzero(np.abs(xs - x0) > band)
        out1 = np.flatnonzero(np.abs(xs - x1) > band)
        i0 = max(0, int(out0[0]) - 1) if out0.size else 0
        i1 = min(b - a, int(out1[-1]) + 2) if out1.size else b - a
        label[a:a + i0] = "dwell at constant slip"
        label[a + i1:b] = "dwell at constant slip"
        xs_t = xs[i0:i1]
        ext = _turning_points(xs_t, 0.25 * span)
        cuts = [0]
        centre = 0.5 * (xs_t.max() + xs_t.min())
        for j in range(2, len(ext), 2):
            e0, e1 = ext[j - 1], ext[j]
            seg = xs_t[e0:e1] - centre
            cross = np.flatnonzero(np.sign(seg[:-1]) != np.sign(seg[1:]))
            cuts.append(int(e0 + cross[0] + 1) if cross.size else int((e0 + e1) // 2))
        cuts.append(len(xs_t))
        for c0, c1 in zip(cuts[:-1], cuts[1:]):
            sweeps.append((a + i0 + c0, a + i0 + c1))

    # 6. partial / warm-up sweeps
    kept: list[tuple[int, int]] = []
    if sweeps:
        spans = np.array([np.ptp(slip[a:b]) for a, b in sweeps])
        ref = float(np.median(spans))
        for (a, b), sp in zip(sweeps, spans):
            if b - a < 20:
                label[a:b] = "sweep with fewer than 20 samples"
            elif sp < min_span_fraction * ref:
                label[a:b] = f"warm-up or partial sweep (slip span < {min_span_fraction:.0%} of the median)"
            else:
                kept.append((a, b))
    if not kept:
        reasons = Counter(label[label != ""])
        raise DataError(f"{source}: no steady slip sweep found in {n} samples; dropped: "
                        + "; ".join(f"{k}: {v}" for k, v in reasons.most_common()) if reasons else
                        f"{source}: no steady slip sweep found in {n} samples")
    run = np.full(n, -1, dtype=int)
    for r, (a, b) in enumerate(kept):
        run[a:b] = r
    for k, v in Counter(label[(run < 0) & (label != "")]).items():
        dropped[k] += int(v)
    other = int(((run < 0) & (label == "")).sum())
    if other:
        dropped["between sweeps"] += other
    out = df.loc[run >= 0].copy()
    out["run"] = run[run >= 0]

    lines = df.index.to_numpy()
    info = []
    for r, (a, b) in enumerate(kept):
        d = {"run": r, "first_line": int(lines[a]), "last_line": int(lines[b - 1]), "n": int(b - a),
             "fz": float(np.mean(fz[a:b]))}
        if "camber" in df:
            d["camber_deg"] = float(np.mean(df["camber"].to_numpy()[a:b]) / _DEG)
        if "pressure" in df:
            d["pressure_kpa"] = float(np.mean(df["pressure"].to_numpy()[a:b]) / 1e3)
        if "speed" in df:
            d["speed_kmh"] = float(np.mean(df["speed"].to_numpy()[a:b]) * 3.6)
        lo_, hi_ = float(slip[a:b].min()), float(slip[a:b].max())
        if var == "slip_angle":
            d["slip_angle_deg"] = [lo_ / _DEG, hi_ / _DEG]
        else:
            d["slip_ratio"] = [lo_, hi_]
        info.append(d)
    meta = {
        "n_samples": n,
        "n_kept": int(len(out)),
        "n_sweeps": len(kept),
        "sweep_variable": var,
        "window": w,
        "tolerances": {"fz_N": tol["fz"], "camber_deg": tol["camber"] / _DEG, "pressure_kPa": tol["pressure"] / 1e3,
                       "speed_kmh": tol["speed"] * 3.6,
                       **({"slip_angle_deg": tol["slip_angle"] / _DEG} if kind == "slip_ratio" else {})},
        "channels": channels,
        "levels": {c: ([v / _DEG for v in lv] if c in ("camber", "slip_angle") else
                       [v / 1e3 for v in lv] if c == "pressure" else [v * 3.6 for v in lv] if c == "speed"
                       else lv) for c, lv in levels_found.items()},
        "dropped": dict(dropped.most_common()),
        "sweeps": info,
        "method": (f"set-point levels of {', '.join(channels)} from histogram peaks of a {w}-sample running median; "
                   f"steady stretches where every channel stays within tolerance of one level, cut into full "
                   f"{var.replace('_', ' ')} cycles; dwell, transitions, unloaded samples and sweeps spanning "
                   f"< {min_span_fraction:.0%} of the median span dropped"),
    }
    return out, meta
