"""Speed in the Magic Formula fit: LMUV, friction decay with slip speed (Pacejka 2012, 4.E7).

MF 6.1 (and 5.2) carry speed in Fx and Fy only through the scaling factor
LMUV: mu* = LMU / (1 + LMUV Vs / V0), Vs = Vcx sqrt(kappa^2 + tan^2 alpha),
V0 = LONGVL.  Records generated from the published MF 6.1 set
(tyrefit.synthetic.ttc_drivebrake) with LMUV = 0.3 and V0 = LONGVL = 16.6 m/s
at three speeds, 1 % noise, are fitted back; at one speed LMUV is held at 0
and the identifiability rule says why.
"""

from __future__ import annotations

import re

import numpy as np
import pandas as pd
import pytest

from tyrefit.fitting.mf import EFFECT_COEFFICIENTS, effect_coefficients, fit_mf, identifiability
from tyrefit.io.tir import read_tyre
from tyrefit.synthetic import ttc_drivebrake as gen

FNOMIN = gen.PUBLISHED_MF61["FNOMIN"]
INFO = {"fnomin": FNOMIN, "unloaded_radius": gen.PUBLISHED_MF61["UNLOADED_RADIUS"]}
V0 = gen.PUBLISHED_MF61["LONGVL"]  # 16.6 m/s: the generating set's reference speed
LMUV = 0.3
SPEEDS = [0.5 * V0, V0, 1.5 * V0]  # 8.3, 16.6, 24.9 m/s: the middle one is the fit's LONGVL
#: 5 loads, one pressure and camber; pure slip and slip-ratio sweeps at -3 and -6 deg
DESIGN = dict(pressures=[260e3], cambers_deg=[0.0], slip_angles_deg=[0.0, -3.0, -6.0])


def _tyre(lmuv: float = LMUV) -> dict:
    return dict(gen.contract_mf61(), LMUV=lmuv)


def _header(text: str) -> list[str]:
    """The ``$`` header lines of a written .tir, continuation lines joined."""
    return [ln for ln in re.sub(r"\n\$ {4,}", " ", text).splitlines() if ln.startswith("$")]


def curve_errors(p_fit, p_true, speed, design=DESIGN) -> dict[str, float]:
    """Worst |fitted - generating| at ``speed`` in % of the channel's peak, noise-free, over the data range.

    fx: along every slip-ratio sweep (pure and at -3, -6 deg); fy: along every sweep, the pure drive/brake sweep
    (alpha = 0) included: there Fy is the combined-slip shift SVy_kappa = DVy_kappa sin(RVY5 atan(RVY6 kappa))
    (with Gy_kappa Fy0(0)), and 81 points per sweep (slip ratio 0.005 apart) see it between the fitted record's
    samples (0.01 apart).  Before the one-lobe constraint on SVy_kappa (tyrefit.fitting.mf.SVYK_LOBE) the fit
    took a phase-wrapped alias there on some seeds (RVY5 ~ 3.6, RVY6 ~ 150 for -1.80 / -27.5: 2.0-2.6 % of peak
    Fy at kappa = +-0.005); this check left that sweep out.
    """
    a = gen.make_sweeps(p_true, noise=0.0, n_points=81, speeds=[speed], **design)
    b = gen.make_sweeps(p_fit, noise=0.0, n_points=81, speeds=[speed], **design)
    kappa_sweep = (a["slip_ratio"].groupby(a["run"]).transform("std") > 0).to_numpy()
    out = {}
    for c, rows in (("fx", kappa_sweep), ("fy", np.ones(len(a), bool))):
        t, f = a[f"true_{c}"].to_numpy()[rows], b[f"true_{c}"].to_numpy()[rows]
        out[c] = 100.0 * float(np.max(np.abs(f - t)) / np.max(np.abs(t)))
    return out


@pytest.fixture(scope="module")
def three_speeds():
    """Every stage (and the joint polish) on 3 speeds x 5 loads, pure and combined, 1 % noise."""
    df = gen.make_sweeps(_tyre(), seed=21, speeds=SPEEDS, **DESIGN)
    return df, fit_mf(df, tyre_info=INFO)


def test_lmuv_recovered_from_three_speeds(three_speeds):
    _, r = three_speeds
    assert r.params["LONGVL"] == pytest.approx(V0)  # the middle speed level: LMUV is referred to the same V0
    assert "LMUV" in r.fitted and "LMUV" not in r.not_identifiable
    # fitted in Fx0, held by Fy0 (Fx0 was fitted with it), polished with both channels
    assert "LMUV" in r.stages["Fx0"].varied and "LMUV" not in r.stages["Fy0"].varied
    assert "LMUV" in r.stages["joint"].varied
    # measured on seeds 21-30 (this design, every stage): 0.2977-0.3030; the staged value before the joint
    # polish (stages Fx0, Fy0 only, no combined sweeps) 0.276-0.322
    assert r.params["LMUV"] == pytest.approx(LMUV, abs=0.03)


def test_fx_fy_within_1pct_of_peak_at_every_speed(three_speeds):
    _, r = three_speeds
    p = _tyre()
    for v in SPEEDS:
        err = curve_errors(r.params, p, v)
        # measured on seeds 21-30: worst Fx 0.50, Fy 0.41 % of peak at any of the three speeds (Fy with the alpha = 0
        # sweeps; without the one-lobe constraint on SVy_kappa seeds 22, 24, 27 took the alias: Fy 2.1-2.6 %; from
        # RVY4 = 0 instead of 20, Fy 0.69 %)
        assert err["fx"] < 1.0 and err["fy"] < 1.0, (v, err)
    # the check can fail: the same tyre without its speed law misses at the speeds away from LONGVL
    # (8 % of mu at 24.9 m/s and kappa = 0.2: Vs / V0 = 0.3), while it is nearly the same at LONGVL
    no_speed = dict(r.params, LMUV=0.0)
    assert curve_errors(no_speed, p, SPEEDS[2])["fx"] > 3.0
    assert curve_errors(no_speed, p, SPEEDS[2])["fy"] > 3.0
    assert curve_errors(no_speed, p, SPEEDS[0])["fx"] > 1.0


def test_fitted_lmuv_written_to_scaling_section_and_read_back(three_speeds, tmp_path):
    _, r = three_speeds
    path = r.write_tir(tmp_path / "speed.tir")
    text = path.read_text()
    section = text.split("[SCALING_COEFFICIENTS]", 1)[1].split("[", 1)[0]
    line = next(ln for ln in section.splitlines() if ln.startswith("LMUV"))
    assert float(line.split("=", 1)[1].split("$", 1)[0]) == r.params["LMUV"]  # repr: the same float
    head = _header(text)
    assert any("LMUV = " in ln and "fitted" in ln and "3 speeds" in ln for ln in head), head
    assert not any("DEFAULTS [SCALING_COEFFICIENTS]" in ln and "LMUV" in ln for ln in head)
    tyre = read_tyre(path)
    assert tyre.params["LMUV"] == r.params["LMUV"]
    k = np.linspace(-0.2, 0.2, 21)
    got = tyre.forces(FNOMIN, slip_angle=0.0, slip_ratio=k, camber=0.0, pressure=260e3, speed=SPEEDS[2])
    from tyrefit.models import mf61

    want = mf61.forces(r.params, FNOMIN, k, 0.0, 0.0, 260e3, SPEEDS[2])
    np.testing.assert_array_equal(got["fx"], want["fx"])


def test_one_speed_holds_lmuv_at_zero_and_says_why(tmp_path):
    df = gen.make_sweeps(_tyre(), seed=22, speeds=[V0], **dict(DESIGN, slip_angles_deg=[0.0]))
    r = fit_mf(df, tyre_info=INFO, stages=["Fx0", "Fy0"])
    assert "LMUV" not in r.fitted and r.params.get("LMUV", 0.0) == 0.0
    why = r.not_identifiable["LMUV"]
    assert "needs >= 2 speeds" in why and "1 speed level" in why and "curvature E" in why
    head = _header(r.write_tir(tmp_path / "one.tir").read_text())
    held = next(ln for ln in head if "held at neutral values" in ln)
    assert "LMUV" in held.split(":", 2)[2].replace(",", " ").split()
    assert not any("LMUV = " in ln and "fitted" in ln for ln in head)
    assert read_tyre(tmp_path / "one.tir").params["LMUV"] == 0.0


def test_identifiability_rule_for_lmuv_speeds_and_peaks():
    sw = pd.DataFrame({"run": range(4), "fz": 4000.0, "camber": 0.0, "pressure": 2.6e5, "slip_angle": 0.0,
                       "kind": "longitudinal", "speed": [8.3, 8.3, 16.6, 16.6]})
    pts = pd.DataFrame({"slip_ratio": np.linspace(-0.2, 0.2, 20)})
    why, facts = identifiability("Fx0", pts, sw, peak_runs=[0, 2])
    assert "LMUV" not in why and facts["speed_levels"] == 2 and facts["speed_levels_through_peak"] == 2
    lat = pd.DataFrame({"slip_angle": np.radians(np.linspace(-12, 12, 20))})
    why, _ = identifiability("Fy0", lat, sw.iloc[:2].assign(kind="lateral"))
    assert "needs >= 2 speeds" in why["LMUV"]
    # two speeds, but only the slow sweeps reach their peak: the friction at speed is not measured
    why, _ = identifiability("Fx0", pts, sw, peak_runs=[0, 1])
    assert "through the peak at >= 2 speeds" in why["LMUV"]
    why, _ = identifiability("Fx0", pts, sw, any_peak=False)
    assert "LMUV" in why
    # no speed channel: nothing to tell
    why, _ = identifiability("Fx0", pts, sw.assign(speed=np.nan))
    assert "needs >= 2 speeds" in why["LMUV"]
    # stages that do not own LMUV never list it
    assert "LMUV" not in identifiability("Mz0", lat, sw.assign(kind="lateral"))[0]


def test_effects_speed_fits_lmuv_only_when_asked():
    assert EFFECT_COEFFICIENTS["speed"] == ("LMUV",)
    vary, notes = effect_coefficients(["speed"])
    assert "LMUV" in vary and any("LMUV" in n and "cornering stiffness" in n for n in notes)
    # a cornering record at one load and two speeds (diagnose's ladder): without the speed effect the tyre
    # carries no speed law, with it the waterfall falls to the noise floor
    df = gen.make_sweeps(_tyre(), seed=23, speeds=[0.5 * V0, 1.5 * V0], loads=[FNOMIN],
                         **dict(DESIGN, slip_angles_deg=[]))
    assert set(df["slip_ratio"].unique()) == {0.0}
    before = fit_mf(df, tyre_info=INFO, effects=["offsets"], stages=["Fy0"])
    speed = fit_mf(df, tyre_info=INFO, effects=["offsets", "speed"], stages=["Fy0"])
    assert "LMUV" not in before.fitted and before.params.get("LMUV", 0.0) == 0.0
    assert "LMUV" in speed.stages["Fy0"].varied
    # measured (seeds 23-25): LMUV 0.277-0.302; RMSE 132-143 N -> 68-74 N, noise floor 64-67 N
    assert speed.params["LMUV"] == pytest.approx(LMUV, abs=0.06)
    floor = speed.stats["fy"]["noise_floor"]
    assert speed.rmse < 0.6 * before.rmse and speed.rmse < 1.25 * floor, (speed.rmse, before.rmse, floor)
    # with drive/brake sweeps as well, --effects without speed holds LMUV in Fx0 too (no note: not asked)
    both = gen.make_sweeps(_tyre(), seed=24, speeds=[0.5 * V0, 1.5 * V0], **dict(DESIGN, slip_angles_deg=[0.0]))
    r = fit_mf(both, tyre_info=INFO, effects=["load_friction"], stages=["Fx0", "Fy0"])
    assert "LMUV" not in r.fitted and not any("LMUV" in n for n in r.notes)


def test_mf52_fit_carries_lmuv():
    df = gen.make_sweeps(dict(_tyre(), FITTYP=6), seed=25, speeds=[0.5 * V0, V0, 1.5 * V0],
                         **dict(DESIGN, slip_angles_deg=[0.0]))
    r = fit_mf(df, model="mf52", tyre_info=INFO, stages=["Fx0", "Fy0"])
    assert "LMUV" in r.fitted and r.params["LMUV"] == pytest.approx(LMUV, abs=0.05)


def test_no_speed_law_in_the_data_gives_lmuv_near_zero_without_warning():
    # two speeds, a tyre without friction decay: LMUV is fitted, ends at (or next to) 0, and that is no warning
    df = gen.make_sweeps(_tyre(0.0), seed=26, speeds=[0.5 * V0, 1.5 * V0], **dict(DESIGN, slip_angles_deg=[0.0]))
    r = fit_mf(df, tyre_info=INFO, stages=["Fx0", "Fy0"])
    # fitted next to 0, or (its standard error above its size) held at its neutral 0 and named so
    assert 0.0 <= r.params["LMUV"] < 0.03
    assert "LMUV" in r.fitted or r.not_identifiable["LMUV"].startswith("not identified")
    assert not any("LMUV" in w for w in r.warnings), r.warnings
    # friction that rises with slip speed (LMUV < 0 in the generating set) is outside MF's law: LMUV ends at its
    # bound 0 and a note says what that means
    df = gen.make_sweeps(_tyre(-0.2), seed=27, speeds=[0.5 * V0, 1.5 * V0], **dict(DESIGN, slip_angles_deg=[0.0]))
    r = fit_mf(df, tyre_info=INFO, stages=["Fx0", "Fy0"])
    assert r.params["LMUV"] < 1e-6 and not any("LMUV" in w for w in r.warnings), r.warnings
    assert any(n.startswith("LMUV = 0") and "no fall of friction with slip speed" in n for n in r.notes), r.notes


@pytest.mark.slow
def test_full_design_at_three_speeds_every_channel_within_1pct():
    # 5 loads x 3 pressures x 3 cambers, pure and combined (0, -3, -6 deg), at 3 speeds, LMUV 0.3, 1 % noise.
    # Before the one-lobe constraint on SVy_kappa (tyrefit.fitting.mf.SVYK_LOBE) seeds 1-3 took the phase-wrapped
    # alias RVY5 ~ 3.6, |RVY6| ~ 151: Fy 5.33-5.38 % of peak (alpha = 0 sweeps, kappa = +-0.005), Mx 1.81-1.83 %
    # (through Fy).  Measured with it, seeds 1-3, worst over the 3 speeds: Fx 0.15, Fy 0.18, Mz 0.32, Mx 0.18,
    # My 0.07 %; RVY5 1.800-1.801, RVY6 -27.41 to -27.50
    p = _tyre()
    df = gen.make_sweeps(p, seed=1, speeds=SPEEDS)
    r = fit_mf(df, tyre_info=INFO)
    for v in SPEEDS:
        a = gen.make_sweeps(p, noise=0.0, n_points=81, speeds=[v])
        b = gen.make_sweeps(r.params, noise=0.0, n_points=81, speeds=[v])
        for c in ("fx", "fy", "mz", "mx", "my"):
            t, f = a[f"true_{c}"].to_numpy(), b[f"true_{c}"].to_numpy()
            err = 100.0 * float(np.max(np.abs(f - t)) / np.max(np.abs(t)))
            assert err < 1.0, (v, c, err, r.params["RVY5"], r.params["RVY6"])
