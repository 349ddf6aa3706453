"""Diagnose's last word on what is left knows correlated noise (issue 24).

Under AR(1) noise the within-sweep spline floor sees about half the true sigma, so a model with nothing
missing ends well above it.  Diagnose must then not call the excess "rig drift" (nor "nothing left")
on its say-so: repeated sweeps measure the noise itself (the model's error cancels between them);
without repeats the verdict is "undecided" and names the repeat test that decides.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from tyrefit.diagnose import diagnose
from tyrefit.diagnose.stats import repeat_noise
from tyrefit.synthetic.validation.cases import make_case

DEG = np.pi / 180.0


def _ar1(n_sweeps, n, rho, sigma, rng):
    e = np.empty((n_sweeps, n))
    e[:, 0] = rng.normal(0, sigma, n_sweeps)
    for i in range(1, n):
        e[:, i] = rho * e[:, i - 1] + rng.normal(0, sigma * np.sqrt(1 - rho**2), n_sweeps)
    return e


@pytest.mark.parametrize("rho", [0.0, 0.8, 0.9])
def test_repeat_noise_sees_the_noise_and_not_the_misfit(rho):
    """Residuals = a large smooth misfit per condition cell + AR(1) noise: the repeats give sigma."""
    rng = np.random.default_rng(7)
    a = np.linspace(-12, 12, 49) * DEG
    cells, reps, sigma = 6, 2, 40.0
    noise = _ar1(cells * reps, a.size, rho, sigma, rng)
    misfit = 300.0 * np.sin(3 * a)[None, :] * np.linspace(-1, 1, cells)[:, None]
    r = (np.repeat(misfit, reps, axis=0) + noise).ravel()
    sweep = np.repeat(np.arange(cells * reps), a.size)
    cell = np.repeat(np.arange(cells).repeat(reps), a.size)
    out = repeat_noise(np.tile(a, cells * reps), r, sweep, cell)
    assert out["pairs"] == cells and out["cells"] == cells
    # one realisation of 6 x 49 AR(1) points: the sd is estimated within sampling error, not misfit-inflated
    assert out["sd_N"] == pytest.approx(sigma, rel=0.35 if rho else 0.15)
    assert repeat_noise(np.tile(a, cells), r[: cells * a.size], sweep[: cells * a.size] // 2 * 2 // 2,
                        np.repeat(np.arange(cells), a.size)) is None  # no cell swept twice


def _record(noise, seed, repeats):
    parts = []
    for k in range(repeats):
        df = make_case("load6", noise, None, seed, repeat=k).data.copy()
        df["run"] = df["run"] + 100 * k
        parts.append(df)
    return pd.concat(parts, ignore_index=True)


@pytest.mark.parametrize("seed", [0, 1])
def test_nothing_missing_under_ar1_noise(seed):
    # no repeats: the excess over the within-sweep floor cannot be told from a misfit; the verdict says so
    dg = diagnose(_record("ar1", seed, 1), rated_load=6000.0, seed=seed)
    u = dg.unexplained
    ratio = dg.steps[-1].rmse_heldout / dg.noise_floor
    assert ratio > 1.5  # the within-sweep floor is blind to the correlated part
    assert u["verdict"] == "undecided" and "twice" in u["summary"] and "rig drift" not in u["summary"]
    # the same test run twice: the repeats measure the noise, and the model ends inside it
    dg2 = diagnose(_record("ar1", seed, 2), rated_load=6000.0, seed=seed)
    u2 = dg2.unexplained
    assert u2["repeat_noise"]["pairs"] == 6
    assert u2["repeat_noise"]["sd_N"] == pytest.approx(40.0, rel=0.3)
    assert u2["verdict"] == "noise", u2["summary"]
    assert dg2.to_dict()["unexplained"]["verdict"] == "noise"
