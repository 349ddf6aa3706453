"""Wear-aware allocation (seed 000 Eq. 24-34, Alg. 1, Eq. 49-50) and the torque controller."""

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.optimize import minimize_scalar

from tyrefit.sim.allocator import (AxleLimits, CharacteristicSlipLimit, CurveCharacteristicSlipLimit, EqualSplit,
                                   ForceTrackingController, PeakShareSlipLimit, WearAwareAllocator,
                                   base_forces_from_motion, greedy_search, optimal_front_force,
                                   resolve_slip_limit, split_no_steering, steering_split)
from tyrefit.sim.emission import DEFAULT_EMISSION, QuadraticEmission
from tyrefit.sim.vehicle import DEFAULT_VEHICLE, VehicleModel

P = DEFAULT_VEHICLE


# ---------------------------------------------------------------- closed form (Eq. 30)

def test_closed_form_equals_brute_force():
    rng = np.random.default_rng(0)
    for _ in range(200):
        e = QuadraticEmission(rng.uniform(1e-3, 2e-2), rng.uniform(-20, 5), rng.uniform(0, 5000)).axle(2)
        k = rng.uniform(0.05, 0.95)
        total = rng.uniform(-9000, 9000)
        grid = np.linspace(-20000, 20000, 400001)
        cost = k * e.rate(grid) + e.rate(total - grid)
        assert_allclose(optimal_front_force(total, e, k), grid[np.argmin(cost)], atol=0.1)


def test_constrained_split_equals_brute_force():
    rng = np.random.default_rng(1)
    e = DEFAULT_EMISSION.axle(2)
    for _ in range(300):
        k = rng.uniform(0.1, 0.9)
        lo_f, hi_f = -rng.uniform(2000, 8000), rng.uniform(2000, 8000)
        lo_r, hi_r = -rng.uniform(2000, 8000), rng.uniform(2000, 8000)
        total = rng.uniform(lo_f + lo_r, hi_f + hi_r)
        ff, fr = split_no_steering(total, e, k, (lo_f, hi_f), (lo_r, hi_r))
        grid = np.linspace(max(lo_f, total - hi_r), min(hi_f, total - lo_r), 200001)
        cost = k * e.rate(grid) + e.rate(total - grid)
        assert_allclose(ff + fr, total, atol=1e-9)
        assert_allclose(ff, grid[np.argmin(cost)], atol=2 * (grid[1] - grid[0]) + 1e-9)
    # demand beyond both axles: both at their limits
    ff, fr = split_no_steering(-1e5, e, 0.3, (-4000, 4000), (-5000, 5000))
    assert (ff, fr) == (-4000, -5000)


def test_ideal_reduction_is_bounded_by_1_minus_k_over_1_plus_k():
    """With N = a F^2 (no linear or constant term) the best split saves exactly (1 - k)/(1 + k)."""
    e = QuadraticEmission(0.01, 0.0, 0.0).axle(2)
    for k in (0.1, 0.25, 0.6):
        total = np.linspace(-8000, 8000, 9)
        ff = optimal_front_force(total, e, k)
        low = k * e.rate(ff) + e.rate(total - ff)
        base = 2 * e.rate(total / 2)
        nz = total != 0
        assert_allclose(1 - low[nz] / base[nz], (1 - k) / (1 + k), rtol=1e-12)


# ---------------------------------------------------------------- Alg. 1

def test_greedy_search_equals_minimize_scalar_on_a_simple_function():
    f = lambda x: (x - 1.2345) ** 2 + 0.1 * np.sin(3 * x)  # noqa: E731
    x, fx, n = greedy_search(f, 0.0, 0.5, tol=1e-12)
    ref = minimize_scalar(f, bracket=(0.0, 2.0), tol=1e-12)
    assert_allclose(x, ref.x, atol=1e-6)
    assert fx <= ref.fun + 1e-12
    # vectorised: several problems at once, each its own step
    xs, _, _ = greedy_search(lambda z: (z - np.array([1.0, -2.0, 5.0])) ** 2, np.zeros(3), np.array([1, .3, 4]),
                             tol=1e-10)
    assert_allclose(xs, [1.0, -2.0, 5.0], atol=1e-9)


def _curve_state(axles, speed, radius, condition=1.0):
    """A vehicle in steady cornering (base, all soft), the allocator and its base body forces."""
    m = VehicleModel(P, axles["hard_f"], axles["soft_r"], [condition])
    x = m.rolling_state(np.array([speed]))
    steer = np.array([P.wheelbase / radius])
    x[5] = speed / radius
    x[4] = P.lr * x[5] - speed * 0.01              # some sideslip
    soft_f = AxleLimits(axles["soft_f"], PeakShareSlipLimit()(axles["soft_f"]), m.condition)
    soft_r = AxleLimits(axles["soft_r"], PeakShareSlipLimit()(axles["soft_r"]), m.condition)
    hard_f = AxleLimits(axles["hard_f"], PeakShareSlipLimit()(axles["hard_f"]), m.condition)
    alloc = WearAwareAllocator(m, axles["soft_f"], soft_f, soft_r, hard_f, soft_r, DEFAULT_EMISSION.axle(2), k=0.26)
    demand = np.array([P.drag * speed**2])
    bx, by, af = alloc.base_body_forces(x, steer, demand)
    return m, alloc, x, steer, demand, bx, by, af


@pytest.mark.parametrize("speed, radius", [(8.33, 31.9), (16.7, 127.5), (33.3, 510.0)])
def test_alg1_equals_minimize_scalar_on_the_steering_objective(axles, speed, radius):
    m, alloc, x, steer, demand, bx, by, af = _curve_state(axles, speed, radius)
    fun = lambda d: alloc.objective(np.atleast_1d(d), steer, af, bx, by)  # noqa: E731
    ff0, _ = split_no_steering(bx, alloc.emission_soft, alloc.k, (alloc.front.lower, alloc.front.upper),
                               (alloc.rear.lower, alloc.rear.upper))
    d0 = alloc._newton_steer(np.zeros(1), ff0, steer, af, by)
    scale = abs(np.sin(steer[0] + d0[0])) / float(alloc.front.axle.cornering_stiffness(af[0] - d0[0]))
    d_g, f_g, _ = greedy_search(fun, d0, 200 * scale, tol=1e-4 * scale)
    ref = minimize_scalar(lambda d: float(fun(d)[0]), bracket=(d0[0] - 50 * scale, d0[0] + 50 * scale),
                          tol=1e-12)
    assert_allclose(d_g[0], ref.x, atol=1e-3 * scale + 1e-12)         # same steering correction
    assert_allclose(f_g[0], ref.fun, rtol=1e-9)                        # same emission
    # the split is the closed form (Eq. 30) of its own total force, up to cos(steer) ~ 1
    fx_f, fx_r, _ = steering_split(d_g, steer=steer, alpha_f=af, body_x=bx, body_y=by,
                                   hard_front=axles["hard_f"], condition=m.condition)
    assert_allclose(fx_f, optimal_front_force(fx_f + fx_r, alloc.emission_soft, alloc.k),
                    atol=0.01 * abs(fx_f[0]) + 5.0)


def test_steering_split_reproduces_the_base_body_forces(axles):
    m, alloc, x, steer, demand, bx, by, af = _curve_state(axles, 16.7, 127.5)
    for d in (-0.01, 0.0, 0.004, 0.02):
        dd = np.array([d])
        fx_f, fx_r, fy = steering_split(dd, steer=steer, alpha_f=af, body_x=bx, body_y=by,
                                        hard_front=axles["hard_f"], condition=m.condition)
        s2 = steer + dd
        assert_allclose(fx_r + fx_f * np.cos(s2) - fy * np.sin(s2), bx, rtol=1e-10)   # Eq. 33
        assert_allclose(fx_f * np.sin(s2) + fy * np.cos(s2), by, rtol=1e-10)          # Eq. 32


def test_allocator_output_matches_the_base_vehicle(axles):
    for speed, radius in ((8.33, 31.9), (33.3, 510.0)):
        m, alloc, x, steer, demand, bx, by, af = _curve_state(axles, speed, radius)
        fx_f, fx_r, d = alloc(0, 0.0, x, steer, demand)
        s2 = steer + d
        fy = m.condition * axles["hard_f"].fy(af - d)
        assert_allclose(fx_r + fx_f * np.cos(s2) - fy * np.sin(s2), bx, rtol=1e-6)
        assert_allclose(fx_f * np.sin(s2) + fy * np.cos(s2), by, rtol=1e-6)
        assert d[0] > 0                     # the hard front tyre needs more steering


def test_allocator_without_steering_is_the_closed_form(axles):
    m = VehicleModel(P, axles["hard_f"], axles["soft_r"], [1.0, 0.5])
    x = m.rolling_state(np.array([20.0, 20.0]))
    lim = {k: AxleLimits(v, PeakShareSlipLimit()(v), m.condition) for k, v in axles.items()}
    alloc = WearAwareAllocator(m, axles["soft_f"], lim["soft_f"], lim["soft_r"], lim["hard_f"], lim["soft_r"],
                               DEFAULT_EMISSION.axle(2), k=0.26)
    demand = np.array([7000.0, 7000.0])
    fx_f, fx_r, d = alloc(0, 0.0, x, np.zeros(2), demand)
    ff, fr = split_no_steering(demand, DEFAULT_EMISSION.axle(2), 0.26, (lim["hard_f"].lower, lim["hard_f"].upper),
                               (lim["soft_r"].lower, lim["soft_r"].upper))
    assert_allclose(fx_f, ff)
    assert_allclose(fx_r, fr)
    assert_allclose(d, 0.0, atol=1e-12)
    assert fx_f[1] == pytest.approx(lim["hard_f"].upper[1])      # wet: the hard tyre is at its limit
    base = EqualSplit(lim["soft_f"], lim["soft_r"])(0, 0.0, x, np.zeros(2), demand)
    assert_allclose(base[0], 3500.0)


def test_base_forces_from_motion_recover_the_forces():
    rng = np.random.default_rng(5)
    m_, drag = 1800.0, 300.0
    steer = rng.uniform(0.01, 0.2, 20)
    fxf, fxr, fyf, fyr = (rng.uniform(-3000, 3000, 20) for _ in range(4))
    vx, vy, r = rng.uniform(5, 30, 20), rng.uniform(-1, 1, 20), rng.uniform(-0.3, 0.3, 20)
    dvx = (fxr + fxf * np.cos(steer) - fyf * np.sin(steer) - drag) / m_ + vy * r      # Eq. 1
    dvy = (fyr + fxf * np.sin(steer) + fyf * np.cos(steer)) / m_ - vx * r            # Eq. 2
    f, rr = base_forces_from_motion(mass=m_, dvx=dvx, dvy=dvy, vx=vx, vy=vy, yaw_rate=r, steer=steer,
                                    drag_force=drag, fy_f=fyf, fy_r=fyr)
    assert_allclose(f, fxf, rtol=1e-8, atol=1e-6)
    assert_allclose(rr, fxr, rtol=1e-8, atol=1e-6)


# ---------------------------------------------------------------- slip limits (Eq. 49-50)

def test_slip_limits(axles):
    soft = axles["soft_f"]
    lo, hi = PeakShareSlipLimit(0.9)(soft)
    assert_allclose(soft.fx(hi), 0.9 * soft.peak_drive[1], rtol=1e-3)
    # a characteristic slip beyond the peak is capped at the peak's slip
    assert CharacteristicSlipLimit(0.5)(soft) == (soft.peak_brake[0], soft.peak_drive[0])
    assert CharacteristicSlipLimit(0.03)(soft) == (-0.03, 0.03)

    class WithSlip:
        characteristic_slip = 0.04
        name = "t"

    assert isinstance(resolve_slip_limit(WithSlip()), CharacteristicSlipLimit)
    assert resolve_slip_limit(WithSlip())(soft) == (-0.04, 0.04)
    assert isinstance(resolve_slip_limit(object()), PeakShareSlipLimit)


def test_characteristic_slip_from_the_curve_uses_seed_002(axles):
    from tyrefit.models import slip as sl
    from tyrefit.fitting.slip import fit_friction_slip

    ax = axles["soft_f"]
    lim = CurveCharacteristicSlipLimit()
    lam = np.linspace(0, ax.peak_drive[0], 60)[1:]
    f = fit_friction_slip(lam / (1 + lam), ax.fx(lam) / (2 * ax.fz))
    sc = float(sl.characteristic_slip(f.mu_peak, f.k))
    assert_allclose(lim.characteristic_slip(ax), sc / (1 - sc), rtol=1e-12)
    lo, hi = lim(ax)
    assert 0 < hi <= ax.peak_drive[0] and lo < 0


# ---------------------------------------------------------------- torque controller

def test_force_tracking_controller_tracks_a_step(axles):
    m = VehicleModel(P, axles["soft_f"], axles["soft_r"], [1.0, 0.5])
    lim_f = AxleLimits(axles["soft_f"], PeakShareSlipLimit()(axles["soft_f"]), m.condition)
    lim_r = AxleLimits(axles["soft_r"], PeakShareSlipLimit()(axles["soft_r"]), m.condition)
    ctrl = ForceTrackingController(m, lim_f, lim_r)
    x = m.rolling_state(np.array([20.0, 20.0]))
    ref_f, ref_r = np.array([3000.0, 1500.0]), np.array([-2000.0, -1000.0])
    dt, vdot = 1e-3, np.zeros(2)
    hist = []
    for i in range(300):
        tf, tr = ctrl(x, np.zeros(2), ref_f, ref_r, vdot)
        x, dx, out = m.step(i * dt, x, np.array([np.zeros(2), tf, tr]), dt)
        vdot = dx[3]
        hist.append((out["fx_f"].copy(), out["fx_r"].copy()))
    ff = np.array([h[0] for h in hist])
    fr = np.array([h[1] for h in hist])
    assert_allclose(ff[50:], np.broadcast_to(ref_f, ff[50:].shape), rtol=0.01)
    assert_allclose(fr[50:], np.broadcast_to(ref_r, fr[50:].shape), rtol=0.01)
    # references beyond the slip limit are held at the limit
    tf, tr = ctrl(x, np.zeros(2), np.array([1e5, 1e5]), np.array([-1e5, -1e5]), vdot)
    assert np.all(np.isfinite(tf)) and np.all(tf <= P.wheel_radius * lim_f.upper * 1.5)
