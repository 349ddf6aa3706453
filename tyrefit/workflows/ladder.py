"""Diagnosis on the model ladder: what the Magic Formula tyre of ``tyrefit fit --model mf61`` still misses.

``tyrefit diagnose DATA... --base mf61`` starts where the PAC89 diagnosis ends: from the Magic
Formula 6.1 (or 5.2) tyre the fit writes (:func:`tyrefit.workflows.fit.fit_mf_records`, the same
code and options as ``tyrefit fit --model mf61``), it says for every channel the records carry
(Fy and Mz of the cornering sweeps, Fx of the drive/brake sweeps at zero slip angle):

1. **what the tyre misses that MF 6.1 could carry**: the coefficients the fit held at their
   neutral values because the data could not identify them, with the fit's reason (a camber term
   with one camber level, a pressure term with one pressure...), grouped by channel;
2. **what is left** after the tyre: its RMSE against the within-sweep noise floor and whether the
   residual's slip pattern repeats from sweep to sweep
   (:func:`~tyrefit.diagnose.channels.systematic_share`) - a misfit - or not (noise);
3. **effects MF 6.1 cannot carry** (:data:`BEYOND`), each tested on held-out sweeps as a
   correction of the tyre's force with its friction law re-adjusted to first order (the fit
   compromised that law to follow what it cannot carry; the rest of the tyre is held): a grip loss above the rated load
   (Komana et al. Sec. 4.2: the patch caves in, friction falls faster than the smooth trend),
   and a friction law curved in load (MF 6.1's mu is linear in dfz, Pacejka 2012 Eq. 4.E13 and
   4.E23).  A correction is accepted on the same rules as a channel effect (practical margin,
   half the held-out sweeps improved, and the nested F test corrected for the noise's correlation
   along the sweeps - as the larger model leaves it - or the paired test over held-out sweeps at
   alpha / (2 m)).

The waterfall of each channel starts at the exported MF tyre and continues through the accepted
corrections; the corrections are not in the ``.tir`` (MF 6.1 has no term for them), and the
report says so.  The MF tyre is not refitted per fold (a Magic Formula fit takes tens of
seconds): its "held-out" error is its error on all sweeps, and only the corrections are held out.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..diagnose.channels import (_DEG, _FLOOR_SPACING, SYSTEMATIC, ChannelData, _verdict, channel_data, nested_p,
                                 sweep_p, systematic_share)
from ..diagnose.data import combine_records
from ..diagnose.ladder_report import write_report
from ..diagnose.result import json_text
from ..errors import DataError, option, render
from ..fitting.noise import LagOneNoise, noise_floor
from .fit import fit_mf_records

__all__ = ["BEYOND", "LadderChannel", "LadderDiagnosis", "diagnose_mf"]

#: corrections beyond MF 6.1: id -> (channel, title, needs, physics)
BEYOND = {
    "overload": ("fy", "grip falling faster above the rated load",
                 "the rated load and load levels on both sides of it",
                 "Above its rated load the contact patch caves in and the friction coefficient falls faster "
                 "than the smooth trend below the rating (Komana et al., Sec. 4.2). MF 6.1's friction is "
                 "linear in the load increment (PDY2, Pacejka 2012 Eq. 4.E23), so it cannot bend there."),
    "load_friction_curved": ("fy", "lateral friction law curved in load", ">= 3 load levels",
                             "Rubber friction falls with contact pressure sub-linearly; over a wide load range the "
                             "friction law bends. MF 6.1's mu_y = PDY1 + PDY2 dfz (Pacejka 2012 Eq. 4.E23) is a "
                             "straight line in load."),
    "fx_load_friction_curved": ("fx", "longitudinal friction law curved in load", ">= 3 load levels",
                                "The same for braking and traction: MF 6.1's mu_x = PDX1 + PDX2 dfz "
                                "(Pacejka 2012 Eq. 4.E13) is a straight line in load."),
}

_CHANNEL_OF = {"X": "fx", "Y": "fy", "Z": "mz"}


@dataclass
class LadderChannel:
    """One channel against the MF tyre: its errors, the corrections tested and the verdict on what is left."""

    channel: str
    data: ChannelData
    resid: np.ndarray = field(repr=False)
    noise_floor: float
    steps: list[dict]
    candidates: list[dict]
    accepted: list[str]
    unexplained: dict

    def to_dict(self) -> dict:
        sd = self.data.sweeps
        return {"unit": self.data.unit, "accepted": list(self.accepted), "noise_floor": float(self.noise_floor),
                "steps": [dict(s) for s in self.steps], "candidates": [dict(c) for c in self.candidates],
                "unexplained": dict(self.unexplained), "data": {"points": int(sd.n), "sweeps": int(sd.n_sweeps)}}


@dataclass
class LadderDiagnosis:
    """What the Magic Formula tyre of ``fit --model mf61`` misses: held terms, corrections, what is left."""

    model: str
    fit: object  # the FitResultMF (its .tyre is the exported tyre)
    channels: dict[str, LadderChannel]
    channels_absent: dict[str, str]
    held: dict[str, dict[str, str]]
    seconds: float = float("nan")

    def to_dict(self) -> dict:
        """JSON of ``diagnose --base mf61``: the contract keys for Fy, plus every channel."""
        fy = self.channels.get("fy")
        return {
            "base": self.model,
            "start": [self.model],
            "accepted": list(fy.accepted) if fy else [],
            "noise_floor": float(fy.noise_floor) if fy else None,
            "steps": [dict(s) for s in fy.steps] if fy else [],
            "candidates": [dict(c) for c in fy.candidates] if fy else [],
            "unexplained": dict(fy.unexplained) if fy else {},
            "held_neutral": {k: dict(v) for k, v in self.held.items()},
            "channels": {k: v.to_dict() for k, v in self.channels.items()},
            "channels_not_diagnosed": dict(self.channels_absent),
            "fit": {"rmse": float(getattr(self.fit, "rmse", float("nan"))), "model": self.model},
            "seconds": float(self.seconds),
        }

    def summary(self) -> str:
        out = [render(f"base: the {self.model.upper()} tyre of a fit with {option('model', self.model)}")]
        for ch, c in self.channels.items():
            u = c.data.unit
            out.append(f"{ch}: RMSE {c.steps[0]['rmse']:.3g} {u} (noise floor {c.noise_floor:.3g} {u})"
                       + "".join(f" -> + {s['added']} {s['rmse']:.3g} {u} (held-out {s['rmse_heldout']:.3g})"
                                 for s in c.steps[1:]))
            held = self.held.get(ch, {})
            if held:
                out.append(f"  held at neutral (the data cannot identify them): {', '.join(sorted(held))}")
            out.append("  " + c.unexplained.get("summary", ""))
        for ch, why in self.channels_absent.items():
            out.append(f"{ch}: not diagnosed ({why})")
        return "\n".join(out)

    def to_json(self, path=None, force: bool = False) -> str:
        """The ladder diagnosis as JSON text; also written atomically to ``path`` when given."""
        return json_text(self.to_dict(), path, force)

    def report(self, directory: str | os.PathLike, force: bool = False) -> Path:
        return write_report(self, directory, force=force)


def _held_by_channel(fit) -> dict[str, dict[str, str]]:
    """The fit's held coefficients (name -> reason) by the channel they belong to (MF 6.1 key names)."""
    out: dict[str, dict[str, str]] = {}
    for k, why in (getattr(fit, "not_identifiable", {}) or {}).items():
        if k.startswith(("QSX", "PPMX")):
            ch = "mx"
        elif k.startswith("QSY"):
            ch = "my"
        elif k.startswith("SSZ"):
            ch = "mz"  # the Fx lever arm of combined Mz (4.E76)
        elif k.startswith("R"):
            ch = "combined"
        elif k[:1] in "PQ" and len(k) > 3:
            ch = _CHANNEL_OF.get(k[2:3], "other")
        else:
            ch = "scaling"
        out.setdefault(ch, {})[k] = str(why)
    return out


def _predict(tyre, cd: ChannelData) -> np.ndarray:
    x = cd.inputs
    kw = dict(fz=x.fz, camber=x.camber, pressure=x.pressure, speed=x.speed)
    if cd.channel == "fx":
        f = tyre.forces(slip_ratio=x.slip_angle, slip_angle=0.0, **kw)
    else:
        f = tyre.forces(slip_angle=x.slip_angle, slip_ratio=0.0, **kw)
    return np.asarray(f[cd.channel], float)


def _peak_weighted(cd: ChannelData, pred: np.ndarray) -> np.ndarray:
    """The tyre's force weighted towards its peak, (F / max|F| of the sweep)^2 F: the direction of a change of
    the friction coefficient (it moves the peak and the sliding part, not the small-slip stiffness)."""
    peak = np.zeros_like(pred)
    for g in range(cd.n_sweeps):
        m = cd.sweep == g
        peak[m] = np.abs(pred[m]) / max(float(np.max(np.abs(pred[m]))), 1e-9)
    return pred * peak ** 2


def _loso(r: np.ndarray, X: np.ndarray, sweep: np.ndarray) -> np.ndarray:
    """Residual r + X theta on each sweep, theta fitted to the other sweeps (leave one sweep out)."""
    out = np.empty_like(r)
    for g in np.unique(sweep):
        tr, te = sweep != g, sweep == g
        th = np.linalg.lstsq(X[tr], -r[tr], rcond=None)[0]
        out[te] = r[te] + X[te] @ th
    return out


def _basis(eid: str, cd: ChannelData, pred: np.ndarray, fnomin: float, rated: float | None):
    """The correction's direction at every point (the peak-weighted force times a load term), or why not."""
    fz = cd.inputs.fz
    levels = cd.sweeps.levels["fz"]
    w = _peak_weighted(cd, pred)
    if eid == "overload":
        if not rated:
            return "needs the rated load (rated_load=)"
        if not (np.any(levels > 1.02 * rated) and np.any(levels < 0.98 * rated)):
            return "needs load levels on both sides of the rated load"
        return -np.maximum(fz - rated, 0.0) / rated * w
    if len(levels) < 3:
        return f"needs >= 3 load levels (have {len(levels)})"
    dfz = (fz - fnomin) / fnomin
    return dfz * dfz * w


def _ladder_channel(cd: ChannelData, tyre, fnomin: float, rated, alpha: float, margin: float,
                    seed: int = 0) -> LadderChannel:
    pred = _predict(tyre, cd)
    r = pred - cd.y
    ok = np.isfinite(r)
    if not ok.all():
        raise DataError(f"the MF tyre gives no {cd.channel} at {int((~ok).sum())} points (a part it does not model)")
    floor, _ = noise_floor(cd.slip, cd.y, cd.sweep, spacing_deg=_FLOOR_SPACING[cd.channel] / _DEG, fz=cd.inputs.fz)
    rmse = float(np.sqrt(np.mean(r * r)))
    steps = [{"effects": [], "added": None, "rmse": rmse, "rmse_heldout": rmse,
              "note": "the MF tyre as exported (not refitted per fold)"}]
    cands, accepted = [], []
    ids = [e for e, v in BEYOND.items() if v[0] == cd.channel]
    bases = {e: _basis(e, cd, pred, fnomin, rated) for e in ids}
    testable = {e: b for e, b in bases.items() if not isinstance(b, str)}
    level = alpha / (2.0 * max(len(testable), 1))
    # the MF friction law re-adjusted with each correction (a first-order refit of PDY1/PDY2 or PDX1/PDX2:
    # the tyre compromised its friction law to fit what it cannot carry, so a correction judged with the
    # law held would be judged against that compromise)
    w = _peak_weighted(cd, pred)
    dfz = (cd.inputs.fz - fnomin) / fnomin
    law = np.column_stack([w, dfz * w])
    rho_of = LagOneNoise(cd.slip, cd.sweep, seed=seed, upper=0.9)
    cur = r.copy()
    for eid in ids:
        b = bases[eid]
        if isinstance(b, str):
            cands.append({"effect": eid, "status": "not testable", "reason": b})
            continue
        X0 = np.column_stack([law] + [bases[a] for a in accepted])
        X1 = np.column_stack([X0, b])
        r0, r1 = _loso(r, X0, cd.sweep), _loso(r, X1, cd.sweep)
        G = cd.n_sweeps
        a = np.bincount(cd.sweep, weights=r0 ** 2, minlength=G)
        c = np.bincount(cd.sweep, weights=r1 ** 2, minlength=G)
        cur_ho = float(np.sqrt(np.mean(r0 ** 2)))
        new_ho = float(np.sqrt(np.mean(r1 ** 2)))
        delta = cur_ho - new_ho
        share = float(np.mean(c < a))
        coef = np.linalg.lstsq(X1, -r, rcond=None)[0]
        f0 = r + X0 @ np.linalg.lstsq(X0, -r, rcond=None)[0]
        f1 = r + X1 @ coef
        # the noise's correlation as the larger model leaves it (its 90 % upper bound), the F test corrected
        rho = rho_of(f1)
        p_f = nested_p(f0, f1, 1, X1.shape[1], rho)
        p_s = sweep_p(a - c)
        p = min(p_f, p_s)
        need = max(margin * floor, 0.01 * cur_ho)
        why = []
        if not delta >= need:
            why.append(f"held-out gain {delta:.3g} below the margin {need:.3g} {cd.unit}")
        if not share >= 0.5:
            why.append(f"better on {100 * share:.0f} % of the held-out sweeps (needs 50 %)")
        if not p < level:
            why.append(f"neither the F test (p = {p_f:.3g}, noise correlation {rho:.2f}) nor the held-out sweeps "
                       f"(p = {p_s:.3g}) below {level:.3g}")
        status = "accepted" if not why else "rejected"
        cands.append({"effect": eid, "status": status, "delta_heldout": delta, "sweeps_improved": share,
                      "p_value": p, "p_f": p_f, "p_sweeps": p_s, "theta": float(coef[-1]), "reason": "; ".join(why), "title": BEYOND[eid][1],
                      "physics": BEYOND[eid][3]})
        if status == "accepted":
            if not accepted:  # the re-adjusted friction law alone, for the waterfall
                steps.append({"effects": [], "added": "friction law re-adjusted", "rmse": float(np.sqrt(np.mean(f0 ** 2))),
                              "rmse_heldout": cur_ho, "note": "MF's PDY1/PDY2 (PDX1/PDX2) to first order"})
            accepted.append(eid)
            cur = r + X1 @ coef
            steps.append({"effects": list(accepted), "added": eid, "rmse": float(np.sqrt(np.mean(cur ** 2))),
                          "rmse_heldout": new_ho,
                          "note": "beyond MF 6.1 (with the friction law re-adjusted): not in the .tir"})
    rho = rho_of(cur)
    ratio = float(np.sqrt(np.mean(cur ** 2))) / floor if floor > 0 else float("nan")
    share = systematic_share(cd, cur)
    verdict, text = _verdict(ratio, floor, cd.unit, share, rho)
    if verdict == "structure":
        text += (". The tyre's residual repeats from sweep to sweep: a coefficient held neutral above, an "
                 "effect MF 6.1 cannot carry, or a fit stuck short of its minimum")
    return LadderChannel(cd.channel, cd, cur, float(floor), steps, cands, accepted,
                         {"verdict": verdict, "structure_found": verdict == "structure", "summary": text,
                          "ratio_to_floor": ratio, "systematic_share": share, "noise_lag_one_correlation": rho,
                          "systematic_threshold": SYSTEMATIC})


def diagnose_mf(records, *, model: str = "mf61", rated_load: float | None = None, seed: int = 0,
                alpha: float = 0.05, margin: float = 0.03, fit=None) -> LadderDiagnosis:
    """What the Magic Formula tyre of ``tyrefit fit --model MODEL`` still misses (see the module docstring).

    ``records``: Datasets of one tyre (cornering and drive/brake).  ``fit``: a fit result to diagnose
    instead of fitting (the FitResultMF of :func:`tyrefit.workflows.fit.fit_mf_records`).
    """
    t0 = time.perf_counter()
    if model not in ("mf61", "mf52"):
        raise DataError(f"base={model!r}: 'mf61' or 'mf52' (or the PAC89 diagnosis without a base)")
    sets = [r for r in records]
    res = fit if fit is not None else fit_mf_records(sets, model=model, rated_load=rated_load)
    tyre = res.tyre
    ds = combine_records(sets)
    fnomin = float(getattr(tyre, "fnomin", None) or tyre.params.get("FNOMIN", 0.0) or 1.0)
    chans, absent = {}, {}
    for ch in ("fy", "mz", "fx"):
        cd = channel_data(ds, ch, rated_load=rated_load)
        if isinstance(cd, str):
            absent[ch] = cd
            continue
        chans[ch] = _ladder_channel(cd, tyre, fnomin, rated_load, alpha, margin, seed)
    return LadderDiagnosis(model, res, chans, absent, _held_by_channel(res), seconds=time.perf_counter() - t0)
