"""Shared test configuration."""

import os

import pytest

import matplotlib

matplotlib.use("Agg")

from hypothesis import HealthCheck, settings  # noqa: E402

# CI runs a bounded fuzz budget; HYPOTHESIS_PROFILE=long for a deeper local run.
settings.register_profile("ci", max_examples=200, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("long", max_examples=5000, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


@pytest.fixture(scope="session")
def axles():
    """The synthetic soft and hard tyres' true PAC89 at the default vehicle's static wheel loads."""
    from tyrefit.sim.tyres import AxleTyre
    from tyrefit.sim.vehicle import DEFAULT_VEHICLE as P
    from tyrefit.synthetic.vehicle_tyres import true_tyre

    soft, hard = true_tyre("soft"), true_tyre("hard")
    return {"soft_f": AxleTyre(soft, P.axle_load_front / 2), "soft_r": AxleTyre(soft, P.axle_load_rear / 2),
            "hard_f": AxleTyre(hard, P.axle_load_front / 2)}


@pytest.fixture(scope="session")
def six():
    """The diagnosis benchmark's commonest rig layout: six loads, one sweep each (294 points), degressive
    friction, AR(1) noise (tyrefit.synthetic.hidden, seed 3), prepared for diagnose."""
    from tyrefit.diagnose import prepare
    from tyrefit.synthetic.hidden import make_case, rig_grid

    case = make_case(("load_friction",), "ar1", seed=3,
                     grid=rig_grid(loads=(2000.0, 3200.0, 4400.0, 5600.0, 6800.0, 8000.0), cambers_deg=(0.0,),
                                   pressures=(220e3,)))
    return prepare(case.data, rated_load=case.rated_load)
