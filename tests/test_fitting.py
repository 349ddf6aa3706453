"""PAC89 fitting: recovery of known coefficients, costs, constraints, identifiability."""

import math

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose

from tyrefit.errors import DataError
from tyrefit.fitting import FitResult, estimate_sweep, fit_pac89
from tyrefit.fitting.engine import _Problem, point_scatter, prepare_data
from tyrefit.io.tir import read_tir
from tyrefit.models import pac89
from tyrefit.synthetic.pac89_example import EXAMPLE, example_tyre, lateral_sweeps, longitudinal_sweeps


@pytest.fixture(scope="module")
def lateral():
    # Fz 2-8 kN, slip -12..12 deg, camber -4..4 deg, 1 % noise (of each sweep's peak), ISO-W signs
    return lateral_sweeps()


@pytest.fixture(scope="module")
def lateral_fit(lateral):
    return fit_pac89(lateral)


def _worst_pct_of_peak(tyre, true, loads=np.linspace(2000, 8000, 13), cambers=np.linspace(-4, 4, 9)):
    sa = np.radians(np.linspace(-12, 12, 481))
    worst = 0.0
    for fz in loads:
        for g in cambers:
            ft = pac89.lateral_force(true, fz, sa, math.radians(g))
            ff = tyre.fy(fz, sa, math.radians(g))
            worst = max(worst, float(np.max(np.abs(ff - ft)) / np.max(np.abs(ft))))
    return 100 * worst


def test_written_tir_reproduces_generating_curves(lateral_fit, tmp_path):
    """Must show: the written .tir is within 0.5 % of peak force of the generating curves everywhere."""
    p = lateral_fit.tyre.to_tir(tmp_path / "fit.tir")
    back = read_tir(p)
    assert back.coefficients["a3"] > 0
    assert _worst_pct_of_peak(back, EXAMPLE) < 0.5
    # the fitted ranges and the fit statistics are recorded
    assert back.ranges["fz"] == pytest.approx((2000.0, 8000.0))
    assert back.ranges["camber"] == pytest.approx((-math.radians(4), math.radians(4)))
    assert any("RMSE" in h for h in back.header)


def test_fit_reaches_noise_and_beats_truth_cost(lateral_fit):
    s = lateral_fit.stats["lateral"]
    assert s["r2"] > 0.999
    assert s["rmse"] < 1.1 * s["noise_floor"]
    pf = lateral_fit._parts["lateral"]
    prob = _Problem(pf.data, EXAMPLE, pf.varied, "l2")
    # the global minimum is at or below the cost of the generating coefficients
    assert pf.objective <= prob.objective(prob.theta_of(EXAMPLE)) * (1 + 1e-9)
    # well-determined coefficients come back close to the truth
    c = lateral_fit.tyre.coefficients
    assert c["a2"] == pytest.approx(1250.0, rel=0.01)
    assert c["a1"] == pytest.approx(-34.0, rel=0.05)
    assert c["a11"] == pytest.approx(19.1656, rel=0.03)


def test_noise_floor_estimates_the_noise(lateral_fit, lateral):
    # the generator's sigma is 1 % of each sweep's peak
    true_sigma = lateral.groupby("run")["fy"].apply(lambda s: 0.01 * np.max(np.abs(s)))
    nf = lateral_fit._parts["lateral"].noise_per_run
    ratio = nf.to_numpy() / true_sigma.reindex(nf.index).to_numpy()
    assert 0.75 < np.median(ratio) < 1.25


def test_l1_cost_minimises_eq5(lateral, lateral_fit):
    r1 = fit_pac89(lateral, cost="l1")
    assert r1.cost == "l1"
    pf1, pf2 = r1._parts["lateral"], lateral_fit._parts["lateral"]
    p = _Problem(pf1.data, pf1.coefficients, pf1.varied, "l1")
    l1_at_l1 = p.objective(p.theta_of(pf1.coefficients))
    l1_at_l2 = p.objective(p.theta_of(pf2.coefficients))
    assert l1_at_l1 < l1_at_l2
    assert _worst_pct_of_peak(r1.tyre, EXAMPLE) < 0.6


def test_l1_is_robust_to_outliers(lateral):
    df = lateral.copy()
    rng = np.random.default_rng(5)
    idx = rng.choice(len(df), 40, replace=False)
    df.loc[idx, "fy"] += rng.choice([-1, 1], 40) * 3000.0
    # screen=False: the costs alone (the default screening leaves most of these 3 kN outliers out)
    w1 = _worst_pct_of_peak(fit_pac89(df, cost="l1", screen=False).tyre, EXAMPLE)
    w2 = _worst_pct_of_peak(fit_pac89(df, cost="l2", screen=False).tyre, EXAMPLE)
    assert w1 < w2


def test_bad_start_does_not_strand_the_fit(lateral, lateral_fit):
    bad = {"a0": 2.6, "a2": 400.0, "a3": 300.0, "a4": 1.0, "a7": -8.0}
    r = fit_pac89(lateral, initial=bad)
    assert r.stats["lateral"]["objective"] == pytest.approx(lateral_fit.stats["lateral"]["objective"], rel=1e-3)


def test_constraints_hold_over_load_range(lateral_fit):
    t = lateral_fit.tyre
    fzk = np.linspace(2, 8, 61)
    f = pac89.lateral_factors(t.coefficients, fzk, 0.0 * fzk)
    assert np.all(f.C > 0) and np.all(f.D > 0) and np.all(f.E <= 1)
    t.check_physical()


def test_e_bound_is_active_when_data_want_e_above_one():
    # a curve whose best curvature is E > 1 at the heavy load: the constraint must hold exactly
    c = dict(EXAMPLE, a6=0.06, a7=0.7)  # E(8 kN) = 1.18 in the generator
    df = lateral_sweeps(cambers_deg=(0.0,), coefficients=c, seed=3)
    r = fit_pac89(df, fixed={"a0": c["a0"]})  # with C held at the truth, only E > 1 would fit
    fzk = np.array([2.0, 8.0])
    E = r.tyre.coefficients["a6"] * fzk + r.tyre.coefficients["a7"]
    assert np.all(E <= 1.0 + 1e-12)
    assert any("upper bound 1" in n for n in r.notes)


def test_identifiability_positive_slip_single_camber(lateral):
    df = lateral[(np.isclose(lateral["camber"], 0.0)) & (lateral["slip_angle"] >= 0)]
    r = fit_pac89(df)
    held = {"a5", "a8", "a9", "a10", "a11", "a12", "a13"}
    assert held <= set(r.not_identifiable)
    for k in held:
        assert r.tyre.coefficients[k] == 0.0
        assert not r.params[k].vary
    assert "slip signs" in r.not_identifiable["a10"] and "camber" in r.not_identifiable["a11"]
    assert r.tyre.coefficients["a3"] > 0


def test_identifiability_single_load(lateral):
    df = lateral[(lateral["fz"] == 4000.0) & np.isclose(lateral["camber"], 0.0)]
    r = fit_pac89(df)
    for k in ("a1", "a4", "a6", "a9", "a12"):
        assert "load levels" in r.not_identifiable[k]
    assert r.tyre.coefficients["a1"] == 0.0 and r.tyre.coefficients["a6"] == 0.0
    # at the tested load the fit is still right
    assert _worst_pct_of_peak(r.tyre, EXAMPLE, loads=[4000.0], cambers=[0.0]) < 1.0


def test_vary_subset_holds_the_rest(lateral):
    start = ["a0", "a2", "a3", "a4", "a7"]
    r = fit_pac89(lateral, vary=start)
    varied = set(r.coefficients.loc[r.coefficients["varied"], "name"])
    assert varied == set(start)
    for k in ("a1", "a5", "a6", "a8", "a9", "a10", "a11", "a12", "a13"):
        assert r.tyre.coefficients[k] == 0.0
    assert r.parts == ["lateral"]
    # adding the camber-thrust term must lower the error a lot (data have camber)
    r2 = fit_pac89(lateral, vary=start + ["a11"])
    assert r2.rmse < 0.8 * r.rmse


def test_vary_only_one_of_a_linear_law_respects_constraint(lateral):
    r = fit_pac89(lateral, vary=["a0", "a1", "a3", "a4", "a7"], fixed={"a2": 900.0})
    c = r.tyre.coefficients
    assert c["a2"] == 900.0
    assert min(c["a1"] * 2 + 900.0, c["a1"] * 8 + 900.0) > 0


def test_fixed_values_are_kept(lateral):
    r = fit_pac89(lateral, fixed={"a0": 1.65, "a7": 0.7})
    assert r.tyre.coefficients["a0"] == 1.65 and r.tyre.coefficients["a7"] == 0.7
    assert r.coefficients.set_index("name").loc["a0", "status"] == "fixed"


def test_unknown_names_and_cost():
    df = lateral_sweeps(loads=(4000.0,), cambers_deg=(0.0,))
    with pytest.raises(DataError, match="not a PAC89 coefficient"):
        fit_pac89(df, vary=["a3", "pky1"])
    with pytest.raises(DataError, match="cost"):
        fit_pac89(df, cost="cauchy")


def test_wrong_sign_convention_is_reported():
    df = lateral_sweeps(loads=(3000.0, 6000.0), cambers_deg=(0.0,))
    df["fy"] = -df["fy"]  # SAE-like data read as ISO-W
    with pytest.raises(DataError, match="convention"):
        fit_pac89(df)


def test_nothing_to_fit():
    df = pd.DataFrame({"fz": [4000.0] * 20, "slip_angle": [0.0] * 20, "fy": [0.0] * 20})
    with pytest.raises(DataError, match="nothing to fit"):
        fit_pac89(df)


def test_static_data_need_conversion():
    df = pd.DataFrame({"run": 1, "fz": 40000.0, "lateral_displacement": np.linspace(0, 0.05, 30),
                       "fy": np.linspace(0, 20000, 30)})
    with pytest.raises(DataError, match="prepare_static_fit"):
        fit_pac89(df)


def test_longitudinal_recovery():
    df = longitudinal_sweeps()
    r = fit_pac89(df)
    assert r.parts == ["longitudinal"]
    k = np.linspace(-0.3, 0.3, 301)
    worst = max(float(np.max(np.abs(r.tyre.fx(fz, k) - pac89.longitudinal_force(EXAMPLE, fz, k)))
                      / np.max(np.abs(pac89.longitudinal_force(EXAMPLE, fz, k)))) for fz in (2000, 5000, 8000))
    assert worst < 0.01
    assert r.tyre.coefficients["b0"] > 0 and r.tyre.has_longitudinal
    assert not r.not_identifiable  # four loads and both slip signs: every b is identifiable
    r3 = fit_pac89(longitudinal_sweeps(loads=(2000.0, 5000.0, 8000.0)))
    assert {"b5", "b6"} <= set(r3.not_identifiable)
    assert r3.tyre.coefficients["b5"] == 0.0 and r3.tyre.coefficients["b6"] == 0.0


def test_file_with_lateral_longitudinal_and_mz():
    lat = lateral_sweeps(cambers_deg=(-4.0, 0.0, 4.0))
    lon = longitudinal_sweeps()
    lon["run"] += 1000
    r = fit_pac89(pd.concat([lat, lon], ignore_index=True))
    assert set(r.parts) == {"lateral", "longitudinal", "aligning"}
    sa = np.radians(np.linspace(-12, 12, 241))
    for fz in (2000.0, 8000.0):
        for g in (-4.0, 0.0, 4.0):
            mt = pac89.aligning_moment(EXAMPLE, fz, sa, math.radians(g))
            assert np.max(np.abs(r.tyre.mz(fz, sa, math.radians(g)) - mt)) < 0.02 * np.max(np.abs(mt))
    assert r.tyre.ranges["slip_ratio"] == pytest.approx((-0.3, 0.3))


def test_combined_slip_sweeps_are_left_out():
    lat = lateral_sweeps(loads=(3000.0, 6000.0), cambers_deg=(0.0,))
    comb = lat[lat["run"] == 1].copy()
    comb["run"] = 99
    comb["slip_ratio"] = np.linspace(-0.1, 0.1, len(comb))
    comb["fx"] = 0.0
    lat["slip_ratio"] = 0.0
    r = fit_pac89(pd.concat([lat, comb], ignore_index=True))
    assert 99 not in set(r.sweeps["run"])
    assert any("combined-slip" in n for n in r.notes)


def test_without_run_column():
    df = lateral_sweeps(loads=(3000.0, 6000.0), cambers_deg=(0.0,)).drop(columns="run")
    r = fit_pac89(df)
    assert r.stats["lateral"]["sweeps"] == 2


def test_static_like_falling_fz_is_fitted_on_mu():
    # measured Fz falls along the push (seed 003): the fit uses each point's Fz
    sa = np.radians(np.linspace(0, 12, 120))
    frames = []
    for run, f0 in enumerate((20000.0, 40000.0, 60000.0), 1):
        fz = f0 * (1 - 0.1 * sa / sa.max())
        c = dict(EXAMPLE, a1=-1.0, a2=800.0, a3=9000.0, a4=60.0, a6=0.0, a7=0.3)
        c.update({k: 0.0 for k in ("a8", "a9", "a10", "a11", "a12", "a13", "a5")})
        frames.append(pd.DataFrame({"run": run, "fz": fz, "slip_angle": sa, "fy": pac89.lateral_force(c, fz, sa)}))
    r = fit_pac89(pd.concat(frames))
    assert r.stats["lateral"]["rmse"] < 1.0  # noise-free: exact within numerical precision
    assert r.tyre.coefficients["a2"] == pytest.approx(800.0, rel=1e-3)


# -- Eq. 2-4 initial estimates ---------------------------------------------------------------
def test_eq2_4_recover_clean_magic_formula():
    B, C, D, E = 0.12, 1.4, 1.0, -0.5
    x = np.linspace(-90, 90, 3601)
    y = D * np.sin(C * np.arctan(B * x - E * (B * x - np.arctan(B * x))))
    e = estimate_sweep(x, y)
    assert e.method == "Eq. 2-4" and e.falls and e.has_peak
    assert e.D == pytest.approx(D, rel=3e-3)  # peak of a running mean over 2 % of the range
    assert e.BCD == pytest.approx(B * C * D, rel=0.02)
    # Eq. 2 with the curve's own y_a (the force at the largest slips, not the true asymptote)
    assert e.C == pytest.approx(1 + (1 - 2 / math.pi * math.asin(e.y_a / e.D)))
    assert e.C == pytest.approx(C, rel=0.05)
    # Eq. 4 with the estimated B and x_m
    bx = e.B * e.x_m
    assert e.E == pytest.approx((bx - math.tan(math.pi / (2 * e.C))) / (bx - math.atan(bx)))
    assert e.E == pytest.approx(E, abs=0.3)
    # sign-agnostic: an ISO-W curve (negative slope) gives the same factors
    e2 = estimate_sweep(x, -y)
    assert e2.C == pytest.approx(e.C) and e2.BCD == pytest.approx(e.BCD)


def test_eq2_minus_branch_for_saturating_curve():
    x = np.linspace(0, 30, 301)
    y = np.tanh(x / 3.0)  # saturates without falling
    e = estimate_sweep(x, y)
    assert not e.falls and e.C <= 1.0


def test_no_peak_fallback():
    # heavy truck tyre: the peak lies beyond the tested 12 deg
    x = np.linspace(-12, 12, 97)
    B, C, D = 0.05, 1.3, 0.8  # E = 0: the formula below is the Magic Formula with no curvature
    y = D * np.sin(C * np.arctan(B * x))
    e = estimate_sweep(x, y)
    assert e.method == "no peak: fallback" and not e.has_peak
    assert e.C == 1.3 and e.E == 0.0
    assert e.D == pytest.approx(D, rel=0.02)  # through the last point with the measured BCD
    assert e.x_m > 12


def test_noise_floor_unaffected_by_smooth_curve():
    df = lateral_sweeps(loads=(4000.0,), cambers_deg=(0.0,), noise=0.0)
    parts, _ = prepare_data(df)
    nf, _ = point_scatter(parts["lateral"])
    peak = df["fy"].abs().max()
    assert nf < 0.002 * peak


# -- FitResult ---------------------------------------------------------------------------------
def test_result_contents(lateral_fit, lateral):
    r = lateral_fit
    assert isinstance(r, FitResult)
    assert set(r.coefficients.loc[r.coefficients["part"] == "lateral", "name"]) == set(pac89.LATERAL)
    assert r.parts == ["lateral", "aligning"]  # the generator also gives Mz
    varied = r.coefficients[r.coefficients["varied"]]
    assert (varied["stderr"] > 0).all() and np.isfinite(varied["stderr"]).all()
    assert r.params["a3"].stderr == pytest.approx(float(varied.set_index("name").loc["a3", "stderr"]))
    corr = r.correlations["lateral"]
    assert_allclose(np.diag(corr.to_numpy()), 1.0)
    assert len(r.sweeps) == 40 and {"rmse", "bias", "rmse_pct", "bias_pct", "noise"} <= set(r.sweeps)
    pred = r.predict(lateral)
    assert_allclose(np.sqrt(np.mean((pred["fy_model"] - lateral["fy"]) ** 2)), r.rmse, rtol=1e-9)
    text = r.summary()
    assert "RMSE" in text and "a3" in text
    html = r._repr_html_()
    assert "<table>" in html and "a11" in html


def test_result_plots_and_report(lateral_fit, tmp_path):
    import matplotlib.pyplot as plt

    # without an Axes: a pyplot figure, one panel per condition level (an array of Axes when several)
    axes = np.atleast_1d(lateral_fit.plot()).ravel()
    assert plt.get_fignums() and axes[0].get_xlabel().startswith("slip angle")
    shown = [a for a in axes if a.get_visible()]
    assert sum(len(a.lines) for a in shown) >= 8 and len(shown) == len(lateral_fit.facets(lateral_fit.parts[0])[0])
    plt.close("all")
    ax = lateral_fit.plot(plt.figure().subplots())  # an Axes: one condition level drawn on it
    assert ax.get_xlabel().startswith("slip angle") and len(ax.lines) >= 8
    ax2 = lateral_fit.plot_residuals()
    assert ax2 is not None
    plt.close("all")
    p = lateral_fit.report(tmp_path / "rep")
    text = p.read_text()
    assert text.count("data:image/png;base64") >= 2
    assert "Not identifiable" not in text or "a9" in text
    assert (tmp_path / "rep" / "sweeps.csv").exists()


def test_tyre_info_goes_into_the_tyre(lateral):
    df = lateral[lateral["fz"].isin([2000.0, 8000.0]) & np.isclose(lateral["camber"], 0.0)]
    base = example_tyre()
    r = fit_pac89(df, tyre_info={"unloaded_radius": 0.326, "width": 0.245, "fnomin": 4000.0,
                                 "lateral_stiffness": 190e3, "name": "x", "header": ["from a test"]})
    t = r.tyre
    assert (t.unloaded_radius, t.width, t.fnomin, t.lateral_stiffness, t.name) == (0.326, 0.245, 4000.0, 190e3, "x")
    assert "from a test" in t.header
    r2 = fit_pac89(df, tyre_info=base)
    assert r2.tyre.unloaded_radius == 0.326 and r2.tyre.name == base.name


def test_fit_speed_200_points():
    import time

    df = lateral_sweeps(loads=(2000.0, 5000.0, 8000.0), cambers_deg=(0.0,), slip_deg=np.linspace(-12, 12, 67))
    fit_pac89(df)  # warm-up (imports)
    t0 = time.perf_counter()
    fit_pac89(df)
    assert time.perf_counter() - t0 < 1.5  # issue 8 needs well under 0.3 s; generous for a loaded CI machine
