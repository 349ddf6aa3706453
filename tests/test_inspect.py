"""tyrefit inspect: data and tyre files, printed summary and --json keys of DESIGN."""

import json
from pathlib import Path

import pytest

from tyrefit.cli import main
from tyrefit.commands.inspect import inspect_file
from tyrefit.io.datasets import data_path
from tyrefit.synthetic.ttc import PROGRAMME

DATA = Path(__file__).parent / "data"


@pytest.mark.parametrize("name, fmt, n_params, container", [
    ("io_adams_pac89_example.tir", "PAC89", 43, "tir"),
    ("io_HMMWV_Pac02Tire.tir", "PAC2002", 121, "tir"),
    ("io_Generic_Pac02Tire.tir", "PAC2002", 121, "tir"),
    ("io_HMMWV_Pac89Tire.json", "PAC89", 43, "chrono_json"),
])
def test_inspect_reference_tyre_files(tmp_path, capsys, name, fmt, n_params, container):
    out = tmp_path / "t.json"
    assert main(["inspect", str(DATA / name), "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert doc["kind"] == "tyre" and doc["format"] == fmt and doc["parameters"] == n_params
    assert doc["container"] == container
    assert doc["dimensions"]["unloaded_radius"] > 0.3 and doc["dimensions"]["width"] > 0.2
    text = capsys.readouterr().out
    assert f"format {fmt}, {n_params} model parameters" in text


def test_pac89_tir_sections_and_dimensions():
    doc = inspect_file(DATA / "io_adams_pac89_example.tir")
    assert doc["coefficient_sections"] == {"LATERAL_COEFFICIENTS": 14, "LONGITUDINAL_COEFFICIENTS": 11,
                                           "ALIGNING_COEFFICIENTS": 18}
    assert doc["dimensions"]["unloaded_radius"] == pytest.approx(0.326)
    assert doc["dimensions"]["width"] == pytest.approx(0.245)


def test_ttc_must_show(tmp_path, capsys):
    """The FSAE TTC-style record: sweeps and conditions found; SAE read gives ISO-W signs."""
    out = tmp_path / "ttc.json"
    assert main(["inspect", str(data_path("ttc", "fsae_cornering.dat")), "--convention", "sae",
                 "--json", str(out)]) == 0
    text = capsys.readouterr().out
    doc = json.loads(out.read_text())
    for key in ("kind", "rows", "sweeps", "conditions", "convention", "columns"):
        assert key in doc
    assert doc["kind"] == "data" and doc["data_kind"] == "slip_angle" and doc["convention"] == "sae"
    assert doc["sweeps"] == 28 and doc["rows"] == doc["segmentation"]["n_kept"]
    assert doc["conditions"]["fz"] == pytest.approx(sorted(PROGRAMME["loads_N"]), rel=0.03)
    assert doc["conditions"]["camber"] == pytest.approx(PROGRAMME["cambers_deg"], abs=0.1)
    assert doc["conditions"]["pressure"] == pytest.approx([p * 1e3 for p in sorted(PROGRAMME["pressures_kPa"])],
                                                          abs=2e3)
    assert doc["flipped"] == ["fz", "fy", "mz", "slip_angle"]
    assert doc["cornering_slope"] < 0
    assert doc["sign"].startswith("positive slip angle gives negative lateral force")
    assert doc["columns"]["fz"] == {"header": "FZ [N]", "unit": "N", "si_unit": "N"}
    assert doc["columns"]["pressure"]["unit"] == "kPa"
    assert "sweeps 28" in text and "convention sae" in text and "dropped:" in text
    assert "positive slip angle gives negative lateral force" in text


def test_inspect_tydex(capsys):
    doc = inspect_file(data_path("ttc", "fsae_sweeps.tdx"))
    assert doc["format"] == "tdx" and doc["sweeps"] == 3 and doc["convention"] == "iso"
    assert doc["conditions"]["pressure"] == [82700.0]
    assert doc["columns"]["fy"]["header"] == "FYW [kN]"
    assert "RELEASE" in doc["header"]


def test_inspect_csv_text(tmp_path, capsys):
    p = tmp_path / "s.csv"
    p.write_text("# synthetic\nrun,load [kg],pressure [bar],lateral_displacement [mm],fy [N],fz [N]\n"
                 + "".join(f"1,500,7.4,{d},{30 * d},{4900 - d}\n" for d in range(10))
                 + "".join(f"2,2200,7.4,{d},{90 * d},{21500 - 3 * d}\n" for d in range(10)))
    assert main(["inspect", str(p)]) == 0
    text = capsys.readouterr().out
    assert "CSV data, static test" in text and "convention iso" in text
    assert "rows 20, sweeps 2" in text
    assert "fz 4.903, 21.57 kN; pressure 7.4 bar" in text
    assert "load [kg] -> load [N]" in text and "lateral_displacement [mm] -> lateral_displacement [m]" in text


def test_positive_slope_is_flagged(tmp_path):
    p = tmp_path / "wrong.csv"
    p.write_text("slip_angle [deg],fy [N],fz [N]\n" + "".join(f"{a},{100 * a},3000\n" for a in range(-5, 6)))
    doc = inspect_file(p)
    assert doc["cornering_slope"] > 0 and "POSITIVE" in doc["sign"]
