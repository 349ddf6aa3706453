"""Chrono PAC89 JSON: read the reference file, write -> read round trip."""

import json
from pathlib import Path

import pytest

from tyrefit.errors import FormatError
from tyrefit.io.chrono_json import chrono_dict, read_chrono_json, write_chrono_json
from tyrefit.io.tir import read_tir
from tyrefit.models import pac89

DATA = Path(__file__).parent / "data"


def test_reads_reference_json():
    t = read_chrono_json(DATA / "ref_HMMWV_Pac89Tire.json")
    assert t.name == "HMMWV Pac89 Tire"
    assert t.coefficients["a2"] == pytest.approx(812.449795340733)
    assert t.coefficients["b8"] == pytest.approx(-1.15310023217878)
    assert t.coefficients["c9"] == pytest.approx(-1.3329)
    assert t.unloaded_radius == 0.464 and t.width == 0.318
    assert t.lateral_stiffness == 261065.0
    assert t.vertical_curve[0] == (0.0, 0.0) and t.vertical_curve[-1] == (0.10, 53140.0)
    assert t.rolling_resistance == 0.015


def test_round_trip(tmp_path):
    t = read_chrono_json(DATA / "ref_HMMWV_Pac89Tire.json")
    p = write_chrono_json(t, tmp_path / "t.json")
    back = read_chrono_json(p)
    assert back.coefficients == t.coefficients
    assert back.vertical_curve == t.vertical_curve
    assert (back.unloaded_radius, back.width, back.lateral_stiffness, back.vertical_stiffness) == \
        (t.unloaded_radius, t.width, t.lateral_stiffness, t.vertical_stiffness)
    doc = json.loads(p.read_text())
    assert doc["Template"] == "Pac89Tire"
    assert set(doc["Lateral Coefficients"]) == set(pac89.LATERAL)


def test_tir_to_json_to_tir_values(tmp_path):
    t = read_tir(DATA / "ref_adams_pac89_example.tir")
    back = read_chrono_json(write_chrono_json(t, tmp_path / "x.json"))
    assert back.coefficients == t.coefficients
    assert chrono_dict(t)["Design Parameters"]["Unloaded Radius"] == pytest.approx(0.326)


def test_not_a_chrono_file(tmp_path):
    p = tmp_path / "x.json"
    p.write_text('{"a": 1}')
    with pytest.raises(FormatError, match="Lateral Coefficients"):
        read_chrono_json(p)
    p.write_text("{not json")
    with pytest.raises(FormatError, match="not a Chrono"):
        read_chrono_json(p)
