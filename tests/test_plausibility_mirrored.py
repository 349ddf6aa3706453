"""Mirrored tyres are caught in fit and inspect (issue 25): camber thrust of the wrong sign, a
negative pneumatic trail over most loads, Fx falling with slip ratio; --allow-mirrored overrides."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pandas as pd
import pytest

from tyrefit.cli import main
from tyrefit.errors import ValueRangeError
from tyrefit.io.plausibility import check_mirrored, mirrored_findings
from tyrefit.io.readers import read_data

ROOT = Path(__file__).resolve().parents[1]
PASSENGER = ROOT / "data" / "passenger" / "passenger_205_55R16.csv"
TTC = ROOT / "data" / "ttc" / "fsae_cornering.dat"
SLIP = ROOT / "data" / "slip" / "slip_ratio.csv"


@pytest.fixture(scope="module")
def camber_negated(tmp_path_factory):
    df = pd.read_csv(PASSENGER, comment="#")
    df["camber [deg]"] = -df["camber [deg]"]
    p = tmp_path_factory.mktemp("mirror") / "camber_negated.csv"
    df.to_csv(p, index=False)
    return p


@pytest.fixture(scope="module")
def mz_negated(tmp_path_factory):
    raw = TTC.read_text().splitlines()
    j = raw[1].split("\t").index("MZ")
    out = raw[:3]
    for line in raw[3:]:
        v = line.split("\t")
        v[j] = repr(-float(v[j]))
        out.append("\t".join(v))
    p = tmp_path_factory.mktemp("mirror") / "mz_negated.dat"
    p.write_text("\n".join(out) + "\n")
    return p


def test_bundled_files_are_not_mirrored():
    assert mirrored_findings(read_data(PASSENGER)) == []
    assert mirrored_findings(read_data(TTC, convention="sae")) == []
    assert mirrored_findings(read_data(SLIP)) == []


def test_camber_negated_refused_by_fit_and_flagged_by_inspect(camber_negated, tmp_path, capsys):
    (f,) = mirrored_findings(read_data(camber_negated))
    assert f.check == "camber_thrust" and "+3 deg" in f.message
    assert main(["fit", str(camber_negated), "--out", str(tmp_path / "t.tir")]) == 2
    err = capsys.readouterr().err
    assert "camber thrust of the wrong sign" in err and "--allow-mirrored" in err and len(err.splitlines()) == 1
    assert not (tmp_path / "t.tir").exists()
    assert main(["fit", str(camber_negated), "--out", str(tmp_path / "t.tir"), "--model", "mf61"]) == 2
    assert "camber thrust" in capsys.readouterr().err
    assert main(["inspect", str(camber_negated)]) == 0
    assert "PROBLEM" in capsys.readouterr().out
    assert main(["inspect", str(camber_negated), "--allow-mirrored"]) == 0
    out = capsys.readouterr().out
    assert "WARNING (--allow-mirrored)" in out and "PROBLEM" not in out


def test_allow_mirrored_fits_and_warns(camber_negated, tmp_path, capsys):
    assert main(["fit", str(camber_negated), "--out", str(tmp_path / "t.tir"), "--allow-mirrored"]) == 0
    assert "WARNING (--allow-mirrored): " in capsys.readouterr().out and (tmp_path / "t.tir").exists()


def test_mz_negated_ttc_refused(mz_negated, tmp_path, capsys):
    found = mirrored_findings(read_data(mz_negated, convention="sae"))
    assert [f.check for f in found] == ["pneumatic_trail"]
    assert main(["fit", str(mz_negated), "--convention", "sae", "--out", str(tmp_path / "t.tir")]) == 2
    assert "negative pneumatic trail" in capsys.readouterr().err


def test_fx_against_slip_ratio_of_the_wrong_sign():
    ds = read_data(SLIP)
    d = ds.df.copy()
    d["fx"] = -d["fx"]
    bad = dataclasses.replace(ds, df=d)
    (f,) = mirrored_findings(bad)
    assert f.check == "fx_slip" and "falls with slip ratio" in f.message
    with pytest.raises(ValueRangeError, match="allow_mirrored=True"):
        check_mirrored(bad)
    assert check_mirrored(bad, allow=True) == [f.message]
