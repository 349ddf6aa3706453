"""Steady-state constant-radius ramp to the limit (ISO 4138 style) with load transfer and aero load.

The vehicle drives a circle of radius R at speeds rising slowly enough that
every point is a steady state: lateral acceleration a_y = v^2 / R, yaw rate
r = v / R.  At each a_y the four wheel loads follow
:func:`~tyrefit.sim.loads.wheel_loads` (lateral transfer, downforce at v, the
small longitudinal transfer of the drive force that holds the speed against
drag and rolling resistance), and the bicycle model's steady equations give
the axle lateral forces (lateral balance and yaw moment, Pham et al. 2025, Eq. 2-3 with
d/dt = 0)::

    F_y,f cos(steer) + F_x,f sin(steer) = m a_y l_r / L,     F_y,r = m a_y l_f / L

Each axle's slip angle is the one at which its two tyres (left, and the
mirrored right, each at its own load) give that force, on the stable branch
(bisection below the axle's peak).  The kinematics (Eq. 6-7) then give the
body slip angle and the steering angle::

    tan(alpha_r) = (v_y - l_r r) / v_x,     steer = atan((v_y + l_f r) / v_x) - alpha_f

The lateral limit is the largest a_y at which both axles can give their
force with every wheel on the ground (which axle ran out, or "wheel lift",
is reported).  The understeer gradient is d(steer)/d(a_y / g) [deg/g] at low
lateral acceleration (the slope over 0.005-0.05 g); :func:`closed_form_understeer_gradient`
is the linear bicycle model's (m / L)(l_r / C_f - l_f / C_r) from the tyres'
cornering stiffness at the static loads, its check.  The tyres are in pure
lateral slip (the drive force is a small fraction of the grip: it moves load,
not the tyre curves).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import DataError
from ..nomenclature import G0
from .loads import wheel_loads

__all__ = ["RampResult", "run_ramp", "axle_lateral_force", "closed_form_understeer_gradient",
           "axle_cornering_stiffness"]

_ALPHA_MAX = math.radians(30.0)


def axle_lateral_force(tyre, fz_left, fz_right, slip_angle):
    """Lateral force [N] of an axle: the left tyre and its mirror image on the right, each at its load.

    Lifted wheels (load <= 0) give no force.  ISO-W: a negative slip angle gives a positive force.
    """
    fl = np.maximum(fz_left, 0.0)
    fr = np.maximum(fz_right, 0.0)
    yl = np.where(fl > 0, tyre.fy(np.maximum(fl, 1.0), slip_angle), 0.0)
    yr = np.where(fr > 0, tyre.mirrored().fy(np.maximum(fr, 1.0), slip_angle), 0.0)
    return yl + yr


def axle_cornering_stiffness(tyre, fz_left, fz_right, h: float = 1e-4) -> float:
    """-dF_y/d(alpha) at zero slip angle [N/rad] of an axle (central difference, left + mirrored right)."""
    return float(-(axle_lateral_force(tyre, fz_left, fz_right, h)
                   - axle_lateral_force(tyre, fz_left, fz_right, -h)) / (2 * h))


def closed_form_understeer_gradient(spec, front, rear) -> dict:
    """Linear bicycle model: K = (m / L)(l_r / C_f - l_f / C_r) [rad/(m/s^2)], in deg/g, at the static loads."""
    w = wheel_loads(spec)
    cf = axle_cornering_stiffness(front, w["fl"], w["fr"])
    cr = axle_cornering_stiffness(rear, w["rl"], w["rr"])
    k = spec.mass / spec.wheelbase * (spec.lr / cf - spec.lf / cr)
    return {"cornering_stiffness_front_N_per_rad": cf, "cornering_stiffness_rear_N_per_rad": cr,
            "understeer_gradient_deg_per_g": math.degrees(k * G0)}


def _solve_axle(tyre, fz_left, fz_right, target, n_grid: int = 161, n_bisect: int = 44):
    """Slip angle [rad] (<= 0) at which the axle gives ``target`` >= 0 [N]; NaN beyond its peak.

    Vectorised over the members of ``target``: a grid search for the peak on
    [-30 deg, 0], then bisection on the stable branch between 0 and the peak.
    """
    target = np.asarray(target, float)
    a = -_ALPHA_MAX * (np.linspace(0.0, 1.0, n_grid) ** 2)            # dense near zero
    f = axle_lateral_force(tyre, fz_left[None, :], fz_right[None, :], a[:, None])
    i = np.argmax(f, axis=0)
    cols = np.arange(target.size)
    peak, a_peak = f[i, cols], a[i]
    ok = target <= peak
    lo = np.where(ok, a_peak, 0.0)    # force >= target here
    hi = np.zeros_like(target)        # force 0 <= target here
    for _ in range(n_bisect):
        mid = 0.5 * (lo + hi)
        fm = axle_lateral_force(tyre, fz_left, fz_right, mid)
        above = fm >= target
        lo = np.where(above, mid, lo)
        hi = np.where(above, hi, mid)
    out = 0.5 * (lo + hi)
    return np.where(ok, out, np.nan), peak


def _states(spec, front, rear, ay, radius, iterations: int = 4):
    """Steady states at lateral accelerations ``ay`` [m/s^2] (arrays); NaN where beyond the limit."""
    ay = np.asarray(ay, float)
    m, L, lf, lr = spec.mass, spec.wheelbase, spec.lf, spec.lr
    v = np.sqrt(ay * radius)
    r = v / radius
    resist = spec.drag_coefficient * v**2 + spec.rolling_resistance * (m * G0 + spec.downforce_coefficient * v**2)
    ax_tyres = resist / m                  # the drive force holding the speed, as acceleration of the body
    loads = wheel_loads(spec, ax=ax_tyres, ay=ay, speed=v)
    share_f = _drive_share(spec)
    fx_f = share_f * resist - spec.rolling_resistance * (np.maximum(loads["fl"], 0) + np.maximum(loads["fr"], 0))
    steer = np.full_like(ay, L / radius)
    beta = np.zeros_like(ay)
    for _ in range(iterations):
        ay_body = ay * np.cos(beta)
        fy_r = m * ay_body * lf / L
        fy_f = (m * ay_body * lr / L - fx_f * np.sin(steer)) / np.cos(steer)
        a_f, peak_f = _solve_axle(front, loads["fl"], loads["fr"], fy_f)
        a_r, peak_r = _solve_axle(rear, loads["rl"], loads["rr"], fy_r)
        vx = v * np.cos(beta)
        vy = vx * np.tan(a_r) + lr * r
        beta = np.arctan2(vy, np.maximum(vx, 1e-9))
        steer = np.arctan2(vy + lf * r, np.maximum(v * np.cos(beta), 1e-9)) - a_f
    lifted = np.minimum.reduce([loads[k] for k in loads]) <= 0.0
    reason = np.where(lifted, "wheel lift", np.where(np.isnan(a_f), "front", np.where(np.isnan(a_r), "rear", "")))
    return {"ay": ay, "speed": v, "yaw_rate": r, "steer": steer, "beta": beta, "slip_angle_f": a_f,
            "slip_angle_r": a_r, "fy_f": fy_f, "fy_r": fy_r, "peak_f": peak_f, "peak_r": peak_r,
            "drive_force": resist, "reason": reason, **{f"fz_{k}": loads[k] for k in loads}}


def _drive_share(spec) -> float:
    f, r = spec.front, spec.rear
    if f.drive and r.drive:
        return spec.front_weight_share
    return 1.0 if f.drive else 0.0


@dataclass
class RampResult:
    """A constant-radius ramp: steady states up to the limit, the gradient, the limit and its checks."""

    radius: float
    states: dict                       # name -> array over the ramp (ay ascending)
    lateral_limit_g: float
    limit_reason: str
    understeer_gradient_deg_per_g: float
    closed_form: dict
    vehicle: dict
    notes: list[str] = field(default_factory=list)

    def to_json(self) -> dict:
        s = self.states
        every = max(1, s["ay"].size // 60)
        table = [{"ay_g": float(s["ay"][i] / G0), "speed_kmh": float(3.6 * s["speed"][i]),
                  "steer_deg": float(math.degrees(s["steer"][i])), "beta_deg": float(math.degrees(s["beta"][i])),
                  "slip_angle_front_deg": float(math.degrees(s["slip_angle_f"][i])),
                  "slip_angle_rear_deg": float(math.degrees(s["slip_angle_r"][i])),
                  **{f"fz_{k}_N": float(s[f"fz_{k}"][i]) for k in ("fl", "fr", "rl", "rr")}}
                 for i in range(0, s["ay"].size, every)]
        return {"radius_m": self.radius, "understeer_gradient_deg_per_g": self.understeer_gradient_deg_per_g,
                "lateral_limit_g": self.lateral_limit_g, "limit": self.limit_reason,
                "closed_form": self.closed_form, "ramp": table, "notes": self.notes}


def run_ramp(spec, front, rear, radius: float | None = None, n_points: int = 400) -> RampResult:
    """Steady-state constant-radius ramp to the limit (left turn).

    Parameters
    ----------
    spec : VehicleSpec
    front, rear : Tyre
        The tyres of each axle (left; the right one is mirrored).
    radius : float, optional
        Circle radius [m]; the vehicle's ``ramp_radius`` by default.
    n_points : int
        Steady states between 0 and the limit (equally spaced in a_y: a ramp at a constant rate).
    """
    radius = float(spec.ramp_radius if radius is None else radius)
    if not (radius > 2 * spec.wheelbase):
        raise DataError(f"ramp radius {radius:g} m is too tight for a {spec.wheelbase:g} m wheelbase; accepted more "
                        f"than {2 * spec.wheelbase:g} m")
    # bracket the limit on a coarse grid, then bisect
    grid = np.linspace(0.01, 4.0, 200) * G0
    ok = _states(spec, front, rear, grid, radius)["reason"] == ""
    if not ok[0]:
        raise DataError(f"the vehicle cannot corner at 0.01 g on a {radius:g} m circle with these tyres")
    k = int(np.argmin(ok)) if not ok.all() else grid.size - 1
    lo, hi = grid[k - 1], grid[k]
    for _ in range(24):
        mid = 0.5 * (lo + hi)
        if _states(spec, front, rear, np.array([mid]), radius)["reason"][0] == "":
            lo = mid
        else:
            hi = mid
    reason = str(_states(spec, front, rear, np.array([hi]), radius)["reason"][0]) or "ay above 4 g"
    limit = lo
    ay = np.linspace(0.0, limit, n_points + 1)[1:]
    st = _states(spec, front, rear, ay, radius)
    low = np.linspace(0.005, 0.05, 10) * G0
    sl = _states(spec, front, rear, low, radius)
    slope = np.polyfit(low / G0, sl["steer"], 1)[0]
    cf = closed_form_understeer_gradient(spec, front, rear)
    grad = math.degrees(slope)
    cf["relative_difference_pct"] = 100.0 * (grad / cf["understeer_gradient_deg_per_g"] - 1.0) \
        if cf["understeer_gradient_deg_per_g"] != 0 else None
    names = {"front": "front axle saturates (limit understeer)", "rear": "rear axle saturates (limit oversteer)",
             "wheel lift": "an inner wheel lifts (roll-over limit) before the tyres saturate"}
    return RampResult(radius=radius, states=st, lateral_limit_g=float(limit / G0),
                      limit_reason=names.get(reason, reason), understeer_gradient_deg_per_g=float(grad),
                      closed_form=cf, vehicle=spec.to_dict(),
                      notes=["steady states (quasi-static load transfer, aero load at each speed), left turn",
                             "understeer gradient: slope of steering angle over a_y/g between 0.005 and 0.05 g"])
