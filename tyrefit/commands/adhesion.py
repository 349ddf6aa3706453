"""``tyrefit sim adhesion [--road-mu MU] [--camber DEG] [--json OUT.json] [--report DIR]``.

The road-adhesion experiment of Zhang et al. 2024 (:mod:`tyrefit.sim.adhesion`): the true
vehicle runs on improved camber brush tyres on a road of adhesion MU with
camber DEG on the left wheels and the opposite on the right; an EKF
estimates mu per wheel from a_x, a_y and the yaw moment, once with the
improved model and once with the original camber brush model.

JSON (DESIGN): ``{"road_mu", "camber_deg", "estimates": [fl, fr, rl, rr],
"relative_error_pct": [...], "converged_s"}`` for the improved model, plus
``"model"``, ``"original_model": {same keys}`` and ``"settings"``.
``relative_error_pct`` is signed, 100 (estimate - mu) / mu; ``converged_s`` is
the time after which all four estimates stay within 2 % of mu of their
final values; ``estimates`` are the means over the last 0.3 s.

With ``--report`` the report also runs cambers 0, 3 and 6 deg on the same road
to show how the two models' errors grow with camber (the paper's Fig. 17).
"""

from __future__ import annotations

import json
import math

import numpy as np

from ..errors import ValueRangeError
from ..io.outputs import write_text
from .outputs import check_outputs
from ..io.report import Report
from ..sim import vehicle7dof as v7
from ..sim.adhesion import Manoeuvre, run_experiment

__all__ = ["run", "adhesion_report", "result_dict"]


def _check(args) -> tuple[float, float]:
    mu = float(args.road_mu)
    cam = float(args.camber)
    if not math.isfinite(mu) or not 0.05 <= mu <= 1.5:
        raise ValueRangeError(f"--road-mu {args.road_mu}: the road adhesion coefficient must be between 0.05 and "
                              "1.5 (dry asphalt ~0.8, wet ~0.3-0.5, snow ~0.2)")
    if not math.isfinite(cam) or abs(cam) > 10.0:
        raise ValueRangeError(f"--camber {args.camber} deg: the brush model's camber range is -10 to 10 deg "
                              "(the paper uses 0, 3 and 6 deg)")
    return mu, cam


def result_dict(road_mu: float, camber_deg: float, results: dict, manoeuvre, truth) -> dict:
    """The ``--json`` document of one run."""
    imp, orig = results["improved"], results.get("original")
    d = {"road_mu": float(road_mu), "camber_deg": float(camber_deg),
         "estimates": [float(x) for x in imp.estimates],
         "relative_error_pct": [float(x) for x in imp.relative_error_pct],
         "converged_s": float(imp.converged_s),
         "model": imp.model,
         "wheels": ["fl", "fr", "rl", "rr"],
         "camber_wheels_deg": [round(float(x), 6) for x in np.rad2deg(truth.camber)]}
    if orig is not None:
        d["original_model"] = orig.as_dict()
    d["settings"] = {"duration_s": manoeuvre.duration, "initial_speed_mps": manoeuvre.speed,
                     "steer_amplitude_deg": float(np.rad2deg(manoeuvre.steer_amplitude)),
                     "brake_phi": manoeuvre.brake_phi,
                     "noise_ax_ay_gamma": list(truth.noise), "sample_rate_hz": float(1 / np.diff(truth.t[:2])[0]),
                     "truth_model": truth.tyre}
    return d


def adhesion_report(road_mu, camber_deg, truth, results, sweep=None):
    """HTML report: convergence plots of both models, the truth's traces, the camber sweep."""
    from matplotlib.figure import Figure

    r = Report(f"Road adhesion estimation: mu = {road_mu:g}, camber {camber_deg:g} deg",
               subtitle="Zhang et al. 2024, §4: 7-DOF vehicle, camber brush tyres, extended Kalman "
                        "filter on a_x, a_y and the yaw moment.")
    r.p(f"The true vehicle runs on the {truth.tyre} model with camber "
        f"{camber_deg:g} deg on the left wheels and {-camber_deg:g} deg on the right (ISO-W inclination), a "
        "sinusoidal steer and slip-controlled braking with per-wheel slip cycling, so that every tyre works in its "
        "partly sliding range, where the forces depend on mu. The EKF treats the four mu as random walks and "
        "updates them from the noisy measurements; it knows the vehicle states. It runs once with the improved "
        "model (2N = 12: coarser than the truth) and once with the original camber brush model calibrated on "
        "the same tyre's zero-camber forces.", cls="note")
    rows = []
    for key, res in results.items():
        rows.append({"model": res.model, **{f"mu {w}": e for w, e in zip(v7.WHEELS, res.estimates)},
                     "max |error| %": res.max_abs_error_pct, "converged [s]": res.converged_s})
    r.h2("Estimates").table(rows)
    fig = Figure(figsize=(6 * len(results), 4))
    axs = fig.subplots(1, len(results), sharey=True)
    for ax, res in zip(np.atleast_1d(axs), results.values()):
        res.plot(ax)
    r.figure(fig, "Estimated adhesion coefficient of each wheel against time (the paper's Fig. 14-16); "
             "dotted: convergence time.")
    if sweep:
        r.h2("Error against camber (the paper's Fig. 17)")
        cams = sorted(sweep)
        fig = Figure(figsize=(6.5, 4))
        ax = fig.subplots()
        table = []
        for key, style, color in (("improved", "o-", "C0"), ("original", "s--", "C3")):
            mean = [float(np.mean(np.abs(sweep[c][key].relative_error_pct))) for c in cams]
            mx = [sweep[c][key].max_abs_error_pct for c in cams]
            ax.plot(cams, mean, style, color=color, label=f"{key}: mean |error|")
            ax.plot(cams, mx, style, color=color, alpha=0.35, label=f"{key}: max |error|")
            for c, m1, m2 in zip(cams, mean, mx):
                table.append({"model": key, "camber [deg]": c, "mean |error| %": m1, "max |error| %": m2})
        ax.set_xlabel("camber [deg]")
        ax.set_ylabel("relative error of mu [%]")
        ax.legend(fontsize=8)
        r.figure(fig, f"Relative error of the estimates on the mu = {road_mu:g} road against camber.")
        r.table(table)
    t = truth.t
    fig = Figure(figsize=(11, 7))
    axs = fig.subplots(2, 2)
    axs[0, 0].plot(t, truth.state[:, 0], label="vx [m/s]")
    axs[0, 0].plot(t, truth.state[:, 1], label="vy [m/s]")
    axs[0, 0].plot(t, np.rad2deg(truth.delta), label="steer [deg]")
    axs[0, 0].legend(fontsize=8)
    axs[0, 0].set_xlabel("time [s]")
    for i, w in enumerate(v7.WHEELS):
        axs[0, 1].plot(t, truth.fx[:, i] / truth.fz[:, i], label=f"Fx/Fz {w}")
        axs[1, 0].plot(t, truth.fy[:, i] / truth.fz[:, i], label=f"Fy/Fz {w}")
    for ax, lab in ((axs[0, 1], "Fx/Fz [-]"), (axs[1, 0], "Fy/Fz [-]")):
        ax.set_xlabel("time [s]")
        ax.set_ylabel(lab)
        ax.legend(fontsize=7, ncol=2)
    for j, lab in enumerate(("a_x [m/s2]", "a_y [m/s2]", "yaw moment [kN m]")):
        sc = 1e-3 if j == 2 else 1.0
        axs[1, 1].plot(t, truth.y_meas[:, j] * sc, lw=0.6, label=lab)
    axs[1, 1].set_xlabel("time [s]")
    axs[1, 1].legend(fontsize=8)
    r.figure(fig, "The true run: speeds and steer; tyre force coefficients; the noisy measurements.")
    return r


def run(args) -> int:
    """Entry point of ``tyrefit sim adhesion``."""
    mu, cam = _check(args)
    check_outputs(args)
    man = Manoeuvre()
    truth, results = run_experiment(mu, cam, manoeuvre=man)
    d = result_dict(mu, cam, results, man, truth)
    for key, res in results.items():
        print(f"{res.model:40s} estimates " + " ".join(f"{x:.4f}" for x in res.estimates)
              + "   error % " + " ".join(f"{x:+.2f}" for x in res.relative_error_pct)
              + f"   converged {res.converged_s:.2f} s")
    if getattr(args, "json", None):
        write_text(args.json, json.dumps(d, indent=2) + "\n", force=args.force)
        print(f"wrote {args.json}")
    if getattr(args, "report", None):
        sweep = {}
        for c in sorted({0.0, 3.0, 6.0, abs(cam)}):
            sweep[c] = results if c == abs(cam) and cam >= 0 else run_experiment(mu, c, manoeuvre=man)[1]
        path = adhesion_report(mu, cam, truth, results, sweep).save(args.report, force=args.force)
        print(f"wrote {path}")
    return 0
