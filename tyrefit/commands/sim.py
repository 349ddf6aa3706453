"""``tyrefit sim braking|straight|curved [--front F.tir --rear R.tir] [--json OUT.json] [--report DIR]``.

The scenarios of Pham et al. 2025 (:mod:`tyrefit.sim.scenarios`) for the base vehicle
(the rear, soft tyre on both axles) and the low-wear vehicle (hard front,
soft rear, wear-aware allocator), at conditions 0.5 and 1.0 and 30, 60 and
120 km/h.  Without ``--front``/``--rear`` the bundled tyres of ``data/sim``
are used (PAC89 fits of synthetic data).

JSON (DESIGN): ``{"rows": [...]}`` with, for ``braking``, ``condition``,
``initial_speed_kmh``, ``vehicle`` ('base' | 'low_wear'),
``stopping_distance_m``, ``max_deceleration_mps2``; for ``straight`` and
``curved``, ``condition``, ``speed_kmh``, ``emission_base``,
``emission_low_wear``, ``reduction_pct``, ``max_path_difference_m``,
``max_speed_difference_pct``.  Extra top-level keys: ``scenario``,
``setup`` (vehicle, tyres, k, emission law, limits) and ``details`` (the
paper's values, comfort and tracking figures per run).

``--report DIR`` writes ``DIR/index.html`` with the paper's panels and the
runs' traces as CSV files beside it.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from ..errors import DataError
from ..io.outputs import check_output, staged_dir, write_text
from ..io.report import Report
from ..sim.api import SCENARIOS, simulate
from ..sim.envelope import envelope_figure
from ..sim.plots import (braking_figure, braking_turn_figure, ramp_figure, scenario_figure, step_steer_figure,
                         traces_frame)
from ..sim.scenarios import SimSetup
from ..sim.tyres import default_tyres, load_tyre
from ..cli import add_scenario_parsers  # noqa: F401  (public here too; the parsers live with the command line's)

__all__ = ["run", "sim_report", "ramp_report", "step_steer_report", "braking_turn_report", "jsonable",
           "add_scenario_parsers"]

_TITLES = {
    "braking": "Emergency braking (Pham et al. 2025, Table 3)",
    "straight": "Straight path: accelerate, then brake (Pham et al. 2025, Table 4, Figs. 7-9)",
    "curved": "Curved path: straight, arc, straight (Pham et al. 2025, Table 5, Figs. 10-12)",
}


def jsonable(x):
    """Plain JSON types (NaN and inf become null)."""
    if isinstance(x, dict):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, (float, np.floating)):
        v = float(x)
        return v if math.isfinite(v) else None
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, np.ndarray):
        return jsonable(x.tolist())
    return x


def _setup(args):
    allow = getattr(args, "allow_unphysical", False)
    front = load_tyre(args.front, allow_unphysical=allow) if getattr(args, "front", None) else None
    rear = load_tyre(args.rear, allow_unphysical=allow) if getattr(args, "rear", None) else None
    if front is None or rear is None:
        f0, r0 = default_tyres()
        front = front or f0
        rear = rear or r0
    return SimSetup(front=front, rear=rear)


def _summary(res) -> str:
    lines = [_TITLES[res.scenario], f"  k = {res.setup['k']:.4f} (ideal reduction "
             f"{res.setup['ideal_reduction_pct']:.1f} %), front {res.setup['front_tyre']!r}, "
             f"rear {res.setup['rear_tyre']!r}"]
    if res.scenario == "braking":
        lines.append(f"  {'eta':>4} {'km/h':>5} {'vehicle':>9} {'stop [m]':>9} {'paper':>6} {'decel':>7} {'paper':>6}")
        for r, d in zip(res.rows, res.details):
            lines.append(f"  {r['condition']:4.1f} {r['initial_speed_kmh']:5.0f} {r['vehicle']:>9} "
                         f"{r['stopping_distance_m']:9.2f} {d['paper_stopping_distance_m']:6.1f} "
                         f"{r['max_deceleration_mps2']:7.2f} {d['paper_max_deceleration_mps2']:6.1f}")
    else:
        lines.append(f"  {'eta':>4} {'km/h':>5} {'reduction %':>12} {'paper %':>8} {'path diff [m]':>14} "
                     f"{'speed diff %':>13}")
        for r, d in zip(res.rows, res.details):
            lines.append(f"  {r['condition']:4.1f} {r['speed_kmh']:5.0f} {r['reduction_pct']:12.1f} "
                         f"{d['paper_reduction_pct']:8.0f} {r['max_path_difference_m']:14.5f} "
                         f"{r['max_speed_difference_pct']:13.4f}")
    return "\n".join(lines)


def sim_report(res):
    """HTML :class:`~tyrefit.io.report.Report` of a scenario result (figures embedded)."""
    st = res.setup
    r = Report(_TITLES[res.scenario],
               subtitle="Pham, Hamedmoghadam, Shorten (2025): low-wear hard tyres on the front axle, soft "
                        "tyres at the rear, and an allocator that makes the vehicle drive like the all-soft one.")
    r.h2("Set-up")
    v = st["vehicle"]
    r.table([
        {"item": "front tyre (low-wear vehicle)", "value": st["front_tyre"]},
        {"item": "rear tyre (both vehicles; base front too)", "value": st["rear_tyre"]},
        {"item": "mass [kg] / yaw inertia [kg m2]", "value": f"{v['mass']:g} / {v['yaw_inertia']:g}"},
        {"item": "l_f / l_r [m]", "value": f"{v['lf']:g} / {v['lr']:g}"},
        {"item": "wheel radius [m] / wheel inertia per axle [kg m2]",
         "value": f"{v['wheel_radius']:g} / {v['wheel_inertia']:g}"},
        {"item": "drag C_d [kg/m] (CALIBRATED to Table 3: C_d/m = 4.8e-4 1/m)", "value": f"{v['drag']:g}"},
        {"item": "static tyre load front / rear [N]",
         "value": f"{st['static_tyre_load_front_N']:.0f} / {st['static_tyre_load_rear_N']:.0f}"},
        {"item": "peak mu_x soft / hard at the front load", "value": f"{st['mu_peak_soft']:.4f} / "
                                                                     f"{st['mu_peak_hard']:.4f}"},
        {"item": "hard/soft peak ratio", "value": f"{st['mu_ratio_hard_soft']:.4f}"},
        {"item": "treadwear-traction exponent b (Eq. 42)", "value": f"{st['traction_b']:.4f} "
                                                                   f"({st['traction_b_source']})"},
        {"item": "emission ratio k = (mu_h/mu_s)^(1/b) (Eq. 43)", "value": f"{st['k']:.4f}"},
        {"item": "ideal reduction (1-k)/(1+k) [%]", "value": f"{st['ideal_reduction_pct']:.2f}"},
        {"item": "emission per tyre N = aF^2 + bF + c (Eq. 14)",
         "value": f"a={st['emission']['a']:.5g}, b={st['emission']['b']:.5g}, c={st['emission']['c']:.5g} "
                  f"({st['emission']['source']})"},
        {"item": "slip limit front / rear (Eq. 49-50)", "value": f"{st['slip_limit_front']} / "
                                                                 f"{st['slip_limit_rear']}"},
        {"item": "time step [s]", "value": str(st["dt_s"])},
    ])
    r.p("Calibrated to Table 3 of Pham et al.: the drag coefficient (from the growth of the maximum deceleration "
        "between 30 and 120 km/h) and, through the synthetic tyres' peak friction and the 0.95 peak share of "
        "the slip limit, the soft tyre's effective friction (about 1.10) and the hard/soft ratio (about 0.815). "
        "Mass, inertias and wheel radius are tyrefit's choices (the paper's values did not survive).", cls="warn")
    r.p("Controller. The allocator predicts the base (all-soft) vehicle's forces at the measured state from the "
        "driver's steering and force demand (equal split within the soft tyres' slip limits; soft-tyre lateral "
        "forces, Eq. 24-25), then splits the longitudinal force between the axles with least emission: the "
        "closed form of Eq. 30 without steering, the paper's Alg. 1 over the steering correction with steering "
        "(Eq. 31-34; re-run every 10 steps, the lateral balance re-solved at every step). Instead of the paper's "
        "offline path-discretised optimal-control problem, a causal force-tracking torque controller (inverse "
        "tyre curve for the reference slip, wheel torque r F_ref + J dw_ref/dt + J K (w_ref - w)) turns the "
        "references into wheel torques at every time step, as an ECU would; the tables below show how closely "
        "the forces follow their references. Slip limits (Eq. 49-50): a tyre's characteristic slip "
        "(Ghasemi et al. 2021) where the tyre provides one, else |mu| <= 0.95 of its peak.")
    if res.scenario == "braking":
        r.h2("Stopping distance and maximum deceleration")
        r.table([{"eta": d["condition"], "km/h": d["initial_speed_kmh"], "vehicle": d["vehicle"],
                  "stop [m]": d["stopping_distance_m"], "paper [m]": d["paper_stopping_distance_m"],
                  "diff %": 100 * (d["stopping_distance_m"] / d["paper_stopping_distance_m"] - 1),
                  "max decel [m/s2]": d["max_deceleration_mps2"], "paper [m/s2]": d["paper_max_deceleration_mps2"]}
                 for d in res.details])
        ratios = [{"eta": res.rows[i]["condition"], "km/h": res.rows[i]["initial_speed_kmh"],
                   "low-wear / base": res.rows[i + 1]["stopping_distance_m"] / res.rows[i]["stopping_distance_m"]}
                  for i in range(0, len(res.rows), 2)]
        r.table(ratios, caption="Stopping-distance ratio (Pham et al.: about 1.10)")
        r.figure(braking_figure(res), "Speed and deceleration against distance; simulated against the paper's "
                                      "stopping distances.")
        r.p("Full brake demand from free rolling; both vehicles' torque controllers hold each axle at its slip "
            "limit. Stopping distance: distance until the speed falls below 0.3 m/s plus v^2/(2a) for the rest.")
    else:
        r.h2("Emission and drivability")
        r.table([{"eta": d["condition"], "km/h": d["speed_kmh"], "emission base [#]": d["emission_base"],
                  "emission low-wear [#]": d["emission_low_wear"], "reduction %": d["reduction_pct"],
                  "paper %": d["paper_reduction_pct"], "ideal %": d["ideal_reduction_pct"],
                  "max path diff [m]": d["max_path_difference_m"],
                  "max speed diff %": d["max_speed_difference_pct"],
                  "max |steer correction| [deg]": math.degrees(d["max_steer_correction_rad"])}
                 for d in res.details])
        r.p("Emission: particles of all four tyres over the run. Path difference: largest difference of the "
            "lateral offset n at equal distance along the path. Speed difference: largest difference at equal "
            "time, in percent of the base vehicle's top speed. The low-wear vehicle replays the base driver's "
            "recorded steering and force demand.")
        r.h3("Comfort of the base driver (Bae et al.'s aggressive driver, Eq. 44-48)")
        r.table([{"eta": d["condition"], "km/h": d["speed_kmh"],
                  **{k: v for k, v in d["comfort_base"].items()}} for d in res.details])
        r.h3("Torque controller: tracking of the reference forces (low-wear vehicle)")
        r.table([{"eta": d["condition"], "km/h": d["speed_kmh"], **d["low_wear"]} for d in res.details])
        for j in range(len(res.members)):
            c, spd = res.members[j]
            r.figure(scenario_figure(res, j), f"eta = {c:g}, {spd:g} km/h: orange base, blue low-wear; "
                                              "solid front axle, dotted rear.")
    r.h2("Traces")
    for j, (c, spd) in enumerate(res.members):
        name = _trace_name(res.scenario, c, spd)
        r.link(name, f"{name}: both vehicles, every 50 ms")
    r.json_block(jsonable(res.to_json()), "JSON")
    return r


def _trace_name(scenario: str, condition: float, speed: float) -> str:
    return f"{scenario}_eta{condition:g}_{speed:g}kmh.csv"


def _ramp_summary(run_) -> str:
    d = run_.json
    cf = d["closed_form"]
    return "\n".join([
        f"Steady-state constant-radius ramp, R = {d['radius_m']:g} m, vehicle {run_.vehicle.name!r}"
        + (f", road friction x{d['road_friction']:g}" if d.get("road_friction", 1.0) != 1.0 else ""),
        f"  understeer gradient {d['understeer_gradient_deg_per_g']:.4f} deg/g (linear bicycle model from the "
        f"tyres' cornering stiffness at static loads, no load transfer: {cf['understeer_gradient_deg_per_g']:.4f} "
        "deg/g)",
        f"  lateral limit {d['lateral_limit_g']:.3f} g: {d['limit']}",
        f"  inside the tyres' declared envelopes up to {d['envelope_limit_g']:.3f} g"
        + ("" if d["envelope_limit_g"] >= d["lateral_limit_g"] - 1e-9 else
           " (beyond it the tyre models are extrapolated: see 'tyres' and the envelope figure)")])


def ramp_report(run_):
    """HTML report of a ramp: steering, body slip, slip angles and wheel loads over a_y, and the envelope."""
    d = run_.json
    r = Report(f"Constant-radius ramp: {run_.vehicle.name}",
               subtitle="Steady states on a circle at rising speed (ISO 4138 style), with lateral load transfer "
                        "and aerodynamic load.")
    r.table([{"item": "radius [m]", "value": d["radius_m"]},
             {"item": "understeer gradient [deg/g]", "value": d["understeer_gradient_deg_per_g"]},
             {"item": "linear bicycle model (m/L)(l_r/C_f - l_f/C_r) at static loads, no load transfer [deg/g]",
              "value": d["closed_form"]["understeer_gradient_deg_per_g"]},
             {"item": "axle cornering stiffness front / rear at static load [N/rad]",
              "value": f"{d['closed_form']['cornering_stiffness_front_N_per_rad']:.0f} / "
                       f"{d['closed_form']['cornering_stiffness_rear_N_per_rad']:.0f}"},
             {"item": "lateral limit [g]", "value": d["lateral_limit_g"]},
             {"item": "limited by", "value": d["limit"]},
             {"item": "inside the tyres' declared envelopes up to [g]", "value": d["envelope_limit_g"]},
             {"item": "road friction [x the tyres' test surface]", "value": d.get("road_friction", 1.0)}])
    r.figure(ramp_figure(run_.result), "Steering angle, body slip angle, axle slip angles and wheel loads over the "
                                       "lateral acceleration.")
    return r


def _step_steer_summary(run_) -> str:
    d = run_.json
    return "\n".join([
        f"Step steer at {d['speed_kmh']:.0f} km/h to {d['steer_deg']:.3f} deg (road wheels), vehicle "
        f"{run_.vehicle.name!r}",
        f"  yaw rate: steady {d['yaw_rate_steady_deg_per_s']:.3f} deg/s, gain {d['yaw_rate_gain_per_s']:.3f} 1/s "
        f"(linear bicycle model {d['closed_form']['linear_bicycle_yaw_rate_gain_per_s']:.3f}), rise time "
        f"{d['yaw_rate_rise_time_s']:.3f} s, response time {d['yaw_rate_response_time_s']:.3f} s, overshoot "
        f"{d['yaw_rate_overshoot_pct']:.2f} %",
        f"  lateral acceleration: steady {d['lateral_acceleration_steady_g']:.3f} g, gain "
        f"{d['lateral_acceleration_gain_g_per_deg']:.4f} g/deg, rise time {d['lateral_acceleration_rise_time_s']:.3f} s, "
        f"response time {d['lateral_acceleration_response_time_s']:.3f} s, overshoot "
        f"{d['lateral_acceleration_overshoot_pct']:.2f} %"])


def _braking_turn_summary(run_) -> str:
    d = run_.json
    lines = [f"Braking in a turn: R = {d['radius_m']:g} m at {d['initial_ay_g']:.2f} g ({d['initial_speed_kmh']:.1f} "
             f"km/h), steering held, vehicle {run_.vehicle.name!r}",
             f"  {'demand':>8} {'decel m/s2':>10} {'max':>6} {'stop [m]':>8} {'dyaw@1s deg/s':>13} "
             f"{'path@1s [m]':>11} {'path@stop':>9}"]
    for r in d["rows"]:
        dem = "full" if r["deceleration_demand_g"] is None else f"{r['deceleration_demand_g']:g} g"
        lines.append(f"  {dem:>8} {r['mean_deceleration_mps2']:10.2f} {r['max_deceleration_mps2']:6.2f} "
                     f"{r['stopping_distance_m']:8.2f} {r['yaw_rate_deviation_1s_deg_per_s']:13.3f} "
                     f"{r['path_deviation_1s_m']:11.3f} {r['path_deviation_stop_m']:9.3f}")
    return "\n".join(lines)


def _notes(r, notes) -> None:
    for n in notes:
        r.p(n)


def step_steer_report(run_):
    """HTML report of a step steer: time responses with rise time, overshoot and steady-state gain."""
    d = run_.json
    r = Report(f"Step steer: {run_.vehicle.name}", subtitle="Steering step from straight running at constant "
               "speed (ISO 7401 style), with load transfer and aerodynamic load.")
    r.table([{"item": k.replace("_", " "), "value": d[k]} for k in d
             if k not in ("trace", "notes", "closed_form", "scenario", "vehicle", "tyres")]
            + [{"item": "linear bicycle model yaw-rate gain v/(L + K v^2) [1/s]",
                "value": d["closed_form"]["linear_bicycle_yaw_rate_gain_per_s"]}])
    r.figure(step_steer_figure(run_.result), "Steering, yaw rate, lateral acceleration and speed over time; dashed "
                                             "the steady values, dotted 10 % and 90 % of them.")
    _notes(r, d["notes"])
    return r


def braking_turn_report(run_):
    """HTML report of braking in a turn: paths, speed, yaw-rate deviation and deceleration per brake demand."""
    d = run_.json
    r = Report(f"Braking in a turn: {run_.vehicle.name}",
               subtitle=f"Steady cornering on R = {d['radius_m']:g} m at {d['initial_ay_g']:.2f} g, then braking "
                        "with the steering held (ISO 7975 style), with load transfer and aerodynamic load.")
    r.table(d["rows"])
    r.figure(braking_turn_figure(run_.result), "Paths against the initial circle; speed, yaw rate minus v/R0 and "
                                               "deceleration after the brake onset, per brake demand.")
    _notes(r, d["notes"])
    return r


_SUMMARIES = {"ramp": _ramp_summary, "step_steer": _step_steer_summary, "braking_turn": _braking_turn_summary}
_REPORTS = {"ramp": ramp_report, "step_steer": step_steer_report, "braking_turn": braking_turn_report}


def _envelope_section(r, run_) -> None:
    r.h2("Where the tyres worked")
    r.table([{"tyre": role, "file": s["file"], "outside envelope [% of time]": 100 * s["outside_envelope"],
              "worst": s["worst"] or ""} for role, s in run_.json["tyres"].items()])
    r.figure(envelope_figure(run_.tyres, run_.points, f"{run_.scenario}, vehicle {run_.vehicle.name}"),
             "Each tyre's operating points (every wheel it is on, every time step) over the envelope its file "
             "declares (grey box: the fitted ranges of load, slip angle and slip ratio); red points are outside.")


def run(args) -> int:
    """Entry point of ``tyrefit sim braking|straight|curved|ramp``: one :func:`tyrefit.sim.api.simulate` call."""
    import sys


    scenario = args.scenario
    if scenario not in SCENARIOS:  # pragma: no cover - argparse restricts the choices
        raise DataError(f"unknown scenario {scenario!r}; accepted: {', '.join(SCENARIOS)}")
    if getattr(args, "json", None):
        check_output(args.json, args.force)
    if getattr(args, "report", None):
        rp = Path(args.report)
        if rp.exists() and any(rp.iterdir()) and not args.force:
            check_output(rp, False)
    run_ = simulate(scenario, getattr(args, "front", None), getattr(args, "rear", None),
                    vehicle=getattr(args, "vehicle", None) or "ev", strict=getattr(args, "strict", False),
                    allow_unphysical=getattr(args, "allow_unphysical", False), radius=getattr(args, "radius", None),
                    speed_kmh=getattr(args, "speed", None), ay_g=getattr(args, "ay", None),
                    road_friction=getattr(args, "road_friction", 1.0))
    res = run_.result
    print(_SUMMARIES.get(scenario, lambda r: _summary(r.result))(run_))
    for w in run_.warnings:
        print(f"tyrefit sim: warning: {w}", file=sys.stderr)
    if getattr(args, "json", None):
        write_text(args.json, json.dumps(jsonable(run_.json), indent=2) + "\n", force=args.force)
        print(f"wrote {args.json}")
    if getattr(args, "report", None):
        report = _REPORTS[scenario](run_) if scenario in _REPORTS else sim_report(res)
        _envelope_section(report, run_)
        with staged_dir(args.report, force=args.force) as d:
            report.save(d)
            if scenario not in _REPORTS:
                for j, (c, spd) in enumerate(res.members):
                    df = traces_frame(res, j)
                    write_text(d / _trace_name(scenario, c, spd),
                               df.to_csv(index=False, lineterminator="\n", float_format="%.7g"),
                               force=True)
        print(f"wrote {Path(args.report) / 'index.html'}")
    return 0
