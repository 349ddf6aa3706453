"""A TTC record exported to CSV with one repeated timestamp or two swapped samples is still one
continuous record (segmented, warm-up dropped), not a table refused for its zero loads (issue 25)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from tyrefit.errors import ValueRangeError
from tyrefit.io.readers import read_data

ROOT = Path(__file__).resolve().parents[1]
DAT = ROOT / "data" / "ttc" / "fsae_cornering.dat"


@pytest.fixture(scope="module")
def record():
    df = pd.read_csv(DAT, sep="\t", skiprows=[0, 2])
    units = pd.read_csv(DAT, sep="\t", skiprows=[0], nrows=1).iloc[0].tolist()
    df.columns = [f"{c} [{u}]" for c, u in zip(df.columns, units)]
    return df.drop(columns=["N [rpm]", "TSTC [degC]"])


def _read(df, tmp_path, name):
    p = tmp_path / name
    df.to_csv(p, index=False)
    return read_data(p, convention="sae")


def test_repeated_timestamp(record, tmp_path):
    ref = _read(record, tmp_path, "ref.csv")
    d = record.copy()
    d.iloc[5000, 0] = d.iloc[4999, 0]
    ds = _read(d, tmp_path, "rep.csv")
    assert ds.df["run"].nunique() == ref.df["run"].nunique()
    assert len(ds.df) == len(ref.df)
    assert "repeated" in ds.meta["time_order"]


def test_two_swapped_samples(record, tmp_path):
    ref = _read(record, tmp_path, "ref.csv")
    d = record.copy()
    a = d.iloc[5000].copy()
    d.iloc[5000] = d.iloc[5001]
    d.iloc[5001] = a
    ds = _read(d, tmp_path, "swap.csv")
    assert ds.df["run"].nunique() == ref.df["run"].nunique() and len(ds.df) == len(ref.df)
    np.testing.assert_allclose(np.sort(ds.df["fy"].to_numpy()), np.sort(ref.df["fy"].to_numpy()))
    assert "out-of-order" in ds.meta["time_order"]
    assert list(ds.df.index) == sorted(ds.df.index)  # file line numbers, in time order again


def test_clock_restart_is_still_not_one_record(record, tmp_path):
    """Two records joined (the clock starts again) are not sorted into one: the zero loads are refused."""
    d = pd.concat([record.iloc[:6000], record.iloc[:6000]], ignore_index=True)
    with pytest.raises(ValueRangeError, match="zero or negative load"):
        _read(d, tmp_path, "joined.csv")
