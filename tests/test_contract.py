"""The physical-validity contract of every tyre tyrefit writes (tyrefit.tyres.contract, issue 23).

Each rule is shown to fail on a parameter set like the one a real TTC record gave before the contract
(QEZ1 = 11.97, PDX1 = 4.62 where the data reach 2.39, RHX1 = -0.0123 with RBX1 = 500, a de-aligning Mz,
QSX4 = -2.2e9 against QSX2 = 3.6e5) and to hold on a set that keeps it; then the fit is shown to keep
it on data whose generating tyre breaks it (MFeval's published MF 6.1 set: G_yk 1.028 inside its own
range) and on drive/brake sweeps that stop short of the Fx peak.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from tyrefit.cli import main
from tyrefit.errors import FitError
from tyrefit.fitting import mf as M
from tyrefit.fitting.mf import fit_mf
from tyrefit.io.tir import read_tyre
from tyrefit.models import mf61
from tyrefit.synthetic import ttc_drivebrake as gen
from tyrefit.tyres.contract import check_tyre, violations
from tyrefit.tyres.size import loaded_radius_law

DEG = math.pi / 180.0
FNOMIN = gen.PUBLISHED_MF61["FNOMIN"]
INFO = {"fnomin": FNOMIN, "unloaded_radius": gen.PUBLISHED_MF61["UNLOADED_RADIUS"]}
#: the envelope a TTC-like fit declares (slip angles of the combined sweeps, slip ratios, loads, cambers)
ENV = {"fz": (0.4 * FNOMIN, 1.6 * FNOMIN), "slip_angle": (-12 * DEG, 12 * DEG), "slip_ratio": (-0.2, 0.2),
       "camber": (0.0, 3 * DEG), "pressure": (220e3, 300e3)}


def _rules(p, **kw):
    return {(v.rule, v.channel) for v in violations(p, ENV, **kw)}


def test_a_set_that_keeps_the_contract_passes():
    assert violations(gen.contract_mf61(), ENV) == []


def test_the_published_set_breaks_g_le_1_and_the_contract_says_where():
    v = violations(gen.published_mf61(), ENV)
    assert ("G<=1", "Fy") in {(x.rule, x.channel) for x in v}
    worst = max(x.worst for x in v if x.rule == "G<=1" and x.channel == "Fy")
    assert 1.02 < worst < 1.04  # G_yk 1.028 near kappa = 0


@pytest.mark.parametrize("key,value,channel", [("QEZ1", 11.97, "Mz"), ("PEX1", 1.3, "Fx"), ("PEY1", 1.2, "Fy"),
                                               ("REX1", 1.5, "Fx"), ("REY1", 1.5, "Fy"), ("PEY3", 3.0, "Fy")])
def test_every_curvature_above_one_is_found(key, value, channel):
    assert ("E<=1", channel) in _rules(dict(gen.contract_mf61(), **{key: value}))


def test_friction_above_the_data_ceiling_is_found():
    p = dict(gen.contract_mf61(), PDX1=4.62)
    ceiling = {"x": (np.array([0.4, 1.6]) * FNOMIN, np.array([2.39, 2.39]) * 1.15)}
    assert ("mu<=ceiling", "Fx") in _rules(p, mu_ceiling=ceiling)
    assert ("mu<=ceiling", "Fx") not in _rules(gen.contract_mf61(), mu_ceiling=ceiling)
    # a callable ceiling (the fit's: a function of the load)
    assert ("mu<=ceiling", "Fx") in _rules(p, mu_ceiling={"x": lambda fz: np.full_like(fz, 2.75)})


def test_combined_slip_that_adds_force_is_found():
    p = dict(gen.contract_mf61(), RHX1=-0.0123, RBX1=500.0)
    assert ("G<=1", "Fx") in _rules(p)
    assert ("G<=1", "Fy") in _rules(dict(gen.contract_mf61(), RHY1=0.01))
    # G below zero: the force reverses with the other slip (C > 1 carries cos past pi/2)
    assert ("G>=0", "Fx") in _rules(dict(gen.contract_mf61(), RCX1=2.5))


def test_an_aligning_moment_of_the_wrong_sign_is_found():
    assert ("aligning", "Mz") in _rules(dict(gen.contract_mf61(), QDZ1=-0.05))  # a negative trail
    # a residual torque larger than a small trail's moment on one side (only -2 deg fails here)
    assert ("aligning", "Mz") in _rules(dict(gen.contract_mf61(), QDZ1=0.02, QDZ6=0.03))
    assert ("aligning", "Mz") not in _rules(gen.contract_mf61())


def test_the_contract_checks_the_whole_declared_range_not_the_samples():
    # PEX2 makes E_x cross 1 only towards the top of the load range
    p = dict(gen.contract_mf61(), PEX1=0.6, PEX2=0.9, PEX4=0.0)
    low = dict(ENV, fz=(0.4 * FNOMIN, FNOMIN))
    assert ("E<=1", "Fx") not in {(v.rule, v.channel) for v in violations(p, low)}
    assert ("E<=1", "Fx") in _rules(p)


# ----------------------------------------------------------------------------- the fit keeps it
@pytest.fixture(scope="module")
def published_fit():
    """The published set (G_yk 1.028 in range), 3 loads x 1 pressure x 2 cambers, pure and combined, 1 % noise."""
    df = gen.make_sweeps(gen.published_mf61(), seed=31, pressures=[260e3], cambers_deg=[0.0, 3.0],
                         loads=[0.5 * FNOMIN, FNOMIN, 1.5 * FNOMIN], n_points=31)
    return fit_mf(df, tyre_info=INFO)


def test_the_fit_keeps_the_contract_on_data_that_break_it(published_fit):
    r = published_fit
    assert r.contract() == []
    env = r.ranges()
    al = np.linspace(*env["slip_angle"], 41)
    ka = np.linspace(*env["slip_ratio"], 41)
    A, K = np.meshgrid(al, ka)
    for fz in (0.5 * FNOMIN, 1.5 * FNOMIN):
        F = np.full(A.shape, fz)
        comb = mf61.forces(r.params, F, slip_ratio=K, slip_angle=A, pressure=260e3)
        fx0 = mf61.forces(r.params, F, slip_ratio=K, slip_angle=0 * A, pressure=260e3)["fx"]
        assert np.all(np.abs(comb["fx"]) <= np.abs(fx0) * (1 + 1e-4) + 1e-6)


def test_the_written_file_loads_in_eval_without_allow_unphysical(published_fit, tmp_path):
    out = published_fit.write_tir(tmp_path / "t.tir")
    assert check_tyre(read_tyre(out)) == []
    pts = tmp_path / "pts.csv"
    pd.DataFrame({"fz [N]": [3000.0, 9000.0], "slip_angle [deg]": [2.0, -4.0],
                  "slip_ratio [-]": [0.05, -0.1]}).to_csv(pts, index=False)
    assert main(["eval", str(out), "--points", str(pts), "--out", str(tmp_path / "f.csv")]) == 0


def test_the_writer_refuses_a_tyre_that_breaks_the_contract(published_fit, tmp_path):
    r = published_fit
    bad = M.FitResultMF(**{**r.__dict__, "params": dict(r.params, QEZ1=11.97)})
    with pytest.raises(FitError, match="E_t > 1"):
        bad.write_tir(tmp_path / "bad.tir")
    assert not (tmp_path / "bad.tir").exists()


def _fx0_fit(kappa_max, loads, seed=41):
    df = gen.make_sweeps(gen.contract_mf61(), seed=seed, pressures=[260e3], cambers_deg=[0.0],
                         slip_angles_deg=[0.0], loads=loads, n_points=31, kappa_max=kappa_max)
    return df, fit_mf(df[df["slip_angle"] == 0.0], tyre_info=INFO, stages=["Fx0"])


def test_fx_sweeps_short_of_the_peak_hold_the_shape_and_say_so():
    # the published tyre's Fx peaks at kappa 0.08-0.12: sweeps to +-0.05 reach no peak at any load
    df, r = _fx0_fit(0.05, [0.5 * FNOMIN, FNOMIN, 1.5 * FNOMIN])
    held = r.stages["Fx0"].held
    assert r.params["PCX1"] == M.SHAPE_DEFAULTS["PCX1"] and "PCX1" in held
    assert held["PCX1"].startswith(M.NO_PEAK) and "PEX1" in held
    assert any("PCX1" in line for line in r.header() + [str(k) for k in r.not_identifiable])


def test_friction_stays_within_the_data_where_some_sweeps_peak():
    # sweeps to +-0.12: the two heavier loads peak (at 0.094, 0.077) and fall, the lightest peaks at 0.121
    loads = [0.4 * FNOMIN, FNOMIN, 1.6 * FNOMIN]
    df, r = _fx0_fit(0.12, loads)
    cap = r.stages["Fx0"].facts["mu_ceiling"]
    assert cap is not None and cap.fz.size >= 2
    mu = np.abs(mf61.factors(r.params, np.array(loads), 0.0, 260e3)["mux"])
    data_mu = (df["fx"].abs() / df["fz"]).groupby(df["run"]).max()
    assert np.all(mu[1:] <= 1.15 * data_mu.max() + 1e-9)
    assert r.contract() == []


def test_the_ceiling_binds_a_shape_that_would_run_away():
    # an Fx0 problem started at mu 4.6, C 0.3 (the real record's answer) comes back under the ceiling
    df, r = _fx0_fit(0.12, [0.4 * FNOMIN, FNOMIN, 1.6 * FNOMIN], seed=42)
    assert r.params["PCX1"] > 0.5
    assert r.params["PDX1"] < 1.15 * float((df["fx"].abs() / df["fz"]).max())


# ------------------------------------------------------------------ channels not written as fitted
def _mx_problem(q):
    df = gen.make_sweeps(gen.contract_mf61(), seed=5, pressures=[260e3], cambers_deg=[0.0, 3.0],
                         slip_angles_deg=[0.0], loads=[0.5 * FNOMIN, FNOMIN, 1.5 * FNOMIN], n_points=21)
    data = M.prepare_mf_data(df)
    st = M._STAGE["Mx"]
    pts = data.subset(st.sweeps, st.channel)
    p = {**mf61.neutral(), **gen.contract_mf61(), **q}
    vary = ["QSX1", "QSX2", "QSX3", "QSX4"]
    return M._Problem(st, pts, p, vary, {"FNOMIN": FNOMIN, "UNLOADED_RADIUS": p["UNLOADED_RADIUS"],
                                         "NOMPRES": 260e3}, "6.1", "l2", p["UNLOADED_RADIUS"], -1.0), vary, p


def test_runaway_terms_are_found():
    prob, vary, p = _mx_problem({"QSX4": -2.2e9, "QSX2": 3.6e5})
    run = M._runaway(prob, np.array([p[k] for k in vary]))  # the real record's values, beyond today's bounds
    assert "QSX4" in run and "QSX2" in run
    prob, vary, p = _mx_problem({})
    assert M._runaway(prob, prob.theta(p)) == {}


def test_a_moment_worse_than_a_constant_is_declared_not_fitted(published_fit, tmp_path):
    r = published_fit
    fits = {k: SimpleNamespace(**vars(v)) for k, v in r.stages.items()}
    fits["Mx"].facts = dict(fits["Mx"].facts, r2=-0.80)
    fits["Mx"].held = dict(fits["Mx"].held)
    p, notes = dict(r.params), []
    M._drop_unfit(r.data, p, fits, notes)
    assert fits["Mx"].varied == [] and all(p[k] == mf61.neutral().get(k, 0.0) for k in r.stages["Mx"].varied)
    assert any(n.startswith("MX not written as fitted") for n in notes)
    # the runaway case names its coefficients
    fits2 = {k: SimpleNamespace(**vars(v)) for k, v in r.stages.items()}
    fits2["Mx"].facts = dict(fits2["Mx"].facts, runaway={"QSX4": 3e8})
    fits2["Mx"].held = dict(fits2["Mx"].held)
    notes2: list[str] = []
    M._drop_unfit(r.data, dict(r.params), fits2, notes2)
    assert any("QSX4" in n for n in notes2)


# ----------------------------------------------------------------------------- identifiability
def test_a_coefficient_lost_in_its_standard_error_is_held_and_named():
    prob, vary, p = _mx_problem({})
    th = prob.theta(dict(p, QSX1=1e-6))
    weak = M._not_identified(prob, th, {"QSX1": 1e-4, "QSX2": 1e-4, "QSX3": 0.0, "QSX4": float("nan")})
    assert set(weak) == {"QSX1", "QSX4"}  # NaN: a direction the data do not see
    assert weak["QSX1"][2] == mf61.neutral()["QSX1"]


# ----------------------------------------------------------------------------- design data
def _ds(name, kind, fz, rl):
    return SimpleNamespace(df=pd.DataFrame({"fz": fz, "loaded_radius": rl}), source=name, kind=kind)


def test_records_whose_loaded_radii_disagree_are_said_and_the_free_rolling_one_used():
    rng = np.random.default_rng(0)
    fz = rng.uniform(200, 1600, 400)
    corner = _ds("cornering.dat", "slip_angle", fz, 0.207 - fz / 180e3 + rng.normal(0, 2e-4, fz.size))
    drive = _ds("drivebrake.dat", "slip_ratio", fz, 0.231 - fz / 180e3 + rng.normal(0, 2e-4, fz.size))
    law = loaded_radius_law([drive, corner])
    assert abs(law["UNLOADED_RADIUS"] - 0.207) < 1e-3 and law["source"] == "cornering.dat"
    assert "disagree" in law["note"] and "free-rolling" in law["note"]
    same = loaded_radius_law([corner, _ds("b.dat", "slip_ratio", fz, 0.207 - fz / 180e3)])
    assert "note" not in same and abs(same["VERTICAL_STIFFNESS"] - 180e3) < 5e3


def test_json_flags_are_checked_before_any_work(tmp_path, monkeypatch, capsys):
    import tyrefit.workflows.fit as workflow

    def boom(*a, **k):  # pragma: no cover - must not be reached
        raise AssertionError("the fit ran before the flags were checked")

    monkeypatch.setattr(workflow, "fit_pac89", boom)
    csv = tmp_path / "d.csv"
    csv.write_text("fz [N],slip_angle [deg],fy [N]\n1000,1,-100\n")
    rc = main(["fit", str(csv), "--out", str(tmp_path / "t.tir"), "--json", str(tmp_path / "t.json")])
    err = capsys.readouterr().err
    assert rc == 2 and "--size" in err and "--rated-load" in err and "nothing was fitted" in err
    rc = main(["fit", str(csv), "--out", str(tmp_path / "t.tir"), "--json", str(tmp_path / "t.json"),
               "--size", "205/55R16"])
    assert rc == 2 and "--rated-load" in capsys.readouterr().err


def test_bundled_tyres_keep_the_contract():
    from tyrefit.io.datasets import data_dir

    files = sorted((data_dir() / "sim").glob("*.tir"))
    assert files
    for f in files:
        assert check_tyre(read_tyre(f)) == [], f


def test_the_result_says_what_it_held_and_the_contract_verdict(published_fit, tmp_path):
    import json

    d = json.loads(json.dumps(published_fit.to_dict(), default=float))
    assert d["contract"] == []
    held = d["not_identified"]
    assert held["RHY1"]["reason"].startswith("held at 0") and held["RHY1"]["value"] == 0.0
    assert any(v["reason"].startswith("not identified: standard error") for v in held.values())
    out = published_fit.write_tir(tmp_path / "t.tir")
    assert "HELD RHX1 = 0: held at 0" in out.read_text()


@pytest.mark.parametrize("truth, rule", [({"QEZ1": 1.6}, "E<=1"), ({"QDZ1": 0.02, "QDZ6": 0.03}, "aligning")])
def test_the_aligning_fit_holds_its_rules_against_data_that_break_them(truth, rule):
    # data whose own aligning moment breaks a rule (E_t above 1, which solvers clip; a residual torque that
    # de-aligns at -2 deg at light load): the Mz0 stage keeps the rule over the declared range
    p = dict(gen.contract_mf61(), **truth)
    assert rule in {v.rule for v in violations(p, ENV)}
    df = gen.make_sweeps(p, seed=51, pressures=[260e3], cambers_deg=[0.0], slip_angles_deg=(), combined=False,
                         loads=[0.4 * FNOMIN, FNOMIN, 1.6 * FNOMIN], n_points=41)
    r = fit_mf(df, tyre_info=INFO, stages=["Fy0", "Mz0"])
    assert rule not in {v.rule for v in r.contract()}, r.contract()
