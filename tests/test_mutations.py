"""Tests that kill the mutations issue 15 found surviving the suite.

Each test names the mutation it kills; ``benchmarks/mutation.py --named`` applies
them and checks that the suite now fails.  The scenarios mutant (the bundled
treadwear exponent silently replaced by HPwizard's 0.15) is killed by
``tests/test_sim_scenarios.py::test_traction_exponent_is_the_bundled_fit_or_an_error``.
"""

import math

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose

from tyrefit.effects import ModelInputs, lateral_force, relative_factor
from tyrefit.fitting import fit_pac89
from tyrefit.fitting.engine import _Problem, prepare_data
from tyrefit.models import pac89
from tyrefit.synthetic.pac89_example import EXAMPLE, lateral_sweeps
from tyrefit.tyres.pac89 import Pac89Tyre

BASE = ("a0", "a2", "a3", "a4", "a7")


# ----------------------------------------------------- mutant: 1/n sweep weighting dropped (default cost)
@pytest.fixture(scope="module")
def sweeps():
    # 4 loads, camber 0, -12..12 deg every 0.5 deg: 4 sweeps of 49 points
    return lateral_sweeps(cambers_deg=(0.0,), slip_deg=np.arange(-12.0, 12.0 + 1e-9, 0.5), seed=77)


def test_default_cost_is_the_mean_square_per_sweep(sweeps):
    """The l2 objective is sum over sweeps of the *mean* squared mu residual, computed here by hand."""
    parts, _ = prepare_data(sweeps)
    d = parts["lateral"]
    prob = _Problem(d, EXAMPLE, list(BASE), "l2")
    theta = prob.theta_of(dict(EXAMPLE, a3=0.9 * EXAMPLE["a3"], a7=EXAMPLE["a7"] + 0.3))
    c = prob.coeffs_of(theta)
    mu_res = (pac89.lateral_force(c, d.fz, d.slip, d.camber) - d.y) / d.fz
    by_hand = pd.Series(mu_res**2).groupby(d.run).mean().sum()
    assert prob.objective(theta) == pytest.approx(by_hand, rel=1e-12)


def test_repeating_a_sweeps_points_does_not_change_the_fit(sweeps):
    """With each sweep weighted 1/n, repeating every point of one sweep 4 times leaves the cost, and so the
    fitted tyre, exactly as it was; without the weighting that sweep would count 4 times as much."""
    dense = pd.concat([sweeps] + [sweeps[sweeps["run"] == 1]] * 3, ignore_index=True)
    a = fit_pac89(sweeps, vary=BASE).values
    b = fit_pac89(dense, vary=BASE).values
    assert_allclose([b[k] for k in BASE], [a[k] for k in BASE], rtol=2e-5)


# ---------------------------------------------------------- mutant: speed effect's stiffness term deleted
def test_speed_effect_scales_the_cornering_stiffness():
    """At small slip Fy ~ BCD alpha: with speed_ky = 0.3 and speed_mu = 0, twice the reference speed gives
    1 + 0.3 (2 - 1) = 1.3 times the cornering stiffness, while the peak force D is unchanged."""
    vals = dict(EXAMPLE, a8=0.0, a9=0.0, a10=0.0, a11=0.0, a12=0.0, a13=0.0, speed_mu=0.0, speed_ky=0.3)
    slip = np.radians(np.r_[0.05, np.linspace(0.5, 30.0, 300)])
    out = {}
    for v in (20.0, 40.0):
        x = ModelInputs(fz=np.full(slip.size, 4000.0), slip_angle=slip, camber=np.zeros(slip.size),
                        speed=np.full(slip.size, v), speed_ref=20.0)
        out[v] = lateral_force(vals, ["speed"], x)
    assert float(relative_factor(40.0, 20.0, 0.3)) == pytest.approx(1.3)
    assert out[40.0][0] / out[20.0][0] == pytest.approx(1.3, rel=2e-3)
    assert np.max(np.abs(out[40.0])) == pytest.approx(np.max(np.abs(out[20.0])), rel=2e-3)


# -------------------------------------------------------------------- mutant: a12 left out of mirrored()
def test_mirrored_tyre_is_the_mirror_image():
    """A right tyre is the left one mirrored: at zero camber Fy_R(alpha) = -Fy_L(-alpha) and
    Mz_R(alpha) = -Mz_L(-alpha), which needs every ply-steer and conicity shift flipped (a9, a10, a12, a13;
    c12, c13, c16, c17).  Each shift is given its own size so that leaving any one out shows."""
    c = dict(EXAMPLE, a9=0.02, a10=0.15, a12=25.0, a13=-40.0, c12=0.03, c13=-0.06, c16=-0.1, c17=-3.3)
    left = Pac89Tyre(coefficients=c)
    right = left.mirrored()
    fz = np.array([2000.0, 5000.0, 8000.0])[:, None]
    a = np.radians(np.linspace(-15.0, 15.0, 61))[None, :]
    assert_allclose(right.fy(fz, a), -left.fy(fz, -a), rtol=1e-12, atol=1e-9)
    assert_allclose(right.mz(fz, a), -left.mz(fz, -a), rtol=1e-12, atol=1e-9)
    # each shift matters on its own: the vertical shift at zero slip flips sign with the side
    for k in ("a9", "a10", "a12", "a13"):
        only = dict(EXAMPLE, a9=0.0, a10=0.0, a12=0.0, a13=0.0)
        only[k] = c[k]
        one = Pac89Tyre(coefficients=only)
        assert_allclose(one.mirrored().fy(fz, a), -one.fy(fz, -a), rtol=1e-12, atol=1e-9)
        assert np.max(np.abs(one.fy(fz, a) - (-one.fy(fz, -a)))) > 1.0  # the shift is visible


# ------------------------------------------------------------------ mutant: 89.5 deg clamp moved to 30 deg
def _plain_fy(p, fz_kn, alpha_deg):
    """PAC89 Fy (PAC89 signs) at zero camber, scalar math, no clamp (shared/reference/README.md)."""
    C = p["a0"]
    D = p["a1"] * fz_kn**2 + p["a2"] * fz_kn
    B = p["a3"] * math.sin(2.0 * math.atan(fz_kn / p["a4"])) / (C * D)
    E = p["a6"] * fz_kn + p["a7"]
    x = alpha_deg + p["a9"] * fz_kn + p["a10"]
    return D * math.sin(C * math.atan(B * x - E * (B * x - math.atan(B * x)))) + p["a12"] * fz_kn + p["a13"]


@pytest.mark.parametrize("alpha_deg", [-80.0, -45.0, 31.0, 45.0, 60.0, 80.0, 89.0])
def test_large_slip_angles_are_not_clamped_below_89_5_deg(alpha_deg):
    """Chrono's ChPac89Tire clamps the shifted slip x to +-89.5 deg, nowhere below: at 31-89 deg the
    model equals the unclamped formula (ISO-W: Fy is the negated PAC89 value)."""
    for fz in (2000.0, 6000.0):
        got = float(pac89.lateral_force(EXAMPLE, fz, math.radians(alpha_deg), 0.0))
        assert got == pytest.approx(-_plain_fy(EXAMPLE, fz / 1e3, alpha_deg), rel=1e-10, abs=1e-8)


def test_beyond_89_5_deg_the_shifted_slip_is_held_at_the_clamp():
    fz = 4000.0
    sh = EXAMPLE["a9"] * 4.0 + EXAMPLE["a10"]
    got = float(pac89.lateral_force(EXAMPLE, fz, math.radians(95.0), 0.0))
    assert got == pytest.approx(-_plain_fy(EXAMPLE, 4.0, 89.5 - sh), rel=1e-10)
