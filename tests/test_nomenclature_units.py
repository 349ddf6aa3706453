"""Unit conversions at the edges (lead's core; the glossary tests live in test_nomenclature.py)."""

import numpy as np
import pytest

from tyrefit.errors import UnitError
from tyrefit.nomenclature import G0, check_unit, parse_header, to_si


@pytest.mark.parametrize("unit, value, si", [
    ("kN", 1.0, 1000.0), ("kg", 1.0, G0), ("lbf", 1.0, 4.4482216152605),
    ("deg", 180.0, np.pi), ("bar", 1.0, 1e5), ("psi", 1.0, 6894.757293168361),
    ("km/h", 36.0, 10.0), ("kph", 36.0, 10.0), ("mph", 1.0, 0.44704), ("mm", 1.0, 1e-3),
    ("in", 1.0, 0.0254), ("ft", 1.0, 0.3048), ("cm2", 1.0, 1e-4), ("mm2", 1.0, 1e-6), ("%", 50.0, 0.5),
])
def test_to_si(unit, value, si):
    np.testing.assert_allclose(to_si(value, unit), si, rtol=1e-15)


def test_parse_header_maps_foreign_names():
    assert parse_header("fz [kN]") == ("fz", "kN")
    assert parse_header("SA [deg]") == ("slip_angle", "deg")
    assert parse_header("INCLANGL") == ("camber", None)


def test_unknown_and_mismatched_units_name_what_is_accepted():
    with pytest.raises(UnitError, match=r"unknown unit \[kNN\].*accepted"):
        check_unit("fz", "kNN")
    with pytest.raises(UnitError, match=r"\[deg\].*'fz' is a force"):
        check_unit("fz", "deg")
