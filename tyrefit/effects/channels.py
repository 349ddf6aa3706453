"""Named physical effects of the aligning moment Mz and the longitudinal force Fx.

The lateral catalogue (:mod:`tyrefit.effects.catalogue`) extends PAC89's lateral force;
this one extends the models of the other two channels, so that a diagnosis can say what a
model misses in every channel a record carries (:mod:`tyrefit.diagnose.channels`):

* **Mz**, the aligning moment of cornering sweeps, in the pneumatic-trail form of Magic
  Formula 5.2/6.1 (Pacejka 2012, Sec. 4.3.2, Eq. 4.E31-4.E47) with the *measured* side
  force of each point (:func:`trail_moment`)::

      Mz = -t(alpha_t) Fy + Mzr(alpha),
      t = Dt cos(Ct atan(Bt alpha_t - Et (Bt alpha_t - atan(Bt alpha_t)))) cos(alpha),
      Mzr = Dr cos(atan(Br alpha_r)) cos(alpha),  alpha_t = alpha + SHt,
      alpha_r = alpha + SHf (centred where the side force crosses zero).

  The trail is a property of the contact patch (where along it the side force acts), so
  the laws that name physics act on t and on the residual torque Mzr: camber shifts the
  trail's curve and adds a camber moment, pressure shortens the trail, conicity and ply
  steer give a residual torque.  What Fy itself does with load, camber or pressure reaches
  Mz through the measured Fy and is Fy's diagnosis, not Mz's.  PAC89's aligning part (one
  sine curve for the whole moment) cannot follow this shape: a camber that acts on the
  trail leaves a misfit no PAC89 camber term removes (diagnose reports the PAC89 aligning
  fit beside it).
* **Fx**, the longitudinal force of drive/brake sweeps at zero slip angle: PAC89's
  longitudinal part (C = b0, D = b1 Fz^2 + b2 Fz, BCD = (b3 Fz^2 + b4 Fz) exp(-b5 Fz),
  E = b6 Fz^2 + b7 Fz + b8, Sh = b9 Fz + b10, Sv = 0).

The start models (:data:`START`) hold the shape factor, one peak coefficient, the
stiffness load law and a constant curvature; every other coefficient is at its neutral
value until an effect frees it.  Fx effects that PAC89 cannot hold (pressure; camber and a
vertical shift) have parameters of their own and name the Magic Formula 6.1 coefficients
that carry them (Pacejka 2012, Sec. 4.3.2).

Units: the trail model's are SI (slip and camber in rad, trail and the residual torque's
lengths in m, dfz = (Fz - Fz_ref) / Fz_ref with Fz_ref the record's middle load level,
dpi = (p - p_ref) / p_ref, Pacejka 2012 Eq. 4.E2); with Fz_ref = FNOMIN the lengths are
UNLOADED_RADIUS times MF's QDZ coefficients.  PAC89's are its own (Fz in kN, slip angle and
camber in degrees, slip ratio in percent).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .base import DataSummary, Effect, ModelInputs, Param, PhysicsCard

__all__ = ["CHANNELS", "START", "COEFFICIENT", "CHANNEL_EFFECTS", "channel_effect", "PAC89_COEFFICIENT",
           "TRAIL_COEFFICIENT", "trail_moment"]

#: the channels this catalogue covers: name -> (PAC89 part, unit of the channel)
CHANNELS: dict[str, tuple[str, str]] = {"mz": ("trail", "N*m"), "fx": ("longitudinal", "N")}

_PACEJKA = "Pacejka, Tire and Vehicle Dynamics, 3rd ed. (2012), Sec. 4.3.2"


def _coef(name: str, scale: float, unit: str, meaning: str, bounds=(-np.inf, np.inf),
          plausible=(-np.inf, np.inf)) -> Param:
    return Param(name, 0.0, bounds, plausible, unit, scale, meaning)


#: every PAC89 Mz/Fx coefficient a channel model can free: definition with neutral value 0
PAC89_COEFFICIENT: dict[str, Param] = {p.name: p for p in [
    # aligning (PAC89 units: Fz kN, alpha and gamma deg, Mz N*m)
    Param("c0", 2.3, (0.3, 5.0), (1.8, 2.8), "-", 1.0, "shape factor C of Mz"),
    _coef("c1", 1.0, "N*m/kN^2", "peak aligning moment, quadratic load term"),
    Param("c2", 3.0, (-np.inf, np.inf), (-np.inf, np.inf), "N*m/kN", 3.0, "peak aligning moment per kN"),
    _coef("c3", 0.5, "N*m/(deg*kN^2)", "aligning stiffness, quadratic load term"),
    Param("c4", 5.0, (-np.inf, np.inf), (-np.inf, np.inf), "N*m/(deg*kN)", 5.0, "aligning stiffness per kN"),
    _coef("c5", 0.1, "1/kN", "exponential fall of the aligning stiffness with load"),
    _coef("c6", 0.05, "1/deg", "aligning stiffness lost per degree of camber"),
    _coef("c7", 0.01, "1/kN^2", "curvature, quadratic load term"),
    _coef("c8", 0.1, "1/kN", "curvature per kN"),
    Param("c9", 0.0, (-20.0, 1.0), (-5.0, 1.0), "-", 0.5, "curvature E of Mz"),
    _coef("c10", 0.05, "1/deg", "curvature change per degree of camber"),
    _coef("c11", 0.1, "deg/deg", "slip shift per degree of camber"),
    _coef("c12", 0.05, "deg/kN", "slip shift per kN"),
    _coef("c13", 0.1, "deg", "slip shift"),
    _coef("c14", 0.05, "N*m/(kN^2 deg)", "camber moment, quadratic load term"),
    _coef("c15", 0.5, "N*m/(kN deg)", "camber moment per kN and degree"),
    _coef("c16", 0.5, "N*m/kN", "residual torque per kN"),
    _coef("c17", 1.0, "N*m", "residual torque"),
    # longitudinal (Fz kN, slip %, Fx N)
    Param("b0", 1.65, (0.3, 3.0), (1.3, 2.0), "-", 1.0, "shape factor C of Fx"),
    _coef("b1", 10.0, "1/kN", "friction, quadratic load term (1000 x d mu / d Fz)"),
    Param("b2", 1000.0, (50.0, 3500.0), (500.0, 3000.0), "-", 1000.0, "friction coefficient x 1000"),
    _coef("b3", 1.0, "N/(%*kN^2)", "longitudinal slip stiffness, quadratic load term"),
    Param("b4", 200.0, (1e-6, np.inf), (50.0, 5000.0), "N/(%*kN)", 200.0, "longitudinal slip stiffness per kN"),
    _coef("b5", 0.05, "1/kN", "exponential fall of the slip stiffness with load"),
    _coef("b6", 0.001, "1/kN^2", "curvature, quadratic load term"),
    _coef("b7", 0.05, "1/kN", "curvature per kN"),
    Param("b8", 0.0, (-30.0, 1.0), (-5.0, 1.0), "-", 0.5, "curvature E of Fx"),
    _coef("b9", 0.05, "%/kN", "slip shift per kN"),
    _coef("b10", 0.1, "%", "slip shift"),
]}


def _q(name: str, scale: float, unit: str, meaning: str, bounds=(-np.inf, np.inf), neutral: float = 0.0) -> Param:
    return Param(name, neutral, bounds, bounds, unit, scale, meaning)


#: every coefficient of the trail model of Mz (:func:`trail_moment`), SI; neutral values switch a term off
TRAIL_COEFFICIENT: dict[str, Param] = {p.name: p for p in [
    # the start model
    Param("mz_Ct", 1.2, (0.3, 3.0), (0.8, 1.6), "-", 1.0, "shape factor Ct of the trail (QCZ1, Eq. 4.E41)"),
    Param("mz_Dt", 0.03, (-0.1, 0.5), (0.005, 0.15), "m", 0.03,
          "peak pneumatic trail at the middle load (UNLOADED_RADIUS x QDZ1, Eq. 4.E42)"),
    Param("mz_Bt", 10.0, (0.3, 150.0), (3.0, 40.0), "1/rad", 10.0, "stiffness factor Bt of the trail (QBZ1, Eq. 4.E40)"),
    _q("mz_Bt_fz", 2.0, "1/rad", "Bt per dfz (QBZ2, Eq. 4.E40)", (-100.0, 100.0)),
    Param("mz_Et", 0.0, (-30.0, 1.0), (-10.0, 1.0), "-", 1.0, "curvature Et of the trail (QEZ1, Eq. 4.E44)"),
    # freed by effects
    _q("mz_Dt_fz", 0.005, "m", "peak trail per dfz beyond proportion to load (UNLOADED_RADIUS x QDZ2, Eq. 4.E42)",
       (-0.3, 0.3)),
    _q("mz_Bt_fz2", 2.0, "1/rad", "Bt per dfz^2 (QBZ3, Eq. 4.E40)", (-100.0, 100.0)),
    _q("mz_Et_fz", 0.5, "-", "Et per dfz (QEZ2, Eq. 4.E44)", (-30.0, 30.0)),
    _q("mz_Et_fz2", 0.5, "-", "Et per dfz^2 (QEZ3, Eq. 4.E44)", (-30.0, 30.0)),
    _q("mz_Et_asym", 0.2, "-", "Et's change between slip signs, x (2/pi) atan(Bt Ct alpha_t) (QEZ4, Eq. 4.E44)",
       (-0.95, 0.95)),
    _q("mz_SHt", 0.003, "rad", "trail's slip shift (QHZ1, Eq. 4.E35)", (-0.1, 0.1)),
    _q("mz_SHt_fz", 0.003, "rad", "trail's slip shift per dfz (QHZ2, Eq. 4.E35)", (-0.1, 0.1)),
    _q("mz_SHt_camber", 0.2, "rad/rad", "trail's slip shift per camber (QHZ3, Eq. 4.E35)", (-3.0, 3.0)),
    _q("mz_SHt_camber_fz", 0.2, "rad/rad", "trail's camber shift per dfz (QHZ4, Eq. 4.E35)", (-3.0, 3.0)),
    _q("mz_Bt_camber", 1.0, "1/rad", "relative change of Bt per camber (MF 5.2 QBZ4, Eq. 4.E40)", (-30.0, 30.0)),
    _q("mz_Bt_abs_camber", 1.0, "1/rad", "relative change of Bt per |camber| (QBZ5, Eq. 4.E40)", (-30.0, 30.0)),
    _q("mz_Dt_abs_camber", 1.0, "1/rad", "relative change of the peak trail per |camber| (QDZ3, Eq. 4.E43)",
       (-30.0, 30.0)),
    _q("mz_Dt_camber2", 5.0, "1/rad^2", "relative change of the peak trail per camber^2 (QDZ4, Eq. 4.E43)",
       (-300.0, 300.0)),
    _q("mz_Et_camber", 2.0, "1/rad", "Et's slip-sign change per camber (QEZ5, Eq. 4.E44)", (-50.0, 50.0)),
    _q("mz_Dr", 0.001, "m", "residual torque / Fz (UNLOADED_RADIUS x QDZ6, Eq. 4.E47)", (-0.05, 0.05)),
    _q("mz_Dr_fz", 0.001, "m", "residual torque / Fz per dfz (UNLOADED_RADIUS x QDZ7, Eq. 4.E47)", (-0.05, 0.05)),
    _q("mz_Dr_camber", 0.05, "m/rad", "camber moment / Fz per camber (UNLOADED_RADIUS x QDZ8, Eq. 4.E47)",
       (-1.0, 1.0)),
    _q("mz_Dr_camber_fz", 0.05, "m/rad", "camber moment / Fz per camber and dfz (UNLOADED_RADIUS x QDZ9, Eq. 4.E47)",
       (-1.0, 1.0)),
    Param("mz_Br", 20.0, (0.5, 1000.0), (2.0, 400.0), "1/rad", 20.0,
          "how fast the residual torque fades with slip (QBZ9 + QBZ10 By Cy, Eq. 4.E45)"),
]}

#: start model of each channel (``mz_Bt_fz`` / ``b5``, the stiffness's load law, are held at 0 with one load level)
START: dict[str, tuple[str, ...]] = {"mz": ("mz_Ct", "mz_Dt", "mz_Bt", "mz_Bt_fz", "mz_Et"),
                                     "fx": ("b0", "b2", "b4", "b5", "b8")}
#: the coefficient definitions of each channel's model
COEFFICIENT: dict[str, dict[str, Param]] = {"mz": TRAIL_COEFFICIENT,
                                            "fx": {k: v for k, v in PAC89_COEFFICIENT.items() if k[0] == "b"}}


def trail_moment(coef: Mapping, x: ModelInputs) -> np.ndarray:
    """The aligning moment Mz [N*m, ISO-W] of the trail model at the inputs ``x``.

    Magic Formula 5.2/6.1's pure-slip aligning moment (Pacejka 2012, Eq. 4.E31-4.E47, without
    the scaling factors) with the measured side force ``x.side_force`` in place of the model's
    Fy, and the slip where it crosses zero (``x.side_force_zero``, 0 if None) in place of -SHf::

        Mz = -t Fy + Mzr                                                   (4.E31, 4.E32)
        t = Dt cos(Ct atan(Bt at - Et (Bt at - atan(Bt at)))) cos(alpha)   (4.E33)
        at = alpha + SHt,  SHt = SHt0 + SHt1 dfz + (SHt2 + SHt3 dfz) gamma   (4.E34, 4.E35)
        Bt = (Bt0 + Bt1 dfz + Bt2 dfz^2)(1 + Btg gamma + Bta |gamma|)     (4.E40; QBZ4 of MF 5.2)
        Dt = Fz / Fz_ref (Dt0 + Dt1 dfz)(1 + Dta |gamma| + Dtg2 gamma^2)  (4.E42, 4.E43)
        Et = min(1, (Et0 + Et1 dfz + Et2 dfz^2)(1 + (Eta + Etg gamma)(2/pi) atan(Bt Ct at)))  (4.E44)
        Mzr = Fz (Dr0 + Dr1 dfz + (Drg + Drg1 dfz) gamma) cos(atan(Br ar)) cos(alpha)  (4.E36, 4.E47)
        ar = alpha - alpha_0, alpha_0 where the side force crosses zero (4.E37, 4.E38: SHf = -alpha_0)

    alpha* = alpha, as TNO's MF-Tyre and MFeval (the tan form of Eq. 4.E3 is not used).
    ``coef`` maps the :data:`TRAIL_COEFFICIENT` names to floats or per-point arrays (effects such
    as pressure scale them point by point); slip angle and camber in rad.
    """
    fy = x.side_force
    if fy is None:
        raise ValueError("the trail model of Mz needs the measured side force of every point (inputs.side_force)")
    fz = np.asarray(x.fz, float)
    a = np.asarray(x.slip_angle, float)
    g = np.asarray(x.camber, float)
    fz_ref = x.fz_ref or float(np.median(fz))
    dfz = (fz - fz_ref) / fz_ref
    c = coef
    at = a + c["mz_SHt"] + c["mz_SHt_fz"] * dfz + (c["mz_SHt_camber"] + c["mz_SHt_camber_fz"] * dfz) * g
    bt = ((c["mz_Bt"] + c["mz_Bt_fz"] * dfz + c["mz_Bt_fz2"] * dfz * dfz)
          * (1.0 + c["mz_Bt_camber"] * g + c["mz_Bt_abs_camber"] * np.abs(g)))
    ct = c["mz_Ct"]
    dt = (fz / fz_ref * (c["mz_Dt"] + c["mz_Dt_fz"] * dfz)
          * (1.0 + c["mz_Dt_abs_camber"] * np.abs(g) + c["mz_Dt_camber2"] * g * g))
    bta = bt * at
    et = np.minimum((c["mz_Et"] + c["mz_Et_fz"] * dfz + c["mz_Et_fz2"] * dfz * dfz)
                    * (1.0 + (c["mz_Et_asym"] + c["mz_Et_camber"] * g) * (2.0 / np.pi) * np.arctan(bta * ct)), 1.0)
    cos_a = np.cos(a)
    t = dt * np.cos(ct * np.arctan(bta - et * (bta - np.arctan(bta)))) * cos_a
    dr = fz * (c["mz_Dr"] + c["mz_Dr_fz"] * dfz + (c["mz_Dr_camber"] + c["mz_Dr_camber_fz"] * dfz) * g)
    br = c["mz_Br"]
    ar = a if x.side_force_zero is None else a - np.asarray(x.side_force_zero, float)  # (4.E37): alpha + SHf
    mzr = dr * np.cos(np.arctan(br * ar)) * cos_a
    return -t * np.asarray(fy, float) + mzr


# -- testability -------------------------------------------------------------------------
def _loads(n: int):
    def check(s: DataSummary) -> str | None:
        k = len(s.fz_levels)
        return None if k >= n else f"needs >= {n} load levels (have {k})"
    return check


def _cambers(s: DataSummary) -> str | None:
    k = len(s.camber_levels)
    return None if k >= 2 else f"needs >= 2 camber levels (have {k})"


def _camber_levels(n: int):
    def check(s: DataSummary) -> str | None:
        k = len(s.camber_levels)
        return None if k >= n else f"needs >= {n} camber levels (have {k})"
    return check


def _camber_both_sides(s: DataSummary) -> str | None:
    c = s.camber_levels
    return None if c and min(c) < 0 < max(c) else "needs camber levels on both sides of zero"


def _pressures(s: DataSummary) -> str | None:
    k = len(s.pressure_levels)
    return None if k >= 2 else f"needs >= 2 pressure levels (have {k})"


def _both_sides(s: DataSummary) -> str | None:
    return None if s.slip_min < 0 < s.slip_max else "needs sweeps to both sides of zero slip"


def _dpi(x: ModelInputs) -> np.ndarray:
    if x.pressure is None or not x.pressure_ref:
        raise ValueError("a pressure effect needs the pressure of every point and a reference pressure")
    return (np.asarray(x.pressure, float) - x.pressure_ref) / x.pressure_ref


# -- modifiers of the PAC89 coefficients (point by point) ---------------------------------------
def _apply_mz_pressure(coef: dict, v: Mapping, x: ModelInputs) -> None:
    # Pacejka 2012 Eq. 4.E42: Dt0 (1 - PPZ1 dpi); here Dt (1 + mz_p_trail dpi), so mz_p_trail = -PPZ1
    kd = 1.0 + v["mz_p_trail"] * _dpi(x)
    for k in ("mz_Dt", "mz_Dt_fz"):
        coef[k] = coef[k] * kd


def _apply_fx_pressure(coef: dict, v: Mapping, x: ModelInputs) -> None:
    dpi = _dpi(x)
    kd = 1.0 + v["fx_p_friction"] * dpi        # Pacejka 2012 Eq. 4.E13: mu_x (1 + PPX3 dpi + PPX4 dpi^2)
    kk = 1.0 + v["fx_p_stiffness"] * dpi       # Eq. 4.E15: K_xk (1 + PPX1 dpi + PPX2 dpi^2)
    for k in ("b1", "b2"):
        coef[k] = coef[k] * kd
    for k in ("b3", "b4"):
        coef[k] = coef[k] * kk


def _apply_fx_camber(coef: dict, v: Mapping, x: ModelInputs) -> None:
    g = np.asarray(x.camber, float)
    kd = 1.0 - v["fx_camber_friction"] * g * g  # Pacejka 2012 Eq. 4.E13: mu_x (1 - PDX3 gamma^2)
    for k in ("b1", "b2"):
        coef[k] = coef[k] * kd


def _apply_fx_rolling(coef: dict, v: Mapping, x: ModelInputs) -> None:
    # a vertical shift of the Fx curve, Sv = Fz (PVX1 + PVX2 dfz) (Pacejka 2012 Eq. 4.E18); PAC89 has Sv = 0
    coef["sv"] = coef.get("sv", 0.0) + v["fx_sv"] * np.asarray(x.fz, float)


def _apply_fx_asymmetry(coef: dict, v: Mapping, x: ModelInputs) -> None:
    # Pacejka 2012 Eq. 4.E14: Ex (1 - PEX4 sgn(kappa_x)): the curve falls differently in drive and in braking
    k = 1.0 - v["fx_asym"] * np.sign(np.asarray(x.slip_angle, float))
    for n in ("b6", "b7", "b8"):
        coef[n] = coef[n] * k


_PRESSURE_TEST = ("sweeps at >= 2 inflation pressures (hot-corrected), the same loads at each")
_CAMBER_TEST = "sweeps at >= 2 camber angles (0 and the car's static camber at least), the same loads at each"


def _card(what, size, test, vehicle, *sources) -> PhysicsCard:
    return PhysicsCard(what, size, test, vehicle, tuple(sources) or (_PACEJKA,))


def _effects() -> list[Effect]:
    P, T = PAC89_COEFFICIENT, TRAIL_COEFFICIENT
    out = [
        # ---- aligning moment (trail model, :func:`trail_moment`) ------------------------------------
        Effect("mz_peak_load", "mz_peak_load", "pneumatic trail not in proportion to load", (T["mz_Dt_fz"],),
               ">= 2 load levels", _loads(2),
               _card("The pneumatic trail is where along the contact patch the side force acts, about a sixth "
                     "of the patch length at small slip.  The patch lengthens with load, but less than in "
                     "proportion (its length goes roughly with the square root of the deflection), and its "
                     "pressure distribution changes shape: the trail per unit load changes with load.",
                     "the peak trail per kN changes by 5-30 % over a tyre's load range",
                     "cornering sweeps at >= 3 loads with Mz and Fy at small slip (+-3 deg)",
                     "steering torque and how it builds with load (the driver's feel on a loaded axle)",
                     _PACEJKA + ", Eq. 4.E42 (QDZ2)"),
               signature="none", pac89_note="MF 5.2/6.1 QDZ2; PAC89's aligning part carries it only approximately "
                                            "(c1)"),
        Effect("mz_stiffness_load", "mz_stiffness_load", "trail's fall with slip changing with load (quadratic)",
               (T["mz_Bt_fz2"],), ">= 3 load levels", _loads(3),
               _card("How fast the trail falls as the patch starts to slide (Bt) depends on how much of the "
                     "patch is still adhering, which changes with load; the start model's straight law in "
                     "load is not enough when the slide starts much earlier at high load.",
                     "Bt changes by 10-40 % over a tyre's load range, not on a straight line",
                     "small- and medium-slip (+-6 deg) sweeps at >= 3 loads",
                     "how early the steering goes light on a loaded axle", _PACEJKA + ", Eq. 4.E40 (QBZ3)"),
               signature="none", pac89_note="MF 5.2/6.1 QBZ3; PAC89 has no trail"),
        Effect("mz_curvature_load", "mz_curvature_load", "trail curvature changing with load", (T["mz_Et_fz"],),
               ">= 2 load levels", _loads(2),
               _card("How sharply the trail collapses after the Mz peak (the patch sliding from its rear "
                     "edge forward) changes with load.",
                     "Et moves by 0.5-3 over the load range",
                     "sweeps past the Mz peak (to 8-10 deg) at >= 2 loads",
                     "how suddenly the steering goes light at the limit", _PACEJKA + ", Eq. 4.E44 (QEZ2)"),
               signature="none", pac89_note="MF 5.2/6.1 QEZ2; PAC89 has no trail"),
        Effect("mz_curvature_load_bent", "mz_curvature_load", "trail curvature bending with load",
               (T["mz_Et_fz"], T["mz_Et_fz2"]), ">= 3 load levels", _loads(3),
               _card("The trail's collapse after the Mz peak changes with load along a curve, not a line: at "
                     "light load the patch is short and slides all at once, at heavy load its rear slides "
                     "long before its front.",
                     "Et's quadratic load term, 0.5-2 over a tyre's load range",
                     "sweeps past the Mz peak (to 8-10 deg) at >= 3 loads",
                     "how suddenly the steering goes light at the limit", _PACEJKA + ", Eq. 4.E44 (QEZ3)"),
               signature="none", pac89_note="MF 5.2/6.1 QEZ3; PAC89 has no trail", refinement=True),
        Effect("mz_camber", "mz_camber", "camber shift of the trail and camber moment",
               (T["mz_SHt_camber"], T["mz_Dr_camber"], T["mz_Br"]), ">= 2 camber levels", _cambers,
               _card("A cambered tyre rolls on a cone: the patch's centre line bends into an arc, so the "
                     "trail's curve shifts along the slip axis (the moment crosses zero at another slip "
                     "angle) and the twist of the patch adds a moment of its own at small slip (the camber "
                     "moment).  The camber thrust itself acts near the patch centre, not at the trail.",
                     "the Mz zero crossing moves 0.2-1 deg per degree of camber; a few N*m per degree",
                     _CAMBER_TEST,
                     "steering torque of a cambered car, pull on a crowned road",
                     _PACEJKA + ", Eq. 4.E35 (QHZ3), Eq. 4.E47 (QDZ8)"),
               signature="none",
               pac89_note="MF 5.2/6.1 QHZ3, QDZ8; PAC89's c11, c15 take part of it"),
        Effect("mz_camber_shape", "mz_camber", "camber on the trail's length and fall with slip",
               (T["mz_SHt_camber"], T["mz_Dr_camber"], T["mz_Br"], T["mz_Bt_abs_camber"], T["mz_Dt_abs_camber"],
                T["mz_Et_camber"]),
               ">= 2 camber levels", _cambers,
               _card("Camber shortens the patch on one shoulder and lengthens it on the other: the trail's "
                     "length, how fast it falls with slip and how differently it falls to either side all "
                     "change with camber.",
                     "5-25 % of the peak trail at 4 deg",
                     _CAMBER_TEST, "steering torque of a cambered car at the limit",
                     _PACEJKA + ", Eq. 4.E40 (QBZ5), Eq. 4.E43 (QDZ3), Eq. 4.E44 (QEZ5)"),
               signature="none", pac89_note="MF 5.2/6.1 QBZ5, QDZ3, QEZ5; PAC89's c6, c10 take part of it",
               refinement=True),
        Effect("mz_camber_curved", "mz_camber", "peak trail bending with camber",
               (T["mz_SHt_camber"], T["mz_Dr_camber"], T["mz_Br"], T["mz_Bt_abs_camber"], T["mz_Dt_abs_camber"],
                T["mz_Et_camber"], T["mz_Dt_camber2"]),
               ">= 3 camber levels", _camber_levels(3),
               _card("The trail's length changes with camber along a curve, not a line, once one shoulder "
                     "starts to carry most of the load.",
                     "a few % of the peak trail at 4 deg", _CAMBER_TEST.replace(">= 2", ">= 3"),
                     "steering torque at large camber (motorcycles, race cars)", _PACEJKA + ", Eq. 4.E43 (QDZ4)"),
               signature="none", pac89_note="MF 5.2/6.1 QDZ4; PAC89 has no trail", refinement=True),
        Effect("mz_camber_sides", "mz_camber", "trail's fall with slip differing between camber sides",
               (T["mz_SHt_camber"], T["mz_Dr_camber"], T["mz_Br"], T["mz_Bt_abs_camber"], T["mz_Dt_abs_camber"],
                T["mz_Et_camber"], T["mz_Bt_camber"]),
               "camber levels on both sides of zero", _camber_both_sides,
               _card("A tyre built asymmetrically (an inner and an outer shoulder) loses trail differently "
                     "when it leans in than when it leans out.",
                     "5-15 % of Bt between +-4 deg", "sweeps at cambers on both sides of zero, the same loads at each",
                     "steering torque of the inner against the outer wheel", _PACEJKA + ", Eq. 4.E40 (MF 5.2 QBZ4)"),
               signature="none", pac89_note="MF 5.2 QBZ4; PAC89 has no trail", refinement=True),
        Effect("mz_camber_load", "mz_camber", "camber shift and moment changing with load",
               (T["mz_SHt_camber"], T["mz_Dr_camber"], T["mz_Br"], T["mz_SHt_camber_fz"], T["mz_Dr_camber_fz"]),
               ">= 2 camber and 2 load levels", lambda s: _cambers(s) or _loads(2)(s),
               _card("The camber moment grows with the patch, faster than in proportion to load, and the "
                     "trail's camber shift changes with the patch length.",
                     "the load terms of the camber moment and shift", _CAMBER_TEST + ", at >= 2 loads",
                     "steering torque of a cambered car", _PACEJKA + ", Eq. 4.E35 (QHZ4), Eq. 4.E47 (QDZ9)"),
               signature="none", pac89_note="MF 5.2/6.1 QHZ4, QDZ9; PAC89's c14 takes part of it", refinement=True),
        Effect("mz_offsets", "mz_offsets", "residual torque and trail shift (conicity, ply steer)",
               (T["mz_SHt"], T["mz_Dr"], T["mz_Br"]), "cornering sweeps through zero slip", lambda s: None,
               _card("Conicity and ply steer give an aligning moment at zero slip angle (the residual "
                     "torque) and shift the trail's curve: the moment crosses zero off the origin, by more "
                     "than the side force's own shift explains.",
                     "1-5 N*m residual torque on a car tyre",
                     "sweeps through zero slip in both directions (to tell rig hysteresis from the tyre)",
                     "steering pull and the torque a straight-running car needs",
                     _PACEJKA + ", Eq. 4.E35 (QHZ1), Eq. 4.E47 (QDZ6)"),
               signature="none", pac89_note="MF 5.2/6.1 QHZ1, QDZ6; PAC89's c13, c17"),
        Effect("mz_offsets_load", "mz_offsets", "residual torque and trail shift changing with load",
               (T["mz_SHt"], T["mz_Dr"], T["mz_Br"], T["mz_SHt_fz"], T["mz_Dr_fz"]), ">= 2 load levels", _loads(2),
               _card("The residual torque of conicity and ply steer grows with load.",
                     "1-5 N*m per kN", "sweeps through zero slip at >= 2 loads",
                     "steering pull", _PACEJKA + ", Eq. 4.E35 (QHZ2), Eq. 4.E47 (QDZ7)"),
               signature="none", pac89_note="MF 5.2/6.1 QHZ2, QDZ7; PAC89's c12, c16", refinement=True),
        Effect("mz_pressure", "mz_pressure", "inflation pressure on the pneumatic trail",
               (Param("mz_p_trail", 0.0, (-3.0, 3.0), (-1.5, 0.5), "1/(dp/p0)", 0.3,
                      "relative change of the peak trail per relative pressure change (-PPZ1, Eq. 4.E42)"),),
               ">= 2 pressure levels", _pressures,
               _card("A harder tyre has a shorter contact patch, so the side force acts nearer the patch "
                     "centre: the pneumatic trail falls as the pressure rises.  (What pressure does to the "
                     "side force itself reaches Mz through Fy and is Fy's diagnosis.)",
                     "-5 to -25 % of the peak trail for +20 % pressure",
                     _PRESSURE_TEST, "steering torque after a pressure change",
                     _PACEJKA + ", Eq. 4.E42 (PPZ1)"),
               signature="none", apply=_apply_mz_pressure,
               pac89_note="PAC89 has no pressure terms: fit MF 6.1 (model=\"mf61\"), PPZ1"),
        Effect("mz_asymmetry", "mz_asymmetry", "trail curvature differing between slip signs", (T["mz_Et_asym"],),
               "cornering sweeps to both sides past the Mz peak", _both_sides,
               _card("The trail collapses differently when the tyre slips to one side than to the other "
                     "(tread pattern, ply construction): the Mz curve falls after its peak more sharply on "
                     "one side.  This is a change of shape, not a shift of the curve.",
                     "Et differs by 10-50 % between the sides",
                     "sweeps to both sides, well past the Mz peak (8-12 deg)",
                     "steering torque at the limit differing between left and right turns",
                     _PACEJKA + ", Eq. 4.E44 (QEZ4)"),
               signature="none",
               pac89_note="PAC89 has one curvature for both sides: fit MF 5.2/6.1 (model=\"mf61\"), QEZ4"),
        # ---- longitudinal force ---------------------------------------------------------------
        Effect("fx_load_friction", "fx_load_friction", "longitudinal friction falling with load", (P["b1"],),
               ">= 2 load levels", _loads(2),
               _card("Rubber friction falls as the contact pressure rises, so the braking and driving "
                     "friction coefficient falls with load.",
                     "mu_x falls 5-15 % from half to full rated load",
                     "drive/brake sweeps past the peak at >= 2 loads",
                     "braking distance with load transfer, the rear axle's share of braking",
                     _PACEJKA + ", Eq. 4.E13 (PDX2)"),
               signature="none", pac89=("b1",)),
        Effect("fx_stiffness_load", "fx_stiffness_load", "slip stiffness load law with a quadratic term",
               (P["b3"],), ">= 3 load levels", _loads(3),
               _card("The longitudinal slip stiffness grows with the patch length, less than in proportion "
                     "to load at high loads.",
                     "10-30 % off a straight line over the load range",
                     "small-slip (+-3 %) drive/brake sweeps at >= 3 loads",
                     "ABS and traction-control slip targets, wheel-speed dynamics",
                     _PACEJKA + ", Eq. 4.E15 (PKX1-3)"),
               signature="none", pac89=("b3",)),
        Effect("fx_curvature_load", "fx_curvature_load", "longitudinal curvature changing with load",
               (P["b7"],), ">= 2 load levels", _loads(2),
               _card("How the force levels off or falls after the peak (the patch sliding from its rear) "
                     "changes with load.",
                     "E of Fx moves by 0.2-1 over the load range", "sweeps past the peak (to 20 % slip) at >= 2 loads",
                     "locked-wheel against peak braking force", _PACEJKA + ", Eq. 4.E14 (PEX2)"),
               signature="none", pac89=("b7",)),
        Effect("fx_camber", "fx_camber", "longitudinal friction lost with camber",
               (Param("fx_camber_friction", 0.0, (-50.0, 200.0), (0.0, 30.0), "1/rad^2", 5.0,
                      "relative friction lost per camber^2 (MF PDX3)"),),
               ">= 2 camber levels", _cambers,
               _card("A cambered tyre carries its load on one shoulder: a shorter, narrower effective patch "
                     "at higher pressure, so less longitudinal grip.",
                     "a few % of mu_x at 4 deg", _CAMBER_TEST.replace("the same loads", "drive/brake, the same loads"),
                     "braking and traction of a cambered axle", _PACEJKA + ", Eq. 4.E13 (PDX3)"),
               signature="none", apply=_apply_fx_camber,
               pac89_note="PAC89's longitudinal part has no camber: fit MF 6.1 (model=\"mf61\"), PDX3"),
        Effect("fx_offsets", "fx_offsets", "slip shift of the Fx curve", (P["b10"],),
               "drive/brake sweeps through zero slip", lambda s: None,
               _card("The Fx curve crosses zero off zero slip: the effective rolling radius the rig used "
                     "for the slip ratio differs from the free-rolling one, or the tyre has a tread offset.",
                     "0.1-0.5 % slip", "sweeps through zero slip in both directions, with the free-rolling "
                     "radius measured at each load",
                     "wheel-speed based slip estimates", _PACEJKA + ", Eq. 4.E17 (PHX1)"),
               signature="none", pac89=("b10",)),
        Effect("fx_offsets_load", "fx_offsets", "slip shift changing with load", (P["b9"], P["b10"]),
               ">= 2 load levels", _loads(2),
               _card("The rolling radius, and with it the zero-force slip ratio, changes with load.",
                     "0.1 % slip per kN", "sweeps through zero slip at >= 2 loads",
                     "wheel-speed based slip estimates", _PACEJKA + ", Eq. 4.E17 (PHX2)"),
               signature="none", pac89=("b9", "b10"), refinement=True),
        Effect("fx_rolling", "fx_rolling", "force offset at zero slip (rolling resistance)",
               (Param("fx_sv", 0.0, (-0.1, 0.1), (-0.03, 0.01), "N/N", 0.01,
                      "vertical shift of Fx per unit load"),),
               "drive/brake sweeps through zero slip", lambda s: None,
               _card("A free-rolling tyre already pushes back: rolling resistance (hysteresis in the "
                     "deforming rubber) shifts the whole Fx curve down by about a percent of the load.",
                     "0.5-1.5 % of Fz", "sweeps through zero slip, and a coast-down or drum test",
                     "energy use, coast-down, the traction needed to hold speed",
                     _PACEJKA + ", Eq. 4.E18 (PVX1)"),
               signature="none", apply=_apply_fx_rolling,
               pac89_note="PAC89's longitudinal Sv is 0: fit MF 6.1 (model=\"mf61\"), PVX1, PVX2"),
        Effect("fx_asymmetry", "fx_asymmetry", "longitudinal curvature differing between drive and braking",
               (Param("fx_asym", 0.0, (-0.95, 0.95), (-0.8, 0.8), "-", 0.2,
                      "relative change of the curvature E of Fx in drive against braking (MF PEX4)"),),
               "drive/brake sweeps to both sides past the peak", _both_sides,
               _card("Driving and braking load the tread differently (the patch's sliding starts at its "
                     "rear in both, but the tread elements are bent the other way): past the peak the force "
                     "levels off differently in drive and in braking.",
                     "E of Fx differs by 20-100 % between drive and braking",
                     "drive/brake sweeps to +-20 % slip", "locked-wheel braking against wheel spin",
                     _PACEJKA + ", Eq. 4.E14 (PEX4)"),
               signature="none", apply=_apply_fx_asymmetry,
               pac89_note="PAC89 has one curvature for drive and braking: fit MF 6.1 (model=\"mf61\"), PEX4"),
        Effect("fx_pressure", "fx_pressure", "inflation pressure on longitudinal grip and stiffness",
               (Param("fx_p_friction", 0.0, (-3.0, 3.0), (-1.0, 1.0), "1/(dp/p0)", 0.3,
                      "relative change of mu_x per relative pressure change (PPX3)"),
                Param("fx_p_stiffness", 0.0, (-3.0, 3.0), (-1.0, 1.5), "1/(dp/p0)", 0.3,
                      "relative change of the slip stiffness per relative pressure change (PPX1)")),
               ">= 2 pressure levels", _pressures,
               _card("Pressure changes the patch: a harder tyre has a shorter patch at higher contact "
                     "pressure, which changes the slip stiffness and lowers the friction.",
                     "5-20 % of the slip stiffness for +20 % pressure", _PRESSURE_TEST.replace("sweeps", "drive/brake sweeps"),
                     "braking distance and ABS tuning after a pressure change",
                     _PACEJKA + ", Eq. 4.E13 (PPX3), Eq. 4.E15 (PPX1)"),
               signature="none", apply=_apply_fx_pressure,
               pac89_note="PAC89 has no pressure terms: fit MF 6.1 (model=\"mf61\"), PPX1-PPX4"),
    ]
    return out


#: channel -> effect id -> Effect
CHANNEL_EFFECTS: dict[str, dict[str, Effect]] = {"mz": {}, "fx": {}}
for _e in _effects():
    CHANNEL_EFFECTS[_e.id[:2]][_e.id] = _e


def channel_effect(channel: str, effect_id: str) -> Effect:
    """The catalogue entry ``effect_id`` of ``channel`` ('mz' or 'fx')."""
    try:
        return CHANNEL_EFFECTS[channel][effect_id]
    except KeyError:
        have = ", ".join(CHANNEL_EFFECTS.get(channel, {})) or "none"
        raise KeyError(f"{effect_id!r} is not a {channel} effect; known: {have}") from None
