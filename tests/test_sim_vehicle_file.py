"""Vehicle files and presets, load transfer, the steady-state ramp against closed form, envelope checks."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from tyrefit.errors import DataError
from tyrefit.nomenclature import G0
from tyrefit.sim.handling import _states, closed_form_understeer_gradient, run_ramp
from tyrefit.sim.loads import wheel_loads
from tyrefit.sim.tyres import default_tyres
from tyrefit.sim.vehicle import DEFAULT_VEHICLE
from tyrefit.sim.vehicle_file import PRESETS, load_vehicle, preset_path

GOOD = """
mass = 280.0
yaw_inertia = 110.0
wheelbase = 1.53
cg_to_front = 0.811
cg_height = 0.28
track = 1.22
drag_area = 1.2
downforce_area = 3.0
rolling_resistance = 0.02
[front]
wheel_radius = 0.2
wheel_inertia = 0.6
drive = false
torque_max = 0.0
power_max = 0.0
[rear]
wheel_radius = 0.2
wheel_inertia = 0.6
drive = true
torque_max = 1000.0
power_max = 80000.0
"""


@pytest.fixture(scope="module")
def tyres():
    return default_tyres()


def test_presets_are_files_and_ev_is_the_old_default():
    for name in PRESETS:
        assert preset_path(name).is_file()
        assert load_vehicle(name).name == name
    assert load_vehicle("ev").to_params() == DEFAULT_VEHICLE      # bit for bit: same floats
    fsae = load_vehicle("fsae")
    assert fsae.mass == 280.0 and fsae.wheelbase == 1.53 and fsae.downforce_area > 0


def test_toml_and_json_files(tmp_path):
    import json
    import tomllib

    p = tmp_path / "car.toml"
    p.write_text(GOOD)
    a = load_vehicle(p)
    q = tmp_path / "car.json"
    q.write_text(json.dumps(tomllib.loads(GOOD)))
    b = load_vehicle(q)
    assert a.to_params() == b.to_params() and a.name == "car"
    assert a.to_dict()["units"]["mass"] == "kg"


@pytest.mark.parametrize("old, new, match", [
    ("mass = 280.0", "mass = -280.0", r"mass \[kg\] = -280.0 is outside the accepted 50 to 60000 kg"),
    ("mass = 280.0", "mass = 0.28", r"mass \[kg\] = 0.28 .*tonnes\?"),
    ("mass = 280.0", "mass = 1.8", r"mass \[kg\] = 1.8 is outside the accepted 50 to 60000 kg \(tonnes\? give the "
                                   r"mass in kg\)"),
    ("mass = 280.0", "mass = 0.01", r"mass \[kg\] = 0.01 is outside the accepted 50 to 60000 kg$"),
    ("wheelbase = 1.53", "wheelbase = 1530", r"wheelbase \[m\] = 1530 .*0.5 to 12 m .*millimetres"),
    ("cg_to_front = 0.811", "cg_to_front = 1.7", r"cg_to_front \[m\] = 1.7 puts the CG outside the wheelbase; "
                                                 r"accepted strictly between 0 and wheelbase = 1.53 m"),
    ("cg_height = 0.28\n", "", r"missing key 'cg_height' \[m\], accepted 0.05 to 3 m"),
    ("track = 1.22", "trak = 1.22", r"unknown key 'trak' \(did you mean 'track'\?\)"),
    ("rolling_resistance = 0.02", "rolling_resistance = 1.5", r"rolling_resistance \[-\] = 1.5 .*fraction"),
    ("power_max = 80000.0", "power_max = 80.0", r"power_max \[W\] = 80.0 is below 1000 W .*kilowatts"),
])
def test_bad_vehicle_files_one_line(tmp_path, old, new, match):
    p = tmp_path / "bad.toml"
    assert old in GOOD
    p.write_text(GOOD.replace(old, new, 1))
    with pytest.raises(DataError, match=match) as e:
        load_vehicle(p)
    assert "\n" not in str(e.value)


def test_unknown_preset():
    with pytest.raises(DataError, match=r"neither a preset .*did you mean 'fsae'"):
        load_vehicle("fsea")


def test_bad_vehicle_cli_exit_2(tmp_path, capsys):
    from tyrefit.cli import _Parser, _allow_unphysical, _common, _main
    from tyrefit.commands.sim import add_scenario_parsers

    p = _Parser(prog="tyrefit")
    sub = p.add_subparsers(dest="command")
    ss = sub.add_parser("sim").add_subparsers(dest="scenario")
    add_scenario_parsers(ss, _common(), _allow_unphysical)
    f = tmp_path / "bad.toml"
    f.write_text(GOOD.replace("wheelbase = 1.53", "wheelbase = 1530"))
    assert _main(p.parse_args(["sim", "ramp", "--vehicle", str(f)])) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "wheelbase [m] = 1530" in err[0] and "Traceback" not in err[0]


def test_constant_deceleration_load_transfer():
    """Closed form: the front axle loses m a h / L; the loads carry the weight and the pitch moment balances."""
    v = load_vehicle("light_truck")
    a = -0.8 * G0                      # braking
    w = wheel_loads(v, ax=a)
    front, rear = w["fl"] + w["fr"], w["rl"] + w["rr"]
    transfer = front - v.mass * G0 * v.lr / v.wheelbase
    np.testing.assert_allclose(transfer, -v.mass * a * v.cg_height / v.wheelbase, rtol=1e-12)
    np.testing.assert_allclose(front + rear, v.mass * G0, rtol=1e-12)
    # moments about the CG: tyre forces (sum m a) at the ground, height h
    np.testing.assert_allclose(front * v.lf - rear * v.lr, -v.mass * a * v.cg_height, rtol=1e-9)


def test_steady_cornering_lateral_transfer_and_aero(tyres):
    v = load_vehicle("fsae")
    st = _states(v, *tyres[:1] * 2, np.array([0.5 * G0, 1.0 * G0]), v.ramp_radius)
    total = (st["fz_fr"] - st["fz_fl"] + st["fz_rr"] - st["fz_rl"]) / 2
    np.testing.assert_allclose(total, v.mass * st["ay"] * v.cg_height / v.track, rtol=1e-3)
    load = st["fz_fl"] + st["fz_fr"] + st["fz_rl"] + st["fz_rr"]
    np.testing.assert_allclose(load, v.mass * G0 + v.downforce_coefficient * st["speed"] ** 2, rtol=1e-12)


def test_understeer_gradient_matches_bicycle_model_within_1pct(tyres):
    """Linear range, no load transfer, a large radius: the ramp's gradient is (m/L)(l_r/C_f - l_f/C_r)."""
    v = replace(load_vehicle("ev"), cg_height=0.05)
    front, rear = tyres
    ay = np.linspace(0.001, 0.01, 10) * G0
    st = _states(v, front, rear, ay, 1000.0)
    k = math.degrees(np.polyfit(ay / G0, st["steer"], 1)[0])
    cf = closed_form_understeer_gradient(v, front, rear)["understeer_gradient_deg_per_g"]
    assert abs(k / cf - 1) < 0.01


def test_ramp_to_the_limit_ev(tyres):
    r = run_ramp(load_vehicle("ev"), *tyres)
    d = r.to_json()
    assert 0.5 < d["lateral_limit_g"] < 1.2
    assert d["understeer_gradient_deg_per_g"] > 0            # hard front, soft rear: understeer
    assert "front axle" in d["limit"]
    s = r.states
    assert np.all(np.diff(s["steer"]) > -1e-9)               # steering grows towards the limit


def test_simulate_ramp_json_and_strict(tyres, tmp_path):
    from tyrefit.errors import ValueRangeError
    from tyrefit.sim.api import simulate

    run = simulate("ramp", vehicle="light_truck")
    d = run.json
    for key in ("understeer_gradient_deg_per_g", "lateral_limit_g", "vehicle", "tyres"):
        assert key in d
    assert set(d["tyres"]) == {"front", "rear"}
    for s in d["tyres"].values():
        assert 0.0 <= s["outside_envelope"] <= 1.0 and "file" in s and "worst" in s
    assert d["vehicle"]["mass"] == 2500.0
    # a vehicle too light for the bundled tyres (declared from about 2 kN): every point outside
    run = simulate("ramp", vehicle="fsae")
    assert run.json["tyres"]["front"]["outside_envelope"] == 1.0 and run.warnings
    assert "load" in run.json["tyres"]["front"]["worst"]
    with pytest.raises(ValueRangeError, match="strict=True: front tyre"):
        simulate("ramp", vehicle="fsae", strict=True)
