"""Drivers: human-like inputs (steering, force demand) within comfort limits.

Pham et al. (2025) generate the base vehicle's trajectories by a minimum-time optimal
control problem constrained to a human driver's comfort envelope: the
*aggressive* driver of Bae et al.'s Occupant's Preference Metric for
longitudinal and lateral acceleration and jerk (Eq. 45-46), bounds on the
steering angle and rate (Eq. 47-48), |n| <= 1 m (Eq. 44) and a speed window.
The paper's values of the bounds are not used; :class:`ComfortLimits`
and :class:`SteeringLimits` hold tyrefit's values, of the size reported for
aggressive human drivers, and the scenario reports show the accelerations and
jerks actually driven.

tyrefit's driver is causal instead of optimal:

* longitudinally, the minimum-time profile under acceleration and jerk limits
  is known in closed form (a jerk-limited "S-curve": jerk +-j_max, then the
  acceleration limit, then jerk back to zero; :func:`s_curve`), and the driver
  follows it with feed-forward m a_ref + C_d v^2 plus PI feedback on speed;
* laterally, the driver steers along its own line through the curve: the
  centre line's curvature smoothed by two box filters of widths
  L_t = v^3 / (R j_y) and 0.3 L_t, which turns each curvature step into a
  transition whose lateral jerk rises smoothly to j_y (like the transition
  curves road designers use); the steering is the feed-forward that makes a
  linear model of the car follow that line (the driver knows its car) plus a
  preview (pure-pursuit) correction of the offset and course errors from the
  line, within the steering angle and rate bounds.

The low-wear vehicle replays the base driver's recorded inputs
(:class:`ReplayDriver`): the paper's "same driver inputs".
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "ComfortLimits",
    "SteeringLimits",
    "s_curve",
    "accelerate_brake_profile",
    "DriverLine",
    "PathDriver",
    "BrakeDriver",
    "ReplayDriver",
]


@dataclass(frozen=True)
class ComfortLimits:
    """Comfort envelope of an aggressive human driver (tyrefit's values; Pham et al. 2025, Eq. 45-46).

    Attributes
    ----------
    accel_max, decel_max : float
        Longitudinal acceleration and deceleration [m/s^2].
    jerk_max : float
        Longitudinal jerk [m/s^3].
    lat_accel_max : float
        Lateral acceleration [m/s^2].
    lat_jerk_max : float
        Lateral jerk [m/s^3].
    line_jerk : float
        Lateral jerk the driver plans its line with [m/s^3] (below the limit,
        leaving room for corrections).
    """

    accel_max: float = 3.0
    decel_max: float = 4.0
    jerk_max: float = 2.5
    lat_accel_max: float = 4.0
    lat_jerk_max: float = 2.0
    line_jerk: float = 1.0


@dataclass(frozen=True)
class SteeringLimits:
    """Steering angle [rad] and rate [rad/s] bounds (Pham et al. 2025, Eq. 47-48; tyrefit's values)."""

    angle_max: float = 0.35
    rate_max: float = 0.5


def s_curve(v0: float, v1: float, a_max: float, j_max: float):
    """Jerk-limited speed change from ``v0`` to ``v1`` [m/s] in the least time.

    Returns the pieces of constant jerk as a list of (duration [s], jerk [m/s^3]):
    jerk +-j_max up to the acceleration limit, hold it, jerk back to zero; a
    change too small to reach ``a_max`` peaks at sqrt(|dv| j_max).
    """
    dv = v1 - v0
    if dv == 0:
        return []
    sgn = np.sign(dv)
    dv = abs(dv)
    if dv >= a_max**2 / j_max:
        tj, ta = a_max / j_max, dv / a_max - a_max / j_max
    else:
        tj, ta = np.sqrt(dv / j_max), 0.0
    return [(tj, sgn * j_max), (ta, 0.0), (tj, -sgn * j_max)]


def _integrate_pieces(pieces, v0: float, t):
    """Speed and acceleration at times ``t`` of a piecewise-constant-jerk profile from v0 at rest acceleration."""
    t = np.asarray(t, float)
    v = np.full_like(t, v0)
    a = np.zeros_like(t)
    t0, vv, aa = 0.0, v0, 0.0
    for dur, j in pieces:
        if dur <= 0:
            continue
        m = (t >= t0) & (t < t0 + dur)
        tau = t[m] - t0
        v[m] = vv + aa * tau + 0.5 * j * tau**2
        a[m] = aa + j * tau
        vv, aa = vv + aa * dur + 0.5 * j * dur**2, aa + j * dur
        t0 += dur
    m = t >= t0
    v[m] = vv
    a[m] = 0.0
    return v, a, t0


def accelerate_brake_profile(v_top, v_floor: float, limits: ComfortLimits, t):
    """Accelerate from ``v_floor`` to ``v_top`` then brake back to ``v_floor``, least time (S-curves).

    Parameters
    ----------
    v_top : array_like, shape (B,)
        Top speeds [m/s].
    v_floor : float
        Start and end speed [m/s].
    limits : ComfortLimits
    t : ndarray, shape (T,)

    Returns
    -------
    v, a : ndarray, shape (T, B)
    t_end : ndarray, shape (B,)
        When each profile is back at ``v_floor``.
    """
    v_top = np.atleast_1d(np.asarray(v_top, float))
    V = np.empty((t.size, v_top.size))
    A = np.empty_like(V)
    ends = np.empty(v_top.size)
    for j, vt in enumerate(v_top):
        up = s_curve(v_floor, vt, limits.accel_max, limits.jerk_max)
        down = s_curve(vt, v_floor, limits.decel_max, limits.jerk_max)
        V[:, j], A[:, j], ends[j] = _integrate_pieces(up + down, v_floor, t)
    return V, A, ends


@dataclass
class DriverLine:
    """The driver's line through a path and the steering that drives it.

    Tabulated on a grid of ``m`` points per member over [0, L_j] (evaluated
    without Python loops over members): the line's curvature, its offset and
    course from the centre line and, when a speed and the driver's model of
    the car are given, the feed-forward steering angle.
    """

    s_grid: np.ndarray      # (M, B)
    kappa: np.ndarray       # (M, B) line curvature
    offset: np.ndarray      # (M, B) line offset n_line [m]
    course: np.ndarray      # (M, B) line heading minus centre-line tangent [rad]
    steer: np.ndarray       # (M, B) feed-forward steering [rad]
    length: np.ndarray      # (B,)

    @classmethod
    def build(cls, path, window, ds: float = 0.1, speed=None, params=None,
              front=None, rear=None, condition=1.0) -> "DriverLine":
        """Tabulate the line and, with ``speed`` and a linear model, its feed-forward steering.

        The line has the smoothed curvature k_line and, to first order in the
        offset, course psi = int (k_line - k) ds and offset n = int psi ds (the
        filter keeps the integral and first moment of the curvature, so the line
        leaves each curve on the centre line with its heading).

        The feed-forward steering inverts the driver's model of its car (the
        bicycle model with the axle tyres ``front``, ``rear`` at condition
        ``condition``) along the line at constant ``speed``
        (:func:`_inverse_steer`).  Without a speed the feed-forward is the
        kinematic L k_line.
        """
        length = path.total_length
        m = int(np.ceil(length.max() / ds)) + 1
        s = np.linspace(0.0, 1.0, m)[:, None] * length[None, :]
        h = length / (m - 1)
        kap_l = np.stack([path.smoothed_curvature(si, window) for si in s])
        theta_c = np.stack([path._integral(si) for si in s])             # exact centre-line heading
        theta_l = np.concatenate([np.zeros((1, s.shape[1])),
                                  np.cumsum(0.5 * (kap_l[1:] + kap_l[:-1]), axis=0) * h], axis=0)
        psi = theta_l - theta_c
        n = np.concatenate([np.zeros((1, s.shape[1])), np.cumsum(0.5 * (psi[1:] + psi[:-1]), axis=0) * h], axis=0)
        if speed is None or params is None:
            L = params.wheelbase if params is not None else 2.8
            steer = L * kap_l
        else:
            steer = _inverse_steer(kap_l, h, np.asarray(speed, float), params, front, rear,
                                   np.broadcast_to(np.asarray(condition, float), length.shape))
        return cls(s, kap_l, n, psi, steer, length)

    def at(self, s, tables=("kappa", "offset", "course", "steer")):
        """Values of the named tables at ``s`` (shape (B,)), linearly interpolated."""
        m = self.s_grid.shape[0]
        u = np.minimum(np.maximum(s / self.length, 0.0), 1.0) * (m - 1)
        i = np.minimum(u.astype(int), m - 2)
        w = u - i
        cols = np.arange(s.size)
        return [getattr(self, t)[i, cols] * (1 - w) + getattr(self, t)[i + 1, cols] * w for t in tables]


def _inverse_steer(kappa, h, v, params, front, rear, eta):
    """Steering that makes the bicycle model's *course* follow curvature ``kappa`` (M, B) at speed ``v``.

    The centre of gravity moves on the line when its lateral acceleration is
    v^2 kappa: the axle forces must sum to m v^2 kappa (Eq. 2).  The rear force
    follows from the state (vy, r) (Eq. 7, 9), the front force is the rest,
    the yaw rate evolves by Eq. 3 and vy by dvy/dt = v^2 kappa - v r; the
    front slip angle that gives the front force (inverse tyre curve) fixes the
    steering (Eq. 6).  (vy, r) are integrated along s with dt = ds / v.
    """
    p = params
    lf, lr, m, iz = p.lf, p.lr, p.mass, p.yaw_inertia
    vy = np.zeros_like(v)
    r = np.zeros_like(v)
    steer = np.empty_like(kappa)
    dt = h / v
    for i in range(kappa.shape[0]):
        fy = m * v**2 * kappa[i]                                            # Eq. 2 with the course on the line
        fyr = eta * rear.fy(np.arctan2(vy - lr * r, v))                     # Eq. 7, 9
        fyf = fy - fyr
        steer[i] = np.arctan2(vy + lf * r, v) - front.slip_angle_for_force(fyf / eta)   # Eq. 6
        r = r + dt * (lf * fyf - lr * fyr) / iz                             # Eq. 3
        vy = vy + dt * (v**2 * kappa[i] - v * r)
    return steer


@dataclass
class PathDriver:
    """A human-like driver following a speed profile and its own line along a path.

    Parameters
    ----------
    params : VehicleParams
    line : DriverLine
    v_ref, a_ref : ndarray, shape (T, B)
        Speed profile on the simulation's time grid.
    steering : SteeringLimits
    dt : float
        Time step [s].
    preview_time, preview_min : float
        Preview distance max(preview_min, preview_time * v) [m] of the
        pure-pursuit correction.
    kp, ki : float
        Speed feedback gains [1/s], [1/s^2].
    reaction : float
        Neuromuscular lag [s] of the steering correction (a first-order lag, as
        in human driver models); the feed-forward is anticipated, not lagged.
    """

    params: object
    line: DriverLine
    v_ref: np.ndarray
    a_ref: np.ndarray
    steering: SteeringLimits
    dt: float
    preview_time: float = 1.5
    preview_min: float = 5.0
    kp: float = 1.5
    ki: float = 0.3
    reaction: float = 0.1

    def __post_init__(self) -> None:
        b = self.v_ref.shape[1]
        self._steer = np.zeros(b)
        self._fb = np.zeros(b)
        self._int = np.zeros(b)

    def __call__(self, i, t, x):
        p = self.params
        s, n, xi, vx, vy = x[0], x[1], x[2], x[3], x[4]
        n_line, psi_line, steer_ff = self.line.at(s, ("offset", "course", "steer"))
        # lateral: feed-forward along the line plus a preview (pure-pursuit) correction
        d = np.maximum(self.preview_min, self.preview_time * np.abs(vx))
        course_err = xi + np.arctan2(vy, np.maximum(vx, p.min_speed)) - psi_line
        e = (n - n_line) + d * np.sin(course_err)
        self._fb += min(self.dt / self.reaction, 1.0) * (-2.0 * p.wheelbase * e / d**2 - self._fb)
        cmd = steer_ff + self._fb
        lim = self.steering
        r = lim.rate_max * self.dt
        step = np.minimum(np.maximum(cmd - self._steer, -r), r)
        self._steer = np.minimum(np.maximum(self._steer + step, -lim.angle_max), lim.angle_max)
        # longitudinal: feed-forward plus PI on speed
        k = min(i, self.v_ref.shape[0] - 1)
        err = self.v_ref[k] - vx
        self._int += err * self.dt
        force = p.mass * (self.a_ref[k] + self.kp * err + self.ki * self._int) + p.drag * vx * np.abs(vx)
        return self._steer.copy(), force


@dataclass
class BrakeDriver:
    """Emergency braking: straight ahead, full brake demand (beyond what the tyres can give)."""

    params: object
    n_members: int

    def __call__(self, i, t, x):
        p = self.params
        return np.zeros(self.n_members), np.full(self.n_members, -2.0 * p.mass * p.g)


@dataclass
class ReplayDriver:
    """The recorded inputs of another run, step by step (the paper's identical driver inputs)."""

    steer: np.ndarray          # (T, B)
    force: np.ndarray          # (T, B)

    def __call__(self, i, t, x):
        k = min(i, self.steer.shape[0] - 1)
        return self.steer[k], self.force[k]
