"""``tyrefit rig calibrate`` and the static-rig chain through ``tyrefit fit``."""

import json

import pytest

from tyrefit.cli import main
from tyrefit.io.datasets import data_path
from tyrefit.rig import RigCalibration


def _a(kind):
    return str(data_path("truck", f"tyre_a_{kind}.csv"))


def test_rig_calibrate_writes_rig_json_and_report(tmp_path, capsys):
    out, rep = tmp_path / "RIG.json", tmp_path / "rep"
    args = ["rig", "calibrate", "--static", _a("static"), "--dynamic", _a("dynamic"), "--patch", _a("patch"),
            "--out", str(out)]
    assert main(args + ["--report", str(rep)]) == 0
    d = json.loads(out.read_text())
    assert {"n", "b", "valid_range"} <= set(d) and 2.0 < d["n"] < 2.5
    assert (rep / "index.html").exists()
    assert "Eq. 1 calibrated" in capsys.readouterr().out
    before = out.read_bytes()
    assert main(args) == 2                                     # exists, no --force
    assert out.read_bytes() == before
    assert main(args + ["--force"]) == 0


def test_rig_calibrate_bad_inputs(tmp_path, capsys):
    out = tmp_path / "RIG.json"
    # dynamic data given as --static
    assert main(["rig", "calibrate", "--static", _a("dynamic"), "--dynamic", _a("dynamic"), "--patch", _a("patch"),
                 "--out", str(out)]) == 2
    assert "lateral_displacement" in capsys.readouterr().err
    assert main(["rig", "calibrate", "--static", _a("static"), "--dynamic", _a("patch"), "--patch", _a("patch"),
                 "--out", str(out)]) == 2
    assert not out.exists()


def test_fit_static_with_rig(tmp_path, capsys):
    """``tyrefit fit STTR.csv --patch P --rig RIG.json --out TYRE.tir`` runs the whole chain."""
    import tyrefit.commands.fit  # noqa: F401 - part of the package: an import error must fail, not skip
    rig = tmp_path / "RIG.json"
    assert main(["rig", "calibrate", "--static", _a("static"), "--dynamic", _a("dynamic"), "--patch", _a("patch"),
                 "--out", str(rig)]) == 0
    b = {k: str(data_path("truck", f"tyre_b_{k}.csv")) for k in ("static", "patch", "vertical")}
    tir = tmp_path / "b.tir"
    assert main(["fit", b["static"], "--patch", b["patch"], "--rig", str(rig), "--vertical", b["vertical"],
                 "--out", str(tir)]) == 0
    text = tir.read_text()
    assert "LATERAL_STIFFNESS" in text and "VERTICAL_STIFFNESS" in text and "Eq. 1 calibrated" in text
    assert RigCalibration.from_json(rig).calibrated
