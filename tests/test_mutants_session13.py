"""Tests for the sampled mutants of a fresh draw that survived the quick suite: issue 25's runner,
``python -m benchmarks.mutation --sample 264 --seed 16`` on the code of 34d42b1 (12 mutants in each of the
22 modules of ``benchmarks/mutation.py::TARGETS``; file, line and site in brackets in each docstring).

Each test states behaviour a user sees - a force or a friction level, a refusal and its message, a file
that must or must not appear, a reported number that must be what its name says - checked against an
independent computation (a finite difference, data generated from known coefficients, the documented
rule), not the mutated text.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose

_DEG = math.pi / 180.0


# ------------------------------------------------------------------------------ tyrefit/models/slip.py
def test_the_friction_slope_is_the_derivative_of_the_friction_curve():
    """slip.py:74 [4] ``friction_slope`` (``mu_p k exp(-k|s|)`` -> ``mu_p k / exp(-k|s|)``).

    The slope a traction controller reads off the friction curve of Ghasemi et al.'s Eq. 8 must be that
    curve's derivative (checked by central differences on both sides of zero slip): the mutant's slope
    grows with slip instead of vanishing at the peak, e^(2k|s|) times too large.
    """
    from tyrefit.models.slip import friction, friction_slope

    mu_p, k = 0.9, 18.0
    s = np.array([-0.4, -0.1, -0.02, 0.005, 0.03, 0.1, 0.25])
    h = 1e-6
    numeric = (friction(s + h, mu_p, k) - friction(s - h, mu_p, k)) / (2 * h)
    assert_allclose(friction_slope(s, mu_p, k), numeric, rtol=1e-6)


def test_the_elasticity_factor_rate_follows_the_slip_it_was_defined_from():
    """slip.py:167 [86] ``elasticity_factor_rate`` (``r0 s_dot - lambda_w T_dot`` -> ``r0 - lambda_w T_dot``).

    With the elasticity factor defined by Eq. 20 from the slip, lambda_w = r0 s / T, its rate (Eq. 21) is the
    time derivative of r0 s(t) / T(t): checked along a smooth slip and torque history by central
    differences.  The mutant drops the slip rate and returns a rate with the wrong units (1/(N m)).
    """
    from tyrefit.models.slip import elasticity_factor, elasticity_factor_rate

    r0 = 0.31
    t = np.linspace(0.1, 2.0, 9)
    h = 1e-6

    def s(t):
        return 0.02 + 0.01 * np.sin(3.0 * t)

    def T(t):
        return 400.0 + 150.0 * t

    lam = elasticity_factor(r0, torque=T(t), slip=s(t))
    lam_dot = (elasticity_factor(r0, torque=T(t + h), slip=s(t + h))
               - elasticity_factor(r0, torque=T(t - h), slip=s(t - h))) / (2 * h)
    s_dot = (s(t + h) - s(t - h)) / (2 * h)
    assert_allclose(elasticity_factor_rate(r0, s_dot, lam, T(t), 150.0), lam_dot, rtol=1e-6)


# ------------------------------------------------------------------------------ tyrefit/fitting/engine.py
def _peak_mu(coefficients, fz):
    from tyrefit.models import pac89

    sa = np.radians(np.arange(-12.0, 12.01, 0.25))
    return float(np.max(np.abs(pac89.lateral_force(coefficients, fz, sa, 0.0))) / fz)


def test_a_high_grip_tyre_tested_at_close_loads_keeps_its_friction():
    """engine.py:647 [231] ``_Problem._build`` (a linear law's end values mapped with ``dz = hi`` instead of
    ``hi - lo``).

    The friction law D/Fz = a1 Fz + a2 is fitted as its values at the lowest and highest load, each
    bounded to [MU_MIN, MU_MAX] (0.02-6).  A racing tyre of friction 2.4-2.5 tested at 4, 5 and 6 kN is
    well inside those limits and is fitted with the friction its data show, no limit note.  The mutant's
    map scales the end values by 1 - lo/hi (1/3 here): the friction stops at 2.0 "at its upper bound
    6000" and the fit misses the data by 18 x the noise floor.
    """
    from tyrefit.fitting import fit_pac89
    from tyrefit.synthetic.pac89_example import EXAMPLE, lateral_sweeps

    co = dict(EXAMPLE, a1=-40.0, a2=2800.0)
    d = lateral_sweeps(loads=(4000.0, 5000.0, 6000.0), cambers_deg=(0.0,), noise=0.005, seed=3, coefficients=co)
    r = fit_pac89(d)
    c = r.tyre.coefficients
    for fz in (4000.0, 5000.0, 6000.0):
        assert _peak_mu(c, fz) == pytest.approx(_peak_mu(co, fz), rel=0.01)
    assert not any("bound" in n for n in r.notes), r.notes


def _e_long(c, fzk):
    return c["b6"] * fzk**2 + c["b7"] * fzk + c["b8"]


def test_a_concave_quadratic_longitudinal_curvature_is_recovered():
    """engine.py:623 [359] ``_Problem._laws`` (``'b6' in vary or base b6 != 0`` -> ``and``).

    With b6 fitted, E = b6 Fz^2 + b7 Fz + b8 is quadratic and is checked for E <= 1 after the fit; its
    linear part b7 Fz + b8 alone is no physical quantity and must not be held to E's limits.  A tyre whose
    E rises and levels off with load (b6 < 0; linear part 2.1 at 8 kN while E stays <= 0.88) is fitted to
    within 0.05 of its E at every tested load.  The mutant (b6's start is 0) keeps the linear part's limit
    E <= 1 and bends the fitted curvature away from the data.
    """
    from tyrefit.fitting import fit_pac89
    from tyrefit.synthetic.pac89_example import EXAMPLE, longitudinal_sweeps

    co = dict(EXAMPLE, b6=-0.02, b7=0.25, b8=0.1)
    r = fit_pac89(longitudinal_sweeps(coefficients=co, noise=0.005))
    c = r.tyre.coefficients
    assert "b6" not in r.not_identifiable
    for fzk in (2.0, 4.0, 6.0, 8.0):  # fitted 0.508, 0.784, 0.892, 0.830; the mutant 0.105 ... 0.465
        assert _e_long(c, fzk) == pytest.approx(_e_long(co, fzk), abs=0.05)


def test_a_quadratic_curvature_above_one_inside_the_load_range_is_refitted_linear():
    """engine.py:859 [374] ``_fit_part`` (E checked as ``b6 / Fz^2 + b7 Fz + b8``).

    The longitudinal E must stay <= 1 over the load range (above 1 the Magic Formula folds back); a
    quadratic E that peaks above 1 between the tested loads is refitted with b6 = 0 and the note says
    so.  Data generated with E = 1.1 - 0.05 (Fz - 5)^2 (1.05 at 4 and 6 kN) ask for exactly that: the fitted
    tyre has E <= 1 everywhere from 2 to 8 kN.  The mutant checks a different function, finds no E > 1 and
    keeps a tyre whose E exceeds 1 inside its own load range.
    """
    from tyrefit.fitting import fit_pac89
    from tyrefit.synthetic.pac89_example import EXAMPLE, longitudinal_sweeps

    co = dict(EXAMPLE, b6=-0.05, b7=0.5, b8=-0.15)
    r = fit_pac89(longitudinal_sweeps(coefficients=co, noise=0.005),
                  vary=["b0", "b1", "b2", "b3", "b4", "b6", "b7", "b8"])
    fzk = np.linspace(2.0, 8.0, 121)
    assert np.max(_e_long(r.tyre.coefficients, fzk)) <= 1.0
    assert any("E > 1 inside the load range" in n for n in r.notes), r.notes


def test_coarse_sweeps_in_two_degree_steps_are_not_called_too_short():
    """engine.py:910 [6] ``SHORT_SWEEP`` (8 -> 16).

    A sweep of -12..12 deg in 2 deg steps has 13 points: coarse, but a slip sweep, and fitted without the
    warning meant for a run column that counts samples or blocks (sweeps of a handful of points); 4-point
    "sweeps" still get it.  The mutant warns about every sweep under 16 points.
    """
    from tyrefit.fitting import fit_pac89
    from tyrefit.synthetic.pac89_example import lateral_sweeps

    coarse = lateral_sweeps(loads=(3000.0, 5000.0, 7000.0), cambers_deg=(0.0,), slip_deg=np.arange(-12, 12.1, 2.0),
                            seed=4)
    r = fit_pac89(coarse, vary=["a0", "a1", "a2", "a3", "a4", "a7"])
    assert not any("too short to be slip sweeps" in w for w in r.warnings), r.warnings
    blocks = coarse.assign(run=np.arange(len(coarse)) // 4)
    r4 = fit_pac89(blocks, vary=["a0", "a1", "a2", "a3", "a4", "a7"])
    assert any("too short to be slip sweeps" in w for w in r4.warnings), r4.warnings


# ------------------------------------------------------------------------------ tyrefit/fitting/initial.py
def test_the_start_curvature_law_is_the_regression_of_the_sweep_estimates_on_load_in_kn():
    """initial.py:319 [341] ``lateral_initial`` (the E law regressed on Fz x 2e-3: a6 per 0.5 kN, half the slope),
    initial.py:318 [37] (``len(levels) >= 3 and ptp > 0`` -> ``or``: a slope from two levels).

    The fit report's "Eq. 2-4 start" column shows a6, a7 of E = a6 Fz + a7 (Fz in kN, PAC89's unit) as the
    docstring defines them: the least-squares line through the per-sweep Eq. 4 estimates over >= 3 load
    levels, a6 = 0 with fewer.  Sweeps of the example tyre to +-30 deg (where the estimates of E are
    not 0) at four loads give a line through the estimates at each load; at two loads the start is flat.
    """
    from tyrefit.fitting.initial import estimate_sweeps, lateral_initial
    from tyrefit.synthetic.pac89_example import lateral_sweeps

    wide = np.arange(-30.0, 30.01, 0.5)
    d = lateral_sweeps(loads=(2000.0, 4000.0, 6000.0, 8000.0), cambers_deg=(0.0,), noise=0.0, slip_deg=wide)
    est = estimate_sweeps(d, "slip_angle", "fy", x_scale=180.0 / math.pi)
    fzk, e = est["fz"].to_numpy() / 1e3, est["E"].to_numpy()
    assert np.ptp(e) > 0.1  # the estimates change with load: the slope is measurable
    c = lateral_initial(est)
    line = np.polyval(np.polyfit(fzk, e, 1), fzk)
    assert_allclose(c["a6"] * fzk + c["a7"], line, atol=1e-9)
    two = lateral_sweeps(loads=(3000.0, 6000.0), cambers_deg=(0.0,), noise=0.0, slip_deg=wide)
    c2 = lateral_initial(estimate_sweeps(two, "slip_angle", "fy", x_scale=180.0 / math.pi))
    assert c2["a6"] == 0.0


# ------------------------------------------------------------------------------ tyrefit/io/tir.py
MF61_TIR = "mfeval_MagicFormula61_Paramerters.tir"


def test_an_mf_tyre_is_named_by_its_name_entry_else_by_its_file(tmp_path):
    """tir.py:152 [23] ``mf_from_property_file`` (``NAME or file stem`` -> ``NAME and file stem``).

    A property file's NAME (in [MODEL]) names the tyre in reports and in the .tir tyrefit writes back;
    without one the file's name stands in.  The mutant names a tyre with a NAME after its file and a tyre
    without one 'None'.
    """
    from pathlib import Path

    from tyrefit.io.tir import read_tyre

    text = (Path(__file__).resolve().parent / "data" / MF61_TIR).read_text()
    assert "NAME" not in text.split("[MODEL]", 1)[1].split("[", 1)[0]
    plain = tmp_path / "track_day_slick.tir"
    plain.write_text(text)
    named = tmp_path / "t1.tir"
    named.write_text(text.replace("[MODEL]\n", "[MODEL]\nNAME                      = 'Slick 240/640 R18'\n", 1))
    assert read_tyre(plain).name == "track_day_slick"
    assert read_tyre(named).name == "Slick 240/640 R18"


# ------------------------------------------------------------------------------ tyrefit/io/readers.py + ttc.py
def _ttc_text(names="ET\tSA\tFY\tFZ\tSR\tSL", units="s\tdeg\tN\tN\tnone\tnone", row=None):
    """A small FSAE-TTC-style record: one steady 0 -> 10 -> -10 -> 0 deg cycle at 1 kN (SAE: FZ < 0)."""
    row = row or (lambda k, sa: f"{k * 0.05:.2f}\t{sa:.3f}\t{-150 * sa:.1f}\t-1000\t0.5\t0.01")
    lines = ["info", names, units]
    sa = np.r_[np.linspace(0, 10, 40), np.linspace(10, -10, 80), np.linspace(-10, 0, 40)]
    lines += [row(k, a) for k, a in enumerate(sa)]
    return "\n".join(lines) + "\n"


def test_a_ttc_record_saved_under_another_extension_is_still_read_as_ttc(tmp_path):
    """readers.py:256 [22] ``_looks_ttc`` (``len(lines) < 4`` -> ``<= 4``: never true of the 4-line head).

    A TTC record is recognised by its layout (info line, tab-separated channel names with FZ and SA or SL,
    a units line), not only by the .dat extension: the same text saved as .txt reads the same sweeps.  The
    mutant reads the .txt as a CSV and refuses it ("cannot tell what test this is from its columns ('info')").
    """
    from tyrefit.io.readers import read_data

    (tmp_path / "run.dat").write_text(_ttc_text())
    (tmp_path / "run.txt").write_text(_ttc_text())
    a, b = read_data(tmp_path / "run.dat", convention="sae"), read_data(tmp_path / "run.txt", convention="sae")
    assert a.meta["format"] == b.meta["format"] == "ttc"
    assert a.n_runs == b.n_runs == 1 and len(a.df) == len(b.df)


def test_a_ttc_units_line_short_of_the_last_channels_leaves_them_unitless(tmp_path):
    """ttc.py:48 [11] ``parse_ttc`` (units padded with one '' instead of one per missing unit).

    A units line that stops before the last channels (two trailing channels without units here) reads with
    those channels dimensionless, like an explicit 'none'.  The mutant pads one unit only and the reader
    fails with an IndexError traceback.
    """
    from tyrefit.io.readers import read_data

    (tmp_path / "short.dat").write_text(_ttc_text(units="s\tdeg\tN\tN"))
    ds = read_data(tmp_path / "short.dat", convention="sae")
    assert_allclose(ds.df["slip_ratio"], 0.01)


def test_a_ttc_file_without_a_load_channel_is_told_which_channels_a_test_needs(tmp_path):
    """ttc.py:49 [12] ``parse_ttc`` (fewer than 2 channel names refused -> fewer than 4).

    A TTC record naming three channels (ET, SA, FY: no FZ) does name its channels; what it lacks is a load,
    and the error says which channels each test needs.  The mutant refuses it as if line 2 named no channels.
    """
    from tyrefit.errors import ColumnError
    from tyrefit.io.readers import read_data

    three = _ttc_text(names="ET\tSA\tFY", units="s\tdeg\tN",
                      row=lambda k, a: f"{k * 0.05:.2f}\t{a:.3f}\t{-150 * a:.1f}")
    (tmp_path / "three.dat").write_text(three)
    with pytest.raises(ColumnError, match=r"slip_angle: slip_angle, fy, fz"):
        read_data(tmp_path / "three.dat", convention="sae")


def _lateral_csv(flip=(), stuck=(), camber=None, loads=(2000.0, 4000.0, 6000.0, 8000.0)):
    """Lateral sweeps (-10..10 deg, 1 deg steps, ISO-W) at ``loads``; sweeps in ``flip`` inverted, in ``stuck``
    a constant 12 N; ``camber``: one value per sweep [deg]."""
    rows = ["run,slip_angle [deg],fy [N],fz [N]" + (",camber [deg]" if camber is not None else "")]
    for r, fz in enumerate(loads, 1):
        for a in np.arange(-10.0, 10.01, 1.0):
            fy = -fz * math.tanh(0.2 * a) * (-1.0 if r in flip else 1.0)
            fy = 12.0 if r in stuck else fy
            rows.append(f"{r},{a:g},{fy:.3f},{fz:g}" + (f",{camber[r - 1]:g}" if camber is not None else ""))
    return "\n".join(rows) + "\n"


def test_a_camber_beyond_30_deg_is_refused_on_either_side(tmp_path):
    """readers.py:120 [100] ``LIMITS`` (camber's lower limit -30 rad instead of -30 deg).

    The accepted camber range is |camber| <= 30 deg, the same for both signs: -45 deg is refused as +45 deg
    is (a camber column in the wrong unit, or a slip angle under the wrong name); -29 deg is read.  The
    mutant takes -45 deg.
    """
    from tyrefit.errors import ValueRangeError
    from tyrefit.io.readers import read_data

    for cam in (45.0, -45.0):
        (tmp_path / "c.csv").write_text(_lateral_csv(camber=[cam, 0, 0, 0]))
        with pytest.raises(ValueRangeError, match=rf"out of range, {cam:g} deg; accepted \|camber\| <= 30 deg"):
            read_data(tmp_path / "c.csv")
    (tmp_path / "ok.csv").write_text(_lateral_csv(camber=[-29, 0, 0, 29]))
    assert read_data(tmp_path / "ok.csv").n_runs == 4


def test_a_slip_ratio_sweep_to_exactly_plus_and_minus_one_is_read(tmp_path):
    """readers.py:788 [334] ``_check_ranges`` (``v > hi`` -> ``v >= hi``: the upper limit itself refused).

    The error message states the accepted range as ``|slip_ratio| <= 1``: a sweep from a locked wheel
    (-1) to +1 is inside it at both ends.  The mutant refuses the +1 sample (and any value exactly at an
    upper limit) while taking -1.
    """
    from tyrefit.io.readers import read_data

    rows = ["run,slip_ratio [-],fx [N],fz [N]"]
    for r, fz in ((1, 3000.0), (2, 6000.0)):
        rows += [f"{r},{k:g},{fz * math.tanh(10 * k):.3f},{fz:g}" for k in np.linspace(-1.0, 1.0, 41)]
    (tmp_path / "sr.csv").write_text("\n".join(rows) + "\n")
    ds = read_data(tmp_path / "sr.csv")
    assert ds.kind == "slip_ratio" and ds.df["slip_ratio"].min() == -1.0 and ds.df["slip_ratio"].max() == 1.0


def test_one_inverted_sweep_among_several_is_refused(tmp_path):
    """readers.py:686 [193] ``_check_sweeps`` (the sign check run for static pushes only, ``!=`` -> ``==``).

    A force channel inverted part-way through a record (or files of two sign conventions joined) gives
    sweeps whose force rises with slip beside sweeps where it falls: refused, naming the odd sweep.  The
    mutant skips the check for slip sweeps and the fit would average the two orientations.  (Also killed by
    tests/test_fuzz_readers.py, which the runner does not run for readers.py.)
    """
    from tyrefit.errors import ValueRangeError
    from tyrefit.io.readers import read_data

    (tmp_path / "flip.csv").write_text(_lateral_csv(flip=(3,)))
    with pytest.raises(ValueRangeError, match=r"sweeps of opposite sign: 'fy \[N\]' rises with slip_angle in sweep 3 "):
        read_data(tmp_path / "flip.csv")


def test_one_stuck_force_channel_sweep_is_refused_by_name(tmp_path):
    """readers.py:665 [387] ``_check_sweeps`` (the stuck sweep named as ``stuck.index[1]``).

    A force constant through a sweep whose slip varies is a stuck or disconnected channel: the error names
    that sweep.  With one such sweep the mutant fails with an IndexError traceback instead.  (Also killed
    by tests/test_fuzz_readers.py, not in the runner's list for readers.py.)
    """
    from tyrefit.errors import ValueRangeError
    from tyrefit.io.readers import read_data

    (tmp_path / "stuck.csv").write_text(_lateral_csv(stuck=(2,)))
    with pytest.raises(ValueRangeError, match=r"constant \(12 N\) in sweep 2 while its slip_angle varies \(1 of 4"):
        read_data(tmp_path / "stuck.csv")


def test_sweeps_without_run_ids_are_split_at_a_load_step_of_an_eighth(tmp_path):
    """readers.py:864 [413] ``derive_runs`` (a load step must exceed 16 % of the load instead of 8 %).

    Without a run column the sweeps are told apart by set-point changes; sweeps that go up and down in slip
    (no restart) at 4.0 and then 4.5 kN are two sweeps at two loads.  The mutant ignores a 12.5 % load
    step and reads them as one sweep mixing both loads.
    """
    from tyrefit.io.readers import read_data

    rows = ["slip_angle [deg],fy [N],fz [N]"]
    up, down = np.arange(-10.0, 10.01, 0.5), np.arange(10.0, -10.01, -0.5)
    for fz, sweep in ((4000.0, up), (4500.0, down), (4000.0, up)):
        rows += [f"{a:g},{-fz * math.tanh(0.2 * a):.3f},{fz:g}" for a in sweep]
    (tmp_path / "noruns.csv").write_text("\n".join(rows) + "\n")
    ds = read_data(tmp_path / "noruns.csv")
    assert ds.n_runs == 3
    assert sorted(ds.df.groupby("run")["fz"].nunique()) == [1, 1, 1]


# ------------------------------------------------------------------------------ tyrefit/fitting/core.py
def _stiffness_line(seed=1):
    """A load-deflection line of a stiff tyre: F = 4e7 N/m x (2-30 mm) + 150 N, 500 N noise."""
    rng = np.random.default_rng(seed)
    x = np.linspace(0.002, 0.03, 40)
    return x, 4e7 * x + 150.0 + 500.0 * rng.standard_normal(x.size)


@pytest.mark.parametrize("cost", ["soft_l1", "l1"])
def test_standard_errors_of_a_stiffness_of_4e7_are_the_least_squares_ones(cost):
    """core.py:717 [89] ``_unweighted_jac`` (finite-difference step ``eps`` instead of ``eps max(|x|, 1)``).

    For the l1 and robust costs the standard errors are the least-squares approximation at the solution,
    s^2 (J^T J)^-1 with J made by finite differences.  For a straight line F = k x + c with k = 4e7 N/m
    (a vertical stiffness, the size covariance() is written for) J is exact and the standard errors are
    the textbook ones at the fitted line (to 1e-3).  The mutant's unscaled step, 1.5e-8 N/m on 4e7,
    drowns in rounding: the standard errors come out 2-6 % off.
    """
    from tyrefit.fitting.core import Parameters, solve

    x, y = _stiffness_line()
    X = np.column_stack([x, np.ones_like(x)])
    p = Parameters()
    p.add("k", 3e7)
    p.add("c", 0.0)
    sol = solve(lambda v: v[0] * x + v[1] - y, p, cost=cost, scale=1e4)
    r = X @ sol.x - y
    se = np.sqrt(np.diag(r @ r / (x.size - 2) * np.linalg.inv(X.T @ X)))
    assert_allclose([sol.stderr["k"], sol.stderr["c"]], se, rtol=1e-3)


def test_a_model_with_as_many_parameters_as_points_is_fitted_exactly():
    """core.py:749 [203] ``covariance`` (``s^2 = SSR / max(1, N - p)`` -> ``max(0, N - p)``).

    Two points and a straight line: the fit is exact and its residual variance 0 (the N - p = 0 guard
    divides by 1); the mutant divides by zero and the fit fails with a ZeroDivisionError.
    """
    from tyrefit.fitting.core import Parameters, covariance, solve

    p = Parameters()
    p.add("m", 1.0)
    p.add("c", 0.0)
    sol = solve(lambda v: v[0] * np.array([0.0, 1.0]) + v[1] - np.array([1.0, 3.0]), p)
    assert_allclose(sol.x, [2.0, 1.0], atol=1e-9)
    cov, s2 = covariance(np.eye(2), np.array([0.1, -0.1]))
    assert s2 == pytest.approx(0.02)


def test_the_batched_solver_leaves_an_upper_bound_the_cost_points_away_from():
    """core.py:911 [395] ``lm_normal_batch`` (a parameter at its upper bound held while ``g < 1`` instead of
    ``g < 0``).

    A parameter is held at a bound only while the descent direction points out of the box.  Started at
    the upper bound 1 of a cost with its minimum at 0.5 (a small gradient, 1e-4), every problem of the batch
    walks to 0.5, as :func:`lm_normal` does alone.  The mutant holds them at 1 for any gradient below 1.
    """
    from tyrefit.fitting.core import lm_normal, lm_normal_batch

    def jac(X, rows):
        return np.repeat(X[:, :1] - 0.5, 3, axis=1) * 0.01, np.full((len(rows), 3, 1), 0.01)

    lo, hi, sc = np.array([0.0]), np.array([1.0]), np.array([1.0])
    X, _, _, conv = lm_normal_batch(jac, None, np.array([[1.0], [1.0]]), np.ones((2, 3)), lo, hi, sc, 100)
    x1, _, _ = lm_normal(lambda v: (np.repeat(v[:1] - 0.5, 3) * 0.01, np.full((3, 1), 0.01)),
                         lambda v: np.repeat(v[:1] - 0.5, 3) * 0.01, np.array([1.0]), lo, hi, sc, 100)
    assert_allclose(X.ravel(), [0.5, 0.5], atol=1e-6)
    assert_allclose(x1, [0.5], atol=1e-6)


# ------------------------------------------------------------------------------ tyrefit/io/pac89_tir.py
def _pac89_text():
    from pathlib import Path

    return (Path(__file__).resolve().parent / "data" / "io_adams_pac89_example.tir").read_text()


def test_a_pac89_file_with_only_the_lateral_block_is_complete_and_one_without_it_is_not(tmp_path):
    """pac89_tir.py:42 [40] ``pac89_fields`` (a part skipped when absent: ``part != 'lateral'`` -> ``==``).

    The lateral block a0..a13 is required, the longitudinal and aligning blocks optional (the module
    docstring): a file with only [LATERAL_COEFFICIENTS] reads with nothing missing and passes its check; a
    file without the lateral block lists a0..a13 as missing.  The mutant requires b0..b10 and c0..c17 of the
    lateral-only file and lets the lateral block go unnoticed.
    """
    from tyrefit.io.tir import read_tyre

    text = _pac89_text()
    head, rest = text.split("[LATERAL_COEFFICIENTS]", 1)
    lateral, other = rest.split("[LONGITUDINAL_COEFFICIENTS]", 1)
    (tmp_path / "lat.tir").write_text(head + "[LATERAL_COEFFICIENTS]" + lateral)
    (tmp_path / "long.tir").write_text(head + "[LONGITUDINAL_COEFFICIENTS]" + other)
    lat = read_tyre(tmp_path / "lat.tir")
    assert lat.missing == [] and not any("missing" in p for p in lat.check())
    long_only = read_tyre(tmp_path / "long.tir")
    assert {f"a{i}" for i in range(14)} <= set(long_only.missing)


# ------------------------------------------------------------------------------ tyrefit/rig/patch.py
_G0 = 9.80665


def _patch_data(loads_kg=(1000, 1500, 2000, 2500, 3000, 3500, 4000, 4500, 5000, 5500)):
    """Contact-patch measurements of a truck tyre with known laws: length and area two-gradient (breakpoints
    2500 kg and 3000 kg), width rising to 300 mm; exact (no noise)."""
    from tyrefit.rig.patch import exp_rise, two_gradient

    F = np.asarray(loads_kg, float) * _G0
    return pd.DataFrame({"fz": F, "length": two_gradient(F, 0.12, 6e-6, 2e-6, 2500 * _G0),
                         "area": two_gradient(F, 0.02, 2.5e-6, 1e-6, 3000 * _G0),
                         "width": exp_rise(F, 0.30, 8000.0)})


def test_the_patch_table_shows_the_fitted_laws_in_its_units():
    """patch.py:387 [175] ``PatchModel.table`` ('L0 [mm]' = 1e3 instead of 1e3 x y0), patch.py:392 [182]
    ('area breakpoint [kg]' = breakpoint x G0 instead of / G0).

    The table of ``tyrefit rig`` reports each law in the units its header names: the length law's L0 of
    120 mm and the area law's breakpoint at 3000 kg, as generated.  The mutants print L0 = 1000 mm for
    every tyre and the breakpoint in N x 9.8.
    """
    from tyrefit.rig.patch import fit_patch

    row = fit_patch(_patch_data()).table().iloc[0]
    assert row["L0 [mm]"] == pytest.approx(120.0, rel=1e-3)
    assert row["length breakpoint [kg]"] == pytest.approx(2500.0, rel=1e-3)
    assert row["area breakpoint [kg]"] == pytest.approx(3000.0, rel=1e-3)


def test_the_patch_plot_draws_the_measured_points_at_their_loads_in_kg():
    """patch.py:456 [197] ``PatchModel.plot`` (measured points at load x G0 instead of load / G0).

    The figure's x axis is 'load [kg]': the measured points sit at 1000..5500 kg on the fitted curves.  The
    mutant draws them at 96 x their load, off the curves.
    """
    from tyrefit.rig.patch import fit_patch

    data = _patch_data()
    axes = fit_patch(data).plot(data)
    pts = [ln for ln in axes[0].get_lines() if ln.get_marker() == "o"]
    assert len(pts) == 1
    assert_allclose(pts[0].get_xdata(), data["fz"] / _G0)


def test_the_patch_laws_are_fitted_from_the_fewest_loads_their_errors_name():
    """patch.py:169 [9] ``fit_two_gradient`` (``< 2 min_side + 1`` distinct loads refused -> ``<=``), patch.py:215
    [35] ``fit_exp_rise`` (fewer than 3 loads refused -> fewer than 6).

    The errors say a two-gradient law needs at least 5 distinct loads and the width law at least 3: with
    exactly 5 loads the patch model is fitted (length, area, width).  The mutants refuse the very number
    their message asks for.
    """
    from tyrefit.errors import DataError
    from tyrefit.rig.patch import fit_exp_rise, fit_patch

    five = _patch_data(loads_kg=(1000, 2000, 3000, 4000, 5000))
    m = fit_patch(five)
    assert m.has("length") and m.has("area") and m.has("width")
    w = fit_exp_rise(five["fz"][:3], five["width"][:3])
    assert w.y_max > 0
    with pytest.raises(DataError, match="at least 5 distinct loads, found 4"):
        fit_patch(five.iloc[:4])


# ------------------------------------------------------------------------------ tyrefit/rig/conversion.py
def test_the_rig_calibration_warns_only_beyond_ten_percent_of_its_pressures():
    """conversion.py:191 [183] [185] ``RigCalibration.check`` (the lower or the upper +-10 % margin dropped),
    conversion.py:193 [239] (the calibrated range printed as lo x 1e5 instead of lo / 1e5 bar).

    The warning says the pressure is outside the calibrated range "(+/-10 %)": a calibration at 2-3 bar
    takes 1.85 and 3.25 bar silently and warns at 1.75 and 3.35 bar, naming the calibrated 2.00-3.00 bar.
    """
    from tyrefit.rig.conversion import RigCalibration

    cal = RigCalibration(n=1.2, b=0.5, u_range=(0.0, 0.5), fz_range=(20e3, 40e3), pressure_range=(2e5, 3e5),
                         points=100)
    assert cal.check(pressure=[1.85e5, 3.25e5]) == []
    for p in (1.75e5, 3.35e5):
        msgs = cal.check(pressure=[2.5e5, p])
        assert len(msgs) == 1 and "outside the calibrated 2.00-3.00 bar (+/-10 %)" in msgs[0], msgs


def test_a_calibration_without_overlapping_loads_names_its_static_data(tmp_path):
    """conversion.py:452 [202] ``calibrate`` (``ssrc or 'static data'`` -> ``and``).

    When no static sample lies within the dynamic loads, the error starts with what the static data are:
    its file when read from one, else 'static data'.  The mutant names a file 'static data' and a
    DataFrame not at all (': only 0 static samples ...').
    """
    from tyrefit.errors import FitError
    from tyrefit.io.datasets import data_path
    from tyrefit.io.readers import read_data
    from tyrefit.rig.conversion import calibrate

    static = read_data(data_path("truck", "tyre_a_static.csv"))
    dynamic = read_data(data_path("truck", "tyre_a_dynamic.csv"))
    patch = read_data(data_path("truck", "tyre_a_patch.csv"))
    light = static.df[static.df["run"] == 1]          # 500 kg: no dynamic sweep near it
    with pytest.raises(FitError, match=r"^static data: only \d+ static samples"):
        calibrate(light, dynamic, patch)
    (tmp_path / "light_static.csv").write_text(
        "run,lateral_displacement [mm],fy [N],fz [N]\n"
        + "".join(f"1,{y * 1e3:.4f},{f:.3f},{z:.1f}\n" for y, f, z in
                  zip(light["lateral_displacement"], light["fy"], light["fz"])))
    with pytest.raises(FitError, match=r"light_static\.csv: only \d+ static samples"):
        calibrate(read_data(tmp_path / "light_static.csv"), dynamic, patch)


# ------------------------------------------------------------------------------ tyrefit/io/outputs.py
def test_a_file_written_beside_a_staged_report_folder_waits_for_the_commit(tmp_path):
    """outputs.py:268 [71] ``OutputRun._in_tmpdir`` (``t == parent or t in parents`` -> ``t != parent or ...``).

    Inside one run every output is committed together or not at all: a .tir written beside a report folder
    that is being built is staged like the folder, and when the run fails neither appears.  The mutant
    takes any file for one inside the staged folder and writes the .tir at once: a failed run leaves it
    behind (over an older one, with --force).
    """
    from tyrefit.io.outputs import output_run, staged_dir, write_text

    tir, report = tmp_path / "fit.tir", tmp_path / "report"
    with pytest.raises(RuntimeError):
        with output_run(force=True):
            with staged_dir(report) as d:
                write_text(d / "summary.txt", "ok")
                write_text(tir, "tyre")
                assert not tir.exists()  # staged, not in place yet
                raise RuntimeError("the report failed")
    assert not tir.exists() and not report.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_a_manifest_that_cannot_be_written_is_one_clean_error(tmp_path, monkeypatch):
    """outputs.py:356 [98] ``OutputRun.commit`` (the error names ``items[1]``'s folder: an IndexError with one
    output).

    When the manifest cannot be written (a full disk) the run fails with tyrefit's one-line OutputError
    naming the folder and writes nothing.  With a single output the mutant raises an IndexError
    traceback from inside the error handling.
    """
    import errno

    from tyrefit.errors import OutputError
    from tyrefit.io import outputs

    def full(self, items):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(outputs.OutputRun, "_manifests", full)
    with pytest.raises(OutputError, match="cannot write the manifest"):
        with outputs.output_run(force=True):
            outputs.write_text(tmp_path / "one.tir", "tyre")
    assert not (tmp_path / "one.tir").exists()


def test_a_refused_report_folder_counts_its_foreign_files_in_words(tmp_path):
    """outputs.py:203 [88] [94] ``check_report_dir`` (the plural of 'file' for ``len != 1`` -> ``== 1`` /
    ``!= 0``).

    The refusal says how many files in the folder tyrefit did not write: "1 file", "2 files".
    """
    from tyrefit.errors import OutputExistsError
    from tyrefit.io.outputs import check_report_dir

    d = tmp_path / "rep"
    d.mkdir()
    (d / "notes.txt").write_text("mine")
    with pytest.raises(OutputExistsError, match=r"it holds 1 file tyrefit did not write \(e\.g\. notes\.txt\)"):
        check_report_dir(d)
    (d / "plan.txt").write_text("mine too")
    with pytest.raises(OutputExistsError, match=r"it holds 2 files tyrefit did not write"):
        check_report_dir(d)


# ------------------------------------------------------------------------------ tyrefit/diagnose/stats.py
def test_the_noise_estimate_corrects_for_the_model_s_parameters_within_the_sweeps():
    """stats.py:506 [222] ``estimate_noise`` (``(N - G) / (N - G - dof_within)`` -> ``+ dof_within``).

    Residuals of a model that spent one slope per sweep (dof_within = G) on white noise of variance 4 keep
    N - 2G of its N degrees of freedom; the documented correction gives back the noise variance (3.89 on
    400 x 30 ten-point sweeps; the AR(1) correction for the removed slope costs the 3 %).  The mutant divides
    the other way and reports 3.11: a noise floor 12 % too low, so noise passes for structure.
    """
    from tyrefit.diagnose.stats import SweepLayout, estimate_noise

    G, n = 30, 10
    sweep = np.repeat(np.arange(G), n)
    e = 2.0 * np.random.default_rng(3).standard_normal((400, G * n))
    X = np.column_stack([np.ones(n), np.arange(n) - (n - 1) / 2])
    H = X @ np.linalg.pinv(X)                      # per-sweep projection on mean and slope
    r = (e.reshape(400, G, n) - e.reshape(400, G, n) @ H.T).reshape(400, G * n)
    sd2 = np.mean(estimate_noise(r, SweepLayout(sweep, G), dof_within=G, dof_between=G).sd ** 2)
    assert sd2 == pytest.approx(4.0, rel=0.06)


# ------------------------------------------------------------------------------ tyrefit/diagnose/engine.py
def _rig(loads, cambers=(0.0,), points=13, effects=(), noise="iid", seed=5):
    from tyrefit.diagnose.data import prepare
    from tyrefit.synthetic.hidden import make_case, rig_grid

    grid = rig_grid(loads=loads, cambers_deg=cambers, pressures=(220e3,), points_per_sweep=points)
    return prepare(make_case(effects, noise, seed=seed, grid=grid).data)


def test_up_to_eight_sweeps_each_is_held_out_in_turn():
    """engine.py:141 [145] ``_Engine.__init__`` (``G <= loso_max_sweeps`` -> ``<``).

    The module docstring: with at most ``Settings.loso_max_sweeps`` (8) sweeps every sweep is held out in
    turn (leave one sweep, here one load level, out); more are grouped in ``n_folds`` (5) folds.  The mutant
    groups exactly 8 sweeps into 5 folds, so two load levels are held out together.
    """
    from tyrefit.diagnose.engine import Settings, _Engine

    s = Settings()
    eight = _Engine(_rig(tuple(1000.0 * k for k in range(2, 2 + s.loso_max_sweeps))), s, 0)
    assert eight.G == s.loso_max_sweeps and len(eight.folds) == eight.G
    assert sorted(int(np.unique(f)[0]) for f in eight.folds if np.unique(f).size == 1) == list(range(eight.G))
    nine = _Engine(_rig(tuple(1000.0 * k for k in range(2, 3 + s.loso_max_sweeps))), s, 0)
    assert len(nine.folds) == s.n_folds


def test_the_misfit_components_are_shares_of_the_fitted_surface():
    """engine.py:910 [39] ``_misfit`` (``sum(var) or 1.0`` -> ``and 1.0``: the variances not normalised).

    The misfit check says how much of the fitted surface belongs to each condition group: shares that add
    up to 1 (a load-growing stiffness error is ~98 % 'fz').  The mutant reports the groups' raw variances
    [N^2] under the same name.
    """
    from types import SimpleNamespace

    from tyrefit.diagnose.engine import Settings, _Engine, _misfit

    data = _rig((3000.0, 5000.0, 7000.0), cambers=(-3.0, 0.0, 3.0), points=25)
    x = data.inputs
    u = np.clip(x.slip_angle / np.max(np.abs(x.slip_angle)), -1, 1)
    lv = np.asarray(data.levels["fz"], float)
    z = (lv[data.level_index["fz"]] - lv.mean()) / (0.5 * np.ptp(lv))
    r = 10.0 * np.random.default_rng(1).standard_normal(data.n) + 40.0 * z * np.tanh(4.0 * u)
    step = SimpleNamespace(fit=SimpleNamespace(resid=r, theta=None), rmse_heldout=20.0, spec=None)
    mf = _misfit(_Engine(data, Settings(), 0), step, 10.0, u, None)
    assert mf["checked"]
    assert sum(mf["components"].values()) == pytest.approx(1.0)
    assert max(mf["components"], key=mf["components"].get) == "fz" and mf["components"]["fz"] > 0.9


def test_a_clear_effect_s_held_out_p_value_is_one_over_the_draws_plus_one():
    """engine.py:336 [305] ``_Engine.heldout_p`` (``(1 + #null >= gain) / (B + 1)`` -> ``/ B``).

    A Monte-Carlo p-value counts the observed gain among the B null draws: (1 + #draws >= gain) / (B + 1),
    never 0 and never above 1.  A friction law in load, clear in six sweeps, beats every draw:
    p = 1 / (B + 1) = 0.002 with B = 499.  The mutant's 1/B is no p-value of any draw count, and reaches
    (B + 1) / B > 1 for a candidate no draw falls short of.
    """
    from tyrefit.diagnose import diagnose
    from tyrefit.synthetic.hidden import make_case, rig_grid

    case = make_case(("load_friction",), "ar1", seed=3,
                     grid=rig_grid(loads=(2000.0, 3200.0, 4400.0, 5600.0, 6800.0, 8000.0), cambers_deg=(0.0,),
                                   pressures=(220e3,)))
    res = diagnose(case.data, rated_load=case.rated_load)
    c = res.candidates["load_friction"]
    assert c.status == "accepted"
    assert c.p_heldout == pytest.approx(1.0 / (res.settings.n_boot_heldout + 1.0), rel=1e-12)


def test_the_end_check_s_slip_shape_groups_are_orders_0_4_and_5_9():
    """engine.py:1015 [534] ``_unexplained`` (the 'orders 0-4' group takes ``min(10, q)`` columns).

    The end check's omnibus test names its slip-shape groups by the Legendre orders they hold: 'orders
    0-4' has at most 5 directions and 'orders 5-9' the next 5, whatever the number of sweeps.  With 30
    sweeps (q = 10) the mutant's 'orders 0-4' holds orders 0-9, overlapping the other group.
    """
    from tyrefit.diagnose import diagnose
    from tyrefit.synthetic.hidden import make_case

    res = diagnose(make_case((), "iid", seed=5).data)
    groups = res.unexplained["omnibus_groups"]
    assert groups["slip shape (orders 0-4)"]["directions"] == 5
    assert groups["slip shape (orders 5-9)"]["directions"] == 5


# ------------------------------------------------------------------------------ fitting/mf*.py (Magic Formula fit)
def _mf_published(loads, **kw):
    """Sweeps of the published MF 6.1 set (tyrefit.synthetic.ttc_drivebrake) at ``loads`` (fractions of FNOMIN),
    one pressure, zero camber; with its tyre info."""
    from tyrefit.synthetic import ttc_drivebrake as gen

    p = gen.contract_mf61()
    fn = p["FNOMIN"]
    kw = {"seed": 3, "pressures": [260e3], "cambers_deg": [0.0], "slip_angles_deg": [0.0], **kw}
    return gen.make_sweeps(p, loads=[f * fn for f in loads], **kw), {"fnomin": fn,
                                                                      "unloaded_radius": p["UNLOADED_RADIUS"]}


def test_an_fx_stage_short_of_the_peak_holds_the_plain_arctangent_shape_and_reports_its_r2():
    """mf_identify.py:74 [4] ``SHAPE_DEFAULTS`` (PEX1 held at 1 instead of 0 without a peak), mf.py:618 [600]
    ``_r2`` (1 - sum(res^4) / SS_tot).

    Drive/brake sweeps to +-0.05 reach no peak: the stage holds the documented shape, Pacejka's typical
    C = 1.65 and E = 0 (the plain sine of the arctangent; E = 1 would flatten the curve into
    sin(C atan(atan(B kappa))) beyond the data), and says so.  The stage's R^2 is 1 - SS_res / SS_tot of
    its channel at the fitted coefficients, here recomputed from :func:`mf61.fx0` (to 1e-5: the stage
    evaluates at the data's pressure levels).  The mutants hold E at 1, and report an R^2 of -3e6.
    """
    from tyrefit.fitting.mf import fit_mf
    from tyrefit.models import mf61

    df, info = _mf_published([0.5, 1.0, 1.5], seed=41, n_points=31, kappa_max=0.05)
    df = df[df["slip_angle"] == 0.0]
    r = fit_mf(df, tyre_info=info, stages=["Fx0"], multistart=False)
    st = r.stages["Fx0"]
    assert r.params["PCX1"] == 1.65 and r.params["PEX1"] == 0.0
    assert st.held["PEX1"].endswith("curvature E held at 0")
    fx = mf61.fx0(r.params, df["fz"].to_numpy(), df["slip_ratio"].to_numpy(), df["camber"].to_numpy(),
                  df["pressure"].to_numpy(), df["speed"].to_numpy())
    y = df["fx"].to_numpy()
    assert st.facts["r2"] == pytest.approx(1.0 - np.sum((fx - y) ** 2) / np.sum((y - y.mean()) ** 2), abs=1e-5)


def _stage_constraints(stage, **coefficients):
    """The stage's constraint report (holds / worst) for MF 6.1 neutral coefficients changed by
    ``coefficients``, on the grid of a record at 2-6 kN, slip ratios +-0.2, zero camber."""
    from tyrefit.fitting.mf import _STAGE
    from tyrefit.fitting.mf_contract import _check_constraints, _grid
    from tyrefit.models import mf61

    nominal = {"FNOMIN": 4000.0, "NOMPRES": 2.2e5, "UNLOADED_RADIUS": 0.3}
    pts = pd.DataFrame({"fz": [2000.0, 4000.0, 6000.0], "pressure": [2.2e5] * 3, "camber": [0.0] * 3,
                        "slip_ratio": [-0.2, 0.0, 0.2]})
    rows = _check_constraints(_STAGE[stage], {**mf61.neutral(), **nominal, **coefficients}, _grid(pts, nominal))
    return {r["constraint"]: r for r in rows}


def test_the_mf_stage_constraints_hold_a_physical_set_and_catch_each_broken_limit():
    """mf_contract.py:204 [227] ``_grid`` (slip signs -1, 1 -> -0, 1: braking never checked), mf_contract.py:108
    [282] ``_factors`` (E_y <= 1 tested as E_y <= 0), mf_contract.py:119 [423] (B_yk > 0 tested as
    B_yk + Fz > 0).

    The stages hold Pacejka's limits over their grid and report each (the fit's notes name a broken one):
    E_x = PEX1 (1 - PEX4 sgn(kappa)) <= 1 on both sides of the slip - 0.8 (1 + 0.5) = 1.2 under braking is
    broken; E_y <= 1 holds at 0.5 (a common curvature) and breaks at 1.2; the combined Fy weight's B_yk
    must be positive.  The mutants check driving only, forbid every positive E_y (the fit is then pushed
    to E_y <= 0) and call B_yk = -2 positive (the load, thousands of N, added to it).
    """
    assert not _stage_constraints("Fx0", PEX1=0.8, PEX4=0.5)["E_x <= 1"]["holds"]
    assert not _stage_constraints("Fx0", PEX1=0.8, PEX4=-0.5)["E_x <= 1"]["holds"]
    assert _stage_constraints("Fx0", PEX1=0.5, PEX4=0.5)["E_x <= 1"]["holds"]
    assert _stage_constraints("Fy0", PEY1=0.5)["E_y <= 1"]["holds"]
    assert not _stage_constraints("Fy0", PEY1=1.2)["E_y <= 1"]["holds"]
    byk = _stage_constraints("Fy", RBY1=-2.0)["B_yk > 0"]
    assert not byk["holds"] and byk["worst"] == pytest.approx(-2.0)
    assert _stage_constraints("Fy", RBY1=5.0)["B_yk > 0"]["holds"]


def test_an_sae_cornering_record_in_three_degree_steps_is_refused_as_iso():
    """mf_initial.py:138 [56] ``_orientation`` (the near-zero points kept when they span no slip: ``ptp <= 0``
    -> ``< 0``).

    Sweeps in 3 deg steps have only their zero-slip points within 2 deg of zero: no slope there, so the
    orientation is measured on the points nearest zero (30 %).  An SAE record (force rising with slip angle)
    passed as ISO at three loads is refused with the hint to pass the convention.  The mutant finds no
    slope at zero slip, assumes ISO, and fits the tyre with its lateral force the wrong way round.
    """
    from tyrefit.errors import DataError
    from tyrefit.fitting.mf import fit_mf

    df, info = _mf_published([0.5, 1.0, 1.5], n_points=9, combined=False)
    lat = df[df.groupby("run")["slip_ratio"].transform(lambda v: v.abs().max()) == 0]
    assert lat["run"].nunique() == 3 and (np.abs(lat["slip_angle"]) <= 2 * _DEG).sum() == 3
    with pytest.raises(DataError, match="rises with slip angle"):
        fit_mf(lat.assign(fy=-lat["fy"]), tyre_info=info, stages=["Fy0"], multistart=False)


def test_an_iso_cornering_record_with_a_third_of_its_samples_at_zero_slip_is_not_called_sae():
    """mf_initial.py:140 [107] ``_orientation`` (without any slope to measure: -1 -> -0, i.e. SAE assumed).

    When even the points nearest zero slip span no slip (a third of the samples held at exactly 0 deg), the
    orientation cannot be measured and ISO-W, tyrefit's convention, is assumed: an ISO record is not refused.
    The mutant assumes the opposite and refuses it as SAE ("rises with slip angle").  (The fit of such a
    record is poor for another reason: the Eq. 2-4 estimates of those sweeps have no slope; see the report.)
    """
    from tyrefit.fitting.mf import fit_mf

    df, info = _mf_published([0.5, 1.0, 1.5], n_points=9, combined=False)
    lat = df[df.groupby("run")["slip_ratio"].transform(lambda v: v.abs().max()) == 0]
    held = pd.concat([lat] + [lat[lat["slip_angle"] == 0.0]] * 3, ignore_index=True)
    assert (held["slip_angle"] == 0.0).mean() > 0.3
    r = fit_mf(held.sort_values(["run", "slip_angle"], kind="stable"), tyre_info=info, stages=["Fy0"],
               multistart=False)
    assert "Fy0" in r.stages


# ------------------------------------------------------------------------------ tyrefit/fitting/initial.py (levels)
def test_three_light_loads_150_n_apart_are_three_load_levels():
    """initial.py:251 [22] ``load_levels`` (``abs_tol`` 100 N -> 200 N).

    Loads are one level when they differ by less than max(100 N, 4 % of the largest): a kart or bicycle
    tyre tested at 300, 450 and 600 N has three load levels, and the fit varies the load laws (a1, a4, a6
    need >= 2 or 3 levels).  The mutant merges them into one level and holds every load law ("needs >= 2
    load levels (data: 1)").
    """
    from tyrefit.fitting import fit_pac89
    from tyrefit.fitting.initial import load_levels
    from tyrefit.synthetic.pac89_example import lateral_sweeps

    assert list(load_levels(np.array([300.0, 450.0, 600.0, 310.0]))) == [0, 1, 2, 0]
    r = fit_pac89(lateral_sweeps(loads=(300.0, 450.0, 600.0), cambers_deg=(0.0,), seed=6))
    assert not {"a1", "a4", "a6"} & set(r.not_identifiable), r.not_identifiable


# ------------------------------------------------------------------------------ tyrefit/io/segment.py
def _cycle(n=200, amp=10.0):
    """One slip-angle cycle 0 -> +amp -> -amp -> 0 deg in n samples."""
    return np.r_[np.linspace(0, amp, n // 4), np.linspace(amp, -amp, n // 2), np.linspace(-amp, 0, n // 4)]


def test_a_sweep_at_a_load_six_percent_above_the_others_is_kept():
    """segment.py:112 [311] ``_local_maxima`` (the valley left of a peak taken over ``c[h:k - 1]``, without the
    bin next to the peak).

    Set-point levels are the histogram peaks of a channel that stand out from the valley towards any higher
    peak.  A record with two cycles at 4.0 kN and one at 4.25 kN (1.2 x the 200 N load tolerance above) has
    both levels and three sweeps.  The mutant misses the valley right beside the smaller peak, loses the
    4.25 kN level and drops its whole sweep as a 'set-point transition'.
    """
    from tyrefit.io.segment import segment_record

    rng = np.random.default_rng(2)
    a = np.r_[_cycle(), _cycle(), _cycle()]
    fz = np.r_[np.full(400, 4000.0), np.full(200, 4250.0)] + rng.normal(0.0, 3.0, 600)
    df = pd.DataFrame({"slip_angle": a * _DEG, "fz": fz, "fy": -100 * a}, index=np.arange(4, 604))
    out, meta = segment_record(df, "slip_angle")
    assert meta["n_sweeps"] == 3 and meta["dropped"] == {}
    assert_allclose([s["fz"] for s in meta["sweeps"]], [4000.0, 4000.0, 4250.0], atol=2.0)


def test_the_dwell_before_the_first_sweep_is_counted_as_a_dwell():
    """segment.py:260 [198] ``segment_record`` (``label[a:a + i0]`` -> ``label[a:a - i0]``: the leading dwell
    unlabelled, or a negative slice that relabels the rest of the record).

    The segmentation says what it dropped and why.  A record that starts unloaded (100 samples), dwells at
    zero slip (60), runs two cycles and dwells again (60) drops 100 samples as unloaded and the two dwells
    (122 samples with their edges) as dwells, none as 'between sweeps'.  The mutant counts the first dwell
    as 'between sweeps'.
    """
    from tyrefit.io.segment import segment_record

    a = np.r_[np.zeros(160), _cycle(), _cycle(), np.zeros(60)]
    fz = np.r_[np.full(100, 20.0), np.full(a.size - 100, 4000.0)]
    df = pd.DataFrame({"slip_angle": a * _DEG, "fz": fz, "fy": -100 * a * (fz > 100)},
                      index=np.arange(4, 4 + a.size))
    _, meta = segment_record(df, "slip_angle")
    assert meta["n_sweeps"] == 2
    assert meta["dropped"] == {"tyre unloaded (fz < 200 N)": 100, "dwell at constant slip": 122}


def test_the_time_order_note_counts_its_samples_in_the_plural(tmp_path):
    """readers.py:772 [455] ``_time_order`` (the plural of 'sample time' for ``back + same > 1`` -> ``back - same``).

    A logged record whose clock repeats one sample time and swaps two is read in time order with the note
    "1 repeated and 1 out-of-order sample times" (two sample times in all); the mutant says 'sample time'.
    """
    from tyrefit.io.readers import read_data

    a = np.concatenate([_cycle() for _ in range(6)])
    t = np.arange(a.size) * 0.01
    t[300] = t[299]
    t[600], t[601] = t[601], t[600]
    rows = ["time [s],slip_angle [deg],fy [N],fz [N]"]
    rows += [f"{x:.3f},{y:.4f},{-3000 * math.tanh(0.2 * y):.3f},3000" for x, y in zip(t, a)]
    (tmp_path / "rec.csv").write_text("\n".join(rows) + "\n")
    ds = read_data(tmp_path / "rec.csv")
    assert ds.meta["time_order"].startswith("time: 1 repeated and 1 out-of-order sample times;")


def test_the_fy0_start_follows_the_cornering_stiffness_of_the_data():
    """mf_initial.py:101 [136] ``_initial_pure`` (the start's PKY4 = 4 while PKY1, PKY2 are fitted for PKY4 = 2).

    The module docstring: PKY1 and PKY2 start from the cornering stiffness against load,
    K_y = PKY1 Fz0 sin(PKY4 atan(Fz / (PKY2 Fz0))) with PKY4 = 2.  The start's K_y is then within 10 % of the
    generating tyre's at each tested load (7 % here), a start near the data's curve.  The mutant starts
    PKY4 at 4 with the PKY1, PKY2 made for 2: its start K_y is 72 % too stiff at the lightest load.
    """
    from tyrefit.fitting.mf import fit_mf
    from tyrefit.synthetic import ttc_drivebrake as gen

    df, info = _mf_published([0.5, 1.0, 1.5], seed=5, n_points=31, combined=False)
    lat = df[df.groupby("run")["slip_ratio"].transform(lambda v: v.abs().max()) == 0]
    start = fit_mf(lat, tyre_info=info, stages=["Fy0"], multistart=False).stages["Fy0"].initial
    true = gen.contract_mf61()
    fn = true["FNOMIN"]

    def ky(c, fz):
        return c["PKY1"] * fn * np.sin(c["PKY4"] * np.arctan(fz / (c["PKY2"] * fn)))

    assert start["PKY4"] == 2.0
    for fz in (0.5 * fn, fn, 1.5 * fn):
        assert ky(start, fz) == pytest.approx(ky(true, fz), rel=0.10)


# ------------------------------------------------------------------------------ found on the way: fitting/noise.py
def test_an_up_and_down_cornering_record_in_three_degree_steps_is_fitted():
    """A bug found while building the tests above (not a sampled mutant): ``noise._magic_formula_ssr``.

    The noise floor fits one Magic Formula through each sweep, started from the slope of the points within
    1/8 of the slip range of zero.  A sweep 0 -> 12 -> -12 -> 0 deg in 3 deg steps visits 0 three times and
    has its +-3 deg points exactly 1/8 of the range away (left out by rounding): the slope was fitted to
    three points at one slip, numpy's least squares failed, and ``tyrefit fit`` ended in a LinAlgError
    traceback (exit 1).  Such a sweep is fitted (the slope then from the sweep's ends).
    """
    from tyrefit.fitting import fit_pac89
    from tyrefit.synthetic.pac89_example import lateral_sweeps

    up = np.arange(0.0, 12.1, 3.0)
    cycle = np.r_[up, up[::-1][1:], -up[1:], -up[::-1][1:-1], 0.0]
    r = fit_pac89(lateral_sweeps(loads=(3000.0, 5000.0, 7000.0), cambers_deg=(0.0,), slip_deg=cycle, seed=2))
    assert r.stats["lateral"]["r2"] > 0.999
    assert np.isfinite(r.stats["lateral"]["noise_floor"])
