"""Lateral-force sweeps prepared for diagnosis: sweeps, condition levels, cells.

A *sweep* is one slip-angle sweep at one steady condition; residuals along it
are correlated, so it is the unit of resampling, clustering and hold-out.  The
``run`` column is taken as the sweep id; a run that holds several conditions
(FSAE TTC files: one run, many loads, cambers and pressures) is split where a
condition level changes.  Condition levels (load, camber, pressure, speed) are
the dense clusters of the measured values.  Long sweeps (thousands of points
per sweep on real rigs) are thinned to at most ``max_points_per_sweep`` points
spread evenly along the record, which keeps the per-point noise scale (RMSE
stays comparable) while making the many refits of a diagnosis fast.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..effects.base import DataSummary, ModelInputs
from ..errors import ColumnError, DataError, option
from ..fitting.noise import MAX_POINTS_PER_SWEEP, thin_sweeps

__all__ = ["SweepData", "prepare", "condition_levels", "segments", "combine_records", "FACTORS"]

#: condition factors: column, resolution used to find levels (SI), display factor, unit
FACTORS: dict[str, tuple[float, float, str]] = {
    "fz": (100.0, 1e-3, "kN"),
    "camber": (0.25 * np.pi / 180.0, 180.0 / np.pi, "deg"),
    "pressure": (5e3, 1e-3, "kPa"),
    "speed": (1.0, 3.6, "km/h"),
}


def condition_levels(values: np.ndarray, resolution: float, min_share: float = 0.01):
    """Find the set-point levels of a measured condition.

    Parameters
    ----------
    values : array_like
        Measured condition per point (SI).
    resolution : float
        Bin width [SI]; levels closer than about twice this merge.
    min_share : float
        Bins holding fewer than this share of the points (ramps between set
        points) do not form levels.

    Returns
    -------
    levels : ndarray
        Level values (median of the points assigned to each), ascending.
    index : ndarray of int
        Level index of every point (nearest level).
    """
    v = np.asarray(values, dtype=float)
    finite = np.isfinite(v)
    if not finite.any():
        return np.array([np.nan]), np.zeros(len(v), dtype=int)
    lo, hi = np.nanmin(v), np.nanmax(v)
    if hi - lo <= 2 * resolution:
        return np.array([float(np.nanmedian(v))]), np.zeros(len(v), dtype=int)
    edges = np.arange(lo - resolution, hi + 2 * resolution, resolution)
    counts, _ = np.histogram(v[finite], edges)
    dense = counts >= max(min_share * finite.sum(), 1)
    # contiguous runs of dense bins form the levels; centres are count-weighted
    centres = []
    i = 0
    while i < len(dense):
        if dense[i]:
            j = i
            while j + 1 < len(dense) and dense[j + 1]:
                j += 1
            mids = 0.5 * (edges[i:j + 1] + edges[i + 1:j + 2])
            centres.append(float(np.average(mids, weights=counts[i:j + 1])))
            i = j + 1
        else:
            i += 1
    if not centres:
        centres = [float(np.nanmedian(v))]
    centres = np.array(centres)
    idx = np.abs(np.where(finite, v, centres[0])[:, None] - centres[None, :]).argmin(axis=1)
    levels = np.array([np.median(v[(idx == k) & finite]) if ((idx == k) & finite).any() else centres[k]
                       for k in range(len(centres))])
    order = np.argsort(levels)
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return levels[order], rank[idx]


@dataclass
class SweepData:
    """Lateral-force points ready for diagnosis (all SI, ISO-W).

    Attributes
    ----------
    inputs : ModelInputs
        Operating conditions of each point and the reference values.
    fy : ndarray
        Measured lateral force [N].
    sweep : ndarray of int
        Sweep index 0..n_sweeps-1 of each point.
    levels : dict
        factor -> level values (SI) for ``fz``, ``camber``, ``pressure``, ``speed``.
    level_index : dict
        factor -> level index of each point.
    cell : ndarray of int
        Condition cell (load x camber x pressure x speed level) of each point.
    summary : DataSummary
    n_raw : int
        Points before thinning.
    source : str
    """

    inputs: ModelInputs
    fy: np.ndarray
    sweep: np.ndarray
    levels: dict[str, np.ndarray]
    level_index: dict[str, np.ndarray]
    cell: np.ndarray
    summary: DataSummary
    n_raw: int
    source: str = ""
    notes: list[str] = field(default_factory=list)
    convention: str = "iso"  # sign convention of the file read (for commands the report suggests)
    #: the sweeps are static-rig pushes converted to slip angles (Komana et al. Eq. 1): the advice asks for pushes
    static_pushes: bool = False
    #: slip-ratio sweeps left out of the lateral diagnosis (drive/brake and combined slip), or None:
    #: ``{"combined_sweeps", "longitudinal_sweeps", "points", "slip_angles"}`` (slip angles [rad])
    slip_ratio_sweeps: dict | None = None

    @property
    def n(self) -> int:
        return len(self.fy)

    @property
    def n_sweeps(self) -> int:
        return int(self.sweep.max()) + 1 if len(self.sweep) else 0

    @property
    def has(self) -> dict[str, bool]:
        """Which optional conditions the data carry."""
        return {"pressure": self.inputs.pressure is not None, "speed": self.inputs.speed is not None}

    def sweep_cells(self) -> np.ndarray:
        """Cell of each sweep."""
        out = np.zeros(self.n_sweeps, dtype=int)
        out[self.sweep] = self.cell
        return out

    def sweep_level(self, factor: str) -> np.ndarray:
        """Level index of ``factor`` for each sweep."""
        out = np.zeros(self.n_sweeps, dtype=int)
        out[self.sweep] = self.level_index[factor]
        return out

    def frame(self) -> pd.DataFrame:
        """The prepared points as a DataFrame (SI)."""
        x = self.inputs
        d = {"sweep": self.sweep, "cell": self.cell, "fz": x.fz, "slip_angle": x.slip_angle,
             "camber": x.camber, "fy": self.fy}
        if x.pressure is not None:
            d["pressure"] = x.pressure
        if x.speed is not None:
            d["speed"] = x.speed
        for f, idx in self.level_index.items():
            d[f"{f}_level"] = self.levels[f][idx]
        return pd.DataFrame(d)


def segments(d: pd.DataFrame) -> tuple[np.ndarray, dict, dict, np.ndarray]:
    """Condition levels of a cleaned frame and its segments (a new one where the run or a level changes).

    Returns ``camber`` [rad] per point (0 without the column), ``levels`` and ``level_index`` per factor
    of :data:`FACTORS` the frame has (camber always), and the segment index of every point.  A ``load``
    column (the load set point), when the file has one, defines the load levels: a measured load that
    wanders along a sweep (air suspension, road) must not split the sweep into "levels".
    """
    n = len(d)
    camber = d["camber"].to_numpy(float) if "camber" in d.columns else np.zeros(n)
    levels, lidx = {}, {}
    setpoint = None
    if "load" in d.columns and d["load"].notna().all() and (d["load"] > 0).all():
        setpoint = d["load"].to_numpy(float)
    for f in FACTORS:
        if f == "camber" or f in d.columns:
            vals = camber if f == "camber" else (setpoint if f == "fz" and setpoint is not None else d[f].to_numpy(float))
            levels[f], lidx[f] = condition_levels(vals, FACTORS[f][0])
            if f == "fz" and setpoint is not None:  # level values: the median measured load of each level
                fzm = d["fz"].to_numpy(float)
                levels[f] = np.array([np.median(fzm[lidx[f] == k]) for k in range(len(levels[f]))])
    run = d["run"].to_numpy() if "run" in d.columns else np.zeros(n)
    key = np.column_stack([pd.factorize(run)[0]] + [lidx[f] for f in lidx])
    change = np.r_[True, (np.diff(key, axis=0) != 0).any(axis=1)]
    return camber, levels, lidx, np.cumsum(change) - 1


#: a segment whose slip ratio spans this much (2-98 %) ...
KAPPA_SWEPT = 0.05
#: ... while its slip angle spans less than this [rad] is a slip-ratio sweep, not a cornering sweep
ALPHA_HELD = 2.0 * np.pi / 180.0
#: a slip-ratio sweep whose median slip angle is within this of zero [rad] is pure drive/brake, else combined
ALPHA_PURE = 0.5 * np.pi / 180.0


def slip_ratio_segments(d: pd.DataFrame, seg: np.ndarray) -> tuple[np.ndarray, np.ndarray, dict]:
    """Points of slip-ratio (drive/brake, combined) segments, those of the pure drive/brake ones, and what they were.

    A lateral slip-angle sweep on a rig carries slip-ratio noise and drift (FSAE TTC: +-0.01,
    more at large slip angles, and an offset from the rolling-radius estimate), so a segment
    counts as a slip-ratio sweep only when its slip ratio spans >= :data:`KAPPA_SWEPT` (2-98 %
    quantiles, robust to spikes) while its slip angle is held (spans < :data:`ALPHA_HELD`): a
    drive/brake sweep at zero slip angle or a combined one at a fixed slip angle.  A swept slip
    angle stays a cornering sweep whatever the slip ratio does.
    """
    kap = d["slip_ratio"].fillna(0.0).to_numpy(float)
    sa = d["slip_angle"].to_numpy(float)
    drop = np.zeros(len(d), dtype=bool)
    pure = np.zeros(len(d), dtype=bool)
    n_comb = n_long = 0
    angles = []
    for k in np.unique(seg):
        m = seg == k
        lo, hi = np.percentile(kap[m], [2, 98])
        alo, ahi = np.percentile(sa[m], [2, 98])
        if hi - lo >= KAPPA_SWEPT and ahi - alo < ALPHA_HELD:
            drop[m] = True
            a = float(np.median(sa[m]))
            if abs(a) < ALPHA_PURE:
                pure[m] = True
                n_long += 1
            else:
                n_comb += 1
                angles.append(a)
    info = {"combined_sweeps": n_comb, "longitudinal_sweeps": n_long, "points": int(drop.sum()),
            "slip_angles": sorted({round(a * 180.0 / np.pi) * np.pi / 180.0 for a in angles})}
    return drop, pure, info


def _slip_ratio_note(info: dict) -> str:
    ang = ", ".join(f"{a * 180.0 / np.pi:g}" for a in info["slip_angles"])
    return (f"{info['points']} points of slip-ratio sweeps left out ({info['longitudinal_sweeps']} drive/brake at "
            f"zero slip angle, {info['combined_sweeps']} combined" + (f" at {ang} deg" if ang else "")
            + "): this diagnosis reads pure cornering (PAC89 has no combined slip); combined slip needs MF 6.1 "
            "(`--model mf61`)")


def _with_df(data, df: pd.DataFrame):
    """A shallow copy of a Dataset with another frame (source and meta kept)."""
    import copy

    out = copy.copy(data)
    out.df = df
    return out


def _frame_of(data) -> tuple[pd.DataFrame, str, dict]:
    if isinstance(data, pd.DataFrame):
        return data, "DataFrame", {}
    df = getattr(data, "df", None)
    if isinstance(df, pd.DataFrame):
        return df, str(getattr(data, "source", "")), dict(getattr(data, "meta", {}) or {})
    raise DataError(f"diagnose needs a Dataset or a DataFrame, got {type(data).__name__}")


def combine_records(records: list):
    """One Dataset of several records of the same tyre (a cornering and a drive/brake record, say).

    The runs are renumbered so that no two records share a sweep id; the first slip-angle record gives
    the source, sign convention and metadata (the lateral diagnosis and its export read it), and
    ``meta['sources']`` lists every record.
    """
    if len(records) == 1:
        return records[0]
    lead = next((r for r in records if getattr(r, "kind", "") == "slip_angle"), records[0])
    frames, offset = [], 0
    for r in records:
        df = r.df.copy()
        if "run" in df.columns:
            run = pd.factorize(df["run"])[0]
            df["run"] = run + offset
            offset += int(run.max()) + 1 if len(run) else 0
        frames.append(df)
    out = _with_df(lead, pd.concat(frames, ignore_index=True, sort=False))
    out.meta = dict(getattr(lead, "meta", {}) or {}, sources=[str(getattr(r, "source", "")) for r in records])
    return out


def prepare(data, rated_load: float | None = None, max_points_per_sweep: int = MAX_POINTS_PER_SWEEP) -> SweepData:
    """Turn a Dataset (or a DataFrame with canonical SI columns) into :class:`SweepData`.

    Parameters
    ----------
    data : Dataset or DataFrame
        Needs ``fy`` [N], ``slip_angle`` [rad], ``fz`` [N]; uses ``run``,
        ``camber`` [rad], ``pressure`` [Pa], ``speed`` [m/s] when present.
    rated_load : float, optional
        Rated load [N] (for the ``overload`` effect); default ``meta['rated_load']``.
    max_points_per_sweep : int
        Longer sweeps are thinned evenly to this many points.
    """
    df, source, meta = _frame_of(data)
    missing = [c for c in ("fy", "slip_angle", "fz") if c not in df.columns]
    if missing:
        raise ColumnError(f"{source or 'data'}: diagnose needs lateral-force slip sweeps; missing column(s) "
                          f"{', '.join(missing)} (have: {', '.join(map(str, df.columns))})")
    cols = ["fy", "slip_angle", "fz"] + [c for c in ("run", "camber", "pressure", "speed", "load", "slip_ratio")
                                         if c in df.columns]
    d = df[cols].apply(pd.to_numeric, errors="coerce")
    keep = d[["fy", "slip_angle", "fz"]].notna().all(axis=1).to_numpy().copy()
    for c in ("camber", "pressure", "speed"):
        if c in d.columns and d[c].isna().all():
            d = d.drop(columns=c)
        elif c in d.columns:
            keep &= d[c].notna().to_numpy()
    d = d[keep].reset_index(drop=True)
    if len(d) < 20:
        raise DataError(f"{source or 'data'}: only {len(d)} usable lateral-force points; diagnose needs sweeps "
                        "(at least 20 points)")
    if (d["fz"] <= 0).mean() > 0.5:
        raise DataError(f"{source or 'data'}: most fz values are <= 0 N; fz must be positive in compression "
                        f"(ISO-W) - for FSAE TTC files pass {option('convention', 'sae')}")
    d = d[d["fz"] > 0].reset_index(drop=True)
    n_raw = len(d)
    camber, levels, lidx, seg = segments(d)
    # drop short segments (ramps between set points)
    counts = np.bincount(seg)
    ok = counts[seg] >= 8
    if not ok.all():
        d, camber, seg = d[ok].reset_index(drop=True), camber[ok], seg[ok]
        lidx = {f: v[ok] for f, v in lidx.items()}
    if "slip_ratio" in d.columns:
        drop, _, info = slip_ratio_segments(d, seg)
        if drop.all():
            raise DataError(f"{source or 'data'}: only slip-ratio sweeps ({info['longitudinal_sweeps']} drive/brake, "
                            f"{info['combined_sweeps']} combined); diagnose reads lateral-force slip-angle sweeps - "
                            "fit these with `tyrefit fit FILE --model mf61`")
        pure = d.drop(columns="slip_ratio")
        if drop.any():
            pure = pure[~drop].reset_index(drop=True)
        out = prepare(pure if not hasattr(data, "df") else _with_df(data, pure), rated_load=rated_load,
                      max_points_per_sweep=max_points_per_sweep)
        if drop.any():
            out.slip_ratio_sweeps = info
            out.notes.insert(0, _slip_ratio_note(info))
        return out
    # merge segments of the same run and condition (a run revisiting a condition is one sweep cluster)
    key = np.column_stack([pd.factorize(d["run"].to_numpy() if "run" in d.columns else np.zeros(len(d)))[0]]
                          + [lidx[f] for f in lidx])
    sweep = pd.factorize(pd.MultiIndex.from_arrays(key.T))[0]
    # thin long sweeps evenly along the record
    take = thin_sweeps(sweep, max_points_per_sweep)
    notes = []
    if len(take) < len(d):
        notes.append(f"{len(d)} points thinned to {len(take)} (at most {max_points_per_sweep} per sweep, "
                     "spread evenly along each record)")
    d, camber, sweep = d.iloc[take].reset_index(drop=True), camber[take], sweep[take]
    lidx = {f: v[take] for f, v in lidx.items()}
    sweep = pd.factorize(sweep, sort=True)[0]
    if "fz" not in lidx:  # pragma: no cover - fz is required
        raise DataError("no fz")
    cell = pd.factorize(pd.MultiIndex.from_arrays([lidx[f] for f in lidx]), sort=True)[0]
    pressure = d["pressure"].to_numpy(float) if "pressure" in d.columns else None
    speed = d["speed"].to_numpy(float) if "speed" in d.columns else None

    def _ref(f):
        lv = levels.get(f)
        if lv is None:
            return None
        return float(lv[len(lv) // 2])  # the middle level

    rated = rated_load if rated_load is not None else meta.get("rated_load")
    if rated is not None and not (np.isfinite(rated) and rated > 0):
        raise DataError(f"rated load must be a positive force in N, got {rated}")
    inputs = ModelInputs(fz=d["fz"].to_numpy(float), slip_angle=d["slip_angle"].to_numpy(float), camber=camber,
                         pressure=pressure, speed=speed, rated_load=None if rated is None else float(rated),
                         pressure_ref=_ref("pressure"), speed_ref=_ref("speed"), fz_ref=_ref("fz"))
    sa = inputs.slip_angle
    summary = DataSummary(
        fz_levels=tuple(map(float, levels["fz"])),
        camber_levels=tuple(map(float, levels["camber"])),
        pressure_levels=tuple(map(float, levels.get("pressure", ()))),
        speed_levels=tuple(map(float, levels.get("speed", ()))),
        slip_min=float(np.quantile(sa, 0.005)), slip_max=float(np.quantile(sa, 0.995)),
        rated_load=inputs.rated_load, n_sweeps=int(sweep.max()) + 1)
    return SweepData(inputs=inputs, fy=d["fy"].to_numpy(float), sweep=sweep, levels=levels, level_index=lidx,
                     cell=cell, summary=summary, n_raw=n_raw, source=source, notes=notes,
                     convention=str(getattr(data, "convention", "iso") or "iso"),
                     static_pushes=bool(meta.get("converted_from") is not None
                                        and "Eq. 1" in str(meta.get("equation", ""))))
