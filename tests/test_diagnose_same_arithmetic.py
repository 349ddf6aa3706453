"""The diagnosis' shortcuts do the same arithmetic as the computations they stand for, bit for bit.

A difference in the last bit of one Levenberg-Marquardt step grows far beyond rounding in the fitted
parameters (the fits stop at a relative cost change, not at the exact minimum), so every shortcut in the
fitting path must give exactly the numbers of the plain computation: the model's value from its Jacobian and
from a prediction, a parameter set alone and repeated, a Jacobian made once and served again, the batch
Levenberg-Marquardt with its trial points evaluated by the Jacobian, the sweep layout read as a reshape,
the min-p ranks from one sort, a refit made once per candidate and current step.
"""

from __future__ import annotations

import numpy as np
import pytest

from tyrefit.diagnose import prepare
from tyrefit.diagnose import stats as S
from tyrefit.diagnose.engine import Settings, _Engine
from tyrefit.diagnose.fitter import ModelSpec, _batch_problem, _start, fit, fit_start
from tyrefit.effects import EFFECTS
from tyrefit.fitting.core import lm_normal_batch
from tyrefit.models import pac89
from tyrefit.synthetic.hidden import make_case


@pytest.fixture(scope="module")
def suite():
    case = make_case(("camber", "pressure"), "ar1", seed=1)
    return prepare(case.data, rated_load=case.rated_load)


def _specs(data):
    out = []
    for eid in EFFECTS:
        try:
            spec = ModelSpec((eid,))
            spec.predict(spec.start(None), data.inputs)
        except Exception:  # noqa: BLE001 - an effect these data cannot carry (no pressure, ...)
            continue
        out.append(spec)
    return out + [ModelSpec(("overload_knee", "offsets")), ModelSpec(("camber_brush", "load_friction"), {"a4": 9.0})]


@pytest.mark.parametrize("which", ["six", "suite"])
def test_the_jacobians_model_value_is_the_prediction_and_each_set_is_computed_alone(which, request):
    """f from jacobian_batch is predict's value bit for bit (the batch refits take their trial residuals from
    it), and a set's row does not depend on the other sets in the batch (the folds' common start is made once)."""
    data = request.getfixturevalue(which)
    rng = np.random.default_rng(2)
    base = fit_start(ModelSpec(()), data).values
    for spec in _specs(data):
        th0 = spec.start(base)  # new terms exactly neutral: the effects' shortcuts
        th1 = np.clip(th0 + rng.normal(0.0, 0.3, th0.size) * spec.scale, spec.lower, spec.upper)
        f, J = spec.jacobian_batch(np.vstack([th0, th1, th0]), data.inputs)
        for i, th in enumerate((th0, th1, th0)):
            assert np.array_equal(f[i], spec.predict(th, data.inputs)), spec.ids
            f1, J1 = spec.jacobian(th, data.inputs)
            assert np.array_equal(f1, f[i]) and np.array_equal(J1, J[i]), spec.ids


def test_lateral_jacobian_of_coefficient_columns_is_each_sets_jacobian():
    fz = np.linspace(1500.0, 9000.0, 40)
    alpha = np.radians(np.linspace(-12.0, 12.0, 40))
    gamma = np.radians(np.linspace(-3.0, 4.0, 40))
    sets = [dict(zip(pac89.LATERAL, c)) for c in
            ([1.5, -20, 1100, 1500, 8, 0.01, -0.05, -0.4, 0.1, 0.02, 0.2, 5, 10, 30],
             [1.3, -5, 1000, 1300, 9, 0.0, 0.0, -0.2, 0.0, 0.0, 0.0, 0, 0, 0])]
    cols = {c: np.array([[s[c]] for s in sets]) for c in pac89.LATERAL}
    names = ("a0", "a3", "a4", "a5", "a8", "a10", "a13")
    f, J = pac89.lateral_jacobian(cols, fz, alpha, gamma, names=names)
    assert f.shape == (2, 40) and J.shape == (2, 40, len(names))
    for i, s in enumerate(sets):
        fi, Ji = pac89.lateral_jacobian(s, fz, alpha, gamma, names=names)
        assert np.array_equal(fi, f[i]) and np.array_equal(Ji, J[i])
        assert np.array_equal(fi, pac89.lateral_force(s, fz, alpha, gamma))


def test_batch_refits_with_the_jacobian_at_the_trial_points_take_the_same_steps(six):
    spec = ModelSpec(("load_friction", "curvature_load"))
    full = fit(spec, six, x0=spec.start(fit_start(ModelSpec(()), six).values))
    w = np.array([six.sweep != g for g in range(6)], dtype=float)
    jac = _batch_problem(spec, six)

    def fun(X, rows):
        return np.array([spec.predict(x, six.inputs) for x in X]) - six.fy

    x = np.repeat(_start(spec, full.theta)[None, :], 6, axis=0)
    a = lm_normal_batch(jac, fun, x, w, spec.lower, spec.upper, spec.scale, 200, 1e-7)
    b = lm_normal_batch(jac, None, x, w, spec.lower, spec.upper, spec.scale, 200, 1e-7)
    for u, v in zip(a, b):
        assert np.array_equal(u, v)


def test_a_fit_served_its_first_evaluation_is_the_fit_that_makes_it(six):
    spec = ModelSpec(("overload",))
    x0 = spec.start(fit_start(ModelSpec(()), six).values)
    made = spec.jacobian(x0, six.inputs)
    a, b = fit(spec, six, x0=x0), fit(spec, six, x0=x0, at_start=made)
    assert np.array_equal(a.theta, b.theta) and np.array_equal(a.resid, b.resid) and a.nfev == b.nfev


@pytest.mark.parametrize("counts", [[49] * 5, [30, 49, 12, 49]])
@pytest.mark.parametrize("shuffled", [False, True])
def test_sweep_layout_shortcuts_are_the_general_gather(counts, shuffled):
    """Whole sweeps stored in order are read as a reshape, full ones without the mask: the same numbers."""
    import copy

    rng = np.random.default_rng(len(counts))
    sweep = np.repeat(np.arange(len(counts)), counts)
    if shuffled:
        sweep = sweep[rng.permutation(sweep.size)]
    lay = S.SweepLayout(sweep, len(counts))
    assert lay.whole == (not shuffled and len(set(counts)) == 1) and lay.full == (len(set(counts)) == 1)
    plain = copy.copy(lay)
    plain.whole = plain.full = False
    x = rng.normal(size=(3, sweep.size))
    want = np.where(lay.mask, np.take(x, np.where(lay.mask, lay.index, 0), axis=-1), 0.0)
    assert np.array_equal(lay.padded(x), want) and np.array_equal(plain.padded(x), want)
    assert np.array_equal(lay.unpad(want), x) and np.array_equal(plain.unpad(want), x)
    a, b = S.estimate_noise(x, lay, 2.0, 1.0), S.estimate_noise(x, plain, 2.0, 1.0)
    assert all(np.array_equal(getattr(a, k), getattr(b, k)) for k in ("sd", "rho", "tau"))
    nm = S.NoiseModel(sd=np.linspace(1.0, 2.0, len(counts)), rho=np.array([0.7]), tau=np.array([0.4]))
    assert np.array_equal(S.simulate_noise(nm, lay, 5, np.random.default_rng(0)),
                          S.simulate_noise(nm, plain, 5, np.random.default_rng(0)))


def test_min_p_ranks_from_one_sort_are_the_double_argsort_ranks():
    rng = np.random.default_rng(5)
    Tb = np.round(rng.chisquare(2, size=(4, 301)), 1)  # ties: ranked in draw order
    T = np.array([4.0, 9.0, 0.5, 6.0])
    p, padj, crit = S._minp_adjust(T, Tb, 0.05)
    ranks = np.argsort(np.argsort(-Tb, axis=1, kind="stable"), axis=1)
    min_boot = np.sort(((1.0 + ranks) / 302.0).min(axis=0))
    p_obs = (1.0 + np.sum(Tb >= T[:, None] * (1 - 1e-9), axis=1)) / 302.0
    want = np.maximum((1.0 + np.searchsorted(min_boot, p_obs * (1 + 1e-9), side="right")) / 302.0, p_obs)
    assert np.array_equal(p, p_obs) and np.array_equal(padj, want)
    c = min_boot[max(int(np.floor(0.05 * 302)) - 2, 0)]
    assert np.array_equal(crit, [np.quantile(Tb[k], 1.0 - c) for k in range(4)])
    assert S.decided(T, Tb, 0.05) == S._settled(padj, 301, 0.05)


def test_residualising_many_against_one_model_is_residualising_each():
    rng = np.random.default_rng(1)
    J = rng.normal(size=(80, 4)) * [1.0, 1e3, 1e-2, 5.0]
    off = S._residualiser(J)
    for X in (rng.normal(size=(80, 1)), rng.normal(size=(80, 3))):
        norms = np.linalg.norm(J, axis=0)
        Js = J / norms
        want = X - Js @ (np.linalg.pinv(Js.T @ Js, rcond=1e-12, hermitian=True) @ (Js.T @ X))
        assert np.array_equal(off(X), want) and np.array_equal(S.residualise(X, J), want)


def test_a_candidate_refitted_again_draws_from_the_random_stream_as_if_refitted_anew(six):
    """The overload's knee check and the round both evaluate a smooth friction law: the second call reuses the
    refit (and its held-out null) but draws its bootstrap from the engine's stream, so what follows sees the
    same random numbers."""
    spec = ModelSpec(())
    full = fit_start(spec, six)
    testable = {eid: e.why_not_testable(six.summary) for eid, e in EFFECTS.items()}

    def engine():
        eng = _Engine(six, Settings(), seed=4)
        cur = eng.step(spec, full, None)
        pool = eng.candidates(spec, testable)
        noise = eng.screen(spec, full, pool).noise
        return eng, cur, dict((e.id, c) for e, c in pool)["load_friction"], noise

    eng, cur, cand, noise = engine()
    st1, ev1 = eng.evaluate(cand, cur, 5.0, noise)
    st2, ev2 = eng.evaluate(cand, cur, 5.0, noise)
    after = eng.rng.random()
    fresh, cur_f, cand_f, noise_f = engine()
    _, f1 = fresh.evaluate(cand_f, cur_f, 5.0, noise_f)
    fresh._refits.clear()
    fresh._nulls.clear()
    st3, f2 = fresh.evaluate(cand_f, cur_f, 5.0, noise_f)
    assert st2 is st1 and np.array_equal(st3.oof, st1.oof) and np.isfinite(ev1["p_heldout"])
    assert repr(ev1) == repr(f1) and repr(ev2) == repr(f2) and after == fresh.rng.random()
