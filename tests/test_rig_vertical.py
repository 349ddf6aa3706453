"""Vertical stiffness (seed 003 Fig. 3): two gradients, hysteresis loop, .tir and Chrono values."""

import numpy as np
import pandas as pd
import pytest

from tyrefit.errors import ColumnError, DataError
from tyrefit.nomenclature import G0
from tyrefit.rig.patch import fit_patch
from tyrefit.rig.vertical import fit_vertical, loop_energy
from tyrefit.synthetic import truck as T


def _si(df: pd.DataFrame) -> pd.DataFrame:
    return pd.DataFrame({"run": df["run"], "pressure": df["pressure [bar]"] * 1e5, "phase": df["phase"],
                         "vertical_displacement": df["vertical_displacement [mm]"] * 1e-3, "fz": df["fz [N]"]})


@pytest.fixture(scope="module")
def tyre_a():
    rng = np.random.default_rng(11)
    df = _si(T.vertical_table(T.TYRE_A, rng))
    return df, fit_vertical(df)


def test_loop_energy_of_a_rectangle():
    # a rectangle 0.02 m x 1000 N traversed once encloses 20 J
    assert loop_energy([0, 0.02, 0.02, 0], [0, 0, 1000, 1000]) == pytest.approx(20.0)
    assert loop_energy([0, 0.01, 0.02], [0, 1, 2]) == pytest.approx(0.0)


def test_gradients_and_breakpoint_recovered(tyre_a):
    _, model = tyre_a
    t = T.TYRE_A
    for f in model.fits:
        p_bar = f.pressure / 1e5
        s = 0.3 + 0.7 * p_bar / t.p_ref_bar
        assert f.loading.k1 == pytest.approx(t.kv1 * s, rel=0.03)
        assert f.loading.k2 == pytest.approx(t.kv2 * s, rel=0.03)
        assert f.breakpoint_force == pytest.approx(T.shoulder_load(t, p_bar), rel=0.06)
        # unloading is softer than loading (hysteresis), the loop dissipates energy
        assert f.unloading.k1 < f.loading.k1 and f.unloading.k2 < f.loading.k2
        assert 0.02 < f.loop_energy / f.loading_work < 0.2
    # stiffer at higher pressure
    k = [f.loading.k1 for f in model.fits]
    assert k == sorted(k)


def test_breakpoint_matches_the_patch(tyre_a):
    _, model = tyre_a
    patch = fit_patch(pd.DataFrame({
        "load": (d := T.patch_table(T.TYRE_A, np.random.default_rng(2), loads_kg=tuple(range(500, 10001, 500))))
        ["load [kg]"] * G0, "pressure": d["pressure [bar]"] * 1e5, "length": d["length [mm]"] * 1e-3}))
    tab = model.table(patch)
    assert (tab["difference [%]"].abs() < 8).all()


def test_vertical_stiffness_and_curve(tyre_a):
    _, model = tyre_a
    fr = 4250 * G0
    k = model.vertical_stiffness(fr, 7.4e5)
    f = model.at(7.4e5)
    assert f.unloading.k1 < k < f.loading.k1        # the middle of the loop
    curve = model.curve(7.4e5)
    d, F = np.array(curve).T
    assert curve[0] == (0.0, 0.0)
    assert np.all(np.diff(d) > 0) and np.all(np.diff(F) >= 0)
    assert F[-1] == pytest.approx(f.max_force, rel=0.01)


def test_loading_only_and_errors():
    df = _si(T.vertical_table(T.TYRE_B, np.random.default_rng(0), pressures_bar=(7.4,)))
    up = df[df["phase"] > 0].drop(columns=["phase", "pressure"])
    model = fit_vertical(up)
    assert model.fits[0].unloading is None and np.isnan(model.fits[0].loop_energy)
    assert model.vertical_stiffness(30e3) == pytest.approx(model.fits[0].loading.k1)
    with pytest.raises(ColumnError, match="vertical_displacement"):
        fit_vertical(up.drop(columns=["vertical_displacement"]))
    with pytest.raises(DataError, match="fewer than 5 loading points"):
        fit_vertical(up.iloc[:3])


def test_plot(tyre_a):
    df, model = tyre_a
    ax = model.plot(df)
    assert ax.get_xlabel() == "vertical deflection [mm]"
