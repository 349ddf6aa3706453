"""``tyrefit eval TYRE --points POINTS.csv --out FORCES.csv`` for every family.

The written forces are compared with the model functions called directly in SI
(PAC89: ``tyrefit.models.pac89``; MF: ``tyrefit.models.mf61``), so the test
checks the CLI's unit handling, defaults and column layout; the models'
own references live in ``test_pac89.py`` and ``test_mf61_model.py``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from tyrefit.cli import main
from tyrefit.io.tir import read_tyre
from tyrefit.models import mf61, pac89

DATA = Path(__file__).parent / "data"
PAC89 = DATA / "ref_adams_pac89_example.tir"
PAC02 = DATA / "ref_Generic_Pac02Tire.tir"
JSON = DATA / "ref_HMMWV_Pac89Tire.json"


def _points(tmp_path, text, name="pts.csv") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def _err_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


def test_eval_pac89_units_and_columns(tmp_path):
    pts = _points(tmp_path, "fz [kN],slip_angle [deg],slip_ratio [%],camber [deg]\n"
                            "4,0,0,0\n4,5,0,0\n6,-3,5,1\n2.5,12,-10,-2\n")
    out = tmp_path / "f.csv"
    assert main(["eval", str(PAC89), "--points", str(pts), "--out", str(out)]) == 0
    df = pd.read_csv(out)
    assert list(df.columns) == ["fz [kN]", "slip_angle [deg]", "slip_ratio [%]", "camber [deg]",
                                "fx [N]", "fy [N]", "mz [N*m]"]
    t = read_tyre(PAC89)
    fz = df["fz [kN]"].to_numpy() * 1e3
    sa, cam = np.radians(df["slip_angle [deg]"].to_numpy()), np.radians(df["camber [deg]"].to_numpy())
    sr = df["slip_ratio [%]"].to_numpy() / 100
    np.testing.assert_allclose(df["fy [N]"], pac89.lateral_force(t.coefficients, fz, sa, cam), rtol=1e-9)
    np.testing.assert_allclose(df["fx [N]"], pac89.longitudinal_force(t.coefficients, fz, sr), rtol=1e-9)
    np.testing.assert_allclose(df["mz [N*m]"], pac89.aligning_moment(t.coefficients, fz, sa, cam), rtol=1e-9,
                               atol=1e-9)
    assert df["fy [N]"][1] < 0  # ISO-W


def test_eval_mf_defaults_and_combined_slip(tmp_path, capsys):
    pts = _points(tmp_path, "fz [N],slip_angle [rad],slip_ratio [-]\n30000,0.05,0\n30000,0.05,-0.1\n"
                            "20000,-0.1,0.08\n")
    out = tmp_path / "f.csv"
    assert main(["eval", str(PAC02), "--points", str(pts), "--out", str(out)]) == 0
    df = pd.read_csv(out)
    assert {"fx [N]", "fy [N]", "mz [N*m]", "mx [N*m]", "my [N*m]"} <= set(df.columns)
    t = read_tyre(PAC02)
    ref = mf61.forces(t.params, df["fz [N]"].to_numpy(), slip_ratio=df["slip_ratio [-]"].to_numpy(),
                      slip_angle=df["slip_angle [rad]"].to_numpy(), camber=0.0, speed=16.7, version="5.2")
    for k, h in (("fx", "fx [N]"), ("fy", "fy [N]"), ("mz", "mz [N*m]"), ("mx", "mx [N*m]"), ("my", "my [N*m]")):
        np.testing.assert_allclose(df[h], ref[k], rtol=1e-9, atol=1e-6)
    # combined slip: braking at the same slip angle lowers |Fy|
    assert abs(df["fy [N]"][1]) < abs(df["fy [N]"][0])


def test_eval_speed_and_pressure_columns_reach_the_model(tmp_path):
    pts = _points(tmp_path, "fz [N],slip_angle [deg],speed [km/h],pressure [bar]\n30000,4,20,8\n30000,4,90,8\n")
    out = tmp_path / "f.csv"
    assert main(["eval", str(PAC02), "--points", str(pts), "--out", str(out)]) == 0
    df = pd.read_csv(out)
    t = read_tyre(PAC02)
    ref = mf61.forces(t.params, 30000.0, slip_angle=math.radians(4), speed=np.array([20, 90]) / 3.6,
                      version="5.2")
    np.testing.assert_allclose(df["my [N*m]"], ref["my"], rtol=1e-9)


def test_eval_chrono_json(tmp_path):
    pts = _points(tmp_path, "fz [N],slip_angle [deg]\n5000,3\n")
    out = tmp_path / "f.csv"
    assert main(["eval", str(JSON), "--points", str(pts), "--out", str(out)]) == 0
    assert pd.read_csv(out)["fy [N]"][0] < 0


def test_eval_refuses_unphysical_unless_allowed(tmp_path, capsys):
    bad = tmp_path / "bad.tir"
    bad.write_text(PAC89.read_text().replace("a4  = 12.8", "a4  = 0.0").replace("a4 = 12.8", "a4 = 0.0"))
    assert "0.0" in bad.read_text()
    pts = _points(tmp_path, "fz [N],slip_angle [deg]\n4000,3\n")
    out = tmp_path / "f.csv"
    assert main(["eval", str(bad), "--points", str(pts), "--out", str(out)]) == 2
    assert "a4 = 0" in _err_line(capsys) and not out.exists()
    assert main(["eval", str(bad), "--points", str(pts), "--out", str(out), "--allow-unphysical"]) == 0
    assert "warning (--allow-unphysical)" in capsys.readouterr().out


@pytest.mark.parametrize("text,match", [
    ("slip_angle [deg]\n3\n", "no 'fz"),
    ("fz [N],camber [deg]\n3000,1\n", "no 'slip_angle"),
    ("fz [N],slip_angle [furlong]\n3000,1\n", "unknown unit"),
    ("fz [N],slip_angle [deg]\n3000,abc\n", "line 2"),
    ("fz [N],slip_angle [deg]\n", "no data rows"),
])
def test_eval_bad_points_one_line(tmp_path, capsys, text, match):
    pts = _points(tmp_path, text)
    out = tmp_path / "f.csv"
    assert main(["eval", str(PAC89), "--points", str(pts), "--out", str(out)]) == 2
    assert match in _err_line(capsys)
    assert not out.exists()


def test_eval_output_may_not_be_an_input_or_exist(tmp_path, capsys):
    pts = _points(tmp_path, "fz [N],slip_angle [deg]\n4000,3\n")
    assert main(["eval", str(PAC89), "--points", str(pts), "--out", str(pts), "--force"]) == 2
    assert "input" in _err_line(capsys)
    assert pts.read_text() == "fz [N],slip_angle [deg]\n4000,3\n"
    out = tmp_path / "f.csv"
    out.write_text("keep")
    assert main(["eval", str(PAC89), "--points", str(pts), "--out", str(out)]) == 2
    assert out.read_text() == "keep"


def test_eval_lateral_only_tyre_leaves_fx_empty(tmp_path, capsys):
    t = read_tyre(PAC89)
    for k in pac89.LONGITUDINAL:
        t.coefficients[k] = 0.0
    tir = tmp_path / "lat.tir"
    t.to_tir(tir)
    pts = _points(tmp_path, "fz [N],slip_angle [deg],slip_ratio [-]\n4000,3,0.1\n")
    out = tmp_path / "f.csv"
    assert main(["eval", str(tir), "--points", str(pts), "--out", str(out)]) == 0
    df = pd.read_csv(out)
    assert np.isnan(df["fx [N]"][0]) and np.isfinite(df["fy [N]"][0])
    assert "no longitudinal model" in capsys.readouterr().out


@pytest.mark.parametrize("text,match", [
    ("fz [N],slip_angle [deg]\nnan,3\n", "'fz \\[N\\]': nan is not finite"),
    ("fz [N],slip_angle [deg]\n4000,inf\n", "inf is not finite"),
    ("fz [N],slip_angle [deg]\n4000,95\n4000,-180\n", "95 is outside -90..90 deg .* \\(2 such rows\\)"),
    ("fz [N],slip_ratio [-]\n4000,-1.5\n", "outside -1"),
    ("fz [N],slip_angle [deg],speed [km/h]\n4000,1,-20\n", "forward speeds"),
    ("fz [N],slip_angle [deg],pressure [bar]\n4000,1,0\n", "positive pressures"),
])
def test_eval_points_outside_their_domain(tmp_path, capsys, text, match):
    import re

    pts = _points(tmp_path, text)
    out = tmp_path / "f.csv"
    assert main(["eval", str(PAC02), "--points", str(pts), "--out", str(out)]) == 2
    assert re.search(match, _err_line(capsys))
    assert not out.exists()


def test_eval_wheel_off_the_ground_gives_zero(tmp_path):
    pts = _points(tmp_path, "fz [N],slip_angle [deg]\n-500,3\n0,3\n")
    out = tmp_path / "f.csv"
    assert main(["eval", str(PAC02), "--points", str(pts), "--out", str(out)]) == 0
    df = pd.read_csv(out)
    assert (df[["fx [N]", "fy [N]", "mz [N*m]", "mx [N*m]", "my [N*m]"]].to_numpy() == 0).all()
