"""Synthetic data for the tyre-emission vehicle simulation (Pham et al. 2025).

**Everything this module writes is synthetic.**  No file in ``data/sim/`` is
a measurement.  Pham, Hamedmoghadam and Shorten (2025) used MATLAB's
"Mid-size passenger car 235/45R18" (soft, high grip, high wear) and "Light
passenger car 205/60R15" (hard, low grip, low wear) tyres, NHTSA UTQG 2024
treadwear grades with Tire Rack stopping distances, and particle counts of
Foitzik et al. (2018); none of these numbers is public in a form we may ship,
so this module makes stand-ins with realistic magnitudes from the documented
"truth" below and seeded noise.

Files written by :func:`generate` (each CSV starts with a ``# synthetic:`` line)
------------------------------------------------------------------------------
``soft_tyre.csv``, ``hard_tyre.csv``
    one rig programme per tyre, every channel recorded in every row:
    ``run``, ``load [N]``, ``pressure [bar]``, ``speed [km/h]``,
    ``camber [deg]``, ``slip_angle [deg]``, ``slip_ratio [-]``, ``fz [N]``,
    ``fx [N]``, ``fy [N]``.  Runs 1-4: free-rolling slip-angle sweeps
    -12..12 deg at 2, 3.5, 5 and 6.5 kN (slip ratio 0); runs 5-8: slip-ratio
    sweeps -0.3..0.3 at zero slip angle and the same loads; 2.4 bar, 60 km/h,
    zero camber.  ISO-W signs: a positive slip angle gives a negative ``fy``;
    ``fx`` is positive driving.  ``tyrefit fit`` fits both parts at once.
``braking_utqg.csv``
    a Tire Rack / UTQG style table of 15 tyres: ``name``, ``treadwear [-]``
    (UTQG grade), ``stopping_distance [ft]`` and ``initial_speed [mph]`` (dry
    50-0 mph), the input of ``tyrefit traction``.
``emission.csv``
    particle emission per tyre vs longitudinal force: ``fx [N]`` (braking
    negative, traction positive), ``particles [#/s]``.
``truth.json``
    every parameter below, for tests and reports.

The truth
---------
*Tyres* are Pacejka '89 (Adams PAC89 as Chrono evaluates it) with the
coefficients :data:`SOFT` and :data:`HARD` (PAC89 units: kN, deg, %).  At the
static load of the default vehicle (about 4.4 kN per tyre) the soft tyre peaks
at mu_x = 1.158 near 9 % slip and mu_y = 1.083 near 7 deg; the hard tyre
at mu_x = 0.944 near 11 % slip (hard tyres peak at larger slip, as Pham et al.
note) and mu_y = 0.883 near 8 deg: a hard/soft peak ratio of 0.815,
the ratio Table 3 of Pham et al. implies (low-wear/base deceleration 9.8/10.8 =
(1 + r)/2).  Friction falls with load (D = b1 Fz^2 + b2 Fz with b1 < 0).
Small conicity offsets (a10, a13) are included, as real tyres have them.
Noise: Gaussian, 0.6 % of the sweep's peak force, plus 0.5 % scatter on the
measured load.

*Treadwear and traction* follow Eq. 42 of Pham et al., mu = a TW^-b with
a = 2.20, b = 0.145 (HPwizard's published law is a = 2.25, b = 0.15), with
2 % lognormal scatter of mu.  Each tyre's stopping distance from 50 mph is
then Eq. 15 with HPwizard's K = 6.58e-5 s^2/m^2 and f_r = 0.013, rounded to
0.1 ft as Tire Rack reports it.

*Emission* per tyre is N(F) = a (F - F0)^2 + N_min with a = 0.012
(#/s)/N^2, F0 = 500 N (the minimum is at a non-zero force, as in Fig. 6 of
Pham et al.) and N_min = 0 (their constrained fit touches zero at its
minimum), with 10 % lognormal noise plus a background count |N(0, 40)| #/s,
24 braking and 24 traction points over 20 N <= |F| <= 2.5 kN.  In Eq. 14's
form N = a F^2 + b F + c this is a = 0.012, b = -12.0, c = 3000.

Seeds: tyres 60 (soft) and 61 (hard), UTQG table 67, emission 63.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import DataError
from ..fitting import fit_pac89
from ..io.outputs import check_output, write_text
from ..io.readers import read_data
from ..sim.tyres import DEFAULT_FRONT, DEFAULT_REAR
from ..tyres.pac89 import Pac89Tyre

__all__ = [
    "SOFT",
    "HARD",
    "LOADS",
    "UTQG_TRUTH",
    "EMISSION_TRUTH",
    "true_tyre",
    "lateral_table",
    "longitudinal_table",
    "tyre_table",
    "utqg_table",
    "emission_table",
    "generate",
]

G = 9.80665

#: the soft (high-grip, high-wear) tyre: 235/45R18, PAC89 coefficients and design data
SOFT = {
    "name": "synthetic soft 235/45R18",
    "seed": 60,
    "unloaded_radius": 0.3344,   # 18 in rim / 2 + 0.45 * 235 mm
    "width": 0.235,
    "fnomin": 6573.0,            # load index 94: 670 kg
    "coefficients": {
        # lateral: C, D = a1 Fz^2 + a2 Fz, BCD = a3 sin(2 atan(Fz/a4)), E = a6 Fz + a7, shifts
        "a0": 1.35, "a1": -22.0, "a2": 1180.0, "a3": 2000.0, "a4": 8.0, "a5": 0.0,
        "a6": -0.04, "a7": -0.30, "a8": 0.0, "a9": 0.0, "a10": 0.04, "a11": 0.0, "a12": 0.0, "a13": 25.0,
        # longitudinal: C, D = b1 Fz^2 + b2 Fz, BCD = (b3 Fz^2 + b4 Fz) exp(-b5 Fz), E = b6 Fz^2 + b7 Fz + b8
        "b0": 1.65, "b1": -25.0, "b2": 1268.0, "b3": 0.0, "b4": 300.0, "b5": 0.01,
        "b6": 0.0, "b7": -0.01, "b8": -0.15, "b9": 0.0, "b10": 0.0,
    },
}

#: the hard (low-grip, low-wear) tyre: 205/60R15
HARD = {
    "name": "synthetic hard 205/60R15",
    "seed": 61,
    "unloaded_radius": 0.3135,   # 15 in rim / 2 + 0.60 * 205 mm
    "width": 0.205,
    "fnomin": 6031.0,            # load index 91: 615 kg
    "coefficients": {
        "a0": 1.30, "a1": -17.0, "a2": 958.0, "a3": 1500.0, "a4": 7.0, "a5": 0.0,
        "a6": -0.05, "a7": -0.30, "a8": 0.0, "a9": 0.0, "a10": -0.03, "a11": 0.0, "a12": 0.0, "a13": -20.0,
        "b0": 1.60, "b1": -18.0, "b2": 1024.0, "b3": 0.0, "b4": 200.0, "b5": 0.01,
        "b6": 0.0, "b7": -0.01, "b8": -0.15, "b9": 0.0, "b10": 0.0,
    },
}

#: test loads [N]
LOADS = (2000.0, 3500.0, 5000.0, 6500.0)
PRESSURE_BAR = 2.4
SPEED_KMH = 60.0
SLIP_ANGLES_DEG = np.round(np.arange(-12.0, 12.0001, 0.5), 6)
SLIP_RATIOS = np.round(np.arange(-0.30, 0.30001, 0.01), 6)
FORCE_NOISE = 0.006      # of the sweep's peak force
LOAD_NOISE = 0.005       # relative scatter of the measured load

#: treadwear-traction truth (Pham et al., Eq. 42 form), stopping-distance law (Eq. 15)
UTQG_TRUTH = {"a": 2.20, "b": 0.145, "scatter": 0.02, "K": 6.58e-5, "f_r": 0.013,
              "initial_speed_mph": 50.0, "seed": 67}

#: emission truth per tyre: N = a (F - F0)^2 + N_min  [#/s], F [N]
EMISSION_TRUTH = {"a": 0.012, "F0": 500.0, "N_min": 0.0, "noise": 0.10, "floor_noise": 40.0,
                  "force_max": 2500.0, "points_per_side": 24, "seed": 63}

_UTQG_NAMES = [
    "Synthetic Sport Max A", "Synthetic Sport Max B", "Synthetic Summer Perf C", "Synthetic Summer Perf D",
    "Synthetic UHP All-Season E", "Synthetic UHP All-Season F", "Synthetic Grand Touring G",
    "Synthetic Grand Touring H", "Synthetic Touring I", "Synthetic Touring J", "Synthetic Touring K",
    "Synthetic Eco Touring L", "Synthetic Eco Touring M", "Synthetic Long-Life N", "Synthetic Long-Life O",
]
_UTQG_GRADES = [200, 220, 240, 300, 340, 400, 440, 500, 540, 600, 640, 700, 740, 800, 860]


def true_tyre(which: str) -> Pac89Tyre:
    """The generating ('true') tyre: ``'soft'`` or ``'hard'``."""
    spec = {"soft": SOFT, "hard": HARD}[which]
    return Pac89Tyre(
        coefficients=dict(spec["coefficients"]),
        unloaded_radius=spec["unloaded_radius"],
        width=spec["width"],
        fnomin=spec["fnomin"],
        ranges={"fz": (min(LOADS), max(LOADS)),
                "slip_angle": (math.radians(SLIP_ANGLES_DEG[0]), math.radians(SLIP_ANGLES_DEG[-1])),
                "camber": (0.0, 0.0), "slip_ratio": (float(SLIP_RATIOS[0]), float(SLIP_RATIOS[-1]))},
        header=[f"{spec['name']}: the TRUE coefficients of tyrefit.synthetic.vehicle_tyres (synthetic)"],
        name=spec["name"],
    )


def lateral_table(which: str, rng: np.random.Generator | None = None) -> pd.DataFrame:
    """Slip-angle sweeps of the soft or hard tyre (ISO-W, display units), runs 1-4.

    Every channel is recorded, as on a rig: ``slip_ratio`` is 0 and ``fx`` the
    free-rolling longitudinal force (zero plus noise).
    """
    spec = {"soft": SOFT, "hard": HARD}[which]
    rng = rng or np.random.default_rng(spec["seed"])
    tyre = true_tyre(which)
    rows = []
    for run, load in enumerate(LOADS, 1):
        alpha = np.radians(SLIP_ANGLES_DEG)
        fz = load * (1.0 + LOAD_NOISE * rng.standard_normal(alpha.size))
        clean = tyre.fy(fz, alpha)
        scale = FORCE_NOISE * np.max(np.abs(clean))
        fy = clean + scale * rng.standard_normal(alpha.size)
        fx = scale * rng.standard_normal(alpha.size)
        rows.append(pd.DataFrame({
            "run": run, "load [N]": load, "pressure [bar]": PRESSURE_BAR, "speed [km/h]": SPEED_KMH,
            "camber [deg]": 0.0, "slip_angle [deg]": SLIP_ANGLES_DEG, "slip_ratio [-]": 0.0,
            "fz [N]": np.round(fz, 1), "fx [N]": np.round(fx, 1), "fy [N]": np.round(fy, 1)}))
    return pd.concat(rows, ignore_index=True)


def longitudinal_table(which: str, rng: np.random.Generator | None = None) -> pd.DataFrame:
    """Slip-ratio sweeps of the soft or hard tyre at zero slip angle (driving positive), runs 5-8.

    ``fy`` is the lateral force at zero slip angle (the conicity offset) plus noise.
    """
    spec = {"soft": SOFT, "hard": HARD}[which]
    rng = rng or np.random.default_rng(spec["seed"] + 100)
    tyre = true_tyre(which)
    rows = []
    for run, load in enumerate(LOADS, len(LOADS) + 1):
        kappa = SLIP_RATIOS
        fz = load * (1.0 + LOAD_NOISE * rng.standard_normal(kappa.size))
        clean = tyre.fx(fz, kappa)
        scale = FORCE_NOISE * np.max(np.abs(clean))
        fx = clean + scale * rng.standard_normal(kappa.size)
        fy = tyre.fy(fz, 0.0 * kappa) + scale * rng.standard_normal(kappa.size)
        rows.append(pd.DataFrame({
            "run": run, "load [N]": load, "pressure [bar]": PRESSURE_BAR, "speed [km/h]": SPEED_KMH,
            "camber [deg]": 0.0, "slip_angle [deg]": 0.0, "slip_ratio [-]": kappa,
            "fz [N]": np.round(fz, 1), "fx [N]": np.round(fx, 1), "fy [N]": np.round(fy, 1)}))
    return pd.concat(rows, ignore_index=True)


def tyre_table(which: str) -> pd.DataFrame:
    """The rig programme of one tyre: slip-angle sweeps (runs 1-4), then slip-ratio sweeps (runs 5-8)."""
    spec = {"soft": SOFT, "hard": HARD}[which]
    rng = np.random.default_rng(spec["seed"])
    return pd.concat([lateral_table(which, rng), longitudinal_table(which, rng)], ignore_index=True)


def utqg_table(rng: np.random.Generator | None = None) -> pd.DataFrame:
    """15 tyres: UTQG treadwear and a dry 50-0 mph stopping distance (Eq. 42 truth, Eq. 15)."""
    t = UTQG_TRUTH
    rng = rng or np.random.default_rng(t["seed"])
    tw = np.asarray(_UTQG_GRADES, float)
    mu = t["a"] * tw ** (-t["b"]) * np.exp(t["scatter"] * rng.standard_normal(tw.size))
    v0 = t["initial_speed_mph"] * 0.44704
    K, fr = t["K"], t["f_r"]
    d = np.log1p(K * v0**2 / (mu + fr)) / (2.0 * G * K)          # Pham et al., Eq. 15
    return pd.DataFrame({"name": _UTQG_NAMES, "treadwear [-]": tw.astype(int),
                         "stopping_distance [ft]": np.round(d / 0.3048, 1),
                         "initial_speed [mph]": t["initial_speed_mph"]})


def emission_table(rng: np.random.Generator | None = None) -> pd.DataFrame:
    """Particle emission per tyre vs longitudinal force (quadratic truth, minimum at F0 > 0)."""
    t = EMISSION_TRUTH
    rng = rng or np.random.default_rng(t["seed"])
    n = t["points_per_side"]
    brake = -np.sort(rng.uniform(20.0, t["force_max"], n))[::-1]
    drive = np.sort(rng.uniform(20.0, t["force_max"], n))
    f = np.concatenate([brake, drive])
    clean = t["a"] * (f - t["F0"]) ** 2 + t["N_min"]
    particles = clean * np.exp(t["noise"] * rng.standard_normal(f.size)) \
        + t["floor_noise"] * np.abs(rng.standard_normal(f.size))
    return pd.DataFrame({"fx [N]": np.round(f, 1), "particles [#/s]": np.round(particles, 1)})


def _csv(df: pd.DataFrame, what: str, seed: int) -> str:
    head = (f"# synthetic: generated by tyrefit.synthetic.vehicle_tyres, seed {seed}\n"
            f"# {what}\n")
    return head + df.to_csv(index=False, lineterminator="\n")


def truth_dict() -> dict:
    """Every generating parameter (JSON-ready)."""
    return {
        "synthetic": "generated by tyrefit.synthetic.vehicle_tyres",
        "tyres": {k: {kk: vv for kk, vv in spec.items()} for k, spec in (("soft", SOFT), ("hard", HARD))},
        "loads_N": list(LOADS), "pressure_bar": PRESSURE_BAR, "speed_kmh": SPEED_KMH,
        "force_noise_of_peak": FORCE_NOISE, "load_noise": LOAD_NOISE,
        "utqg": UTQG_TRUTH,
        "emission": {**EMISSION_TRUTH, "eq14": {"a": EMISSION_TRUTH["a"],
                                                "b": -2 * EMISSION_TRUTH["a"] * EMISSION_TRUTH["F0"],
                                                "c": EMISSION_TRUTH["a"] * EMISSION_TRUTH["F0"] ** 2
                                                + EMISSION_TRUTH["N_min"]}},
    }


_README = """# data/sim — synthetic inputs of the tyre-emission simulation (Pham et al. 2025)

Everything here is **synthetic**, made by `tyrefit.synthetic.vehicle_tyres`
(`python -m tyrefit.synthetic --only sim`); its module docstring documents the
physics, the true parameters and the seeds (`truth.json` repeats them).

| file | what |
|---|---|
| `soft_tyre.csv` | soft 235/45R18 stand-in: slip-angle sweeps (runs 1-4) and slip-ratio sweeps (runs 5-8), 2-6.5 kN |
| `hard_tyre.csv` | hard 205/60R15 stand-in (about 0.815 of the soft tyre's grip), same programme |
| `braking_utqg.csv` | 15 tyres: UTQG treadwear and dry 50-0 mph stopping distance (input of `tyrefit traction`) |
| `emission.csv` | particles per tyre vs longitudinal force (input of the Eq. 14 fit) |
| `soft_rear.tir`, `hard_front.tir` | the default tyres of `tyrefit sim`: PAC89 fits of the CSVs above by `tyrefit.fitting.fit_pac89` (see each file's header) |
| `truth.json` | the generating parameters |
"""


def fit_vehicle_tyres(data_dir: str | os.PathLike, out_dir: str | os.PathLike,
                      force: bool = False) -> dict[str, Path]:
    """Fit the hard and soft tyres from their rig data; write the default ``.tir`` files.

    Reads ``hard_tyre.csv`` and ``soft_tyre.csv`` in ``data_dir`` (slip-angle
    and slip-ratio sweeps), fits each with :func:`tyrefit.fitting.fit_pac89`
    (what ``tyrefit fit`` runs; lateral a0-a13 from the slip-angle sweeps,
    longitudinal b0-b10 from the slip-ratio sweeps) with the tyres' design
    data, and writes ``hard_front.tir`` and ``soft_rear.tir`` to ``out_dir``.

    Returns
    -------
    dict
        ``{'front': path, 'rear': path}``.
    """
    data_dir, out_dir = Path(data_dir), Path(out_dir)
    targets = {"front": out_dir / DEFAULT_FRONT, "rear": out_dir / DEFAULT_REAR}
    for p in targets.values():
        check_output(p, force)
    out = {}
    for role, which in (("front", "hard"), ("rear", "soft")):
        info = dict(_DESIGN[which])
        path = data_dir / f"{which}_tyre.csv"
        info["header"] = [f"{'front (hard, low-wear)' if role == 'front' else 'rear (soft)'} tyre of tyrefit sim; "
                          "data SYNTHETIC, generated by tyrefit.synthetic.vehicle_tyres"]
        tyre = fit_pac89(read_data(path), tyre_info=info).tyre
        missing = [part for part, ok in (("lateral", tyre.has_lateral), ("longitudinal", tyre.has_longitudinal))
                   if not ok]
        if missing:
            raise DataError(f"{path}: the fit has no {' and no '.join(missing)} coefficients; the simulation "
                            "needs slip-angle and slip-ratio sweeps")
        out[role] = tyre.to_tir(targets[role], force=force)
    return out


#: design data of the two synthetic tyres (sizes of Pham et al.'s MATLAB tyres)
_DESIGN = {
    "soft": {"name": "tyrefit soft 235/45R18 (synthetic data)", "unloaded_radius": 0.3344, "width": 0.235,
             "fnomin": 6573.0},
    "hard": {"name": "tyrefit hard 205/60R15 (synthetic data)", "unloaded_radius": 0.3135, "width": 0.205,
             "fnomin": 6031.0},
}


def generate(out_dir: Path, fit: bool = True) -> list[Path]:
    """Write the synthetic simulation inputs to ``out_dir``; return the files written.

    The generator is deterministic (same seeds, same bytes).  With ``fit``
    (default) and when :mod:`tyrefit.fitting` is available, the default
    ``.tir`` files of ``tyrefit sim`` are refitted from the new CSVs
    (:func:`fit_vehicle_tyres`).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files: list[Path] = []
    for which, spec in (("soft", SOFT), ("hard", HARD)):
        what = (f"{spec['name']}: free-rolling slip-angle sweeps (runs 1-4) and slip-ratio sweeps at zero slip "
                f"angle (runs 5-8), {PRESSURE_BAR} bar, {SPEED_KMH:g} km/h, ISO-W signs")
        files.append(write_text(out / f"{which}_tyre.csv", _csv(tyre_table(which), what, spec["seed"]), force=True))
    files.append(write_text(out / "braking_utqg.csv",
                            _csv(utqg_table(), "UTQG treadwear grades and dry 50-0 mph stopping distances "
                                 "(Tire Rack style), 15 tyres", UTQG_TRUTH["seed"]), force=True))
    files.append(write_text(out / "emission.csv",
                            _csv(emission_table(), "tyre-wear particle emission per tyre vs longitudinal force "
                                 "(braking negative, traction positive)", EMISSION_TRUTH["seed"]), force=True))
    files.append(write_text(out / "truth.json", json.dumps(truth_dict(), indent=2) + "\n", force=True))
    files.append(write_text(out / "README.md", _README, force=True))
    if fit:
        files += list(fit_vehicle_tyres(out, out, force=True).values())
    return files
