"""``tyrefit slip`` end to end on generated files."""

import json

import pytest

from tyrefit.cli import main
from tyrefit.synthetic import slip as gen


@pytest.fixture(scope="module")
def slip_dir(tmp_path_factory):
    d = tmp_path_factory.mktemp("slip")
    gen.generate(d)
    return d


def test_slip_several_loads_json_and_report(slip_dir, tmp_path):
    out = tmp_path / "s.json"
    rep = tmp_path / "rep"
    assert main(["slip", str(slip_dir / "slip_ratio.csv"), "--json", str(out), "--report", str(rep)]) == 0
    d = json.loads(out.read_text())
    assert d["characteristic_curvature"] == -2.0
    assert len(d["loads"]) == 3
    for row, load in zip(d["loads"], gen.TRUTH["loads_N"]):
        assert abs(row["fz"] / load - 1) < 0.01
        assert abs(row["mu_peak"] / gen.mu_peak_at(load) - 1) < 0.03
        assert abs(row["k"] / gen.k_at(load) - 1) < 0.05
        assert row["characteristic_slip"] > 0
        assert row["characteristic_mu"] < row["mu_peak"]
    html = (rep / "index.html").read_text()
    assert "data:image/png;base64" in html and "characteristic" in html


def test_slip_single_load_with_radius(slip_dir, tmp_path):
    out = tmp_path / "r.json"
    assert main(["slip", str(slip_dir / "rolling_radius.csv"), "--json", str(out)]) == 0
    d = json.loads(out.read_text())
    for key in ("mu_peak", "k", "characteristic_curvature", "characteristic_slip", "characteristic_mu"):
        assert key in d
    assert "loads" not in d
    assert abs(d["rolling_radius"]["r0"] - gen.TRUTH["radius"]["r0_m"]) < 1e-3
    assert d["rolling_radius"]["elasticity_factor"] > 0


def test_slip_bad_input_and_existing_output(slip_dir, tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("slip_angle [deg],fy [N],fz [N]\n1,-100,3000\n2,-200,3000\n")
    assert main(["slip", str(bad)]) == 2
    assert "slip" in capsys.readouterr().err
    out = tmp_path / "x.json"
    out.write_text("{}")
    assert main(["slip", str(slip_dir / "slip_ratio.csv"), "--json", str(out)]) == 2
    assert out.read_text() == "{}"
    assert main(["slip", str(slip_dir / "slip_ratio.csv"), "--json", str(out), "--force"]) == 0
    assert "loads" in json.loads(out.read_text())
