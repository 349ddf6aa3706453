"""Vehicle description files for ``tyrefit sim``: TOML or JSON, presets ``ev``, ``fsae``, ``light_truck``.

A vehicle file carries (SI; DESIGN "Vehicles for `sim`")::

    mass [kg], yaw_inertia [kg*m^2], wheelbase [m], cg_to_front [m], cg_height [m], track [m],
    drag_area [m^2] (Cd*A), downforce_area [m^2] (Cl*A), rolling_resistance [-],
    [front] and [rear]: wheel_radius [m], wheel_inertia [kg*m^2] (the axle's two wheels),
                        drive (true/false), torque_max [N*m] (at the axle's wheels), power_max [W]

and optionally ``name``, ``description``, ``downforce_front_share`` [-] (default: the static
front weight share), ``roll_stiffness_front_share`` [-] (share of the lateral load transfer
on the front axle; default: the static front weight share), ``air_density`` [kg/m^3]
(default 1.225) and ``ramp_radius`` [m] (the ``ramp`` scenario's radius; default 40 m,
ISO 4138's smallest).  In JSON the axles are objects ``"front": {...}``.

Every value is checked at the boundary against a plausible range for its unit, so a unit
slip (a mass of 1.8 meaning tonnes, a wheelbase of 1530 meaning mm) is refused with one
line naming the key, the unit and the accepted range.  :func:`load_vehicle` takes a path
or a preset name and returns a :class:`VehicleSpec`.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import asdict, dataclass
from pathlib import Path

from ..errors import ColumnError, DataError, FormatError, ValueRangeError, close_matches
from ..nomenclature import G0
from .vehicle import VehicleParams

__all__ = ["AxleSpec", "VehicleSpec", "PRESETS", "AIR_DENSITY", "load_vehicle", "vehicle_from_dict",
           "preset_path"]

#: air density of the drag and downforce terms [kg/m^3] (ISA sea level, 15 C)
AIR_DENSITY = 1.225
#: preset name -> file in ``tyrefit/sim/vehicles/``
PRESETS = {"ev": "ev.toml", "fsae": "fsae.toml", "light_truck": "light_truck.toml"}

#: key -> (unit, low, high, hint for a value below / above the range).  Ranges are what a road or
#: race vehicle can have; they are there to catch unit slips, not to judge a design.
_TOP = {
    "mass": ("kg", 50.0, 60000.0, "tonnes? give the mass in kg", "grams? give the mass in kg"),
    "yaw_inertia": ("kg*m^2", 5.0, 1e6, "", ""),
    "wheelbase": ("m", 0.5, 12.0, "", "millimetres? give the wheelbase in m"),
    "cg_to_front": ("m", 0.0, 12.0, "", "millimetres? give it in m"),
    "cg_height": ("m", 0.05, 3.0, "", "millimetres? give the CG height in m"),
    "track": ("m", 0.5, 3.0, "", "millimetres? give the track in m"),
    "drag_area": ("m^2", 0.0, 20.0, "", "give Cd times the frontal area in m^2"),
    "downforce_area": ("m^2", -2.0, 10.0, "", "give Cl times the frontal area in m^2"),
    "rolling_resistance": ("-", 0.0, 0.1, "", "percent? give the coefficient as a fraction (0.015)"),
}
_OPTIONAL = {
    "downforce_front_share": ("-", 0.0, 1.0, "", "give a fraction 0-1"),
    "roll_stiffness_front_share": ("-", 0.0, 1.0, "", "give a fraction 0-1"),
    "air_density": ("kg/m^3", 0.5, 1.5, "", ""),
    "ramp_radius": ("m", 5.0, 1000.0, "", ""),
}
_AXLE = {
    "wheel_radius": ("m", 0.1, 1.0, "", "millimetres or a diameter? give the rolling radius in m"),
    "wheel_inertia": ("kg*m^2", 0.01, 500.0, "", ""),
    "torque_max": ("N*m", 0.0, 1e5, "", ""),
    "power_max": ("W", 0.0, 2e6, "", ""),
}
_TEXT = ("name", "description")


@dataclass(frozen=True)
class AxleSpec:
    """One axle: wheel rolling radius [m], the axle's wheel inertia [kg*m^2], drive and motor limits."""

    wheel_radius: float
    wheel_inertia: float
    drive: bool
    torque_max: float
    power_max: float


@dataclass(frozen=True)
class VehicleSpec:
    """A vehicle as the simulations use it (SI).  See the module docstring for the keys."""

    name: str
    mass: float
    yaw_inertia: float
    wheelbase: float
    cg_to_front: float
    cg_height: float
    track: float
    drag_area: float
    downforce_area: float
    rolling_resistance: float
    front: AxleSpec
    rear: AxleSpec
    description: str = ""
    downforce_front_share: float | None = None
    roll_stiffness_front_share: float | None = None
    air_density: float = AIR_DENSITY
    ramp_radius: float = 40.0
    source: str = ""

    # -- derived ------------------------------------------------------------------
    @property
    def lf(self) -> float:
        """CG to front axle [m]."""
        return self.cg_to_front

    @property
    def lr(self) -> float:
        """CG to rear axle [m]."""
        return self.wheelbase - self.cg_to_front

    @property
    def front_weight_share(self) -> float:
        """Static front axle load over the weight, l_r / L [-]."""
        return self.lr / self.wheelbase

    @property
    def downforce_share_front(self) -> float:
        return self.front_weight_share if self.downforce_front_share is None else self.downforce_front_share

    @property
    def roll_share_front(self) -> float:
        return self.front_weight_share if self.roll_stiffness_front_share is None \
            else self.roll_stiffness_front_share

    @property
    def drag_coefficient(self) -> float:
        """C_d of F = C_d v^2 [kg/m]: 0.5 rho Cd*A."""
        return 0.5 * self.air_density * self.drag_area

    @property
    def downforce_coefficient(self) -> float:
        """C_l of F = C_l v^2 [kg/m]: 0.5 rho Cl*A."""
        return 0.5 * self.air_density * self.downforce_area

    def to_params(self):
        """The :class:`~tyrefit.sim.vehicle.VehicleParams` of Pham et al.'s bicycle model (braking/straight/curved).

        That model has one wheel radius and one wheel inertia per axle for both
        axles, static axle loads and drag only (no downforce, rolling resistance
        or load transfer, as in the paper).
        """
        f, r = self.front, self.rear
        for key in ("wheel_radius", "wheel_inertia"):
            if getattr(f, key) != getattr(r, key):
                raise DataError(f"vehicle {self.name!r}: front and rear {key} differ ({getattr(f, key):g} and "
                                f"{getattr(r, key):g}); the scenarios of Pham et al. (braking, straight, curved) "
                                f"model one {key} for both axles: give equal values, or run ramp")
        return VehicleParams(mass=self.mass, yaw_inertia=self.yaw_inertia, lf=self.lf, lr=self.lr,
                             wheel_radius=f.wheel_radius, wheel_inertia=f.wheel_inertia,
                             drag=self.drag_coefficient)

    def to_dict(self) -> dict:
        """What was used, SI (the ``"vehicle"`` key of ``sim --json``)."""
        d = asdict(self)
        d["downforce_front_share"] = self.downforce_share_front
        d["roll_stiffness_front_share"] = self.roll_share_front
        d["cg_to_rear"] = self.lr
        d["static_axle_load_front_N"] = self.mass * G0 * self.front_weight_share
        d["static_axle_load_rear_N"] = self.mass * G0 * (1.0 - self.front_weight_share)
        d["units"] = {**{k: v[0] for k, v in {**_TOP, **_OPTIONAL}.items()},
                      **{f"front.{k}": v[0] for k, v in _AXLE.items()},
                      **{f"rear.{k}": v[0] for k, v in _AXLE.items()}}
        return d


def preset_path(name: str) -> Path:
    """Path of a preset's file (``tyrefit/sim/vehicles/<name>.toml``)."""
    from importlib.resources import files

    return Path(str(files("tyrefit.sim") / "vehicles" / PRESETS[name]))


def load_vehicle(vehicle: "str | os.PathLike | VehicleSpec | dict | None" = "ev") -> VehicleSpec:
    """A vehicle from a preset name (``ev``, ``fsae``, ``light_truck``), a TOML/JSON file, or a dict.

    Raises
    ------
    DataError
        (one line) naming the key, the unit and the accepted range of a bad value,
        a missing key, or an unknown preset or key with close matches.
    """
    if vehicle is None:
        vehicle = "ev"
    if isinstance(vehicle, VehicleSpec):
        return vehicle
    if isinstance(vehicle, dict):
        return vehicle_from_dict(vehicle, "vehicle")
    text = str(vehicle)
    if text in PRESETS:
        path = preset_path(text)
        return vehicle_from_dict(_read(path), f"preset {text!r}", source=f"preset {text}")
    p = Path(text)
    if not p.exists():
        if p.suffix.lower() not in (".toml", ".json"):
            raise DataError(f"vehicle {text!r}: neither a preset ({', '.join(PRESETS)})"
                            f"{close_matches(text, PRESETS)} nor a vehicle file (.toml or .json)")
        raise DataError(f"{p}: vehicle file not found")
    if p.is_dir():
        raise DataError(f"{p}: is a folder; give a vehicle file (.toml or .json) or a preset "
                        f"({', '.join(PRESETS)})")
    return vehicle_from_dict(_read(p), str(p), source=str(p))


def _read(path: Path) -> dict:
    import tomllib

    try:
        raw = path.read_bytes()
    except OSError as e:
        raise DataError(f"{path}: cannot read the vehicle file ({e.strerror or e})") from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise FormatError(f"{path}: not a text file; a vehicle file is TOML or JSON") from None
    is_json = path.suffix.lower() == ".json" or text.lstrip().startswith("{")
    try:
        data = json.loads(text) if is_json else tomllib.loads(text)
    except json.JSONDecodeError as e:
        raise FormatError(f"{path}: not valid JSON (line {e.lineno}: {e.msg})") from None
    except tomllib.TOMLDecodeError as e:
        raise FormatError(f"{path}: not valid TOML ({' '.join(str(e).split())})") from None
    if not isinstance(data, dict):
        raise FormatError(f"{path}: a vehicle file holds one table (TOML) or object (JSON) of keys")
    return data


def _number(where: str, key: str, value, spec) -> float:
    unit, lo, hi, hint_lo, hint_hi = spec
    shown = f"{key} [{unit}]"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise DataError(f"{where}: {shown} = {value!r} is not a number; accepted {lo:g} to {hi:g} {unit}")
    v = float(value)
    if not math.isfinite(v) or v < lo or v > hi:
        hint = hint_lo if v < lo and lo > 0 and v > 0 else hint_hi if v > hi else ""
        if key == "mass" and v < lo and not lo <= 1000.0 * v <= hi:
            hint = ""                     # "tonnes?" only where the value in tonnes is a plausible mass
        raise ValueRangeError(f"{where}: {shown} = {value!r} is outside the accepted {lo:g} to {hi:g} {unit}"
                              + (f" ({hint})" if hint else ""))
    return v


def _check_keys(where: str, got, known, required) -> None:
    for k in got:
        if k not in known:
            raise DataError(f"{where}: unknown key {k!r}{close_matches(k, known)}; accepted keys: "
                            f"{', '.join(known)}")
    for k in required:
        if k not in got:
            unit = {**_TOP, **_AXLE}.get(k, ("",))[0]
            rng = {**_TOP, **_AXLE}.get(k)
            what = f" [{unit}], accepted {rng[1]:g} to {rng[2]:g} {unit}" if rng else ""
            raise ColumnError(f"{where}: missing key {k!r}{what}")


def vehicle_from_dict(data: dict, where: str = "vehicle", source: str = "") -> VehicleSpec:
    """Validate a vehicle's keys (one-line :class:`~tyrefit.errors.DataError` on the first problem)."""
    known = list(_TOP) + list(_OPTIONAL) + list(_TEXT) + ["front", "rear"]
    _check_keys(where, data, known, list(_TOP) + ["front", "rear"])
    vals = {k: _number(where, k, data[k], s) for k, s in _TOP.items()}
    opt = {k: _number(where, k, data[k], s) for k, s in _OPTIONAL.items() if k in data}
    axles = {}
    for axle in ("front", "rear"):
        a = data[axle]
        w = f"{where}: [{axle}]"
        if not isinstance(a, dict):
            raise DataError(f"{where}: {axle!r} must be a table of wheel_radius, wheel_inertia, drive, torque_max, "
                            "power_max")
        _check_keys(w, a, list(_AXLE) + ["drive"], list(_AXLE) + ["drive"])
        nums = {k: _number(w, k, a[k], s) for k, s in _AXLE.items()}
        if not isinstance(a["drive"], bool):
            raise DataError(f"{w}: drive = {a['drive']!r}; accepted true (a driven axle) or false")
        if a["drive"]:
            for k, lo, unit in (("torque_max", 10.0, "N*m"), ("power_max", 1000.0, "W")):
                if nums[k] < lo:
                    raise ValueRangeError(f"{w}: {k} [{unit}] = {a[k]!r} is below {lo:g} {unit} on a driven axle"
                                          + (" (kilowatts? give the power in W)" if k == "power_max" and nums[k] > 0
                                             else ""))
        axles[axle] = AxleSpec(drive=a["drive"], **nums)
    if not (axles["front"].drive or axles["rear"].drive):
        raise DataError(f"{where}: no driven axle; set drive = true on [front], [rear] or both")
    L, a = vals["wheelbase"], vals["cg_to_front"]
    if not (0.0 < a < L):
        raise ValueRangeError(f"{where}: cg_to_front [m] = {data['cg_to_front']!r} puts the CG outside the wheelbase; "
                              f"accepted strictly between 0 and wheelbase = {L:g} m")
    if vals["track"] > 0 and vals["cg_height"] > 1.5 * vals["track"]:
        raise ValueRangeError(f"{where}: cg_height [m] = {vals['cg_height']:g} is more than 1.5 x the track "
                              f"({vals['track']:g} m); accepted 0.05 m to {1.5 * vals['track']:g} m")
    # radius of gyration sqrt(Iz/m) of a vehicle lies between 0.2 and 0.7 wheelbase
    k = math.sqrt(vals["yaw_inertia"] / vals["mass"]) / L
    if not 0.15 <= k <= 0.8:
        lo, hi = vals["mass"] * (0.15 * L) ** 2, vals["mass"] * (0.8 * L) ** 2
        raise ValueRangeError(f"{where}: yaw_inertia [kg*m^2] = {data['yaw_inertia']!r} is implausible for "
                              f"{vals['mass']:g} kg on a {L:g} m wheelbase; accepted {lo:.3g} to {hi:.3g} kg*m^2")
    for key in _TEXT:
        if key in data and not isinstance(data[key], str):
            raise DataError(f"{where}: {key} = {data[key]!r} must be text")
    name = data.get("name") or (Path(source).stem if source else "vehicle")
    return VehicleSpec(name=name, description=data.get("description", ""), front=axles["front"],
                       rear=axles["rear"], source=source, **vals, **opt)
