"""Stopping distance, treadwear-traction law and emission ratio (seed 000 Eq. 15-18, 41-43)."""

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose

from tyrefit.io.datasets import data_path
from tyrefit.errors import DataError
from tyrefit.nomenclature import G0
from tyrefit.sim.traction import (HPWIZARD, K_TYPICAL, emission_ratio, fit_treadwear_traction,
                                  mu_from_stopping_distance, peak_lateral_acceleration, stopping_distance,
                                  traction_from_data, vehicle_peak_friction)


def test_stopping_distance_and_its_inverse():
    v0 = np.array([8.0, 22.352, 33.3])
    mu = np.array([0.5, 0.9, 1.1])
    d = stopping_distance(v0, mu)
    assert_allclose(mu_from_stopping_distance(d, v0), mu, rtol=1e-12)
    # without drag: v0^2 / (2 g (mu + f_r)); drag shortens the distance
    d0 = stopping_distance(v0, mu, K=0.0)
    assert_allclose(d0, v0**2 / (2 * G0 * (mu + 0.013)))
    assert np.all(d < d0)
    assert_allclose(stopping_distance(v0, mu, K=1e-9), d0, rtol=1e-6)


def test_emission_ratio_and_vehicle_friction():
    assert_allclose(emission_ratio(0.81, 1.0, 0.15), 0.81 ** (1 / 0.15))
    assert_allclose(emission_ratio(0.81, 1.0, 0.15), 0.2454, atol=1e-4)
    assert_allclose(emission_ratio(1.0, 1.0, 0.15), 1.0)
    assert_allclose(vehicle_peak_friction(0.9, 1.1, 1.4, 1.4), 1.0)
    assert_allclose(vehicle_peak_friction(0.9, 1.1, 1.0, 2.0), (2.0 * 0.9 + 1.0 * 1.1) / 3.0)
    assert_allclose(peak_lateral_acceleration(0.8, 1.0), 0.8 * G0)


def test_fit_recovers_a_power_law():
    tw = np.linspace(200, 800, 15)
    fit = fit_treadwear_traction(tw, 2.25 * tw ** -0.15)
    assert_allclose([fit.a, fit.b], [2.25, 0.15], rtol=1e-6)
    assert_allclose(fit.treadwear_for(fit.predict(400.0)), 400.0)
    assert_allclose(fit.k(0.81, 1.0), 0.81 ** (1 / 0.15), rtol=1e-6)


def test_bundled_table_agrees_with_hpwizard():
    table = traction_from_data(data_path("sim", "braking_utqg.csv"))
    fit = table.fit
    assert len(table.names) == 15
    assert_allclose(table.initial_speed, 50 * 0.44704)                       # 50 mph
    assert np.all((table.mu > 0.75) & (table.mu < 1.2))
    # within two standard errors of HPwizard's published law
    assert abs(fit.b - HPWIZARD["b"]) < 2 * fit.b_stderr
    assert abs(fit.a - HPWIZARD["a"]) < 2 * fit.a_stderr
    assert fit.r2 > 0.8
    assert table.K == K_TYPICAL


def test_traction_input_errors():
    with pytest.raises(DataError, match="missing column"):
        traction_from_data(pd.DataFrame({"treadwear": [300, 400, 500]}))
    bad = pd.DataFrame({"treadwear": [300, 400, 500], "stopping_distance": [30.0, 30.0, 2000.0],
                        "initial_speed": [22.0, 22.0, 22.0]})
    with pytest.raises(DataError, match="mu = "):
        traction_from_data(bad)
    with pytest.raises(DataError, match="at least 3"):
        fit_treadwear_traction([300, 400], [1.0, 0.9])
    with pytest.raises(DataError, match="same treadwear"):
        fit_treadwear_traction([300, 300, 300], [1.0, 0.9, 0.95])
