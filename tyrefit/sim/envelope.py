"""Where the tyres worked: operating points against the envelope each tyre declares.

A tyre file declares the ranges it was fitted over (:meth:`~tyrefit.tyres.base.Tyre.validity`:
``fz`` [N], ``slip_angle`` [rad], ``slip_ratio`` [-]).  A simulation gives each wheel's
load, slip angle and slip ratio at every time step (or steady state); the share of
simulated time in which any wheel of an axle is outside its tyre's ranges is the
``outside_envelope`` of ``sim --json``, and the largest excursion is named in ``worst``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["OperatingPoints", "envelope_summary", "points_from_paper_result", "points_from_ramp",
           "envelope_figure"]

_QUANTITIES = (("fz", "load", "N", 1.0), ("slip_angle", "slip angle", "deg", 180.0 / math.pi),
               ("slip_ratio", "slip ratio", "-", 1.0))


@dataclass
class OperatingPoints:
    """Operating points of one tyre's wheels: arrays of shape (T, W) (time x wheels) and time weights (T,)."""

    fz: np.ndarray
    slip_angle: np.ndarray
    slip_ratio: np.ndarray
    weight: np.ndarray

    @classmethod
    def concat(cls, parts: list["OperatingPoints"]) -> "OperatingPoints":
        w = max(p.fz.shape[1] for p in parts)

        def pad(a):
            return a if a.shape[1] == w else np.concatenate([a] + [a[:, -1:]] * (w - a.shape[1]), axis=1)

        return cls(*(np.concatenate([pad(getattr(p, k)) for p in parts]) for k in ("fz", "slip_angle",
                                                                                   "slip_ratio")),
                   np.concatenate([p.weight for p in parts]))


def _excess(value, lo, hi):
    """How far outside [lo, hi] (0 inside), relative to the range's half width."""
    half = max(0.5 * (hi - lo), 1e-12)
    return np.maximum(lo - value, 0.0) / half + np.maximum(value - hi, 0.0) / half


def envelope_summary(tyre, pts: OperatingPoints, file: str | None = None) -> dict:
    """``{"file", "outside_envelope" (share of time), "worst", "ranges", "used"}`` of one tyre."""
    v = tyre.validity()
    outside = np.zeros(pts.fz.shape[0], bool)
    worst, worst_x = "", 0.0
    used = {}
    for key, label, unit, scale in _QUANTITIES:
        lo, hi = v[key]
        val = getattr(pts, key)
        out = (val < lo) | (val > hi)
        outside |= out.any(axis=1)
        used[key] = [float(np.min(val)), float(np.max(val))]
        x = _excess(val, lo, hi)
        if x.size and float(x.max()) > worst_x:
            worst_x = float(x.max())
            t, w = np.unravel_index(int(np.argmax(x)), x.shape)
            share = float(np.sum(pts.weight[out.any(axis=1)]) / np.sum(pts.weight))
            worst = (f"{label} {val[t, w] * scale:.4g} {unit} outside the declared {lo * scale:.4g} to "
                     f"{hi * scale:.4g} {unit} ({100 * share:.1f} % of the time outside in {label})")
    share = float(np.sum(pts.weight[outside]) / np.sum(pts.weight)) if pts.weight.size else 0.0
    return {"file": file if file is not None else tyre.name, "outside_envelope": share, "worst": worst or None,
            "ranges": {k: list(v[k]) for k, *_ in _QUANTITIES}, "used": used}


def points_from_paper_result(res, role: str, fz: dict) -> OperatingPoints:
    """Operating points of the ``front`` or ``rear`` tyre file in Pham et al.'s scenarios (static loads).

    The front file runs on the low-wear vehicle's front axle; the rear file on the
    base vehicle's both axles and the low-wear vehicle's rear axle.  ``fz`` maps
    ``'front'``/``'rear'`` to the static load per tyre [N].  Left and right wheels
    have the axle's slip angle and slip ratio (bicycle model).
    """
    uses = [(res.low_wear, "f", "front")] if role == "front" else \
        [(res.base, "f", "front"), (res.base, "r", "rear"), (res.low_wear, "r", "rear")]
    parts = []
    for sim, ax, where in uses:
        dt = np.diff(sim.t, append=sim.t[-1] + (sim.t[1] - sim.t[0] if sim.t.size > 1 else 1.0))
        for j in range(sim.n_members):
            e = int(sim.end_index[j]) + 1
            a = sim[f"slip_angle_{ax}"][:e, j]
            k = sim[f"slip_ratio_{ax}"][:e, j]
            parts.append(OperatingPoints(np.full((e, 1), fz[where]), a[:, None], k[:, None], dt[:e]))
    return OperatingPoints.concat(parts)


def points_from_ramp(ramp, role: str) -> OperatingPoints:
    """Operating points of the front or rear axle's two wheels over a steady-state ramp (equal time per step)."""
    s = ramp.states
    ax = "f" if role == "front" else "r"
    fz = np.stack([s[f"fz_{ax}l"], s[f"fz_{ax}r"]], axis=1)
    a = np.repeat(s[f"slip_angle_{ax}"][:, None], 2, axis=1)
    return OperatingPoints(fz, a, np.zeros_like(a), np.ones(fz.shape[0]))


def envelope_figure(tyres: dict, points: dict, title: str = ""):
    """Each tyre's operating points over its declared envelope: load against slip angle and against slip ratio.

    ``tyres`` and ``points`` map ``'front'``/``'rear'`` to the Tyre and its
    :class:`OperatingPoints`.  The declared ranges are the grey boxes; points
    inside are blue, outside red.
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    roles = [r for r in ("front", "rear") if r in tyres]
    fig = Figure(figsize=(12, 4.2 * len(roles)))
    axs = np.atleast_2d(fig.subplots(len(roles), 2))
    for row, role in zip(axs, roles):
        tyre, p = tyres[role], points[role]
        v = tyre.validity()
        n = p.fz.shape[0]
        step = max(1, n // 4000)
        for ax, key, label, scale in ((row[0], "slip_angle", "slip angle [deg]", 180.0 / math.pi),
                                      (row[1], "slip_ratio", "slip ratio [-]", 1.0)):
            lo, hi = v[key]
            flo, fhi = v["fz"]
            ax.add_patch(Rectangle((lo * scale, flo / 1e3), (hi - lo) * scale, (fhi - flo) / 1e3,
                                   facecolor="0.9", edgecolor="0.4", lw=1, label="declared (fitted) envelope"))
            x = getattr(p, key)[::step] * scale
            z = p.fz[::step] / 1e3
            out = ((getattr(p, key)[::step] < lo) | (getattr(p, key)[::step] > hi)
                   | (p.fz[::step] < flo) | (p.fz[::step] > fhi))
            ax.scatter(x[~out], z[~out], s=4, color="tab:blue", label="inside")
            ax.scatter(x[out], z[out], s=6, color="tab:red", label="outside")
            ax.set_xlabel(label)
            ax.set_ylabel("wheel load Fz [kN]")
            ax.set_title(f"{role}: {tyre.name}", fontsize=9)
            ax.legend(fontsize=7, loc="upper right")
            ax.autoscale_view()
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig
