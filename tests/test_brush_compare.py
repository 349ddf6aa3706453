"""Camber brush model vs PAC89 (tyrefit.compare.brush): PAC89-like limits, Eq. 20, the findings, figures."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tyrefit.compare.brush import LATERAL_VARY, compare_brush_pac89
from tyrefit.models import brush as bm
from tyrefit.models import pac89

P = bm.DEFAULT_PARAMS
DEG = np.pi / 180


@pytest.fixture(scope="module")
def cmp():
    return compare_brush_pac89(loads=(3000.0, 4500.0, 6000.0), camber_deg=(-6.0, -3.0, 0.0, 3.0, 6.0), n_slip=33)


def test_grid_and_fit(cmp):
    m = cmp.improved
    assert len(m.data) == 3 * 5 * 33 and m.data["run"].nunique() == 15
    assert set(m.cells["camber_deg"]) == {-6.0, -3.0, 0.0, 3.0, 6.0} and len(m.loads) == 3
    # the data are the camber brush model itself
    row = m.data.iloc[40]
    f = bm.camber_brush_lateral_force(row.fz, row.slip_angle, row.camber, params=P, n=cmp.n)
    assert float(f) == pytest.approx(row.fy, rel=1e-12)
    # the fitted PAC89 is what fy_pac89 holds, with only the lateral coefficients asked for
    assert_allclose(pac89.lateral_force(m.coefficients, m.data.fz, m.data.slip_angle, m.data.camber),
                    m.data.fy_pac89, rtol=1e-12)
    assert all(m.coefficients[k] == 0.0 for k in ("a9", "a10", "a12", "a13"))
    assert set(LATERAL_VARY) <= set(m.coefficients)


def test_pac89_follows_the_brush_where_it_should(cmp):
    """At zero camber and one load the brush curve is a saturating S-curve PAC89 can follow within a few % of
    the peak; the global fit stays within a few % too at the loads near the reference (4821 N)."""
    for mc in cmp.models:
        assert np.all(mc.loads["rmse_single_pct"] < 1.5), mc.model
        zero = mc.cells[mc.cells["camber_deg"] == 0.0]
        assert np.all(zero["rmse_pct"] < 6.0)
        assert zero.loc[zero["fz"] == 4500.0, "rmse_pct"].item() < 3.0
        # mirror symmetry of both models carries over to the fit: odd in (slip, camber) together
        c = mc.cells.set_index(["fz", "camber_deg"])
        for L in (3000.0, 6000.0):
            assert c.loc[(L, 3.0), "fy0_brush_N"] == pytest.approx(-c.loc[(L, -3.0), "fy0_brush_N"], rel=1e-9)
            assert c.loc[(L, 3.0), "fy0_pac89_N"] == pytest.approx(-c.loc[(L, -3.0), "fy0_pac89_N"], rel=1e-9)
    # zero camber: no thrust in either model
    z = cmp.improved.cells[cmp.improved.cells["camber_deg"] == 0.0]
    assert np.all(np.abs(z["fy0_brush_N"]) < 1e-6) and np.all(np.abs(z["fy0_pac89_N"]) < 1e-6)


def test_camber_thrust_numbers_are_eq20_in_the_linear_limit(cmp):
    m = cmp.improved
    # Eq. 20 by hand: 2 a^3 k / (3 Re) summed over the strips at zero camber
    for _, t in m.loads.iterrows():
        st = bm.strip_states(P, t.fz, P.p_ref, 0.0, cmp.n)
        by_hand = np.sum(2 * st.a**3 * st.ky / (3 * st.re))
        assert t.kyg_eq20 == pytest.approx(by_hand, rel=1e-12)
        # the brush's own camber stiffness at zero slip and camber (finite difference) is Eq. 20
        assert t.kyg_brush == pytest.approx(t.kyg_eq20, rel=2e-3)
        # PAC89's camber stiffness (BCD a8 + a11 Fz) is the derivative of its own zero-slip force
        c = m.coefficients
        h = 1e-5
        dfy = -(pac89.lateral_force(c, t.fz, 0.0, h) - pac89.lateral_force(c, t.fz, 0.0, -h)) / (2 * h)
        assert t.kyg_pac89 == pytest.approx(float(dfy), rel=1e-5)
    # at a finite camber, zero slip: no sliding, so the thrust is -sum K_yg,i(gamma) sin(gamma) exactly
    assert_allclose(m.cells["fy0_brush_N"], m.cells["fy0_eq20_N"], rtol=1e-4, atol=1e-9)
    # the original model: one brush at the mean line load, Eq. 20 in closed form at the reference load
    o = compare_brush_pac89(loads=(P.fz_ref, 6000.0), camber_deg=(0.0, 2.0, 4.0), n_slip=25,
                            single_fits=False).original
    k = P.ky * 2 * P.b0
    assert o.loads["kyg_eq20"].iloc[0] == pytest.approx(2 * P.a_ref**3 * k / (3 * P.r_ref), rel=1e-12)
    # its K_yg is a pure power law: a ~ q^a2, Re ~ q^-c3 -> K_yg ~ Fz^(3 a2 + c3)
    assert o.exponent("kyg_eq20") == pytest.approx(3 * P.a2 + P.c3, rel=1e-9)


def test_where_pac89_cannot_follow(cmp):
    m = cmp.improved
    L = m.loads
    # the brush's cornering stiffness grows faster than linearly with load (a ~ q^0.7): Fz^(2 a2)
    assert m.exponent("ky0_brush") == pytest.approx(2 * P.a2, abs=0.05)
    assert m.exponent("kyg_eq20") > 1.9
    # PAC89's sin(2 atan(Fz/a4)) is at most linear: it over-predicts at the lightest load, under at the heaviest
    assert L["ky0_pac89"].iloc[0] > L["ky0_brush"].iloc[0] and L["ky0_pac89"].iloc[-1] < L["ky0_brush"].iloc[-1]
    # and the global fit is worse than a fit per load: the load laws, not the shape, cost the most
    assert m.rmse > 2 * np.sqrt(np.mean(L["rmse_single_N"] ** 2))
    for i in (0, -1):  # the lightest and the heaviest load
        assert L["rmse_N"].iloc[i] > 2 * L["rmse_single_N"].iloc[i]
    # camber at full sliding: the brush's camber effect fades (Eq. 22), PAC89's a11 Fz gamma does not
    c = m.cells[(m.cells["camber_deg"] > 0)]
    assert np.all(np.abs(c["dfy_sat_brush_N"]) < 0.25 * np.abs(c["fy0_brush_N"]))
    top = c[c["fz"] == 6000.0]  # all but sliding at 12 deg: K_y tan(12 deg) ~ 3 mu Fz
    assert np.all(np.abs(top["dfy_sat_brush_N"]) < 0.05 * np.abs(top["fy0_brush_N"]))
    assert np.all(np.abs(top["dfy_sat_pac89_N"]) > 2 * np.abs(top["dfy_sat_brush_N"]))
    # the improved model's cornering stiffness rises with |camber|, evenly; the original's does not change
    i = m.cells.set_index(["fz", "camber_deg"])["ky_brush"]
    assert i[(4500.0, 6.0)] > i[(4500.0, 3.0)] > i[(4500.0, 0.0)]
    assert i[(4500.0, 6.0)] == pytest.approx(i[(4500.0, -6.0)], rel=1e-9)
    o = cmp.original.cells.groupby("fz")["ky_brush"]
    assert np.all(o.max() / o.min() - 1 < 1e-4)
    text = " ".join(cmp.findings())
    for phrase in ("Cornering-stiffness load law", "Curve shape", "Camber stiffness (Eq. 20)",
                   "Cornering stiffness against camber", "Camber at the largest slip", "Original brush"):
        assert phrase in text
    d = cmp.to_dict()
    assert d["improved"]["rmse_N"] == pytest.approx(m.rmse) and len(d["improved"]["cells"]) == 15


def test_figures_and_report_section(cmp, tmp_path):
    import matplotlib.pyplot as plt

    from tyrefit.io.report import Report

    assert cmp.plot_sweeps(6000.0).get_xlabel() == "slip angle [deg]"
    assert cmp.plot_rmse().get_ylabel() == "RMSE [% of peak]"
    assert cmp.plot_camber_thrust().get_xlabel() == "camber [deg]"
    assert cmp.plot_cornering_stiffness().get_yscale() == "log"
    fig, ax = plt.subplots()
    assert cmp.plot_camber_stiffness(ax=ax) is ax
    plt.close("all")
    r = Report("brush vs PAC89")
    assert cmp.report_section(r) is r
    path = r.save(tmp_path)
    html = path.read_text()
    assert "Camber brush model vs PAC89" in html and "Where PAC89 cannot follow" in html
    assert html.count("data:image/png;base64") == 3
