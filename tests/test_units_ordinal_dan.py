"""Units written ``º`` (ordinal indicator U+00BA, typed for a degree) and ``daN`` (decanewton, 10 N)
are read (issue 25)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import tyrefit.nomenclature as nm
from tyrefit.cli import main
from tyrefit.io.readers import read_data

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data" / "passenger" / "passenger_205_55R16.csv"


@pytest.mark.parametrize("unit, si", [("º", np.pi / 180), ("˚", np.pi / 180), ("daN", 10.0), ("DAN", 10.0),
                                      ("daN*m", 10.0), ("daNm", 10.0)])
def test_units_known(unit, si):
    assert nm.to_si(1.0, unit) == pytest.approx(si)


def test_ordinal_degree_and_decanewton_in_a_csv(tmp_path, capsys):
    df = pd.read_csv(DATA, comment="#")
    ren = {}
    for c in df.columns:
        if c.endswith("[deg]"):
            ren[c] = c.replace("[deg]", "[º]")
    df = df.rename(columns=ren)
    for c in ("fz [N]", "fy [N]"):
        df[c.replace("[N]", "[daN]")] = df.pop(c) / 10.0
    p = tmp_path / "odd_units.csv"
    df.to_csv(p, index=False)
    a, b = read_data(DATA), read_data(p)
    for col in ("fz", "fy", "slip_angle", "camber"):
        np.testing.assert_allclose(np.sort(b.df[col].to_numpy()), np.sort(a.df[col].to_numpy()), rtol=1e-12,
                                   atol=1e-12)
    assert main(["inspect", str(p)]) == 0, capsys.readouterr().err


def test_unknown_unit_still_refused():
    with pytest.raises(Exception, match="unknown unit"):
        nm.canonical_unit("dN")
