"""The diagnosis' fast paths give what the plain computations give (issue 24, speed).

Each fast path is checked against the direct computation it replaces: the folds refitted together
(:func:`tyrefit.diagnose.fitter.fit_folds`, :func:`tyrefit.fitting.core.lm_normal_batch`) against one
:func:`tyrefit.diagnose.fitter.fit` per fold; the held-out null's thin products against the hat matrix;
the closed-form AR(1) sums against the sum of powers; the quadratic forms against ``np.linalg.pinv``;
and the sequential Monte Carlo screening against its stopping rule.
"""

from __future__ import annotations

import numpy as np
import pytest

from tyrefit.diagnose import stats as S
from tyrefit.diagnose.fitter import ModelSpec, fit, fit_folds, fit_start
from tyrefit.fitting.core import lm_normal, lm_normal_batch


@pytest.mark.parametrize("effects", [(), ("load_friction",), ("overload",), ("load_friction", "curvature_load")])
def test_folds_refitted_together_are_the_folds_refitted_one_by_one(six, effects):
    spec = ModelSpec(effects)
    full = fit(spec, six, x0=spec.start(fit_start(ModelSpec(()), six).values))
    tests = [six.sweep == g for g in range(6)] + [six.sweep >= 4]
    X, R = fit_folds(spec, six, tests, full.theta, tol=1e-7)
    for f, te in enumerate(tests):
        one = fit(spec, six, idx=np.flatnonzero(~te), x0=full.theta, tol=1e-7)
        assert np.allclose(X[f], one.theta, rtol=1e-8, atol=1e-9 * spec.scale.max())
        held = spec.predict(one.theta, six.inputs.take(te)) - six.fy[te]
        assert np.max(np.abs(R[f][te] - held)) < 1e-5  # N
        train = spec.predict(one.theta, six.inputs.take(~te)) - six.fy[~te]
        assert np.max(np.abs(R[f][~te] - train)) < 1e-5


def test_batch_levenberg_marquardt_takes_each_problem_to_its_own_bounded_minimum():
    """Three exponential fits, one with its rate held at a bound, one leaving out half its points."""
    t = np.linspace(0.0, 4.0, 40)
    y = 3.0 * np.exp(-0.7 * t) + 0.01 * np.sin(7 * t)
    lower, upper, scale = np.array([0.0, 0.9]), np.array([10.0, 5.0]), np.ones(2)  # the rate may not go below 0.9

    def model(x):
        return x[0] * np.exp(-x[1] * t)

    def jac1(x):
        e = np.exp(-x[1] * t)
        return x[0] * e - y, np.column_stack([e, -x[0] * t * e])

    w = np.ones((3, t.size))
    w[2, ::2] = 0.0
    starts = np.array([[1.0, 1.5], [5.0, 3.0], [2.0, 1.0]])

    def jac(X, rows):
        out = [jac1(x) for x in X]
        return np.array([o[0] for o in out]), np.array([o[1] for o in out])

    X, R, nfev, ok = lm_normal_batch(jac, lambda X, rows: np.array([model(x) - y for x in X]), starts, w, lower,
                                     upper, scale, 200, 1e-12)
    assert ok.all()
    for f in range(3):
        m = w[f] > 0

        def jm(x, m=m):
            r, J = jac1(x)
            return r[m], J[m]

        x1, n1, _ = lm_normal(jm, lambda x, m=m: model(x)[m] - y[m], starts[f], lower, upper, scale, 200, 1e-12)
        assert np.allclose(X[f], x1, rtol=1e-9)
        assert nfev[f] == n1
        assert np.allclose(R[f], model(X[f]) - y)
    assert X[0, 1] == pytest.approx(0.9)  # held at the bound: the unbounded rate is 0.7


def test_heldout_null_thin_products_are_the_hat_matrix_ones():
    rng = np.random.default_rng(4)
    sweep = np.repeat(np.arange(5), 30)
    lay = S.SweepLayout(sweep, 5)
    J0 = np.column_stack([np.ones(150), np.linspace(-1, 1, 150), rng.normal(size=150)])
    J1 = rng.normal(size=(150, 2))
    nm = S.NoiseModel(sd=np.full(5, 2.0), rho=np.array([0.6]), tau=np.array([0.5]))
    inside = sweep != 0
    hn = S.HeldoutNull(J0, nm, lay, sweep, np.random.default_rng(1), 50)
    e = hn.e
    X0 = J0 / np.linalg.norm(J0, axis=0)
    X1 = np.hstack([X0, J1 / np.linalg.norm(J1, axis=0)])
    want = np.zeros(50)
    for f in range(5):
        te, tr = (sweep == f) & inside, sweep != f
        if not te.any():
            continue
        for X, sign in ((X0, 1.0), (X1, -1.0)):
            M = X[te] @ np.linalg.pinv(X[tr], rcond=1e-10)
            oof = e[:, te] - e[:, tr] @ M.T
            want += sign * np.sum(oof * oof, axis=1)
    assert np.allclose(hn.gain(J1, inside), want, rtol=1e-10, atol=1e-9)
    # the same draws serve every candidate: a second candidate's gain uses the cached model part
    J2 = rng.normal(size=(150, 1))
    assert np.allclose(hn.gain(J2, inside), S.HeldoutNull(J0, nm, lay, sweep, np.random.default_rng(1), 50)
                       .gain(J2, inside))


def test_ar1_sweep_sum_factor_in_closed_form_is_the_sum_of_powers():
    lay = S.SweepLayout(np.repeat(np.arange(4), [1, 3, 10, 58]), 4)
    rho = np.array([-0.5, 0.0, 0.3, 0.8, 0.97])
    f = S._ar_f(lay, rho)
    for b, r in enumerate(rho):
        for g, n in enumerate(lay.n):
            i = np.arange(n)
            want = np.sum(r ** np.abs(i[:, None] - i[None, :])) / n
            assert f[b, g] == pytest.approx(want, rel=1e-12)


@pytest.mark.parametrize("q", [1, 2, 3])
def test_pinv_quadratic_is_the_pseudo_inverse_form_singular_matrices_included(q):
    rng = np.random.default_rng(q)
    A = rng.normal(size=(40, q, q))
    V = A @ A.transpose(0, 2, 1)
    V[0] = 0.0
    if q > 1:
        v = np.arange(1.0, q + 1)
        V[1] = np.outer(v, v)  # rank one
    s = rng.normal(size=(40, q))
    want = np.einsum("bi,bij,bj->b", s, np.linalg.pinv(V, rcond=1e-10, hermitian=True), s)
    assert np.allclose(S._pinv_quadratic(s, V, 1e-10), want, rtol=1e-10, atol=1e-12)


def test_draw_blocks_add_up_to_at_most_n_boot():
    assert S.draw_blocks(1999) == [499, 500, 1000]
    assert S.draw_blocks(999) == [499, 500]
    assert S.draw_blocks(499) == [499]
    assert S.draw_blocks(200) == [200]


def test_a_screening_stops_only_when_its_decision_is_settled():
    """decided(): the count of draws at least as extreme is binomial(B, p); settled when p = alpha is ruled out."""
    B, alpha = 499, 0.025
    Tb = np.linspace(0.0, 10.0, B)[None, :]

    def with_count(c):  # the observed statistic exceeded by exactly c of the B draws
        return np.array([0.5 * (Tb[0, B - c - 1] + Tb[0, B - c])]) if c else np.array([11.0])

    assert S.decided(with_count(0), Tb, alpha)  # 0.975^499 = 3e-6: clearly below alpha
    assert not S.decided(with_count(5), Tb, alpha)  # 5 of 499 is compatible with p = 0.025 (12.5 expected)
    assert not S.decided(with_count(25), Tb, alpha)
    assert S.decided(with_count(60), Tb, alpha)  # 12 %: clearly above
    # every candidate must be settled
    assert not S.decided(np.r_[with_count(0), with_count(5)], np.vstack([Tb, Tb]), alpha)


def test_noise_screening_uses_all_its_draws_only_where_a_decision_is_close(monkeypatch):
    rng = np.random.default_rng(0)
    sweep = np.repeat(np.arange(6), 49)
    u = np.tile(np.linspace(-1, 1, 49), 6)
    z = np.repeat(np.linspace(0.2, 1.0, 6), 49)
    J_model = np.column_stack([u, u * z, np.ones_like(u)])
    cands = [(z**2 * u)[:, None], (u**3)[:, None]]
    lay = S.SweepLayout(sweep, 6)
    y = rng.normal(0, 1.0, u.size)  # nothing there: settled after the first block
    r = y - J_model @ np.linalg.lstsq(J_model, y, rcond=None)[0]
    scr = S.screen_candidates(J_model, cands, r, lay, np.random.default_rng(1), n_boot=1999, alpha=0.025,
                              method="noise")
    assert scr.draws == 499 and np.all(scr.p_adjusted > 0.025)
    monkeypatch.setattr(S, "DRAW_STEPS", ())
    full = S.screen_candidates(J_model, cands, r, lay, np.random.default_rng(1), n_boot=1999, alpha=0.025,
                               method="noise")
    assert full.draws == 1999 and np.all(full.p_adjusted > 0.025)


def test_large_records_refit_their_folds_one_by_one_with_the_same_result(six, monkeypatch):
    import tyrefit.diagnose.fitter as F

    spec = ModelSpec(("load_friction",))
    full = fit(spec, six, x0=spec.start(fit_start(ModelSpec(()), six).values))
    tests = [six.sweep == g for g in range(6)]
    Xb, Rb = fit_folds(spec, six, tests, full.theta, tol=1e-7)
    monkeypatch.setattr(F, "BATCH_MAX_POINTS", 100)
    Xl, Rl = F.fit_folds(spec, six, tests, full.theta, tol=1e-7)
    assert np.allclose(Xb, Xl, rtol=1e-8) and np.max(np.abs(Rb - Rl)) < 1e-5
