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
:func:`_to_pac` and :func:`_from_pac` and nowhere else in tyrefit: the slip
angle is negated on the way in, ``fy`` and ``mz`` on the way out; camber,
slip ratio and ``fx`` keep their sign.

The model is pure: no validation, no clipping of loads; NumPy broadcasting
over ``fz``, ``slip_angle``, ``camber`` and over array-valued coefficients.

References
----------
Bakker, Nyborg, Pacejka (1989), Tyre modelling for use in vehicle dynamics
studies, SAE 870421 / the 1989 extension; Adams/Tire PAC89 documentation;
Chrono ``ChPac89Tire.cpp``.  Komana, Els, Becker, *Cost efficient tyre
testing, modelling and validation for PBS assessments* (seed 003) fit a0-a13
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
    "Factors",
    "magic_formula",
    "lateral_factors",
    "longitudinal_factors",
    "aligning_factors",
    "lateral_force",
    "longitudinal_force",
    "aligning_moment",
]

LATERAL: tuple[str, ...] = tuple(f"a{i}" for i in range(14))
LONGITUDINAL: tuple[str, ...] = tuple(f"b{i}" for i in range(11))
ALIGNING: tuple[str, ...] = tuple(f"c{i}" for i in range(18))
ALL: tuple[str, ...] = LATERAL + LONGITUDINAL + ALIGNING

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
    """SI/ISO-W inputs -> PAC89 inputs: Fz [kN], alpha [deg] (negated), gamma [deg]."""
    return (np.asarray(fz, dtype=float) * 1e-3,
            -np.asarray(slip_angle, dtype=float) * _RAD2DEG,
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
    """
    C = p["a0"] + 0.0 * fzk
    D = p["a1"] * fzk**2 + p["a2"] * fzk
    BCD = p["a3"] * np.sin(2.0 * np.arctan(fzk / p["a4"])) * (1.0 - p["a5"] * np.abs(gamma))
    B = BCD / (C * D)
    E = p["a6"] * fzk + p["a7"]
    Sh = p["a8"] * gamma + p["a9"] * fzk + p["a10"]
    Sv = p["a11"] * fzk * gamma + p["a12"] * fzk + p["a13"]
    return Factors(B, C, D, E, Sh, Sv)


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
    alpha = -slip_angle in degrees, x clamped to +/-89.5 deg as in Chrono;
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
