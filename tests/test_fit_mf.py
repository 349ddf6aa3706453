"""Staged Magic Formula 6.1 fit (tyrefit.fitting.mf) and ``tyrefit fit --model mf61``.

Physics is tested by recovery: records generated from a *published* MF 6.1
set (MFeval's example file MagicFormula61_Parameters.tir, see
tyrefit.synthetic.ttc_drivebrake) with 1 % noise are fitted back, and the
fitted tyre's curves are compared with the generating curves, noise-free,
over the data range (every load x pressure x camber cell, pure and combined).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from tyrefit.cli import main
from tyrefit.fitting.mf import (EFFECT_COEFFICIENTS, START_FY0, SVYK_LOBE, condition_levels, effect_coefficients,
                                fit_mf, identifiability, prepare_mf_data)
from tyrefit.io.tir import read_tyre
from tyrefit.models import mf61
from tyrefit.synthetic import ttc_drivebrake as gen

FNOMIN = gen.PUBLISHED_MF61["FNOMIN"]
INFO = {"fnomin": FNOMIN, "unloaded_radius": gen.PUBLISHED_MF61["UNLOADED_RADIUS"]}


def recovery_error(p_fit, p_true=None, **design) -> dict[str, float]:
    """Worst |fitted - generating| over every cell of ``design``, in % of the channel's peak (noise-free)."""
    p_true = gen.contract_mf61() if p_true is None else p_true
    a = gen.make_sweeps(p_true, noise=0.0, n_points=81, **design)
    b = gen.make_sweeps(p_fit, noise=0.0, n_points=81, **design)
    return {c: 100.0 * float(np.max(np.abs(a[f"true_{c}"] - b[f"true_{c}"])) / np.max(np.abs(a[f"true_{c}"])))
            for c in ("fx", "fy", "mz", "mx", "my")}


@pytest.fixture(scope="module")
def full_fit():
    """5 loads x 3 pressures x 3 cambers, pure and combined (slip angles 0, -3, -6 deg), 1 % noise."""
    df = gen.make_sweeps(gen.contract_mf61(), seed=1)
    return df, fit_mf(df, tyre_info=INFO)


def test_recovery_one_seed_every_force_channel_within_1pct_of_peak(full_fit):
    _, r = full_fit
    err = recovery_error(r.params)
    for c in ("fx", "fy", "mz", "mx", "my"):
        assert err[c] < 1.0, (c, err)
    # the RMSE of every fitted channel sits near the noise floor (the noise is 1 % of each sweep's peak)
    for c in ("fx", "fy", "mz"):
        assert r.stats[c]["rmse"] < 1.3 * r.stats[c]["noise_floor"], (c, r.stats[c])


def test_recovery_measure_can_fail(full_fit):
    # the same comparison fails for a tyre without its combined-slip terms, or with a 3 % friction error
    _, r = full_fit
    err = recovery_error(dict(r.params, RBX1=0.0, RBY1=0.0))
    assert err["fx"] > 5.0 and err["fy"] > 5.0
    assert recovery_error(dict(r.params, PDY1=1.03 * r.params["PDY1"]))["fy"] > 1.5


def test_identifiability_rules_hold_terms_the_data_cannot_carry():
    df = gen.make_sweeps(gen.contract_mf61(), seed=3, pressures=[260e3], cambers_deg=[0.0], slip_angles_deg=[0.0], loads=[4000, 7000],
                         n_points=31)
    r = fit_mf(df, tyre_info=INFO, stages=["Fx0", "Fy0", "Mz0"])
    held = r.not_identifiable
    for k in ("PPY1", "PPY3", "PPX1", "PPZ1"):
        assert "pressure" in held[k]
    for k in ("PDY3", "PKY6", "PVY3", "PDX3", "QDZ8"):
        assert "camber" in held[k]
    for k in ("PKY4", "PEX3", "QBZ3"):
        assert ">= 3 load levels" in held[k]
    # held terms stay neutral in the written parameter set, fitted ones move
    neutral = mf61.neutral()
    assert r.params["PPY1"] == neutral["PPY1"] and r.params["PKY6"] == neutral["PKY6"]
    assert "PDY2" in r.fitted and "PKY2" in r.fitted
    # combined-slip stages need combined sweeps: none here, so they are not fitted
    assert "Fx" not in r.stages and "Fy" not in r.stages


def test_pressure_rules_two_and_three_levels():
    sw = pd.DataFrame({"run": range(6), "fz": [3e3, 6e3] * 3, "camber": 0.0, "speed": np.nan,
                       "slip_angle": 0.0, "kind": "lateral", "pressure": [2.2e5, 2.2e5, 2.6e5, 2.6e5, 3e5, 3e5]})
    pts = pd.DataFrame({"slip_angle": np.radians(np.linspace(-10, 10, 20))})
    why2, _ = identifiability("Fy0", pts, sw.iloc[:4])
    assert "PPY1" not in why2 and "PPY3" not in why2 and "PPY4" in why2 and "PPY2" in why2  # 2 loads only
    why3, facts = identifiability("Fy0", pts, sw)
    assert not {"PPY1", "PPY2", "PPY3", "PPY4"} & set(why3)
    assert facts["pressure_levels"] == 3
    # one-sided slip: shifts are held
    why1, _ = identifiability("Fy0", pd.DataFrame({"slip_angle": np.radians(np.linspace(0, 10, 20))}), sw)
    assert "PHY1" in why1 and "PVY1" in why1


def test_held_out_pressure_predicted_within_2pct_of_peak():
    df = gen.make_sweeps(gen.contract_mf61(), seed=2)
    train = df[df["pressure"] != 260e3]
    r = fit_mf(train, tyre_info=INFO)  # every stage, the joint polish, Mx and My
    assert "PPY4" in r.not_identifiable and "PPX2" in r.not_identifiable  # two pressures: quadratic terms held
    err = recovery_error(r.params, pressures=[260e3])
    # measured on seeds 2-11: worst Fx 1.48, Fy 0.70, Mz 1.54, Mx 0.67, My 0.09 % of peak
    for c in ("fx", "fy", "mz", "mx", "my"):
        assert err[c] < 2.0, (c, err)


def test_prepare_gathers_files_and_classifies_sweeps():
    df = gen.make_sweeps(gen.contract_mf61(), seed=4, pressures=[260e3], cambers_deg=[0.0], loads=[5000.0], n_points=21)
    lat = df[df["slip_ratio"].abs().groupby(df["run"]).transform("max") == 0]
    lon = df[df["slip_ratio"].abs().groupby(df["run"]).transform("max") > 0]
    d = prepare_mf_data([lat.drop(columns="run").assign(run=lat["run"]),
                         lon.drop(columns="run").assign(run=lon["run"])])
    kinds = d.sweeps.groupby("kind").size().to_dict()
    assert kinds == {"lateral": 1, "longitudinal": 1, "combined": 2}
    assert d.df["run"].nunique() == 4 and len(d.sources) == 2
    lv = condition_levels(d.sweeps)
    assert len(lv["fz"]) == 1 and len(lv["slip_angle"]) == 3


def test_cornering_sweeps_with_a_drifting_slip_ratio_channel_stay_cornering(ttc_pair):
    # a rig's slip-ratio channel during cornering: an offset and a drift with slip angle (the rolling-radius
    # estimate; diagnose keeps such sweeps as cornering).  Read as combined slip they left the Fy0/Mz0 stages
    from tyrefit.io.readers import read_data

    corner, drive = (read_data(f, convention="sae").df for f in ttc_pair)
    drifted = corner.assign(slip_ratio=corner["slip_ratio"] + 0.025 + 0.3 * corner["slip_angle"].abs())
    clean, drift = prepare_mf_data([corner, drive]), prepare_mf_data([drifted, drive])
    kinds = drift.sweeps.groupby(["source", "kind"]).size().to_dict()
    assert kinds == clean.sweeps.groupby(["source", "kind"]).size().to_dict()
    assert kinds[("data 1", "lateral")] == clean.sweeps["kind"].eq("lateral").sum() > 0
    a = fit_mf(clean, tyre_info=INFO, stages=["Fy0"])
    b = fit_mf(drift, tyre_info=INFO, stages=["Fy0"])
    assert b.stats["fy"]["rmse"] == pytest.approx(a.stats["fy"]["rmse"], rel=1e-6)
    # a slip-angle sweep at a held drive slip (kappa = 0.05: |Fx| ~ |Fy|) is combined slip, not cornering
    p = gen.contract_mf61()
    alpha = np.radians(np.linspace(-12, 12, 41))
    f = mf61.forces(p, FNOMIN, 0.05, alpha, 0.0, 260e3, 11.1)
    held = pd.DataFrame({"run": 0, "fz": FNOMIN, "slip_angle": alpha, "slip_ratio": 0.05, "camber": 0.0,
                         "fx": f["fx"], "fy": f["fy"]})
    assert prepare_mf_data(held).sweeps["kind"].tolist() == ["combined"]
    held2 = held.assign(slip_ratio=0.05 + 0.3 * np.abs(alpha))  # swept as well: still combined
    assert prepare_mf_data(held2).sweeps["kind"].tolist() == ["combined"]


def test_effects_map_to_mf61_coefficients():
    vary, notes = effect_coefficients(["load_friction", "pressure", "offsets_constant"])
    assert vary[:5] == list(START_FY0)
    assert {"PDY2", "PPY1", "PPY2", "PPY3", "PPY4", "PHY1", "PVY1"} <= set(vary)
    assert set(EFFECT_COEFFICIENTS["pressure"]) <= set(mf61.GROUPS["fy0"])
    with pytest.raises(Exception, match="unknown effect"):
        effect_coefficients(["presure"])


def test_effects_fit_varies_only_the_ladder():
    df = gen.make_sweeps(gen.contract_mf61(), seed=5, cambers_deg=[0.0], slip_angles_deg=[0.0], n_points=31)
    start = fit_mf(df, tyre_info=INFO, effects=[], stages=["Fy0"])
    withp = fit_mf(df, tyre_info=INFO, effects=["load_friction", "pressure"], stages=["Fy0"])
    assert set(start.stages["Fy0"].varied) == set(START_FY0)
    assert {"PDY2", "PPY1", "PPY3"} <= set(withp.stages["Fy0"].varied)
    assert "PKY4" not in withp.stages["Fy0"].varied
    assert withp.rmse < 0.5 * start.rmse


@pytest.fixture(scope="module")
def ttc_pair(tmp_path_factory):
    """A small TTC-style cornering + drive/brake pair (SAE signs, warm-up, lag, drift, noise)."""
    d = tmp_path_factory.mktemp("ttc")
    p = gen.contract_mf61()
    kw = dict(loads=[0.5 * FNOMIN, FNOMIN, 1.5 * FNOMIN], pressures=[260e3], cambers_deg=[0.0, 3.0],
              slip_angles_deg=[0.0, -4.0])
    files = []
    for kind in ("cornering", "drivebrake"):
        f = d / f"{kind}.dat"
        f.write_text(gen.format_record(gen.make_record(kind, p, **kw), kind))
        files.append(f)
    return files


def test_cli_fits_one_tyre_to_two_ttc_files(ttc_pair, tmp_path, capsys):
    out, rep = tmp_path / "mf.tir", tmp_path / "rep"
    assert main(["fit", *map(str, ttc_pair), "--convention", "sae", "--model", "mf61", "--out", str(out),
                 "--report", str(rep)]) == 0
    text = capsys.readouterr().out
    assert "MF 6.1" in text and "from 2 file(s)" in text and "FX RMSE" in text and "FY RMSE" in text
    tyre = read_tyre(out)
    assert tyre.family == "MF61"
    head = "\n".join(tyre.header)
    assert "cornering.dat" in head and "drivebrake.dat" in head and "RMSE FY" in head
    # every coefficient of a complete MF 6.1 file is there
    missing = [k for names in mf61.COEFFICIENTS.values() for k in names if k not in tyre.params]
    assert not missing
    # the fitted ranges are written
    assert tyre.ranges["fz"][1] > 1.4 * FNOMIN and tyre.ranges["slip_ratio"][1] > 0.15
    # the tyre read back reproduces the generating tyre at a pure and a combined point (nominal conditions)
    pt = gen.contract_mf61()
    a, k = np.radians(-4.0), np.linspace(-0.15, 0.15, 31)
    ref = mf61.forces(pt, FNOMIN, k, a, 0.0, 260e3, 11.1)
    got = tyre.forces(FNOMIN, a, k, 0.0, 260e3, 11.1)
    for c in ("fx", "fy"):
        assert np.max(np.abs(got[c] - ref[c])) < 0.03 * np.max(np.abs(ref[c])), c
    html = (rep / "index.html").read_text()
    assert "data:image/png;base64" in html and "condition cell" in html and "Kamm" in html


def test_cli_says_which_channels_are_not_fitted(ttc_pair, tmp_path, capsys):
    # a cornering record measures FX (R^2 < 0 against the model's pure-cornering Fx): reported, marked not fitted
    assert main(["fit", str(ttc_pair[0]), "--convention", "sae", "--model", "mf61", "--out",
                 str(tmp_path / "c.tir")]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    chans = {c.split(" RMSE")[0].strip(): c for c in first.split(": ", 1)[1].split("), ")}
    assert "not fitted" in chans["FX"] and "not fitted" not in chans["FY"] and "not fitted" not in chans["MZ"]


def test_cli_rejects_several_files_for_pac89_and_pac89_flags_for_mf(ttc_pair, tmp_path, capsys):
    out = tmp_path / "x.tir"
    assert main(["fit", *map(str, ttc_pair), "--convention", "sae", "--out", str(out)]) == 2
    assert "--model mf61" in capsys.readouterr().err
    assert main(["fit", str(ttc_pair[0]), "--convention", "sae", "--model", "mf61", "--json", str(tmp_path / "c.json"),
                 "--out", str(out)]) == 2
    assert "pac89" in capsys.readouterr().err
    assert not out.exists()


def test_mf52_fit_holds_pressure_terms_and_writes_fittyp_6(tmp_path):
    p52 = dict(gen.contract_mf61(), FITTYP=6, PHY3=0.02)
    df = gen.make_sweeps(p52, seed=6, cambers_deg=[0.0, 3.0], slip_angles_deg=[0.0], n_points=31, pressures=[260e3])
    r = fit_mf(df, model="mf52", tyre_info=INFO, stages=["Fy0"])
    assert "MF 5.2" in r.not_identifiable["PPY1"] and "PHY3" in r.fitted
    assert r.version == "5.2"
    tyre = read_tyre(r.write_tir(tmp_path / "t52.tir"))
    assert tyre.family == "MF52" and tyre.params["PHY3"] == pytest.approx(r.params["PHY3"], rel=1e-6)
    a = np.radians(np.linspace(-10, 10, 21))
    ref = mf61.fy0(p52, 6000.0, a, math.radians(3.0), 260e3, version="5.2")
    got = tyre.forces(6000.0, a, 0.0, math.radians(3.0), 260e3)["fy"]
    assert np.max(np.abs(got - ref)) < 0.01 * np.max(np.abs(ref))


def test_orientation_error_for_sae_data():
    df = gen.make_sweeps(gen.contract_mf61(), seed=7, cambers_deg=[0.0], pressures=[260e3], slip_angles_deg=[0.0], n_points=31)
    df = df.assign(fy=-df["fy"])
    with pytest.raises(Exception, match="convention=sae"):
        fit_mf(df, tyre_info=INFO, stages=["Fy0"])


@pytest.mark.slow
def test_recovery_ten_seeds_worst_case():
    worst = {c: 0.0 for c in ("fx", "fy", "mz", "mx", "my")}
    for seed in range(10, 20):
        r = fit_mf(gen.make_sweeps(gen.contract_mf61(), seed=seed), tyre_info=INFO)
        err = recovery_error(r.params)
        print(f"seed {seed} [% of peak]:", {c: round(v, 3) for c, v in err.items()})
        worst = {c: max(worst[c], err[c]) for c in worst}
    print("worst over 10 seeds [% of peak]:", {c: round(v, 3) for c, v in worst.items()})
    # issue 13's target as written: every channel within 1 % of its peak on every one of the 10 seeds
    for c in ("fx", "fy", "mz", "mx", "my"):
        assert worst[c] < 1.0, (c, worst)


def _csv(df: pd.DataFrame, path):
    out = pd.DataFrame({"run": df["run"], "fz [N]": df["fz"], "slip_angle [deg]": np.degrees(df["slip_angle"]),
                        "camber [deg]": np.degrees(df["camber"]), "pressure [kPa]": df["pressure"] / 1e3,
                        "fy [N]": df["fy"], "mz [N*m]": df["mz"]})
    path.write_text(out.to_csv(index=False))
    return path


def test_batch_fit_takes_model(tmp_path, capsys):
    src = tmp_path / "data"
    src.mkdir()
    for k, seed in enumerate((8, 9)):
        df = gen.make_sweeps(gen.contract_mf61(), seed=seed, pressures=[260e3], cambers_deg=[0.0], slip_angles_deg=(), n_points=31,
                             loads=[3000.0, 6000.0, 9000.0], combined=False)
        _csv(df, src / f"tyre{k}.csv")
    out = tmp_path / "out"
    assert main(["batch", "fit", str(src), "--out", str(out), "--model", "mf61", "--workers", "1"]) == 0
    for k in (0, 1):
        tyre = read_tyre(out / f"tyre{k}.tir")
        assert tyre.family == "MF61"
        a = np.radians(np.linspace(-10, 10, 21))
        ref = mf61.fy0(gen.contract_mf61(), 6000.0, a, 0.0, 260e3)
        assert np.max(np.abs(tyre.forces(6000.0, a, 0.0, 0.0, 260e3)["fy"] - ref)) < 0.02 * np.max(np.abs(ref))
    assert "2 fitted" in capsys.readouterr().out


def test_l1_cost_resists_outliers_better_than_l2():
    # Komana et al. Eq. 5 (sum of absolute mu errors): a few gross outliers pull l2 more than l1
    df = gen.make_sweeps(gen.contract_mf61(), seed=11, pressures=[260e3], cambers_deg=[0.0], slip_angles_deg=[0.0], n_points=41,
                         loads=[3000.0, 6000.0, 9000.0], noise=0.003)
    rng = np.random.default_rng(0)
    lat = df["slip_ratio"].abs().groupby(df["run"]).transform("max") == 0
    idx = rng.choice(df.index[lat & (df["slip_angle"].abs() > math.radians(6))], 12, replace=False)
    df.loc[idx, "fy"] *= 0.6
    err = {}
    for cost in ("l2", "l1"):
        r = fit_mf(df, cost=cost, tyre_info=INFO, stages=["Fy0"])
        a = np.radians(np.linspace(-12, 12, 49))
        ref = mf61.fy0(gen.contract_mf61(), 6000.0, a, 0.0, 260e3)
        err[cost] = float(np.max(np.abs(mf61.fy0(r.params, 6000.0, a, 0.0, 260e3) - ref)) / np.max(np.abs(ref)))
    assert err["l1"] < 0.5 * err["l2"], err


def test_constraints_checked_on_the_grid_of_the_fitted_range(full_fit):
    from tyrefit.fitting.mf_contract import _factors

    _, r = full_fit
    cons = [c for f in r.stages.values() for c in f.constraints]
    names = {c["constraint"] for c in cons}
    assert {"mu_x > 0", "E_x <= 1", "K_x > 0", "mu_y > 0", "E_y <= 1", "K_y > 0 (data's sign)"} <= names
    assert all(c["holds"] for c in cons), cons
    # the check itself sees a broken curvature: E_y = PEY1 + ... > 1 somewhere on the grid
    fz = np.array([3000.0, 9000.0])
    bad = dict(r.params, PEY1=1.2)
    ey = dict((n, v) for n, v, _ in _factors(bad, "Fy0", fz, 0.0 * fz, 0.0 * fz, np.ones(2)))["E_y <= 1"]
    assert np.min(ey) < 0



def fy_alpha0_error(p_fit, **design) -> float:
    """Worst |fitted - generating| Fy of the drive/brake sweeps at alpha = 0, in % of the peak Fy of ``design``.

    Evaluated noise-free at 81 points per sweep (slip ratio 0.005 apart): between the 41 samples (0.01 apart)
    of the fitted record, where the kappa-induced side force SV_yk rises from 0 to its peak (kappa ~ 0.04).
    """
    a = gen.make_sweeps(gen.contract_mf61(), noise=0.0, n_points=81, **design)
    b = gen.make_sweeps(p_fit, noise=0.0, n_points=81, **design)
    at0 = ((a["slip_angle"].abs() < 1e-9) & (a.groupby("run")["slip_ratio"].transform("std") > 0)).to_numpy()
    t, f = a["true_fy"].to_numpy(), b["true_fy"].to_numpy()
    return 100.0 * float(np.max(np.abs(f[at0] - t[at0])) / np.max(np.abs(t)))


#: 5 loads, one pressure and camber, pure slip and slip-ratio sweeps at 0, -3, -6 deg (41 points: kappa 0.01 apart)
SMALL = dict(pressures=[260e3], cambers_deg=[0.0], slip_angles_deg=[0.0, -3.0, -6.0])


@pytest.fixture(scope="module")
def combined_fy_fits():
    """The staged fit up to combined Fy (no joint polish) of SMALL, seeds 21-25, 1 % noise."""
    out = []
    for seed in range(21, 26):
        df = gen.make_sweeps(gen.contract_mf61(), seed=seed, **SMALL)
        out.append((seed, df, fit_mf(df, tyre_info=INFO, stages=["Fx0", "Fy0", "Fx", "Fy"])))
    return out


def test_kappa_induced_side_force_keeps_one_lobe_between_the_samples(combined_fy_fits):
    # SV_yk = DV_yk sin(RVY5 atan(RVY6 kappa)) (4.E66), the only Fy of a drive/brake sweep at alpha = 0 and camber 0
    # besides Gy_kappa Fy0(0).  Slip-ratio samples 0.01 apart did not rule out a phase-wrapped alias (RVY5 ~ 3.6,
    # |RVY6| ~ 150 for -1.80 / -27.5): it meets the generating curve at the samples and swings through the opposite
    # lobe between kappa = 0 and +-0.01.  Before the one-lobe constraint (tyrefit.fitting.mf.SVYK_LOBE), seeds 21
    # and 25 took it: 2.09 and 2.05 % of peak Fy at kappa = +-0.005; with it and the RVY4 start (staged fit, no joint
    # polish) seeds 21-25: 0.09-0.29 %, RVY5 1.78-1.81, |RVY6| 25.6-28.6
    for seed, df, r in combined_fy_fits:
        err = fy_alpha0_error(r.params, **SMALL)
        assert err < 1.0, (seed, err, r.params["RVY5"], r.params["RVY6"])
        kmax = float(df["slip_ratio"].abs().max())
        phase = abs(r.params["RVY5"] * math.atan(r.params["RVY6"] * kmax))
        cons = {c["constraint"]: c for c in r.stages["Fy"].constraints}
        assert cons[SVYK_LOBE]["holds"] and phase <= math.pi + 1e-6, (seed, r.params["RVY5"], r.params["RVY6"])
    # the constraint tells the alias the old fit took (seed 21) from the generating set and the published ones
    from tyrefit.fitting.mf_contract import _factors

    def lobe(rvy5, rvy6):
        fz = np.full(2, FNOMIN)
        out = dict((n, v) for n, v, _ in _factors(dict(gen.contract_mf61(), RVY5=rvy5, RVY6=rvy6), "Fy", fz,
                                                  0.0 * fz, 0.0 * fz, np.array([-1.0, 1.0]),
                                                  kappa=np.array([-0.2, 0.2])))
        return float(np.min(out[SVYK_LOBE]))

    assert lobe(-3.5677, 145.78) < -2.0
    assert lobe(-1.7992, -27.5155) > 0.5 and lobe(1.9, 10.0) > 0.5 and lobe(1.95, -50.0) > 0.0
    # the alias is what it seems: the same samples, 2 % of peak Fy between them
    alias = dict(gen.contract_mf61(), RVY1=0.0133, RVY2=0.0119, RVY5=-3.5677, RVY6=145.78)
    assert fy_alpha0_error(alias, **SMALL) > 1.5


def test_combined_fy_shift_is_not_traded_for_the_kappa_induced_force(combined_fy_fits):
    # DV_yk fades with slip angle as cos(atan(RVY4 alpha)) (4.E67), flat at RVY4 = 0.  Started there, the Fy stage
    # kept SV_yk at full size at -3 and -6 deg (RVY4 -3.1 to 8.6 for -97) and moved the shift SHy_kappa = RHY1 +
    # RHY2 dfz to carry it (RHY1 -0.0032 to -0.0039, RHY2 0.0064-0.0077 for -0.0062, 0.0045: 0.004 off at the highest
    # load) on seeds 21, 22, 23, 25, a minimum of higher cost; Mz 1.7-2.4 % of peak near kappa = 0 at -3 deg with the
    # whole fit.  Measured from RVY4 = 20 (seeds 21-30, whole fit): RHY1 -0.0061 to -0.0068, RHY2 0.0039-0.0053,
    # |RVY4| 76-200, Mz <= 1.88 % (seed 30, the same before)
    p = gen.contract_mf61()
    dfz = (np.array(gen.PROGRAMME["load_fractions"]) * FNOMIN - FNOMIN) / FNOMIN
    for seed, _, r in combined_fy_fits:
        sh = r.params["RHY1"] + r.params["RHY2"] * dfz
        sh_true = p["RHY1"] + p["RHY2"] * dfz
        assert np.max(np.abs(sh - sh_true)) < 0.0015, (seed, r.params["RHY1"], r.params["RHY2"], r.params["RVY4"])
        assert abs(r.params["RVY4"]) > 30.0, (seed, r.params["RVY4"])


def test_channel_of_pure_noise_is_not_fitted():
    # qa bug 7: an MX channel of pure noise was fitted with 14 coefficients (R2 -0.0016)
    df = gen.make_sweeps(gen.contract_mf61(), seed=21, pressures=[260e3], cambers_deg=[0.0, 3.0], slip_angles_deg=[0.0], n_points=31,
                         loads=[3000.0, 6000.0, 9000.0], combined=False)
    noisy = df.assign(mx=np.random.default_rng(0).normal(0.0, 5.0, len(df)))
    r = fit_mf(noisy, tyre_info=INFO, stages=["Fy0", "Mx"])
    assert "Mx" not in r.stages and "Fy0" in r.stages
    assert any("MX not fitted: no signal above its noise floor" in n for n in r.notes), r.notes
    assert r.stats["mx"]["fitted"] is False
    neutral = mf61.neutral()
    assert all(r.params[k] == neutral[k] for k in ("QSX1", "QSX2", "QSX3", "QSX4"))
    # the same record with its real Mx (1 % noise) is fitted: the rule tells signal from noise
    real = fit_mf(df, tyre_info=INFO, stages=["Fy0", "Mx"])
    assert "Mx" in real.stages and real.stats["mx"]["fitted"] and real.stats["mx"]["r2"] > 0.95


def test_no_coefficient_sits_at_a_bound_silently(full_fit, tmp_path):
    # the generating tyre's data: nothing at a bound, every channel at its noise floor -> no warning
    assert full_fit[1].warnings == []
    # a curve the bounds cannot reach (PCY1 = 3.6 > 3) ends at the bound: said in the result and the .tir header,
    # with the RMSE above 1.5 x the noise floor it leaves
    design = dict(pressures=[260e3], cambers_deg=[0.0], slip_angles_deg=(), n_points=41,
                  loads=[3000.0, 6000.0, 9000.0], combined=False)
    r = fit_mf(gen.make_sweeps(dict(gen.contract_mf61(), PCY1=3.6), seed=24, **design), tyre_info=INFO,
               stages=["Fy0"])
    assert r.params["PCY1"] == pytest.approx(3.0, rel=1e-6)
    assert any(w.startswith("PCY1 = 3 is at its upper bound 3 (stage Fy0)") for w in r.warnings), r.warnings
    assert any(w.startswith("FY: RMSE") and "x the noise floor" in w for w in r.warnings), r.warnings
    head = "\n".join(read_tyre(r.write_tir(tmp_path / "b.tir")).header)
    assert "WARNING: PCY1 = 3 is at its upper bound" in head and "WARNING: FY: RMSE" in head


def test_mx_sine_term_fitted_from_two_loads():
    # the bundled TTC-style pair has 2 loads: holding QSX4-QSX9 there (old rule: >= 3 loads and 2 cambers)
    # left Mx at 5.3 x its noise floor; the sine term along Fy needs cornering sweeps, only its load factor 3 loads
    design = dict(loads=[3500.0, 7000.0], pressures=[260e3], cambers_deg=[0.0, 3.0], slip_angles_deg=(),
                  combined=False)
    df = gen.make_sweeps(gen.contract_mf61(), seed=23, n_points=41, **design)
    r = fit_mf(df, tyre_info=INFO, stages=["Fy0", "Mx"])
    assert {"QSX4", "QSX7", "QSX8", "QSX9"} <= set(r.fitted)
    assert ">= 3 load levels" in r.not_identifiable["QSX5"] and "QSX6" in r.not_identifiable
    assert r.stats["mx"]["rmse"] < 1.2 * r.stats["mx"]["noise_floor"], r.stats["mx"]
    assert recovery_error(r.params, **design)["mx"] < 1.0
    # the same record without the sine term (what the old rule held) is far off: the measure can fail
    held = fit_mf(df, tyre_info=INFO, stages=["Fy0", "Mx"], fixed={f"QSX{i}": 0.0 for i in range(4, 10)})
    assert held.stats["mx"]["rmse"] > 2.0 * held.stats["mx"]["noise_floor"]
    assert recovery_error(held.params, **design)["mx"] > 3.0


def test_one_noise_floor_for_pac89_and_mf(tmp_path, capsys):
    # qa bug 3 / issue 14: `fit X` and `fit X --model mf52` printed 62.1 and 68.5 N for one file
    df = gen.make_sweeps(gen.contract_mf61(), seed=22, pressures=[260e3], cambers_deg=[0.0, 3.0], slip_angles_deg=(), n_points=41,
                         loads=[3000.0, 6000.0, 9000.0], combined=False)
    f = _csv(df, tmp_path / "lat.csv")
    floors = []
    for extra in ([], ["--model", "mf52"]):
        assert main(["fit", str(f), "--out", str(tmp_path / f"t{len(extra)}.tir"), *extra]) == 0
        text = capsys.readouterr().out
        floors.append(float(text.split("noise floor ")[1].split(" N")[0]))
    assert floors[0] == pytest.approx(floors[1], rel=1e-3), floors  # the same number, printed to 3-4 digits
    # and it estimates the generator's noise (1 % of each sweep's peak |Fy|, pooled)
    sig = df.groupby("run")["true_fy"].transform(lambda v: 0.01 * np.max(np.abs(v)))
    assert abs(floors[1] / float(np.sqrt(np.mean(sig**2))) - 1.0) < 0.15


def test_combined_shifts_are_held_by_the_contract():
    # a shift of G (RHX1, RHY1, RHY2; 4.E52, 4.E60) makes G > 1 between zero slip and twice the shift: combined slip
    # would add force there, which the physical-validity contract forbids; they are held at 0 whatever the design
    sw = pd.DataFrame({"run": range(4), "fz": [3e3, 6e3] * 2, "camber": 0.0, "speed": np.nan, "pressure": 2.6e5,
                       "slip_angle": np.radians([-3.0, -3.0, -6.0, -6.0]), "kind": "combined"})
    pts = pd.DataFrame({"slip_ratio": np.linspace(-0.2, 0.2, 20)})
    for stage, names in (("Fx", ("RHX1",)), ("Fy", ("RHY1", "RHY2"))):
        why, _ = identifiability(stage, pts, sw)
        for k in names:
            assert "G exceed 1" in why[k]


@pytest.mark.parametrize("name", ["ref_Generic_Pac02Tire.tir", "mfeval_MagicFormula52_Paramerters.tir"])
def test_mf52_aligning_moment_reaches_the_noise_floor(name):
    # qa bug 4: the MF 5.2 Mz0 stage fitted the book's pure Mz0 (-t0 Fy0(gamma=0) + Mzr0) to data that MF 5.2
    # solvers give as -t (Fy - SVyk) + Mzr + s Fx at kappa = 0 (Chrono's VW microbus file: 3.3 x the floor)
    from pathlib import Path

    tyre = read_tyre(Path(__file__).parent / "data" / name)
    p = {k.upper(): v for k, v in tyre.params.items()}
    fz0 = p["FNOMIN"]
    rng = np.random.default_rng(4)
    rows = []
    for run, (fz, g) in enumerate((f, g) for g in (-3.0, 0.0, 3.0) for f in (0.5 * fz0, fz0, 1.5 * fz0)):
        a = np.radians(np.linspace(-12, 12, 81))
        f = tyre.forces(fz, a, 0.0, np.radians(g))
        rows.append(pd.DataFrame({"run": run, "fz": fz, "slip_angle": a, "slip_ratio": 0.0, "camber": np.radians(g),
                                  "fy": f["fy"] + rng.normal(0, 0.01 * np.max(np.abs(f["fy"])), a.size),
                                  "mz": f["mz"] + rng.normal(0, 0.01 * np.max(np.abs(f["mz"])), a.size)}))
    r = fit_mf(pd.concat(rows, ignore_index=True), model="mf52", stages=["Fy0", "Mz0"],
               tyre_info={"fnomin": fz0, "unloaded_radius": p["UNLOADED_RADIUS"]})
    for c in ("fy", "mz"):
        assert r.stats[c]["rmse"] < 1.1 * r.stats[c]["noise_floor"], (c, r.stats[c])


def test_rvy4_at_its_bound_is_a_note_not_a_warning():
    # sweeps at alpha = 0 and >= 3 deg do not measure how fast DV_yk fades in between once cos(atan(RVY4 alpha)) is
    # within the noise there (1 pressure and camber: 3 of seeds 21-30 end at +-200); another coefficient at its
    # bound stays a warning
    from tyrefit.fitting.mf import StageFit, _bound_warnings

    levels = {"slip_angle": [math.radians(-6.0), math.radians(-3.0), 0.0]}
    fy = StageFit("Fy", "fy", ["RVY4", "RCY1"], {}, {}, {"levels": levels}, 0.0, 0, 0.0, [], pd.DataFrame(), {}, [],
                  0, 0)
    notes: list[str] = []
    warns = _bound_warnings(dict(gen.contract_mf61(), RVY4=-200.0, RCY1=0.05), {"Fy": fy}, notes)
    assert len(warns) == 1 and warns[0].startswith("RCY1 = 0.05 is at its lower bound"), warns
    assert len(notes) == 1 and notes[0].startswith("RVY4 = -200 (stage Fy), its lower bound") and "3, 6 deg" in notes[0]
