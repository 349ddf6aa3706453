"""The scenarios of Pham et al. (2025): emergency braking, straight path, curved path.

Each scenario simulates the *base* vehicle (soft tyres on both axles, equal
split) and the *low-wear* vehicle (hard front, soft rear, wear-aware
allocator) at the conditions eta = 0.5 and 1.0 and the speeds 30, 60 and
120 km/h, all six runs of a vehicle in one vectorised batch.

* **braking** (Table 3): full brake demand from the initial speed with both
  vehicles' slip limits active; stopping distance and maximum deceleration.
* **straight** (Table 4): from 1 m/s accelerate to the speed and brake back
  to 1 m/s in the least time the comfort limits allow.
* **curved** (Table 5): constant speed along 100 m straight, a 90 deg left arc
  of half the UK desirable minimum radius for the speed (DMRB CD 109), 100 m
  straight.

In the straight and curved scenarios the low-wear vehicle replays the base
driver's recorded steering and force demand; the allocator must make it
follow the base vehicle.  Reported: emission of both vehicles over the run
(particles, all four tyres), the reduction, the largest lateral-offset
difference at equal distance and the largest speed difference at equal time
(percent of the base vehicle's top speed).
"""

from __future__ import annotations

import math

from dataclasses import dataclass, field

import numpy as np

from ..errors import DataError
from ..tyres.base import Tyre
from .allocator import (AxleLimits, EqualSplit, ForceTrackingController, PeakShareSlipLimit, WearAwareAllocator,
                        resolve_slip_limit)
from .driver import (BrakeDriver, ComfortLimits, DriverLine, PathDriver, ReplayDriver, SteeringLimits,
                     accelerate_brake_profile)
from .emission import DEFAULT_EMISSION, QuadraticEmission
from .path import PathGeometry, curve_path, straight_path, uk_desirable_minimum_radius
from .simulate import simulate
from .traction import HPWIZARD, emission_ratio, traction_from_data
from .tyres import AxleTyre, default_tyres
from .vehicle import DEFAULT_VEHICLE, SimResult, VehicleModel, VehicleParams
from ..errors import TyrefitError
from ..io.datasets import data_path

__all__ = [
    "SPEEDS_KMH",
    "CONDITIONS",
    "PAPER_TABLE3",
    "PAPER_REDUCTION",
    "SimSetup",
    "ScenarioResult",
    "run_braking",
    "run_straight",
    "run_curved",
    "run_scenario",
    "SCENARIOS",
]

SPEEDS_KMH = (30.0, 60.0, 120.0)
CONDITIONS = (0.5, 1.0)
#: default fixed time step per scenario [s]
STEP_SIZES = {"braking": 2e-3, "straight": 4e-3, "curved": 4e-3}

#: Pham et al. 2025, Table 3: (condition, km/h) -> (stop base, stop low-wear [m], decel base, decel low-wear [m/s^2])
PAPER_TABLE3 = {
    (0.5, 30): (6.3, 7.0, 5.4, 4.9), (0.5, 60): (25.8, 28.6, 5.5, 5.0), (0.5, 120): (98.6, 109.6, 5.9, 5.4),
    (1.0, 30): (3.2, 3.6, 10.8, 9.8), (1.0, 60): (13.2, 14.4, 10.9, 9.9), (1.0, 120): (50.6, 56.2, 11.3, 10.3),
}
#: Pham et al. 2025, Tables 4-5: emission reduction [%]
PAPER_REDUCTION = {
    "straight": {(0.5, 30): 48, (0.5, 60): 51, (0.5, 120): 48, (1.0, 30): 48, (1.0, 60): 57, (1.0, 120): 61},
    "curved": {(0.5, 30): 46, (0.5, 60): 50, (0.5, 120): 63, (1.0, 30): 46, (1.0, 60): 50, (1.0, 120): 61},
}


@dataclass
class SimSetup:
    """Everything a scenario needs: vehicle, tyres, emission, limits, driver and step.

    Parameters
    ----------
    front, rear : Tyre
        Low-wear front (hard) and rear (soft) tyres; the base vehicle runs the
        rear tyre on both axles.
    vehicle : VehicleParams
    emission : QuadraticEmission
        Soft tyre's emission per tyre (Eq. 14); :data:`~tyrefit.sim.emission.DEFAULT_EMISSION` by default.
    traction_b : float
        Exponent b of the treadwear-traction law (Eq. 42) for k (Eq. 43);
        default: the fit of the bundled braking table (an error if it cannot
        be read); ``'hpwizard'`` for HPwizard's published 0.15.
    k : float, optional
        Hard/soft emission ratio; computed by Eq. 43 from the tyres' peak
        friction at the front axle load when omitted.
    slip_limit : callable
        Default slip limit (Eq. 49-50) for tyres without a characteristic slip.
    comfort, steering : ComfortLimits, SteeringLimits
    dt : float, optional
        Time step [s] for every scenario; by default :data:`STEP_SIZES`
        (2 ms for braking, whose brake onset and stop take a few wheel time
        constants; 4 ms for the straight and curved paths, where halving the
        step changes no reported figure by more than 0.01 points).
    speeds_kmh, conditions : tuple
    """

    front: Tyre
    rear: Tyre
    vehicle: VehicleParams = DEFAULT_VEHICLE
    emission: QuadraticEmission = DEFAULT_EMISSION
    traction_b: float | str | None = None
    k: float | None = None
    slip_limit: object = field(default_factory=PeakShareSlipLimit)
    comfort: ComfortLimits = field(default_factory=ComfortLimits)
    steering: SteeringLimits = field(default_factory=SteeringLimits)
    dt: float | None = None
    speeds_kmh: tuple = SPEEDS_KMH
    conditions: tuple = CONDITIONS

    def __post_init__(self) -> None:
        p = self.vehicle
        self.hard_front = AxleTyre(self.front, p.axle_load_front / 2.0)
        self.soft_front = AxleTyre(self.rear, p.axle_load_front / 2.0)
        self.soft_rear = AxleTyre(self.rear, p.axle_load_rear / 2.0)
        self.limit_front = resolve_slip_limit(self.front, self.slip_limit)
        self.limit_rear = resolve_slip_limit(self.rear, self.slip_limit)
        if self.traction_b is None:
            self.traction_b, self.traction_source = _bundled_traction_b()
        elif isinstance(self.traction_b, str) and self.traction_b.lower() == "hpwizard":
            self.traction_b, self.traction_source = HPWIZARD["b"], "HPwizard's published b = 0.15 (chosen)"
        else:
            b = float(self.traction_b)
            if not (math.isfinite(b) and b > 0):
                raise DataError(f"traction_b = {self.traction_b!r}: the treadwear-traction exponent must be a "
                                "positive number (HPwizard: 0.15), or 'hpwizard'")
            self.traction_b, self.traction_source = b, "given"
        self.mu_ratio = self.hard_front.mu_peak / self.soft_front.mu_peak
        if self.k is None:
            self.k = float(emission_ratio(self.hard_front.mu_peak, self.soft_front.mu_peak, self.traction_b))
        if not 0 < self.k:
            raise DataError(f"emission ratio k must be positive, got {self.k!r}")
        # the same tyre on both axles (mu ratio 1, k = 1) is allowed: the low-wear vehicle is then the base
        # vehicle with the wear-aware allocator, and the stopping distances are those of that one tyre
        if self.mu_ratio > 1.0 + 1e-9:
            raise DataError(f"the front tyre ({self.front.name!r}) must be the harder one (lower peak friction) or "
                            f"the same: its peak mu is {self.mu_ratio:.3f} x the rear tyre's at the front axle load")

    def step(self, scenario: str) -> float:
        """Time step [s] of a scenario."""
        return float(self.dt) if self.dt is not None else STEP_SIZES[scenario]

    @classmethod
    def default(cls, **kw) -> "SimSetup":
        """The bundled hard (front) and soft (rear) tyres and the default vehicle."""
        front, rear = default_tyres()
        return cls(front=front, rear=rear, **kw)

    # -- members ------------------------------------------------------------------
    def grid(self):
        """(condition, speed_kmh) arrays of the batch members (conditions outer, speeds inner)."""
        c, v = np.meshgrid(np.asarray(self.conditions, float), np.asarray(self.speeds_kmh, float), indexing="ij")
        return c.ravel(), v.ravel()

    def models(self, condition, path: PathGeometry | None = None):
        """(base, low_wear) vehicle models for a batch."""
        base = VehicleModel(self.vehicle, self.soft_front, self.soft_rear, condition, path)
        low = VehicleModel(self.vehicle, self.hard_front, self.soft_rear, condition, path)
        return base, low

    def limits(self, condition):
        """Axle force limits: base front (soft), rear (soft), low-wear front (hard)."""
        soft_f = AxleLimits(self.soft_front, self.limit_rear(self.soft_front), condition)
        soft_r = AxleLimits(self.soft_rear, self.limit_rear(self.soft_rear), condition)
        hard_f = AxleLimits(self.hard_front, self.limit_front(self.hard_front), condition)
        return soft_f, soft_r, hard_f

    @property
    def emission_axle(self) -> QuadraticEmission:
        return self.emission.axle(2)

    def describe(self) -> dict:
        return {
            "front_tyre": self.front.name, "rear_tyre": self.rear.name,
            "vehicle": self.vehicle.to_dict(),
            "static_tyre_load_front_N": self.hard_front.fz, "static_tyre_load_rear_N": self.soft_rear.fz,
            "mu_peak_soft": self.soft_front.mu_peak, "mu_peak_hard": self.hard_front.mu_peak,
            "mu_ratio_hard_soft": self.mu_ratio, "traction_b": self.traction_b,
            "traction_b_source": self.traction_source, "k": self.k,
            "ideal_reduction_pct": 100.0 * (1 - self.k) / (1 + self.k),
            "emission": self.emission.to_dict(),
            "slip_limit_front": self.limit_front.describe(), "slip_limit_rear": self.limit_rear.describe(),
            "calibrated_to_table3": ("vehicle drag C_d (C_d/m = 4.8e-4 1/m, from the growth of Table 3's maximum "
                                     "deceleration between 30 and 120 km/h); the bundled tyres' peak friction "
                                     "(soft ~1.158, hard/soft ~0.815) with the 0.95 peak share of the slip limit "
                                     "(effective soft friction ~1.10)"),
            "comfort": self.comfort.__dict__, "steering": self.steering.__dict__,
            "dt_s": {k: self.step(k) for k in STEP_SIZES},
        }


def _bundled_traction_b():
    """Exponent b fitted to the bundled braking table; a missing or unreadable table is an error.

    There is no silent fallback: HPwizard's published 0.15 is used only when the
    caller asks for it (``traction_b="hpwizard"``), and is then reported as such.
    """
    try:
        fit = traction_from_data(data_path("sim", "braking_utqg.csv")).fit
    except (OSError, TyrefitError) as e:
        raise DataError(f"the treadwear-traction exponent b (Eq. 42) is fitted to the bundled "
                        f"data/sim/braking_utqg.csv, which could not be used ({e}); pass traction_b=<value>, or "
                        "traction_b='hpwizard' for HPwizard's published b = 0.15") from e
    return fit.b, "fit of the bundled data/sim/braking_utqg.csv (synthetic)"


@dataclass
class ScenarioResult:
    """Rows (the ``sim --json`` contract), both vehicles' simulations and the setup."""

    scenario: str
    rows: list[dict]
    base: SimResult
    low_wear: SimResult
    members: list[tuple[float, float]]
    setup: dict
    details: list[dict] = field(default_factory=list)

    def to_json(self) -> dict:
        return {"rows": self.rows, "scenario": self.scenario, "setup": self.setup, "details": self.details}


def _controllers(setup: SimSetup, condition, base_model, low_model):
    soft_f, soft_r, hard_f = setup.limits(condition)
    base_alloc = EqualSplit(soft_f, soft_r)
    low_alloc = WearAwareAllocator(low_model, setup.soft_front, soft_f, soft_r, hard_f, soft_r,
                                   setup.emission_axle, setup.k)
    base_ctrl = ForceTrackingController(base_model, soft_f, soft_r)
    low_ctrl = ForceTrackingController(low_model, hard_f, soft_r)
    return base_alloc, low_alloc, base_ctrl, low_ctrl


def _emissions(setup: SimSetup):
    e = setup.emission_axle
    return (e, e), (e.scaled(setup.k), e)


def _tracking(res: SimResult, j: int) -> dict:
    m = res.member(j, ["fx_f", "fx_r", "force_ref_f", "force_ref_r"])
    out = {}
    for ax in ("f", "r"):
        err = m[f"fx_{ax}"] - m[f"force_ref_{ax}"]
        scale = max(np.max(np.abs(m[f"force_ref_{ax}"])), 1.0)
        out[f"tracking_rms_{ax}_N"] = float(np.sqrt(np.mean(err**2)))
        out[f"tracking_rms_{ax}_pct_of_max"] = float(100 * np.sqrt(np.mean(err**2)) / scale)
    return out


# ------------------------------------------------------------------------------ braking

def run_braking(setup: SimSetup, stop_speed: float = 0.3) -> ScenarioResult:
    """Emergency braking from each speed at each condition (Pham et al. 2025, Table 3).

    Stopping distance: distance travelled until the speed falls below
    ``stop_speed`` plus v^2 / (2 a) for the last bit at the last deceleration.
    """
    cond, speed = setup.grid()
    v0 = speed / 3.6
    p = setup.vehicle
    base_m, low_m = setup.models(cond)
    base_a, low_a, base_c, low_c = _controllers(setup, cond, base_m, low_m)
    (ebf, ebr), (elf, elr) = _emissions(setup)
    t_end = v0 / (0.3 * cond * p.g) + 1.0
    kw = dict(dt=setup.step("braking"), t_end=t_end, stop=lambda t, x: x[3] < stop_speed)
    driver = BrakeDriver(p, cond.size)
    base = simulate(base_m, base_m.rolling_state(v0), driver=driver, allocator=base_a, controller=base_c,
                    emission_front=ebf, emission_rear=ebr, meta={"vehicle": "base"}, **kw)
    low = simulate(low_m, low_m.rolling_state(v0), driver=driver, allocator=low_a, controller=low_c,
                   emission_front=elf, emission_rear=elr, meta={"vehicle": "low_wear"}, **kw)
    rows, details = [], []
    for j in range(cond.size):
        for name, res in (("base", base), ("low_wear", low)):
            m = res.member(j, ["s", "vx", "ax"])
            decel = -m["ax"]
            a_end = max(decel[-1], 1e-3)
            dist = float(m["s"][-1] + m["vx"][-1] ** 2 / (2 * a_end))
            rows.append({"condition": float(cond[j]), "initial_speed_kmh": float(speed[j]), "vehicle": name,
                         "stopping_distance_m": round(dist, 3),
                         "max_deceleration_mps2": round(float(np.max(decel[1:])), 3)})
            paper = PAPER_TABLE3[(float(cond[j]), int(speed[j]))]
            details.append({**rows[-1], "paper_stopping_distance_m": paper[0 if name == "base" else 1],
                            "paper_max_deceleration_mps2": paper[2 if name == "base" else 3],
                            "stop_time_s": float(m["t"][-1]), **_tracking(res, j)})
    return ScenarioResult("braking", rows, base, low, list(zip(cond, speed)), setup.describe(), details)


# ------------------------------------------------------------------------------ straight and curved

def _paired_runs(setup: SimSetup, scenario, cond, path, x0, v_ref, a_ref, t_end, window, stop=None,
                 speed=None):
    p = setup.vehicle
    dt = setup.step(scenario)
    base_m, low_m = setup.models(cond, path)
    base_a, low_a, base_c, low_c = _controllers(setup, cond, base_m, low_m)
    (ebf, ebr), (elf, elr) = _emissions(setup)
    line = DriverLine.build(path, window, speed=speed, params=p, front=setup.soft_front, rear=setup.soft_rear,
                            condition=cond)
    driver = PathDriver(p, line, v_ref, a_ref, setup.steering, dt)
    kw = dict(dt=dt, t_end=t_end, stop=stop)
    base = simulate(base_m, x0, driver=driver, allocator=base_a, controller=base_c,
                    emission_front=ebf, emission_rear=ebr, meta={"vehicle": "base"}, **kw)
    replay = ReplayDriver(base["steer_driver"], base["force_demand"])
    low = simulate(low_m, x0, driver=replay, allocator=low_a, controller=low_c,
                   emission_front=elf, emission_rear=elr, meta={"vehicle": "low_wear"}, **kw)
    return base, low, line, low_a


def _compare(base: SimResult, low: SimResult, j: int) -> dict:
    b = base.member(j, ["s", "n", "vx"])
    lw = low.member(j, ["s", "n", "vx"])
    e = min(b["t"].size, lw["t"].size)
    n_on_b = np.interp(b["s"], lw["s"], lw["n"])
    inside = b["s"] <= lw["s"][-1]
    path_diff = float(np.max(np.abs(n_on_b - b["n"])[inside]))
    vmax = float(np.max(b["vx"]))
    speed_diff = float(100.0 * np.max(np.abs(lw["vx"][:e] - b["vx"][:e])) / vmax)
    eb = float(base.integral("emission_f")[j] + base.integral("emission_r")[j])
    el = float(low.integral("emission_f")[j] + low.integral("emission_r")[j])
    return {"emission_base": eb, "emission_low_wear": el, "reduction_pct": 100.0 * (1.0 - el / eb),
            "max_path_difference_m": path_diff, "max_speed_difference_pct": speed_diff}


def _comfort(res: SimResult, j: int, dt: float) -> dict:
    m = res.member(j, ["ax", "ay", "steer_driver", "n"])
    jerk_x = np.diff(m["ax"]) / dt
    jerk_y = np.diff(m["ay"]) / dt
    k = max(1, int(round(0.05 / dt)))   # jerk over 50 ms windows (the wheel transients are ms)
    jx = (m["ax"][k:] - m["ax"][:-k]) / (k * dt) if m["ax"].size > k else jerk_x
    jy = (m["ay"][k:] - m["ay"][:-k]) / (k * dt) if m["ay"].size > k else jerk_y
    return {"max_accel_mps2": float(np.max(m["ax"])), "max_decel_mps2": float(-np.min(m["ax"])),
            "max_lat_accel_mps2": float(np.max(np.abs(m["ay"]))),
            "max_jerk_mps3": float(np.max(np.abs(jx))), "max_lat_jerk_mps3": float(np.max(np.abs(jy))),
            "max_steer_rad": float(np.max(np.abs(m["steer_driver"]))),
            "max_steer_rate_radps": float(np.max(np.abs(np.diff(m["steer_driver"]))) / dt),
            "max_offset_m": float(np.max(np.abs(m["n"])))}


def _rows(scenario, setup, cond, speed, base, low, extra=None):
    rows, details = [], []
    for j in range(cond.size):
        c = _compare(base, low, j)
        rows.append({"condition": float(cond[j]), "speed_kmh": float(speed[j]),
                     "emission_base": c["emission_base"], "emission_low_wear": c["emission_low_wear"],
                     "reduction_pct": round(c["reduction_pct"], 3),
                     "max_path_difference_m": c["max_path_difference_m"],
                     "max_speed_difference_pct": c["max_speed_difference_pct"]})
        d = {**rows[-1], "paper_reduction_pct": PAPER_REDUCTION[scenario][(float(cond[j]), int(speed[j]))],
             "ideal_reduction_pct": 100.0 * (1 - setup.k) / (1 + setup.k),
             "comfort_base": _comfort(base, j, setup.step(scenario)), "low_wear": _tracking(low, j),
             "max_steer_correction_rad": float(np.max(np.abs(low.member(j, ["steer_correction"])
                                                             ["steer_correction"])))}
        if extra:
            d.update(extra[j])
        details.append(d)
    return rows, details


def run_straight(setup: SimSetup, v_floor: float = 1.0) -> ScenarioResult:
    """Accelerate from ``v_floor`` to each speed and brake back, least time within comfort limits (Table 4)."""
    cond, speed = setup.grid()
    v_top = speed / 3.6
    c = setup.comfort
    horizon = float(np.max(v_top / c.accel_max + v_top / c.decel_max + 4 * c.accel_max / c.jerk_max + 5))
    dt = setup.step("straight")
    t = np.arange(int(np.ceil(horizon / dt)) + 2) * dt
    v_ref, a_ref, t_prof = accelerate_brake_profile(v_top, v_floor, c, t)
    dist = np.sum(v_ref, axis=0) * dt
    path = straight_path(dist + 50.0, cond.size)
    x0 = VehicleModel(setup.vehicle, setup.soft_front, setup.soft_rear, cond, path).rolling_state(v_floor)
    base, low, _, alloc = _paired_runs(setup, "straight", cond, path, x0, v_ref, a_ref, t_prof + 0.5,
                                       window=np.full(cond.size, 10.0))
    rows, details = _rows("straight", setup, cond, speed, base, low,
                          [{"profile_time_s": float(t_prof[j]), "path_length_m": float(dist[j])}
                           for j in range(cond.size)])
    return ScenarioResult("straight", rows, base, low, list(zip(cond, speed)),
                          {**setup.describe(), "v_floor_mps": v_floor}, details)


def run_curved(setup: SimSetup, straight: float = 100.0, angle_deg: float = 90.0) -> ScenarioResult:
    """Constant speed on straight - arc (half the UK desirable minimum radius) - straight (Table 5)."""
    cond, speed = setup.grid()
    v = speed / 3.6
    radius = 0.5 * uk_desirable_minimum_radius(speed)
    path = curve_path(straight, radius, np.radians(angle_deg))
    length = path.total_length
    t_end = length / v + 2.0
    n_t = int(np.ceil(t_end.max() / setup.step("curved"))) + 2
    v_ref = np.broadcast_to(v, (n_t, v.size)).copy()
    a_ref = np.zeros_like(v_ref)
    window = v**3 / (radius * setup.comfort.line_jerk)   # peak lateral jerk of the line = line_jerk
    base_m = VehicleModel(setup.vehicle, setup.soft_front, setup.soft_rear, cond, path)
    drag = setup.vehicle.drag * v**2
    x0 = base_m.cruise_state(v, 0.5 * drag, 0.5 * drag)     # steady straight running, drag shared equally
    base, low, line, alloc = _paired_runs(setup, "curved", cond, path, x0, v_ref, a_ref, t_end, window,
                                          stop=lambda t, x: x[0] >= length, speed=v)
    extra = [{"radius_m": float(radius[j]), "arc_angle_deg": angle_deg, "straight_m": straight,
              "line_window_m": float(window[j]), "lateral_accel_mps2": float(v[j] ** 2 / radius[j]),
              "line_max_offset_m": float(np.max(np.abs(line.offset[:, j])))} for j in range(cond.size)]
    rows, details = _rows("curved", setup, cond, speed, base, low, extra)
    details[0]["allocator_stats"] = dict(alloc.stats)
    return ScenarioResult("curved", rows, base, low, list(zip(cond, speed)), setup.describe(), details)


SCENARIOS = {"braking": run_braking, "straight": run_straight, "curved": run_curved}


def run_scenario(name: str, setup: SimSetup) -> ScenarioResult:
    """Run a scenario by name (``braking``, ``straight``, ``curved``)."""
    try:
        fn = SCENARIOS[name]
    except KeyError:
        raise DataError(f"unknown scenario {name!r}; accepted: {', '.join(SCENARIOS)}") from None
    return fn(setup)
