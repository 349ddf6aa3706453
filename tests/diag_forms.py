"""Independent truths for testing ``tyrefit diagnose`` (test helper, not a test module).

The diagnosis fits PAC89 plus catalogue effects; data generated from those
same forms would make its tests circular.  Here the tyre is a Magic Formula
written out afresh (Pacejka, *Tyre and Vehicle Dynamics*, Eq. 4.49:
y = D sin(C atan(B x - E (B x - atan(B x))))), in SI units and ISO-W signs,
and every effect takes a form the catalogue does not contain:

==============  ===========================================================
family          truth form here (catalogue form in brackets)
==============  ===========================================================
load_friction   mu = mu0 (Fz/Fref)^-p, a power law  [D = a1 Fz^2 + a2 Fz]
curvature_load  E = E0 + e1 tanh((Fz - Fm)/Fs)       [E = a6 Fz + a7]
offsets         Sh = sh0 + sh1 sqrt(Fz/Fref), Sv = sv0 + sv1 (Fz/Fref)^1.5
                                                      [linear in Fz]
overload        mu = mu0 (1 - k softplus_w(Fz - Fr)/Fr), a smooth knee
                                                      [a hinge at Fr]
==============  ===========================================================

The base tyre (the null) has the usual cornering-stiffness law
Ky = c1 sin(2 atan(Fz/c2)) -- every Magic Formula variant shares it -- with
constant friction and curvature; its parameters are drawn per seed.

Layouts: ``one_per_load`` (5-7 loads, one -12..+12 deg sweep each at 0.5 deg,
one pressure, no camber: a supplier's dynamic-rig sheet), ``repeated``
(loads x repeats), ``one_sided`` (0..12 deg).  Noise models: ``iid``;
``offsets`` (a random offset per sweep, 0.6 sigma, plus 0.8 sigma independent);
``ar1`` (AR(1) along the sweep, rho 0.8, stationary sd sigma).
"""

from __future__ import annotations

import zlib

import numpy as np
import pandas as pd

DEG = np.pi / 180.0
FAMILIES = ("load_friction", "curvature_load", "offsets", "overload")
NOISES = ("iid", "offsets", "ar1")


def magic_formula(alpha, fz, mu, c, ky, e, sh=0.0, sv=0.0):
    """ISO-W lateral force [N] of a Magic Formula tyre (Pacejka Eq. 4.49), alpha [rad], fz [N], ky [N/rad]."""
    d = mu * fz
    b = ky / (c * d)
    x = alpha + sh
    bx = b * x
    return -(d * np.sin(c * np.arctan(bx - e * (bx - np.arctan(bx))))) + sv


def _softplus(x, w):
    return w * np.logaddexp(0.0, x / w)


def tyre(rng):
    """A passenger tyre drawn at random: mu0, C, Ky law (c1 [N/rad], c2 [N]), E0."""
    return {"mu0": rng.uniform(0.95, 1.2), "c": rng.uniform(1.3, 1.6), "c1": rng.uniform(70e3, 100e3),
            "c2": rng.uniform(6e3, 9e3), "e0": rng.uniform(-0.6, 0.1)}


def truth_force(t, family, alpha, fz, rng_effect, fref, rated):
    """Force of tyre ``t`` with the hidden ``family`` (None: the null) in its non-catalogue form."""
    mu = np.full_like(fz, t["mu0"])
    e = np.full_like(fz, t["e0"])
    sh = sv = 0.0
    if family == "load_friction":
        mu = t["mu0"] * (fz / fref) ** (-rng_effect.uniform(0.08, 0.14))
    elif family == "curvature_load":
        e = t["e0"] + rng_effect.choice([-1, 1]) * rng_effect.uniform(0.3, 0.45) * np.tanh((fz - fref) / (0.4 * fref))
    elif family == "offsets":
        s = rng_effect.choice([-1, 1])
        sh = s * (rng_effect.uniform(0.1, 0.2) + rng_effect.uniform(0.05, 0.1) * np.sqrt(fz / fref)) * DEG
        sv = -s * (rng_effect.uniform(40, 80) + rng_effect.uniform(20, 40) * (fz / fref) ** 1.5)
    elif family == "overload":
        mu = t["mu0"] * (1 - rng_effect.uniform(0.35, 0.5) * _softplus(fz - rated, 0.04 * rated) / rated)
    elif family is not None:
        raise ValueError(family)
    ky = t["c1"] * np.sin(2 * np.arctan(fz / t["c2"]))
    return magic_formula(alpha, fz, mu, t["c"], ky, e, sh, sv)


def noise(kind, sweep, sigma, rng, rho=0.8):
    n = len(sweep)
    if kind == "iid":
        return rng.normal(0, sigma, n)
    if kind == "offsets":
        return rng.normal(0, 0.6 * sigma, sweep.max() + 1)[sweep] + rng.normal(0, 0.8 * sigma, n)
    if kind == "ar1":
        out = np.empty(n)
        w = rng.normal(0, sigma * np.sqrt(1 - rho**2), n)
        for i in range(n):
            out[i] = rng.normal(0, sigma) if i == 0 or sweep[i] != sweep[i - 1] else rho * out[i - 1] + w[i]
        return out
    raise ValueError(kind)


def make(family, noise_kind, seed, layout="one_per_load", n_loads=6, repeats=1, sigma=30.0, slip_max_deg=12.0,
         step_deg=0.5, above_rated=2):
    """One data set: (DataFrame with canonical SI columns, rated load [N], true sigma [N]).

    ``above_rated`` load levels lie above the rated load (overload needs >= 1).
    """
    rng = np.random.default_rng([seed, zlib.crc32(f"{family}|{noise_kind}|{layout}".encode())])
    t = tyre(rng)
    loads = np.linspace(2000.0, rng.uniform(6500, 8000), n_loads)
    rated = 0.5 * (loads[-above_rated - 1] + loads[-above_rated])
    fref = float(np.median(loads))
    lo = 0.0 if layout == "one_sided" else -slip_max_deg
    slips = np.arange(lo, slip_max_deg + 1e-9, step_deg) * DEG
    rows = []
    run = 0
    for _ in range(repeats):
        for fz in loads:
            rows.append(pd.DataFrame({"run": run, "fz": fz * (1 + 0.005 * rng.standard_normal(len(slips))),
                                      "slip_angle": slips}))
            run += 1
    d = pd.concat(rows, ignore_index=True)
    fy = truth_force(t, family, d["slip_angle"].to_numpy(), d["fz"].to_numpy(), np.random.default_rng(seed + 7),
                     fref, rated)
    d["fy"] = fy + noise(noise_kind, d["run"].to_numpy(), sigma, rng)
    return d, rated, sigma
