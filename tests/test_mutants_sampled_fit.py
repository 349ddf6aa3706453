"""Fitting: tests for the sampled mutants that survived the quick suite (issue 25's mutation run).

``nice python -m benchmarks.mutation --sample 216 --seed 15`` (12 mutants per module) left these
mutants alive; each test states documented behaviour (the module docstrings' costs, standard errors
and back ends), not the mutated text.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tyrefit.fitting.core import Parameter, Parameters, lm_normal, solve

ROOT_DATA = Path(__file__).resolve().parent / "data"


def _line(n=40, seed=3, outliers=True):
    rng = np.random.default_rng(seed)
    x = np.linspace(-1.0, 1.0, n)
    y = 0.4 + 1.7 * x + 0.02 * rng.standard_normal(n)
    if outliers:
        y[::9] += 0.8
    return x, y


def _pars():
    p = Parameters()
    p.add("a", 0.0)
    p.add("b", 1.0)
    return p


# ------------------------------------------------------------------------------ tyrefit/fitting/core.py
def test_a_parameter_without_bounds_is_unbounded():
    # the class docstring: hard bounds, -inf / inf for none
    p = Parameter("k", 2.0, min=None, max=None)
    assert p.min == -np.inf and p.max == np.inf


def test_weighted_soft_l1_with_per_point_scales_minimises_the_documented_cost():
    # module docstring: 'soft_l1' minimises sum w_i s_i^2 rho((r_i / s_i)^2), rho(z) = 2 (sqrt(1 + z) - 1)
    from scipy.optimize import minimize

    x, y = _line()
    w = np.where(x > 0, 2.0, 1.0)
    s = np.full(x.size, 0.05)

    def cost(q):
        z = ((q[0] + q[1] * x - y) / s) ** 2
        return float(np.sum(w * s**2 * 2.0 * (np.sqrt(1.0 + z) - 1.0)))

    sol = solve(lambda q: q[0] + q[1] * x - y, _pars(), cost="soft_l1", weights=w, scale=s)
    ref = minimize(cost, [0.0, 1.0], method="Nelder-Mead", options={"xatol": 1e-10, "fatol": 1e-14})
    assert sol.cost == pytest.approx(cost(sol.x), rel=1e-9)
    assert sol.cost <= ref.fun * (1 + 1e-7)
    assert_allclose(sol.x, ref.x, atol=1e-4)


def _lin_fun_jac(x, y, calls=None):
    def fun_jac(q):
        if calls is not None:
            calls["fun_jac"] += 1
        return q[0] + q[1] * x - y, np.column_stack([np.ones_like(x), x])

    def fun(q):
        if calls is not None:
            calls["fun"] += 1
        return q[0] + q[1] * x - y

    return fun, fun_jac


def test_lm_normal_and_trf_give_the_same_weighted_solution_and_standard_errors():
    # module docstring: both back ends take the same weights and give the same Solution; for a
    # straight line the weighted least-squares solution and its Gauss-Newton errors are closed-form
    x, y = _line(outliers=False)
    w = np.linspace(0.5, 2.0, x.size)
    fun, fun_jac = _lin_fun_jac(x, y)
    trf = solve(fun, _pars(), weights=w)
    lmn = solve(fun, _pars(), weights=w, fun_jac=fun_jac, method="lm-normal")
    A = np.column_stack([np.ones_like(x), x])
    sw = np.sqrt(w)
    beta = np.linalg.lstsq(A * sw[:, None], y * sw, rcond=None)[0]
    r = A @ beta - y
    s2 = float(np.sum(w * r * r)) / (x.size - 2)
    se = np.sqrt(np.diag(s2 * np.linalg.inv((A * w[:, None]).T @ A)))
    for sol in (trf, lmn):
        assert_allclose(sol.x, beta, rtol=1e-6)
        assert sol.s2 == pytest.approx(s2, rel=1e-6)
        assert_allclose([sol.stderr["a"], sol.stderr["b"]], se, rtol=1e-5)


def test_the_residual_variance_does_not_depend_on_asking_for_standard_errors():
    # s^2 = sum w r^2 / (N - p) (module docstring), with or without the standard errors
    x, y = _line()
    w = np.linspace(0.5, 2.0, x.size)
    fun, _ = _lin_fun_jac(x, y)
    a = solve(fun, _pars(), weights=w)
    b = solve(fun, _pars(), weights=w, stderr=False)
    assert b.s2 == pytest.approx(a.s2, rel=1e-9)
    assert b.s2 == pytest.approx(float(np.sum(w * b.resid**2)) / (x.size - 2), rel=1e-12)


def test_lm_normal_counts_every_evaluation_and_keeps_to_max_nfev():
    # lm_normal returns (x, evaluations, converged): the start's evaluation and one per trial step
    x = np.linspace(0.0, 3.0, 30)
    y = 2.0 * np.exp(-1.3 * x)
    calls = {"fun": 0, "fun_jac": 0}

    def fun(q):
        calls["fun"] += 1
        return q[0] * np.exp(-q[1] * x) - y

    def jac(q):
        calls["fun_jac"] += 1
        e = np.exp(-q[1] * x)
        return q[0] * e - y, np.column_stack([e, -q[0] * x * e])

    lo, hi = np.array([0.0, 0.0]), np.array([10.0, 10.0])
    for max_nfev in (3, 200):
        calls.update(fun=0, fun_jac=0)
        q, n, ok = lm_normal(jac, fun, np.array([1.0, 0.5]), lo, hi, np.ones(2), max_nfev)
        assert n == 1 + calls["fun"] <= max_nfev
    assert ok
    assert_allclose(q, [2.0, 1.3], rtol=1e-6)


def test_lm_normal_takes_the_same_steps_whatever_the_unit_of_the_residuals():
    """core.py [313] ``lm_normal`` (the gain ratio rho = 0 when the predicted fall is <= 1, not <= 0).

    Marquardt's damping on the scaled normal equations and Nielsen's update from the gain ratio
    (actual / predicted fall of the cost) make Levenberg-Marquardt blind to the unit of the residuals:
    an exponential fit in N, in kN or in mN (a PAC89 fit on mu has costs far below 1) takes the same
    evaluations to the same minimum, the least-squares solution of scipy's own solver.  The mutant
    reads every step of a cost under 1 as a bad one and doubles the damping: on the small scale it
    stops at a = 0.33 instead of 2.03 (33 evaluations), on the unit scale short of the minimum.
    """
    from scipy.optimize import least_squares

    x = np.linspace(0.0, 3.0, 30)
    y0 = 2.0 * np.exp(-1.3 * x) + 0.05 * np.random.default_rng(1).standard_normal(x.size)
    ref = least_squares(lambda q: q[0] * np.exp(-q[1] * x) - y0, [0.2, 4.0], xtol=1e-15, ftol=1e-15, gtol=1e-15).x
    out = {}
    for c in (1e-3, 1.0, 1e3):
        y = c * y0

        def fun(q, y=y):
            return q[0] * np.exp(-q[1] * x) - y

        def jac(q, y=y):
            e = np.exp(-q[1] * x)
            return q[0] * e - y, np.column_stack([e, -q[0] * x * e])

        q, n, ok = lm_normal(jac, fun, np.array([0.2 * c, 4.0]), np.array([0.0, 0.0]), np.array([10.0 * c, 10.0]),
                             np.array([c, 1.0]), 200)
        assert ok
        out[c] = (q / [c, 1.0], n)
    assert out[1e-3][1] == out[1.0][1] == out[1e3][1]
    for c in out:
        assert_allclose(out[c][0], ref, rtol=1e-7)


# ------------------------------------------------------------------------------ tyrefit/fitting/engine.py
@pytest.fixture(scope="module")
def lateral_sweeps_example():
    from tyrefit.synthetic.pac89_example import lateral_sweeps

    return lateral_sweeps()


def test_missing_camber_values_are_read_as_zero_camber(lateral_sweeps_example):
    # fit_pac89's data: camber optional; a missing value is no camber (0 rad), not some other angle
    from tyrefit.fitting.engine import prepare_data

    df = lateral_sweeps_example[np.isclose(lateral_sweeps_example["camber"], 0.0)].copy()
    parts, _ = prepare_data(df)
    df["camber"] = np.nan
    parts_nan, _ = prepare_data(df)
    np.testing.assert_array_equal(parts_nan["lateral"].camber, 0.0)
    np.testing.assert_array_equal(parts_nan["lateral"].camber, parts["lateral"].camber)


def test_an_explicit_vary_list_of_identifiable_names_is_not_reported_as_held(lateral_sweeps_example):
    # fit_pac89(vary=...): names the data cannot identify are held and reported; these all can be fitted
    from tyrefit.fitting import fit_pac89

    r = fit_pac89(lateral_sweeps_example, vary=["a0", "a2", "a3", "a4", "a7"])
    assert not [n for n in r.notes if "not identifiable" in n], r.notes


def test_b1_is_fitted_from_two_load_levels():
    # engine module docstring, identifiability: b1 (D's load curvature) needs >= 2 load levels
    from tyrefit.fitting import fit_pac89
    from tyrefit.synthetic.pac89_example import longitudinal_sweeps

    r = fit_pac89(longitudinal_sweeps(loads=(3000.0, 7000.0)))
    assert "b1" not in r.not_identifiable
    assert {"b3", "b7", "b5", "b6"} <= set(r.not_identifiable)


def test_a_fixed_quadratic_e_coefficient_of_fx_is_kept():
    # fit_pac89(fixed=...): coefficients held at these values (the E <= 1 refit frees only a b6 it fitted)
    from tyrefit.fitting import fit_pac89
    from tyrefit.synthetic.pac89_example import longitudinal_sweeps

    # b6 = 0.2 /kN^2 puts E above 1 at both ends of the 2-8 kN range: still the user's value
    r = fit_pac89(longitudinal_sweeps(), fixed={"b6": 0.2})
    assert r.tyre.coefficients["b6"] == 0.2


# ------------------------------------------------------------------------------ tyrefit/fitting/initial.py
def _mf(x, B, C, D, E):
    return D * np.sin(C * np.arctan(B * x - E * (B * x - np.arctan(B * x))))


def test_the_bcd_estimate_is_the_slope_over_0_to_2_deg_inclusive():
    # Komana et al.'s BCD: the slope of mu over |slip| <= 2 deg; a sweep at whole degrees has 5 such points
    from tyrefit.fitting.initial import estimate_sweep

    x = np.arange(-12.0, 12.5, 1.0)
    mu = _mf(x, 0.25, 1.4, 1.1, -0.5)
    near = np.abs(x) <= 2.0
    e = estimate_sweep(x, mu)
    assert e.BCD == pytest.approx(np.polyfit(x[near], mu[near], 1)[0], rel=1e-12)


def test_the_aligning_slope_start_is_the_slope_over_0_to_2_deg_inclusive():
    # aligning_initial: |BCD|/Fz = |c4| from the 0-2 deg slope of Mz/Fz [N m/kN]
    import pandas as pd

    from tyrefit.fitting.initial import aligning_initial

    a = np.arange(-10.0, 10.5, 1.0)
    mz = 4000.0 * 1e-3 * 30.0 * np.sin(2.3 * np.arctan(0.3 * a))  # N m: a sin-shaped Mz sweep at 4 kN
    df = pd.DataFrame({"run": 0, "fz": 4000.0, "slip_angle": np.radians(a), "mz": mz})
    c = aligning_initial(df, x_scale=np.degrees(1.0))
    near = np.abs(a) <= 2.0
    assert abs(c["c4"]) == pytest.approx(abs(np.polyfit(a[near], mz[near] / 4.0, 1)[0]), rel=1e-9)


def test_the_lateral_start_of_a3_is_near_the_peak_cornering_stiffness_of_the_data(lateral_sweeps_example):
    # a3 [N/deg] is the peak of BCD(Fz) = a3 sin(2 atan(Fz/a4)): the Eq. 2-4 start must be of the data's order
    from tyrefit.fitting.initial import estimate_sweeps, lateral_initial
    from tyrefit.synthetic.pac89_example import EXAMPLE

    est = estimate_sweeps(lateral_sweeps_example, "slip_angle", "fy", x_scale=np.degrees(1.0))
    c = lateral_initial(est)
    assert c["a3"] == pytest.approx(EXAMPLE["a3"], rel=0.25)
    assert c["a4"] == pytest.approx(EXAMPLE["a4"], rel=0.5)


def test_the_longitudinal_bcd_law_is_regressed_on_three_close_loads():
    # longitudinal_initial: BCD/Fz = b3 Fz + b4 from >= 3 load levels, however close (FSAE: 0.2-0.7 kN)
    import pandas as pd

    from tyrefit.fitting.initial import longitudinal_initial

    fz = np.array([200.0, 450.0, 700.0])
    bcd_per_fz = 0.030 - 0.012 * fz * 1e-3  # the sweeps' mu slopes [1/%], i.e. BCD / Fz
    est = pd.DataFrame({"fz": fz, "camber": 0.0, "has_peak": True, "C": 1.6, "D": 1.5, "E": 0.2,
                        "BCD": bcd_per_fz, "x_m": 8.0})
    c = longitudinal_initial(est)
    assert c["b3"] * fz * 1e-3 + c["b4"] == pytest.approx(bcd_per_fz * 1e3, rel=1e-9)


# ------------------------------------------------------------------------------ tyrefit/fitting/mf.py
def test_the_friction_ceiling_is_held_just_below_each_of_its_steps():
    # MuCeiling.steps: the loads where the ceiling steps (each sweep's load / 1.1) and just below them,
    # where the ceiling is still the lower one and a friction-load law rising with load meets it first
    from tyrefit.fitting.mf import MuCeiling

    cap = MuCeiling(np.array([2000.0, 4000.0, 6000.0]), np.array([1.6, 1.8, 2.0]))
    pts = cap.steps()
    for f in (2000.0, 4000.0, 6000.0):
        s = f / 1.1
        assert np.any(np.isclose(pts, s, rtol=1e-12))
        below = pts[(pts < s) & (pts > s * (1 - 1e-4))]
        assert below.size == 1
        assert cap(below)[0] < cap(np.array([s]))[0] or f == 2000.0  # the lightest: unbounded below


def _grid_points():
    fz = np.array([1000.0, 3000.0, 4000.0, 6000.0, 9000.0])
    dpi = np.array([-0.2, 0.0, 0.1, 0.2, 0.3])
    gamma = np.radians([-4.0, 0.0, 2.0, 4.0, 6.0])
    sgn = np.array([1.0, -1.0, 1.0, -1.0, 1.0])
    return fz, dpi, gamma, sgn


def test_the_fx0_friction_constraint_is_pacejkas_mu_x():
    # _factors Fx0: mu_x (Pacejka 2012, 4.E13) = (PDX1 + PDX2 dfz)(1 + PPX3 dpi + PPX4 dpi^2)(1 - PDX3 gamma^2)
    from tyrefit.fitting.mf_contract import _factors
    from tyrefit.models import mf61

    p = {k.upper(): float(v) for k, v in mf61.neutral().items()}
    p.update(FNOMIN=4000.0, PDX1=1.2, PDX2=-0.15, PDX3=3.0, PPX3=-0.3, PPX4=0.2)
    fz, dpi, gamma, sgn = _grid_points()
    dfz = (fz - 4000.0) / 4000.0
    want = (1.2 - 0.15 * dfz) * (1 - 0.3 * dpi + 0.2 * dpi**2) * (1 - 3.0 * gamma**2)
    got = dict((n, v) for n, v, _ in _factors(p, "Fx0", fz, dpi, gamma, sgn))["mu_x > 0"]
    assert_allclose(got, want, rtol=1e-12)


def test_the_fy0_friction_constraint_is_pacejkas_mu_y():
    # _factors Fy0: mu_y (Pacejka 2012, 4.E23) = (PDY1 + PDY2 dfz)(1 + PPY3 dpi + PPY4 dpi^2)(1 - PDY3 gamma^2)
    from tyrefit.fitting.mf_contract import _factors
    from tyrefit.models import mf61

    p = {k.upper(): float(v) for k, v in mf61.neutral().items()}
    p.update(FNOMIN=4000.0, PDY1=1.1, PDY2=-0.12, PDY3=4.0, PPY3=-0.2, PPY4=0.1)
    fz, dpi, gamma, sgn = _grid_points()
    dfz = (fz - 4000.0) / 4000.0
    want = (1.1 - 0.12 * dfz) * (1 - 0.2 * dpi + 0.1 * dpi**2) * (1 - 4.0 * gamma**2)
    got = dict((n, v) for n, v, _ in _factors(p, "Fy0", fz, dpi, gamma, sgn))["mu_y > 0"]
    assert_allclose(got, want, rtol=1e-12)


def test_the_rvy4_bound_note_evaluates_cos_atan_rvy4_alpha_in_radians():
    # 4.E67: the kappa-induced side force fades as cos(atan(RVY4 alpha)), alpha in rad
    from types import SimpleNamespace

    from tyrefit.fitting.mf import _bound_note

    fits = {"Fy": SimpleNamespace(facts={"levels": {"slip_angle": list(np.radians([-4.0, 0.0, 4.0, 8.0]))}})}
    note = _bound_note("RVY4", 100.0, "upper", "Fy", fits)
    f = 1.0 / np.sqrt(1.0 + (100.0 * np.radians(4.0)) ** 2)
    assert f"= {f:.2g} at 4 deg" in note, note


# ------------------------------------------------------------------------------ tyrefit/models/mf61.py
def test_lmuv_lowers_lateral_friction_as_pacejkas_slip_speed_law():
    # 4.E7: mu_y* = LMUY / (1 + LMUV Vs / V0), Vs the slip speed (|tan alpha| Vcx in pure side slip):
    # with LMUV = 0.3 the force is that of LMUV = 0 and LMUY scaled by 1 / (1 + 0.3 Vs / V0)
    from tyrefit.io.tir import read_tyre
    from tyrefit.models import mf61

    p = dict(read_tyre(ROOT_DATA / "mfeval_MagicFormula61_Paramerters.tir").params)
    v0 = p["LONGVL"]
    alpha = np.radians([1.0, 4.0, 8.0, 12.0])
    for v in (0.5 * v0, 2.0 * v0):
        vs = np.abs(np.tan(alpha)) * v
        with_v = mf61.fy0({**p, "LMUV": 0.3}, 4000.0, alpha, speed=v)
        scaled = [float(mf61.fy0({**p, "LMUV": 0.0, "LMUY": p.get("LMUY", 1.0) / (1 + 0.3 * s / v0)}, 4000.0, a,
                                 speed=v)) for a, s in zip(alpha, vs)]
        assert_allclose(with_v, scaled, rtol=1e-9)


def test_a_parameter_made_without_a_value_starts_where_parameters_add_starts_it():
    p = Parameters()
    assert Parameter("x").value == p.add("x").value == 0.0


def _published_sweeps(loads, **kw):
    """Sweeps of the published MF 6.1 set at ``loads`` (fractions of its FNOMIN), its tyre info and FNOMIN."""
    from tyrefit.synthetic import ttc_drivebrake as gen

    fnomin = gen.PUBLISHED_MF61["FNOMIN"]
    info = {"fnomin": fnomin, "unloaded_radius": gen.PUBLISHED_MF61["UNLOADED_RADIUS"]}
    df = gen.make_sweeps(gen.contract_mf61(), pressures=[260e3], loads=[f * fnomin for f in loads], **kw)
    return df, info, fnomin


def test_the_fx0_stage_holds_friction_under_the_data_ceiling_at_every_grid_load():
    # _factors: Fx0 given the ceiling at each grid load, |mu_x| <= cap; the stage reports that constraint's
    # worst margin cap - |mu_x| over its grid, which cannot exceed the ceiling, 1.15 x the data's peak |F|/Fz
    from tyrefit.fitting.mf import MU_CAP, fit_mf

    df, info, _ = _published_sweeps([0.4, 1.0, 1.6], seed=41, cambers_deg=[0.0], slip_angles_deg=[0.0], n_points=31,
                                    kappa_max=0.12)
    r = fit_mf(df, tyre_info=info, stages=["Fx0"])
    row = next(c for c in r.stages["Fx0"].constraints if c["constraint"] == MU_CAP.format(axis="x"))
    assert row["holds"] and 0.0 <= row["worst"] <= 1.15 * float((df["fx"].abs() / df["fz"]).max())


def test_camber_curvature_terms_are_fitted_from_two_camber_levels_at_two_loads():
    # identifiability: PEY5, PKY5, QDZ4, QSY6 need >= 3 levels of |camber|, or 2 with >= 2 loads
    from tyrefit.fitting.mf import _STAGE, identifiability, prepare_mf_data

    df, _, fnomin = _published_sweeps([0.5, 1.5], seed=5, cambers_deg=[0.0, 3.0], slip_angles_deg=[0.0, -3.0],
                                      n_points=13)
    data = prepare_mf_data(df)
    st = _STAGE["Fy0"]
    why, facts = identifiability(st, data.subset(st.sweeps, st.channel), data.sweeps, version="6.1")
    assert (facts["load_levels"], facts["abs_camber_levels"]) == (2, 2)
    assert "PKY5" not in why and "PEY5" not in why
    one_load = df[df["fz"] < fnomin]
    data1 = prepare_mf_data(one_load)
    why1, _ = identifiability(st, data1.subset(st.sweeps, st.channel), data1.sweeps, version="6.1")
    assert "PKY5" in why1


def test_each_stage_reports_the_time_it_took_within_the_whole_fit():
    """mf.py [352] ``_joint_polish`` (its StageFit's seconds = time.perf_counter(), "- t0" deleted).

    Every stage's ``seconds`` is the time that stage took: non-negative, and together no more than the
    whole fit's ``seconds`` (the stages run one after the other inside it).  The mutant reports the joint
    polish's time as the clock's reading (hours since boot) in the stage table and the summary.
    """
    from tyrefit.fitting.mf import fit_mf

    df, info, _ = _published_sweeps([0.5, 1.0, 1.5], seed=3, cambers_deg=[0.0], slip_angles_deg=[0.0], n_points=15,
                                    combined=False)
    r = fit_mf(df, tyre_info=info, stages=["Fy0", "Mz0", "joint", "Mx"], multistart=False)
    assert set(r.stages) == {"Fy0", "Mz0", "joint", "Mx"} and r.stages["joint"].varied
    times = {k: s.seconds for k, s in r.stages.items()}
    assert all(t >= 0.0 for t in times.values()), times
    assert sum(times.values()) <= r.seconds, (times, r.seconds)


def test_the_nominal_pressure_is_the_datas_pressure_level_to_100_pa():
    """mf.py [1118] ``_nominal`` (NOMPRES = np.round(median level, 2) instead of -2: to 0.01 Pa, not 100 Pa).

    Without a nominal pressure in the tyre data, NOMPRES (and INFLPRES) is the records' middle pressure
    level rounded to 100 Pa, as FNOMIN is the middle load rounded to 10 N: a rig that holds 2.4 bar and
    measures 240 020 +- 30 Pa gives NOMPRES = 240000, not the measured mean's 240019.87 in the .tir.
    """
    from tyrefit.fitting.mf import fit_mf

    df, info, _ = _published_sweeps([0.6, 1.4], seed=3, cambers_deg=[0.0], slip_angles_deg=[0.0], n_points=11,
                                    combined=False)
    df = df.assign(pressure=240e3 + 20.0 + 30.0 * np.random.default_rng(0).standard_normal(len(df)))
    assert abs(df.groupby("run")["pressure"].mean().mean() - 240020.0) < 10.0
    r = fit_mf(df, tyre_info=info, stages=["Fy0"], multistart=False)
    assert r.params["NOMPRES"] == r.params["INFLPRES"] == 240000.0


def test_a_slip_at_exactly_half_the_largest_counts_on_neither_side():
    """engine.py [328] ``identifiability`` (``x < -0.5 * xmax`` -> ``<=``: a negative point at exactly half counts).

    The module docstring's rule: the shift and camber-asymmetry coefficients need both slip signs *reaching
    beyond* half the largest |slip| (>= 3 points each side, the same strict test on both sides).  A sweep with
    4 points past +half but only 2 past -half and one exactly at -half does not qualify; the mutant counts the
    one at -half on the negative side only, calls the data two-sided and fits a8/a10/a13 from 2 points.
    """
    import pandas as pd

    from tyrefit.fitting.engine import identifiability, prepare_data

    # dyadic slips: x = slip x 180/pi is exactly -0.5 x max|x| at slip = -2**-5
    pos = np.array([1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 12.0, 14.0, 16.0]) * 2.0**-8
    slip = np.concatenate([-np.array([16.0, 12.0, 8.0, 4.0, 2.0]) * 2.0**-8, [0.0], pos])
    df = pd.DataFrame({"run": 1, "fz": 3000.0, "camber": 0.0, "slip_angle": slip,
                       "fy": -3000.0 * np.sin(1.3 * np.arctan(12.0 * slip))})
    why, facts = identifiability(prepare_data(df, screen=False)[0]["lateral"])
    assert (facts["points_pos"], facts["points_neg"]) == (4, 2), facts
    assert facts["both_signs"] is False
    assert {"a8", "a10", "a13"} <= set(why)


def test_a_noise_free_sweep_gets_a_positive_robust_scale():
    """engine.py [248] ``robust_scale`` (``sig > 0`` -> ``sig >= 0``: a sweep of zero noise keeps scale 0).

    The robust costs divide each residual by s = 1.345 x the sweep's noise: a sweep whose noise floor is 0
    (a noise-free linear sweep on an even slip grid, e.g. rounded rig data) takes the pooled value, and with
    every sweep at 0 a floor of 1e-3 x the largest force.  The mutant leaves s = 0 there: r / s is infinite
    (or 0 / 0) for every point of the sweep and a huber / soft_l1 fit of it is undefined.
    """
    import pandas as pd

    from tyrefit.fitting.engine import point_scatter, prepare_data, robust_scale

    i = np.arange(-10, 11)
    rows = [pd.DataFrame({"run": k, "fz": fz, "camber": 0.0, "slip_angle": i * 2.0**-7, "fy": -fz / 3.0 * i})
            for k, fz in ((1, 3000.0), (2, 6000.0))]
    d = prepare_data(pd.concat(rows, ignore_index=True), screen=False)[0]["lateral"]
    pooled, per = point_scatter(d)
    assert pooled == 0.0 and (per == 0.0).all()
    s = robust_scale(d)
    assert np.all(np.isfinite(s)) and np.all(s > 0), s
    assert_allclose(s, 1.345 * 1e-3 * 20000.0 / d.norm)


def test_c5_bounds_given_beyond_its_physical_range_are_refused(lateral_sweeps_example):
    """engine.py [362] ``_Problem._direct_bounds`` (c5's upper bound 10 / Fz_hi -> 10 x Fz_hi).

    Mz's BCD carries exp(-c5 Fz); its physical range keeps c5 Fz_hi in [-2, 10] (bounds -2/Fz_hi, 10/Fz_hi
    in kN), and fit_pac89(bounds=) refuses bounds outside the physical range with a DataError.  The mutant
    lets c5 reach 10 Fz_hi (80 /kN at 8 kN: exp(-640) at the top load, an Mz slope of zero).
    """
    from tyrefit.errors import DataError
    from tyrefit.fitting import fit_pac89

    d0 = lateral_sweeps_example[np.isclose(lateral_sweeps_example["camber"], 0.0)]
    hi = d0["fz"].max() / 1e3
    with pytest.raises(DataError, match="outside its physical range"):
        fit_pac89(d0, vary=["c0", "c2", "c3", "c4", "c5"], bounds={"c5": (20.0 / hi, 30.0 / hi)})


def test_a_fit_ending_within_a_relative_1e_6_of_a_large_bound_reports_it(lateral_sweeps_example):
    """engine.py [475] ``_fit_part`` (at-bound test ``<= 1e-6 x max(1, |bound|)`` -> ``<= 1e-6``, absolute).

    A coefficient within a relative 1e-6 of its bound has ended there: the fit reports it in ``at_bound``
    and says in the notes that the data want a value beyond it.  The solver stops a few 1e-4 short of a given
    a3 bound of 2457 (the data want 2461); the mutant's absolute 1e-6 misses it, and the fit is reported as
    free of its bounds.
    """
    from tyrefit.fitting import fit_pac89

    d0 = lateral_sweeps_example[np.isclose(lateral_sweeps_example["camber"], 0.0)]
    r = fit_pac89(d0, vary=["a0", "a2", "a3", "a4", "a7"], bounds={"a3": (100.0, 2457.0)})
    assert 0.0 < 2457.0 - r.tyre.coefficients["a3"] <= 1e-6 * 2457.0
    assert "a3" in r.at_bound["lateral"]
    assert any("a3 ended at its upper bound 2457" in n for n in r.notes), r.notes


def test_a_sweep_rising_again_over_its_last_15_percent_takes_the_no_peak_fallback():
    """initial.py [184] ``estimate_sweep`` (``last.sum() >= 3`` -> ``> 3``: a rising tail of 3 points not seen).

    The module docstring's fallback: when the smoothed curve is still rising over the last 15 % of the
    tested slip, Eq. 2 and Eq. 4 have nothing to work on (the peak may lie beyond the range); C takes the
    typical 1.3, E = 0, and the sweep is flagged ``'no peak: fallback'``.  A one-sided sweep 0-12 deg in
    0.75 deg steps has 3 points in its last 15 % (10.5, 11.25, 12 deg); here the force falls after 5 deg and
    climbs again by 0.08 mu over them.  The mutant needs 4 points to see the rise: it takes the early
    maximum as the peak and reports Eq. 2-4 estimates (C 1.24, E -3.5) of a curve that is still rising.
    """
    from tyrefit.fitting.initial import TYPICAL_C, estimate_sweep

    x = np.arange(0.0, 12.0 + 1e-9, 0.75)
    mu = np.sin(1.9 * np.arctan(0.22 * x)) + 0.09 * np.clip(x - 9.75, 0.0, None)
    last = x >= 0.85 * x.max()
    assert last.sum() == 3 and np.all(np.diff(mu[last]) > 0)
    e = estimate_sweep(x, mu)
    assert e.method == "no peak: fallback" and not e.has_peak
    assert (e.C, e.E) == (TYPICAL_C["lateral"], 0.0)
    # the same curve stopped before its rise has a peak: the Eq. 2-4 estimates
    assert estimate_sweep(x[~last], mu[~last]).has_peak


def test_the_fy0_start_puts_the_cornering_stiffness_law_through_the_sweeps_measured_slopes():
    """mf.py [990] ``_initial_pure`` (the PKY2 grid keeps a value when ``res < best[1]``, the PKY2 in hand, not
    the best residual ``best[0]``: no grid value is ever taken).

    The module docstring's initial values: PKY1 and PKY2 from the cornering stiffness against load, with
    PKY4 = 2, i.e. K_y = PKY1 FNOMIN sin(2 atan(Fz / (PKY2 FNOMIN))) (4.E25) fitted to each sweep's measured
    slope BCD x Fz; the report lists these starts in its coefficient table.  On three loads of the published
    MF 6.1 set the start law passes within 3 % of every sweep's measured stiffness.  The mutant never accepts
    a grid point and starts from PKY1 = -2, PKY2 = 20: a cornering stiffness 1 % of the measured one.
    """
    from tyrefit.fitting.mf import fit_mf

    df, info, fnomin = _published_sweeps([0.5, 1.0, 1.5], seed=3, cambers_deg=[0.0], slip_angles_deg=[0.0],
                                         n_points=15, combined=False)
    df = df[["run", "fz", "slip_angle", "slip_ratio", "camber", "pressure", "speed", "fy"]]
    st = fit_mf(df, tyre_info=info, stages=["Fy0"], vary=["PKY1", "PKY2"], multistart=False).stages["Fy0"]
    fz = st.estimates["fz"].to_numpy(float)
    measured = st.estimates["BCD"].to_numpy(float) * 180.0 / np.pi * fz  # N/rad
    pky1, pky2 = st.initial["PKY1"], st.initial["PKY2"]
    assert pky1 < 0  # ISO-W: Fy falls with the slip angle
    start = -pky1 * fnomin * np.sin(2.0 * np.arctan(fz / (pky2 * fnomin)))
    assert_allclose(start, measured, rtol=0.03)
