"""The synthetic hard FSAE-TTC-style pair (tyrefit.synthetic.ttc_field): determinism and layout."""

import math

import numpy as np
import pytest

from tyrefit.io.readers import condition_levels, read_data
from tyrefit.synthetic import ttc_field as tf

_DEG = math.pi / 180.0


@pytest.fixture(scope="module")
def small_pair(tmp_path_factory):
    d = tmp_path_factory.mktemp("ttc_field")
    paths = tf.write_pair(d, scale="small")
    return paths, tf.make_pair(scale="small")


def test_same_seed_same_bytes(small_pair, tmp_path):
    (c, d), _ = small_pair
    c2, d2 = tf.write_pair(tmp_path, scale="small")
    assert c.read_bytes() == c2.read_bytes()
    assert d.read_bytes() == d2.read_bytes()
    other = tf.format_record(tf.make_record("cornering", tf.SEED + 1, "small"), "cornering", tf.SEED + 1, "small")
    assert other.encode() != c.read_bytes()


def test_says_synthetic(small_pair):
    (c, d), _ = small_pair
    for p in (c, d):
        first = p.read_text().splitlines()[0]
        assert first.startswith("SYNTHETIC") and "not a measurement" in first
    assert "Synthetic" in tf.__doc__ or "SYNTHETIC" in tf.__doc__.upper()


def test_layout_cornering(small_pair):
    (c, _), (cdf, _) = small_pair
    sweeps = cdf[cdf["sweep"] >= 0]
    assert sorted(np.round(sweeps["sp_pressure"].unique() / 1e3, 1)) == [55.2, 68.9, 82.7]
    assert sorted(np.round(sweeps["sp_camber"].unique() / _DEG, 3)) == [0.0, 2.0, 4.0]
    assert sweeps["slip_angle"].max() == pytest.approx(12 * _DEG, abs=0.2 * _DEG)
    assert sweeps["slip_angle"].min() == pytest.approx(-12 * _DEG, abs=0.2 * _DEG)
    assert sweeps["sp_fz"].max() > tf.TRUTH["FNOMIN"] * 1.3  # a load above FNOMIN
    ds = read_data(c, convention="sae")
    lv = condition_levels(ds)
    assert len(lv["pressure"]) == 3 and len(lv["camber"]) == 3
    assert ds.df["run"].nunique() == sweeps["sweep"].nunique()
    assert {"mz", "mx"} <= set(ds.df.columns)
    # realistic cornering Mz noise (1-3 N m)
    assert 1.0 < float(np.std(cdf["mz"] - cdf["true_mz"])) < 3.0


def test_layout_drivebrake(small_pair):
    (_, d), (_, ddf) = small_pair
    sweeps = ddf[ddf["sweep"] >= 0]
    assert sorted(np.round(sweeps["sp_slip_angle"].unique() / _DEG, 3)) == [-6.0, -3.0, 0.0]
    ds = read_data(d, convention="sae")
    assert ds.kind == "slip_ratio"
    assert ds.df["run"].nunique() == sweeps["sweep"].nunique()
    assert sorted(np.round(np.unique(np.round(ds.df["slip_angle"] / _DEG)), 0)) == [-6.0, -3.0, 0.0]
    # the drive/brake rig's Mz is much noisier
    assert float(np.std(ddf["mz"] - ddf["true_mz"])) > 12.0


def test_kappa_stops_short_of_the_peak_at_high_load(small_pair):
    _, (_, ddf) = small_pair
    kmax = tf.SCALES["small"]["kappa_max"]
    assert tf.SCALES["full"]["kappa_max"] == kmax
    set_k = np.abs(ddf["slip_ratio"]).max()
    assert set_k < kmax + 0.01  # set range plus noise
    top = max(tf.SCALES["full"]["db_loads"])
    drive, brake = tf.fx_peak_slip(top)
    assert drive > kmax + 0.03 and -brake > kmax + 0.03
    drive, brake = tf.fx_peak_slip(tf.SCALES["full"]["db_loads"][2])  # 1112 N
    assert drive > kmax + 0.015 and -brake > kmax + 0.015
    light = min(tf.SCALES["full"]["db_loads"])
    drive, brake = tf.fx_peak_slip(light)
    assert drive < kmax and -brake < kmax  # only the lightest load reaches its peak


def test_loaded_radius_of_the_records_disagree(small_pair):
    _, (cdf, ddf) = small_pair
    rc = cdf.loc[cdf["fz"] > 150, "loaded_radius"]
    rd = ddf.loc[ddf["fz"] > 150, "loaded_radius"]
    assert rc.max() < rd.min()
    assert 0.195 < rc.min() and rc.max() < 0.21
    assert 0.215 < rd.min() and rd.max() < 0.232


def test_truth_friction_and_scale():
    fz = np.array([222.0, 1112.0, 1557.0])
    a = np.linspace(-20, 20, 801)[:, None] * _DEG
    mu = np.max(np.abs(tf.truth(fz[None, :], slip_angle=a)["fy"]), axis=0) / fz
    assert 2.4 < mu[0] < 2.9 and mu[0] > mu[1] > mu[2] > 2.0
    # thermal grip: a cold tyre grips less
    cold = np.max(np.abs(tf.truth(1112.0, slip_angle=a[:, 0], temperature=30.0)["fy"])) / 1112.0
    assert cold < 0.95 * mu[1]
    c, d = tf.make_pair(scale="full")
    assert 125_000 < len(c) + len(d) < 145_000
