"""``tyrefit traction BRAKING.csv [--json] [--report]`` (seed 000 Eq. 41-43)."""

import json

from numpy.testing import assert_allclose

from tyrefit.cli import main
from tyrefit.io.datasets import data_path

TABLE = str(data_path("sim", "braking_utqg.csv"))


def test_traction_json_and_report(tmp_path, capsys):
    out, rep = tmp_path / "t.json", tmp_path / "rep"
    assert main(["traction", TABLE, "--json", str(out), "--report", str(rep)]) == 0
    d = json.loads(out.read_text())
    for key in ("a", "b", "a_stderr", "b_stderr", "r2", "n_tyres", "hpwizard", "tyres", "examples", "bundled_pair"):
        assert key in d
    assert d["n_tyres"] == 15 and len(d["tyres"]) == 15
    assert d["hpwizard"] == {"a": 2.25, "b": 0.15}
    pair = d["bundled_pair"]
    assert_allclose(pair["k"], pair["mu_ratio"] ** (1 / d["b"]), rtol=1e-12)          # Eq. 43
    html = (rep / "index.html").read_text()
    assert "data:image/png;base64" in html and "HPwizard" in html
    assert "mu = " in capsys.readouterr().out


def test_traction_refuses_existing_output_and_wrong_tables(tmp_path, capsys):
    out = tmp_path / "t.json"
    out.write_text("{}")
    assert main(["traction", TABLE, "--json", str(out)]) == 2
    assert "exists" in capsys.readouterr().err
    assert out.read_text() == "{}"
    assert main(["traction", str(data_path("sim", "emission.csv"))]) == 2
    assert "stopping_distance" in capsys.readouterr().err
    bad = tmp_path / "bad.csv"
    bad.write_text("name,stopping_distance [m],initial_speed [mph]\na,30,50\nb,31,50\nc,32,50\n")
    assert main(["traction", str(bad)]) == 2
    assert "treadwear" in capsys.readouterr().err
