"""``tyrefit sim braking|straight|curved`` (the DESIGN contract) and the emission-control pipeline."""

import importlib.util
import json

import pytest

from tyrefit.cli import main
from tyrefit.io.datasets import data_dir, data_path
from tyrefit.tyres.pac89 import Pac89Tyre

KEYS = {"condition", "initial_speed_kmh", "vehicle", "stopping_distance_m", "max_deceleration_mps2"}


def test_sim_braking_json_and_report(tmp_path, capsys):
    out, rep = tmp_path / "b.json", tmp_path / "rep"
    assert main(["sim", "braking", "--json", str(out), "--report", str(rep)]) == 0
    d = json.loads(out.read_text())
    assert len(d["rows"]) == 12 and all(set(r) == KEYS for r in d["rows"])
    assert {r["condition"] for r in d["rows"]} == {0.5, 1.0}
    assert {r["initial_speed_kmh"] for r in d["rows"]} == {30, 60, 120}
    assert "drag" in d["setup"]["calibrated_to_table3"]
    html = (rep / "index.html").read_text()
    assert html.count("data:image/png;base64") >= 1 and "calibrated" in html.lower()
    traces = sorted(p.name for p in rep.glob("*.csv"))
    assert len(traces) == 6 and traces[0].startswith("braking_eta")
    assert "stop [m]" in capsys.readouterr().out
    # no silent overwrite, --force replaces
    assert main(["sim", "braking", "--json", str(out)]) == 2
    assert "exists" in capsys.readouterr().err


def test_sim_with_given_tyres(tmp_path, capsys):
    front, rear = str(data_path("sim", "hard_front.tir")), str(data_path("sim", "soft_rear.tir"))
    out = tmp_path / "b.json"
    assert main(["sim", "braking", "--front", front, "--rear", rear, "--json", str(out)]) == 0
    assert json.loads(out.read_text())["setup"]["front_tyre"] == Pac89Tyre.from_file(front).name
    # the front tyre must be the harder one
    assert main(["sim", "braking", "--front", rear, "--rear", front]) == 2
    assert "harder" in capsys.readouterr().err


def test_sim_bad_tyre_files(tmp_path, capsys):
    assert main(["sim", "braking", "--front", str(tmp_path / "missing.tir")]) == 2
    assert "not found" in capsys.readouterr().err
    t = Pac89Tyre.from_file(data_path("sim", "hard_front.tir"))
    for k in list(t.coefficients):
        if k.startswith("b"):
            t.coefficients[k] = 0.0
    lat_only = tmp_path / "lat.tir"
    t.to_tir(lat_only)
    assert main(["sim", "straight", "--front", str(lat_only)]) == 2
    assert "longitudinal" in capsys.readouterr().err


@pytest.mark.slow
def test_emission_control_pipeline(tmp_path):
    script = data_dir().parent / "pipelines" / "emission_control.py"
    spec = importlib.util.spec_from_file_location("emission_control", script)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    res = mod.main(tmp_path / "ec")
    assert (tmp_path / "ec" / "index.html").exists()
    assert (tmp_path / "ec" / "tyres" / "hard_front.tir").exists()
    assert res["max_stopping_distance_error_pct"] < 5
    assert 40 <= res["reduction_pct"][0] <= res["reduction_pct"][1] <= 65
    assert res["max_path_difference_m"] <= 0.05 and res["max_speed_difference_pct"] <= 1
