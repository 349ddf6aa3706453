"""A TTC-style cornering + drive/brake pair, fitted as a user would (issue 23).

The pair is tyrefit.synthetic.ttc_field's (SYNTHETIC: an FSAE-sized tyre with physics the MF 6.1 form
does not carry; 3 pressures x 3 cambers x 6 loads of cornering, drive/brake at 0/-3/-6 deg whose
slip ratios stop short of the Fx peak at the heavy loads, a noisy drive/brake Mz, the two records'
loaded-radius channels 2 cm apart).  Fitted once through the command line; then the written tyre
must load in eval, compare and sim without --allow-unphysical, keep the contract over its declared
envelope, carry the cornering record's radius, and judge each record against its own noise.  The fit
result the command wrote is kept (:func:`_cli_fit`) for the tests of its statistics, instead of fitting
the same records again through the library; the FSAE ramp at the belt's grip is run once for two tests.
"""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from tyrefit.cli import main
from tyrefit.io.tir import read_tyre
from tyrefit.synthetic import ttc_field
from tyrefit.tyres.contract import check_tyre


def _cli_fit(argv):
    """``tyrefit fit argv`` (exit 0 asserted); returns the fit result the command wrote to its .tir."""
    from tyrefit.fitting.mf_result import FitResultMF

    written = []
    original = FitResultMF.write_tir

    def keep(self, path, **kw):
        written.append(self)
        return original(self, path, **kw)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(FitResultMF, "write_tir", keep)
        assert main(["fit", *argv]) == 0
    assert len(written) == 1
    return written[0]


@pytest.fixture(scope="module")
def fitted_result(tmp_path_factory):
    d = tmp_path_factory.mktemp("ttc_pair")
    corner, drive = ttc_field.write_pair(d, scale="small")
    tir = d / "mf61.tir"
    r = _cli_fit([str(corner), str(drive), "--convention", "sae", "--model", "mf61", "--out", str(tir)])
    return (d, corner, drive, tir), r


@pytest.fixture(scope="module")
def fitted(fitted_result):
    return fitted_result[0]


@pytest.fixture(scope="module")
def fsae_ramp(fitted, tmp_path_factory):
    """``sim ramp`` of the fitted tyre on the FSAE preset at the default road friction: (exit code, JSON path)."""
    _, _, _, tir = fitted
    js = tmp_path_factory.mktemp("fsae_ramp") / "ramp.json"
    code = main(["sim", "ramp", "--front", str(tir), "--rear", str(tir), "--vehicle", "fsae", "--json", str(js)])
    return code, js


def test_the_written_tyre_keeps_the_contract_over_its_declared_range(fitted):
    _, _, _, tir = fitted
    tyre = read_tyre(tir)
    assert check_tyre(tyre) == []
    lo, hi = tyre.validity()["fz"]
    assert lo < 300 and hi > 1500  # every record's loads, not one record's


def test_eval_compare_and_sim_load_it_without_allow_unphysical(fitted, tmp_path, capsys):
    d, _, _, tir = fitted
    pts = tmp_path / "pts.csv"
    pd.DataFrame({"fz [N]": [250.0, 800.0, 1500.0], "slip_angle [deg]": [3.0, -6.0, 10.0],
                  "slip_ratio [-]": [0.05, -0.08, 0.0], "camber [deg]": [0.0, 2.0, 4.0]}).to_csv(pts, index=False)
    assert main(["eval", str(tir), "--points", str(pts), "--out", str(tmp_path / "f.csv")]) == 0
    out = pd.read_csv(tmp_path / "f.csv")
    assert np.all(np.isfinite(out.filter(like="fy").to_numpy()))
    assert main(["compare", str(tir), str(tir), "--json", str(tmp_path / "c.json")]) == 0
    js = json.loads((tmp_path / "c.json").read_text())
    assert {"fx", "fy", "mz"} <= set(js["channels"])
    # the default vehicle (the paper's 1800 kg car) puts 4.4 kN on each wheel, 2.7 x this FSAE tyre's fitted range,
    # where its friction law is extrapolated: sim refuses in one line naming the range (no traceback)
    capsys.readouterr()
    assert main(["sim", "braking", "--front", str(tir), "--rear", str(tir), "--json", str(tmp_path / "s.json")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "outside its declared load range" in err[0]


def test_sim_runs_the_fsae_tyre_on_the_fsae_preset(fitted, fsae_ramp, tmp_path):
    # the FSAE preset (280 kg, downforce) puts the tyre's own loads on it: braking and the constant-radius ramp run
    _, _, _, tir = fitted
    for scenario in ("braking", "ramp"):
        if scenario == "ramp":  # the same command as braking's, run once for this test and the next (fsae_ramp)
            code, js = fsae_ramp
            assert code == 0
        else:
            js = tmp_path / f"{scenario}.json"
            assert main(["sim", scenario, "--front", str(tir), "--rear", str(tir), "--vehicle", "fsae",
                         "--json", str(js)]) == 0
        out = json.loads(js.read_text())
        assert out["vehicle"]["mass"] == pytest.approx(280.0, rel=0.05)
        assert "outside_envelope" in out["tyres"]["front"]
    assert out["lateral_limit_g"] > 1.5
    # the fitted loads start at 172 N: the inner wheels unload below them before the limit, and the ramp says where
    assert 1.0 < out["envelope_limit_g"] < out["lateral_limit_g"]
    rows = [r for r in out["ramp"] if r["ay_g"] <= out["envelope_limit_g"]]
    lo = json.loads(fsae_ramp[1].read_text())["tyres"]["front"]["ranges"]["fz"][0]
    assert rows and all(min(r[f"fz_{w}_N"] for w in ("fl", "fr", "rl", "rr")) >= lo for r in rows)


def test_fsae_ramp_on_a_track_keeps_every_wheel_inside_the_fitted_loads(fitted, fsae_ramp, tmp_path):
    """Belt-rig grip scaled to a track (road friction 0.7): the whole ramp, to its limit, inside the envelope."""
    _, _, _, tir = fitted
    out = {}
    # road friction 1 is the default: the belt's grip is the fsae_ramp run (no --road-friction), and says so
    code, js = fsae_ramp
    assert code == 0
    out[1.0] = json.loads(js.read_text())
    assert out[1.0]["road_friction"] == 1.0
    for rf in (0.7,):
        js = tmp_path / f"ramp{rf}.json"
        assert main(["sim", "ramp", "--front", str(tir), "--rear", str(tir), "--vehicle", "fsae",
                     "--road-friction", f"{rf:g}", "--json", str(js)]) == 0
        out[rf] = json.loads(js.read_text())
    track = out[0.7]
    assert track["road_friction"] == 0.7
    assert track["tyres"]["front"]["outside_envelope"] == 0.0 and track["tyres"]["rear"]["outside_envelope"] == 0.0
    assert track["envelope_limit_g"] == pytest.approx(track["lateral_limit_g"])
    lo = track["tyres"]["front"]["ranges"]["fz"][0]
    assert min(min(r[f"fz_{w}_N"] for w in ("fl", "fr", "rl", "rr")) for r in track["ramp"]) >= lo
    # grip scales the limit (load transfer shrinks with it, so a little less than in proportion); the linear
    # range, set by the cornering stiffness, does not move
    ratio = track["lateral_limit_g"] / out[1.0]["lateral_limit_g"]
    assert 0.66 < ratio < 0.75
    assert track["understeer_gradient_deg_per_g"] == pytest.approx(out[1.0]["understeer_gradient_deg_per_g"],
                                                                    abs=0.005)


def test_sim_runs_a_fitted_mf_tyre_at_loads_inside_its_range(tmp_path):
    # the bundled TTC-style pair of a 6.75 kN passenger-car tyre: the default vehicle's 4.4 kN is inside its range
    from tyrefit.io.datasets import data_dir

    d = data_dir() / "ttc_mf61"
    tir = tmp_path / "car.tir"
    assert main(["fit", str(d / "cornering.dat"), str(d / "drivebrake.dat"), "--convention", "sae", "--model",
                 "mf61", "--out", str(tir)]) == 0
    assert check_tyre(read_tyre(tir)) == []
    assert main(["sim", "braking", "--front", str(tir), "--rear", str(tir), "--json", str(tmp_path / "s.json")]) == 0
    rows = json.loads((tmp_path / "s.json").read_text())["rows"]
    assert rows and all(r["stopping_distance_m"] > 0 for r in rows)


def test_radius_from_the_free_rolling_record_and_the_disagreement_said(fitted):
    _, _, _, tir = fitted
    text = tir.read_text()
    tyre = read_tyre(tir)
    assert abs(tyre.unloaded_radius - ttc_field.TRUTH["UNLOADED_RADIUS"]) < 0.003, tyre.unloaded_radius
    assert "disagree" in text and "cornering.dat" in text


def test_each_record_is_judged_against_its_own_noise(fitted_result):
    # the fit of both records that the command wrote (the fixture's tyrefit fit)
    (_, corner, drive, _), r = fitted_result
    assert [str(ds.source) for ds in r.datasets] == [str(corner), str(drive)]
    by = r.stats["mz"]["by_record"]
    # the drive/brake rig's Mz is ~10 x noisier than the cornering record's: one pooled floor would hide a
    # cornering misfit of several N*m
    assert by["drivebrake.dat"]["noise_floor"] > 5 * by["cornering.dat"]["noise_floor"]
    assert by["cornering.dat"]["rmse"] < 3 * by["cornering.dat"]["noise_floor"]
    head = "\n".join(r.header())
    assert "MZ on cornering.dat" in head and "MZ on drivebrake.dat" in head


def test_a_drive_brake_record_alone_fits_fx_and_says_why_not_fy(fitted, tmp_path):
    # combined Fy and Mx are evaluated on Fy0, which a drive/brake record (slip angles 0, -3, -6 only) does not
    # give: fitted on a neutral Fy0 they were nonsense (Fy 725 N RMSE, R2 0.46) reported as fitted
    _, _, drive, _ = fitted
    out = tmp_path / "db.tir"
    r = _cli_fit([str(drive), "--convention", "sae", "--model", "mf61", "--out", str(out)])  # the fit it wrote
    assert r.stats["fx"]["fitted"] and not r.stats["fy"]["fitted"] and "Fy" not in r.stages
    assert any(n.startswith("Fy not fitted: it is evaluated on the Fy0 stage") for n in r.notes)
    tyre = read_tyre(out)
    assert tyre.use_mode == 1 and check_tyre(tyre) == []
