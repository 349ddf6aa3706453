"""Pacejka '89 (Adams PAC89) steady-state tyre model.

Evaluated exactly as Project Chrono's ``ChPac89Tire`` does (Adams/Tire PAC89):
coefficients in PAC89's own units (Fz in kN, slip angle and camber in degrees,
longitudinal slip in percent, forces in N, moments in N*m) and its "modified
SAE" sign convention, in which a positive slip angle gives a positive lateral
force (``a3 > 0``).

The public functions take and return **SI and ISO-W**: ``fz`` [N] positive in
compression, ``slip_angle`` and ``camber`` [rad], ``slip_ratio`` [-], and
return ``fy``, ``fx`` [N] and ``mz`` [N*m] in ISO-W, where a positive slip
angle gives a negative lateral force.  The ISO-W <-> PAC89 mapping lives in
:func:`_to_pac` and :func:`_from_pac` and nowhere else in tyrefit:
``fy`` and ``mz`` are negated on the way out; slip angle, camber, slip ratio
and ``fx`` keep their sign.

Why only one flip: PAC89's "modified SAE" axes have y to the right and z
down (ISO-W: y left, z up), so lateral force and aligning moment change sign
between the two, while its slip angle is SAE's negated, which is ISO-W's
slip angle.  Negating *both* the slip angle and Fy (as Chrono does with its
own slip-angle definition, in which a positive angle gives a positive force)
would leave the odd part of Fy(alpha) unchanged and give a positive Fy for
a positive ISO-W slip angle with a3 > 0, against the ISO-W data convention
of DESIGN.md.  With the mapping here, a normal tyre (a3 > 0) gives
Fy < 0 and Mz > 0 for a positive ISO-W slip angle, and camber thrust
(a11 > 0) pushes towards the side the wheel top leans to (Fy < 0 for
positive ISO-W inclination).

The model is pure: no validation, no clipping of loads; NumPy broadcasting
over ``fz``, ``slip_angle``, ``camber`` and over array-valued coefficients.

References
----------
Bakker, Nyborg, Pacejka (1989), Tyre modelling for use in vehicle dynamics
studies, SAE 870421 / the 1989 extension; Adams/Tire PAC89 documentation;
Chrono ``ChPac89Tire.cpp``.  Komana, Els, Becker, *Cost efficient tyre
testing, modelling and validation for PBS assessments* (Eq. 2-5) fit a0-a13
on the friction coefficient.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

__all__ = [
    "LATERAL",
    "LONGITUDINAL",
    "ALIGNING",
    "ALL",
    "PARTS",
    "Factors",
    "magic_formula",
    "lateral_factors",
    "longitudinal_factors",
    "aligning_factors",
    "lateral_force",
    "longitudinal_force",
    "aligning_moment",
    "magic_formula_partials",
    "lateral_jacobian",
    "longitudinal_jacobian",
    "aligning_jacobian",
]

LATERAL: tuple[str, ...] = tuple(f"a{i}" for i in range(14))
LONGITUDINAL: tuple[str, ...] = tuple(f"b{i}" for i in range(11))
ALIGNING: tuple[str, ...] = tuple(f"c{i}" for i in range(18))
ALL: tuple[str, ...] = LATERAL + LONGITUDINAL + ALIGNING
#: the coefficients of each part (a block present in a tyre file must give them all)
PARTS: dict[str, tuple[str, ...]] = {"lateral": LATERAL, "longitudinal": LONGITUDINAL, "aligning": ALIGNING}

_RAD2DEG = 180.0 / np.pi
#: Chrono clamps the shifted slip to +/-89.5 deg before the Magic Formula
X_LIMIT_DEG = 89.5


class Factors(NamedTuple):
    """Magic Formula factors at each point (PAC89 units and convention)."""

    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    E: np.ndarray
    Sh: np.ndarray
    Sv: np.ndarray


def magic_formula(x, B, C, D, E):
    """y = D sin(C atan(B x - E (B x - atan(B x))))  (Pacejka's Magic Formula)."""
    bx = B * x
    return D * np.sin(C * np.arctan(bx - E * (bx - np.arctan(bx))))


# --- the one place where ISO-W meets PAC89 ------------------------------------
def _to_pac(fz, slip_angle, camber):
    """SI/ISO-W inputs -> PAC89 inputs: Fz [kN], alpha [deg], gamma [deg] (signs kept)."""
    return (np.asarray(fz, dtype=float) * 1e-3,
            np.asarray(slip_angle, dtype=float) * _RAD2DEG,
            np.asarray(camber, dtype=float) * _RAD2DEG)


def _from_pac(value):
    """PAC89 lateral force or aligning moment -> ISO-W (negated)."""
    return -value


# --- factors --------------------------------------------------------------------
def lateral_factors(p: Mapping[str, float], fzk, gamma) -> Factors:
    """PAC89 lateral factors at ``fzk`` [kN] and ``gamma`` [deg] (PAC89 units).

    C = a0, D = a1 Fz^2 + a2 Fz, BCD = a3 sin(2 atan(Fz/a4)) (1 - a5 |gamma|),
    B = BCD / (C D), E = a6 Fz + a7, Sh = a8 gamma + a9 Fz + a10,
    Sv = a11 Fz gamma + a12 Fz + a13.
    sin(2 atan z) is evaluated as 2 z / (1 + z^2) (the same value without
    trigonometric calls, which dominate the cost of large evaluations).
    """
    return _lateral_parts(p, fzk, gamma)[0]


def _lateral_parts(p: Mapping[str, float], fzk, gamma) -> tuple[Factors, dict]:
    """:func:`lateral_factors` and the terms in load and camber that its Jacobian reuses.

    Returns the factors and ``fzk2`` = Fz^2, ``z2`` = (Fz/a4)^2, ``den`` = 1 + z2, ``s2`` = sin(2 atan(Fz/a4)),
    ``ag`` = |gamma|, ``cam`` = 1 - a5 |gamma| and ``CD`` = C D.
    """
    fzk2 = fzk**2
    C = p["a0"] + 0.0 * fzk
    D = p["a1"] * fzk2 + p["a2"] * fzk
    z = fzk / p["a4"]
    z2 = z * z
    den = 1.0 + z2
    s2 = 2.0 * z / den  # = sin(2 atan z)
    ag = np.abs(gamma)
    cam = 1.0 - p["a5"] * ag
    BCD = p["a3"] * s2 * cam
    CD = C * D
    B = BCD / CD
    E = p["a6"] * fzk + p["a7"]
    Sh = p["a8"] * gamma + p["a9"] * fzk + p["a10"]
    Sv = p["a11"] * fzk * gamma + p["a12"] * fzk + p["a13"]
    return Factors(B, C, D, E, Sh, Sv), {"fzk2": fzk2, "z2": z2, "den": den, "s2": s2, "ag": ag, "cam": cam, "CD": CD}


def longitudinal_factors(p: Mapping[str, float], fzk) -> Factors:
    """PAC89 longitudinal factors at ``fzk`` [kN] (slip in percent).

    C = b0, D = b1 Fz^2 + b2 Fz, BCD = (b3 Fz^2 + b4 Fz) exp(-b5 Fz),
    E = b6 Fz^2 + b7 Fz + b8, Sh = b9 Fz + b10, Sv = 0.
    """
    C = p["b0"] + 0.0 * fzk
    D = p["b1"] * fzk**2 + p["b2"] * fzk
    BCD = (p["b3"] * fzk**2 + p["b4"] * fzk) * np.exp(-p["b5"] * fzk)
    B = BCD / (C * D)
    E = p["b6"] * fzk**2 + p["b7"] * fzk + p["b8"]
    Sh = p["b9"] * fzk + p["b10"]
    return Factors(B, C, D, E, Sh, 0.0 * fzk)


def aligning_factors(p: Mapping[str, float], fzk, gamma) -> Factors:
    """PAC89 aligning-moment factors at ``fzk`` [kN] and ``gamma`` [deg].

    C = c0, D = c1 Fz^2 + c2 Fz, BCD = (c3 Fz^2 + c4 Fz)(1 - c6 |gamma|) exp(-c5 Fz),
    E = (c7 Fz^2 + c8 Fz + c9)(1 - c10 |gamma|), Sh = c11 gamma + c12 Fz + c13,
    Sv = (c14 Fz^2 + c15 Fz) gamma + c16 Fz + c17.
    """
    C = p["c0"] + 0.0 * fzk
    D = p["c1"] * fzk**2 + p["c2"] * fzk
    BCD = (p["c3"] * fzk**2 + p["c4"] * fzk) * (1.0 - p["c6"] * np.abs(gamma)) * np.exp(-p["c5"] * fzk)
    B = BCD / (C * D)
    E = (p["c7"] * fzk**2 + p["c8"] * fzk + p["c9"]) * (1.0 - p["c10"] * np.abs(gamma))
    Sh = p["c11"] * gamma + p["c12"] * fzk + p["c13"]
    Sv = (p["c14"] * fzk**2 + p["c15"] * fzk) * gamma + p["c16"] * fzk + p["c17"]
    return Factors(B, C, D, E, Sh, Sv)


# --- forces and moments (SI, ISO-W) ---------------------------------------------
def lateral_force(p: Mapping[str, float], fz, slip_angle, camber=0.0, *, return_factors: bool = False):
    """Lateral force Fy [N] in ISO-W.

    Parameters
    ----------
    p : mapping
        PAC89 coefficients ``a0``..``a13`` (PAC89 units and convention).
    fz : array_like
        Normal load [N], positive in compression.
    slip_angle : array_like
        Slip angle [rad], ISO-W.
    camber : array_like, optional
        Camber (inclination) angle [rad].
    return_factors : bool
        Also return the :class:`Factors` (B, C, D, E, Sh, Sv) in PAC89 units.

    Notes
    -----
    Fy_pac = D sin(C atan(B x - E (B x - atan B x))) + Sv with x = alpha + Sh,
    alpha = slip_angle in degrees, x clamped to +/-89.5 deg as in Chrono;
    Fy = -Fy_pac.
    """
    fzk, alpha, gamma = _to_pac(fz, slip_angle, camber)
    f = lateral_factors(p, fzk, gamma)
    x = np.clip(alpha + f.Sh, -X_LIMIT_DEG, X_LIMIT_DEG)
    fy = _from_pac(magic_formula(x, f.B, f.C, f.D, f.E) + f.Sv)
    return (fy, f) if return_factors else fy


def longitudinal_force(p: Mapping[str, float], fz, slip_ratio, *, return_factors: bool = False):
    """Longitudinal force Fx [N], positive driving (same sign in ISO-W and PAC89).

    ``slip_ratio`` [-] is converted to percent; Fx = D sin(C atan(B x - E(B x - atan B x)))
    with x = 100 kappa + Sh.
    """
    fzk = np.asarray(fz, dtype=float) * 1e-3
    kappa = np.asarray(slip_ratio, dtype=float) * 100.0
    f = longitudinal_factors(p, fzk)
    fx = magic_formula(kappa + f.Sh, f.B, f.C, f.D, f.E) + f.Sv
    return (fx, f) if return_factors else fx


def aligning_moment(p: Mapping[str, float], fz, slip_angle, camber=0.0, *, return_factors: bool = False):
    """Aligning moment Mz [N*m] in ISO-W (pure side slip; no Fx*deflection term)."""
    fzk, alpha, gamma = _to_pac(fz, slip_angle, camber)
    f = aligning_factors(p, fzk, gamma)
    x = np.clip(alpha + f.Sh, -X_LIMIT_DEG, X_LIMIT_DEG)
    mz = _from_pac(magic_formula(x, f.B, f.C, f.D, f.E) + f.Sv)
    return (mz, f) if return_factors else mz


# --- analytic Jacobians (for fitting) -------------------------------------------
def magic_formula_partials(x, B, C, D, E):
    """Magic Formula value and its partial derivatives.

    Returns ``(y, dy_dx, dy_dB, dy_dC, dy_dD, dy_dE)`` for
    y = D sin(C atan(Phi)), Phi = (1 - E) B x + E atan(B x), each a partial
    derivative with the other arguments held constant (B is *not* expanded
    into BCD / (C D) here; see :func:`_factor_partials`).
    """
    u = B * x
    atu = np.arctan(u)
    w = u - atu
    phi = u - E * w
    at_phi = np.arctan(phi)
    theta = C * at_phi
    s = np.sin(theta)
    # cos from sin (one trigonometric call instead of two; |error| <~ 1e-8 where cos ~ 0,
    # i.e. at the peak, where the derivatives that use it vanish anyway)
    c = np.sqrt(np.maximum(1.0 - s * s, 0.0))
    c = np.where(np.abs(theta) > 0.5 * np.pi, -c, c)
    y = D * s
    Dc = D * c
    dy_dphi = Dc * C / (1.0 + phi * phi)
    dphi_du = (1.0 - E) + E / (1.0 + u * u)
    g = dy_dphi * dphi_du
    return y, g * B, g * x, Dc * at_phi, s, -dy_dphi * w


def _factor_partials(x, f: Factors, cd=None):
    """y and dy/d(C, D, BCD, E, Sh, Sv) with B = BCD / (C D) expanded (PAC89 units); ``cd``: C D if made."""
    y, dx, dB, dC, dD, dE = magic_formula_partials(x, f.B, f.C, f.D, f.E)
    dBCD = dB / (f.C * f.D if cd is None else cd)
    dBB = dB * f.B
    return (y + f.Sv, {"C": dC - dBB / f.C, "D": dD - dBB / f.D, "BCD": dBCD,
                       "E": dE, "Sh": dx, "Sv": 1.0})


def _assemble(names, all_names, columns, shape, sign=1.0):
    """Jacobian ``shape + (len(names),)`` from per-coefficient columns (arrays, scalars or callables).

    Built column by column in a (k,) + ``shape`` array (contiguous writes) and
    returned with that axis moved last; ``sign`` is applied on the way (the
    ISO-W output mapping).  Only the requested columns are computed.
    """
    out = np.empty((len(names),) + tuple(shape))
    for j, name in enumerate(names):
        if name not in all_names:
            raise KeyError(f"{name} is not a coefficient of this part ({all_names[0]}..{all_names[-1]})")
        v = columns[name]
        np.multiply(v() if callable(v) else v, sign, out=out[j])
    return out.transpose(tuple(range(1, out.ndim)) + (0,))


def lateral_jacobian(p: Mapping[str, float], fz, slip_angle, camber=0.0, names=LATERAL):
    """Lateral force [N] (ISO-W) and its analytic Jacobian wrt PAC89 coefficients.

    Parameters
    ----------
    p : mapping
        ``a0``..``a13`` (PAC89 units).
    fz, slip_angle, camber : array_like
        [N], [rad], [rad], SI and ISO-W, broadcast to a common 1-D shape.
    names : sequence of str
        coefficients to differentiate with respect to (columns of the Jacobian).

    Returns
    -------
    fy : ndarray, shape (n,)
        lateral force [N], ISO-W (identical to :func:`lateral_force`).
    jac : ndarray, shape (n, len(names))
        d fy / d coefficient [N per coefficient unit], ISO-W.

    Coefficients may be arrays that broadcast against the points, e.g.
    (F, 1) columns holding F coefficient sets: ``fy`` then has the broadcast
    shape (F, n) and ``jac`` that shape plus the coefficient axis.

    Notes
    -----
    Chain rule through C = a0, D = a1 Fz^2 + a2 Fz,
    BCD = a3 sin(2 atan(Fz/a4)) (1 - a5 |gamma|), B = BCD/(C D), E = a6 Fz + a7,
    Sh = a8 gamma + a9 Fz + a10, Sv = a11 Fz gamma + a12 Fz + a13.  Where
    Chrono's +/-89.5 deg clamp on x is active, dF/dSh = 0.
    """
    fzk, alpha, gamma = _to_pac(fz, slip_angle, camber)
    if not (fzk.ndim == 1 and fzk.shape == alpha.shape == gamma.shape):
        fzk, alpha, gamma = np.broadcast_arrays(np.atleast_1d(fzk), np.atleast_1d(alpha), np.atleast_1d(gamma))
    f, t = _lateral_parts(p, fzk, gamma)
    xs = alpha + f.Sh
    x = np.minimum(np.maximum(xs, -X_LIMIT_DEG), X_LIMIT_DEG)  # Chrono's clamp (np.clip, without its overhead)
    y, d = _factor_partials(x, f, t["CD"])
    ag, s2, cam, z2, den, fzk2 = t["ag"], t["s2"], t["cam"], t["z2"], t["den"], t["fzk2"]
    dBCD = d["BCD"]
    a3, a4 = p["a3"], p["a4"]
    made = []

    def dSh():  # dF/dSh, zero where the clamp holds x
        if not made:
            made.append(np.where(np.abs(xs) < X_LIMIT_DEG, d["Sh"], 0.0))
        return made[0]

    cols = {
        "a0": d["C"],
        "a1": lambda: d["D"] * fzk2,
        "a2": lambda: d["D"] * fzk,
        "a3": lambda: dBCD * s2 * cam,
        # d/da4 sin(2 atan(Fz/a4)) = cos(2 atan(Fz/a4)) * (-2 Fz / (a4^2 + Fz^2)), cos(2 atan z) = (1-z^2)/(1+z^2)
        "a4": lambda: dBCD * (a3 * cam * ((1.0 - z2) / den) * (-2.0 * fzk / (a4**2 + fzk2))),
        "a5": lambda: dBCD * (-a3 * s2 * ag),
        "a6": lambda: d["E"] * fzk,
        "a7": d["E"],
        "a8": lambda: dSh() * gamma,
        "a9": lambda: dSh() * fzk,
        "a10": dSh,
        "a11": lambda: fzk * gamma,
        "a12": fzk,
        "a13": 1.0,
    }
    sign = _from_pac(1.0)
    return sign * y, _assemble(tuple(names), LATERAL, cols, np.shape(y), sign)


def longitudinal_jacobian(p: Mapping[str, float], fz, slip_ratio, names=LONGITUDINAL):
    """Longitudinal force [N] and its analytic Jacobian wrt ``b0``..``b10``.

    Same layout as :func:`lateral_jacobian`; C = b0, D = b1 Fz^2 + b2 Fz,
    BCD = (b3 Fz^2 + b4 Fz) exp(-b5 Fz), E = b6 Fz^2 + b7 Fz + b8,
    Sh = b9 Fz + b10 (Fz in kN, slip in percent).
    """
    fzk = np.atleast_1d(np.asarray(fz, dtype=float) * 1e-3)
    kappa = np.atleast_1d(np.asarray(slip_ratio, dtype=float) * 100.0)
    fzk, kappa = np.broadcast_arrays(fzk, kappa)
    f = longitudinal_factors(p, fzk)
    y, d = _factor_partials(kappa + f.Sh, f)
    ex = np.exp(-p["b5"] * fzk)
    bcd = (p["b3"] * fzk**2 + p["b4"] * fzk) * ex
    dBCD = d["BCD"]
    cols = {
        "b0": d["C"],
        "b1": lambda: d["D"] * fzk**2,
        "b2": lambda: d["D"] * fzk,
        "b3": lambda: dBCD * fzk**2 * ex,
        "b4": lambda: dBCD * fzk * ex,
        "b5": lambda: dBCD * (-fzk * bcd),
        "b6": lambda: d["E"] * fzk**2,
        "b7": lambda: d["E"] * fzk,
        "b8": d["E"],
        "b9": lambda: d["Sh"] * fzk,
        "b10": d["Sh"],
    }
    return y, _assemble(tuple(names), LONGITUDINAL, cols, fzk.shape)


def aligning_jacobian(p: Mapping[str, float], fz, slip_angle, camber=0.0, names=ALIGNING):
    """Aligning moment [N*m] (ISO-W) and its analytic Jacobian wrt ``c0``..``c17``."""
    fzk, alpha, gamma = _to_pac(fz, slip_angle, camber)
    fzk, alpha, gamma = np.broadcast_arrays(np.atleast_1d(fzk), np.atleast_1d(alpha), np.atleast_1d(gamma))
    f = aligning_factors(p, fzk, gamma)
    xs = alpha + f.Sh
    x = np.clip(xs, -X_LIMIT_DEG, X_LIMIT_DEG)
    y, d = _factor_partials(x, f)
    dSh = np.where(np.abs(xs) < X_LIMIT_DEG, d["Sh"], 0.0)
    ag = np.abs(gamma)
    ex = np.exp(-p["c5"] * fzk)
    law = p["c3"] * fzk**2 + p["c4"] * fzk
    cam = 1.0 - p["c6"] * ag
    elaw = p["c7"] * fzk**2 + p["c8"] * fzk + p["c9"]
    ecam = 1.0 - p["c10"] * ag
    dBCD = d["BCD"]
    cols = {
        "c0": d["C"],
        "c1": lambda: d["D"] * fzk**2,
        "c2": lambda: d["D"] * fzk,
        "c3": lambda: dBCD * fzk**2 * cam * ex,
        "c4": lambda: dBCD * fzk * cam * ex,
        "c5": lambda: dBCD * (-fzk * law * cam * ex),
        "c6": lambda: dBCD * (-law * ag * ex),
        "c7": lambda: d["E"] * fzk**2 * ecam,
        "c8": lambda: d["E"] * fzk * ecam,
        "c9": lambda: d["E"] * ecam,
        "c10": lambda: d["E"] * (-elaw * ag),
        "c11": lambda: dSh * gamma,
        "c12": lambda: dSh * fzk,
        "c13": dSh,
        "c14": lambda: fzk**2 * gamma,
        "c15": lambda: fzk * gamma,
        "c16": fzk,
        "c17": 1.0,
    }
    sign = _from_pac(1.0)
    return sign * y, _assemble(tuple(names), ALIGNING, cols, fzk.shape, sign)
