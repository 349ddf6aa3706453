"""Which coefficients of a Magic Formula stage the data can determine (:func:`identifiability`).

A coefficient the data do not determine is not fitted: fitted, it follows the noise (PEY5 = 2670 +- 2797 on a
real record) or trades off against another term that is the same column on these data, and the tyre file
carries a value no simulator should trust.  It is held at its neutral value and listed with the reason, so
the result says what the data lacked (a second load, both slip signs, ...).  The stages of
:func:`tyrefit.fitting.mf.fit_mf` ask here before they fit.  Counts are taken over the sweeps of the stage:

* load: the ``*2`` load slopes need >= 2 load levels, the quadratic/exponent
  terms (PEX3, PKX3, PKY4, QBZ3, QEZ3) >= 3;
* camber: |gamma| terms (PDX3, PDY3, PKY3, QBZ5, QDZ3, RBX3, RBY4, QSY5) need
  >= 2 levels of |gamma|, gamma^2 terms beyond the first (PEY5, PKY5,
  QDZ4, QSY6) >= 3 levels of |gamma| or 2 with loads; signed camber terms
  (PKY6/PKY7, PVY3/PVY4, PEY4, QDZ8-QDZ11, QHZ3/QHZ4, RVY3, SSZ3/SSZ4,
  QSX2) >= 2 camber levels;
* pressure: PPX1, PPX3, PPY1, PPY3, PPZ1, PPZ2, PPY5, PPMX1, QSY8 need >= 2
  pressures; PPX2, PPX4, PPY4 (quadratic in dpi) >= 3; PPY2 (the load of the
  stiffness peak, inside the atan of Pacejka 2012 4.E25) >= 3, or 2 with >= 3 loads;
* shifts need both slip signs reaching half the largest |slip| (PHX1, PVX1,
  PHY1, PVY1, QHZ1, QDZ6, PEX4 (drive and brake), PEY3, QEZ4, RVY1/RVY5/RVY6
  and RHY1 (drive and brake in the combined sweeps), RHX1 (>= 2 non-zero
  slip angles, or both signs, in the combined sweeps));
* the combined-slip shifts RHX1, RHY1, RHY2 (:data:`COMBINED_SHIFTS`) are always held at 0: with a shift
  the weighting function G exceeds 1 near zero slip (4.E51-4.E53, 4.E59-4.E61), and combined slip would
  add force;
* combined slip needs combined sweeps; RBY3 and RVY4 >= 2 slip-angle levels;
* Mx: the Fy terms (QSX3, QSX13) and the sine term along Fy (QSX4, QSX8,
  QSX9) need cornering sweeps; its load factor (QSX5, QSX6) >= 3 loads;
* speed: QSY3/QSY4 need >= 2/3 speeds; LMUV, MF 6.1's only speed term in the
  forces (the scaling factor of friction decay with slip speed, 4.E7:
  mu* = LMU / (1 + LMUV Vs/V0), Vs = Vcx sqrt(kappa^2 + tan^2 alpha), V0 =
  LONGVL), needs >= 2 speeds *and* sweeps through the peak: at one speed the
  fall of mu with Vs is a fall with slip, the curvature E's and the post-peak
  shape's, and without a peak the friction itself is not measured.  It is one
  factor on mu_x and mu_y: the Fx0 stage fits it from drive/brake sweeps and
  the Fy0 stage holds that value (as every stage holds the stages before it;
  refitted there, Fx would be evaluated with an LMUV it was not fitted with),
  or fits it from cornering sweeps when Fx0 did not; the joint polish moves it
  with both channels.  Bounds 0 <= LMUV <= 2 (friction falls with slip
  speed; 2 halves it at Vs = V0/2).  Only LMUV/V0 is defined by the data: the
  fit's V0 is LONGVL = the middle speed level;
* with no sweep reaching its peak the curvature E of that stage is held at 0 and its shape factor C at
  Pacejka's typical value (:data:`NO_PEAK`, :data:`SHAPE_DEFAULTS`).

References
----------
Pacejka, *Tire and Vehicle Dynamics*, 3rd ed. (2012), sections 4.3.2-4.3.4 and the equations 4.E1-4.E78;
Besselink, Schmeitz, Pacejka, VSD 48 (2010) (the PP* pressure terms).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd

from .mf_data import _levels, condition_levels
from .mf_stages import _ONLY_61, _STAGE, Stage

__all__ = ["identifiability", "COMBINED_SHIFTS", "NO_PEAK", "SHAPE_DEFAULTS"]

_DEG = math.pi / 180.0

#: the combined-slip shifts S_Hxa = RHX1, S_Hyk = RHY1 + RHY2 dfz, held at 0: with a shift G = cos(C atan(B (x +
#: S_H)))/cos(C atan(B S_H)) is 1/cos(C atan(B S_H)) > 1 at x = -S_H, inside any range that reaches zero slip
#: (Pacejka 2012, 4.E51-4.E53, 4.E59-4.E61); without it G <= 1 everywhere
COMBINED_SHIFTS = ("RHX1", "RHY1", "RHY2")
#: the reason given for a shape held because no sweep of the stage reaches its peak
NO_PEAK = "no sweep reaches its peak"
#: the documented shape a stage holds when no sweep reaches its peak: Pacejka's typical C (2012, sec. 4.3.2:
#: 1.65 longitudinal, 1.3 lateral) and E = 0 (the plain sine of the arctangent)
SHAPE_DEFAULTS = {"PCX1": 1.65, "PCY1": 1.3, "PEX1": 0.0, "PEY1": 0.0}


def identifiability(stage: Stage | str, pts: pd.DataFrame, sweeps: pd.DataFrame, *,
                    any_peak: bool = True, version: str = "6.1",
                    peak_runs: Sequence | None = None) -> tuple[dict[str, str], dict]:
    """Coefficients of ``stage`` the data cannot determine, with the reason.

    Parameters
    ----------
    stage : Stage or str
    pts : DataFrame
        the stage's points (columns as :class:`MFData.df`).
    sweeps : DataFrame
        the stage's sweeps (rows of :attr:`MFData.sweeps`).
    any_peak : bool
        some sweep of a pure-slip stage reaches its peak (else E is held).
    peak_runs : sequence, optional
        the runs whose sweep reaches its peak (Eq. 2-4); LMUV needs >= 2 speed levels among them.
        None: every sweep counts when ``any_peak``.

    Returns
    -------
    (dict name -> reason, facts)
    """
    st = _STAGE[stage] if isinstance(stage, str) else stage
    lv = condition_levels(sweeps)
    n_l, n_c, n_ac = len(lv["fz"]), len(lv["camber"]), len(lv["abs_camber"])
    if np.max(np.abs(sweeps["camber"].to_numpy(float)), initial=0.0) < 0.25 * _DEG:
        n_ac = min(n_ac, 1)
    n_p, n_v = len(lv["pressure"]), len(lv["speed"])
    nz_alpha = [a for a in lv["slip_angle"] if abs(a) >= 0.5 * _DEG]
    slip_col = "slip_angle" if st.name in ("Fy0", "Mz0", "Mx") else "slip_ratio"
    x = pts[slip_col].to_numpy(float)
    xmax = float(np.max(np.abs(x))) if x.size else 0.0
    pos, neg = int(np.sum(x > 0.5 * xmax)), int(np.sum(x < -0.5 * xmax))
    both = pos >= 3 and neg >= 3
    a_sign = {int(np.sign(a)) for a in nz_alpha}
    facts = {"points": int(len(pts)), "sweeps": int(len(sweeps)), "load_levels": n_l, "camber_levels": n_c,
             "abs_camber_levels": n_ac, "pressure_levels": n_p, "speed_levels": n_v,
             "slip_angle_levels": len(lv["slip_angle"]), "both_slip_signs": both, "points_pos": pos,
             "points_neg": neg, "any_peak": bool(any_peak), "levels": lv}
    why: dict[str, str] = {}

    def need(names, ok, reason):
        for nm in names:
            if nm in st.names and not ok:
                why.setdefault(nm, reason)

    loads2 = f"needs >= 2 load levels (data: {n_l})"
    loads3 = f"needs >= 3 load levels (data: {n_l})"
    cam = f"needs >= 2 camber levels (data: {n_c})"
    acam = f"needs >= 2 levels of |camber| (data: {n_ac})"
    acam3 = f"needs >= 3 levels of |camber|, or 2 with >= 2 loads (data: {n_ac} |camber|, {n_l} loads)"
    pr2 = f"needs >= 2 inflation pressures (data: {n_p})"
    pr3 = f"needs >= 3 inflation pressures (quadratic in dpi or inside the stiffness law's atan; data: {n_p})"
    bothr = (f"needs both slip signs reaching half the largest |{slip_col}| (data: {pos} points above, "
             f"{neg} below)")
    if version != "5.2":
        need(["PHY3"], False, "an MF 5.2 coefficient (6.1 shifts with camber through K_y_gamma, PKY6/PKY7)")
    else:
        need(["PHY3"], n_c >= 2, cam)
    if version == "5.2":
        for nm in st.names:
            if nm in _ONLY_61:
                why[nm] = "not an MF 5.2 coefficient (5.2 has no pressure terms and other camber forms)"
    # load
    need(["PDX2", "PKX2", "PEX2", "PHX2", "PVX2", "PDY2", "PKY2", "PEY2", "PHY2", "PVY2", "QBZ2", "QDZ2",
          "QDZ7", "QEZ2", "QHZ2", "REX2", "REY2", "RHY2", "RVY2", "QSY7"], n_l >= 2, loads2)
    need(["PEX3", "PKX3", "PKY4", "QBZ3", "QEZ3"], n_l >= 3, loads3)
    # camber
    need(["PDX3", "PDY3", "PKY3", "QBZ5", "QDZ3", "RBX3", "RBY4", "QSY5"], n_ac >= 2, acam)
    need(["PEY5", "PKY5", "QDZ4", "QSY6"], n_ac >= 3 or (n_ac >= 2 and n_l >= 2), acam3)
    need(["PKY6", "PVY3", "PEY4", "QBZ4", "QDZ8", "QDZ10", "QHZ3", "QEZ5", "RVY3", "SSZ3", "QSX2", "QSX7",
          "QSX14"], n_c >= 2, cam)
    # Mx's g|g| term beside its g terms (QSX2, QSX10): with one non-zero camber the two are one column, and the
    # pair ran away together (QSX10, QSX12 3e5 x the measured Mx, cancelling; cambers 0 and 3 deg)
    need(["QSX12"], n_ac >= 3, f"needs >= 3 levels of |camber| (g|g| is g itself at one non-zero camber; "
         f"data: {n_ac})")
    need(["PKY7", "PVY4", "QDZ9", "QDZ11", "QHZ4", "SSZ4", "QSX10", "QSX11"], n_c >= 2 and n_l >= 2,
         f"needs >= 2 camber levels and >= 2 load levels (data: {n_c} camber, {n_l} loads)")
    # with cambers of one sign only, a signed term and an |gamma| term on the same factor are one column
    cams = sweeps["camber"].to_numpy(float)
    one_sign = cams.size > 0 and (cams.min() > -0.25 * _DEG or cams.max() < 0.25 * _DEG)
    need(["QBZ4"], not one_sign or n_c < 2,
         "with cambers of one sign only QBZ4 (gamma) and QBZ5 (|gamma|) in B_t are the same column; QBZ5 is "
         "fitted (symmetric), QBZ4 held")
    # pressure
    need(["PPX1", "PPX3", "PPY1", "PPY3", "PPZ1", "PPZ2", "PPMX1", "QSY8"], n_p >= 2, pr2)
    need(["PPX2", "PPX4", "PPY4"], n_p >= 3, pr3)
    # PPY2 moves the load of the stiffness peak with pressure: K_y against load at two pressures shows it
    need(["PPY2"], n_p >= 3 or (n_p >= 2 and n_l >= 3),
         f"needs >= 3 pressures, or 2 with >= 3 load levels (data: {n_p} pressures, {n_l} loads)")
    need(["PPY5"], n_p >= 2 and n_c >= 2, f"needs >= 2 pressures and >= 2 camber levels (data: {n_p}, {n_c})")
    # speed
    need(["QSY3"], n_v >= 2, f"needs >= 2 speeds (data: {n_v})")
    need(["QSY4"], n_v >= 3, f"needs >= 3 speeds (data: {n_v})")
    # LMUV: friction decay with slip speed Vs (4.E7).  At one speed Vs grows with the slip alone, so the decay is
    # one more shape term beside the curvature E and the fall past the peak; the speed levels tell it apart.  It
    # scales the peak friction: sweeps that reach no peak do not measure it
    sp = ", ".join(f"{v:.3g}" for v in lv["speed"]) or "none given"
    need(["LMUV"], n_v >= 2, f"needs >= 2 speeds: at one speed friction decay with slip speed (4.E7) is a fall "
         f"with slip, which the curvature E and the post-peak shape carry (data: {n_v} speed level(s) [m/s]: {sp})")
    if peak_runs is None:
        n_vp = n_v if any_peak else 0
    else:
        n_vp = len(_levels(sweeps.loc[sweeps["run"].isin(list(peak_runs)), "speed"], 2.0 / 3.6))
    facts["speed_levels_through_peak"] = n_vp
    need(["LMUV"], n_vp >= 2, f"needs sweeps through the peak at >= 2 speeds: LMUV scales the peak friction, which "
         f"sweeps short of their peak do not measure (data: sweeps through the peak at {n_vp} speed level(s))")
    # shifts and asymmetry
    if st.name in ("Fx0", "Fy0", "Mz0"):
        need(["PHX1", "PVX1", "PHX2", "PVX2", "PEX4", "PHY1", "PVY1", "PHY2", "PVY2", "PEY3", "PEY4",
              "QHZ1", "QHZ2", "QDZ6", "QDZ7", "QEZ4", "QEZ5"], both, bothr)
    if st.name in ("Fy", "Fx"):
        need(["RVY1", "RVY2", "RVY3", "RVY5", "RVY6", "RHY1", "RHY2"], both,
             bothr.replace("needs", "needs drive and brake:"))
        # the shift SHxa = RHX1 moves G_xa along alpha; G_xa(alpha = 0) = 1 by its normalisation (4.E55), so
        # one slip-angle level cannot tell it from B_xa, two of one sign (TTC: -3, -6 deg) can (measured:
        # 0.0031 fitted for 0.0037 generated from -3/-6 deg sweeps at 1 % noise)
        need(["RHX1"], len(a_sign) >= 2 or len(nz_alpha) >= 2,
             f"needs combined sweeps at >= 2 non-zero slip angles or at both signs "
             f"(data: {sorted(round(a / _DEG, 1) for a in nz_alpha)} deg)")
        need(["RBY3", "RVY4"], len(nz_alpha) >= 2,
             f"needs combined sweeps at >= 2 non-zero slip angles (data: {len(nz_alpha)})")
    if st.name == "Mx":
        lat = bool((sweeps["kind"] != "longitudinal").any())
        need(["QSX3", "QSX13", "QSX8", "QSX9"], lat, "needs cornering sweeps")
        # the sine term QSX4 sin(QSX7 g + QSX8 atan(QSX9 Fy/Fz0)) is a shape along Fy: cornering sweeps at one
        # load and camber show it (QSX7 needs cambers, above); only its load factor cos(QSX5 atan((QSX6
        # Fz/Fz0)^2)) needs >= 3 loads.  Holding the whole term below 3 loads and 2 cambers left the bundled
        # TTC-style pair (2 loads) at 5.3 x its Mx noise floor (6.99 N*m); fitted, 1.76 N*m = the generating
        # tyre's own 1.755 N*m on those data
        need(["QSX4"], lat, "needs cornering sweeps")
        need(["QSX5", "QSX6"], lat and n_l >= 3, f"the load factor of the Mx sine term needs cornering sweeps "
             f"at >= 3 load levels (data: {n_l})")
    for nm in COMBINED_SHIFTS:  # the contract: combined slip only takes force away
        need([nm], False, "held at 0: a shift of the combined-slip weight makes G exceed 1 between zero slip and "
             "twice the shift (G is normalised at the shift, 4.E52, 4.E60), so combined slip would add force there")
    if st.name in ("Fx0", "Fy0") and not any_peak:
        # without a peak the shape is not measured: C and E trade against D along the rising branch (C at its
        # lower bound with mu 4.6 where the data reach 2.4); both are held at documented defaults
        for nm in st.names:
            if nm.startswith(("PEX", "PEY")):
                why.setdefault(nm, f"{NO_PEAK}: curvature E held at {SHAPE_DEFAULTS.get(nm, 0.0):g}")
            elif nm in SHAPE_DEFAULTS:
                why.setdefault(nm, f"{NO_PEAK}: shape factor C held at the typical {SHAPE_DEFAULTS[nm]:g} "
                               "(Pacejka 2012, sec. 4.3.2)")
    if not len(pts):
        for nm in st.names:
            why.setdefault(nm, f"no {'/'.join(st.sweeps)} sweeps with {st.channel}")
    return why, facts
