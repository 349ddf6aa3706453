"""The one within-sweep noise floor (tyrefit.fitting.noise.noise_floor) and its fit parametrisation."""

import numpy as np
import pandas as pd

from tyrefit.fitting.noise import MAX_POINTS_PER_SWEEP, noise_floor, thin_sweeps
from tyrefit.fitting.result import noise_floor_of


def _sweeps(seed=3):
    rng = np.random.default_rng(seed)
    labels, xs = [], []
    for lab, n in ((7, 260), (2, 40), (11, 130), (5, 8)):
        labels.append(np.full(n, lab))
        xs.append(np.linspace(-0.2, 0.2, n))
    run, x = np.concatenate(labels), np.concatenate(xs)
    fz = 4000 + 40 * rng.standard_normal(len(x))
    y = 3000 * np.sin(1.4 * np.arctan(10 * x)) + 15 * rng.standard_normal(len(x))
    return x, y, run, fz


def test_thinning_inside_the_floor_is_thinning_first():
    x, y, run, fz = _sweeps()
    _, idx = np.unique(run, return_inverse=True)
    take = thin_sweeps(idx, 50)
    assert np.bincount(idx[take]).max() == 50
    a = noise_floor(x, y, idx, fz=fz, max_points_per_sweep=50)
    b = noise_floor(x[take], y[take], idx[take], fz=fz[take])
    assert a[0] == b[0]
    np.testing.assert_array_equal(a[1], b[1])


def test_noise_floor_of_is_noise_floor_with_the_fits_parameters():
    x, y, run, fz = _sweeps()
    _, idx = np.unique(run, return_inverse=True)
    for part, spacing in (("lateral", 1.5), ("longitudinal", 0.03 * 180 / np.pi)):
        floor, per = noise_floor_of(x, y, run, fz, part)
        f2, per2 = noise_floor(x, y, idx, spacing_deg=spacing, fz=fz, max_points_per_sweep=MAX_POINTS_PER_SWEEP)
        assert floor == f2
        pd.testing.assert_series_equal(per, pd.Series(per2, index=np.unique(run), dtype=float))
        assert np.isnan(per[5])  # fewer than 10 points: no value
