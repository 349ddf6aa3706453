"""Robust fitting: the cases that once gave a confident wrong tyre (issue 15), each measured against the clean fit.

The cases are built by :mod:`tyrefit.synthetic.robust_cases` from clean sweeps of
the PAC89 example set; a case's damage is the RMS error of its fitted tyre
against the generating one divided by the clean fit's (before the fixes:
spikes 868x, load glitch 7.5x, load drop-out 322x, lift-off 320x;
``python -m benchmarks.confident_wrong``).
"""

import json
import math
import subprocess
import sys
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from tyrefit.cli import main
from tyrefit.errors import DataError, FitError
from tyrefit.fitting import fit_pac89
from tyrefit.fitting.engine import (_check_orientation, _Problem, prepare_data, robust_scale, screen_sweeps)
from tyrefit.io.tir import read_tir
from tyrefit.synthetic.pac89_example import EXAMPLE, lateral_sweeps
from tyrefit.synthetic.robust_cases import make_case, tyre_error


@pytest.fixture(scope="module")
def clean_error():
    return tyre_error(fit_pac89(make_case("clean")).values)


def _ratio(result, clean_error):
    return tyre_error(result.values) / clean_error


def test_clean_fit_has_no_warnings_and_leaves_nothing_out(clean_error):
    r = fit_pac89(make_case("clean"))
    assert clean_error < 0.1                         # % of peak: the clean fit is good
    assert r.warnings == []
    assert r.screening["lateral"]["low_load"] == r.screening["lateral"]["force_spikes"] == 0
    assert r.screening["lateral"]["load_spikes"] == 0


# ------------------------------------------------------------------------------------------ spikes
def test_force_spikes_are_left_out_and_reported(clean_error):
    """Before: 5 samples x100 gave a tyre 868x worse than the clean fit, with no warning."""
    r = fit_pac89(make_case("spikes"))
    assert _ratio(r, clean_error) < 1.2
    assert r.screening["lateral"]["force_spikes"] == 5
    assert any("5 force spike(s)" in w for w in r.warnings)
    assert any("WARNING: lateral: left out of the fit: 5 force spike(s)" in h for h in r.tyre.header)
    assert "force spike" in r.summary()


@pytest.mark.parametrize("cost", ["huber", "soft_l1"])
def test_robust_costs_resist_spikes_without_screening(cost, clean_error):
    """The cost alone (screen=False): Huber / soft-l1 ignore the spikes, least squares does not."""
    df = make_case("spikes")
    robust = fit_pac89(df, cost=cost, screen=False)
    assert _ratio(robust, clean_error) < 1.5
    assert robust.cost == cost
    l2 = fit_pac89(df, cost="l2", screen=False)
    assert _ratio(l2, clean_error) > 100            # the damage the robust cost prevents


def test_robust_cost_is_least_squares_near_the_noise():
    """Below its scale (1.345 x each sweep's noise) Huber's cost is the l2 cost: same minimum on clean data."""
    df = make_case("clean")
    a, b = fit_pac89(df, vary=("a0", "a2", "a3", "a4", "a7")), fit_pac89(df, cost="huber",
                                                                         vary=("a0", "a2", "a3", "a4", "a7"))
    assert b.values["a3"] == pytest.approx(a.values["a3"], rel=0.01)
    d = prepare_data(df)[0]["lateral"]
    s = robust_scale(d)
    nf = d.df.groupby("run")["fy"].apply(lambda g: 0.01 * np.max(np.abs(g)))  # the generator's noise
    expect = 1.345 * pd.Series(d.run).map(nf).to_numpy() / d.fz
    assert np.median(s / expect) == pytest.approx(1.0, abs=0.25)
    # the robust objective is (1/n_s) s^2 rho(r^2 / s^2) summed: check one point of it by hand
    prob = _Problem(d, a.values, ["a3"], "huber")
    th = prob.theta_of(a.values)
    r = prob.rows(th) / prob.robust_scale
    rho = np.where(r**2 <= 1, r**2, 2 * np.abs(r) - 1)
    assert prob.objective(th) == pytest.approx(float(np.sum(rho * prob.robust_scale**2 / d.n_per_run)), rel=1e-10)


# ------------------------------------------------------------------------------------- load glitches
@pytest.mark.parametrize("case, key", [("fz_glitch_high", "load_spikes"), ("fz_glitch_low", "low_load"),
                                       ("liftoff", "low_load")])
def test_load_glitches_and_lift_off_are_left_out(case, key, clean_error):
    """Before: one load x10 gave 7.5x, one load /100 gave 322x, one lift-off sample (0.5 N) 320x."""
    r = fit_pac89(make_case(case))
    assert _ratio(r, clean_error) < 1.2
    assert r.screening["lateral"][key] == 1
    assert sum(r.screening["lateral"][k] for k in ("low_load", "load_spikes", "force_spikes")) == 1
    assert any("left out of the fit" in w for w in r.warnings)


def test_residuals_divide_by_a_robust_load(clean_error):
    """Without screening, a lift-off sample's mu residual divides by the sweep's half-median load, not 0.5 N."""
    r = fit_pac89(make_case("liftoff"), screen=False)
    assert _ratio(r, clean_error) < 20               # 320x when divided by the measured 0.5 N
    d = prepare_data(make_case("liftoff"), screen=False)[0]["lateral"]
    i = int(np.argmin(d.fz))
    assert d.fz[i] == 0.5 and d.norm[i] == pytest.approx(0.5 * np.median(d.fz[d.run == d.run[i]]))
    ok = d.fz > 100
    assert np.array_equal(d.norm[ok], d.fz[ok])      # every ordinary sample: the measured load


def test_screening_flags_nothing_on_bundled_rig_data():
    """No false alarms on the bundled records (TTC-like hysteresis and transients included)."""
    from tyrefit.io.datasets import data_path
    from tyrefit.io.readers import read_data

    for parts_, conv in ((("ttc", "fsae_cornering.dat"), "sae"), (("passenger", "passenger_205_55R16.csv"), "iso"),
                         (("truck", "tyre_a_dynamic.csv"), "iso"), (("slip", "slip_ratio.csv"), "iso")):
        parts, _ = prepare_data(read_data(data_path(*parts_), convention=conv))
        for name, d in parts.items():
            s = d.screening
            assert s["low_load"] + s["load_spikes"] + s["force_spikes"] == 0, (parts_, name, s)


def test_screen_sweeps_finds_a_spike_at_a_sweep_end_and_two_adjacent():
    df = lateral_sweeps(loads=(4000.0,), cambers_deg=(0.0,), seed=3)
    df.loc[0, "fy"] = 5e4                          # first point of the sweep (mirror-padded running median)
    df.loc[[80, 81], "fy"] *= 20                    # two adjacent samples (8 deg, past the peak)
    keep, rep = screen_sweeps(df, "fy", "slip_angle")
    assert rep["force_spikes"] == 3 and set(rep["index"]) == {0, 80, 81} and not keep[[0, 80, 81]].any()
    # (two adjacent spikes on the steep part near zero slip can also take out one good neighbour: harmless)


# ------------------------------------------------------------------------------------------- signs
def test_sign_flipped_data_is_refused():
    """Before: a flipped channel could be fitted as a reversed tyre (C ~ 3) with R^2 0.99."""
    with pytest.raises(DataError, match=r"rises with slip angle in 12 of 12 sweeps.*convention=sae"):
        fit_pac89(make_case("sign_flip"))


def test_sweeps_of_opposite_sign_are_refused():
    df = make_case("clean")
    flip = df["run"].isin([2, 7])
    df.loc[flip, "fy"] = -df.loc[flip, "fy"]
    with pytest.raises(DataError, match=r"sweeps of opposite sign: in runs \[2, 7\]"):
        fit_pac89(df)


def test_longitudinal_sign_is_checked():
    from tyrefit.synthetic.pac89_example import longitudinal_sweeps

    df = longitudinal_sweeps()
    df["fx"] = -df["fx"]
    with pytest.raises(DataError, match="falls with slip ratio"):
        fit_pac89(df)


def test_a_fitted_curve_that_turns_over_is_an_error():
    """C = 3 turns the curve over past its peak: the force has the wrong sign at large slip."""
    d = prepare_data(make_case("clean"))[0]["lateral"]
    bad = dict(EXAMPLE, a0=3.0, a3=8.5e8)
    with pytest.raises(FitError, match="turns over"):
        _check_orientation({"lateral": SimpleNamespace(data=d, coefficients=bad)})
    _check_orientation({"lateral": SimpleNamespace(data=d, coefficients=dict(EXAMPLE))})


# ------------------------------------------------------------------------------------- degenerate
def test_load_ramp_without_runs_fits_a_sane_tyre(clean_error):
    r = fit_pac89(make_case("load_ramp"))
    assert _ratio(r, clean_error) < 5                # measured 2.8 (fewer points than the clean data)
    assert r.stats["lateral"]["r2"] > 0.999


def test_many_tiny_sweeps_give_a_sane_tyre_and_a_warning(clean_error):
    """800 'sweeps' of 5 samples (a block counter used as run): a sane tyre, and a warning that says why."""
    clean = make_case("clean")
    big = pd.concat([clean] * 4, ignore_index=True).iloc[:4_000].copy()
    big["run"] = np.arange(len(big)) // 5
    r = fit_pac89(big)
    assert _ratio(r, clean_error) < 3
    assert any("too short to be slip sweeps" in w for w in r.warnings)


def test_rmse_far_above_the_noise_floor_is_a_warning():
    """A base model fitted to data with camber: RMSE many times the floor, said in one line."""
    df = make_case("clean")
    r = fit_pac89(df, vary=("a0", "a2", "a3", "a4", "a7"))
    w = [x for x in r.warnings if "x the within-sweep noise floor" in x]
    assert len(w) == 1 and w[0].startswith("lateral: RMSE")
    ratio = r.stats["lateral"]["rmse"] / r.stats["lateral"]["noise_floor"]
    assert f"{ratio:.1f} x" in w[0] and ratio > 3


# --------------------------------------------------------------------------------------- the CLI
def test_cli_reports_spikes_in_one_line_and_in_the_json(tmp_path, capsys):
    df = make_case("spikes")
    csv = tmp_path / "spiky.csv"
    out = df.assign(slip_angle=np.degrees(df["slip_angle"]), camber=np.degrees(df["camber"]))
    out.rename(columns={"fz": "fz [N]", "fy": "fy [N]", "mz": "mz [N*m]", "slip_angle": "slip_angle [deg]",
                        "camber": "camber [deg]"}).to_csv(csv, index=False)
    tir, js = tmp_path / "t.tir", tmp_path / "t.json"
    assert main(["fit", str(csv), "--out", str(tir), "--json", str(js), "--cost", "huber", "--size", "245/45R17",
                 "--rated-load", "5000"]) == 0
    lines = [x for x in capsys.readouterr().out.splitlines() if "WARNING" in x]
    assert len(lines) == 1 and "5 force spike(s)" in lines[0]
    assert any("5 force spike(s)" in w for w in json.loads(js.read_text())["warnings"])
    assert any("force spike" in h for h in read_tir(tir).header)


# ------------------------------------------------------------------------------------------ figures
def test_library_never_switches_the_backend_or_imports_pyplot(tmp_path):
    """Inline Jupyter figures need the user's backend untouched: a fit report renders through the object API, and
    plot() without an Axes draws on the user's pyplot backend (so plt.show() and a notebook display it)."""
    code = f"""
import matplotlib, sys
matplotlib.use("svg")
import tyrefit.cli, tyrefit.io.report, tyrefit.diagnose.report, tyrefit.diagnose.views, tyrefit.sim.plots
import tyrefit.compare.tyres, tyrefit.workflows.sttr_vs_dttr
from tyrefit.fitting import fit_pac89
from tyrefit.synthetic.pac89_example import lateral_sweeps
r = fit_pac89(lateral_sweeps(loads=(3000.0, 6000.0), cambers_deg=(0.0,), slip_deg=range(-12, 13)))
r.report({str(tmp_path / 'rep')!r})
assert "matplotlib.pyplot" not in sys.modules   # the report renders through the object API
import numpy as np
ax = np.atleast_1d(r.plot()).ravel()[0]          # no Axes given: a pyplot figure, which notebooks show
import matplotlib.pyplot as plt
assert ax.figure.number in plt.get_fignums()
assert matplotlib.get_backend() == "svg", matplotlib.get_backend()  # the user's backend, untouched
print("ok")
"""
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert res.returncode == 0 and res.stdout.strip() == "ok", res.stderr[-2000:]
    assert (tmp_path / "rep" / "index.html").stat().st_size > 10_000   # figures embedded


def test_fitted_tyre_error_metric_is_zero_for_the_truth():
    assert tyre_error(EXAMPLE) == 0.0
    assert tyre_error(dict(EXAMPLE, a3=1.1 * EXAMPLE["a3"])) > 0.5
    assert math.isfinite(tyre_error(dict(EXAMPLE, a2=1.1 * EXAMPLE["a2"])))


# ------------------------------------------------------------------------------------ property test
@pytest.fixture(scope="module")
def small_clean():
    df = lateral_sweeps(loads=(3000.0, 6000.0), cambers_deg=(0.0,), slip_deg=np.arange(-12.0, 12.0 + 1e-9, 0.5),
                        seed=21)
    return df, tyre_error(fit_pac89(df).values, loads=(3000.0, 6000.0))


def _spike_strategy():
    from hypothesis import strategies as st

    # not the first or last 2 samples of a sweep (49 each): there the mirrored running median sees two adjacent
    # spikes three times out of five and misses them (a known limit; the turn-over check then refuses the fit)
    inner = st.integers(0, 97).filter(lambda i: 2 <= i % 49 <= 46)

    def median_can_see(spikes):
        # a running median of 5 passes up to two spikes in any 5 neighbouring samples (screen_sweeps: its
        # documented limit); three within 5 samples of one sweep carry the median with them
        idx = sorted(i for i, _ in spikes)
        return not any(c // 49 == a // 49 and c - a <= 4 for a, c in zip(idx, idx[2:]))

    return st.lists(st.tuples(inner, st.sampled_from([-300.0, -20.0, -3.0, 4.0, 25.0, 1000.0])),
                    min_size=1, max_size=4, unique_by=lambda t: t[0]).filter(median_can_see)


def test_any_few_large_spikes_are_found_and_do_not_move_the_tyre(small_clean):
    """Property (hypothesis): 1-4 samples scaled by -300..1000 anywhere in two sweeps (at most two within any 5
    neighbouring samples, the running median's limit) are all left out, nothing else is, and the tyre stays
    within 1.3x the clean fit's error.  On the steep part near zero slip a spike shifts its neighbours'
    running median by one slip step; the second pass (the running median without the flagged samples)
    gives those good neighbours back (without it, a spike at -2.5 deg also took out its neighbour at
    -1.5 deg, and two spikes 5 samples apart three good samples, which moved the tyre 1.31x)."""
    from hypothesis import HealthCheck, given, settings

    df0, err0 = small_clean

    @settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
    @given(_spike_strategy())
    def check(spikes):
        df = df0.copy()
        for i, f in spikes:
            # scaled by f and pushed 20 kN further the same way: at least 20 kN off, a spike anywhere (adding
            # sign(f) 20 kN instead put f = 4 at -6.4 kN back within 0.7 kN of the curve: no spike at all)
            y = df.loc[i, "fy"]
            df.loc[i, "fy"] = y * f + np.sign(y * f - y or f) * 2e4
        r = fit_pac89(df)
        out, want = set(r.screening["lateral"]["index"]), {i for i, _ in spikes}
        assert out == want
        assert tyre_error(r.values, loads=(3000.0, 6000.0)) < 1.3 * err0

    check()
