"""The non-circular diagnose validation: its truth physics, noise, runner, and a handful of diagnoses.

The truth tyre (:mod:`tyrefit.synthetic.validation.truth`) is checked with
physics: limits (slope at zero slip, saturation at mu Fz), symmetries (odd in
slip), and that every effect changes what it names while the null tyre has
none of it.  The slow tier (``tests/test_diagnose_suite.py``) runs the rates.
"""

import ast
import json
from pathlib import Path

import numpy as np
import pytest

from tyrefit.synthetic.validation import cases as vc
from tyrefit.synthetic.validation import runner as vr
from tyrefit.synthetic.validation.truth import EFFECT_FAMILY, EFFECT_SIZES, EFFECTS, FZ0, P0, RATED_LOAD, TruthTyre

DEG = np.pi / 180.0
NULL = TruthTyre()
ALPHA = np.linspace(-12, 12, 241) * DEG


def _fy(t, fz, alpha=ALPHA, camber=0.0, pressure=P0):
    return t.lateral_force(np.full_like(alpha, fz), alpha, camber, pressure)


def test_truth_code_does_not_use_the_catalogue_or_pac89():
    pkg = Path(vr.__file__).parent
    for name in ("truth.py", "cases.py"):
        tree = ast.parse((pkg / name).read_text())
        mods = [n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
        mods += [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
        assert not [m for m in mods if "effects" in m or "pac89" in m or "models" in m or "diagnose" in m], mods


@pytest.mark.parametrize("fz", [2000.0, 4000.0, 8000.0])
def test_null_tyre_limits_and_symmetry(fz):
    fy = _fy(NULL, fz)
    np.testing.assert_allclose(fy, -fy[::-1], atol=1e-9)  # odd in slip: no shift in the null
    h = 1e-6
    slope = (NULL.lateral_force(fz, h) - NULL.lateral_force(fz, -h)) / (2 * h)
    assert slope == pytest.approx(-NULL.cornering_stiffness(fz), rel=1e-6)  # ISO-W: dFy/dalpha = -K_alpha
    assert np.max(np.abs(fy)) < NULL.mu0 * fz
    # peak inside the sweep, sliding value below it and towards mu (1 - d) far out
    k = np.argmax(np.abs(fy[ALPHA > 0]))
    assert 3.0 < np.degrees(ALPHA[ALPHA > 0][k]) < 12.0 or fz >= 8000.0
    far = abs(NULL.lateral_force(fz, 80 * DEG))
    assert far == pytest.approx(NULL.mu0 * fz * (1 - NULL.d), rel=0.03)


def test_null_tyre_realistic_magnitudes():
    k4 = NULL.cornering_stiffness(4000.0)
    assert 50e3 < k4 < 80e3  # N/rad: 205/55R16 around 60-80 kN/rad at 4 kN
    assert 10 < NULL.cornering_stiffness(2000.0) / 2000.0 < 20  # cornering-stiffness coefficient [1/rad]


def _peak_mu(t, fz, **kw):
    return np.max(np.abs(_fy(t, fz, **kw))) / fz


def test_null_has_no_effect_and_effects_change_what_they_name():
    loads = [2000.0, 4000.0, 6000.0, 8000.0]
    null_mu = [_peak_mu(NULL, f) for f in loads]
    np.testing.assert_allclose(null_mu, null_mu[0], rtol=1e-3)  # grip does not change with load
    for eff in ("load_friction_power", "load_friction_tanh"):
        t = TruthTyre.with_effects([eff])
        mu = np.array([_peak_mu(t, f) for f in loads])
        assert np.all(np.diff(mu) < 0), eff  # degressive
        assert 0.75 < mu[-1] / mu[0] < 0.92, eff  # 8-25 % over 2 -> 8 kN
    # overload: nothing well below the rated load, a smooth knee past it
    t = TruthTyre.with_effects(["overload"])
    assert t.friction(0.7 * RATED_LOAD) / NULL.friction(0.7 * RATED_LOAD) > 0.997
    r8 = t.friction(8000.0) / NULL.friction(8000.0)
    assert 0.8 < r8 < 0.9
    f = np.linspace(4000, 9000, 501)
    d2 = np.diff(t.friction(f), 2)
    assert np.all(d2 <= 1e-12) and np.max(np.abs(d2)) < 1e-5  # concave, no kink
    # curvature: the normalised curve shape changes with load only when the effect is there
    for tyre, changes in ((NULL, False), (TruthTyre.with_effects(["curvature"]), True)):
        shapes = []
        for fz in (2000.0, 8000.0):
            phi = np.linspace(0.05, 4, 50)
            alpha = np.arctan(phi * tyre.friction(fz) * fz / tyre.cornering_stiffness(fz))
            shapes.append(-tyre.lateral_force(np.full_like(alpha, fz), alpha) / (tyre.friction(fz) * fz))
        diff = np.max(np.abs(shapes[0] - shapes[1]))
        assert (diff > 0.02) == changes, (tyre.effects, diff)
        # the friction and the stiffness do not change with the curvature effect, nor does the peak force
        assert tyre.friction(8000.0) == NULL.friction(8000.0)
        wide = np.linspace(0, 40, 1601) * DEG
        for fz in (2000.0, 8000.0):
            assert _peak_mu(tyre, fz, alpha=wide) == pytest.approx(_peak_mu(NULL, fz, alpha=wide), rel=2e-4)


def test_offsets_are_a_slip_offset_and_a_force_growing_with_load():
    t = TruthTyre.with_effects(["offsets"])
    assert NULL.lateral_force(5000.0, 0.0) == 0.0
    f0 = [t.lateral_force(fz, -t.alpha_ps) for fz in (2000.0, 8000.0)]
    np.testing.assert_allclose(f0, [-t.c_con * 2000.0, -t.c_con * 8000.0], atol=1e-9)  # conicity ~ Fz
    assert 20 < abs(f0[0]) < 150 and 0.05 * DEG < abs(t.alpha_ps) < 0.5 * DEG  # uniformity sizes
    # no longer odd in slip
    fy = _fy(t, 5000.0)
    assert np.max(np.abs(fy + fy[::-1])) > 50.0


def test_camber_thrust_saturates_fades_and_null_has_none():
    t = TruthTyre.with_effects(["camber"])
    g = np.array([-8, -4, 0, 4, 8]) * DEG
    for fz in (2000.0, 6000.0):
        assert np.all(NULL.lateral_force(fz, 0.0 * g, g) == 0.0)
        f = t.lateral_force(np.full(5, fz), 0.0 * g, g)
        np.testing.assert_allclose(f, -f[::-1], atol=1e-9)  # odd in camber at zero slip
        assert f[3] < 0  # ISO-W: positive inclination pushes towards -y, like positive slip
        assert abs(f[4]) < 1.8 * abs(f[3])  # saturating
        assert abs(f[3]) == pytest.approx(t.c_gamma * fz * t.g_s * np.tanh(4 * DEG / t.g_s), rel=1e-9)
    # fades where the patch slides: the camber part at 12 deg slip is a small share of that at 0
    d0 = t.lateral_force(4000.0, 0.0, 4 * DEG) - t.lateral_force(4000.0, 0.0, 0.0)
    d12 = t.lateral_force(4000.0, 12 * DEG, 4 * DEG) - t.lateral_force(4000.0, 12 * DEG, 0.0)
    assert abs(d12) < 0.25 * abs(d0)


def test_pressure_raises_stiffness_lowers_grip_and_null_ignores_it():
    t = TruthTyre.with_effects(["pressure"])
    for p in (190e3, 250e3):
        np.testing.assert_array_equal(_fy(NULL, 4000.0, pressure=p), _fy(NULL, 4000.0, pressure=P0))
    assert t.cornering_stiffness(4000.0, 250e3) > 1.03 * t.cornering_stiffness(4000.0, P0)
    assert _peak_mu(t, 4000.0, pressure=250e3) < 0.995 * _peak_mu(t, 4000.0, pressure=P0)


def test_every_effect_has_a_size_and_a_family():
    assert set(EFFECT_SIZES) == set(EFFECTS)
    with pytest.raises(ValueError, match="unknown validation effect"):
        TruthTyre.with_effects(["nope"])
    assert FZ0 == 4000.0


@pytest.mark.parametrize("kind", vc.NOISE_MODELS)
def test_noise_models_have_the_stated_sd_and_correlation(kind):
    rng = np.random.default_rng(5)
    sweep = np.repeat(np.arange(400), 49)
    e = vc.noise(kind, sweep, 40.0, rng)
    assert np.std(e) == pytest.approx(40.0, rel=0.03)
    e2 = e.reshape(400, 49)
    lag1 = np.mean(e2[:, :-1] * e2[:, 1:]) / np.mean(e2 * e2)  # pooled over sweeps (per-sweep r is biased low)
    means_sd = np.std(e2.mean(axis=1))
    if kind == "ar1":
        assert lag1 == pytest.approx(vc.AR_RHO, abs=0.04)
    elif kind == "offsets":
        assert lag1 == pytest.approx(vc.OFFSET_SHARE**2, abs=0.04)  # the shared offset, nothing else
    else:
        assert abs(lag1) < 0.03
    if kind == "offsets":
        assert means_sd == pytest.approx(np.sqrt((0.5 * 40) ** 2 + 0.75 * 40**2 / 49), rel=0.1)
    if kind == "iid":
        assert means_sd == pytest.approx(40 / 7, rel=0.1)


def test_cases_are_deterministic_and_layouts_as_stated():
    a = vc.make_case("load6", "ar1", "offsets", 3)
    b = vc.make_case("load6", "ar1", "offsets", 3)
    c = vc.make_case("load6", "ar1", "offsets", 4)
    assert a.data.equals(b.data) and not a.data["fy"].equals(c.data["fy"])
    assert a.data["run"].nunique() == 6 and a.family == "offsets"
    assert set(a.data.columns) >= {"run", "fz", "slip_angle", "fy", "camber", "pressure"}
    assert np.degrees(a.data["slip_angle"]).min() == pytest.approx(-12) and a.data.groupby("run").size().iloc[0] == 49
    assert vc.make_case("grid24", "iid", None, 0).data["run"].nunique() == 24
    assert vc.make_case("grid60", "iid", None, 0).data["run"].nunique() == 60
    assert vc.make_case("onesided6", "iid", None, 0).data["slip_angle"].min() == 0.0
    # ISO-W: positive slip gives negative force
    d = a.data
    assert (d.loc[d.slip_angle > 4 * DEG, "fy"] < 0).all()
    assert not vc.applicable(vc.LAYOUTS["load6"], "camber") and vc.applicable(vc.LAYOUTS["grid24"], "pressure")


def test_start_model_follows_the_null_but_not_the_effects():
    bf = vr.base_fit(["load6"])["load6"]
    assert bf["null"] < 0.2  # a null the start model can represent (RMSE / sigma)
    for eff in ("load_friction_power", "load_friction_tanh", "curvature", "overload", "offsets"):
        assert bf[eff] > 0.6, (eff, bf[eff])


@pytest.mark.parametrize("layout", ["load5", "load6", "load7"])
@pytest.mark.parametrize("effect", ["curvature", "offsets", "load_friction_power", "load_friction_tanh", "overload"])
def test_the_catalogue_can_name_the_truth_family(effect, layout):
    # an ideal diagnosis (best single catalogue effect on noise-free data) names the truth's family, and
    # leaves a misfit small against the noise, so one accepted effect can bring the held-out error near
    # it (a straight friction-load law leaves 0.6-0.8 sigma of a power or tanh law; a hinge at the
    # rated load with grip flat below it leaves 0.42-0.76 sigma of a smooth knee)
    o = vr.oracle(layout, effect)
    best = next(k for k in o if k != "start")
    assert best.startswith(EFFECT_FAMILY[effect]), o
    assert o[best] < 0.5 * o["start"], o
    assert o[best] < 0.55, o
    # and the best other family is clearly worse
    other = min(v for k, v in o.items() if k != "start" and not k.startswith(EFFECT_FAMILY[effect]))
    assert other > 1.35 * o[best], o


def test_overload_cannot_raise_grip_above_the_rated_load():
    from tyrefit.effects import get_effect
    assert get_effect("overload").params[0].bounds[0] == 0.0  # a hinge that adds grip is not overload


def test_wilson_interval():
    lo, hi = vr.wilson(0, 200)
    assert lo == 0.0 and hi == pytest.approx(0.0188, abs=5e-4)  # 3.84 / (200 + 3.84)
    lo, hi = vr.wilson(95, 100)
    assert lo == pytest.approx(0.888, abs=2e-3) and hi == pytest.approx(0.978, abs=2e-3)


def test_plan_filters():
    p = vr.plan_cases(["load6"], ["iid"], ["null"], n_null=7)
    assert len(p) == 7 and all(e is None for _, _, e, _ in p)
    p = vr.plan_cases(["load6"], None, ["load_friction"], n_effect=2)
    assert {e for _, _, e, _ in p} == {"load_friction_power", "load_friction_tanh"} and len(p) == 12
    assert not [c for c in vr.plan_cases(["load6"], None, ["camber"])]  # no camber levels in load6
    with pytest.raises(ValueError, match="unknown layout"):
        vr.plan_cases(["nope"])


def test_runner_scores_caches_and_tabulates(tmp_path, monkeypatch):
    cases = [("grid24", "iid", "load_friction_tanh", 0), ("load6", "iid", None, 0)]
    rows = vr.run(cases, out=tmp_path, verbose=False)
    eff, null = sorted(rows, key=lambda r: r["effect"] is None)
    assert eff["right_first"] and eff["first_family"] == "load_friction" and eff["ratio"] < 1.3
    assert null["false_alarm"] is False and 0.8 < null["ratio"] < 1.3
    # cached: a second run does not diagnose again
    monkeypatch.setattr(vr, "run_case", lambda *a, **k: pytest.fail("not cached"))
    again = vr.run(cases, out=tmp_path, verbose=False)
    assert sorted(json.dumps(r, sort_keys=True) for r in again) == sorted(json.dumps(r, sort_keys=True) for r in rows)
    res = vr.rates(rows)
    md = vr.markdown(res)
    assert "| grid24 | iid | load_friction_tanh (load_friction) | 1 | 100 %" in md
    assert "| load6 | iid | null | 1 |" in md and "0 % [0-79]" in md


@pytest.mark.parametrize("layout,noise,effect", [
    ("load6", "iid", None), ("load6", "ar1", None), ("grid24", "offsets", None),
    ("grid24", "ar1", "camber"), ("grid60", "offsets", "overload"), ("grid24", "iid", "pressure"),
])
def test_a_handful_of_diagnoses(layout, noise, effect):
    row = vr.run_case(layout, noise, effect, seed=11)
    assert "error" not in row, row
    assert row["heldout_over_insample"] > 1.0001, row  # held-out predictions come from fits without the sweep
    if effect is None:
        assert not row["false_alarm"], row
    else:
        assert row["right_first"], row
        assert row["ratio"] <= 1.3, row


def test_check_targets_pools_a_family_and_counts_misses():
    def row(eff, noise, right=True, ratio=1.1, fa=None):
        r = {"layout": "load6", "noise": noise, "effect": eff, "ratio_first": ratio, "ratio": 1.0, "right_first": right}
        if eff is None:
            r = {"layout": "load6", "noise": noise, "effect": None, "false_alarm": fa}
        return r
    rows = ([row("load_friction_power", "iid")] * 10 + [row("load_friction_tanh", "iid", right=False)]
            + [row("offsets", "iid", ratio=1.4)] * 2 + [row(None, "iid", fa=False)] * 19 + [row(None, "iid", fa=True)])
    checks = {(c["family"], c["check"]): c for c in vr.check_targets(rows)}
    lf = checks[("load_friction", "right family first")]
    assert (lf["k"], lf["n"], lf["ok"]) == (10, 11, False)
    assert checks[("load_friction", "held-out RMSE after it <= 1.3 sigma")]["ok"]
    assert not checks[("offsets", "held-out RMSE after it <= 1.3 sigma")]["ok"]
    assert checks[("offsets", "final held-out RMSE <= 1.3 sigma")]["ok"]
    fa = checks[("null", "false alarms")]
    assert (fa["k"], fa["n"], fa["ok"]) == (1, 20, True)
    assert "**no**" in vr.targets_markdown(list(checks.values()))


def test_insample_mutation_makes_held_out_equal_in_sample_and_is_undone():
    from tyrefit.diagnose import diagnose, engine

    case = vc.make_case("grid8", "iid", None, 0)
    orig = engine.fit_folds
    with vr.mutated("insample"):
        assert engine.fit_folds is not orig
        dg = diagnose(case.data, rated_load=case.rated_load, seed=0)
    assert engine.fit_folds is orig
    step = dg.steps[0]
    assert step.rmse_heldout == pytest.approx(step.rmse, rel=1e-6)
    with vr.mutated("insample"):
        row = vr.run_case("load6", "iid", None, seed=0)
    assert row["heldout_over_insample"] == pytest.approx(1.0, abs=1e-6)
    checks = [c for c in vr.check_targets([row]) if c["check"] == "held-out evidence is out of sample"]
    assert len(checks) == 1 and not checks[0]["ok"]
    with pytest.raises(ValueError, match="unknown mutation"):
        with vr.mutated("nope"):
            pass


def test_invariant_checks_fail_on_an_accepted_effect_that_does_not_hold_up():
    def row(heldout, levelout=None, ph=None):
        return {"layout": "grid8", "noise": "iid", "effect": None, "step_heldout": heldout, "margin": 0.5,
                "step_levelout": levelout or [None] * len(heldout), "accepted_p_heldout": ph or []}
    good = [row([60.0, 42.0, 41.0], [55.0, 44.0, 43.5], [0.002, 0.01]), row([40.0])]
    checks = {c["check"]: c for c in vr.invariant_checks(good)}
    assert len(checks) == 3 and all(c["ok"] for c in checks.values())
    assert checks["every accepted effect lowers the held-out RMSE by the practical margin"]["n"] == 2
    # the second effect lowers the held-out RMSE by 0.2 N < margin 0.5 N; the levels get worse; p_heldout 0.2
    bad = good + [row([60.0, 42.0, 41.8], [55.0, 44.0, 44.5], [0.002, 0.2])]
    checks = {c["check"]: c for c in vr.invariant_checks(bad)}
    assert [c["k"] for c in checks.values()] == [3, 3, 3] and not any(c["ok"] for c in checks.values())


# --- the truth-form floor and the rerun of a test (ceiling.py) ------------------------------------------------------

def test_refitting_the_truth_form_recovers_its_laws_from_a_wrong_start():
    from dataclasses import replace

    from tyrefit.synthetic.validation.ceiling import free_parameters, refit_truth

    case = vc.make_case("load6", "iid", "load_friction_tanh", 0, sigma=0.0)
    assert {"f_m", "m_tanh", "mu0", "k_max"} <= set(free_parameters(case.tyre))
    d = case.data
    wrong = replace(case.tyre, mu0=1.1, m_tanh=0.05, f_m=6000.0, k_max=120e3, q0=0.8)
    t = refit_truth(wrong, *(d[c].to_numpy() for c in ("fz", "slip_angle", "camber", "pressure")), case.truth_fy)
    for name, want in (("mu0", 1.0), ("m_tanh", 0.15), ("f_m", 4000.0), ("k_max", 140e3), ("q0", 0.5)):
        assert getattr(t, name) == pytest.approx(want, rel=2e-3), name


def test_the_truth_form_floor_holds_out_the_interior_sweeps():
    from tyrefit.synthetic.validation.ceiling import interior_sweeps, refit_truth, truth_form_heldout

    case = vc.make_case("load6", "ar1", "load_friction_power", 3)
    runs = interior_sweeps(case)
    load = case.data.groupby("run")["fz"].mean()
    assert len(runs) == 4 and load.idxmin() not in runs and load.idxmax() not in runs
    with pytest.raises(ValueError, match="one sweep per load"):
        interior_sweeps(vc.make_case("grid8", "iid", None, 0))
    floor = truth_form_heldout(case)
    # fitted to every sweep, the same form predicts those sweeps better than when each is held out
    d = case.data
    cols = [d[c].to_numpy() for c in ("fz", "slip_angle", "camber", "pressure")]
    full = refit_truth(case.tyre, *cols, d["fy"].to_numpy())
    m = d["run"].isin(runs).to_numpy()
    insample = np.sqrt(np.mean((full.lateral_force(*cols) - d["fy"].to_numpy())[m] ** 2)) / case.sigma
    assert floor["ratio"] > insample
    assert 0.0 < floor["error"] < 1.0  # estimated, so not exact; a sensible fit, so well inside the noise
    tiny = truth_form_heldout(vc.make_case("load6", "ar1", "load_friction_power", 3, sigma=1e-3))
    assert tiny["error"] * 1e-3 < 0.05  # N: with (almost) no noise the held-out sweeps are predicted exactly


def test_a_rerun_of_the_test_has_the_same_tyre_and_set_points_and_new_noise():
    a, b = vc.make_case("load6", "ar1", "offsets", 4), vc.make_case("load6", "ar1", "offsets", 4, repeat=1)
    assert vc.make_case("load6", "ar1", "offsets", 4, repeat=0).data.equals(a.data)
    assert a.tyre == b.tyre and (a.data["run"] == b.data["run"]).all()
    assert np.allclose(a.data["slip_angle"], b.data["slip_angle"])
    assert np.allclose(a.data["fz"], b.data["fz"], rtol=0.05) and not np.allclose(a.data["fz"], b.data["fz"])
    na, nb = a.data["fy"] - a.truth_fy, b.data["fy"] - b.truth_fy
    assert abs(np.corrcoef(na, nb)[0, 1]) < 0.15


def test_run_case_scores_the_model_on_the_rerun_and_the_floor():
    row = vr.run_case("load6", "iid", "curvature", seed=2)
    assert row["right_first"], row
    # a fitted model on new data: about the noise (its own error adds little), not its in-sample fit; the
    # start model on a curvature truth is far off, the model after the right effect close to the truth
    assert 0.9 < row["rerun_first"] < 1.2 and row["rerun"] != row["ratio"]
    assert row["model_error_first"] < 0.5 < row["ratio_first"]
    assert 0.9 < row["ratio_truth_form"] < 1.3 and 0.0 < row["model_error_truth_form"] < row["model_error_first"]
    null = vr.run_case("grid8", "iid", None, seed=1)
    assert "ratio_truth_form" not in null and 0.9 < null["rerun"] < 1.2 and null["model_error"] < 0.3


def test_model_scores_use_the_fitted_data_reference_values_and_reject_another_case():
    from tyrefit.diagnose import diagnose
    from tyrefit.synthetic.validation.ceiling import model_scores

    case = vc.make_case("load6", "iid", "load_friction_tanh", 1)
    dg = diagnose(case.data, rated_load=case.rated_load, seed=1)
    assert any(e.startswith("load_friction_curved") or e.startswith("load_friction_cubic") for e in dg.accepted)
    sc = model_scores(dg.steps, case, vc.make_case("load6", "iid", "load_friction_tanh", 1, repeat=1))
    assert sc[0]["error"] > 2.0 and sc[-1]["error"] < 0.4  # the start model vs the model with the law
    # the same model scored on its own data again (a "rerun" that is the case): the in-sample RMSE
    own = model_scores(dg.steps[-1:], case, case)[0]["rerun"]
    assert own == pytest.approx(dg.steps[-1].rmse / case.sigma, rel=1e-9)
    with pytest.raises(ValueError, match="same case"):
        model_scores(dg.steps, case, vc.make_case("load6", "iid", "load_friction_tanh", 2, repeat=1))
