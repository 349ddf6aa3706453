"""CSV reader: every rig kind, units to SI, runs, sign convention, fit checks."""

import math

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from tyrefit.io.datasets import data_path
from tyrefit.errors import ColumnError, DataError, UnitError
from tyrefit.io.readers import (SAE_FLIPPED, Dataset, check_fittable, condition_levels, detect_kind, lateral_slope,
                                read_data, require_patch)

DEG = math.pi / 180


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


def slip_angle_csv(sae=False):
    """Two loads, two sweeps each 0..8 deg; ISO-W signs unless sae (then fz, fy, sa negated)."""
    s = -1 if sae else 1
    rows = ["# synthetic: test table", "slip_angle [deg],fy [kN],fz [kN],camber [deg],pressure [bar],speed [km/h]"]
    for fz in (3.0, 5.0):
        for a in range(0, 9, 2):
            fy = -0.9 * fz * math.sin(1.4 * math.atan(0.2 * a))
            rows.append(f"{s * a},{s * fy:.4f},{s * fz},1.0,2.2,60")
    return "\n".join(rows) + "\n"


def test_slip_angle_csv_units_kind_and_runs(tmp_path):
    ds = read_data(write(tmp_path, "sa.csv", slip_angle_csv()))
    assert isinstance(ds, Dataset) and ds.kind == "slip_angle" and ds.meta["format"] == "csv"
    df = ds.df
    assert list(df.columns[:1]) == ["run"] and df["run"].dtype.kind == "i"
    assert_allclose(df["slip_angle"].iloc[1], 2 * DEG)
    assert_allclose(df["fz"].unique(), [3000.0, 5000.0])
    assert_allclose(df["camber"].iloc[0], 1 * DEG)
    assert_allclose(df["pressure"].iloc[0], 2.2e5)
    assert_allclose(df["speed"].iloc[0], 60 / 3.6)
    assert_array_equal(df["run"].to_numpy(), [0] * 5 + [1] * 5)
    assert "fz steps" in ds.meta["runs"]
    cond = ds.conditions()
    assert list(cond["n"]) == [5, 5]
    assert_allclose(cond["fz"], [3000, 5000])
    assert ds.meta["columns"]["fy"] == {"header": "fy [kN]", "unit": "kN", "si_unit": "N"}


def test_sae_convention_flips_exactly_the_documented_columns(tmp_path):
    iso = read_data(write(tmp_path, "iso.csv", slip_angle_csv()))
    sae = read_data(write(tmp_path, "sae.csv", slip_angle_csv(sae=True)), convention="sae")
    assert sae.meta["flipped"] == ["fz", "fy", "slip_angle"]
    assert set(sae.meta["flipped"]) <= set(SAE_FLIPPED)
    pd.testing.assert_frame_equal(iso.df, sae.df)
    # positive slip angle -> negative lateral force after reading
    assert lateral_slope(sae) < 0
    pos = sae.df["slip_angle"] > 0
    assert (sae.df.loc[pos, "fy"] < 0).all()


def test_sae_static_flips_displacement_with_force(tmp_path):
    text = "lateral_displacement [mm],fy [N],fz [N],mx [N*m]\n" + "".join(
        f"{-d},{-30 * d},{-5000 + d},{7}\n" for d in range(0, 40, 4))
    ds = read_data(write(tmp_path, "st.csv", text), convention="sae")
    assert ds.kind == "static"
    assert (ds.df["lateral_displacement"] >= 0).all() and (ds.df["fy"] >= 0).all()
    assert (ds.df["fz"] > 0).all()
    assert_allclose(ds.df["mx"], 7.0)  # moment about x: not flipped


def test_static_csv_runs_from_load_and_displacement_restarts(tmp_path):
    rows = ["lateral_displacement [mm];fy [kN];fz [kN];load [kg]"]
    for m in (500, 1100, 2200):
        for d in range(0, 50, 5):
            rows.append(f"{d};{0.7 * m * 9.80665e-3 * math.tanh(d / 15):.3f};{m * 9.80665e-3 * (1 - d / 500):.3f};{m}")
    ds = read_data(write(tmp_path, "static.csv", "\n".join(rows)))
    assert ds.kind == "static" and ds.n_runs == 3
    assert_allclose(condition_levels(ds)["fz"], [500 * 9.80665, 1100 * 9.80665, 2200 * 9.80665], rtol=1e-3)
    assert_allclose(ds.df["load"].iloc[0], 500 * 9.80665)


def test_slip_ratio_csv(tmp_path):
    rows = ["fz [N],slip_ratio [%],fx [N]"]
    for k in range(-20, 21, 5):
        rows.append(f"4000,{k},{4000 * math.sin(1.6 * math.atan(0.15 * k)):.1f}")
    ds = read_data(write(tmp_path, "sr.csv", "\n".join(rows)))
    assert ds.kind == "slip_ratio"
    assert_allclose(ds.df["slip_ratio"].min(), -0.2)
    assert ds.n_runs == 1


def test_combined_file_with_flat_slip_angle_is_a_slip_ratio_test(tmp_path):
    rows = ["fz [N],slip_ratio [-],slip_angle [deg],fx [N],fy [N]"]
    for k in np.linspace(-0.2, 0.2, 11):
        rows.append(f"4000,{k:.3f},0.02,{20000 * k:.1f},3")
    assert read_data(write(tmp_path, "c.csv", "\n".join(rows))).kind == "slip_ratio"


def test_patch_csv_runs_per_pressure(tmp_path):
    rows = ["load [kg],pressure [bar],length [mm],width [mm],area [cm2]"]
    for p in (5.9, 7.4, 9.0):
        for m in (500, 2000, 4000, 6000):
            rows.append(f"{m},{p},{100 + m / 30 - 5 * p:.1f},{200 + m / 100:.1f},{m / 10 / p:.1f}")
    ds = read_data(write(tmp_path, "patch.csv", "\n".join(rows)))
    assert ds.kind == "patch" and ds.n_runs == 3
    assert_allclose(ds.df["area"].iloc[0], 8.5e-4, rtol=1e-12)  # 8.5 cm2 as written
    assert_allclose(condition_levels(ds)["pressure"], [5.9e5, 7.4e5, 9.0e5])


def test_vertical_csv_phase_from_displacement(tmp_path):
    z = list(range(0, 31, 5)) + list(range(25, -1, -5))
    text = "vertical_displacement [mm],fz [kN]\n" + "".join(f"{v},{0.9 * v}\n" for v in z)
    ds = read_data(write(tmp_path, "v.csv", text))
    assert ds.kind == "vertical"
    assert_array_equal(ds.df["phase"].to_numpy(), [1] * 7 + [-1] * 6)
    assert "phase" in ds.meta
    assert ds.df["fz"].iloc[0] == 0.0  # a load cycle may start at zero load


def test_vertical_csv_phase_given_is_kept(tmp_path):
    text = "vertical_displacement [mm],fz [N],phase\n0,0,1\n10,900,1\n10,880,-1\n0,0,-1\n"
    ds = read_data(write(tmp_path, "v.csv", text))
    assert_array_equal(ds.df["phase"], [1, 1, -1, -1])


def test_braking_table_keeps_text_columns(tmp_path):
    text = ("tyre,brand,treadwear,stopping_distance [m],initial_speed [mph]\n"
            "Eco 1,Acme,700,42.1,50\n\"Grip, 2\",Acme,300,36.9,50\n")
    ds = read_data(write(tmp_path, "b.csv", text))
    assert ds.kind == "braking"
    assert list(ds.df["tyre"]) == ["Eco 1", "Grip, 2"]
    assert not pd.api.types.is_numeric_dtype(ds.df["tyre"])
    assert ds.df["treadwear"].dtype == float
    assert_allclose(ds.df["initial_speed"], 50 * 0.44704)


def test_utqg_and_emission_tables(tmp_path):
    u = read_data(write(tmp_path, "u.csv", "tyre,treadwear,traction\nA,400,AA\nB,600,A\n"))
    assert u.kind == "utqg" and list(u.df["traction"]) == ["AA", "A"]
    e = read_data(write(tmp_path, "e.csv", "fx [kN],particles [#/min]\n0.5,60\n1.0,240\n2.0,960\n"))
    assert e.kind == "emission"
    assert_allclose(e.df["fx"], [500, 1000, 2000])
    assert_allclose(e.df["particles"], [1, 4, 16])  # per second


def test_particles_per_km_is_not_read_as_per_second(tmp_path):
    """Issue 15: 'particles [#/km]' was read as particles per second."""
    with pytest.raises(UnitError, match=r"per distance.*speed"):
        read_data(write(tmp_path, "e.csv", "fx [N],particles [#/km]\n500,1e6\n1000,4e6\n2000,1.6e7\n"))
    e = read_data(write(tmp_path, "v.csv", "fx [N],particles [#/km],speed [km/h]\n500,1e6,36\n1000,4e6,72\n"
                                          "2000,1.6e7,36\n"))
    # 1e6 per km at 10 m/s = 1e3 per m * 10 m/s = 1e4 per s
    assert_allclose(e.df["particles"], [1e4, 8e4, 1.6e5])
    with pytest.raises(UnitError, match="is a"):
        read_data(write(tmp_path, "w.csv", "fx [N],particles [N]\n500,1\n1000,4\n2000,16\n"))


def test_given_run_column_and_delimiters(tmp_path):
    text = "run\tslip_angle [rad]\tfy [N]\tfz [N]\n" + "".join(
        f"{r}\t{a / 100}\t{-a * 1000}\t{3000 + 1000 * r}\n" for r in (7, 9) for a in range(5))
    ds = read_data(write(tmp_path, "t.tsv", text))
    assert ds.meta["runs"] == "given in the file"
    assert set(ds.df["run"]) == {7, 9}


def test_kind_forced_and_detect_kind():
    assert detect_kind(["slip_angle", "fy", "fz"]) == "slip_angle"
    assert detect_kind(["length", "load"]) == "patch"
    assert detect_kind(["fy"]) is None


def test_forced_kind_needs_its_columns(tmp_path):
    p = write(tmp_path, "sa.csv", slip_angle_csv())
    with pytest.raises(ColumnError, match=r"missing required columns 'slip_ratio', 'fx' for a slip_ratio test"):
        read_data(p, kind="slip_ratio")


def test_bundled_truck_files_read():
    for name, kind in (("tyre_a_static.csv", "static"), ("tyre_a_dynamic.csv", "slip_angle"),
                       ("tyre_a_patch.csv", "patch"), ("tyre_a_vertical.csv", "vertical")):
        path = data_path("truck", name)  # bundled with the package: missing data is a failure, not a skip
        assert read_data(path).kind == kind


# --------------------------------------------------------------------------- fit checks


def _static(tmp_path):
    rows = ["run,lateral_displacement [mm],fy [N],fz [N]"]
    for r, fz in enumerate((5000, 10000)):
        for d in range(0, 60, 4):
            rows.append(f"{r},{d},{0.7 * fz * math.tanh(d / 20):.1f},{fz - d}")
    return write(tmp_path, "static.csv", "\n".join(rows))


def _patch(tmp_path, lengths=True):
    cols = "load [kg],length [mm]" if lengths else "load [kg],width [mm]"
    return write(tmp_path, "patch.csv", cols + "\n500,120\n1000,160\n2000,230\n")


def test_check_fittable_passes_and_returns_patch(tmp_path):
    ds = read_data(write(tmp_path, "sa.csv", slip_angle_csv()))
    assert check_fittable(ds) is None
    st = read_data(_static(tmp_path))
    pds = check_fittable(st, patch=_patch(tmp_path))
    assert pds.kind == "patch" and "length" in pds.df
    assert require_patch(st, pds) is pds


def test_static_needs_patch_length(tmp_path):
    st = read_data(_static(tmp_path))
    with pytest.raises(DataError, match=r"needs contact-patch data .*Eq. 1.*patch=PATCH.csv"):
        check_fittable(st)
    with pytest.raises(ColumnError, match=r"without a 'length' column"):
        check_fittable(st, patch=_patch(tmp_path, lengths=False))


def test_fast_numeric_path_gives_the_same_dataset_as_the_careful_path(tmp_path, monkeypatch):
    """pandas' tokenizer (all-numeric files) and the csv-module path must agree exactly."""
    import numpy as np

    from tyrefit.io import readers

    rng = np.random.default_rng(1)
    rows = ["# synthetic", "run,fz [kN],slip_angle [deg],fy [N]"]
    for run, fz in enumerate([2.0, 4.0, 6.0]):
        for a in np.linspace(-12, 12, 49):
            fz_m = fz * (1 + 0.001 * rng.standard_normal())
            rows.append(f"{run},{fz_m!r}, {a:.3f} ,{-900 * fz * np.tanh(a / 4) + rng.standard_normal():.6g}")
    p = tmp_path / "sweeps.csv"
    p.write_text("\n".join(rows) + "\n")
    real, used = readers._parse_numeric_fast, []
    monkeypatch.setattr(readers, "_parse_numeric_fast", lambda *a: used.append(real(*a)) or used[-1])
    fast = readers.read_data(p)
    assert used and used[0] is not None  # the fast path did read this file
    monkeypatch.setattr(readers, "_parse_numeric_fast", lambda *a: None)
    slow = readers.read_data(p)
    assert fast.kind == slow.kind == "slip_angle"
    pd.testing.assert_frame_equal(fast.df, slow.df, check_exact=True)
