"""Diagnosis of the aligning moment and the drive/brake force (tyrefit.diagnose.channels).

Truth tyres: MFeval's published MF 6.1 set evaluated by tyrefit.models.mf61, with coefficient
groups switched off or on (benchmarks/diagnose_channels.py); noise added here.  The Fx catalogue
is built on PAC89's longitudinal curve, a form the truth does not share; the Mz catalogue is MF
5.2/6.1's own trail form (tyrefit.effects.channels.trail_moment), so its Mz tests also use a truth
of another form (Pacejka's brush model, tests/test_trail_model.py).
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from tyrefit.diagnose.channels import channel_data, diagnose_channel, nested_p, sweep_p
from tyrefit.fitting.noise import LagOneNoise
from tyrefit.models import mf61
from tyrefit.synthetic.ttc_drivebrake import COEFFICIENT_GROUPS, make_sweeps, published_mf61

_GROUPS = COEFFICIENT_GROUPS


def _truth(keep: str | None) -> dict:
    p = published_mf61()
    for g, keys in _GROUPS.items():
        if g != keep:
            for k in keys:
                p[k] = 0.0
    return p


def _case(channel, keep, loads=(0.5, 1.0, 1.5), cambers=(0.0,), pressures=(260e3,), seed=3, noise=0.01):
    p = _truth(keep)
    df = make_sweeps(p, seed=seed, noise=0.0, loads=[f * p["FNOMIN"] for f in loads], cambers_deg=cambers,
                     pressures=pressures, slip_angles_deg=(0.0,), n_points=41, combined=False, pure=True)
    rng = np.random.default_rng(seed)
    for y in (channel, "fy"):  # the Mz model reads the measured side force: it is noisy too
        for _, g in df.groupby("run"):
            t = g[f"true_{y}"].to_numpy(float)
            df.loc[g.index, y] = t + rng.normal(0.0, noise * np.max(np.abs(t)), len(g))
    swept = df.groupby("run")["slip_ratio"].transform(np.ptp) > 0.05
    df = df[swept if channel == "fx" else ~swept].reset_index(drop=True)
    cols = ["run", "fz", "slip_angle", "slip_ratio", "camber", "pressure", channel] + (["fy"] if channel == "mz" else [])
    cd = channel_data(df[cols], channel)
    assert not isinstance(cd, str), cd
    return p, df, diagnose_channel(cd)


def test_rolling_resistance_is_named_with_its_size():
    """PVX1/PVX2 shift the whole Fx curve (Pacejka 2012, 4.E18); fx_sv is Sv/Fz, PVX1 + PVX2 dfz averaged."""
    p, df, dg = _case("fx", "rolling")
    assert "fx_rolling" in dg.accepted
    dfz = (df["fz"] - p["FNOMIN"]) / p["FNOMIN"]
    expect = float(np.mean(p["PVX1"] + p["PVX2"] * dfz))
    got = dg.steps[-1].values["fx_sv"]
    assert got == pytest.approx(expect, rel=0.15)
    sizes = {s["effect"]: s for s in dg.to_dict()["effects"]}
    # leaving it out costs about Sv itself at every point: |Sv| ~ 6.8 % of Fz
    assert sizes["fx_rolling"]["size_rms"] > 0.5 * expect * float(np.sqrt(np.mean(df["fz"] ** 2)))


def test_plain_fx_names_no_shift_rolling_or_asymmetry():
    _, _, dg = _case("fx", None)
    assert not {"fx_rolling", "fx_offsets", "fx_asymmetry", "fx_camber", "fx_pressure"} & set(dg.accepted)
    assert dg.unexplained["ratio_to_floor"] < 1.5


def test_drive_brake_asymmetry_is_named_only_when_present():
    """PEX4 = 0.59: Ex (1 - PEX4 sgn kappa) (4.E14) differs between drive and braking."""
    _, _, with_it = _case("fx", "asymmetry")
    assert "fx_asymmetry" in with_it.accepted
    assert with_it.steps[-1].values["fx_asym"] > 0.0  # the sign of PEX4: E smaller in drive than in braking
    _, _, without = _case("fx", None, seed=4)
    assert "fx_asymmetry" not in without.accepted


def test_aligning_pressure_is_named_only_when_present():
    pr = (220e3, 260e3, 300e3)
    _, _, with_it = _case("mz", "pressure", pressures=pr)
    assert "mz_pressure" in with_it.accepted
    _, _, without = _case("mz", None, pressures=pr)
    assert "mz_pressure" not in without.accepted
    assert {c["effect"]: c["status"] for c in without.candidates}["mz_pressure"] != "not testable"


def test_nested_p_holds_its_level_under_correlated_noise_only_with_the_correction():
    """AR(1) noise at rho 0.8 along 6 sweeps of 60 points, two smooth directions tested: the corrected test
    rejects about alpha of 300 null sets, the uncorrected one far more."""
    rng = np.random.default_rng(0)
    n, G, rho = 60, 6, 0.8
    x = np.tile(np.linspace(-1, 1, n), G)
    X = np.column_stack([np.ones_like(x), x, np.sin(np.pi * x)])  # H0: the first; H1 adds two smooth ones
    rej = {0.0: 0, rho: 0}
    for _ in range(300):
        e = np.concatenate([_ar1(rng, n, rho) for _ in range(G)])
        r0 = e - e.mean()
        r1 = e - X @ np.linalg.lstsq(X, e, rcond=None)[0]
        for r in rej:
            rej[r] += nested_p(r0, r1, 2, 3, r) < 0.05
    assert rej[rho] / 300 <= 0.10
    assert rej[0.0] / 300 >= 0.25


def test_sweep_p_is_a_one_sided_paired_test():
    assert sweep_p(np.array([3.0, 2.5, 4.0, 3.2, 2.9])) < 0.001
    assert sweep_p(np.array([-3.0, -2.5, -4.0, -3.2])) > 0.99
    assert 0.3 < sweep_p(np.array([1.0, -1.0, 2.0, -2.0])) < 0.7
    assert sweep_p(np.array([5.0, 6.0])) == 1.0  # two sweeps: no test


def test_lag_one_noise_is_calibrated_on_short_sweeps():
    """41-point sweeps: the raw lag-one correlation after the spline is biased; the calibrated one is not."""
    rng = np.random.default_rng(5)
    x = np.tile(np.linspace(-0.2, 0.2, 41), 12)
    sweep = np.repeat(np.arange(12), 41)
    est = LagOneNoise(x, sweep)
    for rho in (0.0, 0.5, 0.8):
        e = np.concatenate([_ar1(rng, 41, rho) for _ in range(12)])
        curve = 0.3 * np.sin(20 * x)  # a smooth model misfit the coarse spline takes away
        assert est(e + curve) == pytest.approx(rho, abs=0.2)
        assert est.raw(e) < rho or rho == 0.0


def test_channels_of_a_cornering_and_a_drive_brake_record():
    """The bundled TTC-style pair of a published MF 6.1 tyre: Fy, Mz and Fx each diagnosed (DESIGN contract)."""
    import tyrefit as tf

    dg = tf.diagnose([tf.datasets.path("ttc_mf61/cornering.dat"), tf.datasets.path("ttc_mf61/drivebrake.dat")],
                     convention="sae")
    ch = dg.to_dict()["channels"]
    assert set(ch) == {"fy", "mz", "fx"}
    for k, unit in (("fy", "N"), ("mz", "N*m"), ("fx", "N")):
        c = ch[k]
        assert c["unit"] == unit
        assert c["steps"][0]["rmse_heldout"] >= c["steps"][-1]["rmse_heldout"]
        assert isinstance(c["unexplained"]["structure_found"], bool)
        assert c["noise_floor"] > 0
    assert ch["fy"]["accepted"] == dg.accepted
    assert "fx_rolling" in ch["fx"]["accepted"]  # PVX1 = 0.068: 6.8 % of the load at zero slip
    assert ch["fx"]["data"]["sweeps"] == 4  # the pure drive/brake sweeps: 2 loads x 2 cambers at zero slip angle


def test_drive_brake_record_alone_is_refused_in_one_line(tmp_path):
    from tyrefit.datasets import path

    out = subprocess.run([sys.executable, "-m", "tyrefit.cli", "diagnose", str(path("ttc_mf61/drivebrake.dat")),
                          "--convention", "sae", "--json", str(tmp_path / "d.json")],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 2
    assert "Traceback" not in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1
    assert "cornering record too" in out.stderr


def _ar1(rng, n, rho):
    z = rng.standard_normal(n + 60)
    out = np.empty(n + 60)
    out[0] = z[0]
    for i in range(1, n + 60):
        out[i] = rho * out[i - 1] + np.sqrt(1 - rho * rho) * z[i]
    return out[60:]


def test_pressure_effect_needs_pressures():
    df = pd.DataFrame({"run": np.repeat([0, 1], 30), "fz": np.repeat([3000.0, 6000.0], 30),
                       "slip_angle": np.tile(np.radians(np.linspace(-10, 10, 30)), 2),
                       "mz": np.tile(40 * np.sin(np.radians(np.linspace(-10, 10, 30)) * 6), 2),
                       "fy": np.tile(-3000 * np.sin(1.3 * np.arctan(np.radians(np.linspace(-10, 10, 30)) * 10)), 2)})
    cd = channel_data(df, "mz")
    assert not isinstance(cd, str)
    assert isinstance(channel_data(df, "fx"), str)


def test_systematic_share_tells_a_repeated_misfit_from_correlated_noise():
    """A misfit pattern that repeats over 9 sweeps (scaled with load) reads as systematic; AR(1) noise at
    rho 0.9, new in every sweep, does not, however large it is."""
    p, df, dg = _case("fx", None, cambers=(0.0, 2.0, 4.0))
    from tyrefit.diagnose.channels import SYSTEMATIC, systematic_share

    cd = dg.data
    rng = np.random.default_rng(2)
    misfit = 30.0 * np.sin(8 * cd.slip) * cd.inputs.fz / 6752.0
    noise = np.concatenate([_ar1(rng, int((cd.sweep == g).sum()), 0.9) for g in range(cd.n_sweeps)]) * 40.0
    assert systematic_share(cd, misfit + 0.3 * noise) > SYSTEMATIC
    assert systematic_share(cd, noise) < SYSTEMATIC


def test_a_channel_that_cannot_be_fitted_is_reported_not_raised(monkeypatch):
    import tyrefit.diagnose.channels as C
    from tyrefit.errors import FitError

    def boom(*a, **k):
        raise FitError("the model is not finite at the start values")

    monkeypatch.setattr(C, "diagnose_channel", boom)
    df = pd.DataFrame({"run": np.repeat([0, 1], 30), "fz": np.repeat([3000.0, 6000.0], 30),
                       "slip_angle": np.tile(np.radians(np.linspace(-10, 10, 30)), 2),
                       "mz": np.tile(40 * np.sin(np.radians(np.linspace(-10, 10, 30)) * 6), 2),
                       "fy": np.tile(-3000 * np.sin(1.3 * np.arctan(np.radians(np.linspace(-10, 10, 30)) * 10)), 2)})
    out, absent = C.diagnose_channels(df)
    assert out == {} and "could not be fitted" in absent["mz"]


def test_mz_camber_is_not_named_for_a_misfit_common_to_every_camber():
    """A published MF 6.1 tyre with only its Mz curvature asymmetry (PEZ2-like, no camber terms), 3 loads x 3
    cambers, independent noise: PAC89's Mz cannot follow the asymmetric shape, and a camber moment once took
    up part of that misfit (it was named in this very case).  Camber is named only where the residual
    differs between the camber levels consistently from load to load (the contrast test of the Fy
    diagnosis), and here it does not."""
    from benchmarks.diagnose_channels import run_case

    row = run_case(("mz", "asymmetry", "3loads_3cambers", "iid", 1001))
    assert "mz_asymmetry" in row["named"]
    assert "mz_camber" not in row["named"]


@pytest.mark.parametrize("truth", ["offsets", "asymmetry"])
def test_fx_effects_under_strongly_correlated_noise_are_found_by_the_noise_models_null(truth):
    """A published MF 6.1 tyre with only its Fx slip shift (PHX1-like) or only its drive/brake curvature
    difference (PEX4-like), 3 loads, AR(1) noise at rho 0.9 along 41-point sweeps: a handful of independent
    values per sweep, so the F test (corrected with the correlation's upper bound) and the paired sweep test
    (3 sweeps) both stay above their level.  The held-out gain against its null under the AR(1) + offset
    noise model estimated from the residuals finds the effect; the plain tyre under the same noise has
    neither named."""
    from benchmarks.diagnose_channels import run_case

    row = run_case(("fx", truth, "3loads", "ar1_09", 1000))
    assert f"fx_{truth}" in row["named"]
    plain = run_case(("fx", "plain", "3loads", "ar1_09", 1000))
    assert not {"fx_offsets", "fx_asymmetry"} & set(plain["named"])
