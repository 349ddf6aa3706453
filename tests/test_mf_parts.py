"""The MF model by parts (tyrefit.fitting.mf_parts): the same numbers as mf61.forces, and the Mx Jacobian."""

from __future__ import annotations

import numpy as np
import pytest

from tyrefit.fitting import mf_parts
from tyrefit.models import mf61
from tyrefit.synthetic import ttc_drivebrake as gen

_DEG = np.pi / 180


def _points(n=400, seed=0):
    rng = np.random.default_rng(seed)
    p = gen.published_mf61()
    fz = rng.uniform(0.4, 1.6, n) * p["FNOMIN"]
    kap = rng.uniform(-0.2, 0.2, n)
    alp = rng.uniform(-12, 12, n) * _DEG
    gam = rng.choice([0.0, 2.0, 4.0], n) * _DEG
    pr = rng.choice([220e3, 260e3, 300e3], n)
    sp = np.full(n, 11.1)
    return p, (fz, kap, alp, gam, pr, sp)


@pytest.mark.parametrize("version", ["6.1", "5.2"])
def test_state_and_updates_are_forces(version):
    p, args = _points()
    f = mf_parts.Forces(version, *args)
    f.bind(p)
    rng = np.random.default_rng(1)
    names = ["PDX1", "PKX1", "PCY1", "PKY1", "PEY1", "QBZ1", "QDZ1", "QDZ6", "RBX1", "RHX1", "RBY1", "RVY1", "SSZ1",
             "SSZ2", "LMUV", "FNOMIN"]
    c, b = f.coefficients([])
    st = f.state(c, b)
    fz, kap, alp, gam, pr, sp = args
    ref = mf61.forces(p, fz, kap, alp, gam, pr, sp, version=version)
    for ch in ("fx", "fy", "mz"):
        np.testing.assert_array_equal(f.out(st, ch), ref[ch])
    for k in names:
        v = float(p.get(k, 0.0)) * (1 + 0.05 * rng.standard_normal()) + 0.01
        q = dict(p, **{k: v})
        ref = mf61.forces(q, fz, kap, alp, gam, pr, sp, version=version)
        cj, bj = f.coefficients([(k, v)])
        sj = f.update(st, cj, bj, mf_parts.group(k, f.v52))
        for ch in ("fx", "fy", "mz"):
            np.testing.assert_allclose(f.out(sj, ch), ref[ch], rtol=1e-12, atol=1e-9, err_msg=f"{k} {ch}")
        untouched = set(("fx", "fy", "mz")) - set(mf_parts.TOUCHES[mf_parts.group(k, f.v52)])
        for ch in untouched:  # a channel the group does not touch does not move
            np.testing.assert_array_equal(f.out(sj, ch), f.out(st, ch))


def test_mx_jacobian_is_the_derivative():
    p, args = _points()
    p.update(QSX4=0.4, QSX5=0.3, QSX6=1.1, QSX7=0.5, QSX8=1.2, QSX9=0.4, QSX10=0.1, QSX11=0.8, QSX12=0.3,
             QSX13=0.01, QSX14=0.02, PPMX1=0.3, QSX2=0.5)
    f = mf_parts.Forces("6.1", *args)
    f.bind(p)
    c, b = f.coefficients([])
    fy = f.out(f.state(c, b), "fy")
    names = [f"QSX{i}" for i in range(1, 15)] + ["PPMX1"]
    J = mf_parts.mx_jacobian(c, b, fy, names)
    assert list(J) == names
    for k in names:
        h = 1e-6 * max(1.0, abs(c[k]))
        up, dn = dict(c, **{k: c[k] + h}), dict(c, **{k: c[k] - h})
        fd = (mf61._mx(up, b, fy) - mf61._mx(dn, b, fy)) / (2 * h)
        np.testing.assert_allclose(J[k], fd, rtol=1e-6, atol=1e-6 * np.max(np.abs(fd)) + 1e-9, err_msg=k)


@pytest.mark.parametrize("pure", [True, False])
def test_mz_jacobian_is_the_derivative(pure):
    """Pure Mz0 (kappa = 0, Fx = 0, as the Mz0 stage) and combined Mz (the Mz and Mz* stages)."""
    p, args = _points(seed=3)
    if pure:
        args = (args[0], 0.0 * args[1]) + args[2:]
    p.update(QDZ10=0.05, QDZ11=0.02, PPZ1=0.3, PPZ2=0.2, QBZ4=0.1, QBZ5=-0.2, QEZ5=0.3, QHZ3=0.01, QHZ4=0.02,
             SSZ1=0.01, SSZ2=0.02, SSZ3=0.1, SSZ4=0.05, QBZ10=0.1)
    f = mf_parts.Forces("6.1", *args)
    f.bind(p)
    c, b = f.coefficients([])
    st = f.state(c, b)
    fyp = st["fyp"]
    if pure:
        fy_prime, kxk, fx, fy = st["fyg0"], 0.0, 0.0, fyp["fy0"]
    else:
        fy_prime, kxk, fx, fy = st["fy_prime"], st["kxk"], st["fx"], st["fy"]
    names = list(mf61.GROUPS["mz0"]) + list(mf61.GROUPS["mz"])

    def mz(cc):
        return mf61._mz(cc, b, mf61._mz_parts(cc, b, fyp), fy_prime, kxk, fx, fy)[0]

    J = mf_parts.mz_jacobian(c, b, fyp, fy_prime, kxk, fx, fy, names)
    assert set(J) == set(names)
    for k in names:
        h = 1e-6 * max(1.0, abs(c[k]))
        fd = (mz(dict(c, **{k: c[k] + h})) - mz(dict(c, **{k: c[k] - h}))) / (2 * h)
        fd = np.broadcast_to(fd, J[k].shape)
        ok = np.abs(fd) < 1e3 * (np.median(np.abs(fd)) + 1e-9)  # not across a kink (E_t = 1, alpha_t = 0)
        np.testing.assert_allclose(J[k][ok], fd[ok], rtol=2e-5, atol=1e-6 * np.max(np.abs(fd)) + 1e-9, err_msg=k)
