"""Glossary, aliases and units of tyrefit.nomenclature (as the readers use them)."""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tyrefit import nomenclature as nm
from tyrefit.errors import UnitError


@pytest.mark.parametrize("header, name, unit", [
    ("fz [kN]", "fz", "kN"),
    ("slip_angle [deg]", "slip_angle", "deg"),
    ("load [kg]", "load", "kg"),
    ("  Lateral Displacement  [mm] ", "lateral_displacement", "mm"),
    ("SA", "slip_angle", None), ("IA", "camber", None), ("FZ", "fz", None), ("P", "pressure", None),
    ("V", "speed", None), ("SL", "slip_ratio", None),
    ("SLIPANGL", "slip_angle", None), ("INCLANGL", "camber", None), ("FZW", "fz", None), ("FYW", "fy", None),
    ("MZW", "mz", None), ("INFLPRES", "pressure", None), ("LONGVEL", "speed", None), ("LONGSLIP", "slip_ratio", None),
    ("FXW", "fx", None), ("tyre", "tyre", None),
])
def test_parse_header_maps_foreign_names(header, name, unit):
    assert nm.parse_header(header) == (name, unit)


@pytest.mark.parametrize("value, unit, si", [
    (1.0, "kg", 9.80665), (1.0, "lbf", 4.4482216152605), (1.0, "lb", 4.4482216152605), (2.0, "kN", 2000.0),
    (180.0, "deg", math.pi), (1.0, "in", 0.0254), (1.0, "ft", 0.3048), (25.4, "mm", 0.0254),
    (1.0, "bar", 1e5), (1.0, "psi", 6894.757293168361), (1.0, "kPa", 1e3),
    (3.6, "km/h", 1.0), (3.6, "kph", 1.0), (1.0, "mph", 0.44704),
    (1.0, "cm2", 1e-4), (1.0, "mm2", 1e-6), (50.0, "%", 0.5), (0.5, "-", 0.5),
    (1.0, "ft-lb", 1.3558179483314004), (1.0, "N-m", 1.0), (1.0, "none", 1.0),
])
def test_units_to_si_and_back(value, unit, si):
    assert_allclose(nm.to_si(value, unit), si, rtol=1e-12)
    assert_allclose(nm.from_si(nm.to_si(np.array([value, -value]), unit), unit), [value, -value], rtol=1e-12)


def test_every_glossary_dimension_has_units():
    for q in nm.GLOSSARY.values():
        assert q.si_unit
        assert q.dimension in nm.UNITS, q


def test_unknown_unit_names_accepted_units():
    with pytest.raises(UnitError, match=r"unknown unit \[furlong\]; accepted: .*\[N\]"):
        nm.check_unit("fz", "furlong")


def test_unit_of_wrong_dimension():
    with pytest.raises(UnitError, match=r"\[deg\] is a angle, but 'fz' is a force; accepted: \[N\], \[kN\]"):
        nm.check_unit("fz", "deg")


def test_close_match_suggested():
    with pytest.raises(UnitError, match="did you mean 'kN'"):
        nm.canonical_unit("kNN")
