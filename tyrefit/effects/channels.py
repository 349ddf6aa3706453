"""Named physical effects of the aligning moment Mz and the longitudinal force Fx.

The lateral catalogue (:mod:`tyrefit.effects.catalogue`) extends PAC89's lateral force;
this one extends its other two parts, so that a diagnosis can say what a model misses in
every channel a record carries (:mod:`tyrefit.diagnose.channels`):

* **Mz**, the aligning moment of cornering sweeps: PAC89's aligning part
  (C = c0, D = c1 Fz^2 + c2 Fz, BCD = (c3 Fz^2 + c4 Fz)(1 - c6 |gamma|) exp(-c5 Fz),
  E = (c7 Fz^2 + c8 Fz + c9)(1 - c10 |gamma|), Sh = c11 gamma + c12 Fz + c13,
  Sv = (c14 Fz^2 + c15 Fz) gamma + c16 Fz + c17; Bakker, Nyborg & Pacejka 1989).
* **Fx**, the longitudinal force of drive/brake sweeps at zero slip angle: PAC89's
  longitudinal part (C = b0, D = b1 Fz^2 + b2 Fz, BCD = (b3 Fz^2 + b4 Fz) exp(-b5 Fz),
  E = b6 Fz^2 + b7 Fz + b8, Sh = b9 Fz + b10, Sv = 0).

The start models (:data:`START`) hold the shape factor, one peak coefficient, the
stiffness load law and a constant curvature, as the lateral start model does; every
other coefficient is 0 until an effect frees it.  Effects that PAC89 cannot hold
(pressure; camber and a vertical shift in Fx) have parameters of their own and name the
Magic Formula 6.1 coefficients that carry them (Pacejka 2012, Sec. 4.3.2).

Units: PAC89's (Fz in kN, slip angle and camber in degrees, slip ratio in percent); the
effects' own parameters act on SI inputs (camber in rad, pressure as
dpi = (p - p_ref) / p_ref, Pacejka 2012 Eq. 4.E2b).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .base import DataSummary, Effect, ModelInputs, Param, PhysicsCard

__all__ = ["CHANNELS", "START", "CHANNEL_EFFECTS", "channel_effect", "PAC89_COEFFICIENT"]

#: the channels this catalogue covers: name -> (PAC89 part, unit of the channel)
CHANNELS: dict[str, tuple[str, str]] = {"mz": ("aligning", "N*m"), "fx": ("longitudinal", "N")}

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

#: start model of each channel (``c5`` / ``b5`` are held at 0 with one load level)
START: dict[str, tuple[str, ...]] = {"mz": ("c0", "c2", "c4", "c5", "c9"), "fx": ("b0", "b2", "b4", "b5", "b8")}


# -- testability -------------------------------------------------------------------------
def _loads(n: int):
    def check(s: DataSummary) -> str | None:
        k = len(s.fz_levels)
        return None if k >= n else f"needs >= {n} load levels (have {k})"
    return check


def _cambers(s: DataSummary) -> str | None:
    k = len(s.camber_levels)
    return None if k >= 2 else f"needs >= 2 camber levels (have {k})"


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
    dpi = _dpi(x)
    kd = 1.0 + v["mz_p_trail"] * dpi           # Pacejka 2012 Eq. 4.E42: Dt0 (1 - PPZ1 dpi)
    kk = 1.0 + v["mz_p_stiffness"] * dpi       # via the cornering stiffness, Eq. 4.E25 (PPY1)
    for k in ("c1", "c2"):
        coef[k] = coef[k] * kd
    for k in ("c3", "c4"):
        coef[k] = coef[k] * kk


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


def _apply_mz_asymmetry(coef: dict, v: Mapping, x: ModelInputs) -> None:
    # Pacejka 2012 Eq. 4.E44: Et (1 + QEZ4 (2/pi) atan(Bt Ct alpha_t)) - here its sign limit, E (1 + q sign(alpha))
    k = 1.0 + v["mz_asym"] * np.sign(np.asarray(x.slip_angle, float))
    for n in ("c7", "c8", "c9"):
        coef[n] = coef[n] * k


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
    P = PAC89_COEFFICIENT
    out = [
        # ---- aligning moment ------------------------------------------------------------------
        Effect("mz_peak_load", "mz_peak_load", "peak aligning moment off a straight line in load", (P["c1"],),
               ">= 2 load levels", _loads(2),
               _card("The peak aligning moment is the pneumatic trail times the side force near the peak. "
                     "The trail grows with the contact patch's length (which grows with load), while the side "
                     "force grows less than in proportion to load; the product is not proportional to load: "
                     "on most tyres the peak moment grows faster than the load, and it levels off near the "
                     "tyre's capacity.",
                     "the peak Mz of a car tyre grows 2.5-4x from half to full rated load, not 2x",
                     "cornering sweeps at >= 3 loads that reach past the Mz peak (4-6 deg)",
                     "steering torque and its drop-off (the driver's feel of the limit)",
                     _PACEJKA + ", Eq. 4.E42 (QDZ2)"),
               signature="none", pac89=("c1",)),
        Effect("mz_stiffness_load", "mz_stiffness_load", "aligning stiffness load law with a quadratic term",
               (P["c3"],), ">= 3 load levels", _loads(3),
               _card("The aligning stiffness (dMz/dalpha at zero slip) is the cornering stiffness times the "
                     "pneumatic trail; both change with load, the trail with the patch length, so the product "
                     "follows a law the start model's exponential alone does not.",
                     "10-30 % over a tyre's load range",
                     "small-slip (+-2 deg) sweeps at >= 3 loads",
                     "steering torque on centre, self-aligning of the steering",
                     _PACEJKA + ", Eq. 4.E40 (QBZ1-3)"),
               signature="none", pac89=("c3",)),
        Effect("mz_curvature_load", "mz_curvature_load", "aligning curvature changing with load", (P["c8"],),
               ">= 2 load levels", _loads(2),
               _card("How sharply the aligning moment falls after its peak (the trail collapsing as the "
                     "patch slides) changes with load.",
                     "E of Mz moves by 0.2-1 over the load range",
                     "sweeps past the Mz peak (to 8-10 deg) at >= 2 loads",
                     "how suddenly the steering goes light at the limit",
                     _PACEJKA + ", Eq. 4.E44 (QEZ2)"),
               signature="none", pac89=("c8",)),
        Effect("mz_camber", "mz_camber", "camber moment and trail shift", (P["c11"], P["c15"]),
               ">= 2 camber levels", _cambers,
               _card("A cambered tyre turns its contact patch into an arc: the side force of camber acts "
                     "off the patch centre and the patch's twist adds a moment (the camber moment), while "
                     "the trail's curve shifts along the slip axis.",
                     "a few N*m per degree on a car tyre, 5-20 % of the peak Mz at 2-4 deg",
                     _CAMBER_TEST,
                     "steering torque of a cambered car, pull on a crowned road",
                     _PACEJKA + ", Eq. 4.E35 (QHZ3), Eq. 4.E47 (QDZ8)"),
               signature="none", pac89=("c11", "c15")),
        Effect("mz_camber_shape", "mz_camber", "camber on aligning stiffness and curvature",
               (P["c6"], P["c10"]), ">= 2 camber levels", _cambers,
               _card("Camber changes the length and pressure distribution of the patch, so the aligning "
                     "stiffness and the fall after the peak change with |camber|.",
                     "5-15 % of the aligning stiffness at 4 deg",
                     _CAMBER_TEST, "steering torque of a cambered car", _PACEJKA + ", Eq. 4.E40 (QBZ5)"),
               signature="none", pac89=("c6", "c10"), refinement=True),
        Effect("mz_camber_load", "mz_camber", "camber moment changing with load", (P["c11"], P["c15"], P["c14"]),
               ">= 2 camber and 3 load levels", lambda s: _cambers(s) or _loads(3)(s),
               _card("The camber moment grows with the patch, so faster than in proportion to load.",
                     "the quadratic term of the camber moment", _CAMBER_TEST + ", at >= 3 loads",
                     "steering torque of a cambered car", _PACEJKA + ", Eq. 4.E47 (QDZ9)"),
               signature="none", pac89=("c11", "c14", "c15"), refinement=True),
        Effect("mz_offsets", "mz_offsets", "residual torque and trail shift (conicity, ply steer)",
               (P["c13"], P["c17"]), "cornering sweeps through zero slip", lambda s: None,
               _card("Conicity and ply steer give an aligning moment at zero slip angle and shift the trail's "
                     "curve: the moment crosses zero off the origin.",
                     "1-5 N*m residual torque on a car tyre",
                     "sweeps through zero slip in both directions (to tell rig hysteresis from the tyre)",
                     "steering pull and the torque a straight-running car needs",
                     _PACEJKA + ", Eq. 4.E35 (QHZ1), Eq. 4.E47 (QDZ6)"),
               signature="none", pac89=("c13", "c17")),
        Effect("mz_offsets_load", "mz_offsets", "residual torque and trail shift changing with load",
               (P["c12"], P["c13"], P["c16"], P["c17"]), ">= 2 load levels", _loads(2),
               _card("The residual torque of conicity and ply steer grows with load.",
                     "1-5 N*m per kN", "sweeps through zero slip at >= 2 loads",
                     "steering pull", _PACEJKA + ", Eq. 4.E35 (QHZ2), Eq. 4.E47 (QDZ7)"),
               signature="none", pac89=("c12", "c13", "c16", "c17"), refinement=True),
        Effect("mz_pressure", "mz_pressure", "inflation pressure on trail and aligning stiffness",
               (Param("mz_p_trail", 0.0, (-3.0, 3.0), (-1.5, 0.5), "1/(dp/p0)", 0.3,
                      "relative change of the peak aligning moment per relative pressure change"),
                Param("mz_p_stiffness", 0.0, (-3.0, 3.0), (-1.0, 1.0), "1/(dp/p0)", 0.3,
                      "relative change of the aligning stiffness per relative pressure change")),
               ">= 2 pressure levels", _pressures,
               _card("A harder tyre has a shorter, stiffer contact patch: the pneumatic trail and with it "
                     "the aligning moment fall as the pressure rises, while the side-force stiffness moves "
                     "the other way.",
                     "-10 to -30 % of the peak Mz for +20 % pressure",
                     _PRESSURE_TEST, "steering torque after a pressure change",
                     _PACEJKA + ", Eq. 4.E42 (PPZ1), Eq. 4.E47 (PPZ2)"),
               signature="none", apply=_apply_mz_pressure,
               pac89_note="PAC89 has no pressure terms: fit MF 6.1 (model=\"mf61\"), PPZ1 and PPZ2"),
        Effect("mz_asymmetry", "mz_asymmetry", "aligning curvature differing between slip signs",
               (Param("mz_asym", 0.0, (-0.95, 0.95), (-0.5, 0.5), "-", 0.2,
                      "relative change of the curvature E of Mz for positive against negative slip"),),
               "cornering sweeps to both sides past the Mz peak", _both_sides,
               _card("The trail collapses differently when the tyre slips to one side than to the other "
                     "(tread pattern, ply construction): the Mz curve falls after its peak more sharply on "
                     "one side.  This is a change of shape, not a shift of the curve.",
                     "E of Mz differs by 10-50 % between the sides",
                     "sweeps to both sides, well past the Mz peak (8-12 deg)",
                     "steering torque at the limit differing between left and right turns",
                     _PACEJKA + ", Eq. 4.E44 (QEZ4)"),
               signature="none", apply=_apply_mz_asymmetry,
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
