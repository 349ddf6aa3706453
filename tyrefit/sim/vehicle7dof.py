"""Seven-degree-of-freedom vehicle model of Zhang et al. (2024, §4.2, Eq. 33-36).

States (named, python-control style): longitudinal and lateral velocity of
the centre of gravity ``vx``, ``vy`` [m/s], yaw rate ``r`` [rad/s] and the
spin of the four wheels ``w_fl, w_fr, w_rl, w_rr`` [rad/s].  Axes ISO
(x forward, y left, z up; yaw positive counter-clockwise); the front wheels
steer by ``delta``.  Aerodynamic drag, heave, pitch and roll are ignored
(the paper's assumptions 1-2); the normal loads follow the quasi-static
load transfer of the measured accelerations.

The measurement of the road-adhesion estimator (Eq. 37) is
``y = [a_x, a_y, Gamma]``: the accelerations of the body (forces over mass,
Eq. 33-34, as an accelerometer reads them) and the yaw moment (Eq. 35).
They are linear in the eight tyre forces, so their derivatives with respect
to the forces are exact (:func:`measurement_matrix`); the Jacobian with
respect to the friction coefficients then only needs dF/dmu of each tyre.

Corrections to the printed equations (which the OCR'd text garbles):
Eq. 33 prints ``- F_yfl sin(delta) - F_yrl sin(delta)`` where the front
right tyre is meant (the rear wheels do not steer); Eq. 34's kinematic
term is ``- v_x r`` in ISO axes (``v_y' = a_y - v_x r``); Eq. 39's second row
uses the lateral forces of the wheels in their own columns.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..nomenclature import G0

__all__ = [
    "WHEELS",
    "STATES",
    "VehicleParams",
    "wheel_positions",
    "wheel_velocities",
    "body_forces",
    "measurement",
    "measurement_matrix",
    "normal_loads",
    "derivatives",
]

#: wheel order everywhere: front left, front right, rear left, rear right
WHEELS = ("fl", "fr", "rl", "rr")
#: state names of the 7-DOF model
STATES = ("vx", "vy", "r", "w_fl", "w_fr", "w_rl", "w_rr")


@dataclass(frozen=True)
class VehicleParams:
    """A compact electric passenger car on 205/55R16 tyres (illustrative values, SI).

    Attributes
    ----------
    mass : float
        Vehicle mass m [kg].
    iz : float
        Yaw inertia I_z [kg m^2].
    la, lb : float
        Distances of the front and rear axle from the centre of gravity [m].
    track_f, track_r : float
        Front and rear track t_f, t_r [m].
    h_cg : float
        Height of the centre of gravity [m] (load transfer).
    roll_share_f : float
        Front share of the lateral load transfer [-].
    wheel_inertia : float
        Spin inertia of a wheel J [kg m^2].
    wheel_radius : float
        Wheel radius R [m] of Eq. 36 (torque arm) and of the slip controller.
    pressure : float
        Tyre inflation pressure [Pa].
    """

    mass: float = 1600.0
    iz: float = 2600.0
    la: float = 1.15
    lb: float = 1.45
    track_f: float = 1.55
    track_r: float = 1.55
    h_cg: float = 0.55
    roll_share_f: float = 0.55
    wheel_inertia: float = 1.1
    wheel_radius: float = 0.305
    pressure: float = 240e3

    def replace(self, **changes) -> "VehicleParams":
        return replace(self, **changes)


def wheel_positions(vp: VehicleParams) -> tuple[np.ndarray, np.ndarray]:
    """x and y of the wheel centres [m] from the centre of gravity (order :data:`WHEELS`)."""
    x = np.array([vp.la, vp.la, -vp.lb, -vp.lb])
    y = np.array([vp.track_f / 2, -vp.track_f / 2, vp.track_r / 2, -vp.track_r / 2])
    return x, y


def _steer(delta):
    d = np.asarray(delta, float)
    z = np.zeros_like(d)
    return np.stack([d, d, z, z], axis=-1)


def wheel_velocities(vx, vy, r, delta, vp: VehicleParams):
    """Velocity of each wheel centre in its own wheel frame, ``(v_xw, v_yw)`` [m/s], shape (..., 4)."""
    x, y = wheel_positions(vp)
    vx = np.asarray(vx, float)[..., None]
    vy = np.asarray(vy, float)[..., None]
    r = np.asarray(r, float)[..., None]
    ux = vx - r * y
    uy = vy + r * x
    d = _steer(delta)
    c, s = np.cos(d), np.sin(d)
    return c * ux + s * uy, -s * ux + c * uy


def body_forces(fx, fy, delta, vp: VehicleParams):
    """Total force and yaw moment on the body ``(F_x, F_y, Gamma)`` [N, N, N m] (Eq. 33-35).

    ``fx``, ``fy`` are the tyre forces in the wheel frames, shape (..., 4).
    """
    x, y = wheel_positions(vp)
    d = _steer(delta)
    c, s = np.cos(d), np.sin(d)
    bx = c * fx - s * fy
    by = s * fx + c * fy
    gamma = (x * by - y * bx).sum(-1)  # Zhang et al., Eq. 35
    return bx.sum(-1), by.sum(-1), gamma


def measurement(fx, fy, delta, vp: VehicleParams):
    """Measurement ``y = [a_x, a_y, Gamma]`` (Eq. 33-35, 37) from the tyre forces; shape (..., 3)."""
    Fx, Fy, G = body_forces(fx, fy, delta, vp)
    return np.stack([Fx / vp.mass, Fy / vp.mass, G], axis=-1)  # Zhang et al., Eq. 33-35


def measurement_matrix(delta, vp: VehicleParams) -> np.ndarray:
    """dy/dF: the 3 x 8 matrix with ``y = D @ [fx_fl..fx_rr, fy_fl..fy_rr]`` (exact; Eq. 39-40)."""
    x, y = wheel_positions(vp)
    d = _steer(delta)
    c, s = np.cos(d), np.sin(d)
    D = np.empty(np.shape(delta) + (3, 8))
    D[..., 0, :4] = c / vp.mass
    D[..., 0, 4:] = -s / vp.mass
    D[..., 1, :4] = s / vp.mass
    D[..., 1, 4:] = c / vp.mass
    D[..., 2, :4] = x * s - y * c
    D[..., 2, 4:] = x * c + y * s
    return D


def normal_loads(ax, ay, vp: VehicleParams):
    """Quasi-static wheel loads [N] from the body accelerations a_x, a_y [m/s^2]; shape (..., 4)."""
    ax = np.asarray(ax, float)[..., None]
    ay = np.asarray(ay, float)[..., None]
    L = vp.la + vp.lb
    m = vp.mass
    static = np.array([m * G0 * vp.lb / L / 2] * 2 + [m * G0 * vp.la / L / 2] * 2)
    dlong = -m * ax * vp.h_cg / L / 2 * np.array([1, 1, -1, -1])
    share = np.array([vp.roll_share_f / vp.track_f] * 2 + [(1 - vp.roll_share_f) / vp.track_r] * 2)
    dlat = m * ay * vp.h_cg * share * np.array([-1, 1, -1, 1])
    return static + dlong + dlat


def derivatives(state, fx, fy, torque, delta, vp: VehicleParams):
    """Time derivative of the 7 states (Eq. 33-36).

    Parameters
    ----------
    state : array_like
        ``[vx, vy, r, w_fl, w_fr, w_rl, w_rr]``.
    fx, fy : array_like
        Tyre forces in the wheel frames [N], order :data:`WHEELS`.
    torque : array_like
        Net wheel torque ``T_d - T_b`` [N m] of each wheel.
    delta : float
        Front steer angle [rad].

    Returns
    -------
    ndarray
        d(state)/dt, and the measurement ``[a_x, a_y, Gamma]``.
    """
    vx, vy, r = state[0], state[1], state[2]
    ax, ay, G = measurement(fx, fy, delta, vp)
    out = np.empty(7)
    out[0] = ax + vy * r  # Zhang et al., Eq. 33
    out[1] = ay - vx * r  # Eq. 34 (ISO axes)
    out[2] = G / vp.iz  # Eq. 35
    out[3:] = (np.asarray(torque, float) - np.asarray(fx, float) * vp.wheel_radius) / vp.wheel_inertia  # Eq. 36
    return out, np.array([ax, ay, G])
