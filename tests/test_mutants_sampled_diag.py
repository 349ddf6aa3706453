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


def test_an_even_misfit_in_slip_is_reported_as_even():
    # a systematic addition even in slip (the same at +alpha and -alpha) that no catalogue effect carries:
    # the end check's surface is even in slip, odd share near 0 ("the forces at zero slip")
    from tyrefit.diagnose import diagnose
    from tyrefit.synthetic.hidden import make_case, rig_grid

    grid = rig_grid(loads=(3000.0, 5000.0, 7000.0), cambers_deg=(-3.0, 0.0, 3.0), pressures=(220e3,))
    df = make_case((), "iid", seed=2, sigma=15.0, grid=grid).data.copy()
    a = df["slip_angle"].to_numpy()
    df["fy"] = df["fy"] + 0.04 * df["fz"] * (np.abs(a) / np.abs(a).max()) ** 1.5
    un = diagnose(df, seed=2).unexplained
    mf = un["misfit"]
    assert mf["checked"] and mf["systematic"]
    # the residual by slip range: eight bins across the sweeps' -12..12 deg
    bins = [b["slip_deg"] for b in un["slip_bins"]]
    assert len(bins) == 8 and bins[0][0] == pytest.approx(-12.0) and bins[-1][1] == pytest.approx(12.0)
    assert all(lo < hi for lo, hi in bins)
    assert mf["odd_share"] < 0.2
    # where: slip ranges inside the sweeps' +-12 deg, each a range (the misfit grows towards both ends)
    assert mf["slip_ranges"] and all(-12.01 <= b["slip_deg"][0] < b["slip_deg"][1] <= 12.01 for b in mf["slip_ranges"])


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
