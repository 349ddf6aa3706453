"""``tyrefit compare`` on every channel both tyres carry (issue 23, item 7): Fx, Fy, Mz, Mx for every family."""

import json
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from tyrefit.cli import main
from tyrefit.compare.tyres import channel_value, compare_tyres, fx_metrics, mz_metrics
from tyrefit.io.readers import Dataset
from tyrefit.io.tir import read_tyre

DATA = Path(__file__).parent / "data"
SIM = Path(__file__).parent.parent / "data" / "sim"
MF61 = DATA / "mfeval_MagicFormula61_Paramerters.tir"
MF52 = DATA / "mfeval_MagicFormula52_Paramerters.tir"
PAC89 = DATA / "ref_adams_pac89_example.tir"
CHRONO89 = DATA / "ref_HMMWV_Pac89Tire.json"
HMMWV02, GENERIC02 = DATA / "ref_HMMWV_Pac02Tire.tir", DATA / "ref_Generic_Pac02Tire.tir"
LOADS = [2e3, 5e3, 8e3]


def _edited(src: Path, tmp_path: Path, key: str, factor: float) -> Path:
    """A copy of a published tyre file with one coefficient scaled by ``factor``."""
    text = src.read_text()
    pat = re.compile(rf"^({re.escape(key)}\s*=\s*)([-+0-9.eE]+)", re.M)
    m = pat.search(text)
    assert m, f"{key} not in {src.name}"
    out = tmp_path / f"{src.stem}_{key}.tir"
    out.write_text(pat.sub(lambda mm: f"{mm.group(1)}{float(mm.group(2)) * factor!r}", text, count=1))
    return out


@pytest.fixture(scope="module")
def mf61():
    return read_tyre(MF61)


@pytest.fixture(scope="module")
def pdx1(tmp_path_factory):
    return read_tyre(_edited(MF61, tmp_path_factory.mktemp("pdx1"), "PDX1", 0.9))


def test_a_perturbed_pdx1_shows_in_fx_peak_mu_and_not_in_fy(mf61, pdx1):
    """PDX1 (peak mu_x) 10 % lower in one copy: the fx channel's peak_mu drops 10 %, fy does not move."""
    same = compare_tyres(mf61, mf61, loads=LOADS)
    cmp = compare_tyres(mf61, pdx1, loads=LOADS)
    assert set(cmp.channels) == {"fx", "fy", "mz", "mx"} and cmp.channels_skipped == {}
    for row, ctrl in zip(cmp.channels["fx"], same.channels["fx"]):
        a, b = row["peak_mu"]
        assert 0.87 < b / a < 0.93                              # peak mu_x follows PDX1 (plus PDX2, SVx terms)
        assert 0.87 < row["peak_mu_braking"][1] / row["peak_mu_braking"][0] < 0.93
        assert row["mean_abs_dmu_over_peak"] > 0.02
        assert ctrl["mean_abs_dmu_over_peak"] == 0.0 and ctrl["peak_mu"][0] == ctrl["peak_mu"][1]
    for row in cmp.channels["fy"]:
        assert row["peak_mu"][0] == row["peak_mu"][1] and row["mean_abs_dmu_over_peak"] == 0.0
        assert row["cornering_stiffness"][0] == row["cornering_stiffness"][1]
    for lc in cmp.loads:                                         # the top-level (lateral) loads[] too
        assert lc.mean_abs_dmu_over_peak == 0.0
    for row in cmp.channels["mz"]:                               # Mz sees Fx only through the small s*Fx term
        assert row["mean_abs_diff_over_peak"] < 1e-3
    for row in cmp.channels["mx"]:
        assert row["mean_abs_diff_over_range"] == 0.0


def test_a_perturbed_qsx3_shows_in_mx_only(mf61, tmp_path):
    other = read_tyre(_edited(MF61, tmp_path, "QSX3", 2.0))
    cmp = compare_tyres(mf61, other, loads=LOADS)
    for ch, key in (("fx", "mean_abs_dmu_over_peak"), ("fy", "mean_abs_dmu_over_peak"),
                    ("mz", "mean_abs_diff_over_peak")):
        assert all(r[key] == 0.0 for r in cmp.channels[ch]), ch
    for r in cmp.channels["mx"]:
        assert r["mean_abs_diff_over_range"] > 0.05
        assert r["overturning_stiffness"][1] != pytest.approx(r["overturning_stiffness"][0], rel=0.05)


def test_a_perturbed_qdz1_shows_in_the_pneumatic_trail(tmp_path):
    """MF 5.2: QDZ1 (peak trail) 20 % up moves the trail at zero slip and peak Mz, not Fy."""
    a, b = read_tyre(MF52), read_tyre(_edited(MF52, tmp_path, "QDZ1", 1.2))
    cmp = compare_tyres(a, b, loads=LOADS)
    for r in cmp.channels["mz"]:
        ta, tb = r["pneumatic_trail_at_zero"]
        assert 0.005 < ta < 0.1 and tb > 1.05 * ta
        assert r["peak_mz"][1] > r["peak_mz"][0] and r["mean_abs_diff_over_peak"] > 0.03
    assert all(r["mean_abs_dmu_over_peak"] == 0.0 for r in cmp.channels["fy"])


def test_trail_and_slip_stiffness_by_definition(mf61):
    fz = 5e3
    m = mz_metrics(mf61, fz)
    h = 1e-3   # another step than the metric's
    dmz = (mf61.mz(fz, h) - mf61.mz(fz, -h)) / (2 * h)
    dfy = (mf61.fy(fz, h) - mf61.fy(fz, -h)) / (2 * h)
    assert m["pneumatic_trail_at_zero"] == pytest.approx(float(-dmz / dfy), rel=1e-3)
    k = np.linspace(0, 0.5, 50001)
    fx = mf61.fx(fz, k)
    f = fx_metrics(mf61, fz)
    assert f["peak_mu"] == pytest.approx(float(fx.max() / fz), rel=1e-5)
    assert f["slip_at_peak"] == pytest.approx(float(k[np.argmax(fx)]), abs=6e-4)


def test_pac89_channels_and_the_missing_mx(tmp_path):
    """PAC89 (Adams example): Fx slip stiffness is 100 BCD (per %), peak mu_x D/Fz; no Mx, said why."""
    a = read_tyre(PAC89)
    b = read_tyre(_edited(PAC89, tmp_path, "b2", 0.95))
    cmp = compare_tyres(a, b, loads=LOADS)
    assert set(cmp.channels) == {"fx", "fy", "mz"}
    assert "PAC89 has no overturning moment" in cmp.channels_skipped["mx"]
    assert any("overturning moment Mx not compared" in n for n in cmp.notes)
    c = a.coefficients
    for r in cmp.channels["fx"]:
        fk = r["fz"] / 1e3
        bcd = (c["b3"] * fk ** 2 + c["b4"] * fk) * math.exp(-c["b5"] * fk)   # N per % slip
        assert r["slip_stiffness"][0] == pytest.approx(100 * bcd, rel=1e-3)
        d = c["b1"] * fk ** 2 + c["b2"] * fk
        assert r["peak_mu"][0] == pytest.approx(d / r["fz"], rel=1e-4)
        assert r["peak_mu"][1] < r["peak_mu"][0]
    for r in cmp.channels["mz"]:
        assert r["mean_abs_diff_over_peak"] == 0.0 and r["peak_mz"][0] > 0


def test_bundled_pac89_tyres_without_mz_and_zero_mx_files():
    cmp = compare_tyres(read_tyre(SIM / "hard_front.tir"), read_tyre(SIM / "soft_rear.tir"))
    assert set(cmp.channels) == {"fx", "fy"}
    assert "aligning block" in cmp.channels_skipped["mz"] and "PAC89" in cmp.channels_skipped["mx"]
    assert all(r["kappa_range"] == [-0.3, 0.3] for r in cmp.channels["fx"])     # the fitted slip-ratio range
    # Chrono's PAC2002 files carry Mx terms that are all zero: not compared, and said so
    cmp = compare_tyres(read_tyre(HMMWV02), read_tyre(GENERIC02), loads=[10e3, 30e3])
    assert set(cmp.channels) == {"fx", "fy", "mz"} and "is zero" in cmp.channels_skipped["mx"]
    # Chrono JSON (PAC89) against the Adams PAC89 example: every PAC89 channel
    cmp = compare_tyres(read_tyre(CHRONO89), read_tyre(PAC89), loads=LOADS)
    assert set(cmp.channels) == {"fx", "fy", "mz"}


def _sweeps(tyre, kind, loads=(3e3, 6e3), cambers=(0.0, 2.0)):
    rows, run = [], 0
    for cam in cambers:
        for fz in loads:
            if kind == "slip_angle":
                a, k = np.radians(np.arange(-10, 10.001, 0.1)), 0.0
            else:
                a, k = math.radians(-3.0 if run % 2 else 0.0), np.arange(-0.25, 0.2501, 0.0025)
            f = tyre.forces(fz, slip_angle=a, slip_ratio=k, camber=math.radians(cam))
            n = np.broadcast_shapes(np.shape(a), np.shape(k))
            rows.append(pd.DataFrame({"run": run, "fz": fz, "slip_angle": np.broadcast_to(a, n),
                                      "slip_ratio": np.broadcast_to(k, n), "camber": math.radians(cam),
                                      **{c: f[c] for c in ("fx", "fy", "mz", "mx")}}))
            run += 1
    return Dataset(pd.concat(rows, ignore_index=True), kind=kind, source=f"{kind} sweeps")


def test_against_slip_angle_data_per_channel(mf61, tmp_path):
    """The data's own tyre scores ~0 on Fy, Mz and Mx; a tyre with other Mz/Mx terms does not."""
    other = read_tyre(_edited(_edited(MF61, tmp_path, "QDZ1", 1.3), tmp_path, "QSX3", 2.0))
    cmp = compare_tyres(mf61, other, _sweeps(mf61, "slip_angle"))
    assert len(cmp.loads) == 4
    for ch in ("mz", "mx"):
        for r in cmp.channels[ch]:
            d = r["data"]
            assert d["rmse"][0] < 1e-6 and d["mean_abs_diff_over_peak_vs_data"][0] < 0.005
            assert d["mean_abs_diff_over_peak_vs_data"][1] > 0.03 and d["unit"] == "N*m"
    for r in cmp.channels["fy"]:
        assert r["data"]["rmse"][0] < 1e-6
    assert all("data" not in r for r in cmp.channels["fx"])   # slip-angle sweeps do not score Fx
    # the data change nothing in the DESIGN contract: loads[] are the lateral channel's
    for d, r in zip(cmp.to_json()["loads"], cmp.channels["fy"]):
        assert d["peak_mu"] == r["peak_mu"] and d["cornering_stiffness"] == r["cornering_stiffness"]


def test_cli_slip_ratio_data_json_and_report(mf61, pdx1, tmp_path, capsys):
    """Drive/brake sweeps (at 0 and -3 deg) score Fx; JSON keeps the contract; one figure per channel."""
    data = _sweeps(mf61, "slip_ratio").df
    csv = tmp_path / "db.csv"
    out = data.assign(slip_angle=np.degrees(data["slip_angle"]), camber=np.degrees(data["camber"]))
    out.columns = [f"{c} [{u}]" if u else c for c, u in zip(out.columns, ["", "N", "deg", "-", "deg", "N", "N",
                                                                         "N*m", "N*m"])]
    out.to_csv(csv, index=False)
    b = _edited(MF61, tmp_path, "PDX1", 0.9)
    js, rep = tmp_path / "c.json", tmp_path / "rep"
    assert main(["compare", str(MF61), str(b), "--data", str(csv), "--json", str(js), "--report", str(rep)]) == 0
    doc = json.loads(js.read_text())
    assert doc["data_kind"] == "slip_ratio" and len(doc["loads"]) == 4
    for d in doc["loads"]:
        assert {"fz", "cornering_stiffness", "peak_mu", "slip_at_peak_deg", "mean_abs_dmu_over_peak"} <= set(d)
    fx = doc["channels"]["fx"]["loads"]
    assert [round(r.get("slip_angle_deg", 0.0)) for r in fx] == [0, -3, 0, -3]
    for r in fx:
        va, vb = r["data"]["mean_abs_diff_over_peak_vs_data"]
        assert va < 0.002 and vb > 0.03 and r["data"]["rmse"][0] < 1e-6
    assert set(doc["channels"]) == {"fx", "fy", "mz", "mx"} and doc["channels_skipped"] == {}
    html = (rep / "index.html").read_text()
    assert html.count("<img") >= 5 and "overturning moment Mx" in html and "http" not in html.split("<body")[0]
    o = capsys.readouterr().out
    assert "  fx: " in o and "vs data RMSE" in o and "  mx: " in o


def test_cli_pac89_names_the_skipped_channel(tmp_path, capsys):
    assert main(["compare", str(PAC89), str(SIM / "hard_front.tir"), "--json", str(tmp_path / "p.json")]) == 0
    doc = json.loads((tmp_path / "p.json").read_text())
    assert set(doc["channels"]) == {"fx", "fy"} and set(doc["channels_skipped"]) == {"mz", "mx"}
    assert "note: aligning moment Mz not compared: hard_front (PAC89)" in capsys.readouterr().out


def test_channel_value_of_an_older_container():
    class Old:
        def fy(self, fz, a, cam=0.0):
            return -1000.0 * np.asarray(a) * np.ones_like(np.asarray(fz, float))

    assert np.isnan(channel_value(Old(), "mx", 1e3, 0.1)).all()
    assert channel_value(Old(), "fy", [1e3, 2e3], 0.1).tolist() == [-100.0, -100.0]
