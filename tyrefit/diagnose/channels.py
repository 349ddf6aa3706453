"""Diagnosis of the aligning moment Mz and the longitudinal force Fx.

The lateral diagnosis (:mod:`tyrefit.diagnose.engine`) looks at Fy.  A rig record usually
carries more: every cornering sweep of an FSAE TTC file has Mz, and its drive/brake sweeps
have Fx against slip ratio.  What the model misses there matters as much (steering torque,
braking and traction), so each channel present gets its own diagnosis with its own
catalogue (:mod:`tyrefit.effects.channels`):

1. **Data.**  Mz comes from the cornering sweeps the lateral diagnosis reads (the same
   sweeps, levels and thinning, :func:`~tyrefit.diagnose.data.prepare`), with the side force
   of the same points (:func:`reference_side_force`: each sweep's Fy smoothed by its own
   Magic Formula curve, taken at the least-cambered sweep of the same load and pressure, since
   the trail multiplies the side force of slip alone); Fx from the
   drive/brake sweeps at zero slip angle (:func:`~tyrefit.diagnose.data.slip_ratio_segments`:
   slip ratio swept by >= ``KAPPA_SWEPT``, median slip angle within ``ALPHA_PURE`` of zero).
   Combined-slip sweeps stay out.
2. **Start model.**  Mz: the pneumatic trail times that side force
   (:func:`tyrefit.effects.channels.trail_moment`, Magic Formula 5.2/6.1's pure-slip form) with
   the trail's shape factor, peak, stiffness factor and its load law, and a constant curvature.
   Fx: PAC89's longitudinal part with the shape factor, one peak coefficient, the stiffness load
   law and a constant curvature.  Both from :data:`~tyrefit.effects.channels.START`, fitted by
   least squares on the channel in N or N*m, every point alike (the statistics below are point-wise).
   Beside the result, PAC89's aligning part fitted with every coefficient the data identify says
   what a PAC89 ``.tir`` keeps of the record's Mz (``pac89`` of the JSON).
3. **Forward selection on held-out sweeps.**  Every testable catalogue effect is added in
   turn and refitted; whole sweeps are held out (each in turn up to
   :attr:`ChannelSettings.loso_max_sweeps`, else ``folds`` groups of sweeps) and
   predicted by the fit to the others.  The best candidate is accepted when

   * its held-out RMSE is lower by at least ``margin`` x the noise floor and 1 % of the
     current held-out RMSE (a practical difference, not only a significant one);
   * it lowers the held-out error in at least half of the held-out sweeps (one sweep
     that happens to suit it is not evidence);
   * a nested F test on all the data, with the error variance inflated by
     (1 + rho) / (1 - rho) for the lag-one correlation rho of the noise along the
     sweeps (:class:`~tyrefit.fitting.noise.LagOneNoise`: its 90 % upper bound, read from
     the richest model's residuals) and the error degrees of freedom shrunk to the effective sample size
     n (1 - rho) / (1 + rho), or a paired t test over the held-out sweeps (independent
     whatever the noise does along a sweep), or the held-out gain against its null under
     the AR(1) + sweep-offset noise model estimated (and bias-corrected) from the richest
     model's residuals (:class:`~tyrefit.diagnose.stats.HeldoutNull`, the lateral
     diagnosis' second gate) gives p < ``alpha / (3 m)`` for the m candidates of the
     round: correlated rig noise along a sweep does not pass for an effect, nor does the
     best of many candidates pass by chance;
   * camber and pressure are named only where the residual differs between their levels
     consistently from load to load (:func:`~tyrefit.diagnose.contrast.camber_evidence`);
     their refinements, once the family is named, need only the held-out evidence;
   * a refinement (:attr:`~tyrefit.effects.base.Effect.refinement`) only refines a
     family that has already been accepted.

   Repeat until nothing passes.
4. **What is left.**  The final held-out RMSE against the within-sweep noise floor
   (:func:`tyrefit.fitting.noise.noise_floor`: a smooth spline through each sweep), with
   whether the residual's slip pattern repeats from sweep to sweep (:func:`systematic_share`),
   in the plain words of :func:`_verdict`: nothing missing, structure remains (and the model
   form that limits it), or undecided (and the repeat test that would decide).

The result, :class:`ChannelDiagnosis`, gives the JSON of the DESIGN contract's
``channels`` entry (``accepted``, ``steps``, ``noise_floor``, ``unexplained``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from scipy import stats
from scipy.optimize import least_squares

from ..effects.base import Effect, ModelInputs
from ..effects.channels import CHANNEL_EFFECTS, CHANNELS, COEFFICIENT, PAC89_COEFFICIENT, START, trail_moment
from ..errors import DataError, FitError
from ..fitting._blas import single_threaded_blas
from ..fitting.core import Parameters, solve
from ..fitting.noise import LagOneNoise, noise_floor
from ..models import pac89
from .data import SweepData, prepare, segments, slip_ratio_segments
from .contrast import CAMBER_ALPHA, _camber_evidence
from .stats import HeldoutNull, SweepLayout, corrected_noise, projection_basis

__all__ = ["ChannelSettings", "ChannelData", "ChannelStep", "ChannelDiagnosis", "channel_data", "diagnose_channel",
           "diagnose_channels", "predict", "nested_p", "sweep_p", "systematic_share", "reference_side_force", "UNITS"]

_DEG = np.pi / 180.0
#: the knot spacing of the noise floor's smooth curve, in the channel's slip unit
_FLOOR_SPACING = {"fy": 1.5 * _DEG, "mz": 1.5 * _DEG, "fx": 0.02}
#: unit of each channel
UNITS = {"fy": "N", "mz": "N*m", "fx": "N"}


@dataclass(frozen=True)
class ChannelSettings:
    """Settings of a channel diagnosis.

    alpha : level of a round of the selection: each candidate's three tests run at alpha / (3 m), m the
        candidates of the round (Bonferroni).
    margin : practical margin, as a fraction of the noise floor, by which a candidate must lower the held-out RMSE.
    min_sweeps_improved : share of held-out sweeps whose error a candidate must lower.
    loso_max_sweeps : up to this many sweeps every sweep is held out in turn; more are grouped in ``folds``.
    rho_upper : confidence of the upper bound on the noise's lag-one correlation the F test is corrected with.
    folds : sweep groups held out in turn with more sweeps.
    max_rounds : most effects added.
    n_null : draws of the held-out gain's null under the estimated noise model.
    """

    alpha: float = 0.05
    margin: float = 0.03
    min_sweeps_improved: float = 0.5
    loso_max_sweeps: int = 16
    folds: int = 8
    max_rounds: int = 8
    rho_upper: float = 0.9
    n_null: int = 499


@dataclass
class ChannelData:
    """One channel's sweeps: the slip, the measured channel and the conditions of every point.

    ``sweeps`` is the :class:`~tyrefit.diagnose.data.SweepData` of the channel (its ``fy`` holds the channel's
    values, its ``inputs.slip_angle`` the channel's slip: slip angle [rad] for Mz, slip ratio [-] for Fx).
    """

    channel: str
    sweeps: SweepData
    #: per point: its sweep, held out, lies inside the condition levels of the rest (set by the diagnosis)
    interior: np.ndarray | None = None

    @property
    def y(self) -> np.ndarray:
        return self.sweeps.fy

    @property
    def slip(self) -> np.ndarray:
        return self.sweeps.inputs.slip_angle

    @property
    def inputs(self) -> ModelInputs:
        return self.sweeps.inputs

    @property
    def sweep(self) -> np.ndarray:
        return self.sweeps.sweep

    @property
    def n_sweeps(self) -> int:
        return self.sweeps.n_sweeps

    @property
    def unit(self) -> str:
        return UNITS[self.channel]


@dataclass
class ChannelStep:
    """One model of the selection: effects, fitted values, and its errors on all and on held-out sweeps."""

    effects: list[str]
    added: str | None
    values: dict[str, float]
    rmse: float
    rmse_heldout: float
    resid: np.ndarray = field(repr=False)
    resid_heldout: np.ndarray = field(repr=False)
    n_params: int = 0
    #: RMSE of the held-out sweeps outside the levels the rest was fitted on (extrapolation), NaN if none
    rmse_extrapolated: float = float("nan")


@dataclass
class ChannelDiagnosis:
    """What a channel's model misses: the steps, the evidence for every candidate, what is left."""

    channel: str
    data: ChannelData
    start: list[str]
    accepted: list[str]
    steps: list[ChannelStep]
    candidates: list[dict]
    noise_floor: float
    unexplained: dict
    pac89: dict
    seconds: float = float("nan")
    #: the accepted effects in words and sizes (:func:`effect_sizes`, computed on first use)
    sizes: list | None = None

    @property
    def unit(self) -> str:
        return self.data.unit

    def to_dict(self) -> dict:
        """The ``channels`` entry of ``diagnose --json`` (DESIGN contract)."""
        sd = self.data.sweeps
        return {
            "unit": self.unit,
            "start": list(self.start),
            "accepted": list(self.accepted),
            "noise_floor": float(self.noise_floor),
            "steps": [{"effects": list(s.effects), "rmse": float(s.rmse), "rmse_heldout": float(s.rmse_heldout),
                       "rmse_extrapolated": None if not np.isfinite(s.rmse_extrapolated) else float(s.rmse_extrapolated),
                       "added": s.added} for s in self.steps],
            "candidates": [dict(c) for c in self.candidates],
            "unexplained": dict(self.unexplained),
            "pac89": dict(self.pac89),
            "effects": effect_sizes(self),
            "data": {"points": int(sd.n), "sweeps": int(sd.n_sweeps),
                     "fz": [float(v) for v in sd.levels["fz"]],
                     "camber_deg": [float(np.degrees(v)) for v in sd.levels["camber"]],
                     **({"pressure": [float(v) for v in sd.levels["pressure"]]} if "pressure" in sd.levels else {}),
                     "notes": list(sd.notes)},
            "seconds": float(self.seconds),
        }

    def summary(self) -> str:
        """A few lines for the terminal."""
        u = self.unit
        out = [f"{self.channel}: noise floor {self.noise_floor:.3g} {u}"]
        for s in self.steps:
            label = ("without " + s.added[1:] if s.added.startswith("-") else "+ " + s.added) if s.added else "start"
            out.append(f"  {label:<28} RMSE {s.rmse:8.3g} {u}   "
                       f"held-out {s.rmse_heldout:8.3g} {u}")
        out.append(f"  accepted: {', '.join(self.accepted) or 'nothing beyond the start model'}")
        out.append("  " + self.unexplained.get("summary", ""))
        return "\n".join(out)


# ----------------------------------------------------------------------------------- data
def _frame_of(data) -> tuple[pd.DataFrame, str, dict]:
    if isinstance(data, pd.DataFrame):
        return data, "DataFrame", {}
    return data.df, str(getattr(data, "source", "")), dict(getattr(data, "meta", {}) or {})


def channel_data(data, channel: str, rated_load: float | None = None) -> ChannelData | str:
    """The sweeps of ``channel`` in ``data`` (a Dataset or a canonical DataFrame), or why there are none.

    Mz: the cornering sweeps that carry ``mz`` (combined-slip and drive/brake segments left out, as the
    lateral diagnosis does).  Fx: the drive/brake sweeps at zero slip angle (see the module docstring).
    """
    if channel not in UNITS:
        raise DataError(f"channel={channel!r}: one of {', '.join(UNITS)}")
    df, source, meta = _frame_of(data)
    rated = rated_load if rated_load is not None else meta.get("rated_load")
    keep = [c for c in ("run", "camber", "pressure", "speed", "load") if c in df.columns]
    side = None
    if channel in ("mz", "fy"):
        what = "aligning moment (mz)" if channel == "mz" else "lateral force (fy)"
        need = (channel, "slip_angle", "fz")
        if any(c not in df.columns for c in need) or df[channel].notna().sum() < 20:
            return f"no {what} in the record"
        cols = ["slip_angle", "fz"] + keep + (["slip_ratio"] if "slip_ratio" in df.columns else [])
        frame = df[cols].assign(fy=df[channel])
        if channel == "mz":
            # the trail model needs the side force of the same points: keep the points that have both
            fy = (pd.to_numeric(df["fy"], errors="coerce").replace([np.inf, -np.inf], np.nan) if "fy" in df.columns
                  else pd.Series(np.nan, index=df.index))
            if fy.notna().sum() < 20:
                return ("the aligning moment's model (Mz = -trail x Fy + residual torque) needs the side force "
                        "of the same points, and the record has no finite fy")
            if not float(np.nanmax(np.abs(fy.to_numpy(float)))) > 1.0:
                return "the side force of the aligning-moment points is zero throughout: no trail to diagnose"
            both = fy.notna().to_numpy()
            frame = frame[both]
            side = frame.assign(fy=fy[both])
        if frame.dropna(subset=["slip_angle", "fz", "fy"]).empty:
            return f"no {what} in the record"
    else:
        need = ("fx", "slip_ratio", "fz")
        if any(c not in df.columns for c in need) or df["fx"].notna().sum() < 20:
            return "no drive/brake sweeps (fx against slip_ratio) in the record"
        frame = _pure_longitudinal(df, keep)
        if frame is None:
            return "no drive/brake sweeps at zero slip angle (slip ratio swept by >= 0.05) in the record"
    try:
        sd = prepare(frame, rated_load=rated)
        if side is not None:
            # the same points in the same order: prepare's choice of points does not look at the values
            sf = prepare(side.assign(fy=side["fy"].where(frame["fy"].notna())), rated_load=rated)
            if (len(sf.fy) != len(sd.fy) or not np.array_equal(sf.inputs.fz, sd.inputs.fz)
                    or not np.array_equal(sf.inputs.slip_angle, sd.inputs.slip_angle)):
                return "the side force and the aligning moment are not measured at the same points"
            force, zero = reference_side_force(sf)
            sd.inputs = sd.inputs._replace(side_force=force, side_force_zero=zero)
    except DataError as e:
        return str(e).split(": ", 1)[-1]
    sd.source = source
    return ChannelData(channel, sd)


def _sweep_curve(x: np.ndarray, y: np.ndarray):
    """One sweep's side force as a Magic Formula curve in slip, or None where a curve cannot follow it.

    Fy = D sin(C atan(B a - E (B a - atan(B a)))) + Sv, a = slip + Sh (Pacejka 2012, Eq. 4.6), fitted by
    least squares from three starts: six numbers per sweep, so the curve keeps the sweep's own peak,
    shifts and shape while about 6 / n of the noise variance remains.  None for a sweep of fewer than
    10 points, or one the curve misses by more than twice the sweep's own point-to-point scatter (a
    loop, a broken sweep).
    """
    if len(x) < 10 or np.ptp(x) <= 0:
        return None
    d0 = float(y[np.argmax(np.abs(y))])
    small = np.abs(x) < max(2.0 * _DEG, float(np.quantile(np.abs(x), 0.2)))
    k0 = (float(np.polyfit(x[small], y[small], 1)[0]) if small.sum() >= 3 and np.ptp(x[small]) > 0
          else d0 / (3 * _DEG))
    if d0 == 0.0 or k0 == 0.0:
        return None

    def curve(p, xx):
        b, c, d, e, sh, sv = p
        a = b * (xx + sh)
        return d * np.sin(c * np.arctan(a - e * (a - np.arctan(a)))) + sv

    best = None
    for c0, e0 in ((1.3, 0.0), (1.8, -1.0), (1.1, 0.5)):
        b0 = k0 / (c0 * d0)
        b0 = b0 if b0 > 0 else (abs(b0) or 10.0)
        try:
            sol = least_squares(lambda p: curve(p, x) - y, [b0, c0, d0 * 1.05, e0, 0.0, 0.0], method="trf",
                                x_scale="jac", bounds=([1e-3, 0.3, -np.inf, -20.0, -0.2, -np.inf],
                                                       [1e3, 3.0, np.inf, 1.0, 0.2, np.inf]), max_nfev=300)
        except (ValueError, FloatingPointError):
            continue
        if np.isfinite(sol.cost) and (best is None or sol.cost < best.cost):
            best = sol
    if best is None:
        return None
    miss = float(np.sqrt(np.mean((curve(best.x, x) - y) ** 2)))
    order = np.argsort(x)
    scatter = float(np.median(np.abs(np.diff(y[order], 2)))) / 0.6745 / np.sqrt(6.0)
    if miss > 2.0 * scatter + 1e-9 * abs(d0):
        return None
    p = best.x
    return lambda xx: curve(p, np.asarray(xx, float))


def reference_side_force(sf: SweepData) -> tuple[np.ndarray, np.ndarray]:
    """The side force the trail multiplies, at every point of ``sf`` (the side-force sweeps of the Mz points).

    Magic Formula 5.2/6.1 multiply the trail by the side force of slip alone, at zero camber
    (Pacejka 2012, Eq. 4.E31 with Fy0(gamma = 0)): the camber thrust acts near the patch centre, not at
    the trail.  So each sweep takes the smoothed side force (:func:`_sweep_curve`) of the sweep at the
    same load, pressure and speed levels with the smallest |camber| (its own where it is that sweep or
    no such sweep exists), evaluated at its own slip angles.  Where no curve follows a sweep, its measured
    values (or the reference sweep's, interpolated in slip) are used.

    Returns the side force at every point and the slip angle [rad] where its sweep's reference side
    force crosses zero (MF 6.1 centres the residual torque there, alpha_r = alpha + SHf, Eq. 4.E37-4.E38;
    0 where it does not cross zero within the sweep).
    """
    x, y = sf.inputs.slip_angle, np.asarray(sf.fy, float)
    G = sf.n_sweeps
    curves, own = [], []
    for g in range(G):
        m = sf.sweep == g
        curves.append(_sweep_curve(x[m], y[m]))
        own.append(m)
    cam = np.abs(sf.levels["camber"][sf.sweep_level("camber")]) if "camber" in sf.levels else np.zeros(G)
    others = [f for f in sf.levels if f != "camber"]
    key = np.column_stack([sf.sweep_level(f) for f in others]) if others else np.zeros((G, 1), int)
    out = y.copy()
    zero = np.zeros(len(y))
    for g in range(G):
        same = np.flatnonzero((key == key[g]).all(axis=1))
        ref = int(same[np.argmin(cam[same])]) if len(same) else g
        if cam[ref] >= cam[g]:
            ref = g
        m = own[g]
        if curves[ref] is not None:
            out[m] = curves[ref](x[m])
        elif ref != g:
            o = np.argsort(x[own[ref]])
            out[m] = np.interp(x[m], x[own[ref]][o], y[own[ref]][o])
        zero[m] = _zero_crossing(x[own[ref]], y[own[ref]], curves[ref])
    return out, zero


def _zero_crossing(x: np.ndarray, y: np.ndarray, curve) -> float:
    """The slip nearest zero where the sweep's side force (its curve, else its points) changes sign; 0 if none."""
    if curve is not None:
        xs = np.linspace(float(np.min(x)), float(np.max(x)), 2001)
        ys = curve(xs)
    else:
        o = np.argsort(x)
        xs, ys = x[o], y[o]
    i = np.flatnonzero(np.sign(ys[:-1]) * np.sign(ys[1:]) < 0)
    if not len(i):
        return 0.0
    roots = xs[i] - ys[i] * (xs[i + 1] - xs[i]) / (ys[i + 1] - ys[i])
    return float(roots[np.argmin(np.abs(roots))])


def _pure_longitudinal(df: pd.DataFrame, keep: list[str]) -> pd.DataFrame | None:
    """Points of the drive/brake sweeps at zero slip angle, as a frame ``prepare`` reads (slip ratio as the slip)."""
    cols = ["fx", "slip_ratio", "fz"] + (["slip_angle"] if "slip_angle" in df.columns else []) + keep
    d = df[cols].apply(pd.to_numeric, errors="coerce")
    d = d[d[["fx", "slip_ratio", "fz"]].notna().all(axis=1) & (d["fz"] > 0)].reset_index(drop=True)
    if len(d) < 20:
        return None
    if "slip_angle" not in d.columns:
        d["slip_angle"] = 0.0
    d["slip_angle"] = d["slip_angle"].fillna(0.0)
    _, _, _, seg = segments(d)
    _, take, _ = slip_ratio_segments(d, seg)
    kap = d["slip_ratio"].to_numpy(float)
    if take.sum() < 20:
        return None
    out = d[take].drop(columns=[c for c in ("slip_angle", "run") if c in d.columns])
    return out.assign(slip_angle=kap[take], fy=d["fx"].to_numpy(float)[take], run=seg[take]).drop(columns="fx")


# ---------------------------------------------------------------------------------- model
def _part(channel: str) -> tuple[str, ...]:
    return tuple(COEFFICIENT["mz"]) if channel == "mz" else pac89.LONGITUDINAL


def predict(channel: str, values: dict, effects: list[Effect], x: ModelInputs) -> np.ndarray:
    """The channel (Mz [N*m] or Fx [N], ISO-W) of the start model plus ``effects`` at the inputs ``x``.

    Mz: the trail model (:func:`tyrefit.effects.channels.trail_moment`, measured Fy in ``x.side_force``);
    Fx: PAC89's longitudinal part.  ``x.slip_angle`` holds the channel's slip (slip angle [rad] for Mz,
    slip ratio for Fx).  Coefficients not in ``values`` take their neutral values.
    """
    defs = COEFFICIENT[channel]
    coef = {k: values.get(k, defs[k].neutral if channel == "mz" else 0.0) for k in _part(channel)}
    for e in effects:
        if e.apply is not None:
            e.apply(coef, {p.name: values.get(p.name, p.neutral) for p in e.params}, x)
    sv = coef.pop("sv", 0.0)
    if channel == "mz":
        return trail_moment(coef, x)
    return pac89.longitudinal_force(coef, x.fz, x.slip_angle) + sv


def _start_values(cd: ChannelData) -> dict[str, float]:
    """Start values of the start model from the sweeps.

    Mz: the peak trail from -Mz / Fy at small slip (1-3 deg, where the trail is near its peak and Fy well
    away from zero), per unit load at the middle load; the trail's shape from typical values (the fit's
    other starts cover the C-E valley).  Fx (PAC89 units, slip ratio in percent): the peak and the
    small-slip slope per kN.
    """
    sd = cd.sweeps
    x, y = sd.inputs.slip_angle, cd.y
    if cd.channel == "mz":
        fy = np.asarray(sd.inputs.side_force, float)
        fz_ref = sd.inputs.fz_ref or float(np.median(sd.inputs.fz))
        near = (np.abs(x) > 1.0 * _DEG) & (np.abs(x) < 3.0 * _DEG) & (np.abs(fy) > 0.05 * np.max(np.abs(fy)))
        t = -y[near] / fy[near] / (sd.inputs.fz[near] / fz_ref)
        dt = float(np.median(t)) if near.sum() >= 3 else 0.03
        return {"mz_Ct": 1.2, "mz_Dt": float(np.clip(dt, -0.09, 0.45)), "mz_Bt": 10.0, "mz_Bt_fz": 0.0, "mz_Et": -1.0}
    d, k = _peak_and_slope(x * 100.0, y, sd.inputs.fz * 1e-3, sd.sweep, sd.n_sweeps, small=2.0, default=1000.0)
    return {"b0": 1.65, "b2": min(max(d, 60.0), 3400.0), "b4": max(k, 1.0), "b5": 0.0, "b8": 0.0}


def _peak_and_slope(xs: np.ndarray, ys: np.ndarray, fzk: np.ndarray, sweep: np.ndarray, n_sweeps: int,
                    small: float, default: float) -> tuple[float, float]:
    """Median over the sweeps of the peak of |ys| at positive slip and of the slope within +-``small``, per kN.

    PAC89 units (``fzk`` in kN, ``xs`` in the part's slip unit); ``default`` for the peak where no sweep has 3
    points at positive slip, 5 x the peak for the slope where none has 4 within ``small``.
    """
    peaks, slopes = [], []
    for g in range(n_sweeps):
        m = sweep == g
        fk = float(np.median(fzk[m]))
        pos = m & (xs > 0)
        if pos.sum() >= 3:
            i = np.argmax(np.abs(ys[pos]))
            peaks.append(ys[pos][i] / fk)
        near = m & (np.abs(xs) < small)
        if near.sum() >= 4 and np.ptp(xs[near]) > 0:
            slopes.append(np.polyfit(xs[near], ys[near], 1)[0] / fk)
    d = float(np.median(peaks)) if peaks else default
    k = float(np.median(slopes)) if slopes else 5.0 * d
    return d, k


class _Model:
    """A channel model: its effects and parameters (start model + effects), fitted by :func:`fit`."""

    def __init__(self, cd: ChannelData, effects: list[Effect], fixed: dict[str, float]):
        self.cd = cd
        self.effects = list(effects)
        names = [n for n in START[cd.channel] if n not in fixed]
        for e in self.effects:
            names += [p.name for p in e.params if p.name not in names and p.name not in fixed]
        self.names = names
        self.fixed = dict(fixed)
        self.defs = {p.name: p for e in self.effects for p in e.params}
        self.defs.update({k: v for k, v in COEFFICIENT[cd.channel].items() if k in names and k not in self.defs})

    def parameters(self, values: dict[str, float]) -> Parameters:
        out = Parameters()
        for k in self.names:
            p = self.defs[k]
            v = float(values.get(k, p.neutral))
            lo, hi = p.bounds
            out.add(k, float(np.clip(v, lo, hi)), min=lo, max=hi, scale=p.scale)
        for k, v in self.fixed.items():
            out.add(k, float(v), vary=False)
        return out

    def fit(self, idx: np.ndarray, start: dict[str, float], multistart: bool = False) -> dict[str, float]:
        """Least-squares values on the points ``idx`` from ``start`` (and the C-E valley's other ends)."""
        x = self.cd.inputs.take(idx)
        y = self.cd.y[idx]
        params = self.parameters(start)
        ch = self.cd.channel

        def resid(theta):
            return predict(ch, params.values_of(theta), self.effects, x) - y

        starts = None
        if multistart:
            base = params.valuesdict()
            if ch == "mz":  # the trail's shape: C-E valley and how fast it falls (Bt)
                starts = [base, {**base, "mz_Ct": 1.0, "mz_Et": 0.0, "mz_Bt": 15.0},
                          {**base, "mz_Ct": 1.5, "mz_Et": -3.0, "mz_Bt": 8.0},
                          {**base, "mz_Ct": 1.1, "mz_Et": -5.0, "mz_Bt": 20.0}]
            else:
                starts = [base, {**base, "b0": 1.5, "b8": 0.0}, {**base, "b0": 1.9, "b8": 0.5},
                          {**base, "b0": 1.2, "b8": -2.0}]
        sol = solve(resid, params, method="trf", x_scale="params", starts=starts, nonfinite="penalise",
                    stderr=False, what=f"{ch} channel fit", max_nfev=400)
        return sol.values

    def residual(self, values: dict[str, float], idx: np.ndarray | None = None) -> np.ndarray:
        x = self.cd.inputs if idx is None else self.cd.inputs.take(idx)
        y = self.cd.y if idx is None else self.cd.y[idx]
        return predict(self.cd.channel, values, self.effects, x) - y


def _jacobian(cd: ChannelData, effects: list[Effect], fixed: dict, values: dict, names: list[str]) -> np.ndarray:
    """d channel / d parameter (N, len(names)) at ``values`` by forward differences (steps 1e-6 of each scale)."""
    model = _Model(cd, effects, fixed)
    v0 = {k: float(values.get(k, model.defs[k].neutral)) for k in model.names}
    v0.update(model.fixed)
    f0 = predict(cd.channel, v0, model.effects, cd.inputs)
    J = np.empty((len(f0), len(names)))
    for j, k in enumerate(names):
        d = model.defs[k]
        h = 1e-6 * max(abs(v0[k]), d.scale)
        if v0[k] + h > d.bounds[1]:
            h = -h
        J[:, j] = (predict(cd.channel, {**v0, k: v0[k] + h}, model.effects, cd.inputs) - f0) / h
    return J


def _noise_model(cd: ChannelData, resid: np.ndarray, J: np.ndarray, rng: np.random.Generator):
    """AR(1) + sweep-offset noise of the channel, estimated from ``resid`` and bias-corrected.

    As in the lateral screening: :func:`tyrefit.diagnose.stats.corrected_noise` of the residuals of a model with
    directions ``J``.
    """
    layout = SweepLayout(cd.sweep, cd.n_sweeps)
    Q, dof_w, dof_b = projection_basis(J, layout)
    _, model = corrected_noise(resid, Q, dof_w, dof_b, layout, rng)
    return layout, model


def _folds(cd: ChannelData, s: ChannelSettings, seed: int) -> list[np.ndarray]:
    """Sweep groups held out in turn: each sweep up to ``loso_max_sweeps``, else ``folds`` shuffled groups."""
    G = cd.n_sweeps
    if G <= s.loso_max_sweeps:
        return [np.array([g]) for g in range(G)]
    order = np.random.default_rng(seed).permutation(G)
    return [np.sort(order[k::s.folds]) for k in range(s.folds)]


def _interior(cd: ChannelData, folds) -> np.ndarray:
    """Points of held-out sweeps whose every condition level lies inside the levels the rest was fitted on.

    With one sweep per load, holding out the lightest or heaviest load asks the model to extrapolate the
    load laws; such sweeps are an extrapolation test, not the held-out evidence (as in the lateral
    diagnosis' ``rmse_extrapolated``).
    """
    sd = cd.sweeps
    out = np.zeros(len(cd.y), dtype=bool)
    lv = {f: sd.sweep_level(f) for f in sd.levels}
    for held in folds:
        train = np.setdiff1d(np.arange(sd.n_sweeps), held)
        if not len(train):
            continue
        ok = np.ones(len(held), dtype=bool)
        for f, v in lv.items():
            ok &= (v[held] >= v[train].min()) & (v[held] <= v[train].max())
        out |= np.isin(cd.sweep, held[ok])
    return out


def _evaluate(cd: ChannelData, effects: list[Effect], fixed: dict, start: dict, folds, added: str | None,
              multistart: bool = False) -> ChannelStep:
    model = _Model(cd, effects, fixed)
    allidx = np.arange(len(cd.y))
    values = model.fit(allidx, start, multistart=multistart)
    r = model.residual(values)
    rh = np.full(len(cd.y), np.nan)
    for held in folds:
        test = np.isin(cd.sweep, held)
        if test.all():
            continue
        v = model.fit(np.flatnonzero(~test), values)
        rh[test] = model.residual(v, np.flatnonzero(test))
    inner = np.isfinite(rh) & cd.interior
    ok = inner if inner.any() else np.isfinite(rh)
    outer = np.isfinite(rh) & ~cd.interior
    return ChannelStep([e.id for e in effects], added, values, float(np.sqrt(np.mean(r * r))),
                       float(np.sqrt(np.mean(rh[ok] ** 2))) if ok.any() else float("nan"), r, rh,
                       n_params=len(model.names),
                       rmse_extrapolated=float(np.sqrt(np.mean(rh[outer] ** 2))) if outer.any() else float("nan"))


def nested_p(r0: np.ndarray, r1: np.ndarray, q: int, p1: int, rho: float) -> float:
    """p-value of the nested F test of a model with ``q`` more parameters (``p1`` in all), under AR(1) noise.

    With noise correlated along a sweep (lag-one ``rho``, :class:`tyrefit.fitting.noise.LagOneNoise`), a
    smooth direction removes about (1 + rho) / (1 - rho) times the variance it would under independent
    noise, and the sample holds about n (1 - rho) / (1 + rho) independent values; both corrections apply.
    """
    n = len(r1)
    infl = (1.0 + rho) / (1.0 - rho)
    dof = max(n / infl - p1, 1.0)
    ssr0, ssr1 = float(np.sum(r0 * r0)), float(np.sum(r1 * r1))
    if ssr1 <= 0:
        return 0.0 if ssr0 > 0 else 1.0
    F = ((ssr0 - ssr1) / q) / (ssr1 / max(n - p1, 1) * infl)
    return float(stats.f.sf(F, q, dof)) if F > 0 else 1.0


def _per_sweep_sse(rh: np.ndarray, sweep: np.ndarray) -> np.ndarray:
    ok = np.isfinite(rh)
    return np.bincount(sweep[ok], weights=rh[ok] ** 2, minlength=int(sweep.max()) + 1)


def systematic_share(cd: ChannelData, resid: np.ndarray, n_bins: int = 12) -> float:
    """Share of the final residual's slip pattern that the *other* sweeps predict (leave one sweep out).

    Each sweep's residual is averaged in ``n_bins`` slip bins; the pattern of sweep g is predicted, bin by
    bin, by a plane in the conditions that vary (load, camber, pressure, speed levels) through the other
    sweeps' patterns (their mean where the others share one condition).
    Share = 1 - sum (r_g - prediction)^2 / sum r_g^2 over sweeps and bins; the larger of that and the
    same share with the nearest other sweep in the conditions as the prediction (a misfit that bends
    with load is shared by neighbouring levels, not by a plane).  A misfit of the model repeats from
    sweep to sweep (share well above 0); noise, however correlated along a sweep, is new in every
    sweep (share near -1 for the neighbour, near or below 0 for the plane).  NaN with fewer than 3
    sweeps.
    """
    sd = cd.sweeps
    G = sd.n_sweeps
    if G < 3:
        return float("nan")
    x = cd.slip
    edges = np.quantile(x, np.linspace(0, 1, n_bins + 1))
    b = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, n_bins - 1)
    sums = np.zeros((G, n_bins))
    cnt = np.zeros((G, n_bins))
    np.add.at(sums, (cd.sweep, b), resid)
    np.add.at(cnt, (cd.sweep, b), 1)
    pat = np.where(cnt > 0, sums / np.maximum(cnt, 1), np.nan)
    # the sweeps' conditions, standardised: load, camber, pressure, speed levels that vary
    cols = [np.ones(G)]
    for f in sd.levels:
        v = sd.levels[f][sd.sweep_level(f)]
        if np.ptp(v) > 0:
            cols.append((v - v.mean()) / np.ptp(v))
    Z = np.column_stack(cols)
    # a second predictor: the pattern of the nearest other sweep in the conditions (a misfit that bends with
    # load, a knee, is not a plane in the conditions but is shared by neighbouring levels)
    D = ((Z[:, None, 1:] - Z[None, :, 1:]) ** 2).sum(axis=2) + np.diag(np.full(G, np.inf))
    nearest = np.argmin(D, axis=1)
    fin = np.isfinite(pat) & np.isfinite(pat[nearest])
    nn_den = float(np.sum(pat[fin] ** 2))
    nn = 1.0 - float(np.sum((pat - pat[nearest])[fin] ** 2)) / nn_den if nn_den > 0 else float("nan")
    num = den = 0.0
    for g in range(G):
        rest = np.flatnonzero(np.arange(G) != g)
        for k in range(n_bins):
            ok = np.isfinite(pat[rest, k])
            if not np.isfinite(pat[g, k]):
                continue
            # as many condition terms as the other sweeps carry (at least one sweep more than terms)
            X = Z[rest][ok]
            use = [0] + [j for j in range(1, Z.shape[1]) if np.ptp(X[:, j]) > 0][: max(ok.sum() - 2, 0)]
            if ok.sum() < len(use) + 1:
                continue
            coef = np.linalg.lstsq(X[:, use], pat[rest, k][ok], rcond=None)[0]
            num += (pat[g, k] - Z[g, use] @ coef) ** 2
            den += pat[g, k] ** 2
    plane = float(1.0 - num / den) if den > 0 else float("nan")
    return float(np.nanmax([plane, nn])) if np.isfinite([plane, nn]).any() else float("nan")


#: above this :func:`systematic_share` the residual left is a misfit, below it noise (or undecided)
SYSTEMATIC = 0.3


def _verdict(ratio: float, floor: float, unit: str, share: float, rho: float) -> tuple[str, str]:
    """The verdict on what is left (``nothing``, ``undecided`` or ``structure``) and its plain words.

    ``ratio`` is the held-out RMSE over the within-sweep noise floor, ``share`` the
    :func:`systematic_share` of the final residuals, ``rho`` the noise's lag-one correlation.  The
    within-sweep floor underestimates noise correlated along a sweep (the smooth curve through each
    sweep follows part of it), so a ratio above 1 alone does not show a misfit: it takes a residual
    pattern that repeats from sweep to sweep.
    """
    if not np.isfinite(ratio):
        return "undecided", "the noise floor could not be estimated (sweeps too short)"
    if ratio <= 1.25:
        return "nothing", (f"nothing missing: the held-out error is {ratio:.2f} x the within-sweep noise floor "
                           f"({floor:.3g} {unit})")
    if np.isfinite(share) and share >= SYSTEMATIC:
        return "structure", (f"structure remains: the held-out error is {ratio:.2f} x the within-sweep noise floor "
                             f"({floor:.3g} {unit}), {100 * share:.0f} % of the residual's slip pattern repeats "
                             "from sweep to sweep, and no catalogue effect the data can test takes it away")
    why = (f"the noise is correlated along the sweeps (lag-one {rho:.2f}), which the within-sweep floor "
           "underestimates" if rho >= 0.5 else "the residual's pattern does not repeat from sweep to sweep"
           if np.isfinite(share) else "too few sweeps to see whether the residual's pattern repeats")
    return "undecided", (f"undecided: the held-out error is {ratio:.2f} x the within-sweep noise floor "
                         f"({floor:.3g} {unit}), but {why}; to decide, run one sweep twice in a row at the same "
                         "conditions: the difference between the two runs is the noise alone")


_FORM = {"mz": ("the trail model (Magic Formula 5.2/6.1's pure-slip Mz, Pacejka 2012, Eq. 4.E31-4.E47) with every "
                "law the data can test leaves it; what it has no term for: the rig's own moment (a wheel-centre "
                "offset turning Fy into a moment, Mz = e x Fy), transient sweeps (the moment lags the slip by its "
                "relaxation length), combined slip (Fx's lever arm s x Fx, Eq. 4.E76) or a trail curve no "
                "cosine form follows"),
         "fx": ("PAC89's longitudinal part has one curvature for drive and braking, no vertical shift and no "
                "camber or pressure terms; Magic Formula 6.1 has them (Pacejka 2012, Eq. 4.E9-4.E18): fit "
                "`tyrefit fit ... --model mf61`")}


def diagnose_channel(cd: ChannelData, settings: ChannelSettings | None = None, seed: int = 0) -> ChannelDiagnosis:
    """Forward selection of ``cd.channel``'s catalogue effects on held-out sweeps (see the module docstring)."""
    t0 = time.perf_counter()
    s = settings or ChannelSettings()
    ch = cd.channel
    summary = cd.sweeps.summary
    fixed = {}
    if len(summary.fz_levels) < 2:
        fixed[START[ch][3]] = 0.0  # c5 / b5: the stiffness's load law needs two loads
    floor, _ = noise_floor(cd.slip, cd.y, cd.sweep, spacing_deg=_FLOOR_SPACING[ch] / _DEG, fz=cd.inputs.fz)
    rho_of = LagOneNoise(cd.slip, cd.sweep, seed=seed, upper=s.rho_upper)
    folds = _folds(cd, s, seed)
    cd.interior = _interior(cd, folds)
    catalogue = CHANNEL_EFFECTS[ch]
    testable = {eid: e.why_not_testable(summary) for eid, e in catalogue.items()}
    for eid, e in catalogue.items():
        if testable[eid] is None and any(p.name in fixed for p in e.params):
            testable[eid] = "needs >= 2 load levels"
    with single_threaded_blas():
        cur = _evaluate(cd, [], fixed, _start_values(cd), folds, None, multistart=True)
        steps = [cur]
        accepted: list[str] = []
        evidence: dict[str, dict] = {}
        # the noise's correlation along the sweeps, read from the residuals of the richest model the data can
        # test (every testable effect at once): a missing effect must not pass for correlated noise, nor
        # correlated noise for a missing effect
        rich = [e for eid, e in catalogue.items() if testable[eid] is None]
        rich = [e for e in rich if not any(_contained(e, f) and e is not f for f in rich)]
        try:
            m_rich = _Model(cd, rich, fixed)
            rho = rho_of(m_rich.residual(m_rich.fit(np.arange(len(cd.y)), cur.values)))
        except Exception:  # noqa: BLE001 - the richest model may not fit; the start model's residuals then
            m_rich, rho = None, rho_of(cur.resid)
        # the same residuals give the noise model the held-out gain's null is drawn from
        rng = np.random.default_rng(seed)
        point_fold = np.empty(len(cd.y), dtype=int)
        for k, held in enumerate(folds):
            point_fold[np.isin(cd.sweep, held)] = k
        try:
            rich_vals = m_rich.fit(np.arange(len(cd.y)), cur.values) if m_rich is not None else cur.values
            J_rich = _jacobian(cd, rich if m_rich is not None else [], fixed, rich_vals,
                               m_rich.names if m_rich is not None else _Model(cd, [], fixed).names)
            r_rich = m_rich.residual(rich_vals) if m_rich is not None else cur.resid
            layout, noise = _noise_model(cd, r_rich, J_rich, rng)
        except Exception:  # noqa: BLE001 - without a noise model the F test and the sweep test decide
            layout = noise = None
        if noise is not None:
            # the richest model follows part of slow noise, so its residuals' correlation reads low; the
            # bias-corrected noise model's correlation is the better one when it is the larger
            rho = max(rho, float(np.ravel(noise.rho)[0]))
        for rnd in range(1, s.max_rounds + 1):
            have = set(cur.effects)
            fams = {catalogue[e].family for e in have}
            best = None
            round_steps = {}
            for eid, e in catalogue.items():
                if eid in have or testable[eid] is not None:
                    continue
                if e.refinement and e.family not in fams:
                    evidence.setdefault(eid, {"status": "not tested",
                                              "reason": f"refines {e.family}, which was not accepted"})
                    continue
                if not e.refinement and e.family in fams:
                    continue
                effs = [catalogue[k] for k in cur.effects if not _contained(catalogue[k], e)] + [e]
                try:
                    st = _evaluate(cd, effs, fixed, cur.values, folds, eid)
                except Exception as exc:  # noqa: BLE001 - a candidate whose fit fails is not evidence
                    evidence[eid] = {"status": "fit failed", "reason": str(exc)[:200]}
                    continue
                round_steps[eid] = st
            level = s.alpha / (3.0 * max(len(round_steps), 1))
            null = None
            if noise is not None and round_steps:
                cur_names = _Model(cd, [catalogue[k] for k in cur.effects], fixed).names
                null = HeldoutNull(_jacobian(cd, [catalogue[k] for k in cur.effects], fixed, cur.values,
                                             cur_names), noise, layout, point_fold, rng, s.n_null)
            for eid, st in round_steps.items():
                p_n = float("nan")
                if null is not None:
                    effs = [catalogue[k] for k in st.effects]
                    new_names = [k for k in _Model(cd, effs, fixed).names if k not in cur_names]
                    if new_names:
                        J_new = _jacobian(cd, effs, fixed, cur.values, new_names)
                        m = cd.interior if cd.interior.any() else np.isfinite(cur.resid_heldout)
                        gain = float(np.nansum(cur.resid_heldout[m] ** 2) - np.nansum(st.resid_heldout[m] ** 2))
                        draws = null.gain(J_new, m)
                        p_n = float((1.0 + np.count_nonzero(draws >= gain)) / (len(draws) + 1.0))
                ev = _evidence(cur, st, cd, floor, rho, s, level, p_noise=p_n)
                factor = _CONTRAST_FACTOR.get(catalogue[eid].family)
                if ev["status"] == "passed" and factor and catalogue[eid].family not in fams:
                    # as on Fy: camber and pressure are named only where the residual differs between their
                    # levels consistently from load to load (a misfit common to every sweep is not theirs);
                    # a refinement of a family already named needs only the held-out evidence
                    why = _camber_evidence(cd.sweeps, cur.resid, CAMBER_ALPHA, factor=factor)
                    if why is not None:
                        ev.update(status="rejected", reason=why)
                ev["round"] = rnd
                evidence[eid] = ev
                if ev["status"] == "passed" and (best is None or ev["delta_heldout"] > best[1]["delta_heldout"]):
                    best = (st, ev)
            if best is None:
                break
            st, ev = best
            ev["status"] = "accepted"
            accepted.append(st.added)
            cur = st
            steps.append(cur)
            for k, v in evidence.items():  # candidates of this round that lost are re-tested next round
                if v.get("status") == "passed":
                    v["status"] = "passed, not the best"
            if not catalogue[st.added].refinement:
                # a family accepted earlier that the new one makes redundant is dropped (a camber moment in a
                # record half of whose sweeps are cambered first passes for a residual torque)
                cur, gone = _backward(cd, cur, catalogue, fixed, folds, floor, rho, s)
                if gone is not None:
                    steps.append(cur)
                    for eid in [a for a in accepted if catalogue[a].family == gone[0]]:
                        evidence[eid] = {**evidence.get(eid, {}), "status": "dropped", "round": rnd,
                                         "reason": f"redundant once {st.added} was accepted: {gone[1]}"}
                    accepted = [a for a in accepted if catalogue[a].family != gone[0]]
    for eid, why in testable.items():
        if why is not None:
            evidence[eid] = {"status": "not testable", "reason": why}
    unit = cd.unit
    ratio = cur.rmse_heldout / floor if floor > 0 else float("nan")
    share = systematic_share(cd, cur.resid)
    verdict, text = _verdict(ratio, floor, unit, share, rho)
    if verdict == "structure":
        text += ". The model form is the likely limit: " + _FORM[ch]
    unexplained = {"structure_found": verdict == "structure", "verdict": verdict, "summary": text,
                   "ratio_to_floor": float(ratio), "systematic_share": share,
                   "noise_lag_one_correlation": rho}
    cands = [{"effect": eid, "family": catalogue[eid].family, **_clean(evidence.get(eid, {"status": "not tested"}))}
             for eid in catalogue]
    return ChannelDiagnosis(ch, cd, [], accepted, steps, cands, float(floor), unexplained,
                            _pac89_export(cd, cur, fixed), seconds=time.perf_counter() - t0)


def _backward(cd: ChannelData, cur: ChannelStep, catalogue: dict, fixed: dict, folds, floor: float, rho: float,
              s: ChannelSettings) -> tuple[ChannelStep, tuple[str, str] | None]:
    """The current model without the one earlier family it no longer needs, if any (backward elimination).

    Every family of ``cur`` but the last one added is taken out in turn (with its refinements) and the
    model refitted; a family whose return no longer gains in practice (held-out RMSE lower by less than
    ``margin`` x the noise floor and 1 %, or lower in fewer than ``min_sweeps_improved`` of the held-out
    sweeps: the first two rules of :func:`_evidence`) is redundant.  Significance is not asked again: a
    family that still carries a practical part of the held-out error stays.  Returns (the model without
    the family that gains least, (family, why)) when one is redundant, else (``cur``, None).
    """
    last = catalogue[cur.added].family
    others = sorted({catalogue[e].family for e in cur.effects} - {last})
    worst = None
    for fam in others:
        without = [catalogue[e] for e in cur.effects if catalogue[e].family != fam]
        try:
            base = _evaluate(cd, without, fixed, cur.values, folds, "-" + fam)
        except Exception:  # noqa: BLE001 - a model that cannot be fitted without the family keeps it
            continue
        ev = _evidence(base, cur, cd, floor, rho, s, s.alpha)
        need = max(s.margin * floor, 0.01 * base.rmse_heldout)
        if ((ev["delta_heldout"] < need or ev["sweeps_improved"] < s.min_sweeps_improved)
                and (worst is None or ev["delta_heldout"] < worst[2]["delta_heldout"])):
            worst = (fam, base, ev)
    if worst is None:
        return cur, None
    ev = worst[2]
    return worst[1], (worst[0], f"without it the held-out RMSE changes by {-ev['delta_heldout']:+.3g} {cd.unit}, "
                                f"better on {100 * ev['sweeps_improved']:.0f} % of the held-out sweeps")


#: families whose name needs the contrast between their condition's levels (:func:`.contrast.camber_evidence`)
_CONTRAST_FACTOR = {"mz_camber": "camber", "fx_camber": "camber", "mz_pressure": "pressure",
                    "fx_pressure": "pressure"}


def _contained(old: Effect, new: Effect) -> bool:
    """A same-family variant whose parameters ``new`` contains is replaced by it."""
    return old.family == new.family and set(old.param_names) <= set(new.param_names)


def sweep_p(d: np.ndarray) -> float:
    """One-sided p-value that the per-sweep held-out error falls (paired t test over >= 3 sweeps, else 1).

    Whole sweeps are held out, so the per-sweep differences are independent whatever the noise does
    along a sweep: this test stays valid when the residuals carry a misfit the model form cannot follow
    (which inflates the correlation the F test corrects for).
    """
    d = np.asarray(d, float)
    if len(d) < 3:
        return 1.0
    sd = float(np.std(d, ddof=1))
    if sd == 0.0:
        return 0.0 if np.mean(d) > 0 else 1.0
    t = float(np.mean(d)) / (sd / np.sqrt(len(d)))
    return float(stats.t.sf(t, len(d) - 1))


def _evidence(cur: ChannelStep, st: ChannelStep, cd: ChannelData, floor: float, rho: float,
              s: ChannelSettings, level: float, p_noise: float = float("nan")) -> dict:
    """Whether ``st`` (the current model plus one effect) passes the acceptance rules of the module docstring.

    Three tests, each at ``level`` (alpha / (3 m) for m candidates in the round: any one passing keeps the
    round's family-wise level at alpha): the nested F test corrected for the noise's correlation along
    the sweeps, the paired test over held-out sweeps, and ``p_noise``, the held-out gain against its null
    under the noise model estimated from the residuals (AR(1) along the sweeps plus sweep offsets,
    :class:`~tyrefit.diagnose.stats.HeldoutNull`, as in the lateral diagnosis; NaN when there is none).
    """
    delta = cur.rmse_heldout - st.rmse_heldout
    need = max(s.margin * floor, 0.01 * cur.rmse_heldout)
    a, b = _per_sweep_sse(cur.resid_heldout, cd.sweep), _per_sweep_sse(st.resid_heldout, cd.sweep)
    held = a > 0
    inner = np.zeros_like(held)
    inner[np.unique(cd.sweep[cd.interior])] = True
    if (held & inner).any():
        held &= inner
    share = float(np.mean(b[held] < a[held])) if held.any() else 0.0
    q = max(st.n_params - cur.n_params, 1)
    p_f = nested_p(cur.resid, st.resid, q, st.n_params, rho)
    p_s = sweep_p(a[held] - b[held])
    p = min(p_f, p_s, p_noise) if np.isfinite(p_noise) else min(p_f, p_s)
    why = []
    if not delta >= need:
        why.append(f"held-out gain {delta:.3g} below the margin {need:.3g} {cd.unit}")
    if not share >= s.min_sweeps_improved:
        why.append(f"better on {100 * share:.0f} % of the held-out sweeps (needs {100 * s.min_sweeps_improved:.0f} %)")
    if not p < level:
        why.append(f"neither the F test (p = {p_f:.3g}, noise correlation {rho:.2f}), the held-out sweeps "
                   f"(p = {p_s:.3g}) nor the noise model's held-out null (p = {p_noise:.3g}) below {level:.3g}")
    return {"status": "passed" if not why else "rejected", "delta_heldout": float(delta),
            "rmse_heldout": float(st.rmse_heldout), "sweeps_improved": share, "p_value": p,
            "p_f": p_f, "p_sweeps": p_s, "p_noise": p_noise, "reason": "; ".join(why)}


def _clean(ev: dict) -> dict:
    return {k: (float(v) if isinstance(v, (np.floating,)) else v) for k, v in ev.items()}


def _pac89_aligning(cd: ChannelData, final: ChannelStep) -> dict:
    """PAC89's aligning part fitted to the Mz sweeps with every coefficient the data can identify.

    Its RMSE beside the trail model's says what a PAC89 ``.tir`` loses on this record (Bakker, Nyborg &
    Pacejka 1989: one sine curve for the whole moment, camber as shifts and a stiffness factor).
    PAC89 units: Fz kN, slip angle and camber in deg, Mz_pac = -Mz (ISO-W).
    """
    s = cd.sweeps.summary
    names = ["c0", "c2", "c4", "c9", "c13", "c17"]
    if len(s.fz_levels) >= 2:
        names += ["c1", "c5", "c8", "c12", "c16"]
    if len(s.fz_levels) >= 3:
        names += ["c3", "c7"]
    if len(s.camber_levels) >= 2:
        names += ["c6", "c10", "c11", "c15"] + (["c14"] if len(s.fz_levels) >= 2 else [])
    x = cd.inputs
    d, k = _peak_and_slope(x.slip_angle / _DEG, -cd.y, x.fz * 1e-3, cd.sweep, cd.n_sweeps, small=1.5, default=1.0)
    params = Parameters()
    start = {"c0": 2.3, "c2": d if abs(d) > 1e-6 else 1.0, "c4": k if abs(k) > 1e-6 else d, "c9": -1.0}
    for n in names:
        p = PAC89_COEFFICIENT[n]
        params.add(n, float(np.clip(start.get(n, p.neutral), *p.bounds)), min=p.bounds[0], max=p.bounds[1],
                   scale=p.scale)

    def resid(theta):
        coef = {k: 0.0 for k in pac89.ALIGNING}
        coef.update(params.values_of(theta))
        return pac89.aligning_moment(coef, x.fz, x.slip_angle, x.camber) - cd.y

    base = params.valuesdict()
    starts = [base, {**base, "c0": 1.5, "c9": 0.0}, {**base, "c0": 3.0, "c9": 0.5}, {**base, "c0": 1.2, "c9": -2.0}]
    try:
        sol = solve(resid, params, method="trf", x_scale="params", starts=starts, nonfinite="penalise",
                    stderr=False, what="PAC89 aligning fit", max_nfev=600)
    except (FitError, ValueError, FloatingPointError, np.linalg.LinAlgError) as exc:
        return {"effects": [], "left_out": list(final.effects), "notes": [f"PAC89's aligning part did not fit ({exc})"],
                "coefficients": {}, "rmse": float("nan")}
    coef = {k: float(sol.values.get(k, 0.0)) for k in pac89.ALIGNING}
    r = resid(np.array([sol.values[n] for n in names]))
    return {"effects": [], "left_out": list(final.effects),
            "notes": [f"PAC89's aligning part (one sine curve for the whole moment) fitted with {', '.join(names)}; "
                      f"the trail model's RMSE is {final.rmse:.3g} N*m"],
            "coefficients": coef, "rmse": float(np.sqrt(np.mean(r * r)))}


def _pac89_export(cd: ChannelData, final: ChannelStep, fixed: dict) -> dict:
    """The final model refitted with only what a PAC89 part can hold (its coefficients and RMSE)."""
    if cd.channel == "mz":
        return _pac89_aligning(cd, final)
    cat = CHANNEL_EFFECTS[cd.channel]
    keep = [cat[e] for e in final.effects if cat[e].representable]
    dropped = [e for e in final.effects if not cat[e].representable]
    if dropped:
        st = _Model(cd, keep, fixed)
        values = st.fit(np.arange(len(cd.y)), final.values)
        r = st.residual(values)
    else:
        values, r = final.values, final.resid
    coef = {k: float(values.get(k, fixed.get(k, 0.0))) for k in _part(cd.channel)}
    return {"effects": [e.id for e in keep], "left_out": dropped,
            "notes": [cat[e].pac89_note for e in dropped], "coefficients": coef,
            "rmse": float(np.sqrt(np.mean(r * r)))}


def diagnose_channels(data, rated_load: float | None = None, seed: int = 0,
                      settings: ChannelSettings | None = None) -> tuple[dict[str, ChannelDiagnosis], dict[str, str]]:
    """Diagnose every channel beyond Fy that ``data`` carries; returns (diagnoses, why a channel is absent)."""
    out, absent = {}, {}
    for ch in CHANNELS:
        cd = channel_data(data, ch, rated_load=rated_load)
        if isinstance(cd, str):
            absent[ch] = cd
            continue
        try:
            out[ch] = diagnose_channel(cd, settings, seed=seed)
        except (FitError, DataError, ValueError, FloatingPointError, np.linalg.LinAlgError) as exc:
            # a channel whose start model cannot be fitted is reported, not allowed to sink the others
            absent[ch] = f"its start model could not be fitted ({exc})"
    return out, absent


def effect_sizes(chd: ChannelDiagnosis) -> list[dict]:
    """Each accepted effect in plain words: its size in the channel's unit and the coefficients it sets.

    The size is what the final model changes by when the effect is left out and the rest refitted
    (RMS and largest change over the measured points): the part of the measured behaviour only that
    effect carries.  Computed once per diagnosis (one refit per accepted effect).
    """
    if chd.sizes is not None:
        return chd.sizes
    cd = chd.data
    cat = CHANNEL_EFFECTS[chd.channel]
    final = chd.steps[-1]
    effs = [cat[e] for e in final.effects]
    full = predict(chd.channel, final.values, effs, cd.inputs)
    fixed = {k: 0.0 for k in START[chd.channel] if k not in final.values}
    out = []
    for eid in final.effects:
        e = cat[eid]
        rest = [f for f in effs if f is not e]
        model = _Model(cd, rest, fixed)
        start = {k: v for k, v in final.values.items() if k not in e.param_names}
        try:
            without = predict(chd.channel, model.fit(np.arange(len(cd.y)), start), rest, cd.inputs)
        except Exception:  # noqa: BLE001 - a refit that fails leaves the size unknown, not the report
            without = np.full(len(cd.y), np.nan)
        d = full - without
        out.append({"effect": eid, "title": e.title, "family": e.family,
                    "size_rms": float(np.sqrt(np.mean(d * d))), "size_max": float(np.max(np.abs(d))),
                    "unit": chd.unit, "coefficients": {p.name: float(final.values.get(p.name, p.neutral))
                                                       for p in e.params},
                    "pac89": list(e.pac89), "pac89_note": e.pac89_note, "what": e.card.what,
                    "sources": list(e.card.sources)})
    chd.sizes = out
    return out
