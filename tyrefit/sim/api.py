"""One call for every vehicle scenario: :func:`simulate` (what ``tyrefit sim`` and ``tf.simulate`` run).

``simulate(scenario, front=None, rear=None, vehicle="ev")`` reads the tyres and the
vehicle, runs the scenario, checks where the tyres worked against the envelope
each declares (:mod:`~tyrefit.sim.envelope`), and returns a :class:`SimRun` whose
``json`` is the ``sim --json`` document (DESIGN: the scenario's keys, plus
``"vehicle"`` (SI) and ``"tyres": {"front": {"file", "outside_envelope",
"worst"}, "rear": {...}}``).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import numpy as np

from ..errors import DataError, ValueRangeError, close_matches, option, render
from ..nomenclature import G0
from .envelope import envelope_summary, points_from_paper_result, points_from_ramp
from .handling import run_ramp
from .scenarios import SimSetup, run_scenario
from .transient import points_from_trace, run_braking_turn, run_step_steer
from .tyres import default_tyres, load_tyre
from .vehicle_file import VehicleSpec, load_vehicle
from ..tyres.base import Tyre

__all__ = ["SimRun", "simulate", "SCENARIOS"]

#: the scenarios of Pham et al. 2025 (bicycle model at static loads) and the vehicle-dynamics ones
PAPER_SCENARIOS = ("braking", "straight", "curved")
SCENARIOS = PAPER_SCENARIOS + ("ramp", "step_steer", "braking_turn")


@dataclass
class SimRun:
    """A scenario's outcome: the JSON document, the result objects, the tyres and the envelope points."""

    scenario: str
    json: dict
    result: object                    # ScenarioResult (paper scenarios), RampResult, StepSteerResult, BrakingTurnResult
    vehicle: VehicleSpec
    tyres: dict                       # 'front'/'rear' -> Tyre
    points: dict                      # 'front'/'rear' -> OperatingPoints
    warnings: list[str] = field(default_factory=list)

    def to_json(self) -> dict:
        return self.json


def _tyre(t, allow_unphysical: bool):
    if t is None or isinstance(t, Tyre):
        return t, (getattr(t, "name", None) if t is not None else None)
    return load_tyre(t, allow_unphysical=allow_unphysical), str(t)


def simulate(scenario: str, front=None, rear=None, vehicle: "str | os.PathLike | VehicleSpec | dict" = "ev", *,
             strict: bool = False, allow_unphysical: bool = False, radius: float | None = None,
             speed_kmh: float | None = None, ay_g: float | None = None, road_friction: float = 1.0) -> SimRun:
    """Run a scenario on a vehicle with its tyres.

    Parameters
    ----------
    scenario : {'braking', 'straight', 'curved', 'ramp', 'step_steer', 'braking_turn'}
    front, rear : Tyre or path, optional
        The front (low-wear in Pham et al.'s scenarios) and rear tyres; the bundled
        hard and soft tyres when omitted.
    vehicle : str, path, VehicleSpec or dict
        A preset (``ev``, the default and Pham et al.'s car; ``fsae``; ``light_truck``) or a
        vehicle file (TOML or JSON; :mod:`~tyrefit.sim.vehicle_file`).
    strict : bool
        Refuse (:class:`~tyrefit.errors.ValueRangeError`) when a tyre works outside the
        envelope it declares, instead of warning.
    allow_unphysical : bool
        Use tyre files whose model is unphysical over their declared range.
    radius : float, optional
        ``ramp``: circle radius [m] (default: the vehicle's ``ramp_radius``); ``braking_turn``: the
        initial circle's radius [m] (default 100 m, ISO 7975).
    speed_kmh : float, optional
        ``step_steer``: speed [km/h] (default 80).
    ay_g : float, optional
        ``step_steer``: steady-state lateral acceleration the steering step aims at [g] (default 0.4);
        ``braking_turn``: lateral acceleration of the steady cornering before braking [g] (default 0.5).
    road_friction : float
        The road's friction as a factor on the surface the tyres were tested on (1: as tested).  Peak
        forces scale, slip stiffnesses do not (:meth:`tyrefit.tyres.base.Tyre.on_road`: LMUX and LMUY
        of a Magic Formula tyre, Pacejka 2012 Sec. 4.3.2).  A belt rig's abrasive surface grips more
        than a road: data from one usually need about 0.6-0.7 for a dry track.

    Returns
    -------
    SimRun
        ``.json`` is the ``sim --json`` document; ``.warnings`` the out-of-envelope warnings.
    """
    if scenario not in SCENARIOS:
        raise DataError(f"unknown scenario {scenario!r}{close_matches(scenario, SCENARIOS)}; accepted: "
                        f"{', '.join(SCENARIOS)}")
    spec = load_vehicle(vehicle)
    (f, f_file), (r, r_file) = _tyre(front, allow_unphysical), _tyre(rear, allow_unphysical)
    if f is None or r is None:
        f0, r0 = default_tyres()
        if f is None:
            f, f_file = f0, f"bundled {f0.name}"
        if r is None:
            r, r_file = r0, f"bundled {r0.name}"
    if road_friction != 1.0:
        f, r = f.on_road(road_friction), r.on_road(road_friction)
    tyres = {"front": f, "rear": r}
    if scenario in PAPER_SCENARIOS:
        setup = SimSetup(front=f, rear=r, vehicle=spec.to_params())
        res = run_scenario(scenario, setup)
        doc = res.to_json()
        fz = {"front": setup.hard_front.fz, "rear": setup.soft_rear.fz}
        points = {role: points_from_paper_result(res, role, fz) for role in ("front", "rear")}
        doc.update(_paper_notes(doc, scenario, spec))
    elif scenario == "ramp":
        res = run_ramp(spec, f, r, radius=radius)
        doc = {"scenario": "ramp", **res.to_json()}
        points = {role: points_from_ramp(res, role) for role in ("front", "rear")}
        doc["envelope_limit_g"] = envelope_limit_g(res, tyres, points)
    else:
        if scenario == "step_steer":
            res = run_step_steer(spec, f, r, **{k: v for k, v in (("speed_kmh", speed_kmh), ("ay_g", ay_g))
                                                if v is not None})
        else:
            res = run_braking_turn(spec, f, r, **{k: v for k, v in (("radius", radius), ("ay_g", ay_g))
                                                  if v is not None})
        doc = {"scenario": scenario, **res.to_json()}
        points = {role: points_from_trace(res.trace, role) for role in ("front", "rear")}
    files = {"front": f_file, "rear": r_file}
    summary = {role: envelope_summary(tyres[role], points[role], files[role]) for role in ("front", "rear")}
    doc["vehicle"] = spec.to_dict()
    doc["road_friction"] = float(road_friction)
    doc["tyres"] = summary
    warns = [f"{role} tyre {files[role]}: outside its declared envelope {100 * s['outside_envelope']:.1f} % of "
             f"the simulated time; worst: {s['worst']}"
             for role, s in summary.items() if s["outside_envelope"] > 0]
    if strict and warns:
        raise ValueRangeError(f"{option('strict', flag=True)}: {warns[0]}" + (f" (and the {warns[1].split()[0]} tyre)" if len(warns) > 1
                                                         else ""))
    return SimRun(scenario, doc, res, spec, tyres, points, warns)


def envelope_limit_g(ramp, tyres: dict, points: dict) -> float:
    """The lateral acceleration [g] up to which every wheel of the ramp stays inside its tyre's declared envelope.

    The ramp's steady states, in rising lateral acceleration, until the first one where a wheel's load or slip
    angle leaves the ranges its tyre file declares (near the limit the inner wheels unload below the fitted
    loads): what the fitted tyres vouch for; ``lateral_limit_g`` beyond it is the model extrapolated.
    """
    inside = np.ones(ramp.states["ay"].size, bool)
    for role, pts in points.items():
        v = tyres[role].validity()
        for key in ("fz", "slip_angle"):
            lo, hi = v[key]
            val = getattr(pts, key)
            inside &= np.all((val >= lo) & (val <= hi), axis=1)
    out = np.flatnonzero(~inside)
    last = (out[0] - 1) if out.size else inside.size - 1
    return float(ramp.states["ay"][last] / G0) if last >= 0 else 0.0


def _paper_notes(doc: dict, scenario: str, spec: VehicleSpec) -> dict:
    """New top-level keys of the paper scenarios: ``comparison`` (the allocator's emission cut or the
    stopping-distance penalty of the low-wear vehicle) and ``notes`` (what the model leaves out)."""
    rows = doc["rows"]
    if scenario == "braking":
        pen = [{"condition": rows[i]["condition"], "initial_speed_kmh": rows[i]["initial_speed_kmh"],
                "stopping_distance_base_m": rows[i]["stopping_distance_m"],
                "stopping_distance_low_wear_m": rows[i + 1]["stopping_distance_m"],
                "stopping_distance_penalty_pct": 100.0 * (rows[i + 1]["stopping_distance_m"]
                                                          / rows[i]["stopping_distance_m"] - 1.0)}
               for i in range(0, len(rows) - 1, 2)
               if rows[i]["vehicle"] == "base" and rows[i + 1]["vehicle"] == "low_wear"]
        vals = [p["stopping_distance_penalty_pct"] for p in pen]
        comp = {"stopping_distance_penalty": pen,
                "stopping_distance_penalty_pct_range": [min(vals), max(vals)] if vals else None}
    else:
        vals = [r["reduction_pct"] for r in rows]
        comp = {"emission_cut_pct_range": [min(vals), max(vals)] if vals else None,
                "emission_cut_pct_mean": sum(vals) / len(vals) if vals else None}
    notes = [f"vehicle {spec.name!r}: mass, yaw inertia, l_f/l_r, wheel radius and inertia and drag from the "
             "vehicle file; Pham et al.'s bicycle model runs at the STATIC axle loads (no longitudinal or lateral "
             "load transfer, no downforce, no rolling resistance, no motor torque or power limits), so that the "
             "ev preset keeps the paper's results; ramp, step_steer and braking_turn carry load transfer and "
             "aero load"]
    k = doc.get("setup", {}).get("k")
    if k is not None and abs(k - 1.0) < 1e-12:
        notes.append(render("k = 1: the front (low-wear) and rear tyres have the same peak friction (the same tyre "
                            "on both axles?), so the allocator has nothing to trade: no emission cut and no "
                            f"stopping-distance penalty by construction; give a harder front tyre ({option('front')})"))
    if spec.downforce_area != 0 or spec.rolling_resistance != 0:
        notes.append(f"vehicle {spec.name!r} declares downforce_area {spec.downforce_area:g} m^2 and "
                     f"rolling_resistance {spec.rolling_resistance:g}: not used by this scenario")
    return {"comparison": comp, "notes": notes}
