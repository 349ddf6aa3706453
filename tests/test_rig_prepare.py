"""prepare_static_fit: static-rig tests -> slip-angle data, stiffnesses and anchors for the PAC89 fit."""

import math
import warnings

import numpy as np
import pytest

from tyrefit.io.datasets import data_path
from tyrefit.errors import DataError
from tyrefit.io.readers import Dataset, read_data
from tyrefit.nomenclature import G0
from tyrefit.io.report import Report
from tyrefit.rig import RigCalibration, RigRangeWarning, prepare_static_fit
from tyrefit.synthetic import truck as T
from tyrefit.tyres.pac89 import Pac89Tyre


def _read(name):
    return read_data(data_path("truck", name))


@pytest.fixture(scope="module")
def files():
    return {k: _read(f"tyre_b_{k}.csv") for k in ("static", "patch", "vertical")}


@pytest.fixture(scope="module")
def rig():
    # the truth's relaxation length ratio, valid up to u = 0.5
    return RigCalibration(n=T.TYRE_B.n_relax, b=0.0, u_range=(0.0, 0.5), fz_range=(5e3, 60e3),
                          pressure_range=(7.4e5, 7.4e5), points=100)


def test_output_is_iso_w_slip_angle_data(files, rig):
    inp = prepare_static_fit(files["static"], files["patch"], rig=rig)
    assert isinstance(inp.data, Dataset) and inp.data.kind == "slip_angle"
    df = inp.data.df
    assert {"run", "fz", "fy", "slip_angle"} <= set(df.columns)
    moving = df["slip_angle"] > math.radians(1)
    assert (df.loc[moving, "fy"] < 0).all()                 # ISO-W: positive slip -> negative Fy
    # the measured, falling load is kept per sample
    static = files["static"].df
    assert set(np.round(df["fz"], 3)) <= set(np.round(static["fz"], 3))


def test_converted_slip_is_the_truth(files, rig):
    """With the true relaxation ratio, Eq. 1 puts every static sample on the rolling tyre's curve."""
    inp = prepare_static_fit(files["static"], files["patch"], rig=rig)
    df = inp.data.df
    mid = (df["slip_angle"] > math.radians(1)) & (df["fz"] > 9e3)
    mu = -df.loc[mid, "fy"] / df.loc[mid, "fz"]
    truth = T.mu_rolling(T.TYRE_B, df.loc[mid, "fz"], df.loc[mid, "slip_angle"])
    assert np.median(np.abs(mu - truth)) < 0.01


def test_uncalibrated_overstates_slip(files, rig):
    with warnings.catch_warnings():
        warnings.simplefilter("error")                       # no range warning without a calibration
        unc = prepare_static_fit(files["static"], files["patch"])
    cal = prepare_static_fit(files["static"], files["patch"], rig=rig)
    ratio = unc.data.df["slip_angle"] / cal.data.df["slip_angle"]
    small = cal.data.df["slip_angle"] > math.radians(0.5)
    assert np.median(ratio[small]) == pytest.approx(T.TYRE_B.n_relax, rel=0.05)
    assert any("uncalibrated" in n for n in unc.notes)


def test_parts_and_anchors(files, rig):
    peak = prepare_static_fit(files["static"], files["patch"], rig=rig, part="peak")
    with pytest.warns(RigRangeWarning):    # the sliding plateau reaches past u = 0.5
        sliding = prepare_static_fit(files["static"], files["patch"], rig=rig, part="sliding")
    assert len(sliding.data.df) == len(files["static"].df) > len(peak.data.df)
    a = peak.anchors
    assert a["a0"] == pytest.approx(T.TYRE_B.a0, abs=0.03)              # Eq. 2 from the sliding level
    # the PAC89 peak law (linear in Fz) through the static peaks: friction falls with load
    assert a["a1"] < 0
    for r in peak.static.runs:
        assert (a["a1"] * r.peak_fz * 1e-3 + a["a2"]) / 1000.0 == pytest.approx(r.max_mu, abs=0.03)
    assert peak.fit_kwargs["fixed"] == a and sliding.anchors == {} and "fixed" not in sliding.fit_kwargs
    with pytest.raises(DataError, match="unknown static part"):
        prepare_static_fit(files["static"], files["patch"], part="top")


def test_stiffnesses_and_tyre_info(files, rig):
    inp = prepare_static_fit(files["static"], files["patch"], rig=rig, vertical_ds=files["vertical"],
                             rated_load=4250 * G0)
    t = T.TYRE_B
    fr = 4250 * G0
    true_cy = T.true_cornering_stiffness(t, fr) / T.relaxation_length(t, fr)
    assert inp.fnomin == fr
    assert inp.lateral_stiffness == pytest.approx(true_cy, rel=0.1)
    s = 1.0  # 7.4 bar is the reference pressure of the vertical truth
    assert t.kv1 * t.unload_ratio * s < inp.vertical_stiffness < t.kv1 * s * 1.02
    info = inp.tyre_info
    assert info["lateral_stiffness"] == inp.lateral_stiffness and info["vertical_curve"] == inp.vertical_curve
    assert any("Eq. 1" in h for h in info["header"])
    bare = Pac89Tyre(coefficients={"a0": 1.3})
    tyre = inp.with_static_design(bare)
    assert tyre.vertical_stiffness == inp.vertical_stiffness and tyre.fnomin == fr
    assert bare.vertical_stiffness is None and bare.fnomin is None  # a copy: the given tyre is not changed


def test_default_fnomin_is_the_shoulder_load(files):
    inp = prepare_static_fit(files["static"], files["patch"])
    assert inp.fnomin == pytest.approx(T.shoulder_load(T.TYRE_B, 7.4), rel=0.05)
    assert any("FNOMIN" in n for n in inp.notes)


def test_leaving_the_calibrated_range_warns(files):
    narrow = RigCalibration(n=2.2, u_range=(0.0, 0.2), fz_range=(20e3, 40e3), pressure_range=(7.4e5, 7.4e5),
                            points=50)
    with pytest.warns(RigRangeWarning) as rec:
        inp = prepare_static_fit(files["static"], files["patch"], rig=narrow)
    text = " ".join(str(w.message) for w in rec)
    assert "beyond the calibrated range 0-0.200" in text and "loads" in text
    assert inp.warnings and any(n.startswith("range warning") for n in inp.notes)


def test_not_static_data_is_refused(files):
    with pytest.raises(DataError, match="is a patch test"):
        prepare_static_fit(files["patch"], files["patch"])


def test_report_section_renders(files, rig, tmp_path):
    inp = prepare_static_fit(files["static"], files["patch"], rig=rig, vertical_ds=files["vertical"])
    r = Report("static")
    inp.report_section(r, model=Pac89Tyre(coefficients={"a0": 1.4, "a2": 800, "a3": 7000, "a4": 50}))
    html = r.html()
    assert "Contact patch" in html and "Vertical stiffness" in html and "Eq. 1" in html
    assert html.count("data:image/png;base64") >= 5
