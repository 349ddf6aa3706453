"""Seed 000 scenario suite: the vectorised fixed-step simulator against one-run-at-a-time and solve_ivp.

Inputs: the bundled tyres of ``tyrefit sim`` (``data/sim/*.tir``, PAC89 fits of
synthetic data) and the default vehicle.  Measurements, each against a
baseline measured in the same run:

* **whole suite**: emergency braking, straight path and curved path, base and
  low-wear vehicle, conditions 0.5 and 1.0 x 30, 60, 120 km/h (36 simulated
  runs, the six runs of each vehicle in one NumPy batch) vs the same suite run
  one condition-speed pair at a time (batch of one): what vectorising over the
  runs buys;
* **per scenario** (braking, straight, curved): the same comparison;
* **integrator**: 3 s of open-loop braking (fixed brake torques, about
  5 m/s^2) with a 0.5 Hz steering sine from 60 km/h, where the wheel spin
  stiffens as the speed falls, with the split explicit / linearly implicit
  fixed-step integrator (2 ms) vs ``scipy.integrate.solve_ivp`` (LSODA, rtol
  1e-8) on the same ``VehicleModel.update``; the state differences are recorded.

``python -m benchmarks.bench_sim`` prints the dict.
"""

from __future__ import annotations

import json
import time

import numpy as np

try:
    from . import best_of, measurement
except ImportError:  # pragma: no cover - run as a script
    from benchmarks import best_of, measurement

from tyrefit.sim.scenarios import SCENARIOS, SimSetup


def _timed_suite(setups) -> tuple[dict, dict]:
    """Run every scenario for each setup; (seconds per scenario summed over setups, results)."""
    seconds = {name: 0.0 for name in SCENARIOS}
    results = {name: [] for name in SCENARIOS}
    for setup in setups:
        for name, fn in SCENARIOS.items():
            t0 = time.perf_counter()
            results[name].append(fn(setup))
            seconds[name] += time.perf_counter() - t0
    return seconds, results


def _integrator_case():
    """3 s of open-loop braking with a steering sine from 60 km/h: the wheels stiffen as the speed falls."""
    from scipy.integrate import solve_ivp

    from tyrefit.sim.path import PathGeometry
    from tyrefit.sim.vehicle import VehicleModel

    s = SimSetup.default()
    p = s.vehicle
    v0 = 60 / 3.6
    model = VehicleModel(p, s.soft_front, s.soft_rear, [1.0], PathGeometry([[5000.0]], [[0.0]]))
    x0 = model.rolling_state(np.array([v0]))
    brake = -0.25 * p.mass * 5.0 * p.wheel_radius          # about 5 m/s^2 shared by both axles

    def u_of(t):
        return np.array([[0.04 * np.sin(2 * np.pi * 0.5 * t)], [brake], [brake]])

    t_end, dt = 3.0, 2e-3

    def fixed():
        x = x0.copy()
        for i in range(int(round(t_end / dt))):
            x, _, _ = model.step(i * dt, x, u_of(i * dt), dt)
        return x[:, 0]

    def ivp():
        sol = solve_ivp(lambda t, y: model.update(t, y[:, None], u_of(t))[:, 0], (0.0, t_end), x0[:, 0],
                        method="LSODA", rtol=1e-8, atol=1e-9)
        return sol.y[:, -1], sol.nfev

    return fixed, ivp


def run() -> dict:
    setup = SimSetup.default()
    one_setups = [SimSetup(front=setup.front, rear=setup.rear, conditions=(c,), speeds_kmh=(v,))
                  for c in setup.conditions for v in setup.speeds_kmh]
    vec, res = _timed_suite([setup])
    one, ones = _timed_suite(one_setups)
    res = {k: v[0] for k, v in res.items()}
    fixed, ivp = _integrator_case()
    t_fixed, x_fixed = best_of(fixed, repeat=2)
    t_ivp, (x_ivp, nfev) = best_of(ivp, repeat=1)
    rows = res["braking"].rows
    paths = res["straight"].rows + res["curved"].rows
    same = all(np.isclose(a["reduction_pct"], b.rows[0]["reduction_pct"], rtol=1e-6)
               for a, b in zip(res["straight"].rows, ones["straight"]))
    meas = [measurement("seed 000 scenario suite, 36 runs (vectorised batches of 6)", sum(vec.values()),
                        "same suite, one condition-speed pair at a time", sum(one.values()), runs=36,
                        note="braking + straight + curved, base and low-wear vehicles")]
    for name in SCENARIOS:
        meas.append(measurement(f"{name}: 12 runs vectorised", vec[name], f"{name}: 12 runs one pair at a time",
                                one[name]))
    diff = np.abs(x_fixed - x_ivp)
    meas.append(measurement("3 s open-loop braking and steering, fixed-step split integrator (2 ms)", t_fixed,
                            "scipy solve_ivp LSODA, rtol 1e-8", t_ivp,
                            max_speed_difference_mps=float(np.max(diff[[3, 4]])),
                            final_distance_difference_m=float(diff[0]), lsoda_evaluations=int(nfev)))
    info = {
        "suite_seconds": sum(vec.values()),
        "stopping_distance_m": [r["stopping_distance_m"] for r in rows],
        "reduction_pct": [r["reduction_pct"] for r in paths],
        "max_path_difference_m": max(r["max_path_difference_m"] for r in paths),
        "one_at_a_time_gives_the_same_reductions": bool(same),
    }
    return {"measurements": meas, "info": info}


if __name__ == "__main__":
    print(json.dumps(run(), indent=2, default=float))
