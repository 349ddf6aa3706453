"""Magic Formula 6.1 and 5.2 steady-state tyre model (pure numpy, vectorised).

The equations are those of Pacejka, *Tire and Vehicle Dynamics*, 3rd ed.
(Pacejka & Besselink, 2012), section 4.3.2, equations (4.E1)-(4.E78), with
the inflation-pressure terms of Besselink, Schmeitz & Pacejka (2010), *An
improved Magic Formula/Swift tyre model that can handle inflation pressure
changes*, Vehicle System Dynamics 48 sup1, Appendix (A..) - the equation set
of MF-Tyre 6.1.  Every formula line carries its number.  Where the book and
the 6.1 paper/manual differ, the 6.1 form is used and the line says so (the
same choices as MFeval, M. Furlan, which is validated against TNO's solver).

Conventions
-----------
* Inputs SI and ISO-W, as in a ``.tir`` file: ``fz`` [N] (> 0), ``slip_ratio``
  kappa [-], ``slip_angle`` alpha [rad], ``camber`` gamma [rad], ``pressure``
  [Pa], ``speed`` = forward speed of the wheel centre Vcx [m/s] (>= 0).
  Outputs ``fx``, ``fy`` [N], ``mx``, ``my``, ``mz`` [N*m] in ISO-W, the MF
  ``.tir`` convention: a negative cornering stiffness K_y_alpha (PKY1 < 0 with
  PKY4 > 0, or PKY1 > 0 with PKY4 < 0 as in some vendor files) gives
  ``fy < 0`` for ``slip_angle > 0``.
* Coefficients: a mapping of ``.tir`` keys in upper case.  A missing scaling
  factor ``L*`` is 1 (``LMUV``, a speed-decay rate whose neutral value is 0,
  is 0); any other missing coefficient is 0.  ``FNOMIN``, ``NOMPRES``,
  ``LONGVL`` and ``UNLOADED_RADIUS`` must be given (positive) - the maths does
  not check them (checks belong to the reader and the CLI).
* Steady state, no clipping of inputs to the file's ``[*_RANGE]`` sections
  (the caller decides; :func:`clip_to_ranges` does what a simulator does).

What is implemented (MF 6.1, ``version='6.1'``)
-----------------------------------------------
* Pure slip Fx0 (4.E9-4.E18), Fy0 (4.E19-4.E30), Mz0 (4.E31-4.E49), with
  camber and pressure (PPX1-4, PPY1-5, PPZ1-2).
* Combined slip: Gx_alpha (4.E50-4.E57), Gy_kappa and SVy_kappa
  (4.E58-4.E67), combined Mz with the s*Fx term (4.E71-4.E78).
* Mx as the MF 6.1 manual / Besselink's draft paper eq. (49) define it: (4.E69)
  plus QSX12-QSX14 and the squared argument ``arctan((QSX6 Fz/Fz0)^2)``, with PPMX1.
* My as the 6.1 paper (A48): (4.E70) with Fz0 in front and the ISO-W sign
  (rolling resistance opposes forward rolling, My < 0).
* Digressive friction scaling (4.E7, 4.E8) with LMUV (speed decay) and
  ``A_MU = 1``.

Where TNO's MF-Tyre 6.1 departs from the book, this module follows TNO, with
the choices MFeval 4.0 (M. Furlan) documents as reproducing TNO's solver
("Changes in the equations" in its documentation); the test against MFeval
(``tests/test_mf61_model.py``) agrees to 1e-13 of peak:

* alpha* = alpha and gamma* = gamma (the tan/sin forms of 4.E3, 4.E4 are not used);
* A_MU = 1 in (4.E8) (the book suggests 10; it matters only when LMUX/LMUY != 1);
* Bt with (1 + QBZ4 gamma + QBZ5 |gamma|) (paper A58; the book's QBZ6 is no file key);
* Dt with (1 + QDZ3 gamma + QDZ4 gamma^2) (paper A60; the book has |gamma*|);
* the equivalent angles of combined Mz through tan/arctan (paper A54, A55);
* s with the unscaled FNOMIN (paper A56), and the trail t multiplied by LFZO;
* Mz0's Fy term is Fy0 at zero camber; combined Mz uses Fy' = Gy_kappa Fy0(gamma = 0) (4.E74).

Low speed (MF 6.1 / TNO, as MFeval's ``parseInputs``): for |Vcx| <= VXLOW the slip
ratio is scaled by |Vcx|/VXLOW and the shifts SHx, SVx, SHy, SVy, SVy_kappa, the
trail t and the residual torque Mzr by ``1 - W``, ``W = (1 + cos(pi Vcx/VXLOW))/2``;
the slip angle is scaled by (|Vcx| + |Vsy|)/VXLOW while that sum is below VXLOW
(Vsy = tan(alpha) Vcx).  My follows the sign of the rolling speed
Vr = Vcx (1 + kappa) and fades as sin(pi/2 Vr/VXLOW) for |Vr| < VXLOW (locked
wheel, standstill).  cos(alpha') = Vcx / (Vc + eps_V) (4.E6, 4.E6a).  epsilon
guards (4.E6a): eps = 1e-6 with the sign of the guarded quantity in the
denominators of Bx (4.E16), By (4.E26), SHy (4.E27) and SHf (K'y_alpha, 4.E39).
E factors are limited to <= 1 (4.E14, 4.E24, 4.E44, 4.E56, 4.E64).

MF 6.2 files (FITTYP 62) are evaluated with these equations too: the force and
moment equations of 6.2 without turn slip are those of 6.1 (as MFeval does).

Not done here (a simulator's or the caller's choice): clipping the inputs to
the ``[*_RANGE]`` sections (:func:`clip_to_ranges` does it on request) and
TNO's extra reductions of Mx and My below FZMIN.

Differences of MF 5.2 (``version='5.2'``; FITTYP 5, 6, 21, 'MF_05', 'PAC2002')
----------------------------------------------------------------------------
As 6.1 (same low-speed model, same TNO choices) except, following the MF-Tyre
5.2 equation manual as MFeval 4.0 evaluates FITTYP 6 (the test against MFeval
on its 5.2 example and on Chrono's PAC2002 file agrees to 1e-14 of peak):

* no pressure terms (dpi = 0; PPX*, PPY*, PPZ*, PPMX1, QSY5-QSY8 unused) and
  no QSX4-QSX14, PKY5-PKY7, PEY5, RBX3, RBY4, QDZ10-11 (absent from 5.2 files)
  -- unless the file carries them (see "MF 5.2 files with MF 6.1 keys" below);
* camber enters as gamma * LGAX / LGAY / LGAZ (the 5.2 camber scaling factors,
  default 1) instead of through LKYC / LKZC;
* Fy0: K_y_alpha = PKY1 Fz0' sin(PKY4 arctan(Fz/(PKY2 Fz0'))) (1 - PKY3 |gamma_y|) LKY
  with PKY4 = 2 when the file does not give it; SHy = (PHY1 + PHY2 dfz) LHY + PHY3 gamma_y;
  SVy = Fz ((PVY1 + PVY2 dfz) LVY + (PVY3 + PVY4 dfz) gamma_y) LMUY';
  Ey = (PEY1 + PEY2 dfz)(1 - (PEY3 + PEY4 gamma_y) sgn(alpha_y)) LEY;
* Mz: Dr = Fz R0 ((QDZ6 + QDZ7 dfz) LRES + (QDZ8 + QDZ9 dfz) gamma_z) LMUY cos(alpha);
  Mz' = -t (Fy - SVy_kappa) in combined slip, SVy_kappa with the zero-camber mu_y;
* Mx = R0 Fz (QSX1 LVMX - QSX2 gamma + QSX3 Fy/Fz0) LMX;
* My = -R0 Fz (QSY1 + QSY2 Fx/Fz0 + QSY3 |Vcx/V0| + QSY4 (Vcx/V0)^4) LMY.

MF 5.2 files with MF 6.1 keys
-----------------------------
Some MF 5.2 files (FITTYP 6) carry MF 6.1-only coefficients -- teasit's
magic-formula-tyre-library FSAE example ``fsaettc_obfuscated_v52.tir`` has
PPX1-PPX4, PPY1-PPY5, PKY5-PKY7, PEY5 with INFLPRES 80 kPa != NOMPRES 98 kPa.
The MF-Tyre 5.2 equations have no such terms, so a strict 5.2 evaluator would
drop them; MFeval 4.0, the open reference most users check against, applies
them: its solver (``+mfeval/Solver.m``) is the 6.1 one for every FITTYP, with
four FITTYP == 6 switches only -- K_y_gamma0 and SHy through PHY3
(``calculateFy0``), the 5.2 My (``calculateMy``) and Mz' = -t (Fy - SVy_kappa)
(``calculateMz``).  tyrefit follows MFeval, because a non-zero 6.1 key in a file
is the fitting tool's statement that the term belongs to the tyre (the 19 % of
peak Fx the pressure terms make at that file's INFLPRES would otherwise be
lost silently), and because a file without them is evaluated exactly as
before (every added term is zero).  So, in an MF 5.2 file, when present and
non-zero: the pressure terms PPX1-PPX4, PPY1-PPY4, PPZ1-PPZ2, PPMX1 (dpi from
NOMPRES, when the file gives NOMPRES > 0), PKY5 and PPY2 in K_y_alpha, PEY5
in Ey, QDZ10-QDZ11 in Dr, RBX3, RBY4, and QSX4-QSX14 in Mx take their MF 6.1
places; PKY6, PKY7, PPY5 and QSY5-QSY8 stay unused (MFeval's FITTYP 6 camber
stiffness and My).  :meth:`tyrefit.tyres.mf.MFTyre.warnings` says which keys
were applied and which were not.  Tested against MFeval's solver in
``tests/test_mf52_61keys.py``.

Project Chrono's ``ChPac02Tire`` evaluates PAC2002 files differently in places
(it scales K_y by LMUY, adds 0.1 N to the B denominators, clamps B*x to
+-(pi/2 - 0.01), uses (1 + PDY3 gamma^2) and combines by a friction ellipse
unless told otherwise); those are Chrono's choices, not the 5.2 manual's, and
are not followed here.

For fitting
-----------
:func:`fx0`, :func:`fy0` and :func:`mz0` give the pure-slip parts; :data:`GROUPS`
names the coefficients of each stage (Fx0, Fy0, Mz0, combined Fx, Fy, Mz, Mx,
My); :data:`PRESSURE_TERMS`, :data:`CAMBER_TERMS` and :data:`SPEED_TERMS` the
terms that only pressure, camber or speed levels can identify; :func:`factors`
the C, mu, D, K, B, E of a parameter set for the physical checks; coefficients
may be arrays to evaluate many candidate sets at once; :func:`neutral` a
complete finite starting set.

Out of scope
------------
Turn slip (the zeta factors are 1, zeta0 = 1), transient behaviour, the
loaded/effective rolling radius and the vertical model, reverse rolling
(Vcx < 0).

References
----------
Pacejka, H.B. & Besselink, I.J.M. (2012), *Tire and Vehicle Dynamics*, 3rd
ed., Butterworth-Heinemann, sec. 4.3.2 (equations 4.E1-4.E78).
Besselink, I.J.M., Schmeitz, A.J.C. & Pacejka, H.B. (2010), Vehicle System
Dynamics 48(S1), 337-352, Appendix.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

__all__ = [
    "COEFFICIENTS",
    "COEFFICIENTS_52",
    "GROUPS",
    "PRESSURE_TERMS",
    "CAMBER_TERMS",
    "SPEED_TERMS",
    "EPSILON",
    "resolve_version",
    "neutral",
    "coefficients",
    "fx0",
    "fy0",
    "mz0",
    "forces",
    "factors",
    "clip_to_ranges",
]

#: the epsilon of (4.E6a) used in every guarded denominator
EPSILON = 1e-6
#: A_mu of the digressive friction scaling (4.E8); 1 as TNO's solver (see module notes)
A_MU = 1.0


def _seq(prefix: str, *numbers: int) -> list[str]:
    return [f"{prefix}{n}" for n in numbers]


#: .tir section -> every coefficient a complete FITTYP = 61 file carries, in file order
COEFFICIENTS: dict[str, list[str]] = {
    "MODEL": ["FITTYP", "LONGVL", "VXLOW"],
    "DIMENSION": ["UNLOADED_RADIUS", "WIDTH", "RIM_RADIUS", "RIM_WIDTH", "ASPECT_RATIO"],
    "OPERATING_CONDITIONS": ["INFLPRES", "NOMPRES"],
    "INERTIA": ["MASS", "IXX", "IYY", "BELT_MASS", "BELT_IXX", "BELT_IYY", "GRAVITY"],
    "VERTICAL": ["FNOMIN", "VERTICAL_STIFFNESS", "VERTICAL_DAMPING", "MC_CONTOUR_A", "MC_CONTOUR_B",
                 "BREFF", "DREFF", "FREFF", "Q_RE0", "Q_V1", "Q_V2", "Q_FZ2", "Q_FCX", "Q_FCY", "Q_CAM",
                 "PFZ1", "BOTTOM_OFFST", "BOTTOM_STIFF"],
    "STRUCTURAL": ["LONGITUDINAL_STIFFNESS", "LATERAL_STIFFNESS", "YAW_STIFFNESS", "FREQ_LONG", "FREQ_LAT",
                   "FREQ_YAW", "FREQ_WINDUP", "DAMP_LONG", "DAMP_LAT", "DAMP_YAW", "DAMP_WINDUP",
                   "DAMP_RESIDUAL", "DAMP_VLOW", "Q_BVX", "Q_BVT", "PCFX1", "PCFX2", "PCFX3", "PCFY1",
                   "PCFY2", "PCFY3", "PCMZ1"],
    "CONTACT_PATCH": ["Q_RA1", "Q_RA2", "Q_RB1", "Q_RB2", "ELLIPS_SHIFT", "ELLIPS_LENGTH", "ELLIPS_HEIGHT",
                      "ELLIPS_ORDER", "ELLIPS_MAX_STEP", "ELLIPS_NWIDTH", "ELLIPS_NLENGTH"],
    "INFLATION_PRESSURE_RANGE": ["PRESMIN", "PRESMAX"],
    "VERTICAL_FORCE_RANGE": ["FZMIN", "FZMAX"],
    "LONG_SLIP_RANGE": ["KPUMIN", "KPUMAX"],
    "SLIP_ANGLE_RANGE": ["ALPMIN", "ALPMAX"],
    "INCLINATION_ANGLE_RANGE": ["CAMMIN", "CAMMAX"],
    "SCALING_COEFFICIENTS": ["LFZO", "LCX", "LMUX", "LEX", "LKX", "LHX", "LVX", "LCY", "LMUY", "LEY", "LKY",
                             "LKYC", "LKZC", "LHY", "LVY", "LTR", "LRES", "LXAL", "LYKA", "LVYKA", "LS",
                             "LMX", "LVMX", "LMY", "LMP"],
    "LONGITUDINAL_COEFFICIENTS": ["PCX1", "PDX1", "PDX2", "PDX3", "PEX1", "PEX2", "PEX3", "PEX4", "PKX1",
                                  "PKX2", "PKX3", "PHX1", "PHX2", "PVX1", "PVX2", "PPX1", "PPX2", "PPX3",
                                  "PPX4", "RBX1", "RBX2", "RBX3", "RCX1", "REX1", "REX2", "RHX1"],
    "OVERTURNING_COEFFICIENTS": _seq("QSX", *range(1, 15)) + ["PPMX1"],
    "LATERAL_COEFFICIENTS": ["PCY1", "PDY1", "PDY2", "PDY3"] + _seq("PEY", 1, 2, 3, 4, 5)
    + _seq("PKY", *range(1, 8)) + ["PHY1", "PHY2"] + _seq("PVY", 1, 2, 3, 4) + _seq("PPY", 1, 2, 3, 4, 5)
    + _seq("RBY", 1, 2, 3, 4) + ["RCY1", "REY1", "REY2", "RHY1", "RHY2"] + _seq("RVY", *range(1, 7)),
    "ROLLING_COEFFICIENTS": _seq("QSY", *range(1, 9)),
    "ALIGNING_COEFFICIENTS": _seq("QBZ", 1, 2, 3, 4, 5, 9, 10) + ["QCZ1"]
    + _seq("QDZ", 1, 2, 3, 4, 6, 7, 8, 9, 10, 11) + _seq("QEZ", 1, 2, 3, 4, 5) + _seq("QHZ", 1, 2, 3, 4)
    + ["PPZ1", "PPZ2"] + _seq("SSZ", 1, 2, 3, 4),
}

#: coefficients an MF 5.2 (PAC2002) file carries that 6.1 does not (or uses differently)
COEFFICIENTS_52: dict[str, list[str]] = {
    "SCALING_COEFFICIENTS": ["LGAX", "LGAY", "LGAZ"],
    "LATERAL_COEFFICIENTS": ["PHY3"],
}

#: fitting stages -> the coefficients each one owns (MF 6.1)
GROUPS: dict[str, list[str]] = {
    "fx0": ["PCX1", "PDX1", "PDX2", "PDX3", "PEX1", "PEX2", "PEX3", "PEX4", "PKX1", "PKX2", "PKX3", "PHX1",
            "PHX2", "PVX1", "PVX2", "PPX1", "PPX2", "PPX3", "PPX4"],
    "fy0": ["PCY1", "PDY1", "PDY2", "PDY3"] + _seq("PEY", 1, 2, 3, 4, 5) + _seq("PKY", *range(1, 8))
    + ["PHY1", "PHY2"] + _seq("PVY", 1, 2, 3, 4) + _seq("PPY", 1, 2, 3, 4, 5),
    "mz0": _seq("QBZ", 1, 2, 3, 4, 5, 9, 10) + ["QCZ1"] + _seq("QDZ", 1, 2, 3, 4, 6, 7, 8, 9, 10, 11)
    + _seq("QEZ", 1, 2, 3, 4, 5) + _seq("QHZ", 1, 2, 3, 4) + ["PPZ1", "PPZ2"],
    "fx": ["RBX1", "RBX2", "RBX3", "RCX1", "REX1", "REX2", "RHX1"],
    "fy": _seq("RBY", 1, 2, 3, 4) + ["RCY1", "REY1", "REY2", "RHY1", "RHY2"] + _seq("RVY", *range(1, 7)),
    "mz": _seq("SSZ", 1, 2, 3, 4),
    "mx": _seq("QSX", *range(1, 15)) + ["PPMX1"],
    "my": _seq("QSY", *range(1, 9)),
}

#: terms that act only through the inflation pressure (dpi or p/pi0)
PRESSURE_TERMS: frozenset[str] = frozenset(
    _seq("PPX", 1, 2, 3, 4) + _seq("PPY", 1, 2, 3, 4, 5) + ["PPZ1", "PPZ2", "PPMX1", "QSY8"])
#: terms that act only through camber (they are free when camber is zero)
CAMBER_TERMS: frozenset[str] = frozenset(
    ["PDX3", "PEY4", "PEY5", "PKY3", "PKY5", "PKY6", "PKY7", "PVY3", "PVY4", "PPY5", "QBZ4", "QBZ5",
     "QDZ3", "QDZ4", "QDZ8", "QDZ9", "QDZ10", "QDZ11", "QEZ5", "QHZ3", "QHZ4", "PPZ2", "RBX3", "RBY4",
     "RVY3", "SSZ3", "SSZ4", "QSX2", "QSX7", "QSX10", "QSX12", "QSX14", "QSY5", "QSY6", "PHY3"])
#: terms that act only through the forward speed
SPEED_TERMS: frozenset[str] = frozenset(["QSY3", "QSY4"])

_SCALING_DEFAULT_ZERO = frozenset(["LMUV"])
_VERSIONS_61 = {61, 62}
_VERSIONS_52 = {5, 6, 21}


def resolve_version(p: Mapping, version: str | None = None) -> str:
    """``'6.1'`` or ``'5.2'`` from an explicit ``version`` or the file's FITTYP / PROPERTY_FILE_FORMAT.

    Raises
    ------
    ValueError
        for a version or FITTYP this module does not evaluate.
    """
    if version is not None:
        v = str(version).strip().upper().strip("'\"")
        if v in ("6.1", "61", "62", "6.2", "MF61", "MF62"):
            return "6.1"
        if v in ("5.2", "5", "6", "21", "MF52", "MF_05", "PAC2002"):
            return "5.2"
        raise ValueError(f"unknown Magic Formula version {version!r}; use '6.1' or '5.2'")
    up = {str(k).upper(): v for k, v in p.items()}
    fittyp = up.get("FITTYP")
    if fittyp is not None and str(fittyp).strip() != "":
        try:
            f = int(float(str(fittyp).strip().strip("'\"")))
        except ValueError:
            raise ValueError(f"FITTYP = {fittyp!r} is not a number") from None
        if f in _VERSIONS_61:
            return "6.1"
        if f in _VERSIONS_52:
            return "5.2"
        raise ValueError(f"FITTYP = {f} is not a Magic Formula 5.2 (5, 6, 21) or 6.1/6.2 (61, 62) file")
    fmt = str(up.get("PROPERTY_FILE_FORMAT", "")).strip().strip("'\"").upper()
    if fmt in ("MF_05", "PAC2002", "MF_5", "MF5"):
        return "5.2"
    return "6.1"


def _all_names() -> list[str]:
    out: list[str] = []
    for names in list(COEFFICIENTS.values()) + list(COEFFICIENTS_52.values()):
        out += [n for n in names if n not in out]
    return out + ["LMUV"]


_NAMES = _all_names()


def coefficients(p: Mapping) -> dict[str, float]:
    """Every coefficient the equations use, as floats, with the defaults filled in.

    Keys are matched case-insensitively; a missing scaling factor ``L*`` is 1
    (``LMUV`` 0), any other missing coefficient 0; non-numeric entries
    (``TYRESIDE = 'LEFT'``) are ignored.  A coefficient may be an array (say, a
    set of candidate values for a fit); it broadcasts with the inputs
    (``FNOMIN``, ``NOMPRES``, ``LONGVL`` and ``VXLOW`` must stay scalars).
    """
    up: dict[str, float] = {}
    for k, v in p.items():
        try:
            up[str(k).upper()] = float(v)
        except (TypeError, ValueError):
            if isinstance(v, (np.ndarray, list, tuple)):   # array-valued coefficients broadcast
                try:
                    up[str(k).upper()] = np.asarray(v, dtype=float)
                except (TypeError, ValueError):
                    pass
            continue
    c = {}
    for n in _NAMES:
        if n in up:
            c[n] = up[n]
        elif n.startswith("L") and n not in _SCALING_DEFAULT_ZERO and n in _SCALING:
            c[n] = 1.0
        else:
            c[n] = 0.0
    return c


_SCALING = frozenset(COEFFICIENTS["SCALING_COEFFICIENTS"] + COEFFICIENTS_52["SCALING_COEFFICIENTS"])


def neutral() -> dict[str, float]:
    """A complete, finite MF 6.1 parameter set with no effect terms.

    Scaling factors 1, shifts, camber, pressure, combined-slip and moment
    terms 0; shape, peak and stiffness factors at generic passenger-car
    values (C_x = 1.65, mu_x = mu_y = 1, C_y = 1.3, K_x = 20 Fz, K_y = -15 Fz0'
    at the peak of PKY2 = 1.5, PKY4 = 2, Mz trail and residual torque generic)
    so that the forces are finite and of realistic shape.  The combined-slip
    weights are exactly 1 (RBX1 = RBY1 = 0 -> G = cos(0)/cos(0)), Mx and My
    are zero.  Geometry and structure: a 205/60R15-sized tyre; these are
    placeholders for a writer to fill, not measurements.
    """
    p: dict[str, float] = {n: 0.0 for names in COEFFICIENTS.values() for n in names}
    p.update({n: 1.0 for n in COEFFICIENTS["SCALING_COEFFICIENTS"]})
    p.update(
        FITTYP=61, LONGVL=16.7, VXLOW=1.0,
        UNLOADED_RADIUS=0.3135, WIDTH=0.205, RIM_RADIUS=0.1905, RIM_WIDTH=0.152, ASPECT_RATIO=0.6,
        INFLPRES=220000.0, NOMPRES=220000.0,
        MASS=9.3, IXX=0.391, IYY=0.736, BELT_MASS=7.0, BELT_IXX=0.34, BELT_IYY=0.6, GRAVITY=-9.81,
        FNOMIN=4000.0, VERTICAL_STIFFNESS=209651.0, VERTICAL_DAMPING=50.0, MC_CONTOUR_A=0.5, MC_CONTOUR_B=0.5,
        BREFF=8.386, DREFF=0.25826, FREFF=0.07394, Q_RE0=1.0, Q_FZ2=0.0, Q_FCX=0.0, Q_FCY=0.0, PFZ1=0.0,
        BOTTOM_OFFST=0.01, BOTTOM_STIFF=2000000.0,
        LONGITUDINAL_STIFFNESS=358066.0, LATERAL_STIFFNESS=102673.0, YAW_STIFFNESS=4793.0,
        FREQ_LONG=77.0, FREQ_LAT=42.0, FREQ_YAW=53.0, FREQ_WINDUP=58.0, DAMP_LONG=0.056, DAMP_LAT=0.037,
        DAMP_YAW=0.007, DAMP_WINDUP=0.05, DAMP_RESIDUAL=0.002, DAMP_VLOW=0.001,
        Q_RA1=0.55, Q_RA2=1.0, Q_RB1=1.0, Q_RB2=-1.0, ELLIPS_SHIFT=0.8, ELLIPS_LENGTH=1.0,
        ELLIPS_HEIGHT=1.0, ELLIPS_ORDER=1.8, ELLIPS_MAX_STEP=0.025, ELLIPS_NWIDTH=10.0, ELLIPS_NLENGTH=10.0,
        PRESMIN=100000.0, PRESMAX=400000.0, FZMIN=100.0, FZMAX=10000.0, KPUMIN=-1.5, KPUMAX=1.5,
        ALPMIN=-1.5, ALPMAX=1.5, CAMMIN=-0.175, CAMMAX=0.175,
        PCX1=1.65, PDX1=1.0, PEX1=0.0, PKX1=20.0, RCX1=1.0,
        PCY1=1.3, PDY1=1.0, PEY1=0.0, PKY1=-15.0, PKY2=1.5, PKY4=2.0, RCY1=1.0,
        QBZ1=10.0, QCZ1=1.1, QDZ1=0.1, QEZ1=0.0, QBZ9=10.0, QDZ6=0.0,
    )
    return p


# --------------------------------------------------------------------------------------------------
# the equations


def _sgn(x):
    """sign with sgn(0) = +1 (guards against 0 in denominators)."""
    return np.where(x >= 0, 1.0, -1.0)


def _mf(b, c, d, e, x):
    """D sin(C arctan(Bx - E(Bx - arctan Bx)))  (4.E9 / 4.E19 form)."""
    bx = b * x
    return d * np.sin(c * np.arctan(bx - e * (bx - np.arctan(bx))))


def _cos_mf(b, c, e, x):
    """cos(C arctan(Bx - E(Bx - arctan Bx)))  (4.E33 / 4.E51 / 4.E59 form)."""
    bx = b * x
    return np.cos(c * np.arctan(bx - e * (bx - np.arctan(bx))))


class _Basic:
    """The shared quantities of (4.E1)-(4.E8) for one call."""

    __slots__ = ("fz", "kappa", "kappa_in", "alpha", "gamma", "vcx", "dfz", "dpi", "fz0p", "astar", "gstar",
                 "cos_ap", "lmux_s", "lmuy_s", "lmux_p", "lmuy_p", "red", "v52", "gx", "gy", "gz")


def _basic(c, v52, fz, kappa, alpha, gamma, pressure, speed) -> _Basic:
    b = _Basic()
    b.v52 = v52
    fz = np.asarray(fz, dtype=float)
    kappa = np.asarray(kappa, dtype=float)
    alpha = np.asarray(alpha, dtype=float)
    gamma = np.asarray(gamma, dtype=float)
    vcx = np.abs(np.asarray(c["LONGVL"] if speed is None else speed, dtype=float))
    press = np.asarray(c["NOMPRES"] if pressure is None else pressure, dtype=float)
    vxlow = c["VXLOW"]
    b.kappa_in = kappa
    if vxlow > 0:
        # MF 6.1 low-speed model (TNO; MFeval 4.0 Solver.parseInputs): below VXLOW the slip
        # ratio falls linearly with |Vcx|, the slip angle with (|Vcx| + |Vsy|), and the shifts,
        # trail and residual torque with the smooth factor 1 - W, W = (1 + cos(pi Vcx/VXLOW))/2
        # (the branches only save work when no point is that slow; the result is the same)
        low = vcx <= vxlow
        b.red = 1.0
        if np.any(low):
            kappa = np.where(low, kappa * np.minimum(vcx / vxlow, 1.0), kappa)
            b.red = np.where(low, 0.5 * (1.0 - np.cos(np.pi * np.minimum(vcx, vxlow) / vxlow)), 1.0)
        if np.any(vcx < vxlow):   # |Vcx| + |Vsy| < VXLOW needs |Vcx| < VXLOW
            ssum = vcx + np.abs(np.tan(alpha) * vcx)
            alpha = np.where(ssum < vxlow, alpha * np.minimum(ssum / vxlow, 1.0), alpha)
    else:
        b.red = 1.0
    b.fz, b.kappa, b.alpha, b.gamma, b.vcx = fz, kappa, alpha, gamma, vcx
    b.fz0p = c["FNOMIN"] * c["LFZO"]                                   # (4.E1)
    b.dfz = (fz - b.fz0p) / b.fz0p                                     # (4.E2a)
    if v52:  # 5.2: no pressure, unless the file carries MF 6.1 pressure terms (module notes; MFeval)
        b.dpi = (press - c["NOMPRES"]) / c["NOMPRES"] if _pressure_52(c) else 0.0
    else:
        b.dpi = (press - c["NOMPRES"]) / c["NOMPRES"]                  # (4.E2b)
    # alpha* = alpha and gamma* = gamma: TNO's MF-Tyre does not use the tan/sin forms of
    # (4.E3), (4.E4) (MFeval 4.0 documentation, "Changes in the equations", 'alpha star')
    b.astar = alpha
    b.gstar = gamma
    # 5.2 camber per channel (MF-Tyre 5.2: gamma_x,y,z = gamma * LGAX,Y,Z)
    b.gx, b.gy, b.gz = gamma * c["LGAX"], gamma * c["LGAY"], gamma * c["LGAZ"]
    vsy = np.tan(alpha) * vcx                                          # (2.12), Vcy = Vsy
    vc = np.sqrt(vcx ** 2 + vsy ** 2)
    b.cos_ap = vcx / (vc + EPSILON)                                    # (4.E6), (4.E6a)
    v0 = c["LONGVL"]
    if np.all(np.asarray(c["LMUV"]) == 0):                             # no speed decay: (4.E7) is LMU
        b.lmux_s, b.lmuy_s = c["LMUX"], c["LMUY"]
    else:
        vsx = -kappa * vcx                                             # (4.E5)
        vs = np.sqrt(vsx ** 2 + vsy ** 2)
        b.lmux_s = c["LMUX"] / (1.0 + c["LMUV"] * vs / v0)             # (4.E7)
        b.lmuy_s = c["LMUY"] / (1.0 + c["LMUV"] * vs / v0)             # (4.E7)
    b.lmux_p = A_MU * b.lmux_s / (1.0 + (A_MU - 1.0) * b.lmux_s)       # (4.E8)
    b.lmuy_p = A_MU * b.lmuy_s / (1.0 + (A_MU - 1.0) * b.lmuy_s)       # (4.E8)
    return b


#: MF 6.1-only keys an MF 5.2 file may carry that MFeval's FITTYP 6 path applies (module notes)
APPLIED_61_IN_52 = ("PPX1", "PPX2", "PPX3", "PPX4", "PPY1", "PPY2", "PPY3", "PPY4", "PPZ1", "PPZ2", "PPMX1", "PKY5",
                    "PEY5", "QDZ10", "QDZ11", "RBX3", "RBY4", "QSX4", "QSX5", "QSX6", "QSX7", "QSX8", "QSX9", "QSX10",
                    "QSX11", "QSX12", "QSX13", "QSX14")
#: ... and those it does not (the 5.2 camber stiffness through PHY3, the 5.2 My)
UNUSED_61_IN_52 = ("PKY6", "PKY7", "PPY5", "QSY5", "QSY6", "QSY7", "QSY8")
_PRESSURE_61 = ("PPX1", "PPX2", "PPX3", "PPX4", "PPY1", "PPY2", "PPY3", "PPY4", "PPZ1", "PPZ2", "PPMX1")
_MX_61 = ("QSX4", "QSX10", "QSX12", "QSX13", "QSX14", "PPMX1")


def _nonzero(c, keys) -> bool:
    return any(np.any(np.asarray(c.get(k, 0.0)) != 0) for k in keys)


def _pressure_52(c) -> bool:
    """An MF 5.2 parameter set with MF 6.1 pressure terms and a NOMPRES to refer them to."""
    return _nonzero(c, _PRESSURE_61) and bool(np.all(np.asarray(c.get("NOMPRES", 0.0)) > 0))


def _fx0_parts(c, b: _Basic, e_sign=None):
    """Fx0 and its factors (4.E9)-(4.E18); ``e_sign`` = +-1 gives Ex for that slip sign, unlimited."""
    fz, dfz, dpi = b.fz, b.dfz, b.dpi
    cx = c["PCX1"] * c["LCX"]                                                          # (4.E11)
    if b.v52:
        mux = (c["PDX1"] + c["PDX2"] * dfz) * (1.0 - c["PDX3"] * b.gx ** 2) * b.lmux_s
        kxk = fz * (c["PKX1"] + c["PKX2"] * dfz) * np.exp(c["PKX3"] * dfz) * c["LKX"]
        if np.any(dpi != 0):  # MF 6.1 pressure terms carried by a 5.2 file (MFeval), (4.E13), (4.E15)
            mux = mux * (1.0 + c["PPX3"] * dpi + c["PPX4"] * dpi ** 2)
            kxk = kxk * (1.0 + c["PPX1"] * dpi + c["PPX2"] * dpi ** 2)
    else:
        mux = ((c["PDX1"] + c["PDX2"] * dfz) * (1.0 + c["PPX3"] * dpi + c["PPX4"] * dpi ** 2)
               * (1.0 - c["PDX3"] * b.gamma ** 2) * b.lmux_s)                         # (4.E13)
        kxk = (fz * (c["PKX1"] + c["PKX2"] * dfz) * np.exp(c["PKX3"] * dfz)
               * (1.0 + c["PPX1"] * dpi + c["PPX2"] * dpi ** 2) * c["LKX"])            # (4.E15)
    dx = mux * fz                                                                      # (4.E12), zeta1 = 1
    bx = kxk / (cx * dx + EPSILON * _sgn(dx))                                          # (4.E16)
    shx = (c["PHX1"] + c["PHX2"] * dfz) * c["LHX"] * b.red                             # (4.E17)
    svx = fz * (c["PVX1"] + c["PVX2"] * dfz) * c["LVX"] * b.lmux_p * b.red             # (4.E18)
    kx = b.kappa + shx                                                                 # (4.E10)
    ex = ((c["PEX1"] + c["PEX2"] * dfz + c["PEX3"] * dfz ** 2)
          * (1.0 - c["PEX4"] * (np.sign(kx) if e_sign is None else e_sign)) * c["LEX"])  # (4.E14)
    if e_sign is not None:
        return dict(cx=cx, mux=mux, dx=dx, kx=kxk, bx=bx, ex=ex, shx=shx, svx=svx)
    fx0 = _mf(bx, cx, dx, np.minimum(ex, 1.0), kx) + svx                               # (4.E9)
    return fx0, mux, kxk


def _fy0_parts(c, b: _Basic, zero_camber: bool = False, e_sign=None):
    """Fy0 and its factors (4.E19)-(4.E30); ``zero_camber`` gives Fy0 at gamma = 0 (used by Mz);
    ``e_sign`` = +-1 gives Ey for that sign of alpha_y, unlimited."""
    fz, dfz, dpi, fz0p = b.fz, b.dfz, b.dpi, b.fz0p
    cy = c["PCY1"] * c["LCY"]                                                          # (4.E21)
    if b.v52:
        gy = 0.0 * b.gy if zero_camber else b.gy
        muy = (c["PDY1"] + c["PDY2"] * dfz) * (1.0 - c["PDY3"] * gy ** 2) * b.lmuy_s
        # MF 5.2 manual: PKY4 = 2 unless the file gives it (see _prepare)
        if np.any(dpi != 0) or _nonzero(c, ("PKY5",)):  # 6.1 terms carried by a 5.2 file (MFeval): (4.E23), (4.E25)
            muy = muy * (1.0 + c["PPY3"] * dpi + c["PPY4"] * dpi ** 2)
            kya = (c["PKY1"] * fz0p * (1.0 + c["PPY1"] * dpi)
                   * np.sin(c["PKY4"] * np.arctan(fz / ((c["PKY2"] + c["PKY5"] * gy ** 2) * (1.0 + c["PPY2"] * dpi)
                                                        * fz0p)))
                   * (1.0 - c["PKY3"] * np.abs(gy)) * c["LKY"])
        else:
            kya = (c["PKY1"] * fz0p * np.sin(c["PKY4"] * np.arctan(fz / (c["PKY2"] * fz0p)))
                   * (1.0 - c["PKY3"] * np.abs(gy)) * c["LKY"])
        shy = (c["PHY1"] + c["PHY2"] * dfz) * c["LHY"] + c["PHY3"] * gy
        svy = fz * ((c["PVY1"] + c["PVY2"] * dfz) * c["LVY"] + (c["PVY3"] + c["PVY4"] * dfz) * gy) * b.lmuy_p
        shy, svy = shy * b.red, svy * b.red
        ay = b.astar + shy
        sg = np.sign(ay) if e_sign is None else e_sign
        ey = (c["PEY1"] + c["PEY2"] * dfz) * (1.0 + c["PEY5"] * gy ** 2 - (c["PEY3"] + c["PEY4"] * gy) * sg) * c["LEY"]
    else:
        gs = 0.0 * b.gstar if zero_camber else b.gstar
        muy = ((c["PDY1"] + c["PDY2"] * dfz) * (1.0 + c["PPY3"] * dpi + c["PPY4"] * dpi ** 2)
               * (1.0 - c["PDY3"] * gs ** 2) * b.lmuy_s)                               # (4.E23)
        kya = (c["PKY1"] * fz0p * (1.0 + c["PPY1"] * dpi) * (1.0 - c["PKY3"] * np.abs(gs))
               * np.sin(c["PKY4"] * np.arctan((fz / fz0p)
                                              / ((c["PKY2"] + c["PKY5"] * gs ** 2) * (1.0 + c["PPY2"] * dpi))))
               * c["LKY"])                                                             # (4.E25), zeta3 = 1
        svyg = fz * (c["PVY3"] + c["PVY4"] * dfz) * gs * c["LKYC"] * b.lmuy_p          # (4.E28), zeta2 = 1
        kyg0 = fz * (c["PKY6"] + c["PKY7"] * dfz) * (1.0 + c["PPY5"] * dpi) * c["LKYC"]  # (4.E30)
        shy = ((c["PHY1"] + c["PHY2"] * dfz) * c["LHY"]
               + (kyg0 * gs - svyg) / (kya + EPSILON * _sgn(kya)))                     # (4.E27), zeta0 = 1, zeta4 = 1
        svy = fz * (c["PVY1"] + c["PVY2"] * dfz) * c["LVY"] * b.lmuy_p + svyg          # (4.E29)
        shy, svy = shy * b.red, svy * b.red
        ay = b.astar + shy                                                             # (4.E20)
        sg = np.sign(ay) if e_sign is None else e_sign
        ey = ((c["PEY1"] + c["PEY2"] * dfz) * (1.0 + c["PEY5"] * gs ** 2 - (c["PEY3"] + c["PEY4"] * gs) * sg)
              * c["LEY"])                                                              # (4.E24)
    dy = muy * fz                                                                      # (4.E22), zeta2 = 1
    by = kya / (cy * dy + EPSILON * _sgn(dy))                                          # (4.E26)
    if e_sign is not None:
        return dict(cy=cy, muy=muy, dy=dy, ky=kya, by=by, ey=ey, shy=shy, svy=svy)
    fy0 = _mf(by, cy, dy, np.minimum(ey, 1.0), ay) + svy                               # (4.E19)
    return dict(fy0=fy0, muy=muy, kya=kya, shy=shy, svy=svy, by=by, cy=cy)


def _gyk(c, b: _Basic, muy):
    """Gy_kappa and SVy_kappa (4.E58)-(4.E67)."""
    dfz, kappa = b.dfz, b.kappa
    if b.v52:
        byk = (c["RBY1"] + c["RBY4"] * b.gamma ** 2) * np.cos(np.arctan(c["RBY2"] * (b.alpha - c["RBY3"]))) * c["LYKA"]
        g = b.gamma
        a = b.alpha
    else:
        byk = ((c["RBY1"] + c["RBY4"] * b.gstar ** 2)
               * np.cos(np.arctan(c["RBY2"] * (b.astar - c["RBY3"]))) * c["LYKA"])     # (4.E62)
        g = b.gstar
        a = b.astar
    cyk = c["RCY1"]                                                                    # (4.E63)
    eyk = np.minimum(c["REY1"] + c["REY2"] * dfz, 1.0)                                 # (4.E64)
    shyk = c["RHY1"] + c["RHY2"] * dfz                                                 # (4.E65)
    ks = kappa + shyk                                                                  # (4.E61)
    gyk = _cos_mf(byk, cyk, eyk, ks) / _cos_mf(byk, cyk, eyk, shyk)                    # (4.E59), (4.E60)
    dvyk = (muy * b.fz * (c["RVY1"] + c["RVY2"] * dfz + c["RVY3"] * g)
            * np.cos(np.arctan(c["RVY4"] * a)))                                        # (4.E67), zeta2 = 1
    svyk = dvyk * np.sin(c["RVY5"] * np.arctan(c["RVY6"] * kappa)) * c["LVYKA"] * b.red  # (4.E66)
    return gyk, svyk


def _gxa(c, b: _Basic):
    """Gx_alpha (4.E51)-(4.E57)."""
    if b.v52:
        bxa = (c["RBX1"] + c["RBX3"] * b.gamma ** 2) * np.cos(np.arctan(c["RBX2"] * b.kappa)) * c["LXAL"]
        a = b.alpha
    else:
        bxa = (c["RBX1"] + c["RBX3"] * b.gstar ** 2) * np.cos(np.arctan(c["RBX2"] * b.kappa)) * c["LXAL"]  # (4.E54)
        a = b.astar
    cxa = c["RCX1"]                                                                    # (4.E55)
    exa = np.minimum(c["REX1"] + c["REX2"] * b.dfz, 1.0)                               # (4.E56)
    shxa = c["RHX1"]                                                                   # (4.E57)
    as_ = a + shxa                                                                     # (4.E53)
    return _cos_mf(bxa, cxa, exa, as_) / _cos_mf(bxa, cxa, exa, shxa)                  # (4.E51), (4.E52)


def _mz_parts(c, b: _Basic, fy_parts):
    """Pneumatic-trail and residual-torque factors of Mz (4.E31)-(4.E47)."""
    fz, dfz, dpi, fz0p = b.fz, b.dfz, b.dpi, b.fz0p
    r0 = c["UNLOADED_RADIUS"]
    kya = fy_parts["kya"]
    kyap = kya + EPSILON * _sgn(kya)                                                   # (4.E39)
    shf = fy_parts["shy"] + fy_parts["svy"] / kyap                                     # (4.E38)
    ar = b.astar + shf                                                                 # (4.E37)
    ct = c["QCZ1"]                                                                     # (4.E41)
    if b.v52:
        gz = b.gz
        sht = c["QHZ1"] + c["QHZ2"] * dfz + (c["QHZ3"] + c["QHZ4"] * dfz) * gz
        bt = ((c["QBZ1"] + c["QBZ2"] * dfz + c["QBZ3"] * dfz ** 2)
              * (1.0 + c["QBZ4"] * gz + c["QBZ5"] * np.abs(gz)) * c["LKY"] / b.lmuy_s)
        dt = (fz * (c["QDZ1"] + c["QDZ2"] * dfz) * (1.0 + c["QDZ3"] * gz + c["QDZ4"] * gz ** 2)
              * (r0 / fz0p) * c["LTR"])
        et_g = c["QEZ5"] * gz
        if np.any(dpi != 0) or _nonzero(c, ("QDZ10", "QDZ11")):  # 6.1 terms of a 5.2 file (MFeval) (4.E42), (4.E47)
            dt = dt * (1.0 - c["PPZ1"] * dpi)
            dr = (fz * r0 * ((c["QDZ6"] + c["QDZ7"] * dfz) * c["LRES"]
                             + ((c["QDZ8"] + c["QDZ9"] * dfz) * (1.0 + c["PPZ2"] * dpi)
                                + (c["QDZ10"] + c["QDZ11"] * dfz) * np.abs(gz)) * gz)
                  * b.lmuy_s * np.cos(b.alpha))
        else:
            dr = (fz * r0 * ((c["QDZ6"] + c["QDZ7"] * dfz) * c["LRES"] + (c["QDZ8"] + c["QDZ9"] * dfz) * gz)
                  * b.lmuy_s * np.cos(b.alpha))
    else:
        g, gs = b.gamma, b.gstar
        sht = c["QHZ1"] + c["QHZ2"] * dfz + (c["QHZ3"] + c["QHZ4"] * dfz) * gs        # (4.E35)
        # 6.1 paper (A58): (1 + QBZ4 gamma + QBZ5 |gamma|); the book's (4.E40) QBZ6 is not a 6.1 file key
        bt = ((c["QBZ1"] + c["QBZ2"] * dfz + c["QBZ3"] * dfz ** 2)
              * (1.0 + c["QBZ4"] * g + c["QBZ5"] * np.abs(g)) * c["LKY"] / b.lmuy_s)
        dt0 = fz * (r0 / fz0p) * (c["QDZ1"] + c["QDZ2"] * dfz) * (1.0 - c["PPZ1"] * dpi) * c["LTR"]  # (4.E42)
        dt = dt0 * (1.0 + c["QDZ3"] * g + c["QDZ4"] * g ** 2)                          # (A60) [(4.E43): |gamma*|], zeta5 = 1
        et_g = c["QEZ5"] * gs
        dr = (fz * r0 * ((c["QDZ6"] + c["QDZ7"] * dfz) * c["LRES"]
                         + ((c["QDZ8"] + c["QDZ9"] * dfz) * (1.0 + c["PPZ2"] * dpi)
                            + (c["QDZ10"] + c["QDZ11"] * dfz) * np.abs(gs)) * gs * c["LKZC"])
              * b.lmuy_s * np.cos(b.alpha))                                            # (4.E47), zeta0 = 1, zeta8 = 1
    at = b.astar + sht                                                                 # (4.E34)
    et = np.minimum((c["QEZ1"] + c["QEZ2"] * dfz + c["QEZ3"] * dfz ** 2)
                    * (1.0 + (c["QEZ4"] + et_g) * (2.0 / np.pi) * np.arctan(bt * ct * at)), 1.0)  # (4.E44)
    br = (c["QBZ9"] * c["LKY"] / b.lmuy_s + c["QBZ10"] * fy_parts["by"] * fy_parts["cy"])  # (4.E45), zeta6 = 1
    cr = 1.0                                                                           # (4.E46), zeta7 = 1
    return dict(at=at, ar=ar, bt=bt, ct=ct, dt=dt, et=et, br=br, cr=cr, dr=dr, kyap=kyap)


def _mz(c, b: _Basic, mzp, fy_prime, kxk, fx, fy):
    """Combined Mz (4.E71)-(4.E78); with kappa = 0 and Fx = 0 it is Mz0 (4.E31)-(4.E36)."""
    r0 = c["UNLOADED_RADIUS"]
    kk = (kxk / mzp["kyap"]) ** 2 * b.kappa ** 2
    # 6.1 paper (A54), (A55): the equivalent angles through tan, = (4.E77), (4.E78) for small angles
    at_eq = np.arctan(np.sqrt(np.tan(mzp["at"]) ** 2 + kk)) * np.sign(mzp["at"])
    ar_eq = np.arctan(np.sqrt(np.tan(mzp["ar"]) ** 2 + kk)) * np.sign(mzp["ar"])
    # (4.E73); times LFZO as TNO's solver (found by MFeval, not in the book or paper)
    t = _cos_mf(mzp["bt"], mzp["ct"], mzp["et"], at_eq) * mzp["dt"] * b.cos_ap * c["LFZO"] * b.red
    mzr = mzp["dr"] * np.cos(mzp["cr"] * np.arctan(mzp["br"] * ar_eq)) * b.red          # (4.E75)
    g = b.gz if b.v52 else b.gamma
    # (4.E76), with Fz0 (unscaled) as the 6.1 paper (A56)
    s = r0 * (c["SSZ1"] + c["SSZ2"] * (fy / c["FNOMIN"]) + (c["SSZ3"] + c["SSZ4"] * b.dfz) * g) * c["LS"]
    return -t * fy_prime + mzr + s * fx, t, mzr                                          # (4.E71), (4.E72)


def _mx(c, b: _Basic, fy):
    """Overturning moment: MF 6.1 manual form of (4.E69); MF 5.2 manual for 5.2."""
    r0, fz0, fz, g = c["UNLOADED_RADIUS"], c["FNOMIN"], b.fz, b.gamma
    if b.v52 and not (np.any(b.dpi != 0) or _nonzero(c, _MX_61)):  # else: 6.1 Mx, as MFeval for every FITTYP
        return r0 * fz * (c["QSX1"] * c["LVMX"] - c["QSX2"] * g + c["QSX3"] * fy / fz0) * c["LMX"]
    return (r0 * fz * c["LMX"]
            * (c["QSX1"] * c["LVMX"] - c["QSX2"] * g * (1.0 + c["PPMX1"] * b.dpi) + c["QSX3"] * fy / fz0
               + c["QSX4"] * np.cos(c["QSX5"] * np.arctan((c["QSX6"] * fz / fz0) ** 2))
               * np.sin(c["QSX7"] * g + c["QSX8"] * np.arctan(c["QSX9"] * fy / fz0))
               + c["QSX10"] * np.arctan(c["QSX11"] * fz / fz0) * g)
            + r0 * c["LMX"] * (fy * (c["QSX13"] + c["QSX14"] * np.abs(g)) - fz * c["QSX12"] * g * np.abs(g)))


def _my(c, b: _Basic, fx, pressure):
    """Rolling-resistance moment, ISO-W sign: 6.1 paper (A48) (= 4.E70); MF 5.2 manual for 5.2."""
    r0, fz0, v0 = c["UNLOADED_RADIUS"], c["FNOMIN"], c["LONGVL"]
    vr = b.vcx / v0
    if b.v52:
        my = -r0 * b.fz * c["LMY"] * (c["QSY1"] + c["QSY2"] * fx / fz0 + c["QSY3"] * np.abs(vr)
                                      + c["QSY4"] * vr ** 4)
    else:
        press = np.asarray(c["NOMPRES"] if pressure is None else pressure, dtype=float)
        my = (-r0 * fz0 * c["LMY"]
              * (c["QSY1"] + c["QSY2"] * fx / fz0 + c["QSY3"] * np.abs(vr) + c["QSY4"] * vr ** 4
                 + (c["QSY5"] + c["QSY6"] * b.fz / fz0) * b.gamma ** 2)
              * (b.fz / fz0) ** c["QSY7"] * (press / c["NOMPRES"]) ** c["QSY8"])
    # rolling resistance follows the sign of the rolling speed Vr = Vcx (1 + kappa) and fades as a
    # sine over |Vr| < VXLOW (locked wheel, standstill; MFeval 4.0 Solver.calculateMy)
    vxlow = c["VXLOW"]
    vr = b.vcx * (1.0 + b.kappa_in)
    if vxlow > 0:
        my = my * np.sin(0.5 * np.pi * np.clip(vr / vxlow, -1.0, 1.0))
    else:
        my = my * np.sign(vr)
    return my


def _prepare(p, version, fz, slip_ratio, slip_angle, camber, pressure, speed):
    v = resolve_version(p, version)
    c = coefficients(p)
    if v == "5.2" and not any(str(k).upper() == "PKY4" for k in p):
        c["PKY4"] = 2.0          # MF 5.2 has sin(2 arctan(...)) in K_y_alpha; PKY4 arrived with 6.x
    return c, _basic(c, v == "5.2", fz, slip_ratio, slip_angle, camber, pressure, speed)


def fx0(p: Mapping, fz, slip_ratio=0.0, camber=0.0, pressure=None, speed=None, *, version=None) -> np.ndarray:
    """Pure longitudinal force Fx0 [N] (4.E9); arguments as :func:`forces`."""
    c, b = _prepare(p, version, fz, slip_ratio, 0.0, camber, pressure, speed)
    out, _, _ = _fx0_parts(c, b)
    return np.asarray(out)


def fy0(p: Mapping, fz, slip_angle=0.0, camber=0.0, pressure=None, speed=None, *, version=None) -> np.ndarray:
    """Pure lateral force Fy0 [N] (4.E19); arguments as :func:`forces`."""
    c, b = _prepare(p, version, fz, 0.0, slip_angle, camber, pressure, speed)
    return np.asarray(_fy0_parts(c, b)["fy0"])


def mz0(p: Mapping, fz, slip_angle=0.0, camber=0.0, pressure=None, speed=None, *, version=None) -> np.ndarray:
    """Pure-slip aligning moment Mz0 [N*m] (4.E31): -t0 Fy0(gamma = 0) + Mzr0."""
    c, b = _prepare(p, version, fz, 0.0, slip_angle, camber, pressure, speed)
    fyp = _fy0_parts(c, b)
    fy_g0 = fyp["fy0"] if not np.any(b.gstar) else _fy0_parts(c, b, zero_camber=True)["fy0"]
    mzp = _mz_parts(c, b, fyp)
    out, _, _ = _mz(c, b, mzp, fy_g0, 0.0, 0.0, fyp["fy0"])
    return np.asarray(out)


def forces(p: Mapping, fz, slip_ratio=0.0, slip_angle=0.0, camber=0.0, pressure=None, speed=None, *,
           version=None) -> dict[str, np.ndarray]:
    """Steady-state forces and moments of an MF 6.1 or 5.2 tyre, combined slip included.

    Parameters
    ----------
    p : Mapping
        ``.tir`` coefficients, keys in upper case (``FNOMIN``, ``NOMPRES``, ``LONGVL``,
        ``UNLOADED_RADIUS``, ``PCX1`` ...).  Missing scaling factors are 1, other missing
        coefficients 0.
    fz : array_like
        Normal load [N], > 0.
    slip_ratio : array_like
        Longitudinal slip kappa [-] (ISO: > 0 driving).
    slip_angle : array_like
        Slip angle alpha [rad] (ISO-W).
    camber : array_like
        Inclination angle gamma [rad] (ISO-W).
    pressure : array_like, optional
        Inflation pressure [Pa]; None -> ``NOMPRES``.  Not used by MF 5.2.
    speed : array_like, optional
        Forward speed of the wheel centre Vcx [m/s], >= 0; None -> ``LONGVL``.
    version : {'6.1', '5.2'}, optional
        Equation set; default from ``p['FITTYP']`` (61/62 -> 6.1; 5/6/21 -> 5.2) or
        ``PROPERTY_FILE_FORMAT`` ('MF_05', 'PAC2002' -> 5.2); 6.1 when neither is given.

    Returns
    -------
    dict
        ``fx``, ``fy`` [N], ``mz``, ``mx``, ``my`` [N*m], ISO-W, broadcast over the inputs.

    Notes
    -----
    Fx = Gx_alpha Fx0 (4.E50); Fy = Gy_kappa Fy0 + SVy_kappa (4.E58);
    Mz = -t Fy' + Mzr + s Fx (4.E71) with Fy' = Gy_kappa Fy0(gamma = 0) for 6.1 (4.E74) and
    Fy' = Fy - SVy_kappa for 5.2.  See the module docstring for every choice.
    """
    c, b = _prepare(p, version, fz, slip_ratio, slip_angle, camber, pressure, speed)
    fx0_, _, kxk = _fx0_parts(c, b)
    fyp = _fy0_parts(c, b)
    fx = _gxa(c, b) * fx0_                                                             # (4.E50)
    gyk, svyk = _gyk(c, b, fyp["muy"])
    fy = gyk * fyp["fy0"] + svyk                                                       # (4.E58)
    mzp = _mz_parts(c, b, fyp)
    if b.v52:
        # MF 5.2 manual: Mz' = -t (Fy - SVy_kappa), SVy_kappa taken with the zero-camber mu_y
        # (as MFeval 4.0 does for FITTYP 6)
        _, svyk0 = _gyk(c, b, _fy0_parts(c, b, zero_camber=True)["muy"])
        fy_prime = fy - svyk0
    else:
        fy_g0 = fyp["fy0"] if not np.any(b.gstar) else _fy0_parts(c, b, zero_camber=True)["fy0"]
        fy_prime = gyk * fy_g0                                                         # (4.E74)
    mz, _, _ = _mz(c, b, mzp, fy_prime, kxk, fx, fy)
    shape = np.broadcast(b.fz, b.kappa, b.alpha, b.gamma, b.vcx,
                         np.asarray(0.0 if pressure is None else pressure)).shape
    out = {"fx": fx, "fy": fy, "mz": mz, "mx": _mx(c, b, fy), "my": _my(c, b, fx, pressure)}
    shape = np.broadcast_shapes(shape, *(np.shape(v) for v in out.values()))
    return {k: np.broadcast_to(np.asarray(v, dtype=float), shape).copy() if np.shape(v) != shape
            else np.asarray(v, dtype=float) for k, v in out.items()}


def factors(p: Mapping, fz, camber=0.0, pressure=None, speed=None, *, version=None) -> dict[str, np.ndarray]:
    """The Magic Formula factors at zero slip, for checks of a parameter set over its ranges.

    Returns ``cx``, ``mux``, ``dx`` [N], ``kx`` [N] (slip stiffness dFx0/dkappa), ``bx``,
    ``ex_drive`` / ``ex_brake`` (Ex for kappa > 0 / < 0, *before* the E <= 1 limit) and the
    lateral ``cy``, ``muy``, ``dy`` [N], ``ky`` [N/rad] (cornering stiffness), ``by``,
    ``ey_pos`` / ``ey_neg`` (Ey for alpha_y > 0 / < 0, unlimited), broadcast over the inputs.
    The physical conditions of Pacejka (2012) sec. 4.3.2 are Cx > 0, Dx > 0 (mux > 0), Kx > 0,
    Ex <= 1 (4.E11-4.E15) and Cy > 0, Dy > 0, Ey <= 1 (4.E21-4.E24), Ky of one sign (its sign
    is the file's convention: < 0 when Fy < 0 for alpha > 0).
    """
    c, b = _prepare(p, version, fz, 0.0, 0.0, camber, pressure, speed)
    xp, xn = _fx0_parts(c, b, e_sign=1.0), _fx0_parts(c, b, e_sign=-1.0)
    yp, yn = _fy0_parts(c, b, e_sign=1.0), _fy0_parts(c, b, e_sign=-1.0)
    shape = np.broadcast(b.fz, b.gamma, np.asarray(0.0 if pressure is None else pressure)).shape
    out = {"cx": xp["cx"], "mux": xp["mux"], "dx": xp["dx"], "kx": xp["kx"], "bx": xp["bx"],
           "ex_drive": xp["ex"], "ex_brake": xn["ex"], "cy": yp["cy"], "muy": yp["muy"], "dy": yp["dy"],
           "ky": yp["ky"], "by": yp["by"], "ey_pos": yp["ey"], "ey_neg": yn["ey"]}
    shape = np.broadcast_shapes(shape, *(np.shape(v) for v in out.values()))
    return {k: np.broadcast_to(np.asarray(v, dtype=float), shape).copy() for k, v in out.items()}


def clip_to_ranges(p: Mapping, fz, slip_ratio=0.0, slip_angle=0.0, camber=0.0, pressure=None):
    """Inputs limited to the file's ``[*_RANGE]`` sections, as a simulator does (a range not given is open).

    Returns ``(fz, slip_ratio, slip_angle, camber, pressure)`` as arrays.
    """
    c = {str(k).upper(): v for k, v in p.items()}

    def lim(x, lo, hi):
        x = np.asarray(x, dtype=float)
        lo_v = float(c[lo]) if lo in c else -np.inf
        hi_v = float(c[hi]) if hi in c else np.inf
        return np.clip(x, lo_v, hi_v)

    return (lim(fz, "FZMIN", "FZMAX"), lim(slip_ratio, "KPUMIN", "KPUMAX"),
            lim(slip_angle, "ALPMIN", "ALPMAX"), lim(camber, "CAMMIN", "CAMMAX"),
            None if pressure is None else lim(pressure, "PRESMIN", "PRESMAX"))
