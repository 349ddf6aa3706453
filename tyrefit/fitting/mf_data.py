"""The records of one tyre gathered for the Magic Formula fit: points, sweep kinds, conditions and levels.

:func:`prepare_mf_data` reads or takes one or more records (a cornering and a drive/brake record, say), gives
every point its sweep kind (lateral, longitudinal, combined; free-rolling sweeps found by their small Fx) and
makes run numbers unique over the records; :class:`MFData` holds them with one row per sweep.
:func:`channel_signal` says whether a channel carries more than its noise, :func:`condition_levels`
groups the sweeps' conditions into levels.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import DataError, option
from ..io.levels import group_levels
from ..io.readers import read_data
from .engine import _derive_runs
from .mf_result import _noise_floor

__all__ = ["MFData", "prepare_mf_data", "channel_signal", "condition_levels", "SIGNAL_RATIO", "FREE_ROLLING_FX"]

_DEG = math.pi / 180.0

# --------------------------------------------------------------------------------- data
_CHANNELS = ("fx", "fy", "mz", "mx", "my")


@dataclass
class MFData:
    """Every point of every record, with its sweep kind, and the sweeps' conditions.

    Attributes
    ----------
    df : DataFrame
        ``fz`` [N], ``slip_angle`` [rad], ``slip_ratio`` [-], ``camber`` [rad],
        ``pressure`` [Pa], ``speed`` [m/s] (NaN where a record does not give
        them: the nominal value is used), measured channels ``fx fy mz mx my``
        (NaN where not measured), ``run`` (unique over all records), ``source``
        and ``kind`` ('lateral', 'longitudinal', 'combined').
    sweeps : DataFrame
        one row per run: kind, source, n, mean conditions, slip span.
    sources : list of str
    notes : list of str
    """

    df: pd.DataFrame
    sweeps: pd.DataFrame
    sources: list[str]
    notes: list[str] = field(default_factory=list)
    #: noise floor per channel [N or N*m], filled on first use (:func:`channel_signal`)
    floors: dict = field(default_factory=dict)

    def envelope(self) -> dict[str, tuple[float, float]]:
        """The operating ranges every record covers (SI): fz, camber, slip_ratio, slip_angle, pressure.

        What the written file declares (``[*_RANGE]``), so what a simulator may evaluate; the fit holds its
        constraints over it (:func:`_grid`).
        """
        df = self.df
        out = {"fz": (float(df["fz"].min()), float(df["fz"].max())),
               "camber": (float(df["camber"].min()), float(df["camber"].max()))}
        lon = df[df["kind"] != "lateral"]
        lat = df[df["kind"] != "longitudinal"]
        if len(lon):
            out["slip_ratio"] = (float(lon["slip_ratio"].min()), float(lon["slip_ratio"].max()))
        if len(lat):
            out["slip_angle"] = (float(lat["slip_angle"].min()), float(lat["slip_angle"].max()))
        pr = df["pressure"].to_numpy(float)
        if np.isfinite(pr).any():
            out["pressure"] = (float(np.nanmin(pr)), float(np.nanmax(pr)))
        return out

    def subset(self, kinds: Sequence[str], channel: str) -> pd.DataFrame:
        d = self.df[self.df["kind"].isin(kinds)]
        if channel not in d:
            return d.iloc[:0]
        return d[np.isfinite(d[channel].to_numpy(float))]


def _span(v: np.ndarray) -> float:
    v = v[np.isfinite(v)]
    if v.size < 2:
        return 0.0
    lo, hi = np.percentile(v, [2, 98])  # robust to single spikes
    return float(hi - lo)


#: a slip-angle sweep is free rolling when its |Fx| (90th percentile) stays below this fraction of its |Fy|
FREE_ROLLING_FX = 0.2


def _free_rolling(g: pd.DataFrame) -> bool:
    """A slip-angle sweep whose longitudinal force stays small beside its lateral force: no drive or brake slip.

    A rig's slip-ratio channel during cornering carries an offset and a drift with slip angle (FSAE TTC: the
    slip ratio is computed from an effective rolling-radius estimate; diagnose keeps such sweeps as cornering,
    :func:`tyrefit.diagnose.data._slip_ratio_segments`).  Read as combined slip, a 0.025 offset plus 0.3 |alpha|
    moved the bundled TTC-style pair's cornering sweeps out of the Fy0/Mz0 stages (FX RMSE 1117 N, 7.7 x its
    floor).  A real drive or brake slip of a few per cent gives |Fx| of the order of |Fy| (slip stiffness
    K_x ~ 20-30 Fz), so |Fx| small beside |Fy| tells free rolling from a slip-angle sweep at a held slip ratio.
    """
    if "fx" not in g or "fy" not in g:
        return False
    fx, fy = g["fx"].to_numpy(float), g["fy"].to_numpy(float)
    fx, fy = fx[np.isfinite(fx)], fy[np.isfinite(fy)]
    if fx.size < 5 or fy.size < 5:
        return False
    return float(np.percentile(np.abs(fx), 90)) < FREE_ROLLING_FX * float(np.percentile(np.abs(fy), 90))


def _classify(g: pd.DataFrame) -> str | None:
    sa = g["slip_angle"].to_numpy(float)
    sr = g["slip_ratio"].to_numpy(float)
    sa_span, sr_span = _span(sa), _span(sr)
    sa_med = float(np.nanmedian(sa)) if np.isfinite(sa).any() else 0.0
    sr_med = float(np.nanmedian(sr)) if np.isfinite(sr).any() else 0.0
    if sa_span >= 0.5 * _DEG and sr_span < 0.05:
        # slip-angle sweep; slip-ratio noise of +-0.01 (FSAE TTC) is still pure cornering
        if abs(sr_med) < 0.02 or (sa_span >= 2.0 * _DEG and _free_rolling(g)):
            return "lateral"
        return "combined"
    if sr_span >= 0.01 and sa_span < 1.5 * _DEG:
        return "longitudinal" if abs(sa_med) < 0.5 * _DEG else "combined"
    if sr_span >= 0.01 and sa_span >= 0.5 * _DEG:
        # a swept slip angle with a drifting slip-ratio channel and no longitudinal force: free-rolling cornering
        return "lateral" if sa_span >= 2.0 * _DEG and _free_rolling(g) else "combined"
    return None


def _as_frame(item, convention: str):
    """(DataFrame, source) of a Dataset, a DataFrame or a path."""
    if isinstance(item, pd.DataFrame):
        return item, ""
    if hasattr(item, "df"):
        return item.df, str(getattr(item, "source", "") or "")
    ds = read_data(item, convention=convention)
    return ds.df, str(ds.source)


def prepare_mf_data(data, *, convention: str = "iso") -> MFData:
    """Gather one or more records of one tyre into an :class:`MFData`.

    Parameters
    ----------
    data : Dataset, DataFrame or path, or a sequence of them
        canonical columns (SI, ISO-W): ``fz`` and at least one of ``fx``,
        ``fy``, ``mz`` with ``slip_angle`` and/or ``slip_ratio``; ``run`` per
        file (derived by the readers).
    convention : {'iso', 'sae'}
        for paths: the files' sign convention.

    Each run is classified: *lateral* (the slip angle spans >= 0.5 deg and the
    slip ratio less than 0.05, with |median slip ratio| < 0.02), *longitudinal*
    (the slip ratio spans >= 0.01, the slip angle less than 1.5 deg and
    |median| < 0.5 deg), *combined* (a slip-ratio sweep at a slip angle, or a
    slip-angle sweep at a slip ratio, or both varying).  Runs that are none
    (no slip variation) are left out with a note.  Points with NaN or
    non-positive ``fz`` or NaN slip are dropped.
    """
    items = list(data) if isinstance(data, (list, tuple)) else [data]
    if not items:
        raise DataError("no data given")
    frames, sources, notes = [], [], []
    next_run = 0
    for k, item in enumerate(items):
        df, src = _as_frame(item, convention)
        src = src or f"data {k + 1}"
        if "fz" not in df:
            raise DataError(f"{src}: no 'fz' column; fitting needs the normal load of every point")
        if not any(c in df for c in ("fx", "fy", "mz")):
            raise DataError(f"{src}: no force channel (fx, fy or mz): nothing to fit")
        if "slip_angle" not in df and "slip_ratio" not in df:
            raise DataError(f"{src}: neither slip_angle nor slip_ratio: a Magic Formula fit needs slip sweeps")
        if "lateral_displacement" in df and "slip_angle" not in df:
            raise DataError(f"{src}: static-rig data (lateral displacement) cannot be fitted to a Magic Formula "
                            f"tyre; fit them with {option('model', 'pac89')} and {option('patch')}")
        d = pd.DataFrame(index=df.index)
        for c in ("fz", "slip_angle", "slip_ratio", "camber", "pressure", "speed") + _CHANNELS:
            d[c] = pd.to_numeric(df[c], errors="coerce").astype(float) if c in df else np.nan
        for c in ("slip_angle", "slip_ratio", "camber"):
            if c not in df:
                d[c] = 0.0
        d["camber"] = d["camber"].fillna(0.0)
        for c in _CHANNELS:  # a rig without a channel often writes zeros: not a measured zero moment
            v = d[c].to_numpy()
            if c in df and np.isfinite(v).any() and not np.any(np.abs(v[np.isfinite(v)]) > 0):
                d[c] = np.nan
                notes.append(f"{src}: '{c}' is zero throughout; it is not fitted")
        if "run" in df:
            run = pd.to_numeric(df["run"], errors="coerce").fillna(-1).astype(int).to_numpy()
        else:
            run = _derive_runs(d.assign(run=0).drop(columns="run"))
        d["source"] = src
        ok = (np.isfinite(d["fz"].to_numpy()) & (d["fz"].to_numpy() > 0) & np.isfinite(d["slip_angle"].to_numpy())
              & np.isfinite(d["slip_ratio"].to_numpy()) & (run >= 0))
        d, run = d[ok], run[ok]
        _, inv = np.unique(run, return_inverse=True)
        d["run"] = inv + next_run
        next_run += int(inv.max()) + 1 if len(inv) else 0
        frames.append(d)
        sources.append(src)
    df = pd.concat(frames, ignore_index=True)
    kinds = {}
    dropped = []
    for run, g in df.groupby("run", sort=True):
        if len(g) < 5:
            dropped.append(int(run))
            continue
        kinds[run] = _classify(g)
        if kinds[run] is None:
            dropped.append(int(run))
    df["kind"] = df["run"].map(kinds)
    if dropped:
        notes.append(f"{len(dropped)} run(s) without slip variation or with < 5 points left out")
    df = df[df["kind"].notna()].reset_index(drop=True)
    if df.empty:
        raise DataError(f"{', '.join(sources)}: nothing to fit: need sweeps of slip_angle (0.5 deg span) or "
                        "slip_ratio (0.01 span) with at least 5 points")
    g = df.groupby("run", sort=True)
    sw = g[["fz", "camber", "pressure", "speed", "slip_angle", "slip_ratio"]].mean()
    sw["n"] = g.size()
    sw["kind"] = g["kind"].first()
    sw["source"] = g["source"].first()
    sw["alpha_span"] = g["slip_angle"].agg(lambda v: _span(v.to_numpy(float)))
    sw["kappa_span"] = g["slip_ratio"].agg(lambda v: _span(v.to_numpy(float)))
    for c in _CHANNELS:
        sw[f"has_{c}"] = g[c].agg(lambda v: bool(np.isfinite(v.to_numpy(float)).sum() >= 5))
    return MFData(df, sw.reset_index(), sources, notes)


#: a channel whose scatter about its mean is within this factor of its noise floor carries no signal
SIGNAL_RATIO = 1.25


def channel_signal(data: MFData, channel: str) -> tuple[float, float, str]:
    """(scatter, noise floor, reason) of one measured channel; reason is '' when it carries a signal.

    The scatter is the rms of the channel about its mean over every point that measures it; the noise
    floor is the one of ``fit``/``diagnose`` (:func:`tyrefit.fitting.mf_result._noise_floor`).  For
    pure noise the two are equal, so a channel whose scatter is within :data:`SIGNAL_RATIO` x the floor
    (signal variance < 0.56 x the noise variance) is not fitted: its coefficients would model noise (a
    pure-noise MX channel would otherwise get a full set of Mx coefficients with R^2 near 0).
    """
    d = data.df
    if channel not in d:
        return float("nan"), float("nan"), ""
    d = d[np.isfinite(d[channel].to_numpy(float))]
    if len(d) < 10:
        return float("nan"), float("nan"), ""
    if channel not in data.floors:
        data.floors[channel] = _noise_floor(d, channel)
    floor = data.floors[channel]
    y = d[channel].to_numpy(float)
    scatter = float(np.sqrt(np.mean((y - y.mean()) ** 2)))
    if np.isfinite(floor) and floor > 0 and scatter <= SIGNAL_RATIO * floor:
        unit = "N*m" if channel in ("mz", "mx", "my") else "N"
        return scatter, floor, (f"{channel.upper()} not fitted: no signal above its noise floor (scatter "
                                f"{scatter:.3g} {unit} rms about its mean, noise floor {floor:.3g} {unit}; "
                                f"needs > {SIGNAL_RATIO:g} x)")
    return scatter, floor, ""


# ------------------------------------------------------------------------ condition levels
def _levels(values, tol: float) -> list[float]:
    """Levels of ``values`` [SI]: gap clustering with the absolute tolerance ``tol`` (:func:`tyrefit.io.levels.group_levels`)."""
    return [float(x) for x in group_levels(values, tol)[0]]


def condition_levels(sweeps: pd.DataFrame) -> dict[str, list[float]]:
    """Levels of load [N], camber [rad], |camber|, pressure [Pa], speed [m/s] and slip angle of ``sweeps``."""
    fz = sweeps["fz"].to_numpy(float)
    lv = group_levels(fz, 100.0, 0.04)[1]  # loads within max(100 N, 4 % of the largest load)
    loads = sorted(float(np.mean(fz[lv == k])) for k in np.unique(lv)) if len(fz) else []
    cam_tol = 0.25 * _DEG
    return {"fz": loads,
            "camber": _levels(sweeps["camber"], cam_tol),
            "abs_camber": _levels(np.abs(sweeps["camber"]), cam_tol),
            "pressure": _levels(sweeps["pressure"], 5e3),
            "speed": _levels(sweeps["speed"], 2.0 / 3.6),
            "slip_angle": _levels(sweeps["slip_angle"], 0.5 * _DEG)}
