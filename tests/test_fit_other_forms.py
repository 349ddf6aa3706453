"""Fits of data drawn from a model form other than the one fitted (issue 25, "Tests that bite").

Every other fitting test draws its data from :mod:`tyrefit.models` itself, so an error in a model moves the
data and the fit together and no test sees it.  Here the data come from a form the fit does not share:

1. a brush tyre written out in this file (no tyrefit code), fitted with PAC89 and with MF 6.1;
2. MFeval's published MF 6.1 parameter set (``data/mfeval_MagicFormula61_Paramerters.tir``; tyrefit's
   MF 6.1 evaluator is checked against MFeval in ``test_mf52_61keys.py``), fitted with PAC89;
3. the Adams/Tire PAC89 example set (``data/ref_adams_pac89_example.tir``; tyrefit's PAC89 evaluator is
   checked against Chrono's ``ChPac89Tire`` in ``test_pac89_chrono_reference.py``), fitted with MF 6.1.

The data go through the public path an engineer uses: ``tyrefit.read_tyre`` evaluates the two files, the
sweeps are written as a CSV with unit headers in kN, deg and % (so the readers' unit conversions are on the
path), and ``tyrefit.fit`` fits them.  The fitted tyres are judged on what engineers read off a tyre, per
load: cornering and slip stiffness at zero slip, peak friction on each side, the force at zero slip, the
RMSE.  The reference numbers come from closed forms written in this file -- the brush model's, and the two
files' pure-slip equations at zero camber and nominal pressure evaluated from the coefficients as the file
states them (its own small parser) -- never from tyrefit's evaluators, so an error in
:mod:`tyrefit.models` cannot move the data and the reference together.

Where the fitted form cannot carry a feature of the source, the expected value says so and why (the
brush curve's |sigma| sigma term; PAC89's Fx, which has no vertical shift); everything else is compared
directly.  Each tolerance is at least 1.5 x the largest disagreement of a correct fit over five noise seeds
(numbers in each test); the file passes for a dozen other seeds.
"""

from __future__ import annotations

import functools
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.optimize import least_squares

import tyrefit as tf

DATA = Path(__file__).parent / "data"
MF61_FILE = DATA / "mfeval_MagicFormula61_Paramerters.tir"
PAC89_FILE = DATA / "ref_adams_pac89_example.tir"

LOADS = (2000.0, 4000.0, 6000.0, 8000.0)  # [N]: inside MFeval's FZMIN..FZMAX = 0..18 kN
SLIP_ANGLE_DEG = np.linspace(-15.0, 15.0, 61)  # rig sweeps, 0.5 deg steps
SLIP_RATIO = np.linspace(-0.25, 0.25, 51)
NOISE = 0.005  # noise sigma: 0.5 % of each sweep's peak |F|
H = 1e-5  # central-difference step at zero slip [rad] / [-]
DENSE_ANGLE = np.radians(np.linspace(-15.0, 15.0, 3001))  # the tested range, for peaks
DENSE_RATIO = np.linspace(-0.25, 0.25, 2001)


# ------------------------------------------------------------------------------------------- the brush tyre
MU = 0.95  # brush friction coefficient (not 1, so that a lost mu shows)
FZ_REF = 4000.0  # [N]
A_REF = 0.06  # contact half-length at FZ_REF [m]
C_ALPHA_REF = 80e3  # cornering stiffness at FZ_REF [N/rad]
C_P = C_ALPHA_REF / (2.0 * A_REF**2)  # tread stiffness per unit length [N/m^2]


def half_length(fz):
    """Contact half-length a [m], growing as sqrt(Fz) (a circle pressed in by a deflection ~ Fz: a^2 ~ 2 R delta)."""
    return A_REF * np.sqrt(np.asarray(fz, dtype=float) / FZ_REF)


def brush_cornering_stiffness(fz):
    """C_alpha = 2 c_p a^2 [N/rad] (Pacejka 2012, Ch. 3: the brush model's slope at zero slip)."""
    return 2.0 * C_P * half_length(fz) ** 2


def brush_fy(fz, slip_angle):
    """Lateral force [N] of the brush model with a parabolic pressure distribution, ISO-W.

    Pacejka, *Tire and Vehicle Dynamics*, 3rd ed. (2012), Ch. 3, theory of the brush model, pure side slip
    (Fiala's form): with theta = 2 c_p a^2 / (3 mu Fz) and sigma = tan(alpha),

        |Fy| = 3 mu Fz theta |sigma| (1 - theta |sigma| + (theta sigma)^2 / 3)   for |sigma| < 1 / theta,
        |Fy| = mu Fz                                                              beyond (full sliding),

    and Fy has the sign opposite to alpha (ISO-W: a positive slip angle gives a negative lateral force,
    ``tyrefit/nomenclature.py``).  Independent of tyrefit's own brush code.
    """
    fz = np.asarray(fz, dtype=float)
    sigma = np.tan(np.asarray(slip_angle, dtype=float))
    theta = 2.0 * C_P * half_length(fz) ** 2 / (3.0 * MU * fz)
    ts = theta * sigma
    adhesion = -3.0 * MU * fz * ts * (1.0 - np.abs(ts) + ts**2 / 3.0)
    return np.where(np.abs(ts) < 1.0, adhesion, -MU * fz * np.sign(sigma))


def brush_fy_by_strips(fz, slip_angle, n=40001):
    """The same brush force integrated strip by strip over the contact length (a check of the closed form).

    A bristle at x (from the leading edge x = a to the trailing edge x = -a) carries c_p (a - x) |tan alpha|
    per unit length while it adheres and mu q(x) once it slides, with q(x) = 3 Fz / (4 a) (1 - x^2 / a^2);
    the parabola is concave, so the bristle force is the smaller of the two everywhere.
    """
    a = float(half_length(fz))
    x = np.linspace(-a, a, n)
    q = 3.0 * fz / (4.0 * a) * (1.0 - (x / a) ** 2)
    s = math.tan(slip_angle)
    per_length = np.minimum(C_P * (a - x) * abs(s), MU * q)
    return -math.copysign(1.0, s) * float(np.sum((per_length[1:] + per_length[:-1]) / 2 * np.diff(x)))


def magic_formula(x, B, C, D, E):
    return D * np.sin(C * np.arctan(B * x - E * (B * x - np.arctan(B * x))))


@functools.lru_cache(maxsize=None)
def _best_magic_formula(fz: float):
    """Least-squares D sin(C atan(Bx - E(Bx - atan Bx))) (E <= 1) through the noiseless brush sweep at ``fz``
    (mu units; a plain scipy fit, no tyrefit code).  Two minima: C ~ 1.29, E ~ -0.26 and, 4.6 % lower in cost,
    C ~ 2.0 on the bound E = 1; both starts are tried and the better kept."""
    alpha = np.radians(SLIP_ANGLE_DEG)
    y = -brush_fy(fz, alpha) / fz
    c0 = float(brush_cornering_stiffness(fz)) / fz
    bounds = ([0.0, 0.1, 0.0, -10.0], [np.inf, 3.0, 3.0, 1.0])
    fits = [least_squares(lambda p: magic_formula(alpha, *p) - y, [c0 / (C * MU), C, MU, E], bounds=bounds)
            for C, E in ((1.3, 0.0), (2.0, 0.9))]
    return min(fits, key=lambda r: r.cost)


def magic_formula_residual(fz):
    """The residual [N] of the best Magic Formula through the noiseless brush sweep at ``fz``: the form gap."""
    return _best_magic_formula(fz).fun * fz


def magic_formula_stiffness_ratio(fz):
    """BCD / C_alpha of the best Magic Formula curve (E <= 1) through the noiseless brush sweep at ``fz``.

    The brush curve falls from its slope as 1 - theta |sigma| (a |sigma| sigma term); the Magic Formula's
    falls as sigma^2 (odd in sigma, no |sigma| sigma term).  Its least-squares best over the tested +-15 deg
    therefore has a slope at zero slip below C_alpha: 0.886 here, at every load (theta is load-independent
    with a ~ sqrt(Fz)); the other minimum's is 0.880.
    """
    B, C, D, _ = _best_magic_formula(fz).x
    return B * C * D / (float(brush_cornering_stiffness(fz)) / fz)


# ------------------------------------------------------------------- the two files' pure-slip closed forms
def read_keys(path) -> dict[str, float]:
    """Every ``KEY = number`` line of a ``.tir`` file, as written (a key given twice must agree)."""
    out: dict[str, float] = {}
    pat = re.compile(r"\s*([A-Za-z][A-Za-z0-9_]*)\s*=\s*([-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?)\s*(?:\$.*)?$")
    for line in Path(path).read_text(encoding="latin-1").splitlines():
        m = pat.match(line)
        if m:
            key, value = m.group(1), float(m.group(2))
            assert out.get(key, value) == value, f"{path}: {key} given twice with different values"
            out[key] = value
    return out


def mf61_fy(p, fz, alpha):
    """MF 6.1 pure lateral force Fy0 [N] at zero camber and nominal pressure, ISO-W (Pacejka 2012, 4.E19-4.E30).

    Cy = PCY1, Dy = (PDY1 + PDY2 dfz) Fz, K_ya = PKY1 Fz0 sin(PKY4 atan(Fz / (PKY2 Fz0))), By = K_ya / (Cy Dy),
    SHy = PHY1 + PHY2 dfz, SVy = Fz (PVY1 + PVY2 dfz), Ey = (PEY1 + PEY2 dfz)(1 - PEY3 sgn(alpha_y)),
    alpha_y = alpha* + SHy with alpha* = alpha as MFeval and TNO's MF-Tyre (not the book's tan alpha, 4.E3).
    Every scaling factor of the file is 1 and the speed is above VXLOW (checked in the fixture).
    """
    fz0 = p["FNOMIN"]
    dfz = (fz - fz0) / fz0
    C = p["PCY1"]
    D = (p["PDY1"] + p["PDY2"] * dfz) * fz
    K = p["PKY1"] * fz0 * np.sin(p["PKY4"] * np.arctan(fz / (p["PKY2"] * fz0)))
    ay = np.asarray(alpha, dtype=float) + p["PHY1"] + p["PHY2"] * dfz
    E = (p["PEY1"] + p["PEY2"] * dfz) * (1.0 - p["PEY3"] * np.sign(ay))
    return magic_formula(ay, K / (C * D), C, D, E) + fz * (p["PVY1"] + p["PVY2"] * dfz)


def mf61_fx(p, fz, kappa):
    """MF 6.1 pure longitudinal force Fx0 [N] at zero camber and nominal pressure (Pacejka 2012, 4.E9-4.E18)."""
    fz0 = p["FNOMIN"]
    dfz = (fz - fz0) / fz0
    C = p["PCX1"]
    D = (p["PDX1"] + p["PDX2"] * dfz) * fz
    K = fz * (p["PKX1"] + p["PKX2"] * dfz) * np.exp(p["PKX3"] * dfz)
    kx = np.asarray(kappa, dtype=float) + p["PHX1"] + p["PHX2"] * dfz
    E = (p["PEX1"] + p["PEX2"] * dfz + p["PEX3"] * dfz**2) * (1.0 - p["PEX4"] * np.sign(kx))
    return magic_formula(kx, K / (C * D), C, D, E) + fz * (p["PVX1"] + p["PVX2"] * dfz)


def pac89_fy(c, fz, alpha):
    """PAC89 (Bakker, Pacejka, Lidner 1989; Adams/Tire, Chrono ChPac89Tire) lateral force at zero camber, ISO-W.

    Fz in kN, alpha in deg: C = a0, D = (a1 Fz + a2) Fz, BCD = a3 sin(2 atan(Fz / a4)), E = a6 Fz + a7,
    Sh = a9 Fz + a10, Sv = a12 Fz + a13; the file's positive slip angle gives positive Fy (its header), ISO-W's
    negative: Fy = -(MF(alpha + Sh) + Sv).
    """
    F = fz * 1e-3
    C, D = c["a0"], (c["a1"] * F + c["a2"]) * F
    B = c["a3"] * np.sin(2.0 * np.arctan(F / c["a4"])) / (C * D)
    x = np.degrees(alpha) + c["a9"] * F + c["a10"]
    return -(magic_formula(x, B, C, D, c["a6"] * F + c["a7"]) + c["a12"] * F + c["a13"])


def pac89_fx(c, fz, kappa):
    """PAC89 longitudinal force (slip in %): C = b0, D = (b1 Fz + b2) Fz, BCD = (b3 Fz^2 + b4 Fz) exp(-b5 Fz),
    E = b6 Fz^2 + b7 Fz + b8, Sh = b9 Fz + b10, no vertical shift."""
    F = fz * 1e-3
    C, D = c["b0"], (c["b1"] * F + c["b2"]) * F
    B = (c["b3"] * F**2 + c["b4"] * F) * np.exp(-c["b5"] * F) / (C * D)
    x = 100.0 * np.asarray(kappa, dtype=float) + c["b9"] * F + c["b10"]
    return magic_formula(x, B, C, D, c["b6"] * F**2 + c["b7"] * F + c["b8"])


# ------------------------------------------------------------------------------------------------- helpers
def _noisy(f, rng, sigmas):
    """f plus normal noise of sigma = NOISE x the sweep's peak |f| (each point's sigma appended to ``sigmas``)."""
    f = np.asarray(f, dtype=float)
    sigma = NOISE * np.max(np.abs(f))
    sigmas.extend([sigma] * f.size)
    return f + sigma * rng.standard_normal(f.size)


def _rms(sigmas):
    return float(np.sqrt(np.mean(np.square(sigmas))))


def _lateral_sweep(run, fz, fy):
    return pd.DataFrame({"run": run, "fz [kN]": fz / 1e3, "slip_angle [deg]": SLIP_ANGLE_DEG,
                         "camber [deg]": 0.0, "fy [N]": fy})


def _longitudinal_sweep(run, fz, fx):
    return pd.DataFrame({"run": run, "fz [kN]": fz / 1e3, "slip_ratio [%]": 100.0 * SLIP_RATIO,
                         "camber [deg]": 0.0, "fx [N]": fx})


def _write(path, frames):
    pd.concat(frames, ignore_index=True).to_csv(path, index=False, float_format="%.6f")
    return path


def fy_of(tyre, **kw):
    """A tyre's pure lateral force as a function (fz, slip angles [rad]) -> Fy [N]."""
    return lambda fz, a: tyre.forces(np.full(np.shape(a), fz), slip_angle=np.asarray(a, float), **kw)["fy"]


def fx_of(tyre, **kw):
    """A tyre's pure longitudinal force as a function (fz, slip ratios) -> Fx [N]."""
    return lambda fz, k: tyre.forces(np.full(np.shape(k), fz), slip_ratio=np.asarray(k, float), **kw)["fx"]


def cornering_stiffness(fy, fz):
    """-dFy/dalpha at zero slip [N/rad] (positive for a tyre with ISO-W signs)."""
    f = fy(fz, np.array([H, -H]))
    return -(f[0] - f[1]) / (2 * H)


def slip_stiffness(fx, fz):
    """dFx/dkappa at zero slip [N per unit slip ratio]."""
    f = fx(fz, np.array([H, -H]))
    return (f[0] - f[1]) / (2 * H)


def lateral_peaks(fy, fz):
    """Peak |Fy| / Fz over the tested range, (positive slip angles, negative slip angles)."""
    f = fy(fz, DENSE_ANGLE) / fz
    return np.array([np.max(-f[DENSE_ANGLE > 0]), np.max(f[DENSE_ANGLE < 0])])


def longitudinal_peaks(fx, fz):
    """Peak |Fx| / Fz over the tested range, (driving, braking)."""
    f = fx(fz, DENSE_RATIO) / fz
    return np.array([np.max(f[DENSE_RATIO > 0]), np.max(-f[DENSE_RATIO < 0])])


def at_zero(f, fz):
    """The force at zero slip [N] (ply steer and conicity for Fy)."""
    return float(f(fz, np.zeros(1))[0])


def curvatures(tyre, fz) -> np.ndarray:
    """The fitted tyre's curvature factors E at load ``fz``, zero camber, both slip signs, from its coefficients:
    PAC89 E = a6 Fz + a7 and b6 Fz^2 + b7 Fz + b8 (Fz in kN); MF 6.1 Ey (4.E24) and Ex (4.E14)."""
    if tyre.family == "PAC89":
        c, F = tyre.coefficients, fz * 1e-3
        return np.array([c["a6"] * F + c["a7"], c["b6"] * F**2 + c["b7"] * F + c["b8"]])
    p = {k: tyre.params.get(k, 0.0) for k in ("PEY1", "PEY2", "PEY3", "PEX1", "PEX2", "PEX3", "PEX4")}
    fz0 = tyre.params["FNOMIN"] * tyre.params.get("LFZO", 1.0)
    dfz = (fz - fz0) / fz0
    ey = (p["PEY1"] + p["PEY2"] * dfz) * tyre.params.get("LEY", 1.0)
    ex = (p["PEX1"] + p["PEX2"] * dfz + p["PEX3"] * dfz**2) * tyre.params.get("LEX", 1.0)
    return np.array([ey * (1.0 - p["PEY3"]), ey * (1.0 + p["PEY3"]), ex * (1.0 - p["PEX4"]), ex * (1.0 + p["PEX4"])])


def assert_curvature_at_most_one(tyre):
    """E <= 1 over the fitted loads: beyond 1 the force turns back with slip (the contract of the README)."""
    for fz in np.linspace(min(LOADS), max(LOADS), 25):
        e = curvatures(tyre, fz)
        assert np.all(e <= 1.0 + 1e-9), f"{tyre.family} at {fz:.0f} N: E = {np.round(e, 4)}"


# ==================================================================== 1. brush-model data -> PAC89, MF 6.1
def test_brush_closed_form_is_the_strip_integral():
    """The data generator itself: the closed form equals the strip integral, its slope at zero slip is
    2 c_p a^2, it saturates at mu Fz, and its sign is ISO-W's."""
    for fz in LOADS:
        for deg in (-12.0, -6.0, -1.0, 0.3, 2.0, 5.0, 9.0, 15.0):
            a = math.radians(deg)
            assert float(brush_fy(fz, a)) == pytest.approx(brush_fy_by_strips(fz, a), rel=1e-6)
        slope = -(brush_fy(fz, 1e-7) - brush_fy(fz, -1e-7)) / 2e-7
        assert slope == pytest.approx(brush_cornering_stiffness(fz), rel=1e-5)
        assert float(brush_fy(fz, math.radians(15.0))) == pytest.approx(-MU * fz)
        assert brush_fy(fz, math.radians(3.0)) < 0 < brush_fy(fz, math.radians(-3.0))


@pytest.fixture(scope="module")
def brush_csv(tmp_path_factory):
    rng = np.random.default_rng(2025)
    sigmas: list[float] = []
    frames = [_lateral_sweep(i + 1, fz, _noisy(brush_fy(fz, np.radians(SLIP_ANGLE_DEG)), rng, sigmas))
              for i, fz in enumerate(LOADS)]
    return _write(tmp_path_factory.mktemp("brush") / "brush_sweeps.csv", frames), _rms(sigmas)


@pytest.fixture(scope="module", params=["pac89", "mf61"])
def brush_fit(request, brush_csv):
    return request.param, tf.fit(brush_csv[0], model=request.param)


def test_brush_fit_cornering_stiffness_per_load(brush_fit):
    """Measured (5 noise seeds): fitted slope / (0.886 C_alpha) = 0.997-1.004 (PAC89), 0.993-0.999 (MF 6.1) at
    every load; against C_alpha alone 0.884-0.890 and 0.880-0.885, the Magic Formula's own limit for this curve
    (:func:`magic_formula_stiffness_ratio`, 0.886).  Fy at 2 deg: +0.6 to +1.2 % of the closed form.
    Tolerances 2 % and 2 %."""
    model, r = brush_fit
    fy = fy_of(r.tyre)
    for fz in LOADS:
        c_alpha = float(brush_cornering_stiffness(fz))
        ratio = magic_formula_stiffness_ratio(fz)
        assert 0.86 < ratio < 0.90, f"the Magic Formula's best slope for the brush curve moved: {ratio:.4f}"
        got = cornering_stiffness(fy, fz)
        assert got == pytest.approx(ratio * c_alpha, rel=0.02), (
            f"{model} at {fz:.0f} N: {got:.0f} N/rad, expected {ratio:.3f} x C_alpha = {ratio * c_alpha:.0f} "
            f"(C_alpha = 2 c_p a^2 = {c_alpha:.0f})")
        # the force at 2 deg, where the stiffness is read on a rig, against the closed form itself
        a2 = math.radians(2.0)
        assert float(r.tyre.fy(fz, a2)) == pytest.approx(float(brush_fy(fz, a2)), rel=0.02)


def test_brush_fit_peak_friction_and_zero_offset_per_load(brush_fit):
    """Measured (5 seeds): |Fy|max / Fz = mu x 1.004-1.008 on both sides at every load; |Fy(0)| at most 0.47 %
    of mu Fz (the brush tyre has none: the noise's share).  Tolerances 2 % and 1 % of mu Fz."""
    model, r = brush_fit
    fy = fy_of(r.tyre)
    for fz in LOADS:
        pos, neg = lateral_peaks(fy, fz)
        assert pos == pytest.approx(MU, rel=0.02), f"{model} at {fz:.0f} N, positive slip"
        assert neg == pytest.approx(MU, rel=0.02), f"{model} at {fz:.0f} N, negative slip"
        assert abs(at_zero(fy, fz)) < 0.01 * MU * fz, f"{model} at {fz:.0f} N: Fy(0) = {at_zero(fy, fz):.1f} N"


def test_brush_fit_rmse(brush_fit, brush_csv):
    """The RMSE is the noise and the Magic Formula's form gap together: sqrt(noise^2 + gap^2), the gap being
    the RMS residual of the best Magic Formula through the noiseless brush sweeps (30 N; noise 26 N).  Measured
    (5 seeds): RMSE / that = 0.89-1.12; the fitted curve's largest distance from the noiseless brush curve is
    1.1-1.7 % of mu Fz.  Tolerances 1.3 x and 2.5 %."""
    model, r = brush_fit
    gap = _rms([np.sqrt(np.mean(np.square(magic_formula_residual(fz)))) for fz in LOADS])
    assert r.rmse < 1.3 * math.hypot(brush_csv[1], gap), f"{model}: RMSE {r.rmse:.1f} N"
    for fz in LOADS:
        err = np.max(np.abs(r.tyre.fy(fz, DENSE_ANGLE) - brush_fy(fz, DENSE_ANGLE))) / (MU * fz)
        assert err < 0.025, f"{model} at {fz:.0f} N: {100 * err:.2f} % of mu Fz"


def test_brush_fit_is_physical(brush_fit):
    """The brush curve's flat top pulls E up: PAC89's fit ends on its bound E = 1 at both load ends (the fit
    says so in its notes).  The bound must hold: E <= 1 over the fitted loads, from the coefficients."""
    assert_curvature_at_most_one(brush_fit[1].tyre)


# =========================================================== 2. MFeval's published MF 6.1 file -> PAC89
@pytest.fixture(scope="module")
def mf61_source():
    """(the file read by tyrefit, its evaluation conditions, its coefficients as written)."""
    tyre = tf.read_tyre(MF61_FILE)
    keys = read_keys(MF61_FILE)
    assert tyre.family == "MF61" and keys["FZMIN"] <= min(LOADS) and max(LOADS) <= keys["FZMAX"]
    # what the closed forms assume: every scaling factor 1, no speed decay, rolling above VXLOW
    assert all(v == 1.0 for k, v in keys.items() if re.fullmatch(r"L[A-Z]{1,4}", k) and k != "LONGVL")
    assert keys.get("LMUV", 0.0) == 0.0 and keys["LONGVL"] > keys["VXLOW"]
    return tyre, {"pressure": keys["NOMPRES"], "camber": 0.0}, keys


def test_mf61_source_is_the_files_equations(mf61_source):
    """The data the fit sees are the file's equations: tyrefit's evaluation of MFeval's file against the closed
    forms above, to 1e-6 N (measured 3e-7 N, the EPSILON in By and Bx)."""
    src, cond, keys = mf61_source
    a, k = np.radians(SLIP_ANGLE_DEG), SLIP_RATIO
    for fz in LOADS:
        np.testing.assert_allclose(fy_of(src, **cond)(fz, a), mf61_fy(keys, fz, a), rtol=0, atol=1e-6)
        np.testing.assert_allclose(fx_of(src, **cond)(fz, k), mf61_fx(keys, fz, k), rtol=0, atol=1e-6)


@pytest.fixture(scope="module")
def pac89_of_mf61(mf61_source, tmp_path_factory):
    src, cond, _ = mf61_source
    rng = np.random.default_rng(61)
    frames, run, sig_y, sig_x = [], 0, [], []
    for fz in LOADS:
        # what a rig measures: every channel of the source, at the other slip held at zero
        lat = src.forces(np.full(SLIP_ANGLE_DEG.size, fz), slip_angle=np.radians(SLIP_ANGLE_DEG), **cond)
        lon = src.forces(np.full(SLIP_RATIO.size, fz), slip_ratio=SLIP_RATIO, **cond)
        run += 1
        frames.append(_lateral_sweep(run, fz, _noisy(lat["fy"], rng, sig_y)).assign(
            **{"slip_ratio [%]": 0.0, "fx [N]": _noisy(lat["fx"], rng, [])}))
        run += 1
        frames.append(_longitudinal_sweep(run, fz, _noisy(lon["fx"], rng, sig_x)).assign(
            **{"slip_angle [deg]": 0.0, "fy [N]": _noisy(lon["fy"], rng, [])}))
    csv = _write(tmp_path_factory.mktemp("mf61") / "mf61_sweeps.csv", frames)
    return tf.fit(csv, model="pac89")


def _mf61_ref(keys):
    return (lambda fz, a: mf61_fy(keys, fz, a)), (lambda fz, k: mf61_fx(keys, fz, k))


def test_pac89_of_mf61_cornering_and_slip_stiffness(mf61_source, pac89_of_mf61):
    """Against the file's slope at zero slip (closed form): measured (5 seeds) C_alpha within 0.9 %, C_kappa
    within 1.6 %.  Tolerance 3 %."""
    keys = mf61_source[2]
    ry, rx = _mf61_ref(keys)
    fit = pac89_of_mf61.tyre
    for fz in LOADS:
        assert cornering_stiffness(fy_of(fit), fz) == pytest.approx(cornering_stiffness(ry, fz), rel=0.03)
        assert slip_stiffness(fx_of(fit), fz) == pytest.approx(slip_stiffness(rx, fz), rel=0.03)


def test_pac89_of_mf61_peak_friction_and_zero_offset(mf61_source, pac89_of_mf61):
    """Lateral: each side's peak |Fy| / Fz against the file's, measured within 1.2 % (5 seeds), and Fy at zero
    slip within 0.93 % of the file's Dy (the file: -36 to -184 N; PAC89's one curvature for both sides cannot
    follow the file's PEY3 = 0.78, and the offset takes part of that).  Tolerances 3 % and 1.5 % of Dy.

    Longitudinal: PAC89's Fx has no vertical shift (Sv = 0; Bakker et al. 1989, ``tyrefit/models/pac89.py``),
    so its driving and braking peaks are equal; the file's differ (1.33 / 1.17 at 2 kN: PVX1 = 0.072).  Each
    fitted peak is compared with the mean of the file's two, measured within 0.4 %.  Tolerance 3 %.  For the same
    reason Fx at zero slip is not compared (the fit's +51..+262 N against the file's -24..-68 N)."""
    keys = mf61_source[2]
    ry, rx = _mf61_ref(keys)
    fy, fx = fy_of(pac89_of_mf61.tyre), fx_of(pac89_of_mf61.tyre)
    for fz in LOADS:
        for got, want, side in zip(lateral_peaks(fy, fz), lateral_peaks(ry, fz), ("+", "-")):
            assert got == pytest.approx(want, rel=0.03), f"mu_y at {fz:.0f} N, {side} slip"
        dy = np.mean(lateral_peaks(ry, fz)) * fz
        assert at_zero(fy, fz) == pytest.approx(at_zero(ry, fz), abs=0.015 * dy), f"Fy(0) at {fz:.0f} N"
        want_x = np.mean(longitudinal_peaks(rx, fz))
        for got, side in zip(longitudinal_peaks(fx, fz), ("driving", "braking")):
            assert got == pytest.approx(want_x, rel=0.03), f"mu_x at {fz:.0f} N, {side}"


def test_pac89_of_mf61_rmse(pac89_of_mf61):
    """Measured (5 seeds): Fy RMSE 45-49 N = 0.6 % of the largest lateral peak (~8 kN; PAC89 has no
    sign-dependent curvature, PEY3 = 0.78); Fx RMSE 310-315 N = 3.2 % of the largest longitudinal peak (9.8 kN):
    the file's driving/braking asymmetry, which PAC89's Fx cannot carry.  Tolerances 1.2 % and 4.5 %.  And E <= 1."""
    s = pac89_of_mf61.stats
    assert s["lateral"]["rmse"] < 0.012 * 8000.0
    assert s["longitudinal"]["rmse"] < 0.045 * 1.22 * 8000.0
    assert_curvature_at_most_one(pac89_of_mf61.tyre)


# ================================================================ 3. Adams' PAC89 example -> MF 6.1
@pytest.fixture(scope="module")
def pac89_source():
    """(the file read by tyrefit, its coefficients as written)."""
    tyre = tf.read_tyre(PAC89_FILE)
    assert tyre.family == "PAC89"
    return tyre, read_keys(PAC89_FILE)


def test_pac89_source_is_the_files_equations(pac89_source):
    """tyrefit's evaluation of the Adams example against the closed forms above (measured: round-off)."""
    src, keys = pac89_source
    a, k = np.radians(SLIP_ANGLE_DEG), SLIP_RATIO
    for fz in LOADS:
        np.testing.assert_allclose(fy_of(src)(fz, a), pac89_fy(keys, fz, a), rtol=1e-12, atol=1e-6)
        np.testing.assert_allclose(fx_of(src)(fz, k), pac89_fx(keys, fz, k), rtol=1e-12, atol=1e-6)


@pytest.fixture(scope="module")
def mf61_of_pac89(pac89_source, tmp_path_factory):
    src = pac89_source[0]
    rng = np.random.default_rng(89)
    d = tmp_path_factory.mktemp("pac89")
    sig_y, sig_x = [], []
    lat = [_lateral_sweep(i + 1, fz, _noisy(src.fy(fz, np.radians(SLIP_ANGLE_DEG)), rng, sig_y))
           for i, fz in enumerate(LOADS)]
    lon = [_longitudinal_sweep(i + 1, fz, _noisy(src.fx(fz, SLIP_RATIO), rng, sig_x))
           for i, fz in enumerate(LOADS)]
    fit = tf.fit([_write(d / "cornering.csv", lat), _write(d / "drive_brake.csv", lon)], model="mf61")
    return fit, {"fy": _rms(sig_y), "fx": _rms(sig_x)}


def _pac89_ref(keys):
    return (lambda fz, a: pac89_fy(keys, fz, a)), (lambda fz, k: pac89_fx(keys, fz, k))


def test_mf61_of_pac89_cornering_and_slip_stiffness(pac89_source, mf61_of_pac89):
    """Measured (5 seeds): C_alpha within 0.8 %, C_kappa within 0.8 %.  Tolerance 2 %."""
    ry, rx = _pac89_ref(pac89_source[1])
    fit = mf61_of_pac89[0].tyre
    for fz in LOADS:
        assert cornering_stiffness(fy_of(fit), fz) == pytest.approx(cornering_stiffness(ry, fz), rel=0.02)
        assert slip_stiffness(fx_of(fit), fz) == pytest.approx(slip_stiffness(rx, fz), rel=0.02)


def test_mf61_of_pac89_peak_friction_and_zero_offset(pac89_source, mf61_of_pac89):
    """Measured (5 seeds): each side's peak |Fy| / Fz and |Fx| / Fz within 0.2 %; Fy and Fx at zero slip within
    0.39 % (Fy) and 0.18 % (Fx) of the peak force (the file: Fy(0) -37 to -319 N, Fx(0) -47 to +104 N).
    Tolerances 2 %, and 1 % (Fy(0)) and 0.5 % (Fx(0)) of the peak."""
    ry, rx = _pac89_ref(pac89_source[1])
    fit = mf61_of_pac89[0].tyre
    fy, fx = fy_of(fit), fx_of(fit)
    for fz in LOADS:
        for got, want in zip(lateral_peaks(fy, fz), lateral_peaks(ry, fz)):
            assert got == pytest.approx(want, rel=0.02), f"mu_y at {fz:.0f} N"
        for got, want in zip(longitudinal_peaks(fx, fz), longitudinal_peaks(rx, fz)):
            assert got == pytest.approx(want, rel=0.02), f"mu_x at {fz:.0f} N"
        peak_y, peak_x = np.max(lateral_peaks(ry, fz)) * fz, np.max(longitudinal_peaks(rx, fz)) * fz
        assert at_zero(fy, fz) == pytest.approx(at_zero(ry, fz), abs=0.01 * peak_y), f"Fy(0) at {fz:.0f} N"
        assert at_zero(fx, fz) == pytest.approx(at_zero(rx, fz), abs=0.005 * peak_x), f"Fx(0) at {fz:.0f} N"


def test_mf61_of_pac89_rmse(mf61_of_pac89):
    """MF 6.1 carries the PAC89 curves within the noise: measured (5 seeds) RMSE / the noise added = 0.95-1.03
    (Fy), 0.90-1.01 (Fx).  Tolerance 1.25 x the noise.  And E <= 1."""
    fit, noise = mf61_of_pac89
    for ch in ("fy", "fx"):
        assert fit.stats[ch]["rmse"] < 1.25 * noise[ch], f"{ch}: RMSE {fit.stats[ch]['rmse']:.1f} N"
    assert_curvature_at_most_one(fit.tyre)
