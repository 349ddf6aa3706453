"""Eq. 1 of seed 003 and its calibration on a tyre tested on both rigs."""

import json
import math
import warnings

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tyrefit.io.datasets import data_path
from tyrefit.errors import FitError, FormatError
from tyrefit.io.readers import read_data
from tyrefit.rig.conversion import (UNCALIBRATED, RigCalibration, RigRangeWarning, calibrate, eq1_slip_angle,
                                    fit_dynamic_curves)
from tyrefit.synthetic import truck as T


@pytest.fixture(scope="module")
def tyre_a():
    return (read_data(data_path("truck", "tyre_a_static.csv")), read_data(data_path("truck", "tyre_a_dynamic.csv")),
            read_data(data_path("truck", "tyre_a_patch.csv")))


@pytest.fixture(scope="module")
def cal_a(tyre_a):
    return calibrate(*tyre_a)


def test_uncalibrated_is_eq1_with_f_1():
    u = np.linspace(-2, 2, 41)
    np.testing.assert_allclose(eq1_slip_angle(u), np.arctan(u))
    np.testing.assert_allclose(UNCALIBRATED.f(u), 1.0)
    assert UNCALIBRATED.slip_angle(0.05, 0.2) == pytest.approx(math.atan(0.25))
    assert not UNCALIBRATED.calibrated and UNCALIBRATED.check(u=[10.0]) == []


@given(n=st.floats(0.1, 20), b=st.floats(0, 10))
def test_relaxation_form_is_monotone_bounded_and_odd(n, b):
    u = np.linspace(0, 200, 2001)
    a = eq1_slip_angle(u, n, b)
    assert np.all(np.diff(a) > 0)
    bound = math.atan(1 / (n * b)) if n * b > 0 else math.pi / 2
    assert np.all(a < bound + 1e-12)
    np.testing.assert_allclose(eq1_slip_angle(-u, n, b), -a)
    cal = RigCalibration(n=n, b=b)
    assert cal.max_slip_angle == pytest.approx(bound)
    assert cal.f(0.0) == pytest.approx(1 / n)


def test_calibration_recovers_the_relaxation_length(cal_a):
    """The truth: sigma = n L with n = 2.25 for both tyres; the calibrated f(u) follows atan(u/n)/atan(u)."""
    t = T.TYRE_A
    assert cal_a.n == pytest.approx(t.n_relax, rel=0.05)
    u = np.linspace(0.01, cal_a.u_range[1], 50)
    np.testing.assert_allclose(cal_a.f(u), T.true_f(t, u), rtol=0.05)
    assert cal_a.rmse_mu < 0.01
    assert 0 < cal_a.u_range[0] < 0.02 and 0.25 < cal_a.u_range[1] < 0.45
    assert math.degrees(cal_a.slip_angle_range[1]) <= 12.0 + 1e-9
    # f depends on u only, as Eq. 1 assumes: n alone per load agrees within 5 %
    ns = [d["n_alone"] for d in cal_a.per_load]
    assert max(ns) / min(ns) < 1.05


def test_calibration_transfers_to_tyre_b(cal_a):
    """Calibrated on A, f describes B (same relaxation-length ratio, different tyre)."""
    cal_b = calibrate(read_data(data_path("truck", "tyre_b_static.csv")),
                      read_data(data_path("truck", "tyre_b_dynamic.csv")),
                      read_data(data_path("truck", "tyre_b_patch.csv")))
    u = np.linspace(0.01, 0.3, 30)
    np.testing.assert_allclose(cal_a.f(u), cal_b.f(u), rtol=0.03)


def test_dynamic_curves_fit_the_truth(tyre_a):
    dyn = fit_dynamic_curves(tyre_a[1])
    a = np.radians(np.linspace(0.5, 12, 24))
    for fz in dyn.fz:
        np.testing.assert_allclose(dyn.mu(a, fz), T.mu_rolling(T.TYRE_A, fz, a), atol=0.015)


def test_json_round_trip_and_range(cal_a, tmp_path):
    p = cal_a.to_json(tmp_path / "RIG.json")
    d = json.loads(p.read_text())
    assert d["valid_range"]["u"] == pytest.approx(list(cal_a.u_range))
    assert {"n", "b", "equation", "f", "valid_range", "source"} <= set(d)
    back = RigCalibration.from_json(p)
    assert (back.n, back.b, *back.u_range, *back.fz_range) == pytest.approx(
        (cal_a.n, cal_a.b, *cal_a.u_range, *cal_a.fz_range))
    assert back.calibrated


def test_from_json_errors(tmp_path):
    with pytest.raises(FormatError, match="no such file"):
        RigCalibration.from_json(tmp_path / "none.json")
    (tmp_path / "x.json").write_text("[1, 2]")
    with pytest.raises(FormatError, match="expected a JSON object"):
        RigCalibration.from_json(tmp_path / "x.json")
    (tmp_path / "y.json").write_text('{"n": -1}')
    with pytest.raises(FormatError, match="monotone, bounded"):
        RigCalibration.from_json(tmp_path / "y.json")
    (tmp_path / "z.json").write_text('{"b": 0}')
    with pytest.raises(FormatError, match="needs numeric 'n'"):
        RigCalibration.from_json(tmp_path / "z.json")


def test_range_check_warns(cal_a):
    hi = cal_a.u_range[1]
    assert cal_a.check(u=[0.1, hi]) == []
    with pytest.warns(RigRangeWarning, match="beyond the calibrated range"):
        msgs = cal_a.warn(u=[0.1, 2 * hi])
    assert len(msgs) == 1 and "1 of 2 samples" in msgs[0]
    with pytest.warns(RigRangeWarning, match="pressure"):
        cal_a.warn(pressure=[3e5])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cal_a.warn(u=[0.1], fz=[30e3], pressure=[7.4e5])


def test_no_overlap_is_a_fit_error(tyre_a):
    static, dynamic, patch = tyre_a
    light = static.df[static.df["run"] == 1]          # 500 kg: no dynamic sweep near it
    with pytest.raises(FitError, match="both rigs"):
        calibrate(light, dynamic, patch)
