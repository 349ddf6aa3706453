"""Asymmetry named by its form (issue 24): a shift (ply steer, conicity), a curvature that differs between the
slip sides, and a camber-driven shift each get their own family; 'offsets' only where the data show a shift.

The truths are the validation's (:mod:`tyrefit.synthetic.validation.truth`), written independently of the
effect catalogue: the side-dependent curvature changes the saturation sharpness by slip sign with each side's
peak kept, the camber-driven shift is a slip offset proportional to camber.
"""

from __future__ import annotations

import pytest

from tyrefit.diagnose import diagnose
from tyrefit.effects import EFFECTS
from tyrefit.synthetic.validation.cases import make_case


def _families(layout, noise, effect, seed):
    case = make_case(layout, noise, effect, seed)
    dg = diagnose(case.data, rated_load=case.rated_load, seed=seed)
    return {EFFECTS[a].family for a in dg.accepted}, dg


@pytest.mark.parametrize("layout, noise, seed", [("load6", "iid", 0), ("load6", "offsets", 1), ("grid24", "iid", 0),
                                                 ("grid60", "iid", 0)])
def test_side_dependent_curvature_is_asymmetry_not_offsets(layout, noise, seed):
    fams, dg = _families(layout, noise, "asym_curvature", seed)
    assert "asymmetry" in fams and "offsets" not in fams, dg.accepted


@pytest.mark.parametrize("layout, noise, seed", [("load6", "iid", 0), ("grid24", "ar1", 1)])
def test_a_shift_is_offsets_not_asymmetry(layout, noise, seed):
    fams, dg = _families(layout, noise, "offsets", seed)
    assert "offsets" in fams and "asymmetry" not in fams, dg.accepted


@pytest.mark.parametrize("layout, noise, seed", [("grid24", "iid", 0), ("grid60", "offsets", 2)])
def test_a_camber_driven_shift_is_camber(layout, noise, seed):
    fams, dg = _families(layout, noise, "camber_shift", seed)
    assert "camber" in fams and "offsets" not in fams, dg.accepted


def test_the_asymmetry_card_and_its_mf61_coefficient():
    from tyrefit.fitting.mf import EFFECT_COEFFICIENTS

    e = EFFECTS["asymmetry_curvature"]
    assert e.family == "asymmetry" and "PEY3" in e.card.sources[0] and "shift" in e.card.what
    assert EFFECT_COEFFICIENTS["asymmetry_curvature"] == ("PEY3",) and not e.pac89
