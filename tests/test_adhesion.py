"""Road-adhesion estimation of seed 001: 7-DOF vehicle, measurement Jacobian, EKF, the paper's experiment."""

import json

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tyrefit.cli import main
from tyrefit.models import brush as bm
from tyrefit.nomenclature import G0
from tyrefit.sim import adhesion as ad
from tyrefit.sim import vehicle7dof as v7

VP = v7.VehicleParams()


# --- vehicle model -------------------------------------------------------------------------
def test_measurement_matrix_is_the_derivative_of_the_measurement():
    rng = np.random.default_rng(3)
    for delta in (0.0, 0.05, -0.1):
        D = v7.measurement_matrix(delta, VP)
        F = rng.normal(0, 2000, 8)
        y = v7.measurement(F[:4], F[4:], delta, VP)
        assert_allclose(D @ F, y, rtol=1e-12, atol=1e-9)  # linear in the forces: exact
        for j in range(8):
            dF = np.zeros(8)
            dF[j] = 1.0
            yj = v7.measurement((F + dF)[:4], (F + dF)[4:], delta, VP)
            assert_allclose(yj - y, D[:, j], rtol=1e-6, atol=1e-9)


def test_body_forces_eq_33_35_without_steer():
    fx = np.array([100.0, 200.0, 300.0, 400.0])
    fy = np.array([10.0, 20.0, 30.0, 40.0])
    Fx, Fy, G = v7.body_forces(fx, fy, 0.0, VP)
    assert_allclose(Fx, 1000.0)
    assert_allclose(Fy, 100.0)
    # Eq. 35 at delta = 0: la (Fyf) - lb (Fyr) - tf/2 (Fxfl - Fxfr) - tr/2 (Fxrl - Fxrr)
    ref = VP.la * 30 - VP.lb * 70 - VP.track_f / 2 * (100 - 200) - VP.track_r / 2 * (300 - 400)
    assert_allclose(G, ref)


def test_normal_loads_and_wheel_kinematics():
    fz = v7.normal_loads(0.0, 0.0, VP)
    assert_allclose(fz.sum(), VP.mass * G0)
    fzb = v7.normal_loads(-6.0, 0.0, VP)  # braking: load to the front
    assert fzb[0] > fz[0] and fzb[2] < fz[2]
    assert_allclose(fzb.sum(), VP.mass * G0)
    fzl = v7.normal_loads(0.0, 4.0, VP)  # left turn (a_y > 0): load to the right wheels
    assert fzl[1] > fzl[0] and fzl[3] > fzl[2]
    vx, vy = v7.wheel_velocities(20.0, 0.0, 0.0, 0.0, VP)
    assert_allclose(vx, 20.0)
    assert_allclose(vy, 0.0)
    vx, vy = v7.wheel_velocities(20.0, 0.0, 0.5, 0.0, VP)  # yawing left: right wheels faster, front slides left
    assert vx[1] > vx[0] and vy[0] > 0 > vy[2]


def test_free_rolling_straight_has_no_accelerations():
    state = np.array([20.0, 0, 0, *([20.0 / VP.wheel_radius] * 4)])
    d, y = v7.derivatives(state, np.zeros(4), np.zeros(4), np.zeros(4), 0.0, VP)
    assert_allclose(d, 0.0)
    assert_allclose(y, 0.0)


# --- EKF Jacobian ----------------------------------------------------------------------------
def test_ekf_jacobian_against_finite_differences_and_full_sliding():
    ekf = ad.AdhesionEKF(ad.improved_tyre(n=4), VP)
    state = np.array([20.0, 0.3, 0.1, 62.0, 60.0, 64.0, 58.0])
    delta, cam = 0.03, ad.camber_vector(np.deg2rad(4))
    fz = v7.normal_loads(-3.0, 1.0, VP)
    mu = np.array([0.6, 0.7, 0.8, 0.5])
    h, H = ekf.jacobian(mu, state, delta, cam, fz)
    for j in range(4):
        e = np.zeros(4)
        e[j] = 1e-3
        hp, _ = ekf.jacobian(mu + e, state, delta, cam, fz)
        hm, _ = ekf.jacobian(mu - e, state, delta, cam, fz)
        assert_allclose((hp - hm) / 2e-3, H[:, j], rtol=2e-3, atol=1e-6 * np.abs(H).max())
    # locked wheels slide fully: F = mu Fz n, so dh/dmu = D (Fz n) exactly
    locked = state.copy()
    locked[3:] = 0.0
    h, H = ekf.jacobian(mu, locked, delta, cam, fz)
    fx, fy = ekf.tyre.forces(fz, *v7.wheel_velocities(*locked[:3], delta, VP), locked[3:], cam, mu, VP.pressure)
    assert_allclose(np.hypot(fx, fy), mu * fz, rtol=1e-9)
    D = v7.measurement_matrix(delta, VP)
    assert_allclose(H, D[:, :4] * (fx / mu) + D[:, 4:] * (fy / mu), rtol=1e-6)


def test_convergence_time():
    t = np.linspace(0, 1, 11)
    est = np.ones((11, 4))
    est[:3] = 2.0
    assert ad.convergence_time(t, est, np.ones(4), 0.01) == pytest.approx(0.3)


# --- the paper's experiment -----------------------------------------------------------------------
CAMBERS = (0.0, 3.0, 6.0)


@pytest.fixture(scope="module", params=[0.8, 0.3], ids=["dry0.8", "wet0.3"])
def experiment(request):
    mu = request.param
    return mu, {c: ad.run_experiment(mu, c)[1] for c in CAMBERS}


def test_ekf_converges_within_3_percent(experiment):
    """Must show: the improved-model EKF within 3 % of the true mu on each road at each camber."""
    mu, runs = experiment
    for c in CAMBERS:
        imp = runs[c]["improved"]
        assert imp.max_abs_error_pct < 3.0, (mu, c, imp.relative_error_pct)
        assert imp.converged_s < 1.9
        assert imp.history.shape == (imp.t.size, 4)


def test_improved_model_error_not_larger_than_original(experiment):
    """Must show: the paper's Fig. 17 trend; mean |error| over the four wheels."""
    mu, runs = experiment
    mean = {k: [np.mean(np.abs(runs[c][k].relative_error_pct)) for c in CAMBERS] for k in ("improved", "original")}
    for i, c in enumerate(CAMBERS):
        if c > 0:
            assert mean["improved"][i] <= mean["original"][i], (mu, c, mean)
    assert mean["original"][-1] > mean["original"][0]  # the original model degrades with camber
    if mu == 0.8:  # the paper's Fig. 17 road: strictly growing with camber
        assert mean["original"][0] < mean["original"][1] < mean["original"][2], mean


def test_original_model_is_calibrated_on_the_same_tyre():
    cal = ad._calibrated(bm.DEFAULT_PARAMS, 16)
    fz = 4000.0
    for kap, alpha in ((0.03, 0.0), (0.0, np.deg2rad(3)), (-0.05, np.deg2rad(-2))):
        fi = bm.camber_brush_forces(bm.DEFAULT_PARAMS, fz, kap, alpha, 0.0, n=16)
        fo = bm.brush_forces(cal, fz, kap, alpha, 0.0)
        assert abs(fi.fx - fo.fx) < 0.02 * fz and abs(fi.fy - fo.fy) < 0.02 * fz


def test_cli_adhesion_json(tmp_path, capsys):
    out = tmp_path / "a.json"
    assert main(["sim", "adhesion", "--road-mu", "0.3", "--camber", "3", "--json", str(out)]) == 0
    d = json.loads(out.read_text())
    assert d["road_mu"] == 0.3 and d["camber_deg"] == 3.0
    assert len(d["estimates"]) == 4 and len(d["relative_error_pct"]) == 4
    assert isinstance(d["converged_s"], float)
    assert max(abs(e) for e in d["relative_error_pct"]) < 3.0
    assert_allclose(d["relative_error_pct"], [100 * (e - 0.3) / 0.3 for e in d["estimates"]])
    assert set(d["original_model"]) >= {"estimates", "relative_error_pct", "converged_s"}
    assert d["camber_wheels_deg"] == [3.0, -3.0, 3.0, -3.0]
    assert main(["sim", "adhesion", "--road-mu", "0.3", "--json", str(out)]) == 2  # exists
    assert main(["sim", "adhesion", "--road-mu", "7", "--json", str(tmp_path / "b.json")]) == 2
    assert "road adhesion coefficient" in capsys.readouterr().err
    assert not (tmp_path / "b.json").exists()
