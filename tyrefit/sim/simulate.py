"""The closed loop: driver -> allocator -> torque controller -> vehicle, at a fixed step.

One call simulates a batch of B runs (conditions and speeds) of one vehicle
together, so each time step is a handful of NumPy operations on arrays of
length B; there are no per-run Python loops and no pandas in the loop.
"""

from __future__ import annotations

import numpy as np

from .emission import QuadraticEmission
from .vehicle import INPUTS, OUTPUTS, STATES, SimResult, VehicleModel

__all__ = ["simulate"]

_EXTRA = ("steer_driver", "force_demand", "force_ref_f", "force_ref_r", "steer_correction",
          "emission_f", "emission_r")


def simulate(model: VehicleModel, x0: np.ndarray, *, driver, allocator, controller,
             emission_front: QuadraticEmission, emission_rear: QuadraticEmission,
             dt: float, t_end, stop=None, meta: dict | None = None) -> SimResult:
    """Run the closed loop from ``x0`` until every member stops or reaches its ``t_end``.

    Parameters
    ----------
    model : VehicleModel
    x0 : ndarray, shape (8, B)
        Initial state (:data:`~tyrefit.sim.vehicle.STATES`).
    driver : callable
        ``driver(i, t, x) -> (steer [rad], force_demand [N])``.
    allocator : callable
        ``allocator(i, t, x, steer, force_demand) -> (F_ref_f, F_ref_r, steer_correction)``.
    controller : callable
        ``controller(x, steer, F_ref_f, F_ref_r, vdot) -> (torque_f, torque_r)``.
    emission_front, emission_rear : QuadraticEmission
        Axle emission laws [#/s] of the front and rear axle.
    dt : float
        Fixed step [s].
    t_end : float or array_like, shape (B,)
        End time per member [s].
    stop : callable, optional
        ``stop(t, x) -> bool array``: members for which it is true stop (their
        state is frozen from then on).

    Returns
    -------
    SimResult
    """
    b = x0.shape[1]
    t_end = np.broadcast_to(np.asarray(t_end, float), (b,))
    n_steps = int(np.ceil(t_end.max() / dt)) + 1
    names = STATES + INPUTS + OUTPUTS + _EXTRA
    rec = {k: np.zeros((n_steps + 1, b)) for k in names}
    t_grid = np.arange(n_steps + 1) * dt
    end = np.full(b, n_steps, dtype=int)
    done = np.zeros(b, dtype=bool)
    x = np.array(x0, dtype=float, copy=True)
    vdot = np.zeros(b)
    u = np.zeros((len(INPUTS), b))
    last = n_steps
    for i in range(n_steps + 1):
        t = t_grid[i]
        steer_d, demand = driver(i, t, x)
        f_ref_f, f_ref_r, d_steer = allocator(i, t, x, steer_d, demand)
        steer = steer_d + d_steer
        tf, tr = controller(x, steer, f_ref_f, f_ref_r, vdot)
        u[0], u[1], u[2] = steer, tf, tr
        xn, dx, out = model.step(t, x, u, dt)
        for k, name in enumerate(STATES):
            rec[name][i] = x[k]
        for k, name in enumerate(INPUTS):
            rec[name][i] = u[k]
        for name in OUTPUTS:
            rec[name][i] = out[name]
        rec["steer_driver"][i] = steer_d
        rec["force_demand"][i] = demand
        rec["force_ref_f"][i] = f_ref_f
        rec["force_ref_r"][i] = f_ref_r
        rec["steer_correction"][i] = d_steer
        rec["emission_f"][i] = emission_front.rate(out["fx_f"])
        rec["emission_r"][i] = emission_rear.rate(out["fx_r"])
        vdot = dx[3]
        finished = (t + 0.5 * dt >= t_end)
        if stop is not None:
            finished |= np.asarray(stop(t, x), bool)
        newly = finished & ~done
        end[newly] = i
        done |= finished
        if done.all():
            last = i
            break
        x = np.where(done[None, :], x, xn)
    rec = {k: v[:last + 1] for k, v in rec.items()}
    # frozen members keep their last value after they stop
    for name, v in rec.items():
        for j in range(b):
            if end[j] < last:
                v[end[j] + 1:, j] = v[end[j], j]
    return SimResult(t=t_grid[:last + 1], channels=rec, end_index=end, meta=dict(meta or {}))
