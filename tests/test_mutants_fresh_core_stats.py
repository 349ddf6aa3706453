"""Tests that bite where a fresh mutation sample of fitting/core.py and diagnose/stats.py found the suite blind.

``python -m benchmarks.mutation --sample 36 --seed 15 --files tyrefit/fitting/core.py,tyrefit/diagnose/stats.py,
tyrefit/diagnose/engine.py`` on 8140e13 (the same draw as ``--sample 216`` for these files): each test
below names the surviving mutant it kills, but checks the documented behaviour, not the mutant.
"""

from __future__ import annotations

import numpy as np
import pytest

from tyrefit.diagnose import stats as S
from tyrefit.fitting.core import L1_STEPS, Parameters, objective, solve


def test_l1_fit_reports_the_evaluations_it_made():
    """``Solution.nfev`` counts residual evaluations over every stage of the l1 continuation
    (core.py [660]: the stages' counts subtracted gave a negative count)."""
    rng = np.random.default_rng(0)
    x = np.linspace(0.0, 1.0, 40)
    y = 1.0 + 2.0 * x + rng.laplace(0.0, 0.05, x.size)
    calls = []

    def resid(t):
        calls.append(1)
        return t[0] + t[1] * x - y

    p = Parameters()
    p.add("a", 0.0)
    p.add("b", 0.0)
    sol = solve(resid, p, cost="l1")
    assert len(L1_STEPS) <= sol.nfev <= len(calls)
    assert sol.values["b"] == pytest.approx(2.0, abs=0.1)


def test_l2_objective_is_the_sum_of_squares_with_or_without_weights():
    """The cost a multi-start ranks its starts by (core.py [694]: the unweighted l2 cost summed the residuals,
    so a start with residuals +-100 would have beaten one with residuals of 1)."""
    r = np.array([3.0, -4.0])
    assert objective(r, None, "l2") == pytest.approx(25.0)
    assert objective(r, np.array([2.0, 1.0]), "l2") == pytest.approx(34.0)
    assert objective(np.array([100.0, -100.0]), None, "l2") > objective(np.array([1.0, 1.0]), None, "l2")


def test_multi_start_keeps_the_start_with_the_lowest_sum_of_squares():
    """Of two starts of a two-minimum problem, the fit kept is the one with the lower sum of squares."""
    x = np.linspace(-1.0, 1.0, 21)
    y = np.cos(3.0 * x)

    def resid(t):  # minima near w = 3 and w = -3 ... and a poorer local one for small |w|
        return np.cos(t[0] * x) - y + 0.1 * (t[0] - 3.0) * (t[0] < 0)

    p = Parameters()
    p.add("w", 0.5, min=-6.0, max=6.0)
    sol = solve(resid, p, starts=[{"w": -3.2}, {"w": 2.7}])
    assert sol.values["w"] == pytest.approx(3.0, abs=1e-4)


def test_min_p_adjustment_of_independent_candidates_is_sidak():
    """Single-step min-p over K candidates whose draws are independent: a candidate with p = 0.01 alone is
    1 - 0.99^K adjusted (Westfall & Young 1993); stats.py [540] (ranks of T instead of -T, or ranked across
    candidates instead of within each) breaks it."""
    rng = np.random.default_rng(3)
    K, B = 3, 19999
    Tb = rng.chisquare(1, size=(K, B))
    T = np.array([np.quantile(Tb[0], 0.99), np.quantile(Tb[1], 0.5), np.quantile(Tb[2], 0.2)])
    p, padj, _ = S._minp_adjust(T, Tb, 0.05)
    assert p == pytest.approx([0.01, 0.5, 0.8], abs=0.005)
    assert padj[0] == pytest.approx(1 - 0.99**3, abs=0.004)
    assert padj[1] == pytest.approx(1 - 0.5**3, abs=0.02)
    assert np.all(padj >= p)
    # candidates 0 and 1 large together (their top tenth is the same draws), small independently: the
    # adjustment pays for two candidates, not three; ranking the smallest statistics first (stats.py [540],
    # the sign of -Tb dropped) pays for three
    q90 = np.quantile(Tb[0], 0.9)
    Tb[1] = np.where(Tb[0] > q90, Tb[0], rng.uniform(0.0, np.quantile(Tb[0], 0.5), B))
    _, padj, _ = S._minp_adjust(T, Tb, 0.05)
    assert padj[0] == pytest.approx(1 - 0.99**2, abs=0.004)


def test_noise_screening_reads_independent_noise_as_uncorrelated():
    """Under independent noise the screening's bias-corrected noise model has a lag-one correlation near 0
    and the sd of the noise (stats.py [765]: its lower clip at +0.5 instead of -0.5 drew every null from
    noise correlated at 0.5, which widens it and takes power)."""
    rng = np.random.default_rng(5)
    sweep = np.repeat(np.arange(6), 49)
    u = np.tile(np.linspace(-1, 1, 49), 6)
    z = np.repeat(np.linspace(0.2, 1.0, 6), 49)
    J_model = np.column_stack([u, u * z, np.ones_like(u)])
    y = rng.normal(0, 2.0, u.size)
    r = y - J_model @ np.linalg.lstsq(J_model, y, rcond=None)[0]
    scr = S.screen_candidates(J_model, [(z**2 * u)[:, None]], r, S.SweepLayout(sweep, 6), rng, n_boot=499,
                              method="noise")
    assert abs(float(np.ravel(scr.noise.rho)[0])) < 0.2
    assert float(np.sqrt(np.mean(np.asarray(scr.noise.sd) ** 2))) == pytest.approx(2.0, rel=0.15)


def test_repeat_noise_pairs_each_point_with_the_nearest_slip_angle_of_the_repeat():
    """Two repeats of a steep misfit on slip grids offset by a tenth of a step: the nearest point of the
    repeat is a tenth of a step away, so the misfit cancels and the noise sd (1 N) comes back; pairing the
    neighbour nine tenths away (stats.py [311]: the distance to xs[j] replaced by |xs[j]|) reads 2 N."""
    rng = np.random.default_rng(8)
    d = np.radians(0.5)
    a1 = np.radians(np.arange(0.25, 12.0, 0.5))
    a2 = a1 + 0.1 * d
    a = np.r_[a1, a2, -a1, -a2]
    misfit = 3.0 * a / d  # 3 N per grid step
    r = misfit + rng.normal(0.0, 1.0, a.size)
    sweep = np.repeat([0, 1, 0, 1], a1.size)
    out = S.repeat_noise(a, r, sweep, np.zeros(a.size, dtype=int))
    assert out is not None and out["pairs"] == 1
    assert out["sd_N"] == pytest.approx(1.0, rel=0.2)


def test_simulated_ar1_noise_is_stationary_with_the_models_sd_and_correlation():
    """simulate_noise draws each sweep's noise as a stationary AR(1): at every point of the sweep the sd is the
    model's sd, and neighbours correlate at rho (stats.py [499]: innovations left unscaled by sqrt(1 - rho^2)
    inflate the sd by 1/sqrt(1 - rho^2), 1.67 x at rho 0.8, and every null drawn from it)."""
    lay = S.SweepLayout(np.repeat(np.arange(2), 40), 2)
    nm = S.NoiseModel(sd=np.array([2.0, 3.0]), rho=np.array([0.8]), tau=np.array([0.0]))
    e = S.simulate_noise(nm, lay, 20000, np.random.default_rng(0))
    first, second = e[:, :40], e[:, 40:]
    assert np.std(first, axis=0) == pytest.approx(np.full(40, 2.0), rel=0.05)
    assert np.std(second, axis=0) == pytest.approx(np.full(40, 3.0), rel=0.05)
    lag1 = np.mean(first[:, 1:] * first[:, :-1]) / np.mean(first * first)
    assert lag1 == pytest.approx(0.8, abs=0.02)
