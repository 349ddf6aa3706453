"""FSAE TTC .dat reader and segmentation of one continuous record into steady sweeps."""

import math
import time

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose

from tyrefit.io.datasets import data_path
from tyrefit.errors import DataError, FormatError, ValueRangeError
from tyrefit.io.readers import condition_levels, lateral_slope, read_data
from tyrefit.io.segment import segment_record
from tyrefit.synthetic.ttc import PROGRAMME, format_ttc, make_record

DEG = math.pi / 180


@pytest.fixture(scope="module")
def record():
    return make_record()


@pytest.fixture(scope="module")
def bundled():
    return read_data(data_path("ttc", "fsae_cornering.dat"), convention="sae")


def test_bundled_file_is_what_the_generator_writes(record):
    df, _ = record
    text = data_path("ttc", "fsae_cornering.dat").read_text()
    assert text == format_ttc(df)
    assert len(text.encode()) < 1.5e6


def test_segmentation_finds_the_generated_sweeps(bundled, record):
    _, truth = record
    seg = bundled.meta["segmentation"]
    assert bundled.kind == "slip_angle" and bundled.meta["format"] == "ttc"
    assert seg["n_sweeps"] == len(truth) == 28 and bundled.n_runs == 28
    # each sweep, in order, at the set points the generator used
    for found, want in zip(seg["sweeps"], truth):
        assert found["fz"] == pytest.approx(want["fz"], rel=0.03)  # load control adds 1 % on average
        assert found["camber_deg"] == pytest.approx(want["camber_deg"], abs=0.1)
        assert found["pressure_kpa"] == pytest.approx(want["pressure_kpa"], abs=2.0)  # warms by <= 1.5 kPa
        assert found["speed_kmh"] == pytest.approx(want["speed_kmh"], abs=0.5)
        lo, hi = found["slip_angle_deg"]
        assert lo < -11.5 and hi > 11.5  # full -12..+12 cycles
    cond = condition_levels(bundled)
    assert_allclose(cond["fz"], sorted(PROGRAMME["loads_N"]), rtol=0.03)
    assert_allclose(cond["camber"], PROGRAMME["cambers_deg"], atol=0.1)
    assert_allclose(cond["pressure"], np.array(sorted(PROGRAMME["pressures_kPa"])) * 1e3, atol=2e3)
    assert_allclose(np.array(cond["speed"]) * 3.6, PROGRAMME["speeds_kmh"], atol=0.5)


def test_segmentation_says_what_it_dropped_and_why(bundled):
    seg = bundled.meta["segmentation"]
    dropped = seg["dropped"]
    assert sum(dropped.values()) + seg["n_kept"] == seg["n_samples"]
    assert any(k.startswith("tyre unloaded") for k in dropped)
    assert any(k.startswith("set-point transition") for k in dropped)
    assert any(k.startswith("warm-up") for k in dropped)
    # the 890 N warm-up is not among the sweeps
    assert all(abs(s["fz"] - PROGRAMME["warmup_load_N"]) > 100 for s in seg["sweeps"])
    assert "histogram" in seg["method"] and seg["window"] == 11


def test_sae_positive_slip_angle_gives_negative_lateral_force(bundled):
    df = bundled.df
    assert (df["fz"] > 0).all()
    assert lateral_slope(bundled) < 0
    pos = df["slip_angle"] > 3 * DEG
    neg = df["slip_angle"] < -3 * DEG
    assert (df.loc[pos, "fy"] < 0).mean() > 0.99 and (df.loc[neg, "fy"] > 0).mean() > 0.99
    # the raw file has the same relation in SAE (SA and FY both negated)
    raw = pd.read_csv(data_path("ttc", "fsae_cornering.dat"), sep="\t", skiprows=[0, 2])
    assert (raw["FZ"] < 50).all() and np.polyfit(raw["SA"][raw["SA"].abs() < 2], raw["FY"][raw["SA"].abs() < 2], 1)[0] < 0


def test_ttc_read_as_iso_says_use_sae():
    with pytest.raises(ValueRangeError, match=r"'FZ \[N\]' is mostly negative.*pass convention=sae"):
        read_data(data_path("ttc", "fsae_cornering.dat"))


def test_us_customary_units(tmp_path, record, bundled):
    df, _ = record
    p = tmp_path / "usc.dat"
    p.write_text(format_ttc(df, units="usc"))
    head = p.read_text().splitlines()[2].split("\t")
    assert {"lb", "psi", "mph", "ft-lb", "in"} <= set(head)
    ds = read_data(p, convention="sae")
    assert ds.n_runs == 28
    assert_allclose(condition_levels(ds)["fz"], condition_levels(bundled)["fz"], rtol=2e-3)
    assert_allclose(condition_levels(ds)["pressure"], condition_levels(bundled)["pressure"], rtol=2e-3)


def test_sr_and_sl_both_present(tmp_path):
    lines = ["info", "ET\tSA\tFY\tFZ\tSR\tSL", "s\tdeg\tN\tN\tnone\tnone"]
    for k, sa in enumerate(np.r_[np.linspace(0, 10, 40), np.linspace(10, -10, 80), np.linspace(-10, 0, 40)]):
        lines.append(f"{k * 0.05:.2f}\t{sa:.3f}\t{-150 * sa:.1f}\t-1000\t0.5\t0.01")
    p = tmp_path / "s.dat"
    p.write_text("\n".join(lines) + "\n")
    ds = read_data(p, convention="sae")
    assert_allclose(ds.df["slip_ratio"], 0.01)
    assert_allclose(ds.df["sr_raw"], 0.5)


def _steady(n_cycles, amp=10.0, n=200):
    a = np.concatenate([np.r_[np.linspace(0, amp, n // 4), np.linspace(amp, -amp, n // 2),
                              np.linspace(-amp, 0, n // 4)] for _ in range(n_cycles)])
    return pd.DataFrame({"slip_angle": np.radians(a), "fz": 1000.0 + 0 * a, "fy": -100 * a},
                        index=np.arange(4, 4 + a.size))


def test_repeated_cycles_in_one_steady_stretch_are_separate_sweeps():
    out, meta = segment_record(_steady(3), "slip_angle")
    assert meta["n_sweeps"] == 3
    assert out.groupby("run").size().between(190, 205).all()


def test_record_without_sweeps(tmp_path):
    df = _steady(1)
    df["slip_angle"] = 0.0
    with pytest.raises(DataError, match=r"no steady slip sweep found in 200 samples; dropped: no slip variation"):
        segment_record(df, "slip_angle", source="x.dat")


def test_ttc_layout_errors(tmp_path):
    p = tmp_path / "short.dat"
    p.write_text("info\nET\tSA\tFY\tFZ\n")
    with pytest.raises(FormatError, match=r"1 line|2 line|needs an info line, a names line and a units line"):
        read_data(p, convention="sae")
    p.write_text("info\nET\tSA\tFY\tFZ\ns\tdeg\tN\tN\n")
    with pytest.raises(DataError, match=r"no data rows after the units line"):
        read_data(p, convention="sae")
    p.write_text("info\nET\tSA\tFY\tFZ\ns\tdeg\tN\tN\n0\t1\tx\t-900\n")
    with pytest.raises(ValueRangeError, match=r"line 4, column 'FY': non-numeric value 'x'"):
        read_data(p, convention="sae")


def test_thousands_of_points_per_sweep_are_cut_quickly():
    df, truth = make_record(rate=100.0)  # ~63 000 samples, ~1600 per sweep
    df.index = np.arange(4, 4 + len(df))
    df = df.assign(fz=df["fz"], slip_angle=df["slip_angle"])
    t0 = time.perf_counter()
    out, meta = segment_record(df, "slip_angle")
    elapsed = time.perf_counter() - t0
    assert meta["n_sweeps"] == len(truth)
    assert out.groupby("run").size().min() > 1400
    assert elapsed < 10.0, elapsed  # vectorised: well under a second on an idle core


def test_drive_brake_record_is_a_slip_ratio_test(tmp_path):
    """TTC drive/brake layout: SA held at 0, -3, -6 deg (SAE) while SL is swept; FX follows SL."""
    lines = ["synthetic drive/brake run", "ET\tV\tSA\tIA\tP\tFX\tFY\tFZ\tSL", "s\tkph\tdeg\tdeg\tkPa\tN\tN\tN\tnone"]
    t = 0.0
    sl = np.r_[np.linspace(0, 0.15, 60), np.linspace(0.15, -0.15, 120), np.linspace(-0.15, 0, 60)]
    for sa in (0.0, -3.0, -6.0):
        for k in range(40):  # ramp the slip angle with the slip ratio at zero
            lines.append(f"{t:.2f}\t40\t{sa * k / 39:.3f}\t0\t83\t0\t{300 * sa * k / 39:.1f}\t-1000\t0")
            t += 0.05
        for x in sl:
            lines.append(f"{t:.2f}\t40\t{sa:.3f}\t0\t83\t{2400 * np.sin(1.6 * np.arctan(12 * x)):.1f}\t{300 * sa:.1f}"
                         f"\t-1000\t{x:.4f}")
            t += 0.05
    p = tmp_path / "db.dat"
    p.write_text("\n".join(lines) + "\n")
    ds = read_data(p, convention="sae")
    assert ds.kind == "slip_ratio" and ds.n_runs == 3
    assert sorted(round(s["fz"]) for s in ds.meta["segmentation"]["sweeps"]) == [1000] * 3
    assert ds.meta["segmentation"]["tolerances"]["slip_angle_deg"] == 0.5
    sa_levels = sorted(round(np.degrees(g["slip_angle"].mean())) for _, g in ds.df.groupby("run"))
    assert sa_levels == [0, 3, 6]  # SAE slip angle negated into ISO-W


def test_logged_csv_record_is_segmented_too(tmp_path, record):
    """The same record as a CSV with unit headers (no run column, a time column): same 28 sweeps."""
    df, truth = record
    sae = df.assign(slip_angle=-np.degrees(df["slip_angle"]), fy=-df["fy"], fz=-df["fz"], mz=-df["mz"],
                    camber=np.degrees(df["camber"]), pressure=df["pressure"] / 1e3, speed=df["speed"] * 3.6)
    cols = {"time": "time [s]", "slip_angle": "slip_angle [deg]", "camber": "camber [deg]",
            "pressure": "pressure [kPa]", "speed": "speed [km/h]", "fx": "fx [N]", "fy": "fy [N]", "fz": "fz [N]",
            "mz": "mz [N*m]"}
    p = tmp_path / "log.csv"
    sae[list(cols)].rename(columns=cols).to_csv(p, index=False, float_format="%.4f")
    ds = read_data(p, convention="sae")
    assert ds.meta["runs"].startswith("segmented") and ds.n_runs == len(truth)
    found = [s["fz"] for s in ds.meta["segmentation"]["sweeps"]]
    assert found == pytest.approx([t["fz"] for t in truth], rel=0.03)
