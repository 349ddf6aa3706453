"""Catalogue-form cases for unit tests of ``tyrefit diagnose`` (synthetic data).

Everything here is **synthetic**: seeded generators that simulate cornering
tests on a tyre rig whose truth is the diagnose start model plus catalogue
effects, computed with the catalogue's own ``effects.lateral_force``.  That
makes these cases right for *parameter-recovery* and report tests (a fitted
catalogue coefficient can be compared with the one that made the data), and
wrong for *validating* the diagnosis: data made by the very functions the
diagnosis fits score it too well.  The validation - truths written
outside the catalogue, rig layouts with few sweeps, rates with confidence
intervals, mutation checks - is :mod:`tyrefit.synthetic.validation`
(``python -m tyrefit.synthetic.validation``); the suite runner that used to
live here is retired in its favour.

The truth model
---------------
A passenger-car tyre (about 205/55R16) in PAC89 (units kN, deg): C = a0 = 1.45,
a2 = 1100 N/kN (mu = 1.1), a3 = 1500 N/deg, a4 = 8 kN, a7 = -0.3, every other
lateral coefficient 0 -- exactly the diagnose start model -- plus at most two
hidden effects from :data:`EFFECT_SIZES` (typical real-tyre sizes):

============  =====================================================================
family        hidden truth
============  =====================================================================
load_friction a1 = -25 N/kN^2 (mu falls from 1.05 at 2 kN to 0.90 at 8 kN)
curvature_load a6 = -0.08 1/kN
overload      overload_mu = 0.45 above the rated load 6000 N (-15 % mu at 8 kN)
camber        a5 = 0.01 1/deg, a8 = 0.05 deg/deg, a11 = 15 N/(kN deg)
offsets       a9 = 0.02 deg/kN, a10 = 0.15 deg, a12 = 8 N/kN, a13 = 60 N
pressure      pressure_ky = 0.5, pressure_mu = -0.3 (reference: middle pressure)
speed         speed_mu = -0.12 (reference: the higher speed level)
============  =====================================================================

The rig grid
------------
Loads 2.0, 3.5, 5.0, 6.5, 8.0 kN (rated load 6.0 kN), cambers -3, 0, +3 deg,
pressures 200 and 240 kPa (speed case: 40 and 100 km/h at one pressure), one
slip sweep -12 -> +12 deg per condition at 0.5 deg steps (49 points); the
measured load jitters 0.5 % around the set point.  ``points_per_sweep`` makes
long records (FSAE TTC rigs log thousands of points per sweep).

Noise models (``sigma`` is the total standard deviation per point, 40 N)
------------------------------------------------------------------------
``iid``      independent Gaussian noise;
``offsets``  a random offset per sweep (0.6 sigma) plus independent noise (0.8 sigma);
``ar1``      Gaussian AR(1) noise along the sweep, correlation 0.9 between
             neighbouring points (stationary sd sigma).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..effects import ModelInputs, get_effect
from ..effects import lateral_force as extended_lateral_force

__all__ = ["TRUTH_BASE", "EFFECT_SIZES", "RATED_LOAD", "NOISE_MODELS", "Case", "rig_grid", "make_case", "generate"]

_DEG = np.pi / 180.0

#: base tyre (the diagnose start model), PAC89 units
TRUTH_BASE: dict[str, float] = {"a0": 1.45, "a2": 1100.0, "a3": 1500.0, "a4": 8.0, "a7": -0.3}
#: rated load of the simulated tyre [N]
RATED_LOAD = 6000.0
#: hidden effect -> its parameter values (typical real-tyre sizes)
EFFECT_SIZES: dict[str, dict[str, float]] = {
    "load_friction": {"a1": -25.0},
    "curvature_load": {"a6": -0.08},
    "overload": {"overload_mu": 0.45},
    "camber": {"a5": 0.01, "a8": 0.05, "a11": 15.0},
    "offsets": {"a9": 0.02, "a10": 0.15, "a12": 8.0, "a13": 60.0},
    "pressure": {"pressure_ky": 0.5, "pressure_mu": -0.3},
    "speed": {"speed_mu": -0.12},
}
NOISE_MODELS = ("iid", "offsets", "ar1")


@dataclass
class Case:
    """One generated data set with its hidden truth."""

    name: str
    truth: list[str]
    noise: str
    sigma: float
    seed: int
    data: pd.DataFrame
    rated_load: float = RATED_LOAD
    values: dict = field(default_factory=dict)

    @property
    def families(self) -> set[str]:
        return {get_effect(t).family for t in self.truth}


def rig_grid(loads=(2000.0, 3500.0, 5000.0, 6500.0, 8000.0), cambers_deg=(-3.0, 0.0, 3.0),
             pressures=(200e3, 240e3), speeds=(60 / 3.6,), slip_max_deg: float = 12.0,
             points_per_sweep: int = 49) -> pd.DataFrame:
    """Set points of a cornering test: one slip sweep per load x camber x pressure x speed.

    Returns a DataFrame with ``run``, ``fz`` [N] (set point), ``slip_angle``
    [rad], ``camber`` [rad], ``pressure`` [Pa], ``speed`` [m/s], sweep
    order preserved (slip from -max to +max).
    """
    slips = np.linspace(-slip_max_deg, slip_max_deg, points_per_sweep) * _DEG
    rows = []
    run = 0
    for p in pressures:
        for v in speeds:
            for c in cambers_deg:
                for fz in loads:
                    rows.append(pd.DataFrame({"run": run, "fz": fz, "slip_angle": slips, "camber": c * _DEG,
                                              "pressure": p, "speed": v}))
                    run += 1
    return pd.concat(rows, ignore_index=True)


def _noise(kind: str, sweep: np.ndarray, sigma: float, rng: np.random.Generator) -> np.ndarray:
    n = len(sweep)
    if kind == "iid":
        return rng.normal(0.0, sigma, n)
    if kind == "offsets":
        G = int(sweep.max()) + 1
        return rng.normal(0.0, 0.6 * sigma, G)[sweep] + rng.normal(0.0, 0.8 * sigma, n)
    if kind == "ar1":
        rho = 0.9
        e = rng.normal(0.0, sigma * np.sqrt(1 - rho**2), n)
        out = np.empty(n)
        for i in range(n):
            if i == 0 or sweep[i] != sweep[i - 1]:
                out[i] = rng.normal(0.0, sigma)
            else:
                out[i] = rho * out[i - 1] + e[i]
        return out
    raise ValueError(f"unknown noise model {kind!r}; known: {', '.join(NOISE_MODELS)}")


def make_case(truth=(), noise: str = "iid", seed: int = 0, sigma: float = 40.0, grid: pd.DataFrame | None = None,
              name: str | None = None, sizes: dict | None = None) -> Case:
    """Generate one data set: base tyre + ``truth`` effects + noise.

    Parameters
    ----------
    truth : sequence of str
        Hidden effect ids (keys of :data:`EFFECT_SIZES`, or any catalogue id
        with ``sizes`` given).
    noise : {'iid', 'offsets', 'ar1'}
    seed : int
    sigma : float
        Total noise standard deviation per point [N].
    grid : DataFrame, optional
        Set points (default :func:`rig_grid`; the speed case uses two speeds).
    """
    rng = np.random.default_rng(seed)
    truth = list(truth)
    if grid is None:
        if "speed" in truth:
            grid = rig_grid(pressures=(220e3,), speeds=(40 / 3.6, 100 / 3.6))
        else:
            grid = rig_grid()
    d = grid.copy()
    fz_levels = np.sort(d["fz"].unique())
    middle = d["fz"].to_numpy() == fz_levels[len(fz_levels) // 2]
    d["fz"] = d["fz"] * (1.0 + 0.005 * rng.standard_normal(len(d)))
    fz_ref = float(np.median(d["fz"].to_numpy()[middle]))  # the middle level's median load, as diagnose takes it
    values = dict(TRUTH_BASE)
    for t in truth:
        values.update((sizes or EFFECT_SIZES)[t])

    def ref(col):
        lv = np.sort(d[col].unique())
        return float(lv[len(lv) // 2])

    x = ModelInputs(fz=d["fz"].to_numpy(), slip_angle=d["slip_angle"].to_numpy(), camber=d["camber"].to_numpy(),
                    pressure=d["pressure"].to_numpy(), speed=d["speed"].to_numpy(), rated_load=RATED_LOAD,
                    pressure_ref=ref("pressure"), speed_ref=ref("speed"),
                    fz_ref=fz_ref)
    fy = extended_lateral_force(values, truth, x)
    sweep = pd.factorize(d["run"])[0]
    d["fy"] = fy + _noise(noise, sweep, sigma, rng)
    return Case(name=name or ("+".join(truth) or "null") + f"/{noise}/{seed}", truth=truth, noise=noise,
                sigma=sigma, seed=seed, data=d, values=values)


def generate(out_dir: Path) -> list[Path]:
    """Write one example case per family (iid noise) to ``out_dir`` as CSV; return the paths.

    The suite itself is generated in memory by the tests; these files only let
    a user run ``tyrefit diagnose`` on a known truth.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    for fam in ("overload",):
        case = make_case((fam,), "offsets", seed=7)
        d = case.data
        p = out_dir / f"hidden_{fam}.csv"
        frame = pd.DataFrame({
            "run": d["run"], "fz [N]": d["fz"].round(1), "slip_angle [deg]": (d["slip_angle"] / _DEG).round(3),
            "camber [deg]": (d["camber"] / _DEG).round(3), "pressure [kPa]": (d["pressure"] / 1e3).round(2),
            "speed [km/h]": (d["speed"] * 3.6).round(2), "fy [N]": d["fy"].round(1)})
        with open(p, "w", newline="\n") as fh:
            fh.write(f"# synthetic: generated by tyrefit.synthetic.hidden, seed {case.seed}\n")
            fh.write(f"# hidden truth: {fam} {EFFECT_SIZES[fam]}, rated load {RATED_LOAD:.0f} N, "
                     f"noise {case.noise} sigma {case.sigma:g} N\n")
            frame.to_csv(fh, index=False)
        paths.append(p)
    return paths
