"""The effect catalogue: every named extension of the PAC89 lateral-force model.

The registry :data:`EFFECTS` maps effect id -> :class:`~tyrefit.effects.base.Effect`.
Ids start with their family name so a variant can be reported
(``camber_thrust`` is a variant of ``camber``).  The *start model* of
``tyrefit diagnose`` is base PAC89 with the parameters :data:`BASE`
(C = a0, one friction coefficient a2, the cornering-stiffness load law a3, a4,
constant curvature a7); every other PAC89 lateral coefficient is 0 until an
effect frees it.

Families
--------
``load_friction``   degressive friction with load (a1); the variant ``load_friction_curved`` adds a
                    curvature of the law, D (1 + q dfz^2), ``load_friction_cubic`` its third-order
                    term, D (1 + q dfz^2 + r dfz^3) (not PAC89 or MF 6.x: see below)
``curvature_load``  curvature changing with load (a6); ``curvature_load_curved`` bends that law,
                    E = a6 Fz + a7 + c dfz^2
``overload``        grip falling above the rated load (Komana et al., Sec. 4.2; not PAC89); the variant
                    ``overload_degressive`` puts the hinge on a degressive trend (a1),
                    ``overload_knee`` fits how wide the knee is (where below the rating the loss starts)
``camber``          camber thrust, shift and stiffness loss (a5, a8, a11; Zhang et al. 2024); the variant
                    ``camber_brush`` is the camber brush model's thrust (Zhang et al., Eq. 17-22)
``offsets``         ply steer and conicity shifts (a9, a10, a12, a13)
``pressure``        inflation pressure on stiffness and grip (not PAC89)
``speed``           travel speed on grip and stiffness (not PAC89)

Why the curved and degressive variants
--------------------------------------
The friction-load law of a real tyre is not a straight line: rubber friction
falls with contact pressure sub-linearly (power laws are common), and the
fall may level off or steepen with load.  Over a passenger tyre's 2-8 kN a
straight mu(Fz) leaves 0.6-0.8 sigma (sigma = 1 % of the peak force) on
noise-free data of such laws, so after a correct ``load_friction`` the
held-out error stays ~1.25 sigma, above the noise floor, and the diagnosis
would call a second, wrong family to absorb it.  The second-order term
``q dfz^2`` (dfz the MF-style normalised load increment about the middle
load level) is the Taylor term every smooth law has; it needs >= 4 load
levels (3 for the straight line plus one to test the bend).  A law that
levels off inside the tested range (a tanh-like saturation: an inflection) or
whose bend grows towards light loads (a power law) still leaves 0.27-0.35
sigma (held out, one sweep per load) with it; the third-order term
``r dfz^3`` takes that to 0.14-0.17 sigma and needs >= 6 load levels (each
sweep held out in turn must leave more levels than the law has friction
terms).  The curvature factor E gets the same treatment
(``curvature_load_curved``: a sharpness that changes as a power of the load
left 0.32 sigma with E linear in Fz, 0.21 with the bend).  Every variant
stands on held-out evidence like any effect: with noisy or few sweeps the
diagnosis keeps the simpler law unless the richer one predicts the held-out
sweeps better by the practical margin.  Both are *refinements*: with three
terms a third-order friction law can mimic a knee at the rated load (on one
sweep per load under AR(1) noise it out-predicted the fitted knee in 4 of 20
overload records), so they may refine a family once it has won on its other
variants, never name it.  Likewise a grip loss above the rated
load usually sits on a degressive trend below it ("faster
than the smooth load trend", Komana et al.), so ``overload_degressive`` frees
a1 with the hinge.  Where the loss starts is a property of the tyre, not of
its load index: the patch caves in gradually, and a rating is a nominal step
of 3-4 %.  The hinge is rounded over Fr (1 +- 0.1) by default; when the loss
sets in further below the rating (a smooth knee 8 % of Fr wide left 0.62
sigma on noise-free one-sweep-per-load data with the fixed rounding, 0.21
sigma with the width fitted) ``overload_knee`` fits the half-width w in
0.01-0.5 Fr.  ``overload_mu`` is bounded at 0: a hinge that *raises*
grip above the rated load is not overload, and allowing it let an overload
variant pass for a friction law that levels off.  When a candidate's terms
contain another confirmed candidate's (``overload_degressive`` contains
``load_friction``'s a1) and their held-out gains are within the practical
margin, the diagnosis adds the one with fewer terms
(:mod:`tyrefit.diagnose.engine`).

References
----------
Komana, Els, Becker, *Cost efficient tyre testing, modelling and validation for
PBS assessments*.  Zhang et al., *Estimation of road adhesion
coefficient based on camber brush model*, WEVJ 15 (2024) 263.
Pacejka, *Tire and Vehicle Dynamics* (MF 6.1 pressure terms PPY1, PPY3).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from ..errors import DataError, close_matches, option, render
from .base import DataSummary, Effect, ModelInputs, Param, PhysicsCard
from .factors import KNEE_HALF_WIDTH, overload_factor, relative_factor

__all__ = ["BASE", "BASE_NAMES", "EFFECTS", "FAMILIES", "get_effect", "parse_effects", "resolve_pac89",
           "brush_camber_fade"]

_DEG = 3.141592653589793 / 180.0

#: parameters of the start model (base PAC89), PAC89 units
BASE: tuple[Param, ...] = (
    Param("a0", 1.5, (0.3, 3.0), (1.1, 1.9), "-", 1.0, "shape factor C"),
    Param("a2", 1000.0, (20.0, 5000.0), (600.0, 1600.0), "N/kN", 1000.0,
          "friction: peak D = a2 Fz (1000 x the friction coefficient)"),
    Param("a3", 1500.0, (1.0, 1e6), (200.0, 1e5), "N/deg", 1000.0, "maximum cornering stiffness"),
    Param("a4", 10.0, (0.2, 1000.0), (2.0, 200.0), "kN", 10.0, "load at maximum cornering stiffness"),
    Param("a7", 0.0, (-30.0, 1.0), (-3.0, 1.0), "-", 1.0, "curvature factor E"),
)
BASE_NAMES: tuple[str, ...] = tuple(p.name for p in BASE)


# --- testability rules ------------------------------------------------------------
def _loads(n: int, reach_deg: float = 0.0):
    def rule(s: DataSummary) -> str | None:
        if len(s.fz_levels) < n:
            return f"needs >= {n} load levels (found {len(s.fz_levels)})"
        if reach_deg and s.slip_extent < reach_deg * _DEG:
            return (f"needs slip sweeps beyond the peak, |slip angle| >= {reach_deg:g} deg "
                    f"(found {s.slip_extent / _DEG:.1f} deg)")
        return None
    return rule


def _overload(s: DataSummary) -> str | None:
    if s.rated_load is None:
        return render(f"needs the rated load ({option('rated_load', 'NEWTONS')})")
    above = [f for f in s.fz_levels if f > 1.02 * s.rated_load]
    below = [f for f in s.fz_levels if f <= 1.02 * s.rated_load]
    if not above:
        return (f"needs loads above the rated load {s.rated_load:.0f} N "
                f"(highest load level {max(s.fz_levels):.0f} N)")
    if len(above) < 2:
        # a knee is named only when it predicts held-out levels above the rating better than the smooth laws;
        # with one level above, holding it out leaves nothing above the rating to fit the knee to
        return (f"needs >= 2 load levels above the rated load {s.rated_load:.0f} N (found one, "
                f"{above[0]:.0f} N): with one, a knee cannot be held out and checked against a smooth friction law")
    if len(below) < 2:
        return f"needs >= 2 load levels at or below the rated load {s.rated_load:.0f} N (found {len(below)})"
    if s.slip_extent < 5 * _DEG:
        return f"needs slip sweeps beyond the peak, |slip angle| >= 5 deg (found {s.slip_extent / _DEG:.1f} deg)"
    return None


def _cambers(n: int):
    def rule(s: DataSummary) -> str | None:
        if len(s.camber_levels) < n:
            return f"needs >= {n} camber levels (found {len(s.camber_levels)})"
        return None
    return rule


def _both_signs(loads: int = 1):
    def rule(s: DataSummary) -> str | None:
        if s.slip_reach < 1.0 * _DEG:
            return ("needs slip sweeps through zero in both directions, |slip angle| >= 1 deg each side "
                    f"(found {s.slip_min / _DEG:.1f} to {s.slip_max / _DEG:.1f} deg)")
        if len(s.fz_levels) < loads:
            return f"needs >= {loads} load levels (found {len(s.fz_levels)})"
        return None
    return rule


def _levels(attr: str, what: str, n: int = 2):
    def rule(s: DataSummary) -> str | None:
        k = len(getattr(s, attr))
        if k < n:
            return f"needs >= {n} {what} levels (found {k})"
        return None
    return rule


def _cambers_loads(n_camber: int, n_load: int):
    def rule(s: DataSummary) -> str | None:
        if len(s.camber_levels) < n_camber:
            return f"needs >= {n_camber} camber levels (found {len(s.camber_levels)})"
        if len(s.fz_levels) < n_load:
            return f"needs >= {n_load} load levels for the camber-stiffness load law (found {len(s.fz_levels)})"
        return None
    return rule


# --- modifiers (pure, vectorised; neutral -> multipliers exactly 1.0) -------------------
def _scale_d(coef: dict, m) -> None:
    coef["a1"] = coef["a1"] * m
    coef["a2"] = coef["a2"] * m


def _apply_overload(coef: dict, v: Mapping, x: ModelInputs) -> None:
    _need(x, "fz", "rated_load")
    _scale_d(coef, overload_factor(x.fz, x.rated_load, v["overload_mu"]))  # Komana et al., Sec. 4.2


def _apply_overload_knee(coef: dict, v: Mapping, x: ModelInputs) -> None:
    _need(x, "fz", "rated_load")
    _scale_d(coef, overload_factor(x.fz, x.rated_load, v["overload_mu"], v["overload_width"]))


def _apply_overload_stiffness(coef: dict, v: Mapping, x: ModelInputs) -> None:
    _need(x, "fz", "rated_load")
    _scale_d(coef, overload_factor(x.fz, x.rated_load, v["overload_mu"]))
    coef["a3"] = coef["a3"] * overload_factor(x.fz, x.rated_load, v["overload_ky"])


def brush_camber_fade(slip_angle, bcd, d):
    """Share of the linear camber thrust left at a slip angle: (2 - 3 u_c + u_c^3)/4 (Zhang et al., Eq. 22).

    Parameters
    ----------
    slip_angle : array_like
        Slip angle [rad].
    bcd : array_like
        Cornering stiffness of the model [N/deg] (PAC89 BCD).
    d : array_like
        Peak force of the model [N] (PAC89 D, the friction limit mu Fz).

    Returns
    -------
    ndarray
        1 at zero slip, falling smoothly to 0 where the whole patch slides.

    Notes
    -----
    In the brush model the camber term of the lateral force is
    ``-(2 - 3 u_c + u_c^3)/4 K_yg sin(gamma)`` (Zhang et al., Eq. 22, with the
    cube of the integrated Eq. 19; see :mod:`tyrefit.models.brush`), u_c the
    slip point.  To first order in the camber the slip point is the pure-slip
    one (the force is stationary in u_c, Eq. 21), and for a parabolic
    length-direction pressure (Fiala's brush, lambda_x = 0) it is
    ``u_c = 2 x - 1`` with ``x = K_y |tan(alpha)| / (3 mu Fz)`` clipped to 1;
    the factor is then the smoothstep ``1 - 3 x^2 + 2 x^3``.  K_y and mu Fz are
    taken from the PAC89 model at each point (BCD and D), so the thrust fades
    with the model's own friction limit.
    """
    ky = np.asarray(bcd, dtype=float) / _DEG  # N/rad
    x = np.clip(ky * np.abs(np.tan(slip_angle)) / (3.0 * np.maximum(np.asarray(d, dtype=float), 1e-9)), 0.0, 1.0)
    return 1.0 - 3.0 * x**2 + 2.0 * x**3  # Zhang et al., Eq. 22 at u_c = 2x - 1 (parabolic pressure)


def _apply_camber_brush(coef: dict, v: Mapping, x: ModelInputs) -> None:
    k = v["camber_brush_k"]
    if np.all(np.asarray(k) == 0.0):
        return  # neutral: the previous model, bit for bit
    fzk = np.asarray(x.fz, dtype=float) * 1e-3
    gdeg = np.asarray(x.camber, dtype=float) / _DEG
    # the model's own cornering stiffness and friction limit (PAC89 units; see tyrefit.models.pac89)
    z = fzk / coef["a4"]
    bcd = coef["a3"] * (2.0 * z / (1.0 + z * z)) * (1.0 - coef["a5"] * np.abs(gdeg))
    d = coef["a1"] * fzk**2 + coef["a2"] * fzk
    kyg = k * fzk ** (1.5 + v["camber_brush_n"])  # K_yg [N/deg]: Zhang et al., Eq. 20 with a ~ Fz^(1/2)
    # PAC89 sign: Sv > 0 is an ISO-W thrust to -y for a positive inclination, as a11 Fz gamma
    coef["a13"] = coef["a13"] + kyg * (np.sin(x.camber) / _DEG) * brush_camber_fade(x.slip_angle, bcd, d)


def _need(x: ModelInputs, what: str, ref: str) -> None:
    if getattr(x, what) is None or getattr(x, ref) is None:
        raise DataError(f"this effect needs the {what} of every point and a reference {what} "
                        f"(ModelInputs.{what}, ModelInputs.{ref})")


def _apply_pressure(coef: dict, v: Mapping, x: ModelInputs) -> None:
    _need(x, "pressure", "pressure_ref")
    # MF 6.1 style: Kya (1 + PPY1 dpi), mu (1 + PPY3 dpi), dpi = (p - p0)/p0
    if "pressure_mu" in v:
        _scale_d(coef, relative_factor(x.pressure, x.pressure_ref, v["pressure_mu"]))
    if "pressure_ky" in v:
        coef["a3"] = coef["a3"] * relative_factor(x.pressure, x.pressure_ref, v["pressure_ky"])


def _dfz(x: ModelInputs) -> np.ndarray:
    """MF-style normalised load increment (Fz - Fz_ref)/Fz_ref, Fz_ref the middle load level."""
    _need(x, "fz", "fz_ref")
    return (np.asarray(x.fz, dtype=float) - x.fz_ref) / x.fz_ref


def _apply_load_friction_law(coef: dict, v: Mapping, x: ModelInputs) -> None:
    """D (1 + q dfz^2) (``load_friction_curved``), + r dfz^3 (``load_friction_cubic``)."""
    q, r = v["load_friction_q"], v.get("load_friction_r", 0.0)
    if np.all(np.asarray(q) == 0.0) and np.all(np.asarray(r) == 0.0):
        return  # neutral: the previous model, bit for bit
    dfz = _dfz(x)
    m = 1.0 + q * dfz**2
    if "load_friction_r" in v:
        m = m + r * dfz**3
    _scale_d(coef, m)


def _apply_curvature_load_curved(coef: dict, v: Mapping, x: ModelInputs) -> None:
    c = v["curvature_q"]
    if np.all(np.asarray(c) == 0.0):
        return  # neutral: the previous model, bit for bit
    coef["a7"] = coef["a7"] + c * _dfz(x) ** 2  # E = a6 Fz + a7 + c dfz^2


def _apply_asymmetry_curvature(coef: dict, v: Mapping, x: ModelInputs) -> None:
    e = v["asym_e"]
    if np.all(np.asarray(e) == 0.0):
        return  # neutral: the previous model, bit for bit
    # the slip the curve sees, x = alpha + Sh (PAC89, degrees), with Sh = a8 gamma + a9 Fz + a10
    sh = coef["a8"] * np.degrees(x.camber) + coef["a9"] * x.fz * 1e-3 + coef["a10"]
    f = 1.0 - e * np.sign(np.degrees(x.slip_angle) + sh)  # E (1 - PEY3 sgn(alpha_y)), Pacejka 2012 (4.E24)
    coef["a6"] = coef["a6"] * f
    coef["a7"] = coef["a7"] * f


def _apply_speed(coef: dict, v: Mapping, x: ModelInputs) -> None:
    _need(x, "speed", "speed_ref")
    _scale_d(coef, relative_factor(x.speed, x.speed_ref, v["speed_mu"]))
    coef["a3"] = coef["a3"] * relative_factor(x.speed, x.speed_ref, v["speed_ky"])


# --- parameters ------------------------------------------------------------------
_A1 = Param("a1", 0.0, (-2000.0, 500.0), (-80.0, 0.0), "N/kN^2", 10.0,
            "degressive friction: D = a1 Fz^2 + a2 Fz")
_LF_Q = Param("load_friction_q", 0.0, (-3.0, 3.0), (-0.3, 0.3), "-", 0.05,
               "curvature of the friction-load law: D (1 + q dfz^2), dfz = (Fz - Fz_ref)/Fz_ref")
_LF_R = Param("load_friction_r", 0.0, (-3.0, 3.0), (-0.3, 0.3), "-", 0.05,
               "third-order term of the friction-load law: D (1 + q dfz^2 + r dfz^3)")
_E_Q = Param("curvature_q", 0.0, (-5.0, 5.0), (-1.0, 1.0), "-", 0.05,
             "curvature of the curvature-load law: E = a6 Fz + a7 + c dfz^2")
_A5 = Param("a5", 0.0, (-0.2, 0.2), (0.0, 0.02), "1/deg", 0.005,
            "cornering-stiffness loss with camber: BCD (1 - a5 |gamma|)")
_A6 = Param("a6", 0.0, (-2.0, 2.0), (-0.1, 0.1), "1/kN", 0.02, "curvature change with load: E = a6 Fz + a7")
_A8 = Param("a8", 0.0, (-2.0, 2.0), (-0.2, 0.2), "deg/deg", 0.01, "horizontal shift with camber: Sh = a8 gamma")
_ASYM_E = Param("asym_e", 0.0, (-0.9, 0.9), (-0.5, 0.5), "-", 0.05,
                "curvature differing between slip signs: E (1 - e sgn(alpha + Sh)) (MF 6.1 PEY3)")
_A9 = Param("a9", 0.0, (-2.0, 2.0), (-0.05, 0.05), "deg/kN", 0.01, "horizontal shift with load: Sh = a9 Fz")
_A10 = Param("a10", 0.0, (-5.0, 5.0), (-0.5, 0.5), "deg", 0.1, "constant horizontal shift (ply steer / conicity)")
_A11 = Param("a11", 0.0, (-1000.0, 1000.0), (-40.0, 40.0), "N/(kN deg)", 10.0,
             "camber thrust: Sv = a11 Fz gamma")
_A12 = Param("a12", 0.0, (-1000.0, 1000.0), (-30.0, 30.0), "N/kN", 10.0, "vertical shift with load: Sv = a12 Fz")
_A13 = Param("a13", 0.0, (-5000.0, 5000.0), (-300.0, 300.0), "N", 50.0, "constant vertical shift (residual force)")
_OV_MU = Param("overload_mu", 0.0, (0.0, 3.0), (0.0, 1.0), "-", 0.3,
               "friction loss per rated load of overload: D (1 - k h(Fz - Fr)/Fr), h a hinge rounded over +-10 % of Fr")
_OV_W = Param("overload_width", KNEE_HALF_WIDTH, (0.01, 0.5), (0.03, 0.3), "-", 0.05,
               "half-width of the rounded knee as a share of the rated load: the grip loss starts at Fr (1 - w)")
_OV_KY = Param("overload_ky", 0.0, (-1.0, 3.0), (0.0, 1.0), "-", 0.3,
               "cornering-stiffness loss per rated load of overload")
_CB_K = Param("camber_brush_k", 0.0, (-200.0, 200.0), (0.0, 30.0), "N/(kN^1.5 deg)", 5.0,
              "brush camber stiffness K_yg = k Fz^(3/2 + n) per deg at zero slip, Fz in kN (Zhang et al., Eq. 20)")
_CB_N = Param("camber_brush_n", 0.0, (-1.5, 1.5), (-0.5, 0.8), "-", 0.2,
              "load exponent of K_yg beyond 3/2 (the brush's 3 a2 + c3 - 3/2, a ~ q^a2, Re ~ q^-c3)")
_P_KY = Param("pressure_ky", 0.0, (-5.0, 5.0), (-0.5, 1.0), "-", 0.3,
              "cornering-stiffness change per relative pressure change (MF 6.1 PPY1)")
_P_MU = Param("pressure_mu", 0.0, (-5.0, 5.0), (-0.6, 0.3), "-", 0.2,
              "friction change per relative pressure change (MF 6.1 PPY3)")
_S_MU = Param("speed_mu", 0.0, (-5.0, 5.0), (-0.3, 0.1), "-", 0.1, "friction change per relative speed change")
_S_KY = Param("speed_ky", 0.0, (-5.0, 5.0), (-0.3, 0.3), "-", 0.1,
              "cornering-stiffness change per relative speed change")

# --- physics cards -----------------------------------------------------------------
_CARD_LOAD_FRICTION = PhysicsCard(
    what=("The friction coefficient falls as the load rises: contact pressure grows faster than the real "
          "contact area and rubber friction is sub-linear in pressure, so the peak lateral force grows less "
          "than in proportion to Fz (degressive friction)."),
    size=("Peak mu falls 5-15 % per doubling of load on passenger tyres (a1 about -20 to -60 N/kN^2 with "
          "a2 = 1000-1300 N/kN); more on truck tyres."),
    test="Lateral-force sweeps through the peak at >= 3 loads (peak mu against Fz).",
    vehicle=("Load transfer costs grip: the axle with more lateral load transfer saturates first, which sets "
             "the limit understeer/oversteer balance."),
    sources=("Komana et al. fit a1 with a2 in their PAC89 parameterisation (Sec. 4.3)",))

_CARD_OVERLOAD = PhysicsCard(
    what=("Above the rated load the contact patch turns rectangular and caves in at the centre line: the "
          "pressure concentrates at the patch boundary and the centre lifts off, so less rubber touches the "
          "road and the friction coefficient drops faster than the smooth load trend."),
    size=("Komana et al. measure a static mu of about 0.75 below the rated 4250 kg of a 385/65R22.5 truck "
          "tyre and lower above it; 5-20 % loss of mu at 40 % overload is typical."),
    test="Lateral-force sweeps at loads below and above the rated load (give rated_load).",
    vehicle=("An overloaded axle loses grip and cornering stiffness: lower yaw damping and more rearward "
             "amplification in PBS manoeuvres (Komana et al.)."),
    sources=("Komana et al., Sec. 2 (patch shape, Fig. 1) and Sec. 4.2 (friction above the rated load)",))

_CARD_CAMBER = PhysicsCard(
    what=("On a cambered tyre the tread elements run through the patch on a curved path: the camber brush "
          "model (Zhang et al. 2024) deflects the bristles sideways by y = -(a^2 - x^2) sin(gamma)/(2 Re) "
          "(Eq. 19) even at zero slip, giving a camber thrust -K_ygamma sin(gamma) with K_ygamma = "
          "2 a^3 k_ty/(3 Re) (Eq. 20) that fades as the sliding zone grows (Eq. 22); PAC89 writes it as a "
          "vertical shift a11 Fz gamma and a horizontal shift a8 gamma. Camber also narrows the contact "
          "(Eq. 1) and pushes the pressure to one shoulder (Eqs. 2-16), which lowers the cornering "
          "stiffness (a5)."),
    size=("Camber thrust about 1-2.5 % of Fz per degree on passenger radials (a11 of 10-25 N/(kN deg)); "
          "cornering-stiffness loss about 0.5 %/deg (a5 about 0.005/deg)."),
    test="The same slip sweeps at >= 3 camber angles, e.g. -4, 0, +4 deg (>= 2 for thrust and shift only).",
    vehicle=("Static camber adds a lateral force on each wheel and more grip in corners; camber gain in roll "
             "shapes the steady-state handling; the road-adhesion estimate depends on it (Zhang et al. 2024)."),
    sources=("Zhang et al. 2024, camber brush model, Eqs. 1, 17-22",
             "tyrefit.models.brush (the camber brush model) computes these terms from the brush physics"))

_CARD_OFFSETS = PhysicsCard(
    what=("Ply steer (from the angle of the belt plies) and conicity (a slightly conical tyre) make a lateral "
          "force at zero slip angle and shift the curve sideways: conicity acts like a small camber and flips "
          "sign when the tyre is mounted the other way round; ply steer acts like a small slip angle."),
    size="Residual lateral force of 50-300 N and slip offsets of 0.1-0.5 deg on passenger tyres.",
    test=("Slip sweeps through zero in both directions; telling ply steer from conicity needs both mounting "
          "sides or both rolling directions."),
    vehicle="Vehicle pull and steering-wheel offset in straight running; negligible for limit handling.",
    sources=("PAC89 shift terms Sh = a9 Fz + a10, Sv = a12 Fz + a13 (Bakker, Nyborg, Pacejka 1989)",))

_CARD_ASYMMETRY = PhysicsCard(
    what=("The force curve bends over differently on the two slip sides: its curvature (how sharply it rounds into "
          "the peak and how much it keeps past it) differs with the sign of the slip angle, while the curve is "
          "not shifted. An asymmetric carcass or belt construction, an asymmetric tread pattern and the tyre's "
          "own ply steer acting differently as the contact patch slides make the two sides differ. It is not "
          "ply steer or conicity: those shift the whole curve, including its zero crossing."),
    size=("MF 6.1 PEY3 of 0.1-0.8 on published passenger tyres (MFeval's example: 0.78): a few percent of the "
          "peak force difference between the sides at 3-8 deg, little at zero slip."),
    test=("Sweeps through the peak on both slip sides (|slip| >= 8 deg each way); repeating the sweep with the "
          "tyre mounted the other way round tells construction asymmetry (it flips) from a rig asymmetry "
          "(it does not)."),
    vehicle="A handling balance that differs between left and right turns near the limit.",
    sources=("MF 6.1 E_y = (PEY1 + PEY2 dfz)(1 + PEY5 gamma^2 - (PEY3 + PEY4 gamma) sgn(alpha_y)), Pacejka "
             "(2012) (4.E24)",))

_NOT_PAC89_ASYMMETRY = (
    "not representable in PAC89: its curvature E = a6 Fz + a7 is the same on both slip sides. MF 6.1 carries "
    "it as PEY3 (a fit with model=\"mf61\"); in a PAC89 file the curve's two sides are averaged.")

_CARD_PRESSURE = PhysicsCard(
    what=("Inflation pressure stiffens the carcass and shortens and narrows the contact patch: cornering "
          "stiffness rises with pressure (until the patch gets too short) and peak friction usually falls "
          "slightly as the contact pressure rises."),
    size=("+20 % pressure changes cornering stiffness by about +3 to +15 % and peak mu by about -2 to -6 % "
          "on passenger tyres."),
    test="The same sweeps at >= 2 inflation pressures.",
    vehicle=("Front/rear pressure split is a handling tuning parameter (understeer gradient); under-inflation "
             "lowers cornering stiffness and stability."),
    sources=("Zhang et al. 2024, Eq. 1: contact width inversely related to pressure",
             "Komana et al., Sec. 4.2: lateral stiffness directly proportional to inflation pressure",
             "MF 6.1 pressure terms PPY1 (stiffness), PPY3 (friction)"))

_CARD_CURVATURE = PhysicsCard(
    what=("The shape of the curve around and after the peak changes with load: a longer patch at high load "
          "makes the transition to full sliding more gradual, so the curvature factor E varies with Fz."),
    size="a6 of -0.1 to +0.1 per kN; visible as a load-dependent slip at the peak and post-peak fall.",
    test="Sweeps through and beyond the peak (|slip angle| >= 6 deg) at >= 2 loads.",
    vehicle="How progressively an axle loses grip at the limit (driver feel, stability control thresholds).",
    sources=("PAC89 E = a6 Fz + a7 (Bakker, Nyborg, Pacejka 1989)",))

_CARD_SPEED = PhysicsCard(
    what=("Rubber friction depends on sliding speed and temperature: at higher travel speed the peak friction "
          "falls a little (more on wet roads) while the cornering stiffness changes little."),
    size="-1 to -5 % peak mu per +50 km/h on dry surfaces.",
    test="The same sweeps at >= 2 speeds.",
    vehicle="Grip at motorway speed against manoeuvring speed; braking and lane-change margins.",
    sources=("Pacejka, Tire and Vehicle Dynamics, MF 6.x speed scaling (LMUV)",))

_NOT_PAC89_PRESSURE = ("not representable in PAC89 (no pressure input): export one .tir per pressure "
                       "(fit each pressure's sweeps separately), or use an MF 6.1/6.2 file (PPY1 for "
                       "cornering stiffness, PPY3/PPY4 for friction).")
_NOT_PAC89_SPEED = ("not representable in PAC89 (no speed input): export one .tir per speed range, or use an "
                    "MF 6.x file with speed scaling (LMUV).")
_NOT_PAC89_OVERLOAD = ("not representable in PAC89 exactly: D = a1 Fz^2 + a2 Fz is one smooth parabola, so a1 < 0 "
                       "can absorb a friction fall spread over the fitted load range but not a knee at the rated "
                       "load (it then under-predicts grip below the rating or over-predicts it above). Refit a1, "
                       "a2 on the load range the vehicle uses, or export separate .tir files below and above the "
                       "rating; MF 6.x (PDY2) is also smooth.")

_NOT_PAC89_CURVED_FRICTION = (
    "not representable in PAC89 or MF 6.x exactly: both carry a friction coefficient linear in load (PAC89 "
    "mu = a1 Fz + a2, MF 6.1 mu = PDY1 + PDY2 dfz), so the curvature q of the law is lost; a1 (PDY2) takes "
    "the best straight line over the fitted load range. Fit the load range the vehicle uses, or export one "
    "tyre per load range.")

_NOT_PAC89_CURVED_CURVATURE = (
    "not representable in PAC89 or MF 6.x exactly: both carry a curvature factor linear in load (PAC89 "
    "E = a6 Fz + a7, MF 6.1 E = PEY1 + PEY2 dfz), so the bend c of the law is lost; a6 (PEY2) takes the "
    "best straight line over the fitted load range.")

_CARD_CAMBER_BRUSH = PhysicsCard(
    what=("The camber brush model's own camber term (Zhang et al. 2024): on a leaning tyre the bristles "
          "follow a parabola y = -(a^2 - x^2) sin(gamma)/(2 Re) through the patch (Eq. 18-19), which gives a "
          "thrust -K_ygamma sin(gamma) at zero slip with K_ygamma = 2 a^3 k_y/(3 Re) (Eq. 20). The half-length a "
          "grows with load (a ~ Fz^(1/2) for a classical tyre, a ~ q^a2 in Eq. 11), so K_ygamma grows like "
          "Fz^(3/2) - faster than the linear a11 Fz gamma of PAC89 - and, as the sliding zone spreads from the "
          "trailing edge, only the adhering part keeps its camber deflection: the thrust fades as "
          "(2 - 3 u_c + u_c^3)/4 (Eq. 21-22) and vanishes when the whole patch slides, so the friction limit "
          "mu Fz is never exceeded."),
    size=("K_ygamma of 40-120 N/deg at 4-5 kN on passenger radials (camber_brush_k about 5-15 N/(kN^1.5 deg)); "
          "tyrefit's 205/55R16 brush parameters give 79 N/deg at 4.5 kN and a load exponent of 2.1 "
          "(camber_brush_n = 0.56, from a ~ q^0.7)."),
    test=("The same slip sweeps at >= 3 camber angles and >= 2 loads; the fade shows in sweeps that reach "
          "full sliding (|slip angle| >= 8 deg)."),
    vehicle=("Camber thrust that grows faster than the load moves more lateral force to the outer, loaded "
             "wheels in a corner and vanishes at the limit: static camber helps in the linear range, not "
             "at the friction limit; the road-adhesion estimator of Zhang et al. uses exactly this term."),
    sources=("Zhang et al. 2024, camber brush model, Eqs. 17-22 (Eq. 19 parabolic camber deflection, "
             "Eq. 20 K_ygamma = 2 a^3 k/(3 Re), Eq. 21-22 slip point and camber term)",
             "tyrefit.models.brush (camber_brush_forces, camber_stiffness) computes the same terms strip by "
             "strip; tyrefit.compare.brush fits PAC89 to it"))

_NOT_PAC89_CAMBER_BRUSH = (
    "not representable in PAC89 exactly: PAC89 writes camber thrust as a vertical shift a11 Fz gamma, linear "
    "in load and constant along the sweep (so at full sliding |Fy| exceeds mu Fz by a11 Fz gamma), plus a "
    "horizontal shift a8 gamma, which fades with saturation but gives a zero-slip thrust BCD a8 gamma that "
    "follows the cornering-stiffness load law, not a^3/Re. a8 and a11 (camber_thrust) absorb the thrust over "
    "the fitted load range and are what the .tir gets; for the Fz^(3/2) law and the fade use MF 6.x "
    "(PKY6/PKY7 camber stiffness with load, PEY5 camber in E) or the brush model itself (tyrefit.models.brush).")

def _effects() -> list[Effect]:
    return [
        Effect("load_friction", "load_friction", "degressive friction with load", (_A1,),
               "sweeps through the peak at >= 3 load levels", _loads(3, 5.0), _CARD_LOAD_FRICTION, "peak_mu_vs_fz",
               pac89=("a1",), pac89_note="PAC89 a1 (D = a1 Fz^2 + a2 Fz): written to the .tir."),
        Effect("load_friction_curved", "load_friction", "degressive friction with a curved load law",
               (_A1, _LF_Q), "sweeps through the peak at >= 4 load levels", _loads(4, 5.0), _CARD_LOAD_FRICTION,
               "peak_mu_vs_fz", apply=_apply_load_friction_law, pac89_approx=("a1",),
               pac89_note=_NOT_PAC89_CURVED_FRICTION),
        Effect("load_friction_cubic", "load_friction", "degressive friction with a third-order load law",
               (_A1, _LF_Q, _LF_R), "sweeps through the peak at >= 6 load levels", _loads(6, 5.0),
               _CARD_LOAD_FRICTION, "peak_mu_vs_fz", apply=_apply_load_friction_law, pac89_approx=("a1",),
               pac89_note=_NOT_PAC89_CURVED_FRICTION, refinement=True),
        Effect("curvature_load", "curvature_load", "curvature changing with load", (_A6,),
               "sweeps beyond the peak (|slip| >= 6 deg) at >= 2 load levels", _loads(2, 6.0), _CARD_CURVATURE,
               "slip_at_peak_vs_fz", pac89=("a6",), pac89_note="PAC89 a6 (E = a6 Fz + a7): written to the .tir."),
        Effect("curvature_load_curved", "curvature_load", "curvature changing with load along a curved law",
               (_A6, _E_Q), "sweeps beyond the peak (|slip| >= 6 deg) at >= 3 load levels", _loads(3, 6.0),
               _CARD_CURVATURE, "slip_at_peak_vs_fz", apply=_apply_curvature_load_curved, pac89_approx=("a6",),
               pac89_note=_NOT_PAC89_CURVED_CURVATURE, extra={"pac89_variant": "curvature_load"},
               refinement=True),
        Effect("overload", "overload", "grip falling above the rated load", (_OV_MU,),
               "loads above the rated load and >= 2 levels at or below it; rated_load", _overload,
               _CARD_OVERLOAD, "peak_mu_vs_fz", apply=_apply_overload, pac89_approx=("a1",),
               pac89_note=_NOT_PAC89_OVERLOAD, requires_rated_load=True),
        Effect("overload_knee", "overload", "grip falling above the rated load, with the knee width fitted",
               (_OV_MU, _OV_W), "loads above the rated load and >= 2 levels at or below it; rated_load",
               _overload, _CARD_OVERLOAD, "peak_mu_vs_fz", apply=_apply_overload_knee, pac89_approx=("a1",),
               pac89_note=_NOT_PAC89_OVERLOAD, requires_rated_load=True),
        Effect("overload_degressive", "overload", "grip falling above the rated load, on a degressive load trend",
               (_A1, _OV_MU), "loads above the rated load and >= 2 levels at or below it; rated_load", _overload,
               _CARD_OVERLOAD, "peak_mu_vs_fz", apply=_apply_overload, pac89=("a1",), pac89_approx=("a1",),
               pac89_note=_NOT_PAC89_OVERLOAD, requires_rated_load=True),
        Effect("overload_stiffness", "overload", "grip and cornering stiffness falling above the rated load",
               (_OV_MU, _OV_KY), "loads above the rated load and >= 2 levels at or below it; rated_load",
               _overload, _CARD_OVERLOAD, "stiffness_vs_fz", apply=_apply_overload_stiffness,
               pac89_approx=("a1",), pac89_note=_NOT_PAC89_OVERLOAD + " The stiffness fall is absorbed by a4 at "
               "best (BCD = a3 sin(2 atan(Fz/a4)) peaks at Fz = a4).", requires_rated_load=True),
        Effect("camber", "camber", "camber thrust, shift and stiffness loss", (_A5, _A8, _A11),
               ">= 3 camber levels", _cambers(3), _CARD_CAMBER, "fy0_vs_camber",
               pac89=("a5", "a8", "a11"), pac89_note="PAC89 a5, a8, a11: written to the .tir."),
        Effect("camber_thrust", "camber", "camber thrust and shift", (_A8, _A11),
               ">= 2 camber levels", _cambers(2), _CARD_CAMBER, "fy0_vs_camber",
               pac89=("a8", "a11"), pac89_note="PAC89 a8, a11: written to the .tir."),
        Effect("camber_brush", "camber", "camber thrust of the brush model (K_ygamma ~ Fz^(3/2), fading at sliding)",
               (_CB_K, _CB_N), ">= 3 camber levels and >= 2 load levels", _cambers_loads(3, 2),
               _CARD_CAMBER_BRUSH, "camber_stiffness_vs_fz", apply=_apply_camber_brush, pac89_approx=("a8", "a11"),
               pac89_note=_NOT_PAC89_CAMBER_BRUSH, extra={"pac89_variant": "camber_thrust", "reads_factors": True}),
        Effect("offsets", "offsets", "ply steer and conicity shifts, load dependent", (_A9, _A10, _A12, _A13),
               "sweeps through zero in both slip directions at >= 2 load levels", _both_signs(2), _CARD_OFFSETS,
               "fy0_vs_fz", pac89=("a9", "a10", "a12", "a13"),
               pac89_note="PAC89 a9, a10, a12, a13: written to the .tir (they flip sign for the other tyre side)."),
        Effect("offsets_constant", "offsets", "constant ply steer and conicity shifts", (_A10, _A13),
               "sweeps through zero in both slip directions", _both_signs(1), _CARD_OFFSETS, "fy0_vs_fz",
               pac89=("a10", "a13"),
               pac89_note="PAC89 a10, a13: written to the .tir (they flip sign for the other tyre side)."),
        Effect("asymmetry_curvature", "asymmetry", "curvature that differs between the slip sides", (_ASYM_E,),
               "sweeps past the peak in both slip directions", _both_signs(1), _CARD_ASYMMETRY,
               "side_difference_vs_fz", apply=_apply_asymmetry_curvature, pac89_note=_NOT_PAC89_ASYMMETRY,
               extra={"needs_model": "mf61"}),
        Effect("pressure", "pressure", "inflation pressure on cornering stiffness and grip", (_P_KY, _P_MU),
               ">= 2 inflation pressures", _levels("pressure_levels", "pressure"), _CARD_PRESSURE,
               "stiffness_vs_pressure", apply=_apply_pressure, pac89_note=_NOT_PAC89_PRESSURE,
               extra={"needs_model": "mf61"}),
        Effect("pressure_stiffness", "pressure", "inflation pressure on cornering stiffness", (_P_KY,),
               ">= 2 inflation pressures", _levels("pressure_levels", "pressure"), _CARD_PRESSURE,
               "stiffness_vs_pressure", apply=_apply_pressure, pac89_note=_NOT_PAC89_PRESSURE,
               extra={"needs_model": "mf61"}),
        Effect("pressure_grip", "pressure", "inflation pressure on grip", (_P_MU,),
               ">= 2 inflation pressures", _levels("pressure_levels", "pressure"), _CARD_PRESSURE,
               "peak_mu_vs_pressure", apply=_apply_pressure, pac89_note=_NOT_PAC89_PRESSURE,
               extra={"needs_model": "mf61"}),
        Effect("speed", "speed", "travel speed on grip and cornering stiffness", (_S_MU, _S_KY),
               ">= 2 speeds", _levels("speed_levels", "speed"), _CARD_SPEED, "peak_mu_vs_speed",
               apply=_apply_speed, pac89_note=_NOT_PAC89_SPEED, extra={"needs_model": "mf61"}),
    ]


#: effect id -> Effect
EFFECTS: dict[str, Effect] = {e.id: e for e in _effects()}
#: family -> effect ids (catalogue order)
FAMILIES: dict[str, list[str]] = {}
for _e in EFFECTS.values():
    assert _e.id.startswith(_e.family), _e.id
    FAMILIES.setdefault(_e.family, []).append(_e.id)


def get_effect(effect_id: str) -> Effect:
    """The catalogue entry ``effect_id``; :class:`DataError` naming the known ids otherwise."""
    try:
        return EFFECTS[effect_id]
    except KeyError:
        raise DataError(f"unknown effect {effect_id!r}; known effects: {', '.join(EFFECTS)}"
                        + close_matches(effect_id, EFFECTS)) from None


def parse_effects(text: str | Iterable[str] | None) -> list[str]:
    """``"camber,pressure"`` (or a list) -> validated list of effect ids, duplicates removed."""
    if text is None:
        return []
    items = text.split(",") if isinstance(text, str) else list(text)
    out: list[str] = []
    for it in items:
        it = it.strip()
        if it and it not in out:
            get_effect(it)
            out.append(it)
    return out


def resolve_pac89(ids: Iterable[str]) -> tuple[list[str], list[str]]:
    """PAC89 coefficients to vary for the start model plus ``ids``, and notes.

    Parameters
    ----------
    ids : iterable of str
        Effect ids (see :data:`EFFECTS`).

    Returns
    -------
    vary : list of str
        ``a0, a2, a3, a4, a7`` plus each effect's PAC89 coefficients (and, for
        effects PAC89 cannot represent exactly, the coefficients that absorb
        part of them, e.g. ``a1`` for ``overload``), in PAC89 order.
    notes : list of str
        One line per effect that PAC89 cannot represent exactly, saying what
        to do instead.

    Examples
    --------
    >>> resolve_pac89(["camber", "pressure"])[0]
    ['a0', 'a2', 'a3', 'a4', 'a5', 'a7', 'a8', 'a11']
    """
    vary = set(BASE_NAMES)
    notes: list[str] = []
    for eid in parse_effects(list(ids)):
        e = EFFECTS[eid]
        vary.update(e.pac89)
        vary.update(e.pac89_approx)
        if not e.representable:
            notes.append(f"{eid}: {e.pac89_note}")
    order = [f"a{i}" for i in range(14)]
    return [a for a in order if a in vary], notes
