"""Diagnose's "past the peak" advice comes from the data, not from the model (issue 24).

Where the measured sweeps rise to a force peak and fall past it, the peak is measured, whatever the
fitted model does; a model whose own peak lies far beyond it is the model's error, and no test is asked
for.  The sweeps here are drawn from a Magic Formula curve written out in this file (Pacejka 2012,
(4.E8)-style sine of an arctangent), not from tyrefit's models.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from tyrefit.diagnose.advice import _test, measured_peak, peak_reach
from tyrefit.diagnose.data import prepare

DEG = np.pi / 180.0


def mf_curve(alpha, fz, mu=1.6, c=2.0, e=0.2, ky_per_fz=30.0):
    """Lateral force [N] (ISO-W) of a Magic Formula curve with peak mu * fz, shape C, curvature E."""
    d = mu * fz
    b = ky_per_fz * fz / (c * d)
    x = b * alpha
    return -d * np.sin(c * np.arctan(x - e * (x - np.arctan(x))))


def peak_slip_deg(fz, **kw):
    a = np.linspace(0, 30, 30001) * DEG
    return float(np.degrees(a[np.argmax(np.abs(mf_curve(a, fz, **kw)))]))


@pytest.mark.parametrize("sigma", [5.0, 20.0])
def test_a_sweep_through_its_peak_is_seen_to_peak(sigma):
    rng = np.random.default_rng(1)
    fz = 800.0
    a = np.linspace(-12, 12, 241) * DEG
    f = mf_curve(a, fz) + rng.normal(0, sigma, a.size)
    for side in (1, -1):
        on = np.sign(a) == side
        r = measured_peak(a[on], f[on])
        assert r["peaked"] and r["peak_deg"] == pytest.approx(peak_slip_deg(fz), abs=1.0)
        assert r["drop"] > 0.05


def test_a_sweep_short_of_its_peak_and_a_plateau_are_not_peaks():
    rng = np.random.default_rng(2)
    fz = 800.0
    short = np.linspace(0, 0.6 * peak_slip_deg(fz), 120) * DEG
    assert not measured_peak(short, mf_curve(short, fz) + rng.normal(0, 5, short.size))["peaked"]
    a = np.linspace(0, 15, 200) * DEG       # a brush-like curve: rises, then slides at constant force
    plateau = -1200 * np.minimum(a / (5 * DEG), 1.0) + rng.normal(0, 5, a.size)
    assert not measured_peak(a, plateau)["peaked"]
    # a fall smaller than the noise can show is not called a peak
    noisy = mf_curve(a, fz, e=0.9) + rng.normal(0, 400, a.size)
    assert not measured_peak(a, noisy)["peaked"]


class _RisingModel:
    """A fitted model that never peaks (linear in slip): its peak is far beyond every sweep."""

    def predict(self, theta, inputs):
        return -20000.0 * inputs.slip_angle * inputs.fz / 1000.0


def _sweeps(reach_deg):
    rng = np.random.default_rng(3)
    rows = []
    run = 0
    for fz in (300.0, 700.0, 1100.0):
        a = np.linspace(-reach_deg, reach_deg, 121) * DEG
        f = mf_curve(a, fz) + rng.normal(0, 8, a.size)
        rows.append(pd.DataFrame({"fy": f, "slip_angle": a, "fz": fz, "run": run}))
        run += 1
    return prepare(pd.concat(rows, ignore_index=True))


def test_peaks_measured_in_the_data_ask_for_no_test_and_blame_the_model():
    data = _sweeps(12.0)
    peaks = peak_reach(_RisingModel(), None, data)
    assert all(p["data_peaked"] and p["reached"] and p["model_misses_peak"] for p in peaks)
    for p in peaks:
        assert p["data_peak_deg"] == pytest.approx(peak_slip_deg(p["fz_N"]), abs=1.0)
    advice = _test("load_friction", data, [], "not detected", peaks)
    assert "past the force peak" not in advice


def test_sweeps_that_stop_short_still_get_the_past_the_peak_advice():
    data = _sweeps(3.0)
    peaks = peak_reach(_RisingModel(), None, data)
    assert not any(p["data_peaked"] or p["reached"] for p in peaks)
    assert "past the force peak" in _test("load_friction", data, [], "not detected", peaks)
