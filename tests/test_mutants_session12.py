"""Tests for the sampled mutants of the redrawn fitting/engine.py, io/readers.py and io/tir.py samples that
survived the quick suite (issue 25's ``--sample 216 --seed 15`` on the code of 8d66ef5).

Each test states documented behaviour (the physical limits of a PAC89 fit, the version an MF property
file declares), not the mutated text.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).resolve().parent / "data"
MF61 = DATA / "mfeval_MagicFormula61_Paramerters.tir"


# ------------------------------------------------------------------------------ tyrefit/fitting/engine.py
def _stiffness_vanishing_at_4_deg():
    """Lateral sweeps (3 and 6 kN, camber -4, 0, 4 deg) of a PAC89 tyre whose cornering stiffness falls to
    zero at |camber| = 4 deg: BCD's camber factor 1 - a5 |gamma| with a5 = 0.25 / deg."""
    from tyrefit.synthetic.pac89_example import EXAMPLE, lateral_sweeps

    return lateral_sweeps(loads=(3000.0, 6000.0), cambers_deg=(-4.0, 0.0, 4.0),
                          coefficients=dict(EXAMPLE, a5=0.25), seed=5)


def _cornering_stiffness(coefficients, fz, camber_deg):
    """dFy/dalpha at zero slip [N/rad] of a PAC89 coefficient set (central difference)."""
    from tyrefit.models import pac89

    h = np.radians(0.01)
    g = np.radians(camber_deg)
    return float((pac89.lateral_force(coefficients, fz, h, g) - pac89.lateral_force(coefficients, fz, -h, g))
                 / (2 * h))


def test_a_camber_fit_keeps_the_cornering_stiffness_at_every_tested_camber():
    """engine.py [227] ``_Problem._direct_bounds`` (the largest |camber| taken in rad, not deg).

    BCD = a3 sin(2 atan(Fz/a4)) (1 - a5 |gamma|), gamma in degrees: the physical limit on a5 keeps the camber
    factor at >= 1 % over the data's camber range, so a fitted tyre has a cornering stiffness of the normal
    (ISO-W negative) sign at every camber it was fitted on (about 1 % of the zero-camber one at the limit: the
    camber shifts move the zero-slip point a little), and the fit says when the data push against
    that limit.  Data whose stiffness vanishes at 4 deg want a5 = 0.25 / deg; the fit stops at 0.99 / 4.
    The mutant measures the largest camber in radians (0.07 instead of 4): the limit becomes 14 / deg, the
    fit follows the data to a tyre with no cornering stiffness at 4 deg, and no note says so.
    """
    from tyrefit.fitting import fit_pac89

    r = fit_pac89(_stiffness_vanishing_at_4_deg(), vary=["a0", "a2", "a3", "a5", "a7"])
    c = r.tyre.coefficients
    for fz in (3000.0, 6000.0):
        k0 = _cornering_stiffness(c, fz, 0.0)
        assert k0 < 0.0
        for cam in (-4.0, 4.0):
            k = _cornering_stiffness(c, fz, cam)
            assert k < 0.0 and k / k0 > 0.005, (fz, cam, k, k0)
    assert "a5" in r.at_bound["lateral"]
    assert any("a5 ended at its upper bound" in n and "physical limits" in n for n in r.notes), r.notes


def test_a5_bounds_given_beyond_the_camber_range_physical_limit_are_refused():
    """engine.py [227], through fit_pac89(bounds=): bounds that would take the camber factor 1 - a5 |gamma| to
    or below zero within the data's camber range (4 deg: a5 >= 0.25 / deg) are outside the physical range and
    refused with a DataError naming the coefficient; the mutant's range (a5 up to 14 / deg) accepts them."""
    from tyrefit.errors import DataError
    from tyrefit.fitting import fit_pac89

    d = _stiffness_vanishing_at_4_deg()
    with pytest.raises(DataError, match=r"bounds given for a5.*outside its physical range"):
        fit_pac89(d, vary=["a0", "a2", "a3", "a5", "a7"], bounds={"a5": (0.3, 0.5)})


# ------------------------------------------------------------------------------ tyrefit/io/tir.py
def test_an_mf_62_file_reads_as_version_6_2_evaluated_as_6_1(tmp_path):
    """tir.py [21] ``mf_from_property_file`` (FITTYP 62 no longer mapped to '6.2').

    MFTyre.version is '5.2', '6.1' or '6.2' (6.2 evaluated as 6.1; tyres/mf.py).  The same coefficients
    declared FITTYP = 62 read as an MF61-family tyre of version '6.2' with the 6.1 file's forces; the mutant
    reports a 6.2 file as version '6.1'.
    """
    from tyrefit.io.tir import read_tyre

    text = MF61.read_text()
    p62 = tmp_path / "mf62.tir"
    p62.write_text(re.sub(r"^(FITTYP\s*=\s*)61\b", r"\g<1>62", text, count=1, flags=re.M))
    t61, t62 = read_tyre(MF61), read_tyre(p62)
    assert (t61.family, t61.version) == ("MF61", "6.1")
    assert (t62.family, t62.version) == ("MF61", "6.2")
    alpha = np.radians([-8.0, -2.0, 0.5, 3.0, 10.0])
    f61 = t61.forces(4500.0, alpha, 0.04, np.radians(2.0))
    f62 = t62.forces(4500.0, alpha, 0.04, np.radians(2.0))
    assert set(f61) == set(f62)
    for k in f61:
        assert np.all(np.isfinite(f61[k])), k
        np.testing.assert_array_equal(f62[k], f61[k])


def test_load_spike_screening_scales_with_the_sweeps_own_load_noise():
    """A record whose measured load fluctuates by 12 % (sd) around its set point (a rig holding position, not
    load) loses no sample as a 'load spike'; a real spike, 2.5 x the set load, is still left out.  The
    threshold is the larger of 25 % of the sweep's median load and 8 robust sd of its own load noise."""
    from tyrefit.fitting.engine import screen_sweeps
    from tyrefit.synthetic.pac89_example import lateral_sweeps

    df = lateral_sweeps(loads=(3000.0, 6000.0), cambers_deg=(0.0,), seed=5)
    rng = np.random.default_rng(11)
    df["fz"] = df["fz"] * (1.0 + 0.12 * rng.standard_normal(len(df)))
    spike = df.index[(df["run"] == df["run"].iloc[0])][40]
    df.loc[spike, "fz"] = 2.5 * 3000.0
    keep, rep = screen_sweeps(df, "fy", "slip_angle")
    assert rep["load_spikes"] == 1 and not keep[df.index.get_loc(spike)]
    assert rep["low_load"] == 0 and rep["force_spikes"] == 0 and int((~keep).sum()) == 1


# ------------------------------------------------------------------------------ tyrefit/io/segment.py
def test_turning_points_are_the_extremes_of_a_noisy_triangle_sweep():
    """The zig-zag detector returns the samples where the slip turns: the largest (smallest) sample of each
    leg, not a neighbour of it, with rig noise on every sample; ripples smaller than the threshold are not
    turns."""
    from tyrefit.io.segment import _turning_points

    x = np.r_[np.linspace(0, 12, 49), np.linspace(12, -12, 97)[1:], np.linspace(-12, 12, 97)[1:],
              np.linspace(12, 0, 49)[1:]]
    x = x + 0.02 * np.random.default_rng(1).standard_normal(x.size)
    x[20:23] += [0.0, 0.6, 0.0]  # a ripple of 0.6 deg on the first leg: below the threshold
    want = [int(np.argmax(x[:96])), 96 + int(np.argmin(x[96:192])), 192 + int(np.argmax(x[192:]))]
    assert want[0] in (47, 48, 49) and want[1] in (143, 144, 145) and want[2] in (239, 240, 241)
    assert _turning_points(x, 3.0).tolist() == want


# ------------------------------------------------------------------------------ tyrefit/fitting/engine.py
# (issue 25's --sample 216 --seed 15 redrawn on the code of bb25c64: engine.py changed in 2be0732 and bed5945)
def _lateral_only(**kw):
    """Lateral sweeps (3 and 6 kN, zero camber) of the PAC89 example tyre, without the aligning moment."""
    from tyrefit.synthetic.pac89_example import lateral_sweeps

    return lateral_sweeps(loads=(3000.0, 6000.0), cambers_deg=(0.0,), seed=5, **kw).drop(columns=["mz"])


def test_data_without_a_camber_column_are_fitted_at_zero_camber():
    """engine.py [59] ``_frame`` (a missing camber column filled with 1 rad instead of 0).

    Camber is optional in the fit's data: a rig record without it was run at zero camber.  The fitted tyre
    then reproduces the data when evaluated at zero camber, also when a camber coefficient is held at a
    non-zero value (a5, the camber fall of the cornering stiffness, from an earlier fit); its fitted camber
    range is (0, 0) and its sweeps are listed at 0 deg.  The mutant fits the same data as if run at 57 deg:
    a3 grows to make up for the camber factor 1 - a5 |gamma|, and the tyre at zero camber is far stiffer
    than the data.
    """
    from tyrefit.fitting import fit_pac89
    from tyrefit.models import pac89

    d = _lateral_only()
    r = fit_pac89(d.drop(columns=["camber"]), fixed={"a5": 0.01})
    assert r.tyre.ranges["camber"] == (0.0, 0.0)
    assert np.all(r.sweeps["camber"] == 0.0)
    f = pac89.lateral_force(r.tyre.coefficients, d["fz"].to_numpy(), d["slip_angle"].to_numpy(), 0.0)
    rmse = float(np.sqrt(np.mean((f - d["fy"].to_numpy()) ** 2)))
    assert rmse < 1.2 * r.stats["lateral"]["noise_floor"], rmse
    assert r.stats["lateral"]["rmse"] == pytest.approx(rmse, rel=1e-6)


def test_the_reported_evaluation_count_is_the_number_of_model_evaluations(monkeypatch):
    """engine.py [137] ``_fit_part`` (each start's stage-2 evaluations subtracted from the total).

    ``FitResult.stats[part]['nfev']`` (the report's "evaluations") counts the residual evaluations of the
    whole fit, all starts and the polish: it is positive and at most the number of times the fit evaluated
    its model's residual (a few of those are the objective read at each start's end), and at least the sum
    over the starts.  The mutant reports a negative count.
    """
    from tyrefit.fitting import engine, fit_pac89

    calls = {"n": 0}
    rows = engine._Problem.rows

    def counted(self, theta):
        calls["n"] += 1
        return rows(self, theta)

    monkeypatch.setattr(engine._Problem, "rows", counted)
    r = fit_pac89(_lateral_only())
    n = r.stats["lateral"]["nfev"]
    starts = r._parts["lateral"].starts
    assert len(starts) >= 2
    assert sum(s["nfev"] for s in starts) <= n <= calls["n"], (n, calls["n"])
    assert n >= 0.8 * calls["n"], (n, calls["n"])


def test_robust_cost_scales_each_sweep_by_its_own_noise_below_one_unit():
    """engine.py [362] ``robust_scale`` (a sweep's own noise used only above 1 N or N*m).

    The robust costs measure each point's residual against its own sweep's noise (point_scatter's per-sweep
    value) times HUBER_K; only sweeps too short for an estimate take the pooled value.  Aligning moments
    have noise well below 1 N*m (here 0.29 and 0.75 N*m in the two sweeps): each sweep keeps its own scale,
    so a residual of 1 N*m counts as 3.4 sigma in the quiet sweep and 1.3 sigma in the noisy one.  The
    mutant gives both sweeps the pooled 0.57 N*m.
    """
    from tyrefit.fitting.engine import HUBER_K, point_scatter, prepare_data, robust_scale
    from tyrefit.synthetic.pac89_example import lateral_sweeps

    parts, _ = prepare_data(lateral_sweeps(loads=(3000.0, 6000.0), cambers_deg=(0.0,), seed=5))
    d = parts["aligning"]
    pooled, per = point_scatter(d)
    assert len(per) == 2 and per.max() < 1.0 and per.max() > 2 * per.min()
    sigma = robust_scale(d) * d.norm / HUBER_K
    for run, s in per.items():
        np.testing.assert_allclose(sigma[d.run == run], s, rtol=1e-12)


def test_a_tyre_whose_force_crosses_zero_only_at_the_end_of_the_sweep_is_fitted():
    """engine.py [475] ``_check_orientation`` (the negative side checked from -xmax to -0.5 rad).

    The turnover check refuses a fitted curve whose force has the wrong sign over the outer half of the
    tested slip range (C > 2 turns the PAC89 curve over past its peak).  It judges the curve where it was
    tested: a tyre with C = 2.8 and E = -1 (a steep fall past the 4 deg peak) whose force crosses zero at
    11-11.6 deg of a +-12 deg sweep keeps the ISO-W sign over most of the outer half, and its fit reproduces
    the data to the noise floor.  The mutant judges the negative side out to 28.6 deg, beyond the data,
    where the curve has turned over, and refuses the fit ("wrong sign beyond half the slip range").
    """
    from tyrefit.fitting import fit_pac89
    from tyrefit.synthetic.pac89_example import EXAMPLE

    d = _lateral_only(coefficients=dict(EXAMPLE, a0=2.8, a6=0.0, a7=-1.0))
    r = fit_pac89(d)
    st = r.stats["lateral"]
    assert st["rmse"] < 1.05 * st["noise_floor"]
    assert r.tyre.coefficients["a0"] == pytest.approx(2.8, abs=0.05)


# ------------------------------------------------------------------------------ tyrefit/diagnose/stats.py
# (the sampled mutants of issue 25's --sample 216 --seed 15 on the code of 8b5c2bc, diagnose's speed-up)
def test_the_noise_screenings_score_variance_is_j_sigma_j_of_the_noise_model(monkeypatch):
    """stats.py [285] ``screen_candidates`` (lagged cross-products of J~ summed as x - x[swap], not x + x[swap]).

    The noise-model screening studentises every candidate's score s = J~' r with its variance under the
    estimated noise, J~' Sigma J~ with Sigma_g = sd_g^2 rho^|i-j| + tau^2 within each sweep (the Notes).
    With the noise model fixed at a known one, the reported score variance of a two-parameter candidate is
    that matrix, computed here the long way.  The mutant drops the correlated part of Sigma (a
    one-parameter candidate's lagged products cancel exactly): under correlated noise the score of a smooth
    direction is judged against white noise.
    """
    from tyrefit.diagnose import stats as S

    G, n = 3, 25
    sweep = np.repeat(np.arange(G), n)
    lay = S.SweepLayout(sweep, G)
    x = np.tile(np.linspace(-1.0, 1.0, n), G)
    J_model = np.column_stack([np.ones_like(x), x])
    J_new = [np.column_stack([x**2, np.abs(x) * (1.0 + 0.3 * sweep)])]
    nm = S.NoiseModel(sd=np.array([1.0, 2.0, 1.5]), rho=np.array([0.7]), tau=np.array([0.4]))
    monkeypatch.setattr(S, "corrected_noise", lambda *a, **k: (nm, nm))
    resid = np.random.default_rng(3).standard_normal(len(x))
    scr = S.screen_candidates(J_model, J_new, resid, lay, np.random.default_rng(4), n_boot=50, method="noise")

    Jt = S.residualise(J_new[0], J_model)
    i = np.arange(n)
    expected = np.zeros((2, 2))
    for g in range(G):
        sigma = nm.sd[g] ** 2 * nm.rho[0] ** np.abs(i[:, None] - i[None, :]) + nm.tau[0] ** 2
        Jg = Jt[sweep == g]
        expected += Jg.T @ sigma @ Jg
    assert scr.info[0]["var"] == pytest.approx(expected, rel=1e-9, abs=1e-9 * np.abs(expected).max())


def test_the_bias_corrected_noise_model_of_strongly_correlated_noise_is_a_stationary_ar1():
    """stats.py [405] ``corrected_noise`` (the corrected rho's upper clip doubled: 1.94).

    The bias correction moves rho by the bias the pilot draws show, 2 rho_obs - mean(rho_pilot); for noise
    as correlated as the estimator can tell (rho 0.99, 20-point sweeps) that lands above 1 (1.08).  The corrected model is what
    the screening draws its null noise from, so it must stay a stationary AR(1) (|rho| < 1): drawn from,
    every point of a sweep has the same sd.  The mutant lets rho pass 1: the draws grow along the sweep.
    """
    from tyrefit.diagnose import stats as S

    G, n = 6, 20
    lay = S.SweepLayout(np.repeat(np.arange(G), n), G)
    x = np.tile(np.linspace(-1.0, 1.0, n), G)
    true = S.NoiseModel(sd=np.full(G, 10.0), rho=np.array([0.99]), tau=np.array([0.0]))
    e = S.simulate_noise(true, lay, 1, np.random.default_rng(0))[0]
    Q, dw, db = S.projection_basis(np.column_stack([x, x**3, np.ones_like(x)]), lay)
    _, cor = S.corrected_noise(e, Q, dw, db, lay, np.random.default_rng(2))
    assert np.all(np.abs(np.asarray(cor.rho)) < 1.0)
    draws = S.simulate_noise(cor, lay, 4000, np.random.default_rng(5))[:, :n]
    assert np.all(np.isfinite(draws))
    assert np.std(draws[:, -1]) == pytest.approx(np.std(draws[:, 0]), rel=0.1)


# ------------------------------------------------------------------------------ tyrefit/models/pac89.py
def test_the_lateral_jacobians_force_without_a_camber_is_the_lateral_force_at_zero_camber():
    """pac89.py [89] ``lateral_jacobian``'s default camber (0 rad changed to 1 rad).

    ``lateral_jacobian`` returns the lateral force identical to :func:`lateral_force`, whose camber
    defaults to 0: called the same way (no camber), both give the zero-camber force, and the Jacobian
    matches a central difference of that force.  The mutant evaluates a cambered (57 deg) tyre instead.
    """
    from tyrefit.models import pac89
    from tyrefit.synthetic.pac89_example import EXAMPLE

    fz = np.array([2000.0, 4000.0, 6000.0])
    alpha = np.radians([-6.0, 1.0, 8.0])
    fy, jac = pac89.lateral_jacobian(EXAMPLE, fz, alpha, names=["a8", "a3"])
    assert fy == pytest.approx(pac89.lateral_force(EXAMPLE, fz, alpha), rel=1e-12)
    assert fy == pytest.approx(pac89.lateral_force(EXAMPLE, fz, alpha, 0.0), rel=1e-12)
    for j, k in enumerate(["a8", "a3"]):
        h = 1e-6 * max(1.0, abs(EXAMPLE[k]))
        up = pac89.lateral_force(dict(EXAMPLE, **{k: EXAMPLE[k] + h}), fz, alpha)
        dn = pac89.lateral_force(dict(EXAMPLE, **{k: EXAMPLE[k] - h}), fz, alpha)
        assert jac[:, j] == pytest.approx((up - dn) / (2 * h), rel=1e-5, abs=1e-6)


# ------------------------------------------------------------------------------ tyrefit/diagnose/engine.py
def test_a_systematic_misfits_where_lines_say_whether_they_list_slip_ranges_or_cells():
    """engine.py [252] ``_misfit_text`` (the slip-range line left as its bare label: the ranges dropped).

    The report of a systematic misfit says where it is largest, one line per kind of place: the slip ranges
    (in deg, with the mean |error|) and the test cells (load, camber, pressure), each line naming its kind.
    The mutant keeps the words 'slip ranges' and drops the ranges themselves: the report says the misfit is
    largest at 'slip ranges' without saying which.
    """
    from tyrefit.diagnose.engine import _misfit_text

    mf = {"odd_share": 0.8, "components": {"common": 0.7, "fz": 0.2}, "rmse_heldout_N": 40.0, "ratio": 2.0,
          "noise_floor_N": 20.0, "predictable_share": 0.6, "predictable_rmse_N": 30.0, "not_testable": [],
          "slip_ranges": [{"slip_deg": (-12.0, -8.0), "mean_abs_N": 55.0},
                          {"slip_deg": (8.0, 12.0), "mean_abs_N": 50.0}],
          "cells": [{"fz_N": 6000.0, "camber_deg": 0.0, "pressure_kPa": None, "rmse_N": 60.0}]}
    text, where = _misfit_text(mf, None)
    assert len(where) == 2
    assert where[0].startswith("slip ranges ") and "-12.0 to -8.0 deg" in where[0]
    assert where[1].startswith("cells ") and "Fz 6.0 kN" in where[1]
    assert "largest at slip ranges -12.0 to -8.0 deg" in text
    assert "the model's curve shape" in text


def test_the_zero_slip_shift_check_reads_only_sweeps_through_zero_slip():
    """engine.py [422] ``_shift_evidence`` (a sweep skipped when its least slip is above +0.3 x the window,
    not above -0.3 x: one-sided sweeps pass).

    The check reads each sweep's force at zero slip as the intercept of a quartic through the points within
    +-3 deg, so only sweeps that reach well into both sides of zero count; with fewer than 3 of them it
    leaves the decision to the held-out evidence.  8 sweeps through zero and 4 that start at zero slip
    (0..3 deg): the verdict rests on the 8.  Only one-sided sweeps: no verdict from this check.  The mutant
    reads the one-sided sweeps' extrapolated intercepts as well (12 sweeps; 4 with only one-sided ones).
    """
    from types import SimpleNamespace

    from tyrefit.diagnose.engine import _shift_evidence

    n, floor = 49, 20.0
    both = np.radians(np.linspace(-3.0, 3.0, n))
    one = np.radians(np.linspace(0.0, 3.0, n))
    slip = np.r_[np.tile(both, 8), np.tile(one, 4)]
    sweep = np.repeat(np.arange(12), n)
    fz = np.repeat(np.r_[np.linspace(2000.0, 8000.0, 8), np.linspace(2000.0, 8000.0, 4)], n)
    d = SimpleNamespace(inputs=SimpleNamespace(slip_angle=slip, fz=fz), sweep=sweep)
    noise = floor * np.random.default_rng(3).standard_normal(slip.size)
    out = _shift_evidence(d, noise, 0.10, floor)
    assert out.startswith("no shift at zero slip") and "of 8 sweeps" in out
    m = sweep >= 8
    d1 = SimpleNamespace(inputs=SimpleNamespace(slip_angle=slip[m], fz=fz[m]), sweep=sweep[m] - 8)
    assert _shift_evidence(d1, noise[m], 0.10, floor) is None


def test_a_knee_on_top_of_the_richest_testable_friction_law_is_refused_naming_that_law():
    """engine.py [429] ``_knee_evidence`` (the friction law in the model read as ``in_model[1]``).

    A grip loss above the rated load is named only when it beats every smooth law of friction in load; when
    the model already has the richest law these loads can test (none richer left in the pool), the knee
    cannot be told from that law's further curvature and the refusal names the law in the model.  The
    mutant reads a second load_friction law that a model never has: the diagnosis stops with an IndexError.
    """
    from types import SimpleNamespace

    from tyrefit.diagnose.engine import _knee_evidence

    fz = np.repeat([3000.0, 5000.0, 7000.0], 10)
    eng = SimpleNamespace(data=SimpleNamespace(inputs=SimpleNamespace(fz=fz, rated_load=5000.0)))
    st = SimpleNamespace(oof=np.ones(fz.size))
    effects = [SimpleNamespace(id="load_friction_curved", family="load_friction"),
               SimpleNamespace(id="overload_knee", family="overload")]
    cur = SimpleNamespace(spec=SimpleNamespace(effects=effects))
    why = _knee_evidence(eng, st, cur, {}, {}, 1.0, None)
    assert why.startswith("no knee told apart: load_friction_curved is in the model")


# ------------------------------------------------------------------ tyrefit/fitting/mf.py and its split (issue 27)
# the sampled mutants of --sample 60 --seed 15 over fitting/mf.py, mf_identify.py, mf_contract.py, mf_eval.py and
# mf_initial.py (code of 4b45581, 12 per file) that survived the quick suite
def _published(loads, tyre=None, **kw):
    """Sweeps of the published MF 6.1 set (combined-slip shifts removed; ``tyre``: changes to it) at ``loads``
    (fractions of FNOMIN), with its tyre info and the set itself."""
    from tyrefit.synthetic import ttc_drivebrake as gen

    p = dict(gen.contract_mf61(), **(tyre or {}))
    fn = p["FNOMIN"]
    info = {"fnomin": fn, "unloaded_radius": p["UNLOADED_RADIUS"]}
    kw = {"pressures": [260e3], "cambers_deg": [0.0], "slip_angles_deg": [0.0], "seed": 3, **kw}
    return gen.make_sweeps(p, loads=[f * fn for f in loads], **kw), info, p


def _why(stage, df):
    """identifiability of ``stage`` on the records ``df``: (reasons, facts)."""
    from tyrefit.fitting.mf import _STAGE, identifiability, prepare_mf_data

    data = prepare_mf_data(df)
    st = _STAGE[stage]
    return identifiability(st, data.subset(st.sweeps, st.channel), data.sweeps, version="6.1")


def test_the_joint_polish_lowers_the_error_the_stages_leave():
    """mf.py [534], [584] ``_joint_polish`` (a Jacobian column of Fx/Fy without the data: ``rj = w``, or with the
    data added instead of subtracted).

    The stages hold the earlier stages' coefficients, so the noise of the pure-slip estimates propagates into
    the later channels (combined Mz through alpha_eq, Pacejka 2012 4.E77-4.E78); the joint polish moves every
    fitted Fx/Fy/Mz coefficient at once and lowers what the stages leave.  With a wrong Jacobian it stops where
    it started (or is dropped for not improving), and the tyre keeps the staged error.
    """
    from tyrefit.fitting.mf import fit_mf

    df, info, _ = _published([0.5, 1.0, 1.5], slip_angles_deg=[0.0, -3.0, -6.0], n_points=15)
    stages = ["Fx0", "Fy0", "Mz0", "Fx", "Fy", "Mz", "Mx"]
    staged = fit_mf(df, tyre_info=info, stages=stages, multistart=False)
    polished = fit_mf(df, tyre_info=info, stages=[*stages, "joint"], multistart=False)
    joint = polished.stages["joint"]
    assert "joint" not in staged.stages and joint.varied
    # measured (seeds 1, 2, 3, 5): the objective falls to 0.93-0.97 of the staged one
    assert joint.objective < 0.98 * joint.facts["objective_before"]
    assert polished.rmse < 0.99 * staged.rmse, (polished.rmse, staged.rmse)


def test_the_lmuv_reason_names_the_records_speed_levels():
    """mf_identify.py [11] (the list of speeds ``and`` 'none given': 'none given' whenever speeds are given).

    At one speed LMUV is held, and the reason says which speed the records were measured at, so the user
    knows what a second speed level would add."""
    df, _, _ = _published([0.6, 1.4], n_points=15, combined=False)
    assert df["speed"].nunique() == 1
    why, facts = _why("Fx0", df)
    assert facts["speed_levels"] == 1
    assert "11.1" in why["LMUV"] and "none given" not in why["LMUV"], why["LMUV"]


def test_the_g_abs_g_term_of_mx_is_fitted_from_three_levels_of_abs_camber():
    """mf_identify.py [25] (QSX12 with > 3 levels of |camber| instead of >= 3).

    QSX12's g|g| is g itself at one non-zero camber, so it needs 3 levels of |camber|; 0, 2 and 4 deg are three.
    """
    why, facts = _why("Mx", _published([0.6, 1.4], cambers_deg=[0.0, 2.0, 4.0], n_points=13)[0])
    assert facts["abs_camber_levels"] == 3
    assert "QSX12" not in why, why.get("QSX12")
    why2, _ = _why("Mx", _published([0.6, 1.4], cambers_deg=[0.0, 3.0], n_points=13)[0])
    assert "QSX12" in why2


def test_camber_curvature_terms_are_fitted_from_three_abs_camber_levels_at_one_load():
    """mf_identify.py [49] (PEY5, PKY5, QDZ4, QSY6 with > 3 levels of |camber| instead of >= 3).

    The gamma^2 terms beyond the first need 3 levels of |camber|, or 2 with loads: at one load, 0, 2 and 4 deg
    identify them."""
    why, facts = _why("Fy0", _published([1.0], cambers_deg=[0.0, 2.0, 4.0], n_points=21, combined=False)[0])
    assert (facts["load_levels"], facts["abs_camber_levels"]) == (1, 3)
    assert "PEY5" not in why and "PKY5" not in why, (why.get("PEY5"), why.get("PKY5"))


def test_a_camber_of_minus_0_4_deg_is_of_the_other_sign():
    """mf_identify.py [120] (one sign when the smallest camber is above -0.5 deg instead of -0.25 deg).

    Cambers within 0.25 deg of zero count as zero; -0.4 deg and +3 deg are of both signs, which tells QBZ4
    (gamma in B_t) from QBZ5 (|gamma|).  With 0 and +3 deg the two are one column and QBZ4 is held."""
    why, facts = _why("Mz0", _published([0.6, 1.4], cambers_deg=[-0.4, 3.0], n_points=21, combined=False)[0])
    assert facts["camber_levels"] == 2
    assert "QBZ4" not in why, why.get("QBZ4")
    why2, _ = _why("Mz0", _published([0.6, 1.4], cambers_deg=[0.0, 3.0], n_points=21, combined=False)[0])
    assert "one sign" in why2["QBZ4"]


def _pressure_points(pressures, nompres):
    import pandas as pd

    fz = np.tile([2000.0, 4000.0, 6000.0], len(pressures))
    pr = np.repeat(pressures, 3)
    pts = pd.DataFrame({"fz": fz, "pressure": pr, "camber": 0.0, "slip_ratio": 0.1, "slip_angle": 0.0})
    return pts, {"NOMPRES": nompres, "FNOMIN": 4000.0}


def test_the_friction_constraint_holds_over_the_measured_pressures_only():
    """mf_contract.py [73] ``_grid`` (dpi of the grid = p / p0 instead of (p - p0) / p0).

    The constraints are held over the declared range: pressures 240-280 kPa about NOMPRES 260 kPa, dpi within
    +-7.7 %.  A friction law mu_x (1 + PPX3 dpi) with PPX3 = -1.5 stays positive there (it would be negative
    at dpi = 1, twice the nominal pressure, which no record measured); with PPX3 = -15 it is negative at 280 kPa.
    """
    from tyrefit.fitting.mf import _STAGE
    from tyrefit.fitting.mf_contract import _check_constraints, _grid
    from tyrefit.models import mf61

    pts, nominal = _pressure_points([240e3, 280e3], 260e3)
    grid = _grid(pts, nominal)
    p = {k.upper(): float(v) for k, v in mf61.neutral().items()}
    p.update(FNOMIN=4000.0, NOMPRES=260e3, PDX1=1.2)

    def mu_x_holds(ppx3):
        rows = _check_constraints(_STAGE["Fx0"], dict(p, PPX3=ppx3), grid)
        return next(r for r in rows if r["constraint"] == "mu_x > 0")["holds"]

    assert mu_x_holds(-1.5)
    assert not mu_x_holds(-15.0)


def test_the_fx0_curvature_constraint_is_pacejkas_e_x():
    """mf_contract.py [103] ``_factors`` (E_x with PEX2's load term subtracted).

    Fx0: E_x (Pacejka 2012, 4.E14) = (PEX1 + PEX2 dfz + PEX3 dfz^2)(1 - PEX4 sgn(kappa)) <= 1."""
    from tyrefit.fitting.mf_contract import _factors
    from tyrefit.models import mf61

    p = {k.upper(): float(v) for k, v in mf61.neutral().items()}
    p.update(FNOMIN=4000.0, PEX1=0.3, PEX2=0.4, PEX3=-0.2, PEX4=0.1)
    fz = np.array([1000.0, 3000.0, 4000.0, 6000.0, 9000.0])
    sgn = np.array([1.0, -1.0, 1.0, -1.0, 1.0])
    dfz = (fz - 4000.0) / 4000.0
    ex = (0.3 + 0.4 * dfz - 0.2 * dfz**2) * (1 - 0.1 * sgn)
    got = dict((n, v) for n, v, _ in _factors(p, "Fx0", fz, np.zeros(5), np.zeros(5), sgn))["E_x <= 1"]
    np.testing.assert_allclose(got, 1.0 - ex, rtol=1e-12)


def test_the_stage_evaluator_gives_the_models_channel_on_the_fast_and_the_plain_path(monkeypatch):
    """mf_eval.py [26], [27] ``_Eval.__call__`` (the plain path's pure-Fy branch taken for the combined Fy stage,
    or for Mz0).

    Each stage is evaluated at its own points as the model gives its channel there: pure-slip stages at zero
    slip angle or ratio (the book's Mz0, 4.E31, for the pure aligning stage), the others with pure-slip sweeps
    as pure slip.  mf_parts.FAST only chooses how (by parts, or the model's functions as they are): both paths
    give the model's values.
    """
    from tyrefit.fitting import mf_parts
    from tyrefit.fitting.mf import STAGES, prepare_mf_data
    from tyrefit.fitting.mf_eval import _Eval
    from tyrefit.models import mf61

    df, _, p = _published([0.6, 1.3], pressures=[240e3, 280e3], cambers_deg=[0.0, 3.0], slip_angles_deg=[0.0, -4.0],
                          n_points=9)
    data = prepare_mf_data(df)
    nominal = {k: float(p[k]) for k in ("FNOMIN", "NOMPRES", "LONGVL", "UNLOADED_RADIUS")}
    seen = set()
    for st in STAGES:
        pts = data.subset(st.sweeps, st.channel)
        if not len(pts):
            continue
        seen.add(st.name)
        fz = pts["fz"].to_numpy(float)
        kap, alp = pts["slip_ratio"].to_numpy(float).copy(), pts["slip_angle"].to_numpy(float).copy()
        kind = pts["kind"].to_numpy()
        if st.pure == "alpha":
            alp[:] = 0.0
        elif st.pure == "kappa":
            kap[:] = 0.0
        else:
            kap[kind == "lateral"] = 0.0
            alp[kind == "longitudinal"] = 0.0
        cond = {"camber": pts["camber"].to_numpy(float), "pressure": pts["pressure"].to_numpy(float),
                "speed": pts["speed"].to_numpy(float)}
        if st.pure == "kappa" and st.channel == "mz":
            want = mf61.mz0(p, fz, alp, cond["camber"], cond["pressure"], cond["speed"])
        else:
            want = mf61.forces(p, fz, slip_ratio=kap, slip_angle=alp, **cond)[st.channel]
        want = np.asarray(want, float)
        for fast in (True, False):
            monkeypatch.setattr(mf_parts, "FAST", fast)
            got = _Eval(pts, st, nominal, "6.1")(p)
            np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9 * np.max(np.abs(want)),
                                       err_msg=f"stage {st.name}, FAST {fast}")
    assert {"Fx0", "Fy0", "Mz0", "Fx", "Fy", "Mz", "Mx", "My"} <= seen, seen


def test_the_lmuv_start_is_the_first_order_regression_of_peak_friction_on_slip_speed():
    """mf_initial.py [22], [24] ``_initial_lmuv`` (slip speed times V0 instead of over it; no estimate at all).

    D = mu / (1 + LMUV Vs/V0) (Pacejka 2012, 4.E7): to first order the peak friction of the sweeps through
    their peak falls along Vs/V0 with slope -mu0 LMUV, so the Fx0 stage's start (``StageFit.initial``) is near
    the generating LMUV = 0.3 from drive/brake sweeps at three speeds.
    """
    from tyrefit.fitting.mf import fit_mf

    v0 = 16.6  # the published set's LONGVL: the middle speed is the fit's V0
    df, info, _ = _published([0.4, 1.0, 1.6], tyre={"LMUV": 0.3}, speeds=[0.5 * v0, v0, 1.5 * v0], n_points=31,
                             combined=False, seed=21)
    r = fit_mf(df, tyre_info=info, stages=["Fx0"], multistart=False)
    assert "LMUV" in r.stages["Fx0"].varied
    start = r.stages["Fx0"].initial.get("LMUV")
    # measured: 0.294 (this seed), 0.322-0.349 (seeds 22-24); the fitted value 0.276-0.304
    assert start is not None and abs(start - 0.3) <= 0.1, start


def test_a_single_sae_cornering_sweep_in_one_degree_steps_is_refused_as_iso():
    """mf_initial.py [141] ``_orientation`` (the slope near zero slip measured only from >= 6 points: with 5,
    -2..2 deg in 1 deg steps, the ISO orientation is assumed).

    In ISO-W a positive slip angle gives a negative lateral force; a record whose force rises with slip angle
    (SAE) passed as ISO is refused with the hint to pass the convention, also when it is one sweep of 1 deg
    steps with five points within 2 deg of zero slip.
    """
    from tyrefit.errors import DataError
    from tyrefit.fitting.mf import fit_mf

    df, info, _ = _published([1.0], n_points=25, combined=False)
    lat = df[df.groupby("run")["slip_ratio"].transform(lambda v: v.abs().max()) == 0]  # the cornering sweep
    assert lat["run"].nunique() == 1 and int((lat["slip_angle"].abs() <= np.radians(2.0) + 1e-12).sum()) == 5
    sae = lat.assign(fy=-lat["fy"])
    with pytest.raises(DataError, match="rises with slip angle"):
        fit_mf(sae, tyre_info=info, stages=["Fy0"], multistart=False)
