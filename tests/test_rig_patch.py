"""Contact-patch models (seed 003 Sec. 4.1): two-gradient length/area, exponential width, pressure law."""

import numpy as np
import pandas as pd
import pytest

from tyrefit.errors import ColumnError, DataError
from tyrefit.nomenclature import G0
from tyrefit.rig.patch import exp_rise, fit_patch, fit_two_gradient, two_gradient
from tyrefit.synthetic import truck as T


def _si(df: pd.DataFrame) -> pd.DataFrame:
    """A generator table in file units -> canonical SI columns."""
    return pd.DataFrame({"load": df["load [kg]"] * G0, "pressure": df["pressure [bar]"] * 1e5,
                         "length": df["length [mm]"] * 1e-3, "width": df["width [mm]"] * 1e-3,
                         "area": df["area [cm2]"] * 1e-4})


def test_two_gradient_is_continuous_with_two_slopes():
    x = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    y = two_gradient(x, 1.0, 2.0, 5.0, 2.0)
    np.testing.assert_allclose(y, [1, 3, 5, 10, 15])
    eps = 1e-9
    assert two_gradient(2 + eps, 1, 2, 5, 2) - two_gradient(2 - eps, 1, 2, 5, 2) == pytest.approx(0, abs=1e-7)


def test_exp_rise_limits():
    assert exp_rise(0.0, 0.3, 1e4) == 0.0
    assert exp_rise(1e9, 0.3, 1e4) == pytest.approx(0.3)


def test_fit_two_gradient_exact_data():
    x = np.linspace(0, 10, 21)
    fit = fit_two_gradient(x, two_gradient(x, 0.5, 1.0, 3.0, 6.3))
    assert fit.breakpoint == pytest.approx(6.3, rel=1e-4)
    assert (fit.k1, fit.k2, fit.y0) == pytest.approx((1.0, 3.0, 0.5), rel=1e-6)
    lo, hi = fit.breakpoint_interval
    assert lo <= fit.breakpoint <= hi


#: a patch test every 500 kg from 500 to 10000 kg
DENSE_LOADS_KG = tuple(range(500, 10001, 500))


@pytest.mark.parametrize("tyre", [T.TYRE_A, T.TYRE_B])
def test_breakpoint_recovered_within_5_percent(tyre):
    """Must show: the patch (shoulder) breakpoint from generated data with a known breakpoint.

    20 loads (every 500 kg), the generator's noise (2 mm on the length), ten
    noise draws, three pressures: every fitted breakpoint within 5 %.
    """
    err = []
    for seed in range(10):
        df = _si(T.patch_table(tyre, np.random.default_rng(seed), loads_kg=DENSE_LOADS_KG))
        model = fit_patch(df)
        for p_bar in T.PRESSURES_BAR:
            true = T.shoulder_load(tyre, p_bar)
            assert model.shoulder_load(p_bar * 1e5) == pytest.approx(true, rel=0.05), (seed, p_bar)
            err.append(model.shoulder_load(p_bar * 1e5) / true - 1)
    assert np.sqrt(np.mean(np.square(err))) < 0.025


def test_breakpoint_with_the_seed_loads_is_unbiased():
    """With the seed's 12 loads the breakpoint scatters more (about 3 % rms), but without bias."""
    t = T.TYRE_A
    err = []
    for seed in range(20):
        model = fit_patch(_si(T.patch_table(t, np.random.default_rng(100 + seed))))
        err.append(model.shoulder_load(7.4e5) / T.shoulder_load(t, 7.4) - 1)
    err = np.array(err)
    assert abs(err.mean()) < 0.02
    assert np.sqrt(np.mean(err**2)) < 0.05


def test_bundled_patch_breakpoint():
    from tyrefit.io.datasets import data_path
    from tyrefit.io.readers import read_data

    for t, name in ((T.TYRE_A, "tyre_a_patch.csv"), (T.TYRE_B, "tyre_b_patch.csv")):
        model = fit_patch(read_data(data_path("truck", name)))
        assert model.shoulder_load(7.4e5) == pytest.approx(T.shoulder_load(t, 7.4), rel=0.05)


def test_width_and_gradients_recovered():
    t = T.TYRE_A
    model = fit_patch(_si(T.patch_table(t, np.random.default_rng(7))))
    f = model._fit_at(7.4e5)
    assert f.width.y_max == pytest.approx(t.shoulder_width, rel=0.02)
    assert f.width.x_scale == pytest.approx(t.width_load_kg * G0, rel=0.15)
    assert f.length.k1 == pytest.approx(t.length_k1 / G0, rel=0.1)
    assert f.length.k2 == pytest.approx(t.length_k2 / G0, rel=0.1)


def test_pressure_law_recovers_exponent_and_interpolates():
    t = T.TYRE_A
    model = fit_patch(_si(T.patch_table(t, np.random.default_rng(3))))
    law = model.laws["length"]["breakpoint"]
    assert law.kind == "power"
    assert law.m == pytest.approx(t.pressure_exponent, abs=0.15)
    # between tested pressures: the law, close to the truth
    fz = 40e3
    true_len = T.patch_truth(t, fz, 8.2)[0]
    assert model.length(fz, 8.2e5) == pytest.approx(true_len, rel=0.03)
    # higher pressure -> shorter, narrower, smaller patch
    assert model.length(fz, 9e5) < model.length(fz, 5.9e5)
    assert model.area(fz, 9e5) < model.area(fz, 5.9e5)


def test_single_pressure_and_fz_column():
    t = T.TYRE_B
    df = _si(T.patch_table(t, np.random.default_rng(1), loads_kg=DENSE_LOADS_KG, pressures_bar=(7.4,)))
    df = df.rename(columns={"load": "fz"})
    df = df.drop(columns=["pressure"])
    model = fit_patch(df)
    assert len(model.fits) == 1 and not model.laws
    # this checks the one-pressure path, not the precision (about 2 % rms, see above)
    assert model.shoulder_load() == pytest.approx(T.shoulder_load(t, 7.4), rel=0.08)
    assert model.length(30e3, 6e5) == model.length(30e3)   # one pressure: used as it is


def test_errors_name_the_problem():
    df = pd.DataFrame({"load": [1e3, 2e3, 3e3, 4e3], "length": [0.1, 0.12, 0.14, 0.17]})
    with pytest.raises(DataError, match="at least 5 distinct loads"):
        fit_patch(df)
    with pytest.raises(ColumnError, match="length"):
        fit_patch(df.drop(columns=["length"]).assign(width=0.2))
    with pytest.raises(ColumnError, match="load"):
        fit_patch(df.drop(columns=["load"]))
    model = fit_patch(pd.DataFrame({"load": np.arange(1, 8) * 1e4, "length": np.linspace(0.1, 0.3, 7)}))
    with pytest.raises(ColumnError, match="width"):
        model.width(1e4)


def test_plot_returns_axes():
    df = _si(T.patch_table(T.TYRE_A, np.random.default_rng(0)))
    axes = fit_patch(df).plot(df)
    assert len(axes) == 3 and axes[0].get_xlabel() == "load [kg]"
