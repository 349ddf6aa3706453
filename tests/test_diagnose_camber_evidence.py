"""Camber is named only where the residual differs between camber levels (tyrefit.diagnose.engine._camber_evidence).

With one-sided cambers (0 and +4 deg) a camber term is a "shift for the cambered sweeps" and can take up part
of any misfit common to every sweep; the validation's asymmetric-curvature truth (no camber at all) had camber
named that way.
"""

from __future__ import annotations

import numpy as np

from tyrefit.diagnose import diagnose, prepare
from tyrefit.diagnose.engine import CAMBER_ALPHA, _camber_evidence
from tyrefit.synthetic.validation.cases import make_case


def _data():
    case = make_case("grid8", "iid", None, 0)
    return prepare(case.data, rated_load=case.rated_load)


def test_a_contrast_repeated_from_load_to_load_is_camber():
    d = _data()
    rng = np.random.default_rng(0)
    gamma = d.inputs.camber
    # a camber thrust's residual: a force growing with camber, fading with slip, the same at every load
    resid = 150.0 * (gamma / np.radians(4.0)) * np.cos(d.inputs.slip_angle * 4) + rng.normal(0, 20.0, d.n)
    assert _camber_evidence(d, resid, CAMBER_ALPHA) is None


def test_a_misfit_common_to_every_camber_is_not_camber():
    d = _data()
    rng = np.random.default_rng(1)
    # the same shape misfit at both cambers (an asymmetric curvature the model lacks) plus noise
    resid = 150.0 * np.sign(d.inputs.slip_angle) * np.abs(np.sin(d.inputs.slip_angle * 6)) + rng.normal(0, 20.0, d.n)
    why = _camber_evidence(d, resid, CAMBER_ALPHA)
    assert why is not None and "common to every camber" in why


def test_asymmetric_curvature_on_one_sided_cambers_does_not_name_camber():
    """grid8, iid noise, seed 2: camber_thrust was accepted after asymmetry_curvature on a tyre without camber."""
    case = make_case("grid8", "iid", "asym_curvature", 2)
    dg = diagnose(case.data, rated_load=case.rated_load, seed=2)
    assert "asymmetry_curvature" in dg.accepted
    assert not any(a.startswith("camber") for a in dg.accepted)
    assert "common to every camber" in dg.candidates["camber_thrust"].reason


def test_real_camber_thrust_is_still_named():
    case = make_case("grid8", "iid", "camber", 2)
    dg = diagnose(case.data, rated_load=case.rated_load, seed=2)
    assert any(a.startswith("camber") for a in dg.accepted)


def test_a_load_dependent_curvature_under_correlated_noise_does_not_name_pressure():
    """grid24 (2 pressures), AR(1) noise, seed 0: pressure_grip was accepted beside curvature_load on a tyre whose
    grip does not depend on pressure; its contrast between the pressures does not repeat from load to load."""
    case = make_case("grid24", "ar1", "curvature", 0)
    dg = diagnose(case.data, rated_load=case.rated_load, seed=0)
    assert not any(a.startswith("pressure") for a in dg.accepted)
    assert "common to every pressure" in dg.candidates["pressure_grip"].reason


def test_real_pressure_is_still_named():
    case = make_case("grid24", "ar1", "pressure", 0)
    dg = diagnose(case.data, rated_load=case.rated_load, seed=0)
    assert any(a.startswith("pressure") for a in dg.accepted)


def test_two_loads_leave_camber_to_the_held_out_evidence():
    """2 loads x 2 cambers (the bundled TTC-style record of MFeval's MF 6.1 tyre, which has camber thrust): one
    load-to-load comparison is too weak to veto; camber_thrust is named as the held-out sweeps confirm it."""
    import tyrefit as tf

    ds = tf.read_data(tf.datasets.path("ttc_mf61/cornering.dat"), convention="sae")
    d = prepare(ds, rated_load=6000.0)
    assert _camber_evidence(d, np.random.default_rng(0).normal(size=d.n), CAMBER_ALPHA) is None
    dg = diagnose(ds, rated_load=6000.0)
    assert "camber_thrust" in dg.accepted
