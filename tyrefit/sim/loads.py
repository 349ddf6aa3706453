"""Wheel loads with load transfer and aerodynamic load (quasi-static).

Pure functions of a :class:`~tyrefit.sim.vehicle_file.VehicleSpec` and the body's
accelerations and speed; arrays broadcast.  Rigid body, quasi-static (no pitch
or roll dynamics), aerodynamic forces acting through the centre of gravity::

    F_z,f = m g l_r / L - m a_x h / L + s_f C_l v^2                (longitudinal transfer)
    F_z,r = m g l_f / L + m a_x h / L + (1 - s_f) C_l v^2
    dF_z,f = q_f m a_y h / t,   dF_z,r = (1 - q_f) m a_y h / t       (lateral transfer, per axle)
    F_z,fl = F_z,f / 2 - dF_z,f,   F_z,fr = F_z,f / 2 + dF_z,f     (a_y > 0: left turn, right wheels outside)

with ``a_x`` the acceleration the tyres' longitudinal forces give the body
(sum F_x / m; braking negative), ``a_y`` the lateral acceleration (ISO: positive
to the left), C_l = rho Cl*A / 2, s_f the downforce's front share and q_f the front
share of the lateral transfer (the roll-stiffness distribution; by default the
static front weight share).  Wheels whose load would fall below zero have
lifted (:func:`wheel_loads` returns the negative value; callers clip it and
treat the vehicle as at its roll-over limit).
"""

from __future__ import annotations

import numpy as np

from ..nomenclature import G0

__all__ = ["WHEELS", "axle_loads", "wheel_loads", "longitudinal_transfer", "lateral_transfer"]

#: wheel order of :func:`wheel_loads`
WHEELS = ("fl", "fr", "rl", "rr")


def longitudinal_transfer(spec, ax):
    """Load moved from the front to the rear axle [N] at longitudinal acceleration ``ax`` [m/s^2]: m a_x h / L."""
    return spec.mass * np.asarray(ax, float) * spec.cg_height / spec.wheelbase


def lateral_transfer(spec, ay):
    """(front, rear) load moved from the inner to the outer wheel [N] at lateral acceleration ``ay`` [m/s^2]."""
    total = spec.mass * np.asarray(ay, float) * spec.cg_height / spec.track
    q = spec.roll_share_front
    return q * total, (1.0 - q) * total


def axle_loads(spec, ax=0.0, speed=0.0, g: float = G0):
    """(front, rear) axle loads [N] with longitudinal transfer and downforce."""
    v2 = np.asarray(speed, float) ** 2
    down = spec.downforce_coefficient * v2
    dx = longitudinal_transfer(spec, ax)
    w = spec.mass * g
    front = w * spec.lr / spec.wheelbase - dx + spec.downforce_share_front * down
    rear = w * spec.lf / spec.wheelbase + dx + (1.0 - spec.downforce_share_front) * down
    return front, rear


def wheel_loads(spec, ax=0.0, ay=0.0, speed=0.0, g: float = G0) -> dict:
    """Loads of the four wheels [N]: ``{'fl', 'fr', 'rl', 'rr'}`` (may be negative: a lifted wheel)."""
    front, rear = axle_loads(spec, ax, speed, g)
    dyf, dyr = lateral_transfer(spec, ay)
    return {"fl": 0.5 * front - dyf, "fr": 0.5 * front + dyf, "rl": 0.5 * rear - dyr, "rr": 0.5 * rear + dyr}
