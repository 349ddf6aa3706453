"""The user guide's tutorial (docs/tutorial.py) runs as it is written: data to diagnosed MF tyre to simulation."""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

TUTORIAL = Path(__file__).resolve().parents[1] / "docs" / "tutorial.py"


def test_tutorial_runs_and_writes_its_outputs(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(sys, "argv", [str(TUTORIAL), str(tmp_path)])
    ns = runpy.run_path(str(TUTORIAL), run_name="__main__")
    out = capsys.readouterr().out
    for name in ("waterfall.png", "fit.png", "passenger_mf61.tir"):
        assert (tmp_path / name).is_file(), name
    assert ns["mf"].contract() == [] and ns["dg"].accepted
    assert "understeer gradient" in out and "stopping distances" in out
    fy = ns["f"]["fy"]
    assert fy[0] > 0 > fy[2] and abs(fy[1]) < 0.05 * fy[0]  # ISO-W: a positive slip angle gives a negative Fy
