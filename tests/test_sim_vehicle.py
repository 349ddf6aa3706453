"""Bicycle model, axle tyres, path coordinates (tyrefit.sim.vehicle, .tyres, .path)."""

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.optimize import fsolve

from tyrefit.errors import DataError, ModelError
from tyrefit.sim.path import PathGeometry, curve_path, curvilinear_rates, uk_desirable_minimum_radius
from tyrefit.sim.tyres import AxleTyre
from tyrefit.sim.vehicle import DEFAULT_VEHICLE, INPUTS, OUTPUTS, STATES, VehicleModel
from tyrefit.synthetic.vehicle_tyres import true_tyre

P = DEFAULT_VEHICLE


# ---------------------------------------------------------------- axle tyres

def test_axle_tables_match_the_pac89_model(axles):
    ax = axles["hard_f"]
    tyre, fz = ax.tyre, ax.fz
    lam = np.linspace(-0.5, 0.5, 1001)
    alpha = np.radians(np.linspace(-15, 15, 1001))
    peak = np.max(np.abs(2 * tyre.fx(fz, lam)))
    assert_allclose(ax.fx(lam), 2 * tyre.fx(fz, lam), atol=2e-4 * peak)
    both = tyre.fy(fz, alpha) + tyre.mirrored().fy(fz, alpha)
    assert_allclose(ax.fy(alpha), both, atol=2e-4 * np.max(np.abs(both)))


def test_axle_is_symmetric_and_iso_w(axles):
    ax = axles["soft_f"]
    # left tyre + mirrored right tyre: conicity cancels, no force at zero slip angle
    assert abs(float(ax.fy(0.0))) < 1e-6 * ax.fz
    assert float(ax.fy(0.05)) < 0 < float(ax.fy(-0.05))        # ISO-W: positive slip angle, negative force
    assert ax.cornering_stiffness(0.0) > 0


def test_inverse_curves_round_trip(axles):
    ax = axles["soft_r"]
    f = np.linspace(0.9 * ax.peak_brake[1], 0.9 * ax.peak_drive[1], 51)
    assert_allclose(ax.fx(ax.slip_for_force(f)), f, atol=1e-3 * ax.peak_drive[1])
    fy = np.linspace(-0.9, 0.9, 41) * ax.mu_y_peak * 2 * ax.fz
    assert_allclose(ax.fy(ax.slip_angle_for_force(fy)), fy, atol=2e-3 * np.max(np.abs(fy)))


def test_peak_share_slip(axles):
    soft, hard = axles["soft_f"], axles["hard_f"]
    for ax in (soft, hard):
        lo, hi = ax.slip_for_mu_share(0.95)
        assert_allclose(ax.fx(hi), 0.95 * ax.peak_drive[1], rtol=1e-3)
        assert_allclose(ax.fx(lo), 0.95 * ax.peak_brake[1], rtol=1e-3)
        assert lo < 0 < hi < ax.peak_drive[0]
    # hard tyres reach their peak at larger slip (seed 000, Sec. 4.2.1)
    assert hard.slip_for_mu_share(0.95)[1] > soft.slip_for_mu_share(0.95)[1]
    with pytest.raises(ModelError, match="share"):
        soft.slip_for_mu_share(1.5)


def test_tyre_without_longitudinal_part_is_refused():
    t = true_tyre("soft")
    for k in list(t.coefficients):
        if k.startswith("b"):
            t.coefficients[k] = 0.0
    with pytest.raises(ModelError, match="longitudinal"):
        AxleTyre(t, 4000.0)


# ---------------------------------------------------------------- vehicle

def test_update_signature_and_named_outputs(axles):
    m = VehicleModel(P, axles["soft_f"], axles["soft_r"], [1.0, 0.5])
    x = m.rolling_state(np.array([20.0, 10.0]))
    u = np.zeros((len(INPUTS), 2))
    dx = m.update(0.0, x, u)
    assert dx.shape == (len(STATES), 2)
    out = m.output(0.0, x, u)
    assert set(OUTPUTS) <= set(out)
    # free rolling, no torque: only the drag decelerates (Eq. 1)
    assert_allclose(dx[3], -P.drag * np.array([20.0, 10.0]) ** 2 / P.mass, rtol=1e-9)
    assert_allclose(dx[[1, 2, 4, 5]], 0.0, atol=1e-12)
    # condition override through params
    dx2 = m.update(0.0, x, u, {"condition": [1.0, 1.0]})
    assert_allclose(dx2, dx, atol=1e-12)


def test_condition_scales_the_forces(axles):
    m = VehicleModel(P, axles["soft_f"], axles["soft_r"], [1.0, 0.5])
    x = m.rolling_state(np.array([20.0, 20.0]))
    x[6] *= 1.03                                  # front wheel spinning 3 % faster
    out = m.output(0.0, x, np.zeros((3, 2)))
    assert out["fx_f"][0] > 0
    assert_allclose(out["fx_f"][1], 0.5 * out["fx_f"][0], rtol=1e-12)


def test_bad_condition():
    ax = AxleTyre(true_tyre("soft"), 4000.0)
    with pytest.raises(DataError, match="eta"):
        VehicleModel(P, ax, ax, [0.0])


def _steady_circle(model, v, radius):
    """Steady cornering on a circle: steering, vy, r and the wheel speeds with rear drive for drag."""
    p = model.params

    def eqs(z):
        steer, vy, fxr = z
        r = np.hypot(v, vy) / radius                  # the velocity turns with the path (Eq. 13: dxi/dt = 0)
        x = model.rolling_state(np.array([v]))
        x[4], x[5] = vy, r
        lam = model.rear.slip_for_force(np.array([fxr]) / model.condition)
        x[7] = (v + lam * v) / p.wheel_radius
        vf, _ = model.wheel_speeds(x, np.array([steer]))
        x[6] = vf / p.wheel_radius                     # front wheel free rolling
        dx, _ = model.evaluate(0.0, x, np.array([[steer], [0.0], [p.wheel_radius * fxr]]))
        return [dx[3][0], dx[4][0], dx[5][0]], x

    sol = fsolve(lambda z: eqs(z)[0], [p.wheelbase / radius, 0.0, p.drag * v**2])
    x = eqs(sol)[1]
    return sol, x


@pytest.mark.parametrize("v, radius", [(10.0, 40.0), (25.0, 250.0)])
def test_constant_radius_circle_keeps_offset_and_heading_error(axles, v, radius):
    """On a circle driven in steady state, n and xi stay constant (Eq. 11-13 and their signs)."""
    path = PathGeometry([[5000.0]], [[1.0 / radius]])
    model = VehicleModel(P, axles["soft_f"], axles["soft_r"], [1.0], path)
    (steer, vy, fxr), x = _steady_circle(model, v, radius)
    x[2] = -np.arctan2(vy, v)                     # heading error = minus the sideslip: velocity tangent
    x[1] = 0.0
    u = np.array([[steer], [0.0], [P.wheel_radius * fxr]])
    x0 = x.copy()
    dt = 2e-3
    for i in range(int(5.0 / dt)):
        x, _, _ = model.step(i * dt, x, u, dt)
    assert abs(x[1, 0]) < 1e-6                    # offset n [m]
    assert abs(x[2, 0] - x0[2, 0]) < 1e-8         # heading error xi [rad]
    assert_allclose(x[0, 0], 5.0 * np.hypot(v, vy), rtol=2e-3)
    assert steer > 0 and x[5, 0] > 0              # left turn: positive steering and yaw rate
    # with the curvature of the wrong sign the same drive leaves the path at once
    bad = VehicleModel(P, axles["soft_f"], axles["soft_r"], [1.0], PathGeometry([[5000.0]], [[-1.0 / radius]]))
    xb = x0.copy()
    for i in range(int(2.0 / dt)):
        xb, _, _ = bad.step(i * dt, xb, u, dt)
    assert abs(xb[1, 0]) > 1.0


def test_curvilinear_rates_on_a_straight():
    ds, dn, dxi = curvilinear_rates(0.3, 0.01, 20.0, 0.5, 0.02, 0.0)
    assert_allclose(ds, 20.0 * np.cos(0.01) - 0.5 * np.sin(0.01))
    assert_allclose(dn, 20.0 * np.sin(0.01) + 0.5 * np.cos(0.01))
    assert_allclose(dxi, 0.02)


# ---------------------------------------------------------------- paths

def test_uk_desirable_minimum_radius():
    assert_allclose(uk_desirable_minimum_radius([60, 120]), [255.0, 1020.0], rtol=1e-12)
    r30 = float(uk_desirable_minimum_radius(30))
    assert 60 < r30 < 68                                    # half is seed 000's ~32 m
    half = 0.5 * uk_desirable_minimum_radius(np.array([30.0, 60.0, 120.0]))
    assert_allclose((np.array([30.0, 60.0, 120.0]) / 3.6) ** 2 / half, 2.18, rtol=0.03)


def test_path_geometry_and_smoothing():
    path = curve_path(100.0, [50.0, 500.0], np.pi / 2)
    assert_allclose(path.total_length, 200.0 + np.array([50.0, 500.0]) * np.pi / 2)
    assert_allclose(path.heading(path.total_length), np.pi / 2)
    s = np.linspace(0, 1, 4001)[:, None] * path.total_length[None, :]
    w = np.array([20.0, 60.0])
    k = np.stack([path.smoothed_curvature(si, w) for si in s])
    h = path.total_length / 4000
    # the smoothing keeps the total turn and never exceeds the arc's curvature
    assert_allclose(np.trapezoid(k, dx=h, axis=0) if hasattr(np, "trapezoid") else np.trapz(k, dx=h, axis=0),
                    np.pi / 2, rtol=1e-4)
    assert np.all(k <= 1.0 / np.array([50.0, 500.0]) + 1e-12)
    x, y = path.xy(path.total_length[0], member=0)
    assert_allclose([x[0], y[0]], [150.0, 150.0], atol=0.05)   # straight 100, quarter circle r=50, straight 100
