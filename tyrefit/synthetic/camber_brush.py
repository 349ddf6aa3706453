"""Synthetic contact-patch and force data of a cambered tyre from the camber brush model (Zhang et al. 2024).

**Everything this module writes is synthetic**: it evaluates tyrefit's
improved camber brush model (:mod:`tyrefit.models.brush`, Zhang et al. 2024)
with the parameters :data:`tyrefit.models.brush.DEFAULT_PARAMS` (a plausible
205/55R16 at 4821 N and 240 kPa chosen by tyrefit, not values from the
paper) and adds seeded noise.  No file in ``data/brush/`` is a measurement.
Use it to exercise the brush fits and as camber test data whose physics is
known (camber thrust from the parabolic bristle deflection plus the load
shift across the width).

Files written by :func:`generate`
---------------------------------
``patch.csv``
    contact-patch length and width (Eq. 1 and the strips' Eq. 11) at 4, 5
    and 6 kN, 180/240/300 kPa, camber 0-6 deg: ``fz [N]``, ``pressure [kPa]``,
    ``camber [deg]``, ``length [mm]``, ``width [mm]``; noise 0.5 mm on both.
``lateral.csv``
    free-rolling slip-angle sweeps -12..12 deg (25 points) at 3.0/4.5/6.0 kN
    and camber -6, -3, 0, 3, 6 deg, 240 kPa, mu = 1: ``run``, ``load [N]``,
    ``camber [deg]``, ``pressure [kPa]``, ``slip_angle [deg]``, ``fz [N]``,
    ``fy [N]`` (ISO-W); noise 0.5 % of the load on fy, 0.3 % on fz.
``longitudinal.csv``
    slip-ratio sweeps -0.3..0.3 (25 points) at the same loads, camber 0 and
    6 deg: ``run``, ``load [N]``, ``camber [deg]``, ``pressure [kPa]``,
    ``slip_ratio [-]``, ``fz [N]``, ``fx [N]``; same noise.
``truth.json``
    the model parameters.

The model uses 2N = 20 strips.  Seeds: patch 3101, lateral 3102, longitudinal 3103.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from ..io.outputs import write_text
from ..models import brush as bm

__all__ = ["generate", "patch_table", "lateral_table", "longitudinal_table", "camber_sweep", "N_STRIPS"]

#: half the number of strips of the generating model
N_STRIPS = 10
_NOISE_F = 0.005
_NOISE_FZ = 0.003


def camber_sweep(fz=(3000.0, 4500.0, 6000.0), camber_deg=(-6.0, -3.0, 0.0, 3.0, 6.0),
                 slip_angle_deg=np.linspace(-12, 12, 25), pressure: float = 240e3, mu: float = 1.0,
                 params: bm.BrushParams = bm.DEFAULT_PARAMS, noise: float = 0.0, seed: int = 0,
                 n: int = N_STRIPS) -> pd.DataFrame:
    """Fy(alpha, gamma, Fz) of the improved camber brush model as a tidy SI DataFrame.

    One run per (load, camber); columns ``run``, ``load``, ``fz`` [N],
    ``camber``, ``slip_angle`` [rad], ``pressure`` [Pa], ``fy`` [N] (ISO-W).
    ``noise`` is the standard deviation of fy as a fraction of the load
    (``fz`` then scatters by 0.6 x that).
    """
    rng = np.random.default_rng(seed)
    rows = []
    run = 0
    for load in fz:
        for g in camber_deg:
            run += 1
            a = np.deg2rad(np.asarray(slip_angle_deg, float))
            fy = bm.camber_brush_lateral_force(load, a, np.deg2rad(g), pressure, mu, params, n)
            fz_meas = load * (1 + 0.6 * noise * rng.standard_normal(a.size))
            rows.append(pd.DataFrame({"run": run, "load": load, "fz": fz_meas, "camber": np.deg2rad(g),
                                      "slip_angle": a, "pressure": pressure,
                                      "fy": fy + noise * load * rng.standard_normal(a.size)}))
    return pd.concat(rows, ignore_index=True)


def patch_table(rng=None, params: bm.BrushParams = bm.DEFAULT_PARAMS) -> pd.DataFrame:
    """Contact-patch length and width (file units)."""
    rng = np.random.default_rng(3101) if rng is None else rng
    F, P, G = np.meshgrid([4000.0, 5000.0, 6000.0], [180e3, 240e3, 300e3], np.deg2rad([0, 2, 4, 6]), indexing="ij")
    F, P, G = F.ravel(), P.ravel(), G.ravel()
    L = bm.contact_length(params, F, P, G, N_STRIPS)
    W = 2 * bm.contact_half_width(params, F, P, G)
    return pd.DataFrame({"fz [N]": F, "pressure [kPa]": P / 1e3, "camber [deg]": np.round(np.rad2deg(G), 3),
                         "length [mm]": np.round(L * 1e3 + 0.5 * rng.standard_normal(F.size), 2),
                         "width [mm]": np.round(W * 1e3 + 0.5 * rng.standard_normal(F.size), 2)})


def lateral_table(rng=None) -> pd.DataFrame:
    """Slip-angle sweeps at three loads and five cambers (file units)."""
    df = camber_sweep(noise=_NOISE_F, seed=3102)
    return pd.DataFrame({"run": df["run"], "load [N]": df["load"], "camber [deg]": np.round(np.rad2deg(df["camber"]), 3),
                         "pressure [kPa]": df["pressure"] / 1e3, "slip_angle [deg]": np.round(np.rad2deg(df["slip_angle"]), 4),
                         "fz [N]": np.round(df["fz"], 1), "fy [N]": np.round(df["fy"], 1)})


def longitudinal_table(rng=None, params: bm.BrushParams = bm.DEFAULT_PARAMS) -> pd.DataFrame:
    """Slip-ratio sweeps at three loads, camber 0 and 6 deg (file units)."""
    rng = np.random.default_rng(3103) if rng is None else rng
    rows = []
    run = 0
    kap = np.linspace(-0.3, 0.3, 25)
    for load in (3000.0, 4500.0, 6000.0):
        for g in (0.0, 6.0):
            run += 1
            fx = bm.camber_brush_forces(params, load, kap, 0.0, np.deg2rad(g), n=N_STRIPS).fx
            rows.append(pd.DataFrame({"run": run, "load [N]": load, "camber [deg]": g, "pressure [kPa]": 240.0,
                                      "slip_ratio [-]": np.round(kap, 4),
                                      "fz [N]": np.round(load * (1 + _NOISE_FZ * rng.standard_normal(kap.size)), 1),
                                      "fx [N]": np.round(fx + _NOISE_F * load * rng.standard_normal(kap.size), 1)}))
    return pd.concat(rows, ignore_index=True)


def _csv(df, what, seed):
    return (f"# synthetic: generated by tyrefit.synthetic.camber_brush, seed {seed}\n# {what}\n"
            + df.to_csv(index=False, lineterminator="\n"))


_README = """# data/brush — synthetic camber brush model data (Zhang et al. 2024)

Everything here is **synthetic**, made by `tyrefit.synthetic.camber_brush` from
tyrefit's improved camber brush model (`tyrefit.models.brush`, Zhang et al. 2024)
with illustrative 205/55R16 parameters (`truth.json`) and seeded noise.

- `patch.csv`: contact length and width vs load, pressure, camber (Eq. 1, 11).
- `lateral.csv`: Fy vs slip angle at 3 loads x 5 cambers (-6..6 deg), mu = 1.
- `longitudinal.csv`: Fx vs slip ratio at 3 loads, camber 0 and 6 deg.
"""


def generate(out_dir: Path) -> list[Path]:
    """Write the synthetic camber brush data to ``out_dir``; return the files (deterministic)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = [
        write_text(out / "patch.csv", _csv(patch_table(), "contact patch vs load, pressure and camber "
                                           "(camber brush model, Zhang et al., Eq. 1, 11)", 3101), force=True),
        write_text(out / "lateral.csv", _csv(lateral_table(), "Fy sweeps, camber -6..6 deg, 240 kPa, mu = 1, ISO-W "
                                             "(camber brush model, Zhang et al. 2024)", 3102), force=True),
        write_text(out / "longitudinal.csv", _csv(longitudinal_table(), "Fx sweeps, camber 0 and 6 deg, 240 kPa, "
                                                  "mu = 1 (camber brush model, Zhang et al. 2024)", 3103), force=True),
        write_text(out / "truth.json", json.dumps({"synthetic": "generated by tyrefit.synthetic.camber_brush",
                                                   "model": "improved camber brush, 2N = %d" % (2 * N_STRIPS),
                                                   "mu": 1.0, "params": bm.DEFAULT_PARAMS.as_dict()}, indent=2) + "\n",
                   force=True),
        write_text(out / "README.md", _README, force=True),
    ]
    return files
