"""Diagnosis: tests for the sampled mutants that survived the quick suite (issue 25's mutation run).

``nice python -m benchmarks.mutation --sample 216 --seed 15`` (12 mutants per module) left these
mutants alive; each test states documented statistics or behaviour, not the mutated text.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from tyrefit.diagnose.stats import SweepLayout, cluster_bootstrap_prob, estimate_noise


# ------------------------------------------------------------------------------ tyrefit/diagnose/stats.py
def test_sweep_bootstrap_probability_is_the_share_of_resamples_with_a_positive_sum():
    # one sweep gains 3, four lose 1: a resample of 5 sweeps sums > 0 iff it draws the gaining one twice or
    # more, P = 1 - (4/5)^5 - 5 (1/5) (4/5)^4 = 0.26272
    d = np.array([3.0, -1.0, -1.0, -1.0, -1.0])
    p = cluster_bootstrap_prob(d, np.random.default_rng(0), n_boot=20000)
    assert p == pytest.approx(1 - 0.8**5 - 0.8**4, abs=0.01)
    assert cluster_bootstrap_prob(-d, np.random.default_rng(0), n_boot=20000) == pytest.approx(1 - p, abs=0.01)


def test_the_sweep_offset_noise_is_unbiased_after_a_model_spent_parameters_on_sweep_means():
    # estimate_noise: the mean square of the sweep means has expectation tau^2 + sd^2 f / n, with the degrees
    # of freedom the model spent on sweep means (dof_between) taken off G; here 3 of 8 sweeps' worth
    rng = np.random.default_rng(2)
    g, per, tau, sd = 8, 30, 2.0, 1.0
    sweep = np.repeat(np.arange(g), per)
    layout = SweepLayout(sweep, g)
    e = sd * rng.standard_normal((4000, g * per)) + tau * rng.standard_normal((4000, g))[:, sweep]
    k = np.arange(g, dtype=float)[sweep]
    Q, _ = np.linalg.qr(np.column_stack([np.ones_like(k), k, k**2]))  # three directions constant in each sweep
    r = e - (e @ Q) @ Q.T
    nm = estimate_noise(r, layout, dof_within=0.0, dof_between=3.0)
    assert float(np.mean(nm.tau**2)) == pytest.approx(tau**2, rel=0.05)
    assert float(np.mean(nm.sd**2)) == pytest.approx(sd**2, rel=0.02)


def test_the_sweep_flip_p_value_is_the_share_of_all_sign_patterns_reaching_the_statistic():
    """stats.py [435] ``screen_candidates`` (flip weights drawn from {-1, 0} instead of {-1, +1}).

    The wild cluster score bootstrap (Kline & Santos 2012) flips the sign of each sweep's score with
    probability 1/2 (Rademacher weights): with 12 sweeps its p-value is, up to the draws' error, the
    share of all 2^12 sign patterns whose statistic reaches the observed one.  Weights in {-1, 0} drop
    sweeps instead of flipping them: the draws' statistic is about a quarter the size and the p-value
    half the exact one (0.07 against 0.14 here), a false alarm at twice the stated rate.
    """
    import itertools

    from tyrefit.diagnose.stats import screen_candidates

    G, n = 12, 15
    sweep = np.repeat(np.arange(G), n)
    x = np.tile(np.linspace(-1.0, 1.0, n), G)
    r = np.random.default_rng(11).standard_normal(G * n) + 0.3 * x
    scr = screen_candidates(np.ones((G * n, 1)), [x[:, None]], r, SweepLayout(sweep, G), np.random.default_rng(0),
                            n_boot=3999, method="flip")
    # the score of x (made orthogonal to the model's constant) per sweep, and T = (sum s)^2 / sum s^2
    s = np.bincount(sweep, weights=(x - x.mean()) * r, minlength=G)
    T = s.sum() ** 2 / (s @ s)
    assert scr.method == "sweep flips" and scr.statistic[0] == pytest.approx(T, rel=1e-9)
    signs = np.array(list(itertools.product([-1.0, 1.0], repeat=G)))
    exact = float(np.mean((signs @ s) ** 2 / (s @ s) >= T * (1 - 1e-9)))
    assert 0.1 < exact < 0.2
    assert scr.p_value[0] == pytest.approx(exact, abs=0.02)


def test_the_noise_models_sweep_offset_sd_is_unbiased_after_the_bootstrap_correction():
    """stats.py [508] ``screen_candidates`` (tau = 4 tau_obs - mean(pilot tau) instead of 2 tau_obs - ...).

    The noise-model bootstrap corrects each noise parameter by the bias its pilot draws show (Efron &
    Tibshirani 1993, 10.3: theta - bias = 2 theta - mean(theta*)).  On records of known offset noise
    (tau 2 N between 10 sweeps, 1 N white within) the corrected tau is right on average; the mutant's
    is three times too large, so the bootstrap's null draws carry offsets the data do not have and
    between-sweep candidates (shifts, load laws) lose their power.
    """
    from tyrefit.diagnose.stats import screen_candidates

    G, n, tau, sd = 10, 40, 2.0, 1.0
    sweep = np.repeat(np.arange(G), n)
    x = np.tile(np.linspace(-1.0, 1.0, n), G)
    taus = []
    for seed in range(30):
        rng = np.random.default_rng(seed)
        r = sd * rng.standard_normal(G * n) + tau * rng.standard_normal(G)[sweep]
        scr = screen_candidates(np.c_[np.ones(G * n), x], [(x**2)[:, None]], r, SweepLayout(sweep, G),
                                np.random.default_rng(seed), n_boot=19, method="noise")
        taus.append(float(np.asarray(scr.noise.tau).ravel()[0]))
    assert np.mean(taus) == pytest.approx(tau, rel=0.15)


# ------------------------------------------------------------------------------ tyrefit/diagnose/engine.py
def test_a_rival_is_a_family_that_alone_brings_the_stated_share_of_the_accepted_gain():
    # _rivals: other families' best confirmed candidates whose held-out gain (fall of the mean square error
    # from the current model) is >= share x the accepted one's
    from tyrefit.diagnose.engine import _rivals

    ev = {i: (None, SimpleNamespace(rmse_heldout=h))
          for i, h in (("camber", 10.0), ("load_friction", 12.0), ("overload", 19.0))}
    new = {"camber": {"a5"}, "load_friction": {"a1"}, "overload": {"overload_k"}}
    out = _rivals("camber", ["camber", "load_friction", "overload"], ev, new, SimpleNamespace(rmse_heldout=20.0),
                  1, 0.5)
    assert [r["rival"] for r in out] == ["load_friction"]
    assert out[0]["share"] == pytest.approx((400.0 - 144.0) / (400.0 - 100.0))


@pytest.fixture(scope="module")
def even_misfit():
    """Diagnosis of 9 sweeps (3 loads x 3 cambers, one pressure and speed) with a misfit even in slip.

    A systematic addition the same at +alpha and -alpha that no catalogue effect carries.
    """
    from tyrefit.diagnose import diagnose
    from tyrefit.synthetic.hidden import make_case, rig_grid

    grid = rig_grid(loads=(3000.0, 5000.0, 7000.0), cambers_deg=(-3.0, 0.0, 3.0), pressures=(220e3,))
    df = make_case((), "iid", seed=2, sigma=15.0, grid=grid).data.copy()
    a = df["slip_angle"].to_numpy()
    df["fy"] = df["fy"] + 0.04 * df["fz"] * (np.abs(a) / np.abs(a).max()) ** 1.5
    return diagnose(df, seed=2)


def test_an_even_misfit_in_slip_is_reported_as_even(even_misfit):
    # the end check's surface is even in slip, odd share near 0 ("the forces at zero slip")
    un = even_misfit.unexplained
    mf = un["misfit"]
    assert mf["checked"] and mf["systematic"]
    # the residual by slip range: eight bins across the sweeps' -12..12 deg
    bins = [b["slip_deg"] for b in un["slip_bins"]]
    assert len(bins) == 8 and bins[0][0] == pytest.approx(-12.0) and bins[-1][1] == pytest.approx(12.0)
    assert all(lo < hi for lo, hi in bins)
    assert mf["odd_share"] < 0.2
    # where: slip ranges inside the sweeps' +-12 deg, each a range (the misfit grows towards both ends)
    assert mf["slip_ranges"] and all(-12.01 <= b["slip_deg"][0] < b["slip_deg"][1] <= 12.01 for b in mf["slip_ranges"])


def test_a_systematic_misfit_names_each_family_the_data_could_not_test_and_why(even_misfit):
    """engine.py [121] ``_misfit_text`` (the list of families deleted from its sentence).

    The summary of a misfit no catalogue effect explains points at the families these data could not
    test (one pressure, one speed, 3 loads, no rated load), each with what it would need; the mutant
    ends the sentence at its colon and names none of them.
    """
    dg = even_misfit
    mf = dg.unexplained["misfit"]
    assert {dg.candidates[e].family for e in mf["not_testable"]} == {"load_friction", "overload", "pressure", "speed"}
    text = dg.unexplained["summary"]
    head = "families these data could not test (one of them may be it): "
    assert head in text
    for e in mf["not_testable"]:
        c = dg.candidates[e]
        assert c.status == "not testable with these data"
        assert f"{c.family} ({c.reason})" in text.split(head, 1)[1]
    assert "pressure (needs >= 2 pressure levels (found 1))" in text


def test_the_omnibus_check_tests_as_many_smooth_directions_per_group_as_a_third_of_the_sweeps(even_misfit):
    """engine.py [252] ``_unexplained`` (q = G // 6 instead of G // 3).

    The end check's omnibus score test: Legendre orders 0-4 of the slip angle (and 5-9, and 0-4 times
    each condition), at most G/3 directions per group.  With 9 sweeps that is orders 0-2 of each group;
    the mutant tests only the constant (order 0, resp. 5) of each: it cannot see a misfit in the slope
    or the curvature of the slip curve.
    """
    un = even_misfit.unexplained
    assert even_misfit.data.n_sweeps == 9
    groups = un["omnibus_groups"]
    assert set(groups) == {"slip shape (orders 0-4)", "slip shape (orders 5-9)", "slip x load", "slip x camber"}
    assert all(g["directions"] == 3 for g in groups.values())
    assert un["directions"] == 12


def test_the_stability_of_a_candidate_is_the_share_of_sweep_resamples_with_a_positive_held_out_gain():
    # Settings.min_boot_prob / stability_guard: the held-out gain (fall of each held-out sweep's squared error)
    # resampled over sweeps; an effect the data do not have (camber, on data without it) gains on some sweeps
    # and loses on others, so it is far from "stays positive in every resample"
    from tyrefit.diagnose.data import prepare
    from tyrefit.diagnose.engine import Settings, _Engine
    from tyrefit.diagnose.fitter import ModelSpec, fit_start
    from tyrefit.diagnose.stats import cluster_sums
    from tyrefit.synthetic.hidden import make_case

    data = prepare(make_case((), "iid", seed=3).data)
    eng = _Engine(data, Settings(), 3)
    spec = ModelSpec((), eng.fixed)
    cur = eng.step(spec, fit_start(spec, data), None)
    st, ev = eng.evaluate(spec.with_effect("camber"), cur, 0.0)
    gain = (cluster_sums(cur.oof**2, data.sweep, eng.G) - cluster_sums(st.oof**2, data.sweep, eng.G))[:, 0]
    gain = gain[eng.inside_sweep]
    assert (gain < 0).any() and (gain > 0).any()
    expected = cluster_bootstrap_prob(gain, np.random.default_rng(0), n_boot=20000)
    assert ev["boot_prob"] == pytest.approx(expected, abs=0.05)
    assert ev["boot_prob"] < 0.95


def test_a_screen_without_bootstrap_draws_rejects_nothing():
    # p = (1 + #{T* >= T}) / (n_boot + 1) is 1 with no draws, and no statistic is critical
    from tyrefit.diagnose import diagnose
    from tyrefit.synthetic.hidden import make_case

    dg = diagnose(make_case(("camber",), "iid", seed=1).data, seed=1, n_boot=0)
    assert dg.accepted == []
    tested = [c for c in dg.candidates.values() if c.status == "not significant"]
    assert tested and all(c.p_value == 1.0 and c.critical == np.inf for c in tested)


def test_repeated_sweeps_measure_the_noise_whatever_the_models_error():
    # repeat_noise: two sweeps of one cell share the model's error; sd = sqrt(mean(diff^2) / 2) is the noise
    from tyrefit.diagnose.stats import repeat_noise

    rng = np.random.default_rng(4)
    a = np.radians(np.linspace(-10.0, 10.0, 41))
    sweeps, cells, slip, resid = [], [], [], []
    for c in range(3):
        model_error = 80.0 * np.sin(3 * a + c)               # the same in both repeats of the cell
        for rep in range(2):
            sweeps.append(np.full(a.size, 2 * c + rep))
            cells.append(np.full(a.size, c))
            slip.append(a)
            resid.append(model_error + 2.0 * rng.standard_normal(a.size))
    out = repeat_noise(np.concatenate(slip), np.concatenate(resid), np.concatenate(sweeps), np.concatenate(cells))
    assert out["pairs"] == 3 and out["cells"] == 3
    assert out["sd_N"] == pytest.approx(2.0, rel=0.15)


def test_a_one_sided_repeat_is_compared_on_its_own_side_only():
    from tyrefit.diagnose.stats import repeat_noise

    rng = np.random.default_rng(5)
    a = np.radians(np.linspace(-10.0, 10.0, 41))
    pos = a[a > 0]
    slip = np.r_[a, pos]
    sweep = np.r_[np.zeros(a.size, int), np.ones(pos.size, int)]
    out = repeat_noise(slip, 2.0 * rng.standard_normal(slip.size), sweep, np.zeros(slip.size, int))
    assert out["pairs"] == 1 and out["points"] == pos.size


def test_a_zero_slip_shift_is_named_from_half_the_noise_floor():
    """engine.py [1] ``SHIFT_MIN_FLOOR`` (1.0 instead of 0.5).

    ``_shift_evidence`` names a shift of the curve at zero slip (ply steer, conicity) when it is
    significant and its RMS over the sweeps is at least half the within-sweep noise floor.  8 sweeps
    through zero slip with 20 N of noise: a 14 N shift (0.7 x the floor, p << 0.1) is named, a 6 N
    one (0.4 x) is too small; the mutant refuses the 14 N shift as well.
    """
    from tyrefit.diagnose.engine import _shift_evidence

    G, n, floor = 8, 49, 20.0
    d = SimpleNamespace(inputs=SimpleNamespace(slip_angle=np.tile(np.radians(np.linspace(-3.0, 3.0, n)), G),
                                               fz=np.repeat(np.linspace(2000.0, 8000.0, G), n)),
                        sweep=np.repeat(np.arange(G), n))
    noise = floor * np.random.default_rng(3).standard_normal(G * n)
    assert _shift_evidence(d, noise + 14.0, 0.10, floor) is None
    small = _shift_evidence(d, noise + 6.0, 0.10, floor)
    assert small.startswith("a shift at zero slip too small to name") and "0.5 x the noise floor 20 N" in small
    assert _shift_evidence(d, noise, 0.10, floor).startswith("no shift at zero slip")


@pytest.fixture(scope="module")
def load_law_at_the_ends():
    """Diagnosis of one sweep at each of 4 loads with a hidden curvature-in-load law (seed 1).

    The 2 interior sweeps are the interpolated held-out evidence; the law shows most at the end loads.
    """
    from tyrefit.diagnose import diagnose
    from tyrefit.synthetic.hidden import make_case, rig_grid

    grid = rig_grid(loads=(2000.0, 4000.0, 6000.0, 8000.0), cambers_deg=(0.0,), pressures=(220e3,))
    return diagnose(make_case(("curvature_load",), "iid", seed=1, grid=grid).data, seed=1)


def test_a_load_law_short_of_the_margin_on_the_interior_sweeps_stands_on_every_held_out_sweep(load_law_at_the_ends):
    """engine.py [292] ``_Engine.evaluate`` (``and`` -> ``or`` in "not (gain >= margin and p < alpha)").

    With one sweep per load the interpolated evidence is 2 sweeps; a candidate whose interpolated
    evidence falls short on either count (here: significant, p < alpha, but a gain below the practical
    margin) may stand on every held-out sweep, the end loads included.  The hidden law is found that
    way; the mutant falls back only when both counts fail, and finds nothing.
    """
    dg = load_law_at_the_ends
    c = dg.candidates["curvature_load"]
    margin = dg.settings.margin * dg.noise_floor
    assert 0.0 < c.delta_heldout < margin  # short on the interior sweeps alone
    assert dg.accepted == ["curvature_load"]
    assert c.evidence.startswith("every held-out sweep")
    assert c.p_heldout < dg.settings.alpha


def test_the_all_sweep_evidence_reports_the_fall_of_the_held_out_rmse(load_law_at_the_ends):
    """engine.py [157] ``_Engine.evaluate`` (delta_heldout_all = cur.rmse_heldout_all, its "- st..." deleted).

    A candidate confirmed on every held-out sweep is reported with that evidence, the RMSE of every
    held-out sweep before -> after (Step.rmse_heldout_all of the two steps), and it must fall by the
    practical margin; the mutant's gain is the whole RMSE before (40.5 N "falls" to 78.4 -> 37.9 N).
    """
    dg = load_law_at_the_ends
    before, after = dg.steps[0].rmse_heldout_all, dg.steps[1].rmse_heldout_all
    assert before - after >= dg.settings.margin * dg.noise_floor
    reason = dg.candidates["curvature_load"].reason
    assert f"(every held-out sweep, extrapolated ends included: {before:.1f} -> {after:.1f} N" in reason


def test_the_end_checks_slip_bins_are_the_mean_over_sweeps_of_each_sweeps_mean_residual():
    """engine.py's end check: each of 8 slip bins reports the mean over sweeps of every sweep's mean residual there,
    with its sweep-robust standard error, and names as 'slip ranges' exactly the bins whose mean exceeds 3 SE
    (kills: per-sweep means as sums times counts [1062]; the flag at 3 / SE [1067])."""
    from tyrefit.diagnose import diagnose
    from tyrefit.synthetic.validation.cases import make_case

    case = make_case("load6", "iid", "overload", 0)
    dg = diagnose(case.data, start=[], seed=0)  # no rated load: the overload knee stays in the residual
    d, r = dg.data, dg.steps[-1].fit.resid
    a = d.inputs.slip_angle
    ext = np.max(np.abs(a))
    edges = np.linspace(-ext, ext, 9)
    expect = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        m = (a >= lo) & (a <= hi)
        if m.sum() < 5:
            continue
        means = np.array([r[m & (d.sweep == g)].mean() for g in np.unique(d.sweep[m])])
        expect.append((means.mean(), means.std(ddof=1) / np.sqrt(len(means))))
    got = dg.unexplained["slip_bins"]
    assert len(got) == len(expect)
    for b, (mean, se) in zip(got, expect):
        assert b["mean_N"] == pytest.approx(mean, rel=1e-9, abs=1e-9)
        assert b["se_N"] == pytest.approx(se, rel=1e-9)
    flagged = [b for b, (mean, se) in zip(got, expect) if abs(mean) > 3 * se]
    where = " ".join(dg.unexplained.get("where") or [])
    assert ("slip ranges" in where) == bool(flagged)
    for b in got:
        text = f"{b['slip_deg'][0]:.1f} to {b['slip_deg'][1]:.1f} deg"
        assert (text in where) == (b in flagged[:3])


def test_a_score_tests_p_value_counts_the_sign_patterns_that_reproduce_the_statistic():
    """stats.py [133] ``score_test`` (``Tb >= T * (1 - 1e-9)`` -> ``Tb >= T * 1``: draws equal to T up to rounding).

    The docstring's null distribution flips the sign of each sweep's score (w_g = +/-1) and counts
    p = (1 + #{T* >= T}) / (n_boot + 1).  Flipping every sweep alike (w = +1 or w = -1 for all) gives
    T* = T exactly (the statistic is even), so with G sweeps p can never fall below about 2 / 2^G: with 3
    sweeps and a strong effect, whose mixed patterns all fall short of T, p is the share 2/8 of the patterns
    that reproduce the data.  The mutant counts those draws only when the bootstrap's arithmetic rounds T*
    up to T, and reports p ~ 1/(n_boot + 1) = 0.0005 for some data: a significance 3 sweeps cannot give.
    """
    import itertools

    from tyrefit.diagnose.stats import score_test

    G, n = 3, 8
    cluster = np.repeat(np.arange(G), n)
    signs = np.array(list(itertools.product([-1.0, 1.0], repeat=G)))
    for seed in range(12):
        rng = np.random.default_rng(seed)
        J_model, J_new = rng.standard_normal((G * n, 2)), rng.standard_normal((G * n, 2))
        r = rng.standard_normal(G * n) + 2.0 * J_new[:, 0]
        t = score_test(J_model, J_new, r, cluster, G, np.random.default_rng(1), n_boot=1999)
        # the exact share over the 2^G patterns: the two uniform ones reproduce T, the mixed ones are computed
        Q, _ = np.linalg.qr(J_model)
        S = np.array([(J_new - Q @ (Q.T @ J_new))[cluster == g].T @ r[cluster == g] for g in range(G)])
        Vp = np.linalg.pinv(S.T @ S)
        T_star = np.einsum("bi,ij,bj->b", signs @ S, Vp, signs @ S)
        uniform = np.all(signs == signs[:, :1], axis=1)
        exact = float(np.mean(uniform | (T_star >= t.statistic)))
        assert t.statistic == pytest.approx(float(S.sum(0) @ Vp @ S.sum(0)), rel=1e-9)
        assert t.p_value == pytest.approx(exact, abs=0.04), (seed, t.p_value, exact)
