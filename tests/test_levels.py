"""tyrefit.io.levels.group_levels, the one level grouping: its two clusterings, its tolerances, and
that it equals the grouping helpers it replaced and the copies left in the mutation-testing targets."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from tyrefit.fitting import engine, initial
from tyrefit.io import readers, segment
from tyrefit.io.facets import channel_levels, format_levels
from tyrefit.io.levels import group_levels

_DEG = math.pi / 180.0


def _samples(seed: int, n: int = 40, nan: bool = False) -> np.ndarray:
    """Per-sweep values at a few set points, with scatter and (optionally) NaN."""
    rng = np.random.default_rng(seed)
    sets = rng.choice([2000.0, 4000.0, 4150.0, 6000.0, 9000.0], n)
    v = sets + rng.normal(0.0, 40.0, n)
    if nan:
        v[rng.choice(n, 3, replace=False)] = np.nan
    return v


def test_gap_clustering_means_and_index():
    v = np.array([5.0, 1.0, 1.2, np.nan, 5.3, 9.0])
    lv, idx = group_levels(v, 0.5)
    np.testing.assert_allclose(lv, [1.1, 5.15, 9.0])
    assert idx.tolist() == [1, 0, 0, -1, 1, 2]
    # chaining: 1, 2, 3 with a tolerance of 1.5 are one level
    assert group_levels([1.0, 2.0, 3.0], 1.5)[0].tolist() == [2.0]
    assert group_levels([], 1.0)[0].size == 0 and group_levels([np.nan], 1.0)[1].tolist() == [-1]


def test_relative_tolerances():
    v = [100.0, 110.0, 1000.0, 1030.0]
    assert len(group_levels(v, 1.0, 0.04, relative_to="max")[0]) == 2       # 41.2 for every step
    assert len(group_levels(v, 1.0, 0.04, relative_to="value")[0]) == 3     # 4.4 at 110, 41.2 at 1030
    assert len(group_levels(v, 1.0, 0.01, relative_to="range")[0]) == 4     # 9.3
    assert len(group_levels(v, 1.0, 0.05, relative_to="range")[0]) == 2     # 46.5
    with pytest.raises(ValueError):
        group_levels(v, relative_to="median")
    with pytest.raises(ValueError):
        group_levels(v, 1.0, method="kmeans")
    with pytest.raises(ValueError):
        group_levels(v, 1.0, method="peaks", relative_to="value")


@pytest.mark.parametrize("seed", range(8))
def test_equals_the_copies_in_the_mutation_targets(seed):
    """On finite values: initial.load_levels, engine._levels, readers._group_levels, segment._levels."""
    v = _samples(seed)
    assert group_levels(v, 100.0, 0.04)[1].tolist() == initial.load_levels(v).tolist()
    assert group_levels(v, 300.0, 0.02)[1].tolist() == initial.load_levels(v, 0.02, 300.0).tolist()
    assert len(group_levels(v, 120.0)[0]) == engine._levels(v, 120.0)
    assert group_levels(v, 100.0, 0.05, relative_to="value")[0].tolist() == readers._group_levels(v, 100.0, 0.05)
    assert group_levels(v, 200.0, method="peaks")[0].tolist() == segment._levels(v, 200.0, 1)


def _old_mf_data_levels(values, tol):
    v = np.sort(np.asarray(values, float))
    v = v[np.isfinite(v)]
    if v.size == 0:
        return []
    out, grp = [], [v[0]]
    for x in v[1:]:
        if x - grp[-1] > tol:
            out.append(float(np.mean(grp)))
            grp = []
        grp.append(x)
    out.append(float(np.mean(grp)))
    return out


def _old_signature_levels(v: pd.Series, tol: float) -> pd.Series:
    if v.isna().all():
        return v
    vals = v.to_numpy(dtype=float)
    order = np.argsort(vals)
    sv = vals[order]
    gap = max(tol, 0.05 * (np.nanmax(sv) - np.nanmin(sv)))
    group = np.r_[0, np.cumsum(np.diff(sv) > gap)]
    means = pd.Series(sv).groupby(group).transform("mean").to_numpy()
    out = np.empty_like(vals)
    out[order] = means
    return pd.Series(out, index=v.index)


def _old_channel_levels(values, channel, tolerance=None):
    v = np.asarray(values, float)
    ok = np.isfinite(v)
    if not ok.any():
        return np.array([np.nan]), np.zeros(v.size, int)
    if tolerance is None:
        tolerance = segment.DEFAULT_TOLERANCES[channel]
        if channel == "fz":
            tolerance = max(tolerance, 0.05 * float(np.median(np.abs(v[ok]))))
    lv = np.asarray(segment._levels(v[ok], float(tolerance), 1), float)
    idx = np.argmin(np.abs(np.where(ok, v, lv[0])[:, None] - lv[None, :]), axis=1)
    return lv, np.where(ok, idx, -1)


@pytest.mark.parametrize("seed", range(8))
def test_callers_give_bit_identical_results_to_the_code_they_replaced(seed):
    from tyrefit.effects.signatures import _levels as signature_levels
    from tyrefit.fitting.mf_data import _levels as mf_data_levels

    v = _samples(seed, nan=seed % 2 == 1)
    assert mf_data_levels(v, 150.0) == _old_mf_data_levels(v, 150.0)
    s = pd.Series(v / 1e3, index=np.arange(len(v)) * 3)
    pd.testing.assert_series_equal(signature_levels(s, 0.2), _old_signature_levels(s, 0.2), check_exact=True)
    for ch, tol in (("fz", None), ("pressure", None), ("camber", 0.15)):
        new, old = channel_levels(v, ch, tol), _old_channel_levels(v, ch, tol)
        assert new[0].tolist() == old[0].tolist() and new[1].tolist() == old[1].tolist()


def test_format_levels():
    assert format_levels("pressure", [2e5, 2.3e5, 2.6e5]) == "200, 230, 260 kPa"
    assert format_levels("camber", [0.0, 2 * _DEG]) == "0.0, 2.0°"
