"""Bicycle model with wheel spin and drag, in path coordinates (Pham et al. 2025, Eq. 1-13).

Notation.  Pham et al. write v for the longitudinal and u for the lateral
velocity, delta for the **yaw rate** and sigma for the **steering angle**;
here they are ``vx``, ``vy``, ``yaw_rate`` and ``steer``.  Axes are ISO 8855
(x forward, y left, z up; yaw and steering positive counter-clockwise), path
coordinates as in :mod:`tyrefit.sim.path`.

Equations (one wheel per axle standing for the axle's two tyres)::

    m (dvx/dt - vy r) = Fx_r + Fx_f cos(steer) - Fy_f sin(steer) - C_d vx|vx|     (Eq. 1)
    m (dvy/dt + vx r) = Fy_r + Fx_f sin(steer) + Fy_f cos(steer)                    (Eq. 2)
    I_z dr/dt         = l_f (Fx_f sin(steer) + Fy_f cos(steer)) - l_r Fy_r          (Eq. 3)
    J dw_i/dt         = T_i - r_w Fx_i                                               (Eq. 5)
    lambda_i = (r_w w_i - v_i) / max(|v_i|, eps)     (driving positive)              (Eq. 4)
    alpha_f = atan((vy + l_f r)/vx) - steer,  alpha_r = atan((vy - l_r r)/vx)        (Eq. 6-7, ISO-W)
    Fx_i = eta AxleTyre_i.fx(lambda_i),  Fy_i = eta AxleTyre_i.fy(alpha_i)           (Eq. 8-10)

and Eq. 11-13 for (s, n, xi).  v_i is the wheel-centre speed along the wheel
(v_r = vx; v_f = vx cos(steer) + (vy + l_f r) sin(steer)), which reduces to
Eq. 4's v without steering.  Pham et al.'s slip angles are positive for a left
turn (SAE-like); ISO-W slip angles have the opposite sign, so a left turn
gives negative alpha and positive (leftward) Fy.  Axle loads are static (no
load transfer) and the tyres have no combined-slip coupling, as in the paper.

The system is written python-control style: :meth:`VehicleModel.update`
``(t, x, u, params) -> dx/dt`` with named states :data:`STATES` and inputs
:data:`INPUTS`; :meth:`VehicleModel.output` gives the named outputs.
:func:`step` advances one fixed step, explicit for the body and linearly
implicit for the stiff wheel spin (whose time constant falls to ~1e-4 s at
low speed).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np

from ..errors import DataError
from ..nomenclature import G0
from .path import PathGeometry, curvilinear_rates
from .tyres import AxleTyre

__all__ = [
    "STATES",
    "INPUTS",
    "OUTPUTS",
    "VehicleParams",
    "DEFAULT_VEHICLE",
    "VehicleModel",
    "SimResult",
]

#: state vector, in order
STATES = ("s", "n", "xi", "vx", "vy", "yaw_rate", "omega_f", "omega_r")
#: input vector, in order
INPUTS = ("steer", "torque_f", "torque_r")
#: named outputs of :meth:`VehicleModel.output`
OUTPUTS = ("fx_f", "fx_r", "fy_f", "fy_r", "slip_ratio_f", "slip_ratio_r", "slip_angle_f", "slip_angle_r",
           "curvature", "ax", "ay", "drag")

S, N, XI, VX, VY, R, WF, WR = range(8)


@dataclass(frozen=True)
class VehicleParams:
    """The simulated vehicle (SI): tyrefit's values, not the paper's.

    Attributes
    ----------
    mass : float
        1800 kg: a mid-size battery-electric car.
    yaw_inertia : float
        3000 kg m^2 (about 0.55 m l_f l_r, typical of saloons).
    lf, lr : float
        1.4 m each: a 2.8 m wheelbase with the centre of gravity midway (Pham et al.: l_f = l_r).
    wheel_radius : float
        0.32 m, the effective rolling radius of both axles.
    wheel_inertia : float
        2.2 kg m^2 per axle (two wheels with hubs, brakes and motor rotor share).
    drag : float
        C_d = 0.864 kg/m in F = C_d v^2.  **Calibrated to Pham et al.'s Table 3**:
        its maximum decelerations grow by 0.5 m/s^2 from 30 to 120 km/h at both
        conditions, i.e. C_d/m = 4.8e-4 1/m.
    min_speed : float
        eps of the slip definitions [m/s] (Eq. 4 divides by max(|v|, eps)).
    g : float
        [m/s^2].
    """

    mass: float = 1800.0
    yaw_inertia: float = 3000.0
    lf: float = 1.4
    lr: float = 1.4
    wheel_radius: float = 0.32
    wheel_inertia: float = 2.2
    drag: float = 0.864
    min_speed: float = 0.5
    g: float = G0

    @property
    def wheelbase(self) -> float:
        return self.lf + self.lr

    @property
    def axle_load_front(self) -> float:
        """Static front axle load m g l_r / L [N]."""
        return self.mass * self.g * self.lr / self.wheelbase

    @property
    def axle_load_rear(self) -> float:
        """Static rear axle load m g l_f / L [N]."""
        return self.mass * self.g * self.lf / self.wheelbase

    def to_dict(self) -> dict:
        return asdict(self)


#: the documented default vehicle
DEFAULT_VEHICLE = VehicleParams()


@dataclass
class VehicleModel:
    """The bicycle model of one vehicle for a batch of B runs.

    Parameters
    ----------
    params : VehicleParams
    front, rear : AxleTyre
        Axle tyres at the static axle loads.
    condition : array_like, shape (B,)
        Condition scaling eta of the tyre forces (1 normal, 0.5 wet; Pham et al. 2025, Sec. 4.2.1).
    path : PathGeometry, optional
        Centre lines (B members); straight when omitted.
    """

    params: VehicleParams
    front: AxleTyre
    rear: AxleTyre
    condition: np.ndarray
    path: PathGeometry | None = None

    def __post_init__(self) -> None:
        self.condition = np.atleast_1d(np.asarray(self.condition, float))
        if np.any(self.condition <= 0):
            raise DataError(f"condition scaling eta must be positive, got {self.condition.min():g}")
        if self.path is not None and self.path.n_members != self.condition.size:
            raise DataError("path and condition arrays have different batch sizes")

    @property
    def n_members(self) -> int:
        return self.condition.size

    # -- kinematics ---------------------------------------------------------------
    def wheel_speeds(self, x, steer):
        """Wheel-centre speeds along the front and rear wheels [m/s]."""
        p = self.params
        vx, vy, r = x[VX], x[VY], x[R]
        vf = vx * np.cos(steer) + (vy + p.lf * r) * np.sin(steer)
        return vf, vx

    def slip_angle_front(self, x, steer):
        """ISO-W front slip angle [rad] (Eq. 6, sign flipped to ISO-W)."""
        p = self.params
        return np.arctan2(x[VY] + p.lf * x[R], np.maximum(x[VX], p.min_speed)) - steer

    def slip_angle_rear(self, x):
        """ISO-W rear slip angle [rad] (Eq. 7, sign flipped to ISO-W)."""
        p = self.params
        return np.arctan2(x[VY] - p.lr * x[R], np.maximum(x[VX], p.min_speed))

    def slip_ratios(self, x, steer):
        """(front, rear) slip ratios (Eq. 4)."""
        p = self.params
        vf, vr = self.wheel_speeds(x, steer)
        lf = (p.wheel_radius * x[WF] - vf) / np.maximum(np.abs(vf), p.min_speed)
        lr = (p.wheel_radius * x[WR] - vr) / np.maximum(np.abs(vr), p.min_speed)
        return lf, lr

    # -- dynamics -----------------------------------------------------------------
    def evaluate(self, t, x, u):
        """State derivative and named outputs at (t, x, u): ``(dx, outputs)``."""
        p = self.params
        eta = self.condition
        steer, tf, tr = u[0], u[1], u[2]
        vx, vy, r = x[VX], x[VY], x[R]
        lam_f, lam_r = self.slip_ratios(x, steer)
        a_f = self.slip_angle_front(x, steer)
        a_r = self.slip_angle_rear(x)
        fxf = eta * self.front.fx(lam_f)                                  # Eq. 8
        fxr = eta * self.rear.fx(lam_r)
        fyf = eta * self.front.fy(a_f)                                    # Eq. 9
        fyr = eta * self.rear.fy(a_r)
        cs, sn = np.cos(steer), np.sin(steer)
        drag = p.drag * vx * np.abs(vx)
        fx_body = fxr + fxf * cs - fyf * sn - drag
        fy_body = fyr + fxf * sn + fyf * cs
        ax = fx_body / p.mass                                              # Eq. 1: dvx/dt - vy r
        ay = fy_body / p.mass                                              # Eq. 2: dvy/dt + vx r
        dvx = ax + vy * r
        dvy = ay - vx * r
        dr = (p.lf * (fxf * sn + fyf * cs) - p.lr * fyr) / p.yaw_inertia  # Eq. 3
        dwf = (tf - p.wheel_radius * fxf) / p.wheel_inertia               # Eq. 5
        dwr = (tr - p.wheel_radius * fxr) / p.wheel_inertia
        kappa = self.path.curvature(x[S]) if self.path is not None else np.zeros_like(vx)
        ds, dn, dxi = curvilinear_rates(x[N], x[XI], vx, vy, r, kappa)   # Eq. 11-13
        dx = np.stack([ds, dn, dxi, dvx, dvy, dr, dwf, dwr])
        out = {"fx_f": fxf, "fx_r": fxr, "fy_f": fyf, "fy_r": fyr, "slip_ratio_f": lam_f,
               "slip_ratio_r": lam_r, "slip_angle_f": a_f, "slip_angle_r": a_r, "curvature": kappa,
               "ax": ax, "ay": ay, "drag": drag}
        return dx, out

    def update(self, t, x, u, params=None):
        """dx/dt (python-control ``updfcn`` signature); ``params`` may override ``condition``."""
        if params and "condition" in params:
            saved = self.condition
            self.condition = np.atleast_1d(np.asarray(params["condition"], float))
            try:
                return self.evaluate(t, x, u)[0]
            finally:
                self.condition = saved
        return self.evaluate(t, x, u)[0]

    def output(self, t, x, u, params=None) -> dict:
        """Named outputs :data:`OUTPUTS` (python-control ``outfcn`` signature)."""
        return self.evaluate(t, x, u)[1]

    def wheel_jacobian(self, x, u, out):
        """Diagonal d(dw_i/dt)/dw_i of the wheel-spin equations [1/s] (<= 0 on the stable branch)."""
        p = self.params
        vf, vr = self.wheel_speeds(x, u[0])
        eta = self.condition
        kf = np.maximum(self.front.slip_stiffness(out["slip_ratio_f"]), 0.0)
        kr = np.maximum(self.rear.slip_stiffness(out["slip_ratio_r"]), 0.0)
        jf = -eta * kf * p.wheel_radius**2 / (p.wheel_inertia * np.maximum(np.abs(vf), p.min_speed))
        jr = -eta * kr * p.wheel_radius**2 / (p.wheel_inertia * np.maximum(np.abs(vr), p.min_speed))
        return jf, jr

    def step(self, t, x, u, dt):
        """One fixed step: explicit Euler for the body, then linearly implicit Euler for the wheels.

        The wheel update uses the body speeds of the *new* step (a split
        scheme): w+ = w + dt f(w, v+) / (1 - dt df/dw).  Evaluating the slip
        at the new speed lets the wheel follow its moving equilibrium with a
        lag of (dw*/dt) / |df/dw|, which vanishes as the wheel gets stiffer
        (low speed), instead of a lag that grows with dt |df/dw|.

        Returns ``(x_next, dx, outputs)`` with ``dx`` and ``outputs`` at (t, x).
        """
        p = self.params
        dx, out = self.evaluate(t, x, u)
        xn = x + dt * dx
        vf, vr = self.wheel_speeds(xn, u[0])
        eta = self.condition
        r, J = p.wheel_radius, p.wheel_inertia
        for k, v, axle, torque in ((WF, vf, self.front, u[1]), (WR, vr, self.rear, u[2])):
            den = np.maximum(np.abs(v), p.min_speed)
            lam = (r * x[k] - v) / den
            f = (torque - r * eta * axle.fx(lam)) / J
            jac = -eta * np.maximum(axle.slip_stiffness(lam), 0.0) * r * r / (J * den)
            xn[k] = x[k] + dt * f / (1.0 - dt * jac)
        return xn, dx, out

    def cruise_state(self, vx, fx_f, fx_r):
        """State of straight running at speed ``vx`` with the wheels slipping to give axle forces ``fx_f``, ``fx_r`` [N]."""
        p = self.params
        x = self.rolling_state(vx)
        eta = self.condition
        den = np.maximum(np.abs(x[VX]), p.min_speed)
        lam_f = self.front.slip_for_force(np.asarray(fx_f, float) / eta)
        lam_r = self.rear.slip_for_force(np.asarray(fx_r, float) / eta)
        x[WF] = (x[VX] + lam_f * den) / p.wheel_radius
        x[WR] = (x[VX] + lam_r * den) / p.wheel_radius
        return x

    def rolling_state(self, vx, n_members: int | None = None):
        """State of straight free rolling at speed ``vx`` (wheels at zero slip)."""
        b = n_members or self.n_members
        x = np.zeros((len(STATES), b))
        x[VX] = vx
        x[WF] = x[VX] / self.params.wheel_radius
        x[WR] = x[VX] / self.params.wheel_radius
        return x


@dataclass
class SimResult:
    """Time histories of a batch simulation (B members).

    Attributes
    ----------
    t : ndarray, shape (T,)
        [s].
    channels : dict of ndarray, shape (T, B)
        States (:data:`STATES`), inputs (:data:`INPUTS`), outputs (:data:`OUTPUTS`)
        and controller signals (``steer_driver``, ``force_demand``, ``force_ref_f``,
        ``force_ref_r``, ``steer_correction``, ``emission_f``, ``emission_r``).
    end_index : ndarray of int, shape (B,)
        Last valid sample of each member (members stop at different times).
    meta : dict
        Labels and settings.
    """

    t: np.ndarray
    channels: dict[str, np.ndarray]
    end_index: np.ndarray
    meta: dict = field(default_factory=dict)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.channels[name]

    def __contains__(self, name: str) -> bool:
        return name in self.channels

    @property
    def n_members(self) -> int:
        return int(self.end_index.size)

    def member(self, j: int, names=None) -> dict[str, np.ndarray]:
        """Channels of member ``j`` up to its end (1-D arrays, ``t`` included)."""
        e = int(self.end_index[j]) + 1
        names = names or list(self.channels)
        out = {"t": self.t[:e]}
        out.update({k: self.channels[k][:e, j] for k in names})
        return out

    def frame(self, j: int, every: int = 1, names=None):
        """Member ``j`` as a pandas DataFrame (every ``every``-th sample)."""
        import pandas as pd

        d = self.member(j, names)
        return pd.DataFrame({k: v[::every] for k, v in d.items()})

    def integral(self, name: str) -> np.ndarray:
        """Time integral of a channel per member, up to each member's end."""
        dt = np.diff(self.t, prepend=self.t[0])
        v = self.channels[name]
        mask = np.arange(self.t.size)[:, None] <= self.end_index[None, :]
        return np.sum(np.where(mask, v * dt[:, None], 0.0), axis=0)
