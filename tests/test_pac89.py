"""PAC89 model: published example set at fixed points, signs, Jacobians."""

import math
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tyrefit.io.tir import read_tir
from tyrefit.models import pac89

DATA = Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def example():
    return read_tir(DATA / "ref_adams_pac89_example.tir").coefficients


# -- a separate, plainly written PAC89 (scalar math only), from shared/reference/README.md --------
def _mf(x, B, C, D, E):
    return D * math.sin(C * math.atan(B * x - E * (B * x - math.atan(B * x))))


def plain_fy_pac(p, fz_kn, alpha_deg, gamma_deg):
    C = p["a0"]
    D = p["a1"] * fz_kn ** 2 + p["a2"] * fz_kn
    BCD = p["a3"] * math.sin(2.0 * math.atan(fz_kn / p["a4"])) * (1.0 - p["a5"] * abs(gamma_deg))
    B = BCD / (C * D)
    E = p["a6"] * fz_kn + p["a7"]
    Sh = p["a8"] * gamma_deg + p["a9"] * fz_kn + p["a10"]
    Sv = p["a11"] * fz_kn * gamma_deg + p["a12"] * fz_kn + p["a13"]
    return _mf(alpha_deg + Sh, B, C, D, E) + Sv


def plain_fx(p, fz_kn, kappa_pct):
    C = p["b0"]
    D = p["b1"] * fz_kn ** 2 + p["b2"] * fz_kn
    BCD = (p["b3"] * fz_kn ** 2 + p["b4"] * fz_kn) * math.exp(-p["b5"] * fz_kn)
    B = BCD / (C * D)
    E = p["b6"] * fz_kn ** 2 + p["b7"] * fz_kn + p["b8"]
    Sh = p["b9"] * fz_kn + p["b10"]
    return _mf(kappa_pct + Sh, B, C, D, E)


def plain_mz_pac(p, fz_kn, alpha_deg, gamma_deg):
    C = p["c0"]
    D = p["c1"] * fz_kn ** 2 + p["c2"] * fz_kn
    BCD = (p["c3"] * fz_kn ** 2 + p["c4"] * fz_kn) * (1 - p["c6"] * abs(gamma_deg)) * math.exp(-p["c5"] * fz_kn)
    B = BCD / (C * D)
    E = (p["c7"] * fz_kn ** 2 + p["c8"] * fz_kn + p["c9"]) * (1 - p["c10"] * abs(gamma_deg))
    Sh = p["c11"] * gamma_deg + p["c12"] * fz_kn + p["c13"]
    Sv = (p["c14"] * fz_kn ** 2 + p["c15"] * fz_kn) * gamma_deg + p["c16"] * fz_kn + p["c17"]
    return _mf(alpha_deg + Sh, B, C, D, E) + Sv


POINTS = [(fz, a, g) for fz in (2000.0, 4000.0, 6500.0, 8000.0) for a in (-10.0, -3.0, -0.5, 0.0, 1.0, 4.0, 12.0)
          for g in (-4.0, 0.0, 2.5)]


def test_example_set_matches_plain_table(example):
    # ISO-W: slip angle and camber keep their sign into PAC89; Fy and Mz change sign on the way out
    table_fy = [-plain_fy_pac(example, fz / 1e3, a, g) for fz, a, g in POINTS]
    table_mz = [-plain_mz_pac(example, fz / 1e3, a, g) for fz, a, g in POINTS]
    fz, a, g = (np.array(v) for v in zip(*POINTS))
    assert_allclose(pac89.lateral_force(example, fz, np.radians(a), np.radians(g)), table_fy, rtol=1e-12, atol=1e-9)
    assert_allclose(pac89.aligning_moment(example, fz, np.radians(a), np.radians(g)), table_mz, rtol=1e-12, atol=1e-9)
    kap = np.array([-0.3, -0.05, 0.0, 0.02, 0.1, 0.25])
    for f in (2000.0, 5000.0, 8000.0):
        assert_allclose(pac89.longitudinal_force(example, f, kap), [plain_fx(example, f / 1e3, 100 * k) for k in kap],
                        rtol=1e-12, atol=1e-9)


def test_example_set_published_magnitudes(example):
    # a hand-checkable anchor: peak factor D = a1 Fz^2 + a2 Fz at 4 kN is 4456 N; the curve comes within 2 %
    fy = pac89.lateral_force(example, 4000.0, np.radians(np.linspace(-20, 20, 801)), 0.0)
    assert 0.97 * 4456.0 < np.max(np.abs(fy)) < 4456.0 + 200.0  # + Sv (a12 Fz + a13 = 11.1 N)


def test_iso_w_signs(example):
    # DESIGN.md: in ISO-W a positive slip angle gives a negative lateral force, a3 > 0 in PAC89
    assert example["a3"] > 0
    assert pac89.lateral_force(example, 4000.0, math.radians(5.0)) < 0
    assert pac89.lateral_force(example, 4000.0, math.radians(-5.0)) > 0
    # aligning moment restores: opposite sign to Fy away from the shifts
    assert pac89.aligning_moment(example, 4000.0, math.radians(3.0)) > 0
    # Fx keeps its sign: positive (driving) slip gives positive force
    assert pac89.longitudinal_force(example, 4000.0, 0.1) > 0


def test_return_factors(example):
    fy, f = pac89.lateral_force(example, 4000.0, 0.05, 0.0, return_factors=True)
    assert f.C == pytest.approx(1.65)
    assert f.D == pytest.approx(-34.0 * 16 + 1250.0 * 4)
    assert f.E == pytest.approx(-0.02103 * 4 + 0.77394)


def test_broadcasting_and_nan(example):
    out = pac89.lateral_force(example, np.array([[2000.0], [4000.0]]), np.radians([0.0, 1.0, np.nan]))
    assert out.shape == (2, 3)
    assert np.isnan(out[:, 2]).all() and np.isfinite(out[:, :2]).all()


def test_clamp_at_89_5_deg(example):
    a = pac89.lateral_force(example, 4000.0, math.radians(89.9))
    b = pac89.lateral_force(example, 4000.0, math.radians(120.0))
    assert a == pytest.approx(b)


@pytest.mark.parametrize("part", ["lateral", "longitudinal", "aligning"])
def test_jacobian_matches_central_differences(example, part):
    rng = np.random.default_rng(0)
    n = 60
    fz = rng.uniform(1500, 9000, n)
    sa = np.radians(rng.uniform(-15, 15, n))
    ga = np.radians(rng.uniform(-5, 5, n))
    kap = rng.uniform(-0.4, 0.4, n)
    if part == "lateral":
        f, jf, names, args = pac89.lateral_force, pac89.lateral_jacobian, pac89.LATERAL, (fz, sa, ga)
    elif part == "longitudinal":
        f, jf, names, args = pac89.longitudinal_force, pac89.longitudinal_jacobian, pac89.LONGITUDINAL, (fz, kap)
    else:
        f, jf, names, args = pac89.aligning_moment, pac89.aligning_jacobian, pac89.ALIGNING, (fz, sa, ga)
    y, J = jf(example, *args)
    assert_allclose(y, f(example, *args), rtol=1e-13)
    for j, k in enumerate(names):
        h = 1e-6 * max(abs(example[k]), 1e-3)
        up, dn = dict(example), dict(example)
        up[k] += h
        dn[k] -= h
        fd = (f(up, *args) - f(dn, *args)) / (2 * h)
        assert_allclose(J[:, j], fd, rtol=1e-5, atol=1e-6 * np.max(np.abs(fd)) + 1e-9, err_msg=k)


def test_jacobian_subset_columns(example):
    _, J = pac89.lateral_jacobian(example, 4000.0, np.radians([1.0, 5.0]), 0.0, names=("a3", "a0"))
    _, Jall = pac89.lateral_jacobian(example, 4000.0, np.radians([1.0, 5.0]), 0.0)
    assert_allclose(J, Jall[:, [3, 0]])
    with pytest.raises(KeyError):
        pac89.lateral_jacobian(example, 4000.0, 0.1, 0.0, names=("b3",))
