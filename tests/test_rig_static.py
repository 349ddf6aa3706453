"""Static lateral push analysis (seed 003 Sec. 4.2, Fig. 5, Eq. 2)."""

import math

import numpy as np
import pandas as pd
import pytest

from tyrefit.errors import ColumnError, DataError
from tyrefit.nomenclature import G0
from tyrefit.rig.static import analyse_static, shape_factor_from_sliding
from tyrefit.synthetic import truck as T


def _si(df: pd.DataFrame) -> pd.DataFrame:
    return pd.DataFrame({"run": df["run"], "load": df["load [kg]"] * G0, "pressure": df["pressure [bar]"] * 1e5,
                         "lateral_displacement": df["lateral_displacement [mm]"] * 1e-3, "fy": df["fy [N]"],
                         "fz": df["fz [N]"]})


@pytest.fixture(scope="module")
def static_a():
    return _si(T.static_table(T.TYRE_A, np.random.default_rng(5)))


@pytest.mark.parametrize("C", [1.05, 1.3, 1.45, 1.7, 1.95])
def test_eq2_inverts_the_magic_formula_asymptote(C):
    # MF asymptote y_a = D sin(pi C / 2) for C > 1
    assert shape_factor_from_sliding(math.sin(math.pi * C / 2), 1.0) == pytest.approx(C)


def test_eq2_outside_its_domain_is_nan():
    assert np.isnan(shape_factor_from_sliding(1.2, 1.0))
    assert np.isnan(shape_factor_from_sliding(-0.1, 1.0))


def test_peak_sliding_and_stiffness(static_a):
    t = T.TYRE_A
    sa = analyse_static(static_a)
    assert [r.load / G0 for r in sa.runs] == pytest.approx(list(T.STATIC_LOADS_KG))
    for r in sa.runs:
        # sliding / peak is the Magic Formula asymptote ratio, so Eq. 2 gives back C
        assert r.shape_factor == pytest.approx(t.a0, abs=0.04)
        # the static peak: the friction limit of the truth at the load then, within 2 %
        dy = np.arange(0, 0.3, 0.5e-3)
        fy, fz, i = T.static_truth(t, r.load / G0, dy)
        assert r.max_mu == pytest.approx(fy[i] / fz[i], rel=0.02)
        assert r.peak_displacement == pytest.approx(dy[i], rel=0.1)   # the force is flat at its peak
        assert 0 < r.fz_drop < 0.15
    # lateral stiffness: C_alpha / sigma of the truth at mid loads (the truth's stage one)
    for r in sa.runs[1:5]:
        true = T.true_cornering_stiffness(t, r.load) / T.relaxation_length(t, r.load)
        assert r.lateral_stiffness == pytest.approx(true, rel=0.08)


def test_parts(static_a):
    sa = analyse_static(static_a)
    peak = sa.select("peak")
    assert (peak["part"] == "rising").all()
    assert len(sa.select("sliding")) == len(static_a) > len(peak)
    for r in sa.runs:
        g = peak[peak["run"] == r.run]
        assert g["lateral_displacement"].max() == pytest.approx(r.peak_displacement, abs=1e-3)
    with pytest.raises(DataError, match="unknown static part 'plateau'"):
        sa.select("plateau")


def test_a_push_to_the_other_side_gives_the_same_numbers(static_a):
    mirrored = static_a.assign(lateral_displacement=-static_a["lateral_displacement"], fy=-static_a["fy"])
    a, b = analyse_static(static_a), analyse_static(mirrored)
    for ra, rb in zip(a.runs, b.runs):
        assert rb.sign == -1 and ra.sign == 1
        assert (rb.max_mu, rb.lateral_stiffness, rb.sliding_mu) == pytest.approx(
            (ra.max_mu, ra.lateral_stiffness, ra.sliding_mu))


def test_lateral_stiffness_interpolates_in_load(static_a):
    sa = analyse_static(static_a)
    r1, r2 = sa.runs[2], sa.runs[3]
    mid = 0.5 * (r1.load + r2.load)
    assert sa.lateral_stiffness(mid) == pytest.approx(0.5 * (r1.lateral_stiffness + r2.lateral_stiffness))


def test_short_push_has_no_sliding_level(static_a):
    g = static_a[static_a["run"] == 3]
    sa = analyse_static(g)
    cut = g[g["lateral_displacement"] <= sa.runs[0].peak_displacement + 2e-3]
    r = analyse_static(cut).runs[0]
    assert math.isnan(r.sliding_mu) and any("no sliding level" in n for n in r.notes)


def test_errors(static_a):
    with pytest.raises(ColumnError, match="'fz'"):
        analyse_static(static_a.drop(columns=["fz"]))
    bad = static_a.copy()
    bad.loc[bad.index[5], "fz"] = 0.0
    with pytest.raises(DataError, match="fz <= 0"):
        analyse_static(bad)
    with pytest.raises(DataError, match="at least 10"):
        analyse_static(static_a.iloc[:5])
