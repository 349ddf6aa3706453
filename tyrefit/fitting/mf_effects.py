"""Diagnose's effects in MF 6.1 terms: which Magic Formula coefficients carry each catalogue effect.

:data:`EFFECT_COEFFICIENTS` maps an effect id of :mod:`tyrefit.effects` to the MF 6.1 lateral coefficients that
carry it (Pacejka 2012, (4.E19)-(4.E30)); :func:`effect_coefficients` gives the coefficients
:func:`tyrefit.fitting.mf.fit_mf` varies for diagnose's start model plus some effects, so the error
waterfall of ``tyrefit diagnose`` continues in the exported tyre.
"""

from __future__ import annotations

from collections.abc import Sequence

from ..effects.catalogue import EFFECTS as _CATALOGUE
from ..errors import DataError, close_matches, option
from .mf_stages import SPEED_FRICTION

__all__ = ["START_FY0", "EFFECT_COEFFICIENTS", "effect_coefficients"]

#: start model of diagnose, in MF 6.1 lateral coefficients (shape, friction, stiffness law, curvature)
START_FY0 = ("PCY1", "PDY1", "PKY1", "PKY2", "PEY1")
#: diagnose effect id -> MF 6.1 coefficients that carry it (Pacejka 2012, 4.E19-4.E30)
EFFECT_COEFFICIENTS: dict[str, tuple[str, ...]] = {
    "load_friction": ("PDY2",),
    # MF 6.1 mu_y is linear in dfz: the curvature of the friction-load law is lost, PDY2 takes the trend
    "load_friction_curved": ("PDY2",),
    "load_friction_cubic": ("PDY2",),
    "curvature_load": ("PEY2",),
    # MF 6.1 E is linear in dfz (4.E24): PEY2 takes the trend of a bent curvature law
    "curvature_load_curved": ("PEY2",),
    # MF 6.1 mu_y is linear in dfz: a fall above the rated load is carried by PDY2 and the curvature
    # law at best; the stiffness fall by PKY4 (the stiffness law's curvature, peak at PKY2 Fz0)
    "overload": ("PDY2", "PEY2"),
    "overload_knee": ("PDY2", "PEY2"),
    "overload_degressive": ("PDY2", "PEY2"),
    "overload_stiffness": ("PDY2", "PEY2", "PKY4"),
    "camber": ("PDY3", "PKY3", "PKY6", "PKY7", "PVY3", "PVY4", "PEY3"),
    "camber_thrust": ("PKY6", "PKY7", "PVY3", "PVY4"),
    "camber_brush": ("PKY6", "PKY7", "PEY4", "PEY5", "PVY3", "PVY4"),
    "offsets": ("PHY1", "PHY2", "PVY1", "PVY2"),
    # a curvature that differs between the slip sides: E (1 - PEY3 sgn(alpha_y)) (4.E24)
    "asymmetry_curvature": ("PEY3",),
    # MF's vertical shift is SVy = Fz (PVY1 + PVY2 dfz) (4.E29): a shift constant in newtons (PAC89's a13,
    # diagnose's offsets_constant) needs the load slope PVY2 as well
    "offsets_constant": ("PHY1", "PVY1", "PVY2"),
    "pressure": ("PPY1", "PPY2", "PPY3", "PPY4"),
    "pressure_stiffness": ("PPY1", "PPY2"),
    "pressure_grip": ("PPY3", "PPY4"),
    # MF 6.1's one speed term in Fx/Fy: friction decay with slip speed (4.E7), on mu_x and mu_y
    "speed": SPEED_FRICTION,
}
_EFFECT_NOTES = {
    "speed": "speed: MF 6.1 carries speed in Fx/Fy through the scaling factor LMUV (friction decay with slip speed, "
             "mu / (1 + LMUV Vs/LONGVL), Pacejka 4.E7), fitted from >= 2 speeds with sweeps through the peak; the "
             "change of cornering stiffness with speed has no MF 6.1 term and is not carried; QSY3/QSY4 (rolling "
             "resistance) are fitted where My is measured",
    "load_friction_curved": "load_friction_curved: MF 6.1 friction is linear in load (PDY2); the curvature of the "
                            "friction-load law is not carried, PDY2 takes the trend over the fitted range",
    "load_friction_cubic": "load_friction_cubic: MF 6.1 friction is linear in load (PDY2); the bend and "
                           "third-order term of the friction-load law are not carried, PDY2 takes the trend "
                           "over the fitted range",
    "curvature_load_curved": "curvature_load_curved: MF 6.1 curvature is linear in load (PEY2); the bend of "
                             "the curvature-load law is not carried",
    "overload": "overload: MF 6.1 friction is linear in load (PDY2); a fall beyond the rated load is absorbed by "
                "PDY2 and PEY2 over the fitted range only",
}


#: effect family -> the effect whose MF 6.1 coefficients carry a variant of the family
_FAMILY_DEFAULT = {"load_friction": "load_friction", "curvature": "curvature_load", "overload": "overload_stiffness",
                   "camber": "camber", "offsets": "offsets", "pressure": "pressure", "speed": "speed",
                   "asymmetry": "asymmetry_curvature"}


def _in_catalogue(eid: str) -> bool:
    return eid in _CATALOGUE


def effect_coefficients(ids: Sequence[str]) -> tuple[list[str], list[str]]:
    """MF 6.1 Fy0 coefficients to vary for the diagnose start model plus effects ``ids``, and notes.

    Unknown ids are a :class:`DataError` naming the known ones.
    """
    vary = list(START_FY0)
    notes: list[str] = []
    for eid in ids:
        coeffs = EFFECT_COEFFICIENTS.get(eid)
        if coeffs is None:  # a variant of a family (diagnose's ids start with their family name)
            fam = next((f for f in _FAMILY_DEFAULT if eid.startswith(f)), None)
            if fam is not None:
                coeffs = EFFECT_COEFFICIENTS[_FAMILY_DEFAULT[fam]]
                notes.append(f"{eid}: carried in MF 6.1 by the {fam} family's coefficients ({', '.join(coeffs)})")
            elif _in_catalogue(eid):
                notes.append(f"{eid}: no MF 6.1 coefficient carries this effect; not in the exported tyre")
                continue
            else:
                raise DataError(f"unknown effect {eid!r} for {option('model', 'mf61')}; known: "
                                f"{', '.join(EFFECT_COEFFICIENTS)}" + close_matches(eid, EFFECT_COEFFICIENTS))
        vary += [k for k in coeffs if k not in vary]
        if eid in _EFFECT_NOTES:
            notes.append(_EFFECT_NOTES[eid])
    return vary, notes
