"""tyrefit.compare.tyres and ``tyrefit compare``: per-load metrics, JSON contract, against data."""

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from tyrefit.cli import main
from tyrefit.compare.tyres import binned_curve, compare_tyres, data_metrics, model_metrics
from tyrefit.errors import DataError
from tyrefit.io.readers import Dataset
from tyrefit.io.tir import read_tyre
from tyrefit.tyres.pac89 import Pac89Tyre

REF = Path(__file__).parent / "data" / "ref_adams_pac89_example.tir"
TRUCK = {"a0": 1.4, "a1": -0.8, "a2": 800.0, "a3": 8000.0, "a4": 55.0, "a6": -0.01, "a7": -0.3}


@pytest.fixture(scope="module")
def ref():
    return read_tyre(REF)


@pytest.fixture(scope="module")
def truck():
    return Pac89Tyre(coefficients=TRUCK, ranges={"fz": (10e3, 60e3)}, name="truck")


def _sweeps(tyre, loads, noise=0.0, seed=0, both_signs=False):
    rng = np.random.default_rng(seed)
    rows = []
    a = np.radians(np.arange(-12 if both_signs else 0, 12.001, 0.05))
    for run, fz in enumerate(loads):
        fy = tyre.fy(fz, a) + noise * rng.normal(size=a.size)
        rows.append(pd.DataFrame({"run": run, "fz": fz, "fy": fy, "slip_angle": a}))
    return Dataset(pd.concat(rows, ignore_index=True), kind="slip_angle", source="generated")


@pytest.mark.parametrize("name", ["ref", "truck"])
def test_cornering_stiffness_is_bcd_within_2_percent(name, ref, truck):
    """Must show: compare's cornering stiffness equals PAC89's BCD at each load within 2 %."""
    tyre = {"ref": ref, "truck": truck}[name]
    loads = np.linspace(2e3, 8e3, 7) if name == "ref" else np.linspace(5e3, 60e3, 7)
    cmp = compare_tyres(tyre, tyre, loads=loads)
    for lc in cmp.loads:
        bcd = float(tyre.cornering_stiffness(lc.fz))
        assert lc.cornering_stiffness[0] == pytest.approx(bcd, rel=0.02)
        assert lc.cornering_stiffness[1] == lc.cornering_stiffness[0]


def test_identical_tyres_agree_exactly(truck):
    cmp = compare_tyres(truck, truck)
    assert all(lc.mean_abs_dmu_over_peak == 0.0 and lc.agreement_pct == 100.0 for lc in cmp.loads)
    assert [lc.fz for lc in cmp.loads] == pytest.approx(np.linspace(10e3, 60e3, 5))   # default: fitted range
    assert any("fitted load ranges" in n for n in cmp.notes)


def test_peak_and_slip_at_peak(truck):
    m = model_metrics(truck, 30e3)
    a = np.radians(np.linspace(0, 30, 30001))
    mu = -truck.fy(30e3, a) / 30e3
    assert m["peak_mu"] == pytest.approx(mu.max(), rel=1e-6)
    assert m["slip_at_peak_deg"] == pytest.approx(math.degrees(a[np.argmax(mu)]), abs=0.02)
    assert m["peak_mu"] == pytest.approx((TRUCK["a1"] * 30 + TRUCK["a2"]) / 1000, rel=1e-3)   # D/Fz


def test_different_tyres_score_the_difference(truck):
    softer = Pac89Tyre(coefficients={**TRUCK, "a3": 6000.0}, name="softer")
    cmp = compare_tyres(truck, softer, loads=[30e3])
    lc = cmp.loads[0]
    a = np.radians(np.arange(0, 12.0001, 0.05))
    mua, mub = -truck.fy(30e3, a) / 30e3, -softer.fy(30e3, a) / 30e3
    assert lc.mean_abs_dmu_over_peak == pytest.approx(np.mean(np.abs(mua - mub)) / mua.max(), rel=1e-4)
    assert lc.cornering_stiffness[1] < lc.cornering_stiffness[0]


def test_json_keys_follow_the_contract(truck):
    doc = compare_tyres(truck, truck, loads=[20e3, 40e3]).to_json()
    assert set(doc) >= {"loads"}
    for d in doc["loads"]:
        assert {"fz", "cornering_stiffness", "peak_mu", "slip_at_peak_deg", "mean_abs_dmu_over_peak"} <= set(d)
        for k in ("cornering_stiffness", "peak_mu", "slip_at_peak_deg"):
            assert len(d[k]) == 2
        assert isinstance(d["mean_abs_dmu_over_peak"], float)
    json.dumps(doc)


def test_against_data_from_the_model_itself(truck):
    data = _sweeps(truck, [15e3, 35e3, 55e3], noise=50.0, both_signs=True)
    other = Pac89Tyre(coefficients={**TRUCK, "a2": 700.0}, name="other")
    cmp = compare_tyres(truck, other, data)
    assert [round(lc.fz) for lc in cmp.loads] == [15000, 35000, 55000]
    for lc in cmp.loads:
        va, vb = lc.data["mean_abs_dmu_over_peak_vs_data"]
        assert va < 0.003 < 0.05 < vb
        assert lc.data["cornering_stiffness"] == pytest.approx(truck.cornering_stiffness(lc.fz), rel=0.03)
        assert lc.data["peak_mu"] == pytest.approx(model_metrics(truck, lc.fz)["peak_mu_in_range"], rel=0.02)
    s = cmp.summary()
    assert s["worst_vs_data"][0] < 0.003 and s["min_agreement_with_data_pct"][0] > 99.7


def test_binned_curve_and_data_metrics():
    df = pd.DataFrame({"slip_angle": np.radians([0.1, 0.2, 0.6, 0.7, 13.0]), "fz": 1000.0,
                       "fy": [-10.0, -20.0, -60.0, -70.0, -500.0]})
    c = binned_curve(df)
    assert len(c) == 2 and list(c["n"]) == [2, 2]           # 13 deg is outside 0-12
    assert c["mu"].tolist() == pytest.approx([0.015, 0.065])
    m = data_metrics(df)
    assert m["peak_mu"] == pytest.approx(0.065)


def test_errors(truck):
    with pytest.raises(DataError, match="is a static test"):
        compare_tyres(truck, truck, Dataset(pd.DataFrame({"run": [0], "fz": [1.0], "fy": [1.0],
                                                          "lateral_displacement": [0.0]}), kind="static"))
    with pytest.raises(DataError, match="loads must be positive"):
        compare_tyres(truck, truck, loads=[-1.0])
    with pytest.raises(DataError, match="no sweep has data"):
        compare_tyres(truck, truck, pd.DataFrame({"run": 0, "fz": 1e4, "fy": [0.0], "slip_angle": [0.0]}))


def test_cli_writes_json_and_report(truck, tmp_path, capsys):
    a, b = tmp_path / "a.tir", tmp_path / "b.tir"
    truck.to_tir(a)
    Pac89Tyre(coefficients={**TRUCK, "a3": 7000.0}, ranges={"fz": (10e3, 60e3)}).to_tir(b)
    data = _sweeps(truck, [20e3, 40e3], noise=30.0)
    csv = tmp_path / "d.csv"
    out = data.df.assign(slip_angle=np.degrees(data.df["slip_angle"]))
    out.columns = ["run", "fz [N]", "fy [N]", "slip_angle [deg]"]
    out.to_csv(csv, index=False)
    js, rep = tmp_path / "cmp.json", tmp_path / "rep"
    assert main(["compare", str(a), str(b), "--data", str(csv), "--json", str(js), "--report", str(rep)]) == 0
    doc = json.loads(js.read_text())
    assert len(doc["loads"]) == 2 and doc["loads"][0]["fz"] == pytest.approx(20e3)
    assert "data" in doc["loads"][0] and (rep / "index.html").exists()
    assert "vs data" in capsys.readouterr().out
    # an existing output is not replaced without --force
    assert main(["compare", str(a), str(b), "--json", str(js)]) == 2
    assert "--force" in capsys.readouterr().err
    assert main(["compare", str(a), str(b), "--json", str(js), "--force"]) == 0
    # no output file: the numbers on stdout only
    assert main(["compare", str(a), str(b)]) == 0
    assert "worst mean |dmu|/mu_peak" in capsys.readouterr().out
    # a missing tyre file
    assert main(["compare", str(a), str(tmp_path / "none.tir"), "--json", str(tmp_path / "x.json")]) == 2
    assert not (tmp_path / "x.json").exists()


# ------------------------------------------------------------------------------ each sweep's own conditions
CAMBER_TYRE = {**TRUCK, "a5": 0.01, "a8": 0.05, "a11": 3.0}


def _cambered(tyre, loads, cambers_deg, noise=20.0, seed=1, amp_deg=9.75):
    rng = np.random.default_rng(seed)
    rows, run = [], 0
    a = np.radians(np.arange(-amp_deg, amp_deg + 1e-9, 0.05))
    for c in cambers_deg:
        for fz in loads:
            fzm = fz + rng.normal(0, 50.0, a.size)
            fy = tyre.fy(fzm, a, math.radians(c)) + noise * rng.normal(size=a.size)
            rows.append(pd.DataFrame({"run": run, "fz": fzm, "fy": fy, "slip_angle": a, "camber": math.radians(c)}))
            run += 1
    return Dataset(pd.concat(rows, ignore_index=True), kind="slip_angle", source="cambered")


def test_models_are_evaluated_at_each_sweeps_camber():
    """Must show: compare --data on cambered data agrees with a direct evaluation at each sweep's camber."""
    truth = Pac89Tyre(coefficients=CAMBER_TYRE, name="truth")
    data = _cambered(truth, [20e3, 40e3], [0.0, 2.0, 4.0])
    other = Pac89Tyre(coefficients={**CAMBER_TYRE, "a2": 760.0}, name="other")
    cmp = compare_tyres(truth, other, data)
    assert len(cmp.loads) == 6
    for lc in cmp.loads:
        g = data.df[data.df["run"] == lc.run]
        assert math.degrees(lc.camber) == pytest.approx(math.degrees(g["camber"].mean()), abs=1e-9)
        # the score recomputed by hand: mu of each tyre at every bin's slip, load and camber
        c = binned_curve(g)
        for k, t in enumerate((truth, other)):
            mu = -t.fy(c["fz"].to_numpy(), c["slip_angle"].to_numpy(), c["camber"].to_numpy()) / c["fz"].to_numpy()
            want = np.mean(np.abs(mu - c["mu"].to_numpy())) / np.abs(c["mu"]).max()
            assert lc.data["mean_abs_dmu_over_peak_vs_data"][k] == pytest.approx(want, rel=1e-12)
            # the zero-camber evaluation (the old behaviour) would score the truth far worse on cambered sweeps
            mu0 = -t.fy(c["fz"].to_numpy(), c["slip_angle"].to_numpy(), 0.0) / c["fz"].to_numpy()
            zero = np.mean(np.abs(mu0 - c["mu"].to_numpy())) / np.abs(c["mu"]).max()
            if k == 0 and abs(lc.camber) > 0.01:
                assert lc.data["mean_abs_dmu_over_peak_vs_data"][0] < 0.5 * zero
        assert lc.data["mean_abs_dmu_over_peak_vs_data"][0] < 0.01
        assert lc.cornering_stiffness[0] == pytest.approx(
            (-truth.fy(lc.fz, 1e-4, lc.camber) + truth.fy(lc.fz, -1e-4, lc.camber)) / 2e-4, rel=1e-9)
    titles = [ax.get_title() for ax in cmp.plot_overlay() if ax.get_visible()]
    assert [t.split("\n")[0] for t in titles] == ["camber 0.0°", "camber 2.0°", "camber 4.0°"]
    assert not any("zero camber" in n for n in cmp.notes)


def test_a_peak_outside_the_tested_range_is_not_reached():
    """A soft tyre peaking near 15 deg at 40 kN: sweeps to 9.75 deg cannot show its peak."""
    t = Pac89Tyre(coefficients={**CAMBER_TYRE, "a3": 5000.0}, name="t")
    assert model_metrics(t, 40e3)["slip_at_peak_deg"] > 10.5
    cmp = compare_tyres(t, t, _cambered(t, [40e3], [0.0]))
    lc = cmp.loads[0]
    assert lc.peak_reached == (False, False) and math.isnan(lc.peak_mu[0]) and math.isnan(lc.slip_at_peak_deg[1])
    assert lc.peak_text(0) == "not reached within ±9.8°"
    d = lc.to_dict()
    assert d["peak_reached"] == [False, False] and d["max_mu_in_search"][0] > 0
    assert any("not reached within the tested slip range" in n for n in cmp.notes)
    doc = json.loads(json.dumps(__import__("tyrefit.commands.compare", fromlist=["_clean"])._clean(cmp.to_json())))
    assert doc["loads"][0]["peak_mu"] == [None, None] and doc["loads"][0]["slip_at_peak_deg"] == [None, None]
    # a tyre that peaks inside the range keeps its peak
    m = model_metrics(t, 10e3, max_slip_deg=30)
    assert m["peak_reached"] and 10 < m["slip_at_peak_deg"] < 12


class _PressureTyre:
    """A tyre of another family, through the tyre interface only: PAC89 with grip scaled by pressure."""

    family = "test"

    def __init__(self, coefficients, p0=2.0e5):
        self.base, self.p0 = Pac89Tyre(coefficients=coefficients), p0
        self.name = "pressure-aware"

    def inputs(self):
        return ("fz", "slip_angle", "camber", "pressure")

    def forces(self, fz, slip_angle=0.0, slip_ratio=0.0, camber=0.0, pressure=None, speed=None):
        k = 1.0 if pressure is None else 1.0 - 0.5 * (np.asarray(pressure) / self.p0 - 1.0)
        return {"fy": k * self.base.fy(fz, slip_angle, camber), "fx": np.zeros_like(np.asarray(fz, float)),
                "mz": np.zeros_like(np.asarray(fz, float))}


def test_any_family_through_the_tyre_interface_at_each_sweeps_pressure():
    ptyre = _PressureTyre(CAMBER_TYRE)
    rows = []
    a = np.radians(np.arange(-9.75, 9.76, 0.05))
    for run, (p, fz) in enumerate([(1.8e5, 30e3), (2.2e5, 30e3)]):
        rows.append(pd.DataFrame({"run": run, "fz": fz, "slip_angle": a, "pressure": p, "camber": 0.0,
                                  "fy": ptyre.forces(fz, slip_angle=a, pressure=p)["fy"]}))
    data = Dataset(pd.concat(rows, ignore_index=True), kind="slip_angle", source="pressures")
    pac = Pac89Tyre(coefficients=CAMBER_TYRE, name="pac89")
    cmp = compare_tyres(ptyre, pac, data)
    for lc in cmp.loads:
        va, vb = lc.data["mean_abs_dmu_over_peak_vs_data"]
        assert va < 0.002 and vb > 0.02  # at the sweep's own pressure only binning remains; PAC89 cannot follow
        assert "pressure" in lc.conditions
    assert any("pac89 has no pressure input" in n for n in cmp.notes)


def test_pac89_against_a_magic_formula_file(tmp_path, ref):
    """PAC89 against Chrono's PAC2002 (MF 5.x) HMMWV file through ``tyrefit compare``, on cambered data.

    The data are the MF tyre's own Fy (through the Tyre interface) at 0 and 3 deg camber, so the MF file
    must score ~0 against them at each sweep's camber; the PAC89 reference tyre is another tyre.
    """
    src = Path(__file__).parent / "data" / "ref_HMMWV_Pac02Tire.tir"   # bundled copy: never a skip
    mf = read_tyre(src)
    assert getattr(mf, "family", "") != "PAC89"
    rows, run = [], 0
    a = np.radians(np.arange(-10, 10.001, 0.1))
    for cam in (0.0, 3.0):
        for fz in (3000.0, 6000.0):
            fy = mf.forces(fz, slip_angle=a, camber=math.radians(cam))["fy"]
            rows.append(pd.DataFrame({"run": run, "fz [N]": fz, "slip_angle [deg]": np.degrees(a),
                                      "camber [deg]": cam, "fy [N]": fy}))
            run += 1
    csv = tmp_path / "mf.csv"
    pd.concat(rows).to_csv(csv, index=False)
    a_tir = tmp_path / "ref.tir"
    ref.to_tir(a_tir)
    js = tmp_path / "c.json"
    assert main(["compare", str(src), str(a_tir), "--data", str(csv), "--json", str(js), "--allow-unphysical"]) == 0
    doc = json.loads(js.read_text())
    assert len(doc["loads"]) == 4
    for d in doc["loads"]:
        assert d["data"]["mean_abs_dmu_over_peak_vs_data"][0] < 0.005   # MF at the sweep's own camber
        assert d["data"]["mean_abs_dmu_over_peak_vs_data"][1] > 0.02
        assert np.isfinite(d["cornering_stiffness"][0]) and d["cornering_stiffness"][0] > 0
