"""Fit cases that can mislead a fit into a confident wrong tyre, made from a clean, known tyre.

Each case starts from clean slip-angle sweeps of the PAC89 example set
(:mod:`tyrefit.synthetic.pac89_example`: Fz 2-8 kN, camber -2/0/+2 deg,
-12..12 deg in 0.25 deg steps, 1 % Gaussian noise of each sweep's peak,
ISO-W signs) and damages it the way real rig files are damaged:

* ``spikes``: 5 samples multiplied by 100 (a logger glitch in the force channel);
* ``fz_glitch_high`` / ``fz_glitch_low``: one sample's measured load times 10 /
  divided by 100 (a glitch in the load channel, force untouched);
* ``liftoff``: one sample's load is 0.5 N (the wheel lifted off; force untouched);
* ``sign_flip``: the force and moment negated (the file was in another
  convention; a normal tyre then looks like one whose force rises with slip);
* ``load_ramp``: no ``run`` column, the load ramps through 40 steps while the
  slip angle sweeps, so a sweep at one load is a slice of a slip sweep;
* ``tiny_sweeps``: 20,000 sweeps of 5 samples each (a ``run`` column that counts
  samples in fives, as some loggers' block counters do).

:func:`tyre_error` measures a fitted tyre against the generating one (RMS of
the Fy difference over a grid of loads, slip angles and cambers, in % of the
peak), so a case's damage is the ratio of its error to the clean fit's.
Used by ``benchmarks/confident_wrong.py`` and ``tests/test_robust_fit.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..models import pac89
from .pac89_example import EXAMPLE, lateral_sweeps

__all__ = ["clean", "CASES", "make_case", "tyre_error"]

SEED = 1515


def clean(seed: int = SEED) -> pd.DataFrame:
    """Clean lateral sweeps (SI, ISO-W): 4 loads x 3 cambers, 97 points each."""
    return lateral_sweeps(cambers_deg=(-2.0, 0.0, 2.0), seed=seed)


def _spikes(df, rng):
    i = rng.choice(len(df), 5, replace=False)
    df.loc[df.index[i], "fy"] *= 100.0
    return df


def _fz_glitch(factor):
    def f(df, rng):
        i = rng.integers(len(df))
        df.loc[df.index[i], "fz"] *= factor
        return df
    return f


def _liftoff(df, rng):
    i = rng.integers(len(df))
    df.loc[df.index[i], "fz"] = 0.5
    return df


def _sign_flip(df, rng):
    df["fy"] = -df["fy"]
    df["mz"] = -df["mz"]
    return df


def _load_ramp(df, rng):
    """4 slip sweeps while the load ramps 2 -> 8 kN in 40 steps; no run column."""
    sa = np.radians(np.arange(-12.0, 12.0 + 1e-9, 0.25))
    slip = np.tile(sa, 4)
    steps = np.repeat(np.linspace(2000.0, 8000.0, 40), math.ceil(slip.size / 40))[: slip.size]
    fy = pac89.lateral_force(EXAMPLE, steps, slip, 0.0)
    fy = fy + rng.normal(0.0, 0.01 * 7000.0, slip.size)  # 1 % of a mid-range peak
    return pd.DataFrame({"fz": steps, "camber": 0.0, "slip_angle": slip, "fy": fy})


def _tiny_sweeps(df, rng):
    """20,000 sweeps of 5 points: the clean sweeps repeated, with a run id that counts in fives."""
    reps = math.ceil(100_000 / len(df))
    big = pd.concat([df] * reps, ignore_index=True).iloc[:100_000].copy()
    big["fy"] = big["fy"] + rng.normal(0.0, 0.01 * np.abs(big["fy"]).max(), len(big))
    big["run"] = np.arange(len(big)) // 5
    return big


CASES = {
    "spikes": _spikes,
    "fz_glitch_high": _fz_glitch(10.0),
    "fz_glitch_low": _fz_glitch(0.01),
    "liftoff": _liftoff,
    "sign_flip": _sign_flip,
    "load_ramp": _load_ramp,
    "tiny_sweeps": _tiny_sweeps,
}


def make_case(name: str, seed: int = SEED) -> pd.DataFrame:
    """The clean data damaged as case ``name`` (see the module docstring)."""
    if name == "clean":
        return clean(seed)
    rng = np.random.default_rng(seed + 1)
    return CASES[name](clean(seed).copy(), rng)


def tyre_error(coefficients, loads=np.linspace(2000.0, 8000.0, 7), cambers_deg=(0.0,)) -> float:
    """RMS of (fitted - true) Fy over loads x slip -12..12 deg (camber 0: every case has it), % of the true peak."""
    sa = np.radians(np.linspace(-12.0, 12.0, 97))
    se, peak = [], 0.0
    for fz in loads:
        for g in cambers_deg:
            ft = pac89.lateral_force(EXAMPLE, fz, sa, math.radians(g))
            ff = pac89.lateral_force(coefficients, fz, sa, math.radians(g))
            se.append(np.mean((ff - ft) ** 2))
            peak = max(peak, float(np.max(np.abs(ft))))
    return 100.0 * math.sqrt(float(np.mean(se))) / peak
