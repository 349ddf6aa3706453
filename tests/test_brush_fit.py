"""Fitting the camber brush models (tyrefit.fitting.brush): recovery of known parameters."""

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose

from tyrefit.errors import ColumnError, DataError
from tyrefit.models import brush as bm
from tyrefit.fitting import brush as bf
from tyrefit.synthetic import camber_brush as gen

P = bm.DEFAULT_PARAMS
DEG = np.pi / 180


def _si_patch():
    t = gen.patch_table()
    return pd.DataFrame({"fz": t["fz [N]"], "pressure": t["pressure [kPa]"] * 1e3, "camber": t["camber [deg]"] * DEG,
                         "length": t["length [mm]"] / 1e3, "width": t["width [mm]"] / 1e3})


def test_contact_width_recovery():
    df = _si_patch()
    start = P.replace(b0=0.06, b1=0.3, b2=0.0, b3=0.0)
    r = bf.fit_contact_width(df, start)
    assert r.rmse["width"] < 1e-3  # noise is 0.5 mm
    assert abs(r.params.b0 - P.b0) < 5e-4
    assert abs(r.params.b1 / P.b1 - 1) < 0.15
    assert abs(r.params.b2 - P.b2) < 0.3


def test_contact_width_needs_camber():
    df = _si_patch()
    with pytest.raises(DataError, match="camber"):
        bf.fit_contact_width(df[df["camber"] == 0])
    with pytest.raises(ColumnError, match="width"):
        bf.fit_contact_width(df.drop(columns="width"))


@pytest.mark.parametrize("lam,B", [(0.6, 0.0), (1.5, 0.5), (-0.1, -0.3)])
def test_width_profile_recovery(lam, B):
    rng = np.random.default_rng(5)
    v = np.linspace(-0.95, 0.95, 7)  # seven paths across the patch, as the paper's Fig. 5
    p = 300.0 * bm.width_pressure_shape(v, lam, B) * (1 + 0.005 * rng.standard_normal(v.size))
    lam_f, B_f, dob = bf.fit_width_profile(v, p)
    assert abs(lam_f - lam) < 0.1
    assert abs(B_f - B) < 0.03
    assert_allclose(dob, B_f * (7 + 3 * lam_f) / (7 * (5 + lam_f)))


def test_width_laws_recovery():
    rng = np.random.default_rng(9)
    F, Pr, G = (x.ravel() for x in np.meshgrid([4000.0, 5000.0, 6000.0], [180e3, 240e3, 300e3],
                                                np.deg2rad([0, 2, 4, 6]), indexing="ij"))
    lam = bm.width_concavity(P, F, Pr) + 0.02 * rng.standard_normal(F.size)
    dy = bm.width_bias(P, G) * (1 + 0.02 * rng.standard_normal(F.size))
    r = bf.fit_width_laws(pd.DataFrame({"fz": F, "pressure": Pr, "camber": G, "lambda_y": lam, "delta_y": dy}),
                          P.replace(qy1=0, qy2=0, qy3=0, qy4=1, qy5=2))
    for k in ("qy1", "qy2", "qy3"):
        assert abs(getattr(r.params, k) - getattr(P, k)) < 0.05
    assert abs(r.params.qy4 / P.qy4 - 1) < 0.1
    assert abs(r.params.qy5 - P.qy5) < 0.1


def test_contact_length_recovery():
    df = _si_patch()
    r = bf.fit_contact_length(df, P.replace(a_ref=0.05, a2=0.5, a3=0.2))
    assert r.rmse["length"] < 1e-3
    assert abs(r.params.a_ref / P.a_ref - 1) < 0.02
    assert abs(r.params.a2 - P.a2) < 0.05
    assert abs(r.params.a3 - P.a3) < 0.05


def test_force_fit_recovers_stiffness_shape_and_friction():
    lat = gen.camber_sweep(noise=0.005, seed=21, fz=(3000.0, 6000.0), camber_deg=(-6, 0, 6),
                           slip_angle_deg=np.linspace(-12, 12, 13), n=6)
    start = P.replace(kx=3e7, ky=6e7, qx3=1.0)
    r = bf.fit_brush_forces(lat, start, vary=("ky", "qx3", "mu"), mu=0.7, n=6)
    assert abs(r.params.ky / P.ky - 1) < 0.03
    assert abs(r.mu - 1.0) < 0.02
    assert abs(r.params.qx3 - P.qx3) < 0.15
    assert r.rmse["fy"] < 0.01 * 4500
    kap = np.linspace(-0.3, 0.3, 13)
    f = bm.camber_brush_forces(P, 4500.0, kap, 0.0, 0.0, n=6)
    lon = pd.DataFrame({"fz": 4500.0, "slip_ratio": kap, "fx": f.fx})
    r = bf.fit_brush_forces(lon, P.replace(kx=3e7), vary=("kx",), mu=1.0, n=6)
    assert abs(r.params.kx / P.kx - 1) < 1e-3
    assert "kx" in r.report()


def test_original_model_fit_and_calibration():
    cal = bf.calibrate_original(P, n=6)
    assert cal.rmse["fx"] < 0.005 * 4500 and cal.rmse["fy"] < 0.005 * 4500
    lat = gen.camber_sweep(fz=(4500.0,), camber_deg=(0.0,), slip_angle_deg=np.linspace(-10, 10, 11), n=6)
    r = bf.fit_brush_forces(lat, P.replace(ky=2e7), model="original", vary=("ky",))
    assert r.rmse["fy"] < 0.02 * 4500


def test_shipped_brush_data_read_and_fit():
    """End to end on data/brush: read with read_data, fit the lateral stiffness and friction."""
    from tyrefit.io.datasets import data_path
    from tyrefit.io.readers import read_data

    ds = read_data(data_path("brush", "lateral.csv"))
    assert ds.kind == "slip_angle"
    df = ds.df[ds.df["fz"] < 5000]
    r = bf.fit_brush_forces(df, P.replace(ky=5e7), vary=("ky", "mu"), mu=0.8, n=10)
    assert abs(r.params.ky / P.ky - 1) < 0.03
    assert abs(r.mu - 1.0) < 0.02
