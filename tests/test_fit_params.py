"""tf.fit takes lmfit Parameters (issue 27 item 7): start values, holds, bounds and expressions, shown back by
``lmfit_params()`` and ``fit_report()``.

PAC89 on generated lateral sweeps (the Adams PAC89 example set at 2, 5 and 8 kN, camber 0, 0.5 % noise):
what a hold or a bound does to the other coefficients is physics (the D law and the shape compensate),
not only what the result says.  Magic Formula 6.1 on the bundled FSAE-format cornering record.
"""

from __future__ import annotations

import re

import lmfit
import numpy as np
import pytest

import tyrefit as tf
from tyrefit.errors import DataError
from tyrefit.io.readers import Dataset
from tyrefit.models import pac89
from tyrefit.synthetic.pac89_example import EXAMPLE, lateral_sweeps

LOADS = (2000.0, 5000.0, 8000.0)


@pytest.fixture(scope="module")
def lateral():
    df = lateral_sweeps(loads=LOADS, cambers_deg=(0.0,), noise=0.005)
    return Dataset(df.drop(columns=["mz"]), kind="slip_angle", source="generated")


@pytest.fixture(scope="module")
def free(lateral):
    return tf.fit(lateral)


def _params(**spec):
    p = lmfit.Parameters()
    for name, kw in spec.items():
        p.add(name, **kw)
    return p


def _rmse(lateral, coefficients):
    df = lateral.df
    fy = pac89.lateral_force(coefficients, df["fz"].to_numpy(), df["slip_angle"].to_numpy(), 0.0)
    return float(np.sqrt(np.mean((fy - df["fy"].to_numpy()) ** 2)))


def test_the_free_fit_finds_the_generating_set(free):
    """The reference the holds and bounds below are measured against."""
    v = free.values
    assert v["a0"] == pytest.approx(EXAMPLE["a0"], rel=0.03)
    assert v["a2"] == pytest.approx(EXAMPLE["a2"], rel=0.01)
    assert free.rmse < 1.1 * free.noise_floor


def test_a_held_coefficient_keeps_its_value_and_the_others_compensate(lateral, free):
    """a0 (the shape factor C) held at a wrong 1.2: exactly 1.2 in the tyre; the shape's other factors (E, BCD)
    move so that the curve stays close to the data, far closer than the free fit's coefficients with C = 1.2."""
    res = tf.fit(lateral, params=_params(a0={"value": 1.2, "vary": False}))
    assert res.values["a0"] == 1.2
    p = res.lmfit_params()
    assert p["a0"].vary is False and p["a0"].value == 1.2
    assert p["a7"].vary and p["a3"].vary
    # compensation: the curvature law moves a long way (C and E trade along the peak's shape)
    assert abs(res.values["a7"] - free.values["a7"]) > 0.3
    naive = _rmse(lateral, dict(free.values, a0=1.2))
    assert res.rmse < 0.5 * naive
    # a wrong hold costs accuracy: the data want C = 1.65
    assert res.rmse > 1.1 * free.rmse
    assert any("held (vary=False) at a0 = 1.2" in n for n in res.notes)
    assert re.search(r"a0:\s+1\.2 \(fixed\)", res.fit_report(show_correl=False))


def test_held_at_the_free_fits_value_changes_nothing(lateral, free):
    """Holding a coefficient at the value the data want gives the free fit back (the hold is honoured, not a
    different problem)."""
    a0 = free.values["a0"]
    res = tf.fit(lateral, params=_params(a0={"value": a0, "vary": False}))
    assert res.values["a0"] == a0
    assert res.rmse == pytest.approx(free.rmse, rel=1e-3)
    assert res.values["a2"] == pytest.approx(free.values["a2"], rel=1e-3)


def test_an_upper_bound_below_the_truth_is_reached_and_shown(lateral, free):
    """a2 (the D law's intercept, true 1250) bounded to at most 1200: the fit ends on the bound, the load slope a1
    moves to keep the peak friction near the data's, and lmfit_params shows the bound given."""
    res = tf.fit(lateral, params=_params(a2={"value": 1150.0, "max": 1200.0}))
    assert res.values["a2"] == pytest.approx(1200.0, rel=1e-9)
    assert res.values["a2"] <= 1200.0
    p = res.lmfit_params()
    assert p["a2"].max == 1200.0 and p["a2"].vary
    # D/Fz = a1 Fz + a2: with the intercept capped the slope rises (less negative) to hold D at the loads tested
    assert res.values["a1"] > free.values["a1"] + 5.0
    d_fit = res.values["a1"] * np.array(LOADS) / 1e3 + res.values["a2"]
    d_true = EXAMPLE["a1"] * np.array(LOADS) / 1e3 + EXAMPLE["a2"]
    assert np.max(np.abs(d_fit / d_true - 1)) < 0.06
    assert any("a2 ended at its upper bound 1200 (the bound given" in n for n in res.notes)
    # the law's ends are checked after the fit (fitted in its own coefficients when a member is bounded)
    assert any("a1 Fz + a2 not constrained" in c and c.endswith("holds") for c in res.constraints)


def test_a_lower_bound_is_intersected_with_the_physical_one(lateral):
    """a0 >= 0.3 is PAC89's own bound (C > 0): a looser one given keeps it, a tighter one replaces it."""
    res = tf.fit(lateral, params=_params(a0={"value": 1.8, "min": 0.1, "max": 1.5}))
    p = res.lmfit_params()
    assert res.values["a0"] == pytest.approx(1.5, rel=1e-9)
    assert p["a0"].min == 0.3 and p["a0"].max == 1.5


def test_a_held_coefficient_shows_the_bounds_given(lateral):
    """lmfit_params() gives back what was asked: a held a0 with its bounds, vary=False."""
    res = tf.fit(lateral, params=_params(a0={"value": 1.4, "vary": False, "min": 1.0, "max": 1.4}))
    p = res.lmfit_params()
    assert res.values["a0"] == 1.4
    assert (p["a0"].vary, p["a0"].min, p["a0"].max, p["a0"].value) == (False, 1.0, 1.4, 1.4)


def test_bounds_outside_the_physical_range_are_refused(lateral):
    with pytest.raises(DataError, match=r"bounds given for a0, \[5, 6\], are outside its physical range \[0.3, 3\]"):
        tf.fit(lateral, params=_params(a0={"value": 5.5, "min": 5.0, "max": 6.0}))


def test_an_expression_is_held_at_its_value_as_documented(lateral):
    """lmfit evaluates a7 = -10 a6 at the values given (a6 = -0.05: a7 = 0.5); tyrefit holds a7 there and says
    that it is not a constraint during the fit: a6 is fitted on, a7 is no longer -10 a6 after it."""
    res = tf.fit(lateral, params=_params(a6={"value": -0.05}, a7={"expr": "-10*a6"}))
    assert res.values["a7"] == pytest.approx(0.5, abs=1e-15)
    assert res.lmfit_params()["a7"].vary is False
    assert res.values["a6"] != pytest.approx(-0.05, rel=0.05)
    assert res.values["a7"] != pytest.approx(-10 * res.values["a6"], rel=0.05)
    assert any("a7 = '-10*a6' held at 0.5" in n and "not a constraint" in n for n in res.notes)


def test_start_values_outside_the_multistart_basin_still_reach_the_minimum(lateral, free):
    """A start value is a start (the first of the multi-start): a poor one does not strand the fit."""
    res = tf.fit(lateral, params=_params(a0={"value": 2.6}, a7={"value": -3.0}))
    assert res.rmse == pytest.approx(free.rmse, rel=1e-3)
    assert any("start values given for a0, a7" in n for n in res.notes)


def test_a_start_value_the_data_cannot_move_is_the_value_held(lateral, free):
    """Camber 0 only: a5 (the camber term of the cornering stiffness BCD) is not identifiable and is held; at 0
    without params, at the value given with it (the value of an lmfit parameter the fit does not vary), and the
    cornering stiffness at camber 2 deg shows it: BCD (1 - a5 |gamma|), gamma in degrees."""
    assert free.values["a5"] == 0.0 and "a5" in free.not_identifiable
    res = tf.fit(lateral, params=_params(a5={"value": 0.02}))
    assert res.values["a5"] == 0.02 and res.lmfit_params()["a5"].vary is False
    g, da = np.radians(2.0), np.radians(0.05)

    def stiffness(r):
        return (r.tyre.fy(5000.0, -da, g) - r.tyre.fy(5000.0, da, g)) / (2 * da)

    assert stiffness(res) / stiffness(free) == pytest.approx(1 - 0.02 * 2.0, rel=0.005)


def test_unknown_names_and_other_objects_are_refused(lateral):
    with pytest.raises(DataError, match=r"params=: a14 not a PAC89 coefficient.*did you mean"):
        tf.fit(lateral, params=_params(a14={"value": 1.0}))
    with pytest.raises(DataError, match=r"params=: PDY1 not a PAC89 coefficient"):
        tf.fit(lateral, params=_params(PDY1={"value": 1.0}))
    with pytest.raises(DataError, match=r"params=: an lmfit.Parameters"):
        tf.fit(lateral, params={"a0": 1.2})
    with pytest.raises(DataError, match=r"params=: a0 is held .* give a value"):
        tf.fit(lateral, params=_params(a0={"vary": False}))


# --------------------------------------------------------------------------- Magic Formula 6.1

@pytest.fixture(scope="module")
def cornering():
    return tf.read_data(tf.datasets.path("ttc_mf61/cornering.dat"), convention="sae")


@pytest.fixture(scope="module")
def mf_free(cornering):
    return tf.fit(cornering, model="mf61")


def test_mf61_held_coefficient_stays_at_its_value(cornering, mf_free):
    """PDY1 (the peak lateral friction at the nominal load) held 10 % below the data's: exactly that value in the
    tyre, not fitted, vary=False in lmfit_params; the force error grows (a wrong peak friction costs accuracy)."""
    pdy1 = round(0.9 * mf_free.params["PDY1"], 4)
    res = tf.fit(cornering, model="mf61", params=_params(PDY1={"value": pdy1, "vary": False}))
    assert res.params["PDY1"] == pdy1
    assert "PDY1" not in res.fitted and "PDY1" in mf_free.fitted
    p = res.lmfit_params()
    assert p["PDY1"].vary is False and p["PDY1"].value == pdy1
    assert p["PCY1"].vary
    assert res.rmse > 1.5 * mf_free.rmse


def test_mf61_held_at_the_free_value_gives_the_free_fit(cornering, mf_free, monkeypatch):
    """Held at the value the free fit found, with a start value for PCY1 (the Fy0 stage's first start instead
    of its Eq. 2-4 estimate) and one for PKY4 (not identifiable from 2 loads: held at it instead of its neutral 2)."""
    from tyrefit.fitting import mf

    first = {}
    starts = mf._starts

    def spy(stage, c0):
        first.setdefault(stage.name, dict(c0))
        return starts(stage, c0)

    monkeypatch.setattr(mf, "_starts", spy)
    pdy1 = mf_free.params["PDY1"]
    res = tf.fit(cornering, model="mf61", params=_params(PDY1={"value": pdy1, "vary": False}, PCY1={"value": 1.3},
                                                          PKY4={"value": 1.9}))
    assert res.params["PDY1"] == pdy1
    assert res.rmse == pytest.approx(mf_free.rmse, rel=0.02)
    assert first["Fy0"]["PCY1"] == 1.3 and first["Fy0"]["PDY1"] == pdy1
    assert mf_free.params["PKY4"] == 2.0 and "PKY4" in mf_free.not_identifiable
    assert res.params["PKY4"] == 1.9 and res.lmfit_params()["PKY4"].vary is False
    assert any("start values given for PCY1, PKY4" in n for n in res.notes)


def test_mf61_bounds_and_unknown_names_are_refused(cornering):
    with pytest.raises(DataError, match="params=: bounds on MF coefficients are not supported yet: PDY1"):
        tf.fit(cornering, model="mf61", params=_params(PDY1={"value": 1.0, "max": 2.0}))
    with pytest.raises(DataError, match="params=: a0 not a Magic Formula coefficient"):
        tf.fit(cornering, model="mf61", params=_params(a0={"value": 1.0}))


def test_one_load_fit_keeps_a_held_or_given_a3():
    """One load level: the BCD law's a4 is held at its estimate, and a3 with it - unless the caller held or
    gave a3 (fit_pac89's ``fixed`` / ``initial``): a held a3 = 1234 came back as the estimate 1428."""
    import numpy as np
    import pandas as pd

    from tyrefit.fitting.engine import fit_pac89
    from tyrefit.models import pac89

    p = {"a0": 1.5, "a1": -20.0, "a2": 1100.0, "a3": 1500.0, "a4": 8.0, "a6": -0.1, "a7": -0.5}
    p = {k: p.get(k, 0.0) for k in pac89.LATERAL}
    a = np.radians(np.linspace(-12, 12, 49))
    fz = np.full(49, 4000.0)
    df = pd.DataFrame({"run": 0, "fz": fz, "slip_angle": a, "camber": 0.0, "fy": pac89.lateral_force(p, fz, a)})
    held = fit_pac89(df, vary=["a0", "a2", "a3", "a7"], fixed={"a3": 1234.0})
    assert held.lmfit_params()["a3"].value == 1234.0
