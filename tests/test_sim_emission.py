"""Particle emission vs longitudinal force (seed 000 Eq. 14): tyrefit.sim.emission."""

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.optimize import nnls

from tyrefit.io.datasets import data_path
from tyrefit.errors import DataError
from tyrefit.io.readers import read_data
from tyrefit.sim.emission import DEFAULT_EMISSION, QuadraticEmission, fit_emission


def test_rate_axle_and_scaling():
    e = QuadraticEmission(0.01, -8.0, 2000.0)
    f = np.linspace(-3000, 3000, 7)
    assert_allclose(e.rate(f), 0.01 * f**2 - 8 * f + 2000)
    ax = e.axle(2)
    assert_allclose(ax.rate(f), 2 * e.rate(f / 2))
    assert_allclose(e.scaled(0.25).rate(f), 0.25 * e.rate(f))
    assert_allclose(e.force_at_minimum, 400.0)
    assert_allclose(e.minimum, 2000 - 64 / 0.04)


@pytest.mark.parametrize("weights", ["absolute", "relative"])
def test_unconstrained_fit_recovers_a_feasible_truth(weights):
    truth = QuadraticEmission(0.012, -6.0, 1500.0)                  # minimum 750 > 0: constraint inactive
    f = np.linspace(-2500, 2500, 41)
    r = fit_emission(f, truth.rate(f), weights=weights)
    assert not r.constrained
    assert_allclose([r.model.a, r.model.b, r.model.c], [0.012, -6.0, 1500.0], rtol=1e-8)
    assert r.r2 > 0.999999


def _brute_constrained(f, y, f0_grid):
    best = (np.inf, None)
    for f0 in f0_grid:
        M = np.column_stack([(f - f0) ** 2, np.ones_like(f)])
        sol, res = nnls(M, y)
        if res**2 < best[0]:
            best = (res**2, (sol[0], f0, sol[1]))
    return best


def test_constrained_fit_is_nonnegative_and_optimal():
    rng = np.random.default_rng(3)
    f = np.sort(rng.uniform(-2500, 2500, 60))
    y = np.clip(0.01 * (f - 400.0) ** 2 - 3000 + 300 * rng.standard_normal(f.size), 0, None)  # counts >= 0
    r = fit_emission(f, y)
    m = r.model
    free = np.linalg.lstsq(np.column_stack([f**2, f, np.ones_like(f)]), y, rcond=None)[0]
    assert free[2] - free[1] ** 2 / (4 * free[0]) < 0                   # the free fit dips below zero
    assert r.constrained
    grid = np.linspace(-5000, 5000, 200001)
    assert m.rate(grid).min() >= -1e-9 * y.max()                        # N >= 0 everywhere
    assert m.a > 0 and m.force_at_minimum > 0                           # minimum at a non-zero force
    ssr = np.sum((m.rate(f) - y) ** 2)
    best, _ = _brute_constrained(f, y, np.linspace(0, 800, 4001))
    assert ssr <= best * (1 + 1e-6)                                      # no feasible quadratic does better


def test_default_coefficients_are_the_fit_of_the_bundled_data():
    ds = read_data(data_path("sim", "emission.csv"))
    assert ds.kind == "emission"
    r = fit_emission(ds.df["fx"], ds.df["particles"])
    assert "DEFAULT" in DEFAULT_EMISSION.source
    assert_allclose([DEFAULT_EMISSION.a, DEFAULT_EMISSION.b], [r.model.a, r.model.b], rtol=2e-3)
    assert_allclose(DEFAULT_EMISSION.force_at_minimum, r.model.force_at_minimum, rtol=2e-3)
    assert DEFAULT_EMISSION.minimum >= 0
    # the synthetic truth: a = 0.012 (#/s)/N^2, minimum at F0 = 500 N
    assert_allclose(r.model.a, 0.012, rtol=0.08)
    assert_allclose(r.model.force_at_minimum, 500.0, atol=40.0)


def test_fit_errors():
    with pytest.raises(DataError, match="at least 4"):
        fit_emission([1, 2, 3], [1, 2, 3])
    with pytest.raises(DataError, match=">= 0"):
        fit_emission([1, 2, 3, 4, 5], [1, -2, 3, 4, 5])
    with pytest.raises(DataError, match="differ in length"):
        fit_emission([1, 2, 3, 4], [1, 2, 3])
    with pytest.raises(DataError, match="weights"):
        fit_emission([1, 2, 3, 4, 5], [1, 2, 3, 4, 5], weights="log")


def test_plot_returns_axes():
    f = np.linspace(-2000, 2000, 20)
    ax = fit_emission(f, 0.01 * (f - 300) ** 2 + 10).plot()
    assert ax.get_xlabel().startswith("longitudinal force")
