"""Tests that kill the hand-made mutations issue 25 found surviving the quick suite.

Each test checks a physical law or a documented contract, not the code's own output:

* l1 fit: with 26 % gross outliers the fit is the exact least-absolute-deviations line (a linear
  programme solved by ``scipy.optimize.linprog``), not a point part-way along the continuation;
* the MF stage fit keeps E_y <= 1 on data whose generating tyre breaks it;
* the allocator keeps both axles inside their force limits, and the torque controller's feed-forward
  is the exact wheel balance J dw/dt = T - r Fx at constant slip;
* the breakpoint's 68 % interval covers the truth about 68 % of the time; a linear pressure law
  recovers a clear pressure dependence with its sign;
* MF 6.1 rolling resistance vanishes with the rolling speed (locked wheel, standstill), VXLOW given or not;
* bootstrap p-values are never below 1 / (n_boot + 1);
* the relaxation length is sigma = n L (1 + b |u|) (its docstring).

Each was checked to fail with its mutation applied by hand (benchmarks/mutation.py ``NAMED``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.optimize import linprog

from tyrefit.fitting.core import Parameters, solve


# ------------------------------------------------------------------------------------------ l1 cost
def _lad_line(X, y):
    """The exact least-absolute-deviations coefficients: min sum(u + v) s.t. X b + u - v = y, u, v >= 0."""
    n, p = X.shape
    c = np.concatenate([np.zeros(p), np.ones(2 * n)])
    A = np.hstack([X, np.eye(n), -np.eye(n)])
    bounds = [(None, None)] * p + [(0, None)] * (2 * n)
    res = linprog(c, A_eq=A, b_eq=y, bounds=bounds, method="highs")
    assert res.status == 0
    return res.x[:p], res.fun


def test_l1_fit_is_the_least_absolute_deviations_solution_with_a_quarter_outliers():
    rng = np.random.default_rng(25)
    x = np.linspace(0.0, 1.0, 101)
    y = 1.0 + 2.0 * x + 0.01 * rng.standard_normal(x.size)
    bad = rng.choice(x.size, 26, replace=False)      # 26 % gross outliers, all on one side
    y[bad] += rng.uniform(2.0, 6.0, bad.size)
    X = np.column_stack([np.ones_like(x), x])
    p = Parameters.from_values({"c": 0.0, "m": 0.0})
    l2 = solve(lambda v: X @ v - y, p, jac=lambda v: X)
    l1 = solve(lambda v: X @ v - y, p, jac=lambda v: X, cost="l1", starts=[l2.x])
    b_lad, f_lad = _lad_line(X, y)
    # the truth, within the noise (l2 is pulled by about 1)
    assert abs(l2.values["c"] - 1.0) > 0.5
    assert l1.values["c"] == pytest.approx(1.0, abs=0.02)
    assert l1.values["m"] == pytest.approx(2.0, abs=0.04)
    # and the l1 optimum itself: the linear programme's coefficients and objective
    assert_allclose(l1.x, b_lad, atol=2e-3)
    assert l1.cost == pytest.approx(np.sum(np.abs(X @ l1.x - y)), rel=1e-12)
    assert l1.cost == pytest.approx(f_lad, rel=1e-4)


def test_l1_fit_of_a_curve_with_outliers_reaches_the_l1_minimum():
    # a nonlinear model: no l1 point may beat the fit's objective (checked by perturbing every coefficient)
    rng = np.random.default_rng(7)
    x = np.linspace(0.0, 4.0, 80)
    y = 2.5 * np.exp(-1.3 * x) + 0.4 + 0.005 * rng.standard_normal(x.size)
    bad = rng.choice(x.size, 20, replace=False)
    y[bad] += rng.uniform(0.5, 2.0, bad.size)

    def r(v):
        return v[0] * np.exp(-v[1] * x) + v[2] - y

    p = Parameters()
    p.add("amp", 1.0, min=0.0, max=10.0)
    p.add("rate", 0.5, min=1e-6, max=10.0)
    p.add("off", 0.0)
    l2 = solve(r, p)
    l1 = solve(r, p, cost="l1", starts=[l2.x])
    assert l1.values["amp"] == pytest.approx(2.5, rel=0.02)
    assert l1.values["rate"] == pytest.approx(1.3, rel=0.02)
    assert l1.values["off"] == pytest.approx(0.4, abs=0.01)
    f = np.sum(np.abs(r(l1.x)))
    for j in range(3):
        for h in (-1e-3, 1e-3):
            t = l1.x.copy()
            t[j] += h
            assert np.sum(np.abs(r(t))) >= f - 1e-9


# ------------------------------------------------------------------------- MF stage constraints
def test_the_fy0_stage_keeps_e_y_le_1_on_data_whose_tyre_breaks_it():
    # the generating tyre's curvature E_y = PEY1 + PEY2 dfz reaches 1.7 at the lightest load: a shape the
    # Magic Formula must not be given (past E = 1 the curve folds back); the penalty rows hold it at <= 1
    from tyrefit.fitting.mf import fit_mf
    from tyrefit.models import mf61
    from tyrefit.synthetic import ttc_drivebrake as gen
    from tyrefit.tyres.contract import violations

    fnomin = gen.PUBLISHED_MF61["FNOMIN"]
    info = {"fnomin": fnomin, "unloaded_radius": gen.PUBLISHED_MF61["UNLOADED_RADIUS"]}
    env = {"fz": (0.4 * fnomin, 1.6 * fnomin), "slip_angle": (-0.21, 0.21), "slip_ratio": (-0.2, 0.2),
           "camber": (0.0, 0.0), "pressure": (260e3, 260e3)}
    truth = dict(gen.contract_mf61(), PEY1=1.2)
    assert ("E<=1", "Fy") in {(v.rule, v.channel) for v in violations(truth, env)}
    loads = [0.4 * fnomin, fnomin, 1.6 * fnomin]
    df = gen.make_sweeps(truth, seed=51, pressures=[260e3], cambers_deg=[0.0], slip_angles_deg=[0.0],
                         loads=loads, n_points=41)
    r = fit_mf(df, tyre_info=info, stages=["Fy0"])
    assert ("E<=1", "Fy") not in {(v.rule, v.channel) for v in r.contract()}, r.contract()
    fz = np.linspace(0.4 * fnomin, 1.6 * fnomin, 25)
    f = mf61.factors(r.params, fz, 0.0, 260e3)
    assert np.all(f["ey_pos"] <= 1.0 + 1e-6) and np.all(f["ey_neg"] <= 1.0 + 1e-6)


# ------------------------------------------------------------------------------------ allocator
def _braking_allocator(axles, members):
    from tyrefit.sim.allocator import AxleLimits, PeakShareSlipLimit, WearAwareAllocator
    from tyrefit.sim.emission import DEFAULT_EMISSION
    from tyrefit.sim.vehicle import DEFAULT_VEHICLE, VehicleModel

    m = VehicleModel(DEFAULT_VEHICLE, axles["hard_f"], axles["soft_r"], [1.0] * members)
    lim = {k: AxleLimits(v, PeakShareSlipLimit()(v), m.condition) for k, v in axles.items()}
    alloc = WearAwareAllocator(m, axles["soft_f"], lim["soft_f"], lim["soft_r"], lim["hard_f"], lim["soft_r"],
                               DEFAULT_EMISSION.axle(2), k=0.26)
    return m, alloc, lim


@pytest.mark.parametrize("steer", [0.0, 0.02])
def test_allocator_keeps_both_axles_inside_their_force_limits(axles, steer):
    # demands from hard braking to full drive: the base (all-soft) vehicle's front brakes harder than the hard
    # front tyre can, and what is left must not be put on the rear beyond its own slip limit
    demands = np.array([-1e5, -3e4, -1.2e4, -8e3, -2e3, 0.0, 2e3, 8e3, 1.2e4, 3e4, 1e5])
    m, alloc, lim = _braking_allocator(axles, demands.size)
    x = m.rolling_state(np.full(demands.size, 20.0))
    fx_f, fx_r, _ = alloc(0, 0.0, x, np.full(demands.size, steer), demands)
    tol = 1e-9 * np.abs(lim["soft_r"].lower)
    assert np.all(fx_r >= lim["soft_r"].lower - tol), (fx_r, lim["soft_r"].lower)
    assert np.all(fx_r <= lim["soft_r"].upper + tol), (fx_r, lim["soft_r"].upper)
    assert np.all(fx_f >= lim["hard_f"].lower - tol) and np.all(fx_f <= lim["hard_f"].upper + tol)
    # at the extremes both axles sit at their limits
    assert fx_r[0] == pytest.approx(lim["soft_r"].lower[0]) and fx_r[-1] == pytest.approx(lim["soft_r"].upper[-1])


def test_torque_feed_forward_is_the_exact_wheel_balance_in_hard_braking(axles):
    # with the wheel at its reference slip lambda and the car decelerating at a, keeping lambda constant needs
    # dw/dt = (1 + lambda) a / r, so the torque must be T = r Fx + J (1 + lambda) a / r (Eq. 5, exactly)
    from tyrefit.sim.allocator import AxleLimits, ForceTrackingController, PeakShareSlipLimit
    from tyrefit.sim.vehicle import DEFAULT_VEHICLE as P, VehicleModel

    m = VehicleModel(P, axles["soft_f"], axles["soft_r"], [1.0])
    lim_f = AxleLimits(axles["soft_f"], PeakShareSlipLimit()(axles["soft_f"]), m.condition)
    lim_r = AxleLimits(axles["soft_r"], PeakShareSlipLimit()(axles["soft_r"]), m.condition)
    ctrl = ForceTrackingController(m, lim_f, lim_r)
    v, a = 25.0, -9.0
    f_f, f_r = 0.95 * lim_f.lower, 0.95 * lim_r.lower            # hard braking, inside the slip limits
    lam_f = float(axles["soft_f"].slip_for_force(f_f[0]))
    lam_r = float(axles["soft_r"].slip_for_force(f_r[0]))
    assert lam_f < -0.03 and lam_r < -0.03
    x = m.rolling_state(np.array([v]))
    x[6] = (1.0 + lam_f) * v / P.wheel_radius                    # each wheel already at its reference slip
    x[7] = (1.0 + lam_r) * v / P.wheel_radius
    tf, tr = ctrl(x, np.zeros(1), f_f, f_r, np.array([a]))
    for t, f, lam in ((tf, f_f, lam_f), (tr, f_r, lam_r)):
        expected = P.wheel_radius * f[0] + P.wheel_inertia * (1.0 + lam) * a / P.wheel_radius
        assert abs(P.wheel_radius * f[0]) > 2000.0
        assert float(t[0]) == pytest.approx(expected, abs=1e-6 * abs(expected))


# ---------------------------------------------------------------------------------- contact patch
def test_breakpoint_68_percent_interval_covers_the_truth_about_68_percent_of_the_time():
    # 40 seeded draws of a two-gradient length law with a known breakpoint and known noise: a 68 % interval
    # that contains the truth in 50-85 % of them (binomial 40 x 0.68: 22-32 at +-2.7 sd); one 3.6x too wide
    # covers it every time
    from tyrefit.rig.patch import fit_two_gradient, two_gradient

    x = np.linspace(5e3, 95e3, 19)
    xb = 52e3
    truth = two_gradient(x, 0.08, 2.0e-6, 0.6e-6, xb)
    hits, widths = 0, []
    for seed in range(40):
        y = truth + 0.002 * np.random.default_rng(seed).standard_normal(x.size)
        fit = fit_two_gradient(x, y)
        lo, hi = fit.breakpoint_interval
        hits += lo <= xb <= hi
        widths.append(hi - lo)
    assert 20 <= hits <= 34, hits
    # and its width is the spread of the estimate: about twice the breakpoint's standard deviation
    est = [fit_two_gradient(x, truth + 0.002 * np.random.default_rng(100 + s).standard_normal(x.size)).breakpoint
           for s in range(40)]
    assert 0.5 < np.median(widths) / (2.0 * np.std(est)) < 2.0, (np.median(widths), np.std(est))


def test_a_linear_pressure_law_recovers_a_clear_pressure_dependence_with_its_sign():
    # the length law's intercept y0 falls 10 mm per bar (a pressure law 'linear'); the breakpoint and gradients
    # follow power laws.  At an untested pressure the model must give the truth, and y0 must fall with pressure
    import pandas as pd

    from tyrefit.rig.patch import fit_patch, two_gradient

    p_ref = 7.4e5

    def law(p):
        s = p / p_ref
        return 0.12 - 0.01 * (p - p_ref) / 1e5, 2.0e-6 * s**-0.5, 0.6e-6 * s**-0.4, 50e3 * s**0.8

    loads = np.linspace(5e3, 100e3, 20)
    rows = [pd.DataFrame({"load": loads, "pressure": p, "length": two_gradient(loads, *law(p))})
            for p in (5.9e5, 7.4e5, 9.0e5)]
    model = fit_patch(pd.concat(rows, ignore_index=True))
    y0 = model.laws["length"]["y0"]
    assert y0.kind == "linear" and y0.m == pytest.approx(-0.01 / 1e5, rel=1e-6)
    for p in (6.5e5, 8.2e5):
        assert_allclose(model.length(loads, p), two_gradient(loads, *law(p)), rtol=1e-6)
    assert np.all(model.length(loads, 8.6e5) < model.length(loads, 6.2e5))


# --------------------------------------------------------------------------- MF 6.1 rolling resistance
@pytest.mark.parametrize("vxlow", [None, 1.0])
def test_rolling_resistance_vanishes_with_the_rolling_speed(vxlow):
    # My opposes the rolling speed Vr = Vx (1 + kappa): a locked wheel (kappa = -1) and a tyre at standstill do
    # not roll, so My = 0 there whether the file gives VXLOW or not (MF 6.1, MFeval's calculateMy)
    from tyrefit.models import mf61
    from tyrefit.synthetic import ttc_drivebrake as gen

    p = {k: v for k, v in gen.contract_mf61().items() if k != "VXLOW"}
    if vxlow is not None:
        p["VXLOW"] = vxlow
    assert gen.contract_mf61()["QSY1"] > 0
    fz = np.array([2000.0, 4000.0, 6000.0])
    locked = mf61.forces(p, fz, slip_ratio=-1.0, speed=16.7)["my"]
    still = mf61.forces(p, fz, slip_ratio=0.0, speed=0.0)["my"]
    assert_allclose(locked, 0.0, atol=1e-9)
    assert_allclose(still, 0.0, atol=1e-9)
    # rolling forwards it resists (ISO-W: My < 0); a wheel spun backwards (kappa < -1) reverses it
    assert np.all(mf61.forces(p, fz, slip_ratio=0.0, speed=16.7)["my"] < 0)
    assert np.all(mf61.forces(p, fz, slip_ratio=-3.0, speed=16.7)["my"] > 0)


# ------------------------------------------------------------------------------- diagnose p-values
def _extreme_scores(n_sweeps=16, n_per=20):
    """Residuals that are exactly one new direction, the same in every sweep: no sign flip beats it."""
    rng = np.random.default_rng(3)
    cluster = np.repeat(np.arange(n_sweeps), n_per)
    x = np.tile(np.linspace(-1.0, 1.0, n_per), n_sweeps)
    J_model = np.column_stack([np.ones_like(x)])
    J_new = np.column_stack([x])
    resid = 5.0 * x + 0.01 * rng.standard_normal(x.size)
    return J_model, J_new, resid, cluster, n_sweeps


def test_score_test_p_values_are_never_below_one_over_n_plus_one():
    from tyrefit.diagnose.stats import score_test, score_test_groups

    J_model, J_new, resid, cluster, G = _extreme_scores()
    for n_boot in (99, 199):
        st = score_test(J_model, J_new, resid, cluster, G, np.random.default_rng(0), n_boot=n_boot)
        assert st.p_value >= 1.0 / (n_boot + 1) and st.p_value == pytest.approx(1.0 / (n_boot + 1))
        gt = score_test_groups(J_model, [J_new, J_new**2], resid, cluster, G, np.random.default_rng(0),
                               n_boot=n_boot)
        assert min(gt.p_groups) >= 1.0 / (n_boot + 1) and gt.p_value >= 1.0 / (n_boot + 1)


@pytest.mark.parametrize("method", ["flip", "noise"])
def test_screening_p_values_are_never_below_one_over_n_plus_one(method):
    from tyrefit.diagnose.stats import SweepLayout, screen_candidates

    J_model, J_new, resid, cluster, G = _extreme_scores()
    n_boot = 99
    sc = screen_candidates(J_model, [J_new, J_new**2], resid, SweepLayout(cluster, G), np.random.default_rng(0),
                           n_boot=n_boot, method=method)
    assert np.all(sc.p_value >= 1.0 / (n_boot + 1)) and np.all(sc.p_adjusted >= 1.0 / (n_boot + 1))
    assert sc.p_value[0] == pytest.approx(1.0 / (n_boot + 1))


# ------------------------------------------------------------------------------ rig relaxation length
@pytest.mark.parametrize("n, b", [(1.0, 0.0), (1.7, 0.0), (1.7, 2.5), (0.6, 0.8)])
def test_relaxation_length_is_n_l_1_plus_b_u(n, b):
    # sigma = n L (1 + b |u|) (docstring), and it is the length over which the displacement gives the slip
    # angle: tan(alpha) = Delta y / sigma (Eq. 1 in relaxation form)
    from tyrefit.rig.conversion import RigCalibration

    cal = RigCalibration(n=n, b=b, points=10)
    L = np.array([0.15, 0.2, 0.25])
    u = np.array([-0.3, 0.1, 0.4])
    sigma = cal.relaxation_length(L, u)
    assert_allclose(sigma, n * L * (1.0 + b * np.abs(u)), rtol=1e-12)
    dy = u * L
    assert_allclose(np.tan(cal.slip_angle(dy, L)), dy / sigma, rtol=1e-12)


# ------------------------------------------------------------------------------- diagnose: a guard decides
def test_the_level_out_guard_refuses_a_law_that_worsens_held_out_load_levels():
    # 5 loads (two above the rating, so a knee is testable) x 2 repeats, a power-law friction truth with sweep
    # offsets: the overload laws fit the training levels but predict a held-out interior load level worse; the
    # level-out guard must refuse them, and
    # nothing confirmed or accepted may worsen a held-out level (the invariant the slow suite checks at scale)
    import importlib
    import sys
    from pathlib import Path

    from tyrefit.diagnose import diagnose

    sys.path.insert(0, str(Path(__file__).parent))
    forms = importlib.import_module("diag_forms")
    d, rated, _ = forms.make("load_friction", "offsets", seed=2, layout="repeated", n_loads=5, repeats=2,
                             above_rated=2)
    dg = diagnose(d, rated_load=rated, seed=2)
    refused = {k for k, c in dg.candidates.items() if c.reason.startswith("worse on held-out condition levels")}
    assert "overload" in refused, {k: (c.status, c.reason) for k, c in dg.candidates.items()}
    for k, c in dg.candidates.items():
        if c.status.startswith(("confirmed", "accepted")) or k in dg.accepted:
            assert not (c.delta_levelout < 0), (k, c.status, c.delta_levelout)
    assert not any(dg.candidates[k].family == "overload" for k in dg.accepted), dg.accepted
