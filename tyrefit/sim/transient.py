"""Time-domain handling scenarios on the user's vehicle: step steer (ISO 7401 style) and braking in a turn
(ISO 7975 style).

Two-track yaw-plane model (states ``vx``, ``vy``, ``r`` in body axes, ISO: x forward, y left,
yaw counter-clockwise; position ``X``, ``Y`` and heading ``psi``), four wheels at
(+l_f, +-t/2) and (-l_r, +-t/2), the front wheels steered by ``steer``::

    m (dvx/dt - r vy) = sum F_x,i - C_d vx^2 - f_r sum F_z,i
    m (dvy/dt + r vx) = sum F_y,i
    I_z dr/dt         = sum (x_i F_y,i - y_i F_x,i)        (F_x,i, F_y,i the tyre forces in body axes)

The wheel loads are :func:`~tyrefit.sim.loads.wheel_loads` at the accelerations the tyre forces
gave the body on the previous step (quasi-static longitudinal and lateral load transfer, no
pitch or roll dynamics) and the downforce at the current speed.  Each wheel's slip angle
follows from its velocity (``alpha = atan(v_y,i / v_x,i) - steer_i``); its slip ratio is held by an
ideal wheel-slip controller (ABS / traction control) that tracks the wheel's share of the
longitudinal force demand and never goes past the peak of the tyre's pure-slip curve at that
load.  The force demand is shared in proportion to the wheel loads (braking: an ideal brake
balance on all four wheels; driving: the driven axles).  A speed controller holds the initial
speed until the manoeuvre (and through the step steer, as a driver holding the speed would).

The left tyre of an axle is the file's tyre; the right one its mirror image.  A tyre without
combined slip (PAC89) is combined by normalised slip (Pacejka, *Tire and Vehicle Dynamics*,
the similarity method): with ``k_n = kappa / kappa_peak`` and ``a_n = alpha / alpha_peak``,
``rho = hypot(k_n, a_n)``, ``F_x = F_x0(rho kappa_peak) |k_n| / rho`` and
``F_y = F_y0(rho alpha_peak) |a_n| / rho``; the JSON notes say so.

Time step 4 ms, Heun's method; the run stops at 1 m/s (the rest of the stop at the last
deceleration).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import DataError
from ..nomenclature import G0
from .envelope import OperatingPoints
from .handling import _states, closed_form_understeer_gradient
from .loads import wheel_loads

__all__ = ["StepSteerResult", "BrakingTurnResult", "run_step_steer", "run_braking_turn", "Trace"]

_DT = 0.004
_KP_SPEED = 2.0          # 1/s: the speed controller's force gain over m
_SLIP_GAIN = 0.6         # share of the slip-ratio correction applied per step
_V_STOP = 1.0            # m/s


def _peak_slips(tyre, fz: float) -> dict:
    """Pure-slip peaks at load ``fz``: brake and drive slip ratio, slip angle (ISO-W: F_y > 0 at alpha < 0)."""
    k = np.concatenate([-np.geomspace(1e-3, 0.6, 200)[::-1], np.geomspace(1e-3, 0.6, 200)])
    fx = tyre.fx(np.full(k.size, fz), k)
    kb = float(k[np.argmin(np.where(k < 0, fx, np.inf))])
    kd = float(k[np.argmax(np.where(k > 0, fx, -np.inf))])
    a = -np.geomspace(1e-3, math.radians(30.0), 300)
    fy = tyre.fy(np.full(a.size, fz), a)
    ap = float(abs(a[int(np.argmax(fy))]))
    h = 1e-4
    ck = float((tyre.fx(fz, h) - tyre.fx(fz, -h)) / (2 * h))
    # the slip controller stays inside the slip-ratio range the tyre declares (its fitted range): a peak
    # beyond it is an extrapolation of the model
    lo, hi = tyre.validity()["slip_ratio"]
    capped = []
    if kb < lo:
        kb = float(lo)
        capped.append("brake")
    if kd > hi:
        kd = float(hi)
        capped.append("drive")
    return {"kappa_brake": kb, "kappa_drive": kd, "alpha": ap, "c_kappa": max(ck, 1.0) / fz, "capped": capped,
            "range": (float(lo), float(hi))}


class _Axle:
    """An axle's tyres (left: the file's, right: mirrored) evaluated in one call."""

    def __init__(self, tyre, fz_static: float):
        self.tyre = tyre
        self.combined = bool(getattr(tyre, "combined", False))
        self.peak = _peak_slips(tyre, fz_static)

    def forces(self, fz, alpha, kappa):
        """``fz``, ``alpha``, ``kappa``: (2, n) arrays (left, right) -> (fx, fy) (2, n), lifted wheels give 0."""
        n = fz.shape[1]
        f = np.concatenate([fz[0], fz[1]])
        a = np.concatenate([alpha[0], -alpha[1]])        # the right tyre is the mirror image
        k = np.concatenate([kappa[0], kappa[1]])
        if self.combined:
            out = self.tyre.forces(np.maximum(f, 1.0), slip_angle=a, slip_ratio=k)
            fx, fy = out["fx"], out["fy"]
        else:
            p = self.peak
            kp = np.where(k < 0, -p["kappa_brake"], p["kappa_drive"])
            kn, an = k / kp, a / p["alpha"]
            rho = np.hypot(kn, an)
            safe = np.maximum(rho, 1e-12)
            out = self.tyre.forces(np.maximum(f, 1.0), slip_angle=np.sign(a) * rho * p["alpha"],
                                   slip_ratio=np.sign(k) * rho * kp)
            fx = np.where(rho > 1e-12, out["fx"] * np.abs(kn) / safe, 0.0)
            fy = np.where(rho > 1e-12, out["fy"] * np.abs(an) / safe, 0.0)
        on = f > 0
        fx, fy = np.where(on, fx, 0.0), np.where(on, fy, 0.0)
        return np.stack([fx[:n], fx[n:]]), np.stack([fy[:n], -fy[n:]])


@dataclass
class Trace:
    """Time histories of a run: arrays (T, n) (time x members), wheels (T, 4, n) in the order fl, fr, rl, rr."""

    t: np.ndarray
    ch: dict
    active: np.ndarray                 # (T, n) bool: the member was still moving


class _Model:
    def __init__(self, spec, front, rear):
        self.spec = spec
        w = wheel_loads(spec)
        self.axles = (_Axle(front, float(w["fl"])), _Axle(rear, float(w["rl"])))
        lf, lr, t = spec.lf, spec.lr, spec.track
        self.x = np.array([lf, lf, -lr, -lr])[:, None]
        self.y = np.array([t / 2, -t / 2, t / 2, -t / 2])[:, None]
        self.driven = np.array([spec.front.drive, spec.front.drive, spec.rear.drive, spec.rear.drive])
        self.fz_static = np.array([w[k] for k in ("fl", "fr", "rl", "rr")])[:, None]
        p = [ax.peak for ax in self.axles for _ in (0, 1)]
        self.k_lo = np.array([q["kappa_brake"] for q in p])[:, None]
        self.k_hi = np.array([q["kappa_drive"] for q in p])[:, None]
        self.c_kappa = np.array([q["c_kappa"] for q in p])[:, None]

    def resistance(self, vx, fz_sum):
        s = self.spec
        return s.drag_coefficient * vx * np.abs(vx) + s.rolling_resistance * fz_sum

    def loads(self, ax, ay, vx):
        w = wheel_loads(self.spec, ax=ax, ay=ay, speed=vx)
        return np.stack([w["fl"], w["fr"], w["rl"], w["rr"]])

    def targets(self, demand, fz):
        """Each wheel's share of the longitudinal force demand (n,) -> (4, n)."""
        f = np.maximum(fz, 0.0)
        brake = f / np.maximum(f.sum(axis=0), 1e-9)
        fd = np.where(self.driven[:, None], f, 0.0)
        drive = fd / np.maximum(fd.sum(axis=0), 1e-9)
        return demand * np.where(demand < 0, brake, drive)

    def slips(self, vx, vy, r, steer):
        d = np.stack([steer, steer, np.zeros_like(steer), np.zeros_like(steer)])
        vxi = vx - r * self.y
        vyi = vy + r * self.x
        return np.arctan2(vyi, np.maximum(vxi, 0.1)) - d, d

    def rates(self, s, kappa, steer, fz):
        vx, vy, r, psi = s[0], s[1], s[2], s[5]
        alpha, d = self.slips(vx, vy, r, steer)
        fxf, fyf = self.axles[0].forces(fz[:2], alpha[:2], kappa[:2])
        fxr, fyr = self.axles[1].forces(fz[2:], alpha[2:], kappa[2:])
        fx, fy = np.concatenate([fxf, fxr]), np.concatenate([fyf, fyr])
        c, sn = np.cos(d), np.sin(d)
        bx, by = fx * c - fy * sn, fx * sn + fy * c
        m, iz = self.spec.mass, self.spec.yaw_inertia
        res = self.resistance(vx, np.maximum(fz, 0).sum(axis=0))
        ax_t = (bx.sum(axis=0) - self.spec.rolling_resistance * np.maximum(fz, 0).sum(axis=0)) / m
        ay_t = by.sum(axis=0) / m
        dvx = (bx.sum(axis=0) - res) / m + r * vy
        dvy = by.sum(axis=0) / m - r * vx
        dr = (self.x * by - self.y * bx).sum(axis=0) / iz
        dX = vx * np.cos(psi) - vy * np.sin(psi)
        dY = vx * np.sin(psi) + vy * np.cos(psi)
        return np.stack([dvx, dvy, dr, dX, dY, r]), dict(fx=fx, fy=fy, alpha=alpha, ax=ax_t, ay=ay_t,
                                                          ax_body=(bx.sum(axis=0) - res) / m)

    def run(self, s0, steer_fn, demand_fn, t_end, record_every=1):
        """Integrate from state ``s0`` (6, n); ``steer_fn(t) -> (n,)``, ``demand_fn(t, s, fz) -> (n,)`` [N]."""
        s = np.array(s0, float)
        n = s.shape[1]
        kappa = np.zeros((4, n))
        fx_last = np.zeros((4, n))
        ax, ay = np.zeros(n), s[0] * s[2]
        active = np.ones(n, bool)
        steps = int(round(t_end / _DT))
        rec = {k: [] for k in ("vx", "vy", "r", "X", "Y", "psi", "steer", "ax", "ay", "demand")}
        wrec = {k: [] for k in ("fz", "alpha", "kappa", "fx", "fy")}
        ts, acts = [], []
        for i in range(steps + 1):
            t = i * _DT
            fz = self.loads(ax, ay, s[0])
            steer = steer_fn(t)
            demand = demand_fn(t, s, fz)
            tgt = self.targets(demand, fz)
            kappa = np.clip(kappa + _SLIP_GAIN * (tgt - fx_last) / (self.c_kappa * np.maximum(fz, 1.0)),
                            self.k_lo, self.k_hi)
            k1, o = self.rates(s, kappa, steer, fz)
            fx_last, ax, ay = o["fx"], o["ax"], o["ay"]
            if i % record_every == 0:
                ts.append(t)
                acts.append(active.copy())
                for k, v in (("vx", s[0]), ("vy", s[1]), ("r", s[2]), ("X", s[3]), ("Y", s[4]), ("psi", s[5]),
                             ("steer", steer), ("ax", o["ax_body"]), ("ay", o["ay"]), ("demand", demand)):
                    rec[k].append(np.array(v, float))
                for k, v in (("fz", fz), ("alpha", o["alpha"]), ("kappa", kappa), ("fx", o["fx"]),
                             ("fy", o["fy"])):
                    wrec[k].append(v)
            if i == steps or not active.any():
                break
            k2, _ = self.rates(s + _DT * k1, kappa, steer_fn(t + _DT), fz)
            step = 0.5 * _DT * (k1 + k2)
            s = s + np.where(active, step, 0.0)
            active = active & (s[0] > _V_STOP)
        ch = {k: np.array(v) for k, v in rec.items()}
        ch.update({k: np.array(v) for k, v in wrec.items()})
        return Trace(np.array(ts), ch, np.array(acts))


def _steady_state(spec, front, rear, ay, radius):
    """The ramp's steady state (speed, yaw rate, body slip, steer) at lateral acceleration ``ay`` on ``radius``."""
    st = _states(spec, front, rear, np.array([ay]), radius)
    if st["reason"][0] != "":
        raise DataError(f"vehicle {spec.name!r}: cannot corner steadily at {ay / G0:.3g} g on a {radius:.4g} m "
                        f"circle with these tyres ({st['reason'][0]}); accepted a lower lateral acceleration")
    return {k: float(st[k][0]) for k in ("speed", "yaw_rate", "beta", "steer")}


def _metrics(t, y, t50):
    """ISO 7401 time-response figures of a step response ``y(t)`` whose input passed 50 % at ``t50``."""
    tail = t >= t[-1] - 0.5
    ss = float(np.mean(y[tail]))
    after = t >= t50 - 0.2
    ta, ya = t[after], y[after]
    s = np.sign(ss) if ss != 0 else 1.0
    yn = s * ya / abs(ss) if ss != 0 else ya * 0

    def first(level):
        idx = np.nonzero(yn >= level)[0]
        if not idx.size:
            return math.nan
        j = int(idx[0])
        if j == 0:
            return float(ta[0])
        return float(np.interp(level, [yn[j - 1], yn[j]], [ta[j - 1], ta[j]]))

    t10, t90 = first(0.1), first(0.9)
    j = int(np.argmax(yn))
    return {"steady_state": ss, "rise_time_s": t90 - t10, "response_time_s": t90 - t50,
            "peak_response_time_s": float(ta[j] - t50), "overshoot_pct": max(0.0, 100.0 * (float(yn[j]) - 1.0))}


@dataclass
class StepSteerResult:
    speed: float
    steer: float
    target_ay: float
    trace: Trace
    yaw: dict
    lat: dict
    closed_form: dict
    t50: float
    notes: list[str] = field(default_factory=list)

    def to_json(self) -> dict:
        deg = math.degrees
        y, a = self.yaw, self.lat
        tr = self.trace
        every = max(1, int(round(0.02 / _DT)))
        table = [{"t_s": float(tr.t[i]), "steer_deg": deg(float(tr.ch["steer"][i, 0])),
                  "yaw_rate_deg_per_s": deg(float(tr.ch["r"][i, 0])), "ay_g": float(tr.ch["ay"][i, 0] / G0),
                  "speed_kmh": 3.6 * float(tr.ch["vx"][i, 0])} for i in range(0, tr.t.size, every)]
        return {
            "speed_kmh": 3.6 * self.speed, "steer_deg": deg(self.steer), "target_ay_g": self.target_ay / G0,
            "yaw_rate_steady_deg_per_s": deg(y["steady_state"]),
            "yaw_rate_gain_per_s": y["steady_state"] / self.steer,
            "yaw_rate_rise_time_s": y["rise_time_s"], "yaw_rate_response_time_s": y["response_time_s"],
            "yaw_rate_peak_response_time_s": y["peak_response_time_s"], "yaw_rate_overshoot_pct": y["overshoot_pct"],
            "lateral_acceleration_steady_g": a["steady_state"] / G0,
            "lateral_acceleration_gain_g_per_deg": a["steady_state"] / G0 / deg(self.steer),
            "lateral_acceleration_rise_time_s": a["rise_time_s"],
            "lateral_acceleration_response_time_s": a["response_time_s"],
            "lateral_acceleration_peak_response_time_s": a["peak_response_time_s"],
            "lateral_acceleration_overshoot_pct": a["overshoot_pct"],
            "closed_form": self.closed_form, "trace": table, "notes": self.notes}


def run_step_steer(spec, front, rear, speed_kmh: float = 80.0, ay_g: float = 0.4, steer_time: float = 0.1,
                   t_end: float = 4.0) -> StepSteerResult:
    """Step steer from straight running at ``speed_kmh`` to the steering angle that gives ``ay_g`` in steady state.

    The steering angle is the ramp's steady state at that speed and lateral acceleration
    (:mod:`~tyrefit.sim.handling`); it rises linearly over ``steer_time`` [s] from t = 0.5 s
    and is then held.  Rise time (10-90 %), response time (50 % steer to 90 % response), peak
    response time and overshoot of yaw rate and lateral acceleration, and the steady-state
    gains; the linear bicycle model's yaw-rate gain v / (L + K v^2) as a check.
    """
    if not 5.0 <= speed_kmh <= 300.0:
        raise DataError(f"step steer: speed = {speed_kmh:g} km/h; accepted 5 to 300 km/h")
    if not 0.01 <= ay_g <= 3.0:
        raise DataError(f"step steer: lateral acceleration = {ay_g:g} g; accepted 0.01 to 3 g")
    v = speed_kmh / 3.6
    ay = ay_g * G0
    ss = _steady_state(spec, front, rear, ay, v * v / ay)
    steer = ss["steer"]
    t0 = 0.5
    model = _Model(spec, front, rear)

    def steer_fn(t):
        return np.array([steer * min(max((t - t0) / steer_time, 0.0), 1.0)])

    def demand_fn(t, s, fz):
        return model.resistance(s[0], np.maximum(fz, 0).sum(axis=0)) + spec.mass * _KP_SPEED * (v - s[0])

    s0 = np.array([[v], [0.0], [0.0], [0.0], [0.0], [0.0]])
    tr = model.run(s0, steer_fn, demand_fn, t_end)
    t50 = t0 + 0.5 * steer_time
    yaw = _metrics(tr.t, tr.ch["r"][:, 0], t50)
    lat = _metrics(tr.t, tr.ch["ay"][:, 0], t50)
    cf = closed_form_understeer_gradient(spec, front, rear)
    k = math.radians(cf["understeer_gradient_deg_per_g"]) / G0
    closed = {"understeer_gradient_deg_per_g": cf["understeer_gradient_deg_per_g"],
              "linear_bicycle_yaw_rate_gain_per_s": v / (spec.wheelbase + k * v * v),
              "ramp_steady_steer_deg": math.degrees(steer)}
    notes = ["two-track yaw-plane model, quasi-static load transfer and downforce, speed held by a speed "
             "controller; steering angle at the road wheels",
             "rise time 10-90 % of the steady value; response time from 50 % of the steering step to 90 % of "
             "the steady value (ISO 7401); steady value: mean of the last 0.5 s"]
    notes += _combined_notes(model)
    return StepSteerResult(speed=v, steer=steer, target_ay=ay, trace=tr, yaw=yaw, lat=lat, closed_form=closed,
                           t50=t50, notes=notes)


def _combined_notes(model) -> list[str]:
    out = [f"{role} tyre {ax.tyre.name!r} has no combined slip; combined by normalised slip (similarity method)"
           for role, ax in zip(("front", "rear"), model.axles) if not ax.combined]
    for role, ax in zip(("front", "rear"), model.axles):
        p = ax.peak
        if p["capped"]:
            out.append(f"{role} tyre {ax.tyre.name!r}: the {' and '.join(p['capped'])} peak of Fx lies beyond the "
                       f"slip-ratio range the file declares ({p['range'][0]:g} to {p['range'][1]:g}); the wheel-slip "
                       "controller stops at the range's edge (the grip there is a lower bound of the tyre's)")
    return out


@dataclass
class BrakingTurnResult:
    radius: float
    ay0: float
    speed: float
    steer: float
    demands_g: list
    trace: Trace
    rows: list
    t_brake: float
    centre: np.ndarray
    radius0: np.ndarray
    notes: list[str] = field(default_factory=list)

    def to_json(self) -> dict:
        return {"radius_m": self.radius, "initial_ay_g": self.ay0 / G0, "initial_speed_kmh": 3.6 * self.speed,
                "steer_deg": math.degrees(self.steer), "rows": self.rows, "notes": self.notes}


def run_braking_turn(spec, front, rear, radius: float = 100.0, ay_g: float = 0.5,
                     decelerations_g=(0.3, 0.5, None), settle: float = 1.5) -> BrakingTurnResult:
    """Braking in a turn: steady cornering at ``ay_g`` on ``radius``, then braking with the steering held.

    ``decelerations_g``: the brake demands [g]; ``None`` is full braking (the wheel-slip
    controller at the tyres' peak, an ABS stop).  Per demand: the mean fully developed
    deceleration (ECE R13: between 80 % and 10 % of the initial speed) and the largest one,
    the yaw-rate deviation 1 s after the brake onset from the yaw rate that would keep the
    initial radius at the current speed (v / R_0; positive: the car turns in), the path
    deviation (distance from the initial circle's centre minus R_0; positive: the car runs
    wide) 1 s after the onset and at the stop, the stopping distance and time, and the largest
    body slip angle.
    """
    if not 10.0 <= radius <= 1000.0:
        raise DataError(f"braking in a turn: radius = {radius:g} m; accepted 10 to 1000 m")
    if not 0.01 <= ay_g <= 3.0:
        raise DataError(f"braking in a turn: lateral acceleration = {ay_g:g} g; accepted 0.01 to 3 g")
    ay = ay_g * G0
    ss = _steady_state(spec, front, rear, ay, radius)
    v, steer = ss["speed"], ss["steer"]
    demands = list(decelerations_g)
    n = len(demands)
    dem = np.array([3.0 if d is None else float(d) for d in demands]) * G0 * spec.mass
    model = _Model(spec, front, rear)
    tb = settle

    def steer_fn(t):
        return np.full(n, steer)

    def demand_fn(t, s, fz):
        if t < tb:
            return model.resistance(s[0], np.maximum(fz, 0).sum(axis=0)) + spec.mass * _KP_SPEED * (v - s[0])
        return -dem

    b = ss["beta"]
    s0 = np.tile(np.array([[v * math.cos(b)], [v * math.sin(b)], [ss["yaw_rate"]], [0.0], [0.0], [0.0]]), (1, n))
    slowest = min(float(np.min(dem)) / spec.mass, 10.0)
    t_end = tb + v / max(0.5 * slowest, 0.5) + 2.0
    tr = model.run(s0, steer_fn, demand_fn, t_end)
    ch, t = tr.ch, tr.t
    i0 = int(np.searchsorted(t, tb - 1e-9))
    vx0, vy0, r0 = ch["vx"][i0], ch["vy"][i0], ch["r"][i0]
    speed0 = np.hypot(vx0, vy0)
    R0 = speed0 / r0
    course = ch["psi"][i0] + np.arctan2(vy0, vx0)
    centre = np.stack([ch["X"][i0] - R0 * np.sin(course), ch["Y"][i0] + R0 * np.cos(course)])
    rows = []
    for j, d in enumerate(demands):
        act = tr.active[:, j] & (t >= tb)
        idx = np.nonzero(act)[0]
        last = int(idx[-1])
        sp = np.hypot(ch["vx"][:, j], ch["vy"][:, j])
        pos = np.stack([ch["X"][:, j], ch["Y"][:, j]])
        dist = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(pos[0]), np.diff(pos[1])))])
        decel = -ch["ax"][:, j]
        a_last = max(float(np.mean(decel[max(i0, last - 10):last + 1])), 0.1)
        stop = float(dist[last] - dist[i0] + sp[last] ** 2 / (2 * a_last))
        t_stop = float(t[last] - tb + sp[last] / a_last)
        # ECE R13 mean fully developed deceleration between 0.8 v0 and 0.1 v0
        vb, ve = 0.8 * speed0[j], 0.1 * speed0[j]
        after = np.arange(t.size) >= i0
        ib = int(np.nonzero(after & (sp <= vb))[0][0]) if np.any(after & (sp <= vb)) else last
        ie_c = np.nonzero(after & (sp <= ve) & tr.active[:, j])[0]
        if ie_c.size:
            ie = int(ie_c[0])
            sb, se = dist[ib], dist[ie]
        else:  # stopped (1 m/s) above 10 % of the speed: extrapolate the last deceleration
            ie = last
            sb, se = dist[ib], dist[last] + (sp[last] ** 2 - ve ** 2) / (2 * a_last)
        mfdd = float((sp[ib] ** 2 - ve ** 2) / (2 * max(se - sb, 1e-9)))
        i1 = min(int(np.searchsorted(t, tb + 1.0)), last)
        ref = sp[i1] / R0[j]
        dev = np.hypot(pos[0] - centre[0, j], pos[1] - centre[1, j]) - R0[j]
        beta = np.arctan2(ch["vy"][:, j], ch["vx"][:, j])
        rows.append({
            "deceleration_demand_g": None if d is None else float(d),
            "mean_deceleration_mps2": mfdd,
            "max_deceleration_mps2": float(np.max(decel[i0:last + 1])),
            "stopping_distance_m": stop, "stopping_time_s": t_stop,
            "yaw_rate_deviation_1s_deg_per_s": math.degrees(float(ch["r"][i1, j] - ref)),
            "yaw_rate_ratio_1s": float(ch["r"][i1, j] / ref) if ref != 0 else None,
            "time_to_1s_reached": bool(t[i1] >= tb + 1.0 - 1e-9),
            "path_deviation_1s_m": float(dev[i1]), "path_deviation_stop_m": float(dev[last]),
            "max_body_slip_deg": math.degrees(float(np.max(np.abs(beta[i0:last + 1])))),
        })
    notes = ["two-track yaw-plane model, quasi-static load transfer and downforce; steady cornering (speed held) "
             f"for {settle:g} s, then the brake demand with the steering held",
             "brake force shared in proportion to the wheel loads (ideal balance); an ideal wheel-slip "
             "controller keeps each wheel at or below its tyre's pure-slip peak (deceleration_demand_g null: "
             "full braking, an ABS stop)",
             "mean_deceleration_mps2: ECE R13 mean fully developed deceleration (80 % to 10 % of the initial "
             "speed); yaw_rate_deviation_1s: yaw rate 1 s after the brake onset minus v/R_0 (positive: turns "
             "in); path_deviation: distance from the initial circle's centre minus R_0 (positive: runs wide)"]
    notes += _combined_notes(model)
    return BrakingTurnResult(radius=radius, ay0=ay, speed=v, steer=steer, demands_g=demands, trace=tr, rows=rows,
                             t_brake=tb, centre=centre, radius0=R0, notes=notes)


def points_from_trace(tr: Trace, role: str):
    """Operating points of the front or rear tyre's two wheels over every member's moving time."""
    w = slice(0, 2) if role == "front" else slice(2, 4)
    parts = []
    for j in range(tr.active.shape[1]):
        m = tr.active[:, j]
        fz = tr.ch["fz"][m][:, w, j]
        parts.append(OperatingPoints(fz, tr.ch["alpha"][m][:, w, j] * np.array([1.0, -1.0]),
                                     tr.ch["kappa"][m][:, w, j], np.full(fz.shape[0], _DT)))
    return OperatingPoints.concat(parts)
