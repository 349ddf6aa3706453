"""Slippage laws of seed 002 (tyrefit.models.slip) and their fits (tyrefit.fitting.slip)."""

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose

from tyrefit.errors import ColumnError, DataError
from tyrefit.models import slip as sl
from tyrefit.fitting.slip import analyse_slip, fit_friction_slip, fit_rolling_radius, load_groups
from tyrefit.synthetic import slip as gen


# --- pure laws ---------------------------------------------------------------------------
def test_friction_law_limits_and_oddness():
    s = np.linspace(-1, 1, 201)
    mu = sl.friction(s, 0.9, 20.0)
    assert_allclose(mu, -mu[::-1], atol=1e-15)
    assert sl.friction(0.0, 0.9, 20.0) == 0.0
    assert_allclose(sl.friction(5.0, 0.9, 20.0), 0.9, rtol=1e-12)
    h = 1e-6
    assert_allclose((sl.friction(h, 0.9, 20.0) - 0) / h, 0.9 * 20.0, rtol=1e-4)  # slope mu_p k at 0


@pytest.mark.parametrize("mu_p,k", [(0.9, 20.0), (0.6, 8.0), (1.1, 35.0), (0.3, 5.0)])
def test_characteristic_slip_is_where_numerical_curvature_meets_nu_c(mu_p, k):
    """Eq. 16 against the slip where the finite-difference curvature of Eq. 8 equals nu_c = -2."""
    s = np.linspace(1e-4, 1.5, 300001)
    mu = sl.friction(s, mu_p, k)
    curv = np.gradient(np.gradient(mu, s), s)  # numerical d2mu/ds2, not Eq. 15
    inner = slice(5, -5)
    assert_allclose(curv[inner], sl.curvature(s, mu_p, k)[inner], rtol=1e-4, atol=1e-4)
    i = np.flatnonzero(np.diff(np.sign(curv[inner] + 2.0)))[0] + 5
    s_num = s[i] + (s[i + 1] - s[i]) * (-2.0 - curv[i]) / (curv[i + 1] - curv[i])
    sc = sl.characteristic_slip(mu_p, k)
    assert_allclose(sc, s_num, atol=1e-5)
    assert_allclose(sl.characteristic_mu(mu_p, k), mu_p - 2.0 / k**2, rtol=1e-12)  # Eq. 17
    assert_allclose(sl.characteristic_mu(mu_p, k), sl.friction(sc, mu_p, k), rtol=1e-12)


def test_characteristic_slip_edge_cases():
    # curvature already flatter than nu_c at s = 0: s_c = 0 and mu_c = 0
    assert sl.characteristic_slip(0.5, 1.5) == 0.0
    assert sl.characteristic_mu(0.5, 1.5) == 0.0
    with pytest.raises(ValueError, match="negative"):
        sl.characteristic_slip(0.9, 20.0, nu_c=0.5)
    # vectorised
    out = sl.characteristic_slip(np.array([0.9, 0.5]), np.array([20.0, 1.5]))
    assert out.shape == (2,) and out[1] == 0 and out[0] > 0
    # a stiffer curve reaches its characteristic slip sooner (seed 002 Fig. 5: blue ~0.2 vs red ~0.45)
    assert sl.characteristic_slip(0.9, 30.0) < sl.characteristic_slip(0.9, 10.0)


def test_mobility_indices():
    mu_p, k = 0.9, 20.0
    s = np.linspace(0, 1, 20001)
    mu = sl.friction(s, mu_p, k)
    assert_allclose(sl.mobility_index(mu, mu_p), 1 - mu / mu_p)  # Eq. 24
    wmai = sl.mobility_agility_index(s, mu_p, k)  # Eq. 26
    i = np.argmax(wmai)
    assert_allclose(wmai[i], mu_p / 4, rtol=1e-6)  # max of mu (1 - mu/mu_p) at mu = mu_p / 2
    assert_allclose(mu[i], mu_p / 2, rtol=1e-3)
    sc = sl.characteristic_slip(mu_p, k)
    mod = sl.modified_mobility_index(s, mu_p, k)  # Eq. 25
    assert np.all(mod[s > sc] == 0)
    assert_allclose(mod[0], 1.0)
    assert np.all(mod[s <= sc] >= -1e-12)
    mwmai = sl.modified_mobility_agility_index(s, mu_p, k)  # Eq. 27
    assert np.all(mwmai[s > sc] == 0)
    assert_allclose(mwmai.max(), sl.characteristic_mu(mu_p, k) / 4, rtol=1e-6)


def test_slip_kinematics_and_rolling_radius():
    r0 = 0.3
    assert_allclose(sl.slippage(9.0, 10.0 / r0, r0), 0.1)  # Eq. 7
    # Eq. 9 equals the time derivative of Eq. 7
    t = np.linspace(0, 1, 10001)
    om = 30 + 10 * t**2
    vx = 8 + np.sin(t)
    s = sl.slippage(vx, om, r0)
    rate = sl.slip_rate(om, np.gradient(om, t), vx, np.gradient(vx, t), r0)
    assert_allclose(rate[5:-5], np.gradient(s, t)[5:-5], rtol=1e-5, atol=1e-8)
    # Eq. 14: at constant vx the slip is 1 - kappa / omega
    assert_allclose(sl.critical_slip(om, 8.0, r0), sl.slippage(8.0, om, r0))
    # Eq. 19-20 round trip
    lam = 2e-5
    T = np.array([100.0, 500.0])
    r = sl.rolling_radius(T, r0, lam)
    assert_allclose(sl.elasticity_factor(r0, radius=r, torque=T), lam)
    assert_allclose(sl.elasticity_factor(r0, slip=(r0 - r) / r0, torque=T), lam)
    assert np.isnan(sl.elasticity_factor(r0, radius=[r0], torque=[0.0]))[0]
    # Eq. 21 and 23: the tracking torque rate makes e_dot = -K e
    lam_rate, Tq, s_ref, s_ref_rate, K = 1e-6, 300.0, 0.1, 0.0, 5.0
    Tdot = sl.slip_tracking_torque_rate(r0, lam, lam_rate, Tq, s_ref, s_ref_rate, K)
    s_now = lam * Tq / r0
    s_dot = (lam * Tdot + Tq * lam_rate) / r0  # Eq. 21
    assert_allclose(s_dot - s_ref_rate, -K * (s_now - s_ref), rtol=1e-12)


# --- fits -------------------------------------------------------------------------------
def test_fit_recovers_generated_law_per_load():
    """Must show: mu_p within 3 % and k within 5 % on generated data (here far tighter)."""
    df = gen.slip_ratio_table()
    df = df.rename(columns={"load [kN]": "load", "speed [km/h]": "speed", "slip_ratio [-]": "slip_ratio",
                            "fz [N]": "fz", "fx [N]": "fx"})
    df["load"] *= 1e3
    a = analyse_slip(df)
    assert len(a.fits) == 3
    for f, load in zip(a.fits, gen.TRUTH["loads_N"]):
        assert abs(f.fz - load) < 0.01 * load
        assert abs(f.mu_peak / gen.mu_peak_at(load) - 1) < 0.03
        assert abs(f.k / gen.k_at(load) - 1) < 0.05
        assert f.rmse < 0.012
    d = a.as_dict()
    assert set(d) >= {"loads", "characteristic_curvature"}
    assert set(d["loads"][0]) >= {"fz", "mu_peak", "k", "characteristic_curvature", "characteristic_slip",
                                  "characteristic_mu"}


@pytest.mark.parametrize("mu_p,k,noise", [(0.8, 12.0, 0.01), (0.45, 40.0, 0.005), (1.05, 25.0, 0.02)])
def test_fit_recovery_random_laws(mu_p, k, noise):
    rng = np.random.default_rng(11)
    s = np.concatenate([np.linspace(0, 0.6, 60), -np.linspace(0, 0.4, 30)])
    mu = sl.friction(s, mu_p, k) + noise * rng.standard_normal(s.size)
    f = fit_friction_slip(s, mu)
    assert abs(f.mu_peak / mu_p - 1) < 0.03
    assert abs(f.k / k - 1) < 0.05
    assert f.mu_peak_stderr < 0.03 * mu_p
    assert_allclose(f.characteristic_slip, sl.characteristic_slip(f.mu_peak, f.k))


def test_fit_errors():
    with pytest.raises(DataError, match="at least 4"):
        fit_friction_slip([0.1, 0.2], [0.5, 0.6])
    with pytest.raises(DataError, match="0.005"):
        fit_friction_slip([0, 1e-3, 2e-3, 3e-3, 4e-3], [0, 0.01, 0.02, 0.03, 0.04])
    with pytest.raises(ColumnError, match="slip_ratio"):
        analyse_slip(pd.DataFrame({"fz": [1.0], "fy": [2.0]}))


def test_load_groups_merge_runs_at_one_load():
    df = pd.DataFrame({"run": [1, 1, 2, 2, 3, 3], "fz": [3000, 3010, 3020, 2995, 6000, 6010.0]})
    g = load_groups(df)
    assert len(g) == 2
    assert_allclose(g[0][0], np.mean([3000, 3010, 3020, 2995]))


def test_rolling_radius_fit_recovers_r0_and_elasticity():
    t = gen.rolling_radius_table()
    s = t["slip_ratio [-]"].to_numpy()
    r = fit_rolling_radius(t["torque [N*m]"].to_numpy(), t["rolling_radius [mm]"].to_numpy() / 1e3, s)
    R = gen.TRUTH["radius"]
    assert abs(r.r0 - R["r0_m"]) < 3e-4
    lam0 = 1 / (gen.mu_peak_at(R["fz_N"]) * gen.k_at(R["fz_N"]) * R["fz_N"])  # 1/(mu_p k Fz), module docstring
    assert abs(r.lambda_0 / lam0 - 1) < 0.10
    assert r.as_dict()["slip_from_radius_rmse"] < 3e-3
    # without the slip: the intercept of the small-torque law
    r2 = fit_rolling_radius(t["torque [N*m]"].to_numpy(), t["rolling_radius [mm]"].to_numpy() / 1e3)
    assert abs(r2.r0 - R["r0_m"]) < 1e-3
