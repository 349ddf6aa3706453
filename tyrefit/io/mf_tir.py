"""Write Magic Formula 6.1 tyre property files (``FITTYP = 61``).

The layout is the vendor one (TNO / MF-Tyre, as MFeval's and Adams' example
files): ``[MDI_HEADER]``, ``[UNITS]``, ``[MODEL]``, ``[DIMENSION]``,
``[OPERATING_CONDITIONS]``, ``[INERTIA]``, ``[VERTICAL]``, ``[STRUCTURAL]``,
``[CONTACT_PATCH]``, the five ``[*_RANGE]`` sections, ``[SCALING_COEFFICIENTS]``,
``[LONGITUDINAL_COEFFICIENTS]``, ``[OVERTURNING_COEFFICIENTS]``,
``[LATERAL_COEFFICIENTS]``, ``[ROLLING_COEFFICIENTS]``,
``[ALIGNING_COEFFICIENTS]`` and ``[TURNSLIP_COEFFICIENTS]``.

``version='5.2'`` writes the same layout as ``FITTYP = 6`` for a parameter set
meant for the MF 5.2 equations (the 6.1-only keys left out, LGAX/LGAY/LGAZ and
PHY3 added), so that every reader evaluates it with the 5.2 equations.

Design choices
--------------
* **Every coefficient is written** (:data:`tyrefit.models.mf61.COEFFICIENTS`),
  so a simulator never falls back to its own defaults.  What the caller does
  not give comes from :func:`tyrefit.models.mf61.neutral` - finite values that
  switch an effect off (shifts, camber, pressure, combined-slip and moment
  terms 0; scaling factors 1, LMUV 0) - and the header says which sections hold such
  placeholders, next to the parts the caller declares ``not_fitted``.  Zeros
  that make B = 0/0 are never written.
* **A part with no data gives no force, and says so twice.**  For a force
  part declared not fitted (stages ``fx0``, ``fy0``, ``mz0``) the whole
  coefficient group is written at its neutral values with the slip stiffness
  (PKX1 = PKX2 = 0; PKY1 = 0) or peak trail (QDZ1 = 0) set to zero: B = K / (C D
  + eps) = 0 with C, D finite and non-zero, so every implementation (Adams,
  MFeval, Chrono, tyrefit) computes Fx, Fy or Mz = 0 there, finite -- the MF
  analogue of the PAC89 writer's ``NEUTRAL_BLOCKS``, never the generic
  passenger-car curve of :func:`tyrefit.models.mf61.neutral`, which a
  simulator would brake or corner on.  Then ``USE_MODE`` (its last digit:
  1 Fx/My only, 2 Fy/Mx/Mz only, 3 uncombined, 4 combined; the same in MSC's
  PAC2002 and TNO's MF-Tyre 6.x, see :mod:`tyrefit.tyres.mf`) tells Adams which
  forces to compute -- steady state (tens digit 0): tyrefit fits no relaxation
  -- and a comment ``$ TYREFIT_NOT_FITTED = fx, mx, ...`` names the channels
  without data for tyrefit's reader (MFeval ignores USE_MODE).  A caller that
  declares no stage not fitted gets its own ``USE_MODE`` or 4.
* ``[SCALING_COEFFICIENTS]`` carries LMUV (friction decay with slip speed,
  Pacejka 2012 4.E7, neutral 0) beside the factors of
  :data:`tyrefit.models.mf61.COEFFICIENTS`, as MF-Tyre 6.x and PAC2002 files
  do: a fit from several speeds sets it (:mod:`tyrefit.fitting.mf`).
* Turn slip is not part of tyrefit's model; ``[TURNSLIP_COEFFICIENTS]`` carries
  the generic values of TNO's example files (which MFeval also uses as its
  defaults) so that a simulator run in a turn-slip mode still gets finite
  values, and the header says they are not fitted.
* SI units throughout (``[UNITS]`` meter, newton, radians, kg, second); the
  values are written with ``repr`` of the float, the shortest text that reads
  back to the same number, so write -> read -> evaluate gives identical forces.
* Comments: the header as ``$`` lines; each value line is
  ``KEY = value  $description`` with at least two spaces before the ``$`` -
  a long value pushes its comment right, never into itself.  Free text given by
  the caller is put on ``$`` lines only, with line breaks removed.
* Nothing is checked inside the model maths; here, at the boundary, a value
  that is not a finite number is a :class:`~tyrefit.errors.ModelError` naming
  the key, raised before anything is written.  The file goes through
  :func:`tyrefit.io.outputs.write_text` (atomic; an existing file is replaced
  only with ``force=True``).
"""

from __future__ import annotations

import math
import os
import textwrap
from collections.abc import Iterable, Mapping
from pathlib import Path

from ..errors import ModelError
from ..models import mf61
from .outputs import write_text

__all__ = ["write_mf_tir", "format_mf_tir", "SECTIONS", "TURNSLIP", "RANGE_KEYS", "ONLY_61", "ZERO_FORCE",
           "EXTRA_SCALING", "not_fitted_channels"]

#: generic turn-slip values of TNO's example files (MFeval 4.0 readTIR defaults); not fitted by tyrefit
TURNSLIP: dict[str, float] = {
    "PDXP1": 0.4, "PDXP2": 0.0, "PDXP3": 0.0, "PKYP1": 1.0, "PDYP1": 0.4, "PDYP2": 0.0, "PDYP3": 0.0,
    "PDYP4": 0.0, "PHYP1": 1.0, "PHYP2": 0.15, "PHYP3": 0.0, "PHYP4": -4.0, "PECP1": 0.5, "PECP2": 0.0,
    "QDTP1": 10.0, "QCRP1": 0.2, "QCRP2": 0.1, "QBRP1": 0.1, "QDRP1": 1.0,
}

#: [MODEL] entries written besides FITTYP / LONGVL / VXLOW (vendor layout; Adams reads them)
_MODEL_EXTRA: list[tuple[str, object, str]] = [
    ("ROAD_INCREMENT", 0.01, "Increment in road sampling"),
    ("ROAD_DIRECTION", 1, "Direction of travelled distance"),
    ("PROPERTY_FILE_FORMAT", "'USER'", ""),
    ("USER_SUB_ID", 815, ""),
    ("N_TIRE_STATES", 5, ""),
    ("USE_MODE", 4, "Tyre use switch (last digit: 1 Fx,My 2 Fy,Mx,Mz 3 uncombined 4 combined)"),
    ("HMAX_LOCAL", 2.5e-4, "Local integration time step (Adams)"),
    ("TIME_SWITCH_INTEG", 0.1, "Time when local integrator is activated (Adams)"),
]

#: section order of the file (after MDI_HEADER, UNITS)
SECTIONS: list[str] = [
    "MODEL", "DIMENSION", "OPERATING_CONDITIONS", "INERTIA", "VERTICAL", "STRUCTURAL", "CONTACT_PATCH",
    "INFLATION_PRESSURE_RANGE", "VERTICAL_FORCE_RANGE", "LONG_SLIP_RANGE", "SLIP_ANGLE_RANGE",
    "INCLINATION_ANGLE_RANGE", "SCALING_COEFFICIENTS", "LONGITUDINAL_COEFFICIENTS", "OVERTURNING_COEFFICIENTS",
    "LATERAL_COEFFICIENTS", "ROLLING_COEFFICIENTS", "ALIGNING_COEFFICIENTS", "TURNSLIP_COEFFICIENTS",
]

#: ``ranges`` may name a range by quantity: quantity -> (min key, max key)
RANGE_KEYS: dict[str, tuple[str, str]] = {
    "pressure": ("PRESMIN", "PRESMAX"),
    "fz": ("FZMIN", "FZMAX"),
    "slip_ratio": ("KPUMIN", "KPUMAX"),
    "slip_angle": ("ALPMIN", "ALPMAX"),
    "camber": ("CAMMIN", "CAMMAX"),
}

_INTEGER_KEYS = frozenset(["FITTYP", "ROAD_DIRECTION", "USER_SUB_ID", "N_TIRE_STATES", "USE_MODE",
                           "ELLIPS_NWIDTH", "ELLIPS_NLENGTH"])

#: short descriptions written as each line's comment (MF-Tyre 6.1 meanings)
_DESCRIPTION: dict[str, str] = {
    "FITTYP": "Magic Formula version number", "LONGVL": "Reference speed", "VXLOW": "Lower boundary of slip calculation",
    "UNLOADED_RADIUS": "Free tyre radius", "WIDTH": "Nominal section width of the tyre",
    "RIM_RADIUS": "Nominal rim radius", "RIM_WIDTH": "Rim width", "ASPECT_RATIO": "Nominal aspect ratio",
    "INFLPRES": "Tyre inflation pressure", "NOMPRES": "Nominal tyre inflation pressure",
    "MASS": "Tyre mass", "IXX": "Tyre diametral moment of inertia", "IYY": "Tyre polar moment of inertia",
    "BELT_MASS": "Belt mass", "BELT_IXX": "Belt diametral moment of inertia", "BELT_IYY": "Belt polar moment of inertia",
    "GRAVITY": "Gravity acting on belt in Z direction",
    "FNOMIN": "Nominal wheel load", "VERTICAL_STIFFNESS": "Tyre vertical stiffness",
    "VERTICAL_DAMPING": "Tyre vertical damping", "MC_CONTOUR_A": "Motorcycle contour ellipse A",
    "MC_CONTOUR_B": "Motorcycle contour ellipse B", "BREFF": "Low load stiffness of effective rolling radius",
    "DREFF": "Peak value of effective rolling radius", "FREFF": "High load stiffness of effective rolling radius",
    "Q_RE0": "Ratio of free tyre radius with nominal tyre radius", "Q_V1": "Tyre radius increase with speed",
    "Q_V2": "Vertical stiffness increase with speed", "Q_FZ2": "Quadratic term in load vs. deflection",
    "Q_FCX": "Longitudinal force influence on vertical stiffness",
    "Q_FCY": "Lateral force influence on vertical stiffness", "Q_CAM": "Stiffness reduction due to camber",
    "PFZ1": "Pressure effect on vertical stiffness", "BOTTOM_OFFST": "Distance to rim when bottoming starts",
    "BOTTOM_STIFF": "Vertical stiffness of bottomed tyre",
    "LONGITUDINAL_STIFFNESS": "Tyre overall longitudinal stiffness",
    "LATERAL_STIFFNESS": "Tyre overall lateral stiffness", "YAW_STIFFNESS": "Tyre overall yaw stiffness",
    "FREQ_LONG": "Undamped frequency fore/aft and vertical mode", "FREQ_LAT": "Undamped frequency lateral mode",
    "FREQ_YAW": "Undamped frequency yaw and camber mode", "FREQ_WINDUP": "Undamped frequency wind-up mode",
    "DAMP_LONG": "Dimensionless damping fore/aft and vertical mode", "DAMP_LAT": "Dimensionless damping lateral mode",
    "DAMP_YAW": "Dimensionless damping yaw and camber mode", "DAMP_WINDUP": "Dimensionless damping wind-up mode",
    "DAMP_RESIDUAL": "Residual damping (proportional to stiffness)",
    "DAMP_VLOW": "Additional low speed damping (proportional to stiffness)",
    "Q_BVX": "Load and speed influence on in-plane translation stiffness",
    "Q_BVT": "Load and speed influence on in-plane rotation stiffness",
    "PCFX1": "Longitudinal stiffness: deflection, linear", "PCFX2": "Longitudinal stiffness: deflection, quadratic",
    "PCFX3": "Longitudinal stiffness: pressure", "PCFY1": "Lateral stiffness: deflection, linear",
    "PCFY2": "Lateral stiffness: deflection, quadratic", "PCFY3": "Lateral stiffness: pressure",
    "PCMZ1": "Yaw stiffness: pressure",
    "Q_RA1": "Square root term in contact length equation", "Q_RA2": "Linear term in contact length equation",
    "Q_RB1": "Root term in contact width equation", "Q_RB2": "Linear term in contact width equation",
    "ELLIPS_SHIFT": "Scaling of distance between front and rear ellipsoid", "ELLIPS_LENGTH": "Semi major axis of ellipsoid",
    "ELLIPS_HEIGHT": "Semi minor axis of ellipsoid", "ELLIPS_ORDER": "Order of ellipsoid",
    "ELLIPS_MAX_STEP": "Maximum height of road step", "ELLIPS_NWIDTH": "Number of parallel ellipsoids",
    "ELLIPS_NLENGTH": "Number of ellipsoids at sides of contact patch",
    "PRESMIN": "Minimum valid tyre inflation pressure", "PRESMAX": "Maximum valid tyre inflation pressure",
    "FZMIN": "Minimum allowed wheel load", "FZMAX": "Maximum allowed wheel load",
    "KPUMIN": "Minimum valid wheel slip", "KPUMAX": "Maximum valid wheel slip",
    "ALPMIN": "Minimum valid slip angle", "ALPMAX": "Maximum valid slip angle",
    "CAMMIN": "Minimum valid camber angle", "CAMMAX": "Maximum valid camber angle",
    "LFZO": "Scale factor of nominal (rated) load", "LCX": "Scale factor of Fx shape factor",
    "LMUX": "Scale factor of Fx peak friction coefficient", "LEX": "Scale factor of Fx curvature factor",
    "LKX": "Scale factor of Fx slip stiffness", "LHX": "Scale factor of Fx horizontal shift",
    "LVX": "Scale factor of Fx vertical shift", "LCY": "Scale factor of Fy shape factor",
    "LMUY": "Scale factor of Fy peak friction coefficient", "LEY": "Scale factor of Fy curvature factor",
    "LMUV": "Scale factor with slip speed Vs decaying friction",
    "LKY": "Scale factor of Fy cornering stiffness", "LKYC": "Scale factor of camber force stiffness",
    "LKZC": "Scale factor of camber torque stiffness", "LHY": "Scale factor of Fy horizontal shift",
    "LVY": "Scale factor of Fy vertical shift", "LTR": "Scale factor of peak of pneumatic trail",
    "LRES": "Scale factor for offset of residual torque", "LXAL": "Scale factor of alpha influence on Fx",
    "LYKA": "Scale factor of kappa influence on Fy", "LVYKA": "Scale factor of kappa induced Fy",
    "LS": "Scale factor of moment arm of Fx", "LMX": "Scale factor of overturning couple",
    "LVMX": "Scale factor of Mx vertical shift", "LMY": "Scale factor of rolling resistance torque",
    "LMP": "Scale factor of parking moment",
    "PCX1": "Shape factor Cfx for longitudinal force", "PDX1": "Longitudinal friction Mux at Fznom",
    "PDX2": "Variation of friction Mux with load", "PDX3": "Variation of friction Mux with camber squared",
    "PEX1": "Longitudinal curvature Efx at Fznom", "PEX2": "Variation of curvature Efx with load",
    "PEX3": "Variation of curvature Efx with load squared", "PEX4": "Factor in curvature Efx while driving",
    "PKX1": "Longitudinal slip stiffness Kfx/Fz at Fznom", "PKX2": "Variation of slip stiffness Kfx/Fz with load",
    "PKX3": "Exponent in slip stiffness Kfx/Fz with load", "PHX1": "Horizontal shift Shx at Fznom",
    "PHX2": "Variation of shift Shx with load", "PVX1": "Vertical shift Svx/Fz at Fznom",
    "PVX2": "Variation of shift Svx/Fz with load", "PPX1": "Pressure: linear, slip stiffness",
    "PPX2": "Pressure: quadratic, slip stiffness", "PPX3": "Pressure: linear, peak longitudinal friction",
    "PPX4": "Pressure: quadratic, peak longitudinal friction",
    "RBX1": "Slope factor for combined slip Fx reduction", "RBX2": "Variation of slope Fx reduction with kappa",
    "RBX3": "Influence of camber on stiffness for Fx combined", "RCX1": "Shape factor for combined slip Fx reduction",
    "REX1": "Curvature factor of combined Fx", "REX2": "Curvature factor of combined Fx with load",
    "RHX1": "Shift factor for combined slip Fx reduction",
    "QSX1": "Vertical shift of overturning moment", "QSX2": "Camber induced overturning couple",
    "QSX3": "Fy induced overturning couple", "QSX4": "Mixed load, lateral force and camber on Mx",
    "QSX5": "Load effect on Mx with lateral force and camber", "QSX6": "B-factor of load with Mx",
    "QSX7": "Camber with load on Mx", "QSX8": "Lateral force with load on Mx",
    "QSX9": "B-factor of lateral force with load on Mx", "QSX10": "Vertical force with camber on Mx",
    "QSX11": "B-factor of vertical force with camber on Mx", "QSX12": "Camber squared induced overturning moment",
    "QSX13": "Lateral force induced overturning moment",
    "QSX14": "Lateral force induced overturning moment with camber",
    "PPMX1": "Influence of inflation pressure on overturning moment",
    "PCY1": "Shape factor Cfy for lateral forces", "PDY1": "Lateral friction Muy",
    "PDY2": "Variation of friction Muy with load", "PDY3": "Variation of friction Muy with squared camber",
    "PEY1": "Lateral curvature Efy at Fznom", "PEY2": "Variation of curvature Efy with load",
    "PEY3": "Zero order camber dependency of curvature Efy", "PEY4": "Variation of curvature Efy with camber",
    "PEY5": "Variation of curvature Efy with camber squared", "PKY1": "Maximum value of stiffness Kfy/Fznom",
    "PKY2": "Load at which Kfy reaches maximum value", "PKY3": "Variation of Kfy/Fznom with camber",
    "PKY4": "Curvature of stiffness Kfy", "PKY5": "Peak stiffness variation with camber squared",
    "PKY6": "Fy camber stiffness factor", "PKY7": "Vertical load dependency of camber stiffness",
    "PHY1": "Horizontal shift Shy at Fznom", "PHY2": "Variation of shift Shy with load",
    "PVY1": "Vertical shift in Svy/Fz at Fznom", "PVY2": "Variation of shift Svy/Fz with load",
    "PVY3": "Variation of shift Svy/Fz with camber", "PVY4": "Variation of shift Svy/Fz with camber and load",
    "PPY1": "Pressure: cornering stiffness", "PPY2": "Pressure: load of peak cornering stiffness",
    "PPY3": "Pressure: linear, peak lateral friction", "PPY4": "Pressure: quadratic, peak lateral friction",
    "PPY5": "Pressure: camber stiffness",
    "RBY1": "Slope factor for combined Fy reduction", "RBY2": "Variation of slope Fy reduction with alpha",
    "RBY3": "Shift term for alpha in slope Fy reduction", "RBY4": "Influence of camber on stiffness of Fy combined",
    "RCY1": "Shape factor for combined Fy reduction", "REY1": "Curvature factor of combined Fy",
    "REY2": "Curvature factor of combined Fy with load", "RHY1": "Shift factor for combined Fy reduction",
    "RHY2": "Shift factor for combined Fy reduction with load",
    "RVY1": "Kappa induced side force Svyk/Muy*Fz at Fznom", "RVY2": "Variation of Svyk/Muy*Fz with load",
    "RVY3": "Variation of Svyk/Muy*Fz with camber", "RVY4": "Variation of Svyk/Muy*Fz with alpha",
    "RVY5": "Variation of Svyk/Muy*Fz with kappa", "RVY6": "Variation of Svyk/Muy*Fz with atan(kappa)",
    "QSY1": "Rolling resistance torque coefficient", "QSY2": "Rolling resistance torque depending on Fx",
    "QSY3": "Rolling resistance torque depending on speed", "QSY4": "Rolling resistance torque depending on speed^4",
    "QSY5": "Rolling resistance torque depending on camber squared",
    "QSY6": "Rolling resistance torque depending on load and camber squared",
    "QSY7": "Rolling resistance torque coefficient load dependency",
    "QSY8": "Rolling resistance torque coefficient pressure dependency",
    "QBZ1": "Trail slope factor for trail Bpt at Fznom", "QBZ2": "Variation of slope Bpt with load",
    "QBZ3": "Variation of slope Bpt with load squared", "QBZ4": "Variation of slope Bpt with camber",
    "QBZ5": "Variation of slope Bpt with absolute camber", "QBZ9": "Factor for scaling factors of slope factor Br of Mzr",
    "QBZ10": "Factor for dimensionless cornering stiffness of Br of Mzr", "QCZ1": "Shape factor Cpt for pneumatic trail",
    "QDZ1": "Peak trail Dpt = Dpt*(Fz/Fznom*R0)", "QDZ2": "Variation of peak Dpt with load",
    "QDZ3": "Variation of peak Dpt with camber", "QDZ4": "Variation of peak Dpt with camber squared",
    "QDZ6": "Peak residual torque Dmr = Dmr/(Fz*R0)", "QDZ7": "Variation of peak factor Dmr with load",
    "QDZ8": "Variation of peak factor Dmr with camber", "QDZ9": "Variation of peak factor Dmr with camber and load",
    "QDZ10": "Variation of peak factor Dmr with camber squared", "QDZ11": "Variation of Dmr with camber squared and load",
    "QEZ1": "Trail curvature Ept at Fznom", "QEZ2": "Variation of curvature Ept with load",
    "QEZ3": "Variation of curvature Ept with load squared", "QEZ4": "Variation of curvature Ept with sign of Alpha-t",
    "QEZ5": "Variation of Ept with camber and sign Alpha-t", "QHZ1": "Trail horizontal shift Sht at Fznom",
    "QHZ2": "Variation of shift Sht with load", "QHZ3": "Variation of shift Sht with camber",
    "QHZ4": "Variation of shift Sht with camber and load", "PPZ1": "Pressure: length of pneumatic trail",
    "PPZ2": "Pressure: residual aligning torque", "SSZ1": "Nominal value of s/R0: effect of Fx on Mz",
    "SSZ2": "Variation of distance s/R0 with Fy/Fznom", "SSZ3": "Variation of distance s/R0 with camber",
    "SSZ4": "Variation of distance s/R0 with load and camber",
}

#: names of the fitting stages for the header
_STAGE_NAMES = {"fx0": "pure-slip Fx", "fy0": "pure-slip Fy", "mz0": "pure-slip Mz", "fx": "combined-slip Fx",
                "fy": "combined-slip Fy", "mz": "combined-slip Mz (s*Fx)", "mx": "overturning moment Mx",
                "my": "rolling resistance My"}


def _num(key: str, value) -> str:
    v = float(value)
    if key in _INTEGER_KEYS and v.is_integer():
        return str(int(v))
    if v == 0.0:
        return "0"
    return repr(v)


def _line(key: str, value: str, comment: str = "") -> str:
    left = f"{key:<25s}= {value}"
    if not comment:
        return left
    return f"{left:<45s}  ${comment}" if len(left) < 45 else f"{left}  ${comment}"


def _clean(text: object) -> str:
    """Free text for a ``$`` comment line: one line, printable."""
    return " ".join(str(text).replace("\r", " ").replace("\n", " ").split())


def _wrap(line: str, width: int = 100) -> list[str]:
    """A ``$`` comment line cut at ``width`` characters, continuation lines indented."""
    if len(line) <= width:
        return [line]
    return textwrap.wrap(line, width=width, subsequent_indent="$     ", break_long_words=True,
                         break_on_hyphens=False)


def _ranges(ranges: Mapping | None) -> dict[str, float]:
    out: dict[str, float] = {}
    if not ranges:
        return out
    for k, v in ranges.items():
        key = str(k)
        if key.lower() in RANGE_KEYS:
            lo, hi = v
            kmin, kmax = RANGE_KEYS[key.lower()]
            out[kmin], out[kmax] = lo, hi
        else:
            out[key.upper()] = v
    return out


#: for a force stage without data: the coefficient whose zero makes the part give no force (B = 0, finite)
ZERO_FORCE: dict[str, dict[str, float]] = {
    "fx0": {"PKX1": 0.0, "PKX2": 0.0},   # Kxk = Fz (PKX1 + PKX2 dfz) exp(PKX3 dfz) = 0   (4.E15)
    "fy0": {"PKY1": 0.0},                # Kya = PKY1 Fz0 sin(...) = 0; PKY6 = PVY3 = 0 neutral   (4.E25)
    "mz0": {"QDZ1": 0.0},                # Dt = Fz (R0 / Fz0') (QDZ1 + QDZ2 dfz) ... = 0; Dr = 0 neutral   (4.E42)
}


def not_fitted_channels(not_fitted: Iterable[str]) -> tuple[list[str], int | None]:
    """Channels without data and the USE_MODE slip digit, from the stage names in ``not_fitted``.

    Returns ``(channels, digit)``; ``digit`` is None when no force stage is
    named (the caller's USE_MODE stands).
    """
    nf = {str(x).lower() for x in not_fitted if str(x).lower() in mf61.GROUPS}
    if not nf & {"fx0", "fy0", "mz0", "fx", "fy"}:
        return [c for c in ("mx", "my") if c in nf], None
    fx, fy = "fx0" not in nf, "fy0" not in nf
    chans = [c for c, st in (("fx", "fx0"), ("fy", "fy0"), ("mz", "mz0"), ("mx", "mx"), ("my", "my")) if st in nf]
    if not fy and "mx" not in chans:
        chans.append("mx")   # Mx = f(Fy): no lateral part, no overturning moment
    combined = (fx or fy) and (not fx or "fx" not in nf) and (not fy or "fy" not in nf)
    if (fx or fy) and not combined:
        chans.append("combined")
    digit = 4 if fx and fy else 2 if fy else 1 if fx else 0
    if digit == 4 and not combined:
        digit = 3
    return chans, digit


def _not_fitted_lines(not_fitted: Iterable[str]) -> list[str]:
    lines = []
    for item in not_fitted:
        name = str(item)
        if name.lower() in ZERO_FORCE:
            names = mf61.GROUPS[name.lower()]
            zero = ", ".join(f"{k} = 0" for k in ZERO_FORCE[name.lower()])
            lines.append(f"NOT FITTED: {_STAGE_NAMES[name.lower()]} ({', '.join(names)}): no data; neutral values "
                         f"with {zero}, so this part gives no force (finite)")
        elif name.lower() in mf61.GROUPS:
            names = mf61.GROUPS[name.lower()]
            lines.append(f"NOT FITTED: {_STAGE_NAMES[name.lower()]} ({', '.join(names)}): neutral values")
        elif name.upper() in mf61.COEFFICIENTS:
            lines.append(f"NOT FITTED: [{name.upper()}]: neutral / generic values")
        else:
            lines.append(f"NOT FITTED: {_clean(name)}")
    return lines


#: MF 6.1 keys an MF 5.2 file does not carry (its equations have no such terms)
ONLY_61: frozenset[str] = frozenset(
    [f"PPX{i}" for i in range(1, 5)] + [f"PPY{i}" for i in range(1, 6)] + ["PPZ1", "PPZ2", "PPMX1"]
    + [f"QSX{i}" for i in range(4, 15)] + [f"QSY{i}" for i in range(5, 9)]
    + ["PKY5", "PKY6", "PKY7", "PEY5", "RBX3", "RBY4", "QDZ10", "QDZ11", "LKYC", "LKZC", "LMP"])


#: scaling factors written besides :data:`tyrefit.models.mf61.COEFFICIENTS`' ones, with their neutral value:
#: LMUV (friction decay with slip speed, Pacejka 2012 4.E7; MF-Tyre 6.x and PAC2002 files carry it) is 0
EXTRA_SCALING: dict[str, float] = {"LMUV": 0.0}


def _keys(version: str) -> dict[str, list[str]]:
    """Section -> keys written for ``version`` ('6.1' or '5.2')."""
    out = {sec: [n for n in names if version == "6.1" or n not in ONLY_61]
           for sec, names in mf61.COEFFICIENTS.items()}
    if version != "6.1":
        for sec, extra in mf61.COEFFICIENTS_52.items():
            out[sec] = out[sec] + list(extra)
    out["SCALING_COEFFICIENTS"] = out["SCALING_COEFFICIENTS"] + [k for k in EXTRA_SCALING
                                                                 if k not in out["SCALING_COEFFICIENTS"]]
    return out


def format_mf_tir(params: Mapping, *, ranges: Mapping | None = None, header: Iterable[str] = (),
                  not_fitted: Iterable[str] = (), version: str = "6.1") -> str:
    """The text of a ``FITTYP = 61`` (or, with ``version='5.2'``, ``FITTYP = 6``) property file;
    see :func:`write_mf_tir`."""
    version = mf61.resolve_version({}, version)
    fittyp = 61 if version == "6.1" else 6
    keys = _keys(version)
    given = {str(k).upper(): v for k, v in params.items()}
    given.update(_ranges(ranges))
    base = dict(mf61.neutral(), LGAX=1.0, LGAY=1.0, LGAZ=1.0, PHY3=0.0, **EXTRA_SCALING)
    not_fitted = list(not_fitted)
    channels, digit = not_fitted_channels(not_fitted)
    for stage in (str(x).lower() for x in not_fitted):
        if stage in ZERO_FORCE:  # a force part without data: neutral group, zero stiffness -> zero force
            given.update({k: base[k] for k in mf61.GROUPS[stage]}, **ZERO_FORCE[stage])
    if digit is not None:
        given["USE_MODE"] = digit
    values: dict[str, object] = {}
    defaulted: dict[str, list[str]] = {}
    for section, names in keys.items():
        for n in names:
            if n == "FITTYP":
                values[n] = fittyp
                continue
            unit_name = n == "MASS" and isinstance(given.get(n), str)   # [UNITS] MASS = 'kg', not a mass
            if n in given and given[n] is not None and str(given[n]).strip() != "" and not unit_name:
                v = given[n]
            else:
                v = base[n]
                defaulted.setdefault(section, []).append(n)
            try:
                fv = float(v)
            except (TypeError, ValueError):
                raise ModelError(f"{n} = {v!r} is not a number; an MF {version} file needs a finite value") from None
            if not math.isfinite(fv):
                raise ModelError(f"{n} = {fv} is not finite; an MF {version} file needs a finite value")
            values[n] = fv
    for key in ("FNOMIN", "NOMPRES", "LONGVL", "UNLOADED_RADIUS"):
        if not values[key] > 0:
            raise ModelError(f"{key} = {values[key]} must be positive")
    tyreside = str(given.get("TYRESIDE", "LEFT")).strip("'\" ").upper() or "LEFT"
    if tyreside not in ("LEFT", "RIGHT", "SYMMETRIC"):
        raise ModelError(f"TYRESIDE = {tyreside!r}; accepted: LEFT, RIGHT, SYMMETRIC")

    out = ["[MDI_HEADER]", _line("FILE_TYPE", "'tir'"), _line("FILE_VERSION", "3.0"),
           _line("FILE_FORMAT", "'ASCII'"),
           f"$ MF-Tyre {version} property file (FITTYP = {fittyp}) written by tyrefit; SI units, ISO-W signs"]
    if channels:
        out.append(f"$ TYREFIT_NOT_FITTED = {', '.join(channels)}")
    out += [f"$ {_clean(h)}" for h in header if _clean(h)]
    out += [f"$ {s}" for s in _not_fitted_lines(not_fitted)]
    for section, names in defaulted.items():
        if section == "MODEL":
            continue
        what = "all" if len(names) == len(keys[section]) else ", ".join(names)
        kind = "neutral / generic values"
        if section == "SCALING_COEFFICIENTS":
            zero = [n for n in names if n in EXTRA_SCALING]
            lmuv = f"{', '.join(zero)} 0: no friction decay with slip speed"
            kind = lmuv if len(zero) == len(names) else "scaling factors 1" + (f" ({lmuv})" if zero else "")
        out.append(f"$ DEFAULTS [{section}]: {what}: {kind}, not from data")
    turnslip = {}
    for k, v in TURNSLIP.items():
        try:
            turnslip[k] = float(given[k]) if k in given else v
        except (TypeError, ValueError):
            raise ModelError(f"{k} = {given[k]!r} is not a number") from None
        if not math.isfinite(turnslip[k]):
            raise ModelError(f"{k} = {turnslip[k]} is not finite")
    missing_ts = [k for k in TURNSLIP if k not in given]
    if missing_ts:
        out.append("$ NOT FITTED: [TURNSLIP_COEFFICIENTS]: generic values of TNO's example files for "
                   + ("all" if len(missing_ts) == len(TURNSLIP) else ", ".join(missing_ts))
                   + " (turn slip is not modelled by tyrefit)")
    out = out[:4] + [w for line in out[4:] for w in _wrap(line)]
    out += ["$" + "-" * 70 + "units", "[UNITS]", _line("LENGTH", "'meter'"), _line("FORCE", "'newton'"),
            _line("ANGLE", "'radians'"), _line("MASS", "'kg'"), _line("TIME", "'second'")]
    for section in SECTIONS:
        out.append("$" + "-" * 70 + section.lower())
        out.append(f"[{section}]")
        if section == "TURNSLIP_COEFFICIENTS":
            out += [_line(k, _num(k, v)) for k, v in turnslip.items()]
            continue
        for n in keys[section]:
            out.append(_line(n, _num(n, values[n]), _DESCRIPTION.get(n, "")))
            if section == "MODEL" and n == "FITTYP":
                out.append(_line("TYRESIDE", f"'{tyreside}'", "Position of tyre during measurements"))
        if section == "MODEL":
            for k, v, c in _MODEL_EXTRA:
                v = given.get(k, v)
                if k == "PROPERTY_FILE_FORMAT":
                    v = "'" + _clean(v).strip("'\"").replace("'", "").replace("$", "") + "'"
                else:
                    try:
                        v = _num(k, v)
                    except (TypeError, ValueError):
                        raise ModelError(f"{k} = {v!r} is not a number") from None
                out.append(_line(k, v, c))
    return "\n".join(out) + "\n"


def write_mf_tir(params: Mapping, path: str | os.PathLike, *, ranges: Mapping | None = None,
                 header: Iterable[str] = (), not_fitted: Iterable[str] = (), force: bool = False,
                 version: str = "6.1") -> Path:
    """Write an MF 6.1 (``FITTYP = 61``) tyre property file with every coefficient.

    Parameters
    ----------
    params : Mapping
        ``.tir`` keys (any case) -> values in SI: coefficients, ``FNOMIN`` [N], ``NOMPRES``
        [Pa], ``LONGVL`` [m/s], ``UNLOADED_RADIUS`` [m], dimensions, ``TYRESIDE`` ...  Keys
        not given take :func:`tyrefit.models.mf61.neutral` values, listed in the header.
    path : path-like
        Output file.
    ranges : Mapping, optional
        The fitted operating ranges: ``{'fz': (min, max) [N], 'slip_ratio': (min, max) [-],
        'slip_angle': (min, max) [rad], 'camber': (min, max) [rad], 'pressure': (min, max)
        [Pa]}`` or the file keys (``FZMIN`` ...); they override ``params``.
    header : iterable of str
        Lines for the header (data sources, RMSE per channel, ...), written as ``$`` comments.
    not_fitted : iterable of str
        Parts declared not fitted: fitting stages of :data:`tyrefit.models.mf61.GROUPS`
        (``'fx'``, ``'mz'``, ``'mx'`` ...), section names, or free text.
    force : bool
        Replace an existing file.
    version : {'6.1', '5.2'}
        '5.2' writes an MF 5.2 file (``FITTYP = 6``) for a parameter set meant for the 5.2
        equations: the 6.1-only keys (:data:`ONLY_61`: pressure terms, QSX4-QSX14, ...) are
        left out and LGAX / LGAY / LGAZ and PHY3 are added.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    ModelError
        a value that is not a finite number, or a non-positive FNOMIN / NOMPRES / LONGVL /
        UNLOADED_RADIUS (nothing is written).
    OutputExistsError
        ``path`` exists and ``force`` is false.
    """
    text = format_mf_tir(params, ranges=ranges, header=header, not_fitted=not_fitted, version=version)
    return write_text(path, text, force=force)
