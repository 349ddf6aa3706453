"""Rig and simulation: tests for the sampled mutants that survived the quick suite (issue 25's mutation run).

``nice python -m benchmarks.mutation --sample 216 --seed 15`` (12 mutants per module) left these
mutants alive; each test states documented behaviour or physics, not the mutated text.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from tyrefit.nomenclature import G0
from tyrefit.rig.patch import exp_rise, fit_exp_rise, fit_patch, fit_two_gradient, two_gradient


# ------------------------------------------------------------------------------ tyrefit/rig/patch.py
def test_the_rmse_of_a_two_gradient_fit_is_that_of_its_residuals():
    rng = np.random.default_rng(4)
    x = np.linspace(0.0, 10.0, 41)
    y = two_gradient(x, 0.5, 1.0, 3.0, 6.3) + 0.05 * rng.standard_normal(x.size)
    fit = fit_two_gradient(x, y)
    assert fit.rmse == pytest.approx(math.sqrt(np.mean((y - fit(x)) ** 2)), rel=1e-9)


def test_the_rmse_of_a_width_law_fit_is_that_of_its_residuals():
    rng = np.random.default_rng(5)
    x = np.linspace(5e3, 8e4, 16)
    y = exp_rise(x, 0.31, 2.2e4) + 0.002 * rng.standard_normal(x.size)
    fit = fit_exp_rise(x, y)
    assert fit.rmse == pytest.approx(math.sqrt(np.mean((y - fit(x)) ** 2)), rel=1e-9)
    assert fit.rmse < 0.004


@pytest.mark.parametrize("fraction", [0.5, 0.9, 0.99])
def test_the_saturation_load_is_where_the_width_reaches_that_fraction_of_the_shoulder_width(fraction):
    x = np.linspace(5e3, 8e4, 16)
    fit = fit_exp_rise(x, exp_rise(x, 0.31, 2.2e4))
    assert fit(fit.saturation_load(fraction)) == pytest.approx(fraction * fit.y_max, rel=1e-9)


@pytest.fixture(scope="module")
def truck_patch():
    from tyrefit.synthetic import truck as T

    df = T.patch_table(T.TYRE_A, np.random.default_rng(0), loads_kg=tuple(range(500, 10001, 500)))
    data = pd.DataFrame({"load": df["load [kg]"] * G0, "pressure": df["pressure [bar]"] * 1e5,
                         "length": df["length [mm]"] * 1e-3, "width": df["width [mm]"] * 1e-3,
                         "area": df["area [cm2]"] * 1e-4})
    return fit_patch(data), data


def test_the_patch_table_gradients_are_the_fitted_laws_slopes_in_mm_per_tonne(truck_patch):
    model, _ = truck_patch
    t = model.table()
    for f, (_, row) in zip(model.fits, t.iterrows()):
        lo, hi = 0.3 * f.length.breakpoint, 1.5 * f.length.breakpoint   # well below and above the knee
        tonne = 1000.0 * G0
        below = 1e3 * (f.length(lo + tonne) - f.length(lo))
        above = 1e3 * (f.length(hi + tonne) - f.length(hi))
        assert row["dL/dF below [mm/t]"] == pytest.approx(below, rel=1e-9)
        assert row["dL/dF above [mm/t]"] == pytest.approx(above, rel=1e-9)


def test_the_patch_plot_draws_the_laws_over_every_tested_load(truck_patch):
    model, data = truck_patch
    axes = model.plot(data)
    hi = model.load_range()[1] / G0
    for ax in axes:
        curves = [ln for ln in ax.get_lines() if ln.get_linestyle() == "-"]
        assert curves and all(np.max(ln.get_xdata()) >= hi for ln in curves)


# ------------------------------------------------------------------------------ tyrefit/rig/conversion.py
def test_a_calibration_keeps_its_slip_angle_range_through_json():
    from tyrefit.rig.conversion import RigCalibration

    cal = RigCalibration(n=1.7, b=0.4, u_range=(0.01, 0.6), fz_range=(1e4, 5e4),
                         slip_angle_range=(math.radians(0.5), math.radians(7.0)))
    back = RigCalibration.from_dict(cal.to_dict())
    assert back.slip_angle_range == pytest.approx(cal.slip_angle_range, rel=1e-12)
    assert back.u_range == pytest.approx(cal.u_range) and back.fz_range == pytest.approx(cal.fz_range)


def test_the_rolling_curves_follow_a_magic_formula_of_low_shape_factor():
    # fit_dynamic_curves: one Magic Formula on mu per sweep, D, C, K, E free within physical bounds; a tyre
    # of low shape factor (C = 1.1: a flat-topped, slowly falling curve) is one of them
    from tyrefit.models.pac89 import magic_formula
    from tyrefit.rig.conversion import fit_dynamic_curves

    a = np.linspace(-12.0, 12.0, 97)
    sweeps = [(2e4, 1.1), (4e4, 1.15), (6e4, 1.2)]
    D, K, E = 0.9, 0.3, -0.5
    rows = [pd.DataFrame({"run": run, "slip_angle": np.radians(a), "fz": fz,
                          "fy": -magic_formula(a, K / (C * D), C, D, E) * fz}) for run, (fz, C) in enumerate(sweeps)]
    dyn = fit_dynamic_curves(pd.concat(rows, ignore_index=True))
    # noiseless sweeps: each one's own Magic Formula is recovered (C 1.1-1.2 lies inside the fit's bounds)
    assert np.all(dyn.rmse < 1e-6)
    np.testing.assert_allclose(dyn.C, [C for _, C in sweeps], rtol=1e-4)
    for fz, C in sweeps:
        np.testing.assert_allclose(dyn.mu(np.radians(a[a > 0]), fz), magic_formula(a[a > 0], K / (C * D), C, D, E),
                                   atol=1e-6)


def test_ten_static_samples_inside_the_dynamic_range_are_enough_to_calibrate():
    # calibrate(): "fewer than 10 static samples map inside the dynamic slip range" is refused; ten are not
    import dataclasses

    from tyrefit.io.datasets import data_path
    from tyrefit.io.readers import read_data
    from tyrefit.rig.conversion import calibrate, fit_dynamic_curves
    from tyrefit.rig.static import analyse_static

    static, dynamic, patch = (read_data(data_path("truck", f"tyre_a_{k}.csv")) for k in ("static", "dynamic", "patch"))
    sa = analyse_static(static)
    dyn = fit_dynamic_curves(dynamic)
    rising = sa.df[(sa.df["part"] == "rising") & (sa.df["mu"] > 0)]
    mid = rising[np.abs(rising["fz"] - np.median(dyn.fz)) < 0.2 * np.median(dyn.fz)]
    ten = mid.sort_values("lateral_displacement", key=np.abs).index[:10]
    sub = dataclasses.replace(sa, df=sa.df.loc[ten.union(sa.df.index[sa.df["part"] != "rising"])])
    cal = calibrate(sub, dynamic, patch)
    assert cal.points == 10
    # the load window is closed: a sample exactly at the lowest dynamic load less the 15 % tolerance is inside
    lo = dyn.fz.min() * (1 - 0.15)
    edge = sub.df.copy()
    edge.loc[ten[0], "fz"] = lo
    assert calibrate(dataclasses.replace(sub, df=edge), dynamic, patch, static_fz_tolerance=0.15).points == 10


# ------------------------------------------------------------------------------ tyrefit/sim/allocator.py
def _curve(axles, speed, radius, demand=None):
    from tyrefit.sim.allocator import AxleLimits, PeakShareSlipLimit, WearAwareAllocator
    from tyrefit.sim.emission import DEFAULT_EMISSION
    from tyrefit.sim.vehicle import DEFAULT_VEHICLE as P, VehicleModel

    m = VehicleModel(P, axles["hard_f"], axles["soft_r"], [1.0])
    x = m.rolling_state(np.array([speed]))
    steer = np.array([P.wheelbase / radius])
    x[5] = speed / radius
    x[4] = P.lr * x[5] - speed * 0.01
    lim = {k: AxleLimits(v, PeakShareSlipLimit()(v), m.condition) for k, v in axles.items()}
    alloc = WearAwareAllocator(m, axles["soft_f"], lim["soft_f"], lim["soft_r"], lim["hard_f"], lim["soft_r"],
                               DEFAULT_EMISSION.axle(2), k=0.26)
    demand = np.array([P.drag * speed**2 if demand is None else demand])
    bx, by, af = alloc.base_body_forces(x, steer, demand)
    return alloc, x, steer, demand, bx, by, af


def test_greedy_search_moves_only_to_a_strictly_lower_value():
    # seed 000's Alg. 1: move to the lower neighbour if it is lower than f(x), else halve the step
    from tyrefit.sim.allocator import greedy_search

    flat = lambda x: np.maximum(np.abs(x) - 1.0, 0.0)  # noqa: E731 - a plateau |x| <= 1
    x, f, _ = greedy_search(flat, np.array([0.0, 0.5]), np.array([0.1, 0.1]), tol=1e-6)
    np.testing.assert_array_equal(x, [0.0, 0.5])
    np.testing.assert_array_equal(f, 0.0)


@pytest.mark.parametrize("speed, radius", [(8.33, 31.9), (16.7, 127.5)])
def test_the_allocators_steering_correction_minimises_the_emission_objective(axles, speed, radius):
    from scipy.optimize import minimize_scalar

    alloc, x, steer, demand, bx, by, af = _curve(axles, speed, radius)
    _, _, d = alloc(0, 0.0, x, steer, demand)
    fun = lambda v: float(alloc.objective(np.atleast_1d(v), steer, af, bx, by)[0])  # noqa: E731
    ref = minimize_scalar(fun, bracket=(d[0] - 0.01, d[0] + 0.01), tol=1e-12)
    assert fun(d[0]) <= ref.fun * (1 + 1e-6)


def test_the_steering_objective_penalises_either_axle_outside_either_of_its_limits(axles):
    # Eq. 34 with limit penalties: a split that puts an axle outside its force limits costs more than its
    # emission, whichever limit (lower or upper) of whichever axle (front or rear) it crosses
    from tyrefit.sim.allocator import steering_split

    alloc, x, steer, demand, bx, by, af = _curve(axles, 16.7, 127.5, demand=-1.5e4)
    seen = set()
    for d in np.linspace(-0.3, 0.3, 601):
        dd = np.array([d])
        ff, fr, _ = steering_split(dd, steer=steer, alpha_f=af, body_x=bx, body_y=by, hard_front=alloc.front.axle,
                                   condition=alloc.model.condition)
        out = {("front", "lower"): ff[0] < alloc.front.lower[0], ("front", "upper"): ff[0] > alloc.front.upper[0],
               ("rear", "lower"): fr[0] < alloc.rear.lower[0], ("rear", "upper"): fr[0] > alloc.rear.upper[0]}
        extra = float(alloc.objective(dd, steer, af, bx, by)[0] - alloc.emission(ff, fr)[0])
        if any(out.values()):
            assert extra > 0, (d, out)
            seen |= {k for k, v in out.items() if v}
        else:
            assert extra == pytest.approx(0.0, abs=1e-12)
    assert ("rear", "lower") in seen


def test_the_uncalibrated_identity_claims_no_range_of_u():
    # UNCALIBRATED: Eq. 1 with f = 1 for any displacement, u = Delta y / L from 0 up
    from tyrefit.rig.conversion import UNCALIBRATED, RigCalibration

    assert UNCALIBRATED.u_range == (0.0, math.inf) and RigCalibration().u_range == (0.0, math.inf)
    assert UNCALIBRATED.to_dict()["valid_range"]["u"] == [0.0, math.inf]
