"""**Synthetic** passenger-car tyre (205/55 R16 91V) cornering tests for the diagnose demo.

Nothing written here is a measurement.  The generator imitates a flat-track
cornering programme on a passenger-car tyre so that ``tyrefit diagnose`` has a
data set with load, camber and pressure sweeps whose hidden truth is known:
the demo report should find the effects below, one by one, and nothing else.

Test programme
--------------
Loads 2.0, 3.5, 5.0, 6.5 kN (the 91 load index rates the tyre at 615 kg =
6031 N, so the highest load is 8 % over the rating), cambers -4, -2, 0, +2,
+4 deg, inflation pressures 200, 230, 260 kPa, 60 km/h: 60 conditions, one
slip-angle sweep -12 -> +12 deg per condition at 0.25 deg steps (97 points,
5820 points in all).  Signs ISO-W: a positive slip angle gives a negative
lateral force.

Hidden truth (PAC89 lateral coefficients in PAC89 units: kN, deg, N)
--------------------------------------------------------------------
* base PAC89: a0 = 1.40, a2 = 1150 N/kN, a3 = 1700 N/deg, a4 = 9.5 kN,
  a7 = -0.4 (about 76 kN/rad of cornering stiffness at 4 kN);
* ``load_friction``: a1 = -22 N/kN^2 (peak mu 1.11 at 2 kN, 1.01 at 6.5 kN);
* ``camber``: a5 = 0.008 1/deg (stiffness -3.2 % at 4 deg), a8 = 0.04 deg/deg,
  a11 = 14 N/(kN deg) (camber thrust 1.4 % of Fz per degree);
* ``pressure`` (not a PAC89 term; MF 6.1-style about the 230 kPa reference):
  pressure_ky = 0.45 (cornering stiffness +5.9 % at 260 kPa),
  pressure_mu = -0.25 (peak mu -3.3 % at 260 kPa);
* ``offsets_constant``: ply steer / conicity a10 = 0.06 deg, a13 = 35 N;
* nothing else: no overload fall, no load-dependent curvature (a6 = 0),
  a9 = a12 = 0.

Measurement imperfections
-------------------------
The measured load jitters 0.5 % (1 sigma) around the set point; the slip
angle carries 0.02 deg of noise; the lateral force carries independent noise
(20 N), a slowly varying AR(1) error along each sweep (correlation 0.85
between neighbouring points, 15 N) and a random offset per sweep (8 N): about
26 N in all, 0.4-1.3 % of the load.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from ..effects import ModelInputs
from ..effects import lateral_force as extended_lateral_force
from ..io.outputs import write_text

__all__ = ["SEED", "TRUTH", "EFFECTS_PRESENT", "RATED_LOAD", "PROGRAMME", "make_data", "generate"]

SEED = 205551691
_DEG = np.pi / 180.0
#: rated load of a 91 load-index tyre [N]
RATED_LOAD = 615.0 * 9.80665
#: effects present in the hidden truth
EFFECTS_PRESENT = ("load_friction", "camber", "pressure", "offsets_constant")
#: the hidden truth (PAC89 units; pressure terms about the reference pressure)
TRUTH = {"a0": 1.40, "a1": -22.0, "a2": 1150.0, "a3": 1700.0, "a4": 9.5, "a5": 0.008, "a7": -0.4,
         "a8": 0.04, "a10": 0.06, "a11": 14.0, "a13": 35.0, "pressure_ky": 0.45, "pressure_mu": -0.25}
PROGRAMME = {"loads_N": [2000.0, 3500.0, 5000.0, 6500.0], "cambers_deg": [-4.0, -2.0, 0.0, 2.0, 4.0],
             "pressures_kPa": [200.0, 230.0, 260.0], "pressure_ref_kPa": 230.0, "speed_kmh": 60.0,
             "slip_max_deg": 12.0, "slip_step_deg": 0.25}
NOISE = {"iid_N": 20.0, "ar1_N": 15.0, "ar1_rho": 0.85, "sweep_offset_N": 8.0, "fz_rel": 0.005,
         "slip_deg": 0.02}


def make_data(seed: int = SEED) -> pd.DataFrame:
    """The cornering programme as a DataFrame in SI (``run``, ``fz``, ``slip_angle``,
    ``camber``, ``pressure``, ``speed``, ``fy``), ISO-W signs."""
    rng = np.random.default_rng(seed)
    pr = PROGRAMME
    slips = np.arange(-pr["slip_max_deg"], pr["slip_max_deg"] + 1e-9, pr["slip_step_deg"]) * _DEG
    frames = []
    run = 0
    for p in pr["pressures_kPa"]:
        for c in pr["cambers_deg"]:
            for fz in pr["loads_N"]:
                n = len(slips)
                e = np.empty(n)
                e[0] = rng.normal(0, NOISE["ar1_N"])
                innov = rng.normal(0, NOISE["ar1_N"] * np.sqrt(1 - NOISE["ar1_rho"] ** 2), n)
                for i in range(1, n):
                    e[i] = NOISE["ar1_rho"] * e[i - 1] + innov[i]
                noise = e + rng.normal(0, NOISE["iid_N"], n) + rng.normal(0, NOISE["sweep_offset_N"])
                frames.append(pd.DataFrame({
                    "run": run, "fz_true": fz * (1 + NOISE["fz_rel"] * rng.standard_normal(n)),
                    "slip_true": slips, "camber": c * _DEG, "pressure": p * 1e3, "speed": pr["speed_kmh"] / 3.6,
                    "noise": noise, "slip_noise": rng.normal(0, NOISE["slip_deg"] * _DEG, n)}))
                run += 1
    d = pd.concat(frames, ignore_index=True)
    x = ModelInputs(fz=d["fz_true"].to_numpy(), slip_angle=d["slip_true"].to_numpy(), camber=d["camber"].to_numpy(),
                    pressure=d["pressure"].to_numpy(), pressure_ref=pr["pressure_ref_kPa"] * 1e3)
    fy = extended_lateral_force(TRUTH, EFFECTS_PRESENT, x) + d["noise"].to_numpy()
    return pd.DataFrame({"run": d["run"], "fz": d["fz_true"], "slip_angle": d["slip_true"] + d["slip_noise"],
                         "camber": d["camber"], "pressure": d["pressure"], "speed": d["speed"], "fy": fy})


_README = """# data/passenger — synthetic passenger-car tyre cornering tests

**Synthetic.** Made by `tyrefit.synthetic.passenger.generate` (seed {seed}; physics,
programme and noise in that module's docstring and in `truth.json`). No file here
is a measurement.

| file | test |
|---|---|
| `passenger_205_55R16.csv` | slip-angle sweeps -12..+12 deg at 2.0/3.5/5.0/6.5 kN, cambers -4..+4 deg, 200/230/260 kPa, 60 km/h; ISO-W signs |
| `truth.json` | the hidden truth: PAC89 coefficients and the pressure terms |

The hidden truth holds degressive friction with load (`load_friction`), camber
thrust/shift/stiffness loss (`camber`), pressure on stiffness and grip (`pressure`)
and a small ply-steer/conicity offset (`offsets_constant`); nothing else. Rated load
{rated:.0f} N (load index 91). Try

    tyrefit diagnose data/passenger/passenger_205_55R16.csv --rated-load {rated:.0f} --json out.json --report reports/diagnose

Regenerate with `python -m tyrefit.synthetic --out data --only passenger`.
"""


def generate(out_dir: Path) -> list[Path]:
    """Write ``passenger_205_55R16.csv``, ``truth.json`` and ``README.md`` to ``out_dir``."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    d = make_data(SEED)
    frame = pd.DataFrame({
        "run": d["run"], "fz [N]": d["fz"].round(1), "slip_angle [deg]": (d["slip_angle"] / _DEG).round(3),
        "camber [deg]": (d["camber"] / _DEG).round(2), "pressure [kPa]": (d["pressure"] / 1e3).round(1),
        "speed [km/h]": (d["speed"] * 3.6).round(1), "fy [N]": d["fy"].round(1)})
    csv = (f"# synthetic: generated by tyrefit.synthetic.passenger, seed {SEED}\n"
           "# 205/55R16 91V passenger tyre, cornering sweeps; hidden truth in truth.json (not a measurement)\n"
           + frame.to_csv(index=False, lineterminator="\n"))
    paths = [write_text(out / "passenger_205_55R16.csv", csv, force=True)]
    truth = {"synthetic": "generated by tyrefit.synthetic.passenger", "seed": SEED, "tyre": "205/55R16 91V",
             "rated_load_N": RATED_LOAD, "effects_present": list(EFFECTS_PRESENT), "pac89_and_effects": TRUTH,
             "programme": PROGRAMME, "noise": NOISE,
             "effects_absent": ["overload", "curvature_load", "offsets (load-dependent a9, a12)", "speed"]}
    paths.append(write_text(out / "truth.json", json.dumps(truth, indent=2) + "\n", force=True))
    paths.append(write_text(out / "README.md", _README.format(seed=SEED, rated=RATED_LOAD), force=True))
    return paths
