"""Synthetic slip-ratio and rolling-radius data for ``tyrefit slip`` (Ghasemi et al. 2021).

**Everything this module writes is synthetic** -- made from the laws of
Ghasemi, Vantsevich et al. 2021 (*Physics based single-wheel module slippage
assessment*) with the parameters below and seeded noise.  No file in
``data/slip/`` is a measurement.

Files written by :func:`generate`
---------------------------------
``slip_ratio.csv``
    traction and braking sweeps of a passenger tyre at three loads (3.0, 4.5,
    6.0 kN): ``run``, ``load [kN]``, ``speed [km/h]``, ``slip_ratio [-]``,
    ``fz [N]``, ``fx [N]``; slip -0.5..0.5 in 81 steps.
``rolling_radius.csv``
    one traction sweep at 4.5 kN with the wheel torque and the instantaneous
    rolling radius: ``run``, ``load [kN]``, ``slip_ratio [-]``, ``fz [N]``,
    ``fx [N]``, ``torque [N*m]``, ``rolling_radius [mm]``; slip 0..0.3 at 61 points
    spaced quadratically (denser at small slip, where Eq. 19 is linear).
``truth.json``
    every parameter below.

The truth
---------
Friction (Ghasemi et al., Eq. 8): ``mu = mu_p (1 - exp(-k s))``, odd in s, with
``mu_p = 0.90 (Fz / 4.5 kN)^-0.08`` (friction falls with load) and
``k = 20 (Fz / 4.5 kN)^-0.25``; so at 3.0 / 4.5 / 6.0 kN mu_p = 0.930 /
0.900 / 0.880 and k = 22.13 / 20.00 / 18.61, and with nu_c = -2 the
characteristic slip (Eq. 16) is 0.245 / 0.260 / 0.270.

Measurement model: ``fz`` scatters by 0.5 % (Gaussian) about the set point;
``fx = mu(s) fz_true + noise`` with a noise of 0.008 fz_true (Gaussian).
The slip column is the paper's slippage s = 1 - v/(r0 omega).

Rolling radius (Ghasemi et al., Eq. 5, 19-20): the wheel torque is quasi-static,
``T = r0 Fx`` with r0 = 0.305 m, and the kinematic rolling radius
``r = v / omega = r0 (1 - s)`` (Eq. 20), so the elasticity factor
``lambda_w = r0 s / T = s / (mu(s) Fz)`` starts at ``1 / (mu_p k Fz)`` =
1.235e-5 m/(N m) and grows with torque (the nonlinear f of Eq. 18).
Noise: 1 % on the torque, 0.3 mm on the radius.

Seeds: slip-ratio sweeps 2002, rolling radius 2003.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from ..io.outputs import write_text
from ..models import slip as sl

__all__ = ["generate", "TRUTH", "mu_peak_at", "k_at", "slip_ratio_table", "rolling_radius_table"]

TRUTH = {
    "mu_peak_ref": 0.90,
    "mu_peak_exponent": -0.08,
    "k_ref": 20.0,
    "k_exponent": -0.25,
    "fz_ref_N": 4500.0,
    "loads_N": [3000.0, 4500.0, 6000.0],
    "slip_range": [-0.5, 0.5],
    "slip_points": 81,
    "fz_scatter": 0.005,
    "mu_noise": 0.008,
    "speed_kmh": 30.0,
    "seed": 2002,
    "radius": {"r0_m": 0.305, "fz_N": 4500.0, "slip_range": [0.0, 0.3], "slip_points": 61,
               "torque_noise": 0.01, "radius_noise_m": 3e-4, "seed": 2003},
}


def mu_peak_at(fz):
    """True peak friction coefficient at load ``fz`` [N]."""
    return TRUTH["mu_peak_ref"] * (np.asarray(fz, float) / TRUTH["fz_ref_N"]) ** TRUTH["mu_peak_exponent"]


def k_at(fz):
    """True slip factor k at load ``fz`` [N]."""
    return TRUTH["k_ref"] * (np.asarray(fz, float) / TRUTH["fz_ref_N"]) ** TRUTH["k_exponent"]


def slip_ratio_table(rng: np.random.Generator | None = None) -> pd.DataFrame:
    """Slip sweeps at the three loads, in the file's units (load kN, speed km/h)."""
    rng = np.random.default_rng(TRUTH["seed"]) if rng is None else rng
    s = np.linspace(*TRUTH["slip_range"], TRUTH["slip_points"])
    rows = []
    for run, load in enumerate(TRUTH["loads_N"], start=1):
        fz = load * (1 + TRUTH["fz_scatter"] * rng.standard_normal(s.size))
        mu = sl.friction(s, mu_peak_at(load), k_at(load))
        fx = mu * load + TRUTH["mu_noise"] * load * rng.standard_normal(s.size)
        rows.append(pd.DataFrame({"run": run, "load [kN]": load / 1e3, "speed [km/h]": TRUTH["speed_kmh"],
                                  "slip_ratio [-]": np.round(s, 5), "fz [N]": np.round(fz, 1),
                                  "fx [N]": np.round(fx, 1)}))
    return pd.concat(rows, ignore_index=True)


def rolling_radius_table(rng: np.random.Generator | None = None) -> pd.DataFrame:
    """One traction sweep with wheel torque and rolling radius (file units)."""
    R = TRUTH["radius"]
    rng = np.random.default_rng(R["seed"]) if rng is None else rng
    lo, hi = R["slip_range"]
    s = lo + (hi - lo) * np.linspace(0.0, 1.0, R["slip_points"]) ** 2  # denser at small slip
    load, r0 = R["fz_N"], R["r0_m"]
    fz = load * (1 + TRUTH["fz_scatter"] * rng.standard_normal(s.size))
    fx = sl.friction(s, mu_peak_at(load), k_at(load)) * load
    torque = r0 * fx * (1 + R["torque_noise"] * rng.standard_normal(s.size))  # Ghasemi et al., Eq. 5
    radius = r0 * (1 - s) + R["radius_noise_m"] * rng.standard_normal(s.size)  # Eq. 20: r0 - r = r0 s
    fx_meas = fx + TRUTH["mu_noise"] * load * rng.standard_normal(s.size)
    return pd.DataFrame({"run": 1, "load [kN]": load / 1e3, "slip_ratio [-]": np.round(s, 5),
                         "fz [N]": np.round(fz, 1), "fx [N]": np.round(fx_meas, 1),
                         "torque [N*m]": np.round(torque, 2), "rolling_radius [mm]": np.round(radius * 1e3, 3)})


def _csv(df: pd.DataFrame, what: str, seed: int) -> str:
    return (f"# synthetic: generated by tyrefit.synthetic.slip, seed {seed}\n# {what}\n"
            + df.to_csv(index=False, lineterminator="\n"))


_README = """# data/slip — synthetic slip-ratio and rolling-radius data (Ghasemi et al. 2021)

Everything here is **synthetic**, made by `tyrefit.synthetic.slip`
(`python -m tyrefit.synthetic --only slip`); its module docstring documents the
laws, the true parameters and the seeds (`truth.json` repeats them).

- `slip_ratio.csv`: traction/braking sweeps at 3.0, 4.5 and 6.0 kN, mu = mu_p (1 - exp(-k s)).
- `rolling_radius.csv`: one traction sweep with wheel torque and rolling radius (Eq. 19-20).

Try: `tyrefit slip data/slip/slip_ratio.csv --json slip.json --report reports/slip`.
"""


def generate(out_dir: Path) -> list[Path]:
    """Write the synthetic slip data to ``out_dir``; return the files written (deterministic)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = [
        write_text(out / "slip_ratio.csv", _csv(slip_ratio_table(), "slip-ratio sweeps at 3.0/4.5/6.0 kN, "
                                                "mu = mu_p (1 - exp(-k s)) (Ghasemi et al., Eq. 8)", TRUTH["seed"]),
                   force=True),
        write_text(out / "rolling_radius.csv", _csv(rolling_radius_table(), "traction sweep at 4.5 kN with wheel "
                                                    "torque and rolling radius (Ghasemi et al., Eq. 19-20)",
                                                    TRUTH["radius"]["seed"]), force=True),
    ]
    truth = {"synthetic": "generated by tyrefit.synthetic.slip", **TRUTH,
             "per_load": [{"fz_N": f, "mu_peak": float(mu_peak_at(f)), "k": float(k_at(f)),
                           "characteristic_slip": float(sl.characteristic_slip(mu_peak_at(f), k_at(f))),
                           "characteristic_mu": float(sl.characteristic_mu(mu_peak_at(f), k_at(f)))}
                          for f in TRUTH["loads_N"]]}
    files.append(write_text(out / "truth.json", json.dumps(truth, indent=2) + "\n", force=True))
    files.append(write_text(out / "README.md", _README, force=True))
    return files
