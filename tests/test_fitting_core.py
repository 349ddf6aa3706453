"""The one fitting core (tyrefit.fitting.core): parameters, sweeps, solve().

Each test can fail: known parameters from generated data, standard errors
against the closed form of linear regression, bounds, held parameters kept
bit for bit, a local minimum that one start cannot escape and a multi-start can,
the l1 cost against outliers, and the two back ends against each other.
"""

from __future__ import annotations

import numpy as np
import pytest

from tyrefit.errors import FitError
from tyrefit.fitting.core import Parameters, Sweeps, solve


def _decay_problem(seed=0, noise=0.0):
    rng = np.random.default_rng(seed)
    x = np.linspace(0.0, 4.0, 80)
    y = 2.5 * np.exp(-1.3 * x) + 0.4 + noise * rng.standard_normal(x.size)
    return x, y


def _decay_params():
    p = Parameters()
    p.add("amp", 1.0, min=0.0, max=10.0)
    p.add("rate", 0.5, min=1e-6, max=10.0)
    p.add("off", 0.0)
    return p


def _decay_residual(p, x, y):
    def r(v):
        a, k, c = v
        return a * np.exp(-k * x) + c - y
    return r


@pytest.mark.parametrize("jac", ["2-point", "analytic"])
def test_known_parameters_recovered(jac):
    x, y = _decay_problem()
    p = _decay_params()

    def J(v):
        a, k, _ = v
        e = np.exp(-k * x)
        return np.column_stack([e, -a * x * e, np.ones_like(x)])

    sol = solve(_decay_residual(p, x, y), p, jac=J if jac == "analytic" else None, tol=1e-12)
    assert sol.values["amp"] == pytest.approx(2.5, rel=1e-7)
    assert sol.values["rate"] == pytest.approx(1.3, rel=1e-7)
    assert sol.values["off"] == pytest.approx(0.4, abs=1e-8)
    assert sol.rmse < 1e-8
    assert sol.success


def test_stderr_matches_linear_regression_closed_form():
    rng = np.random.default_rng(3)
    x = np.linspace(-2, 3, 60)
    y = 1.5 - 0.7 * x + 0.3 * rng.standard_normal(x.size)
    X = np.column_stack([np.ones_like(x), x])
    beta, *_ = np.linalg.lstsq(X, y, rcond=None)
    res = y - X @ beta
    s2 = res @ res / (x.size - 2)
    se = np.sqrt(np.diag(s2 * np.linalg.inv(X.T @ X)))
    p = Parameters()
    p.add("b0", 0.0)
    p.add("b1", 0.0)
    for jac in (None, lambda v: X):
        sol = solve(lambda v: X @ v - y, p, jac=jac, tol=1e-14)
        np.testing.assert_allclose(sol.x, beta, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose([sol.stderr["b0"], sol.stderr["b1"]], se, rtol=1e-6)
        assert sol.params["b1"].stderr == pytest.approx(se[1], rel=1e-6)
        assert sol.s2 == pytest.approx(s2, rel=1e-9)


def test_weighted_stderr_matches_weighted_regression():
    rng = np.random.default_rng(5)
    x = np.linspace(0, 1, 40)
    w = np.where(x < 0.5, 4.0, 1.0)
    y = 2.0 + 3.0 * x + rng.standard_normal(x.size) / np.sqrt(w)
    X = np.column_stack([np.ones_like(x), x])
    W = np.diag(w)
    beta = np.linalg.solve(X.T @ W @ X, X.T @ W @ y)
    res = y - X @ beta
    s2 = res @ W @ res / (x.size - 2)
    se = np.sqrt(np.diag(s2 * np.linalg.inv(X.T @ W @ X)))
    p = Parameters.from_values({"c": 0.0, "m": 0.0})
    sol = solve(lambda v: X @ v - y, p, jac=lambda v: X, weights=w, tol=1e-14)
    np.testing.assert_allclose(sol.x, beta, rtol=1e-9)
    np.testing.assert_allclose(list(sol.stderr.values()), se, rtol=1e-6)
    assert sol.cost == pytest.approx(res @ W @ res, rel=1e-9)


def test_bounds_are_honoured_and_reported():
    x, y = _decay_problem()
    p = _decay_params()
    p["rate"].max = 1.0  # the truth (1.3) lies outside
    sol = solve(_decay_residual(p, x, y), p)
    assert sol.values["rate"] <= 1.0
    assert sol.values["rate"] == pytest.approx(1.0, abs=1e-6)
    assert sol.at_bound() == {"rate": "upper"}
    assert all(p_.min <= p_.value <= p_.max for p_ in sol.params.values())


def test_held_parameter_is_kept_exactly():
    x, y = _decay_problem(noise=0.01)
    p = _decay_params()
    held = 0.4123456789
    p["off"].value = held
    p["off"].vary = False
    seen = []

    def r(v):
        seen.append(len(v))
        return p.values_of(v)["amp"] * np.exp(-p.values_of(v)["rate"] * x) + p.values_of(v)["off"] - y

    sol = solve(r, p)
    assert sol.values["off"] == held  # bit for bit
    assert sol.names == ["amp", "rate"] and set(seen) == {2}
    assert sol.params["off"].stderr is None and "off" not in sol.stderr
    # the free ones are the best fit *given* the held value: the conditional optimum
    sol2 = solve(r, p, starts=[{"amp": 3.0, "rate": 2.0}])
    assert sol2.values["amp"] == pytest.approx(sol.values["amp"], rel=1e-6)


def test_multistart_escapes_a_local_minimum():
    # y = sin(w x): from w0 = 1 the fit stops in the local minimum near w = 1 (truth: 3.1)
    x = np.linspace(0, 6, 200)
    y = np.sin(3.1 * x)
    p = Parameters()
    p.add("w", 1.0, min=0.1, max=6.0)

    def r(v):
        return np.sin(v[0] * x) - y

    one = solve(r, p)
    assert abs(one.values["w"] - 3.1) > 0.5  # stuck: the test below means something
    multi = solve(r, p, starts=[{"w": 1.0}, {"w": 2.0}, {"w": 3.0}, {"w": 4.5}])
    assert multi.values["w"] == pytest.approx(3.1, rel=1e-6)
    assert len(multi.starts) == 4 and multi.cost == pytest.approx(min(s["cost"] for s in multi.starts))
    assert multi.cost < one.cost


def test_l1_cost_resists_outliers_where_l2_does_not():
    rng = np.random.default_rng(11)
    x = np.linspace(0, 1, 101)
    y = 1.0 + 2.0 * x + 0.01 * rng.standard_normal(x.size)
    y[::10] += 5.0  # 11 gross outliers
    X = np.column_stack([np.ones_like(x), x])
    p = Parameters.from_values({"c": 0.0, "m": 0.0})
    l2 = solve(lambda v: X @ v - y, p, jac=lambda v: X)
    l1 = solve(lambda v: X @ v - y, p, jac=lambda v: X, cost="l1",
               starts=[l2.x])
    assert abs(l2.values["c"] - 1.0) > 0.3
    assert l1.values["c"] == pytest.approx(1.0, abs=0.02)
    assert l1.values["m"] == pytest.approx(2.0, abs=0.04)
    assert l1.cost == pytest.approx(np.sum(np.abs(X @ l1.x - y)), rel=1e-12)


def test_huber_with_per_point_scale_resists_outliers():
    rng = np.random.default_rng(2)
    x = np.linspace(0, 1, 101)
    y = 1.0 + 2.0 * x + 0.01 * rng.standard_normal(x.size)
    y[5::10] -= 3.0
    X = np.column_stack([np.ones_like(x), x])
    p = Parameters.from_values({"c": 0.0, "m": 0.0})
    sol = solve(lambda v: X @ v - y, p, jac=lambda v: X, cost="huber", scale=np.full(x.size, 0.0135),
                weights=np.ones(x.size))
    assert sol.values["c"] == pytest.approx(1.0, abs=0.01)


def test_sweep_weights_make_each_sweep_count_once():
    # two sweeps of a constant: one sampled 10x as densely; with 1/n_s weights the fitted
    # constant is the mean of the two sweep means, without them the dense sweep dominates
    y = np.r_[np.full(10, 1.0), np.full(100, 3.0)]
    run = np.r_[np.zeros(10), np.ones(100)]
    data = Sweeps(y, run)
    np.testing.assert_allclose(data.w, np.r_[np.full(10, 0.1), np.full(100, 0.01)])
    p = Parameters.from_values({"c": 0.0})
    sol = solve(lambda v: np.full(y.size, v[0]) - data.y, p, data=data)
    assert sol.values["c"] == pytest.approx(2.0, rel=1e-8)
    flat = solve(lambda v: np.full(y.size, v[0]) - y, p)
    assert flat.values["c"] == pytest.approx(y.mean(), rel=1e-8)
    sub = data.take(data.sweep == 1)
    assert sub.n == 100 and np.allclose(sub.w, 0.01) and sub.n_sweeps == 1


def test_lm_normal_back_end_agrees_with_trf():
    x, y = _decay_problem(noise=0.02, seed=4)
    p = _decay_params()
    p["amp"].scale, p["rate"].scale, p["off"].scale = 1.0, 1.0, 0.1

    def J(v):
        a, k, _ = v
        e = np.exp(-k * x)
        return np.column_stack([e, -a * x * e, np.ones_like(x)])

    a = solve(_decay_residual(p, x, y), p, jac=J, tol=1e-12)
    b = solve(_decay_residual(p, x, y), p, jac=J, method="lm-normal", tol=1e-14, max_nfev=500)
    np.testing.assert_allclose(b.x, a.x, rtol=1e-6)
    np.testing.assert_allclose(list(b.stderr.values()), list(a.stderr.values()), rtol=1e-5)


def test_penalty_rows_do_not_enter_the_statistics():
    rng = np.random.default_rng(8)
    x = np.linspace(0, 1, 50)
    y = 0.5 + rng.standard_normal(x.size) * 0.1
    p = Parameters.from_values({"c": 0.0})

    def r(v):  # one penalty row pushing c below 0.3 when it exceeds it
        return np.r_[np.full(x.size, v[0]) - y, 100.0 * max(0.0, v[0] - 0.3)]

    sol = solve(r, p, n_data=x.size)
    assert sol.values["c"] < 0.31
    assert sol.rmse == pytest.approx(np.sqrt(np.mean((sol.values["c"] - y) ** 2)), rel=1e-12)


def test_non_finite_start_raises_fit_error():
    p = Parameters.from_values({"c": -1.0})
    with pytest.raises(FitError, match="not finite"):
        with np.errstate(invalid="ignore"):
            solve(lambda v: np.sqrt(np.full(5, v[0])), p)


def test_lmfit_round_trip():
    p = Parameters()
    p.add("a", 1.5, min=0.0, max=3.0, unit="N")
    p.add("b", -2.0, vary=False)
    lp = p.to_lmfit()
    assert lp["a"].min == 0.0 and lp["a"].max == 3.0 and not lp["b"].vary
    q = Parameters.from_lmfit(lp)
    assert q.valuesdict() == p.valuesdict() and q.free() == ["a"]
