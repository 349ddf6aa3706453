"""A load programme of 40 held levels (one sweep each) is read; a load ramp through the sweeps is
still refused (issue 25)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from tyrefit.errors import ValueRangeError
from tyrefit.io.readers import read_data

sys.path.insert(0, str(Path(__file__).resolve().parent))
from hostile import sweeps_csv, sweeps_frame  # noqa: E402

LOADS = tuple(np.linspace(1500, 7000, 40))


def test_forty_held_load_levels_are_read(tmp_path):
    p = tmp_path / "p40.csv"
    p.write_text(sweeps_csv(arr=sweeps_frame(loads=LOADS, n=41)))
    ds = read_data(p)
    assert ds.df["run"].nunique() == 40


def test_load_ramp_through_the_sweeps_is_refused(tmp_path):
    ramp = sweeps_frame(loads=LOADS, n=15)
    ramp[:, 3] = np.linspace(1500, 7000, len(ramp))
    p = tmp_path / "ramp.csv"
    p.write_text(sweeps_csv(arr=ramp))
    with pytest.raises(ValueRangeError, match="load ramp"):
        read_data(p)


def test_descending_ramp_is_refused(tmp_path):
    ramp = sweeps_frame(loads=LOADS, n=15)
    ramp[:, 3] = np.linspace(7000, 1500, len(ramp))
    p = tmp_path / "ramp.csv"
    p.write_text(sweeps_csv(arr=ramp))
    with pytest.raises(ValueRangeError, match="load ramp"):
        read_data(p)
