"""MF 6.1 fit of a TTC-size cornering + drive/brake pair: today's fit vs the fit of the branch point vs plain scipy.

Data (synthetic, nothing here is a measurement): :mod:`tyrefit.synthetic.ttc_drivebrake`
records of MFeval's published MF 6.1 example tyre in the FSAE TTC ``.dat``
layout (SAE signs, warm-up, relaxation lag, drift, noise): a cornering record
and a drive/brake record (slip-ratio sweeps at 0, -3, -6 deg) at 5 loads x 3
pressures x 3 cambers, 50 Hz, about 136 000 samples together (the size of the
real TTC pair of issue 23).

Measured in one run (one thread of BLAS, :func:`tyrefit.fitting._blas.single_threaded_blas`), wall and CPU
seconds of each, and the load average (the machine is shared; CPU seconds are the comparable figure):

* ``tyrefit fit A.dat B.dat --model mf61`` end to end in-process: reading and
  segmenting both files, gathering, the staged fit (Fx0 -> Fy0 -> Mz0 ->
  combined Fx, Fy, Mz -> joint polish -> Mx), statistics.  Goal <= 60 s wall on
  the 2-core machine, <= 25 s CPU.
* the same fit with :data:`tyrefit.fitting.mf_parts.FAST` = False: the
  evaluation of the branch point (the coefficient mapping rebuilt at every
  evaluation, every part of the model for every forward-difference column,
  forward differences for Mx and Mz), the "today's fit" of issue 23 item 8.  Its
  RMSEs are recorded beside the new fit's.
* plain ``scipy.optimize.least_squares`` (``trf``, 2-point
  finite-difference Jacobian, no scaling) on the *same* residual - every
  channel of every sweep at once, each point (model - data)/Fz (moments /(Fz R0))
  weighted 1/sqrt(n_sweep), the model evaluated by
  :func:`tyrefit.models.mf61.forces` - over the same coefficients, from the
  same start (the fitter's Eq. 2-4 estimates and typical combined-slip
  values).  It is stopped when its cost reaches the staged fit's cost on that
  residual (+1 %) - "equal RMSE" - or when its time budget (4 x the staged
  fit's time, at least 60 s; 600 s with ``TYREFIT_BENCH_FULL=1``; any number
  of seconds with ``TYREFIT_BENCH_FD_BUDGET``; 0 skips it) runs out, or when it
  converges on its own tolerances above that cost; then the ratio is a lower
  bound and the row says which stop it was and the best cost reached.

Measured on the shared 2-core machine (2026-11-27, commit c3e7270, load average 3.9-4.8 from three other
workers): the fit 15.3 s CPU / 30.1 s wall, the branch point's 27.8 s CPU / 55.5 s wall (ratio 0.55 in CPU,
0.54 in wall); RMSEs equal to 3e-8 relative (fx 150.67 N, fy 74.520 N, mz 3.1331 N*m, mx 1.9545 N*m).  Plain
scipy stopped by its 127 s budget at 1.78 x the staged fit's cost (67.9 s CPU): >= 4.4 x in CPU.  What is left
(process-time profile): the trust-region SVDs of SciPy's ``trf`` (~5 s CPU, 4 of them the joint polish's
54 000 x 100 Jacobian), the variable projection's grid of the Mx stage, the statistics' condition table.

With the physical-validity contract (2026-11-27, after the commit "Mx/My variable projection"): the
published pair 17.3 s CPU / 24.0 s wall against FAST = False 27.0 / 48.9 (load 2-3), RMSE fx 151.3, fy 85.4
(the contract holds RHY1/RHY2 at 0; that tyre's G_yk reaches 1.03), mz 3.22, mx 2.01; plain scipy >= 4.1 x
in CPU.  ``TYREFIT_BENCH_PAIR=field`` (tyrefit.synthetic.ttc_field, 136 060 samples): 24.3 s CPU / 24.4 s wall
(load 1.5) against FAST = False 37.0 / 37.2; plain scipy >= 3.2 x in CPU.  The code before this session fitted
the field pair in 81.9 s CPU (in process, same data, measured beside it; RMSE fx 45.64, fy 51.30, mz 12.78,
mx 3.35 against 45.69, 52.94, 12.78, 3.36 now) and wrote a file that breaks the contract six times.

``python -m benchmarks.bench_fit_mf`` prints the dict.
"""

from __future__ import annotations

import math
import os
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

from . import full, measurement


#: environment variable: the baseline's time budget [s] (default 4 x the staged fit, >= 60 s; 600 s with --full)
BUDGET_ENV = "TYREFIT_BENCH_FD_BUDGET"


class _Reached(Exception):
    pass


#: environment variable: 'field' fits tyrefit.synthetic.ttc_field's FSAE pair (136k samples, physics beyond MF 6.1,
#: sweeps short of the Fx peak) instead of the published MF 6.1 tyre's records
PAIR_ENV = "TYREFIT_BENCH_PAIR"


def _write_pair(folder: Path, rate: float = 50.0) -> list[Path]:
    """The 136k-sample pair: 5 loads x 3 pressures x 3 cambers; drive/brake at 0, -3, -6 deg."""
    from tyrefit.synthetic import ttc_drivebrake as gen

    if os.environ.get(PAIR_ENV) == "field":
        from tyrefit.synthetic import ttc_field

        c, d = ttc_field.make_pair(scale="full")
        paths = ttc_field.write_pair(folder, scale="full")
        return [(paths[0], len(c)), (paths[1], len(d))]

    files = []
    for kind in ("cornering", "drivebrake"):
        df = gen.make_record(kind, pressures=[220e3, 260e3, 300e3], cambers_deg=[0.0, 2.0, 4.0], rate=rate,
                             sweep_seconds=9.0 if kind == "drivebrake" else 16.0)
        f = folder / f"{kind}.dat"
        f.write_text(gen.format_record(df, kind))
        files.append((f, len(df)))
    return files


def _timed_fit(paths, fast: bool):
    """(wall s, CPU s, load average before, result) of the in-process ``fit`` with or without the fast path."""
    from tyrefit.fitting import mf_parts
    from tyrefit.fitting._blas import single_threaded_blas
    from tyrefit.fitting.mf import fit_mf, prepare_mf_data
    from tyrefit.io.readers import read_data

    load = os.getloadavg() if hasattr(os, "getloadavg") else None
    saved = mf_parts.FAST
    mf_parts.FAST = fast
    try:
        with single_threaded_blas():
            t0, c0 = time.perf_counter(), time.process_time()
            res = fit_mf(prepare_mf_data([read_data(f, convention="sae") for f in paths]))
            return time.perf_counter() - t0, time.process_time() - c0, load, res
    finally:
        mf_parts.FAST = saved


def _joint(data, p_fixed, names):
    """The joint residual of every channel and sweep (the staged fit's stage residuals, stacked)."""
    from tyrefit.models import mf61

    df = data.df
    kind = df["kind"].to_numpy()
    kap = np.where(kind == "lateral", 0.0, df["slip_ratio"].to_numpy(float))
    alp = np.where(kind == "longitudinal", 0.0, df["slip_angle"].to_numpy(float))
    fz = df["fz"].to_numpy(float)
    gam, pr, v = (df[c].to_numpy(float) for c in ("camber", "pressure", "speed"))
    pr = np.where(np.isfinite(pr), pr, p_fixed["NOMPRES"])
    v = np.where(np.isfinite(v), v, p_fixed.get("LONGVL", 16.7))
    n = df.groupby("run")["run"].transform("size").to_numpy(float)
    r0 = p_fixed["UNLOADED_RADIUS"]
    parts = []
    for c, scale in (("fx", 1.0), ("fy", 1.0), ("mz", r0), ("mx", r0), ("my", r0)):
        y = df[c].to_numpy(float)
        ok = np.isfinite(y)
        if ok.sum() >= 10:
            parts.append((c, ok, y[ok], 1.0 / (np.sqrt(n[ok]) * fz[ok] * scale)))

    def residual(theta):
        p = dict(p_fixed)
        p.update(zip(names, theta))
        out = mf61.forces(p, fz, kap, alp, gam, pr, v)
        r = np.concatenate([w * (np.asarray(out[c])[ok] - y) for c, ok, y, w in parts])
        return np.where(np.isfinite(r), r, 1e3)

    return residual


def run() -> dict:
    from tyrefit.fitting._blas import single_threaded_blas

    out, info = [], {}
    with tempfile.TemporaryDirectory() as tmp:
        files = _write_pair(Path(tmp))
        samples = sum(n for _, n in files)
        paths = [f for f, _ in files]
        # today's fit and the branch point's, same files, same process, one after the other
        t_old, cpu_old, load_old, res_old = _timed_fit(paths, fast=False)
        t_fit, cpu_fit, load_fit, res = _timed_fit(paths, fast=True)
    rm_old = {c: s["rmse"] for c, s in res_old.stats.items()}
    rm_new = {c: s["rmse"] for c, s in res.stats.items()}
    drift = {c: rm_new[c] / rm_old[c] - 1.0 for c in rm_new if c in rm_old and rm_old[c] > 0}
    out.append(measurement(
        f"fit --model mf61, TTC-size cornering + drive/brake pair, {samples} samples (read, segment, staged fit, "
        "statistics): coefficient mapping built once per stage, fixed parts cached, Jacobian columns by parts, "
        "analytic Mx and Mz Jacobians", t_fit,
        "the same fit at the branch point (tyrefit.fitting.mf_parts.FAST = False: mapping per evaluation, whole "
        "model per forward-difference column)", t_old,
        samples=samples, fit_cpu_seconds=cpu_fit, baseline_cpu_seconds=cpu_old,
        ratio_cpu=cpu_fit / cpu_old if cpu_old > 0 else math.nan, load_average_before_baseline=load_old,
        load_average_before_fit=load_fit, rmse=rm_new, baseline_rmse=rm_old, rmse_relative_change=drift,
        goal_seconds=60.0, goal_cpu_seconds=25.0,
        stages={k: round(f.seconds, 2) for k, f in res.stages.items()},
        baseline_stages={k: round(f.seconds, 2) for k, f in res_old.stages.items()}))
    info.update(samples=samples, fit_seconds=t_fit, fit_cpu_seconds=cpu_fit, branch_point_seconds=t_old,
                branch_point_cpu_seconds=cpu_old, rmse=rm_new, branch_point_rmse=rm_old)
    budget_env = os.environ.get(BUDGET_ENV)
    if budget_env is not None and float(budget_env) <= 0:
        return {"measurements": out, "info": info}
    data = res.data
    names = list(res.fitted)
    from tyrefit.models import mf61

    # the fitter's own start: neutral set, the data's nominal conditions, the Eq. 2-4 estimates and the
    # typical combined-slip values of each stage, and the non-zero starts that give RVY*/QSX* a gradient
    start = mf61.neutral()
    start.update({k: res.params[k] for k in ("FNOMIN", "NOMPRES", "INFLPRES", "LONGVL", "UNLOADED_RADIUS")
                  if k in res.params})
    for f in res.stages.values():
        start.update(f.initial)
    start.update({k: v for k, v in (("RVY1", 0.02), ("RVY5", 1.9), ("RVY6", 10.0), ("QSX4", 0.5), ("QSX5", 0.3),
                                    ("QSX6", 1.0), ("QSX7", 0.5), ("QSX8", 1.0), ("QSX9", 0.5), ("QSX11", 1.0))
                  if k in names})
    residual = _joint(data, start, names)
    target = float(np.sum(residual(np.array([res.params[k] for k in names])) ** 2))
    budget = float(budget_env or (600.0 if full() else max(60.0, 4.0 * t_fit)))
    track = {"best": math.inf, "t_reach": None, "cpu_reach": None, "calls": 0}
    load_fd = os.getloadavg() if hasattr(os, "getloadavg") else None
    t_start, c_start = time.perf_counter(), time.process_time()

    def watched(theta):
        r = residual(theta)
        track["calls"] += 1
        cost = float(np.sum(r * r))
        track["best"] = min(track["best"], cost)
        if cost <= 1.01 * target and track["t_reach"] is None:
            track["t_reach"] = time.perf_counter() - t_start
            track["cpu_reach"] = time.process_time() - c_start
            raise _Reached
        if time.perf_counter() - t_start > budget:
            raise _Reached
        return r

    th0 = np.array([start[k] for k in names], float)
    stop = "budget"
    with single_threaded_blas():
        try:
            sol = least_squares(watched, th0, jac="2-point", method="trf")
            stop = f"converged ({sol.message})"  # returned on its own tolerances without reaching the cost
        except _Reached:
            pass
    t_fd = track["t_reach"] if track["t_reach"] is not None else time.perf_counter() - t_start
    cpu_fd = track["cpu_reach"] if track["cpu_reach"] is not None else time.process_time() - c_start
    reached = track["t_reach"] is not None
    load_end = os.getloadavg() if hasattr(os, "getloadavg") else None
    rm = {c: s["rmse"] for c, s in res.stats.items()}
    out.append(measurement(
        f"fit --model mf61, TTC-style cornering + drive/brake pair, {samples} samples, {len(names)} coefficients "
        "(read, segment, staged fit, statistics)", t_fit,
        "scipy least_squares, 2-point FD Jacobian, same joint residual/model/start, until equal cost"
        + ("" if reached else f" (NOT reached: {'time budget' if stop == 'budget' else 'solver ' + stop} after "
                              f"{t_fd:.0f} s, best cost {track['best'] / target:.2f} x the staged fit's: ratio is a "
                              "lower bound)"), t_fd,
        samples=samples, points_fitted=int(len(data.df)), coefficients=len(names), rmse=rm,
        joint_cost=target, baseline_best_cost=track["best"], baseline_reached=reached,
        baseline_residual_calls=track["calls"], baseline_budget_seconds=budget,
        baseline_stop="reached" if reached else stop, speedup=t_fd / t_fit if t_fit > 0 else math.nan,
        fit_cpu_seconds=cpu_fit, baseline_cpu_seconds=cpu_fd,
        speedup_cpu=cpu_fd / cpu_fit if cpu_fit > 0 else math.nan, load_average_before_fit=load_fit,
        load_average_before_baseline=load_fd, load_average_end=load_end, goal_seconds=60.0, stages={k: round(f.seconds, 2) for k, f in res.stages.items()}))
    info.update(samples=samples, fit_seconds=t_fit, fit_cpu_seconds=cpu_fit, baseline_seconds=t_fd,
                baseline_cpu_seconds=cpu_fd, baseline_reached=reached, load_average_before_fit=load_fit,
                load_average_end=load_end)
    return {"measurements": out, "info": info}


if __name__ == "__main__":  # pragma: no cover
    import json

    print(json.dumps(run(), indent=2, default=float))
