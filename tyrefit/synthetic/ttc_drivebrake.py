"""**Synthetic** FSAE-TTC-style drive/brake and cornering records from a published MF 6.1 tyre.

Nothing written here is a measurement.  The tyre is a *published* Magic
Formula 6.1 parameter set, :data:`PUBLISHED_MF61`: the example property file
``MagicFormula61_Parameters.tir`` of MFeval (Marco Furlan Tassara; a
255/55-size tyre, FNOMIN 6752 N, NOMPRES 260 kPa, made with OptimumT), in
the version published in girish-radhakrishnan-250894/slip_angle_control @
598f2c2 (transcribed unchanged).  MFeval 4.0's own copy of that file
(``tests/data/mfeval_MagicFormula61_Paramerters.tir``) carries different
values (another fit of the same tyre); either is a published set.
Forces and moments come from :func:`tyrefit.models.mf61.forces` at the
*actual* load, slips, camber, pressure and speed of every sample; the
recorded channels then get sensor noise.

Two generators:

:func:`make_sweeps`
    clean set-point sweeps (DataFrame, SI, ISO-W) for recovery tests: pure
    slip-ratio sweeps at alpha = 0, pure slip-angle sweeps, and slip-ratio
    sweeps at each non-zero slip angle (combined), at every load x pressure x
    camber; Gaussian noise of ``noise`` x the sweep's peak |channel| on every
    force and moment.
:func:`make_record`
    one continuous flat-track record in the layout of an FSAE TTC run (20 Hz;
    written by :func:`tyrefit.synthetic.ttc.format_ttc` in SAE signs), as the
    TTC's drive/brake programme: warm-up (sine slip cycles), then for each
    pressure, camber and slip angle (0, -3, -6 deg) slip-ratio sweeps
    0 -> +k -> -k -> 0 at every load, with load/camber ramps and dwells
    between them; ``kind='cornering'`` gives the matching cornering record
    (slip-angle sweeps 0 -> +12 -> -12 -> 0 deg).

Measurement imperfections of :func:`make_record`: the forces follow the
slip with a first-order relaxation lag of 0.03 s while the kinematic slip is
recorded (hysteresis between the up and down branches), the load rising 2 %
with |slip| and a 0.3 % slow drift, the pressure rising with tread
temperature (up to +3 kPa), camber compliance 0.015 deg per kN of Fy, and
noise (1 sigma): 0.03 deg on SA, IA; 0.002 on SL; 15 N on FZ; 1 % + 10 N on
FX, FY; 1 % + 0.5 N m on MZ, MX; 0.3 kPa on P.

References
----------
MFeval (M. Furlan Tassara), example file ``MagicFormula61_Parameters.tir`` (FITTYP 61), as in
girish-radhakrishnan-250894/slip_angle_control @ 598f2c2;
Pacejka & Besselink (2012), *Tire and Vehicle Dynamics*, 3rd ed., 4.3.2.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from ..io.outputs import write_text
from ..models import mf61
from .ttc import format_ttc

__all__ = ["PUBLISHED_MF61", "COEFFICIENT_GROUPS", "published_mf61", "contract_mf61", "make_sweeps", "make_record", "generate", "SEED", "PROGRAMME"]

SEED = 20251125
_DEG = math.pi / 180.0

#: MFeval's MagicFormula61_Parameters.tir (FITTYP 61): the coefficients the steady-state equations use
PUBLISHED_MF61: dict[str, float] = {
    "FITTYP": 61, "LONGVL": 16.6, "VXLOW": 1.0, "UNLOADED_RADIUS": 0.3943, "WIDTH": 0.255, "ASPECT_RATIO": 0.55,
    "RIM_RADIUS": 0.254, "RIM_WIDTH": 0.2159, "INFLPRES": 260000.0, "NOMPRES": 260000.0, "FNOMIN": 6752.0,
    "VERTICAL_STIFFNESS": 314931.2969, "VERTICAL_DAMPING": 500.0,
    # [LONGITUDINAL_COEFFICIENTS]
    "PCX1": 1.5482, "PDX1": 1.1632, "PDX2": -0.11154, "PDX3": 0.94173, "PEX1": 0.27, "PEX2": 0.011693,
    "PEX3": 0.053303, "PEX4": 0.59223, "PKX1": 32.9102, "PKX2": 12.7911, "PKX3": -0.11254, "PHX1": -0.0017527,
    "PHX2": 0.00068824, "PVX1": 0.068079, "PVX2": 0.0023429, "PPX1": -0.8733, "PPX2": 0.7035, "PPX3": -0.0080216,
    "PPX4": -0.47776, "RBX1": 18.3369, "RBX2": 18.2559, "RBX3": 607.8133, "RCX1": 0.96372, "REX1": -1.2699,
    "REX2": -0.14323, "RHX1": 0.0037359,
    # [OVERTURNING_COEFFICIENTS]
    "QSX1": 0.00062469, "QSX2": -9.9089, "QSX3": 1.621, "QSX4": 11.4346, "QSX5": -0.22968, "QSX6": 1.3749,
    "QSX7": -0.90713, "QSX8": 4.5166, "QSX9": -0.033238, "QSX10": 0.73734, "QSX11": -1.7614, "QSX12": 0.0,
    "QSX13": 0.0, "QSX14": 0.0, "PPMX1": -0.032723,
    # [LATERAL_COEFFICIENTS]
    "PCY1": 1.4759, "PDY1": 1.0085, "PDY2": -0.1323, "PDY3": 2.4957, "PEY1": -0.34653, "PEY2": -0.60297,
    "PEY3": -0.084051, "PEY4": -20.7741, "PEY5": 57.615, "PKY1": -28.3155, "PKY2": 3.313, "PKY3": -0.21509,
    "PKY4": 2.7364, "PKY5": 49.8685, "PKY6": -1.001, "PKY7": 0.17458, "PHY1": 0.0016662, "PHY2": 0.00081921,
    "PVY1": 0.022144, "PVY2": 0.0073185, "PVY3": -0.47424, "PVY4": -0.2317, "PPY1": 0.34039, "PPY2": 1.1056,
    "PPY3": 0.098508, "PPY4": -0.10018, "PPY5": -0.81071, "RBY1": 25.972, "RBY2": -16.0345, "RBY3": -0.012821,
    "RBY4": 1747.3832, "RCY1": 0.93848, "REY1": 0.47225, "REY2": 0.089042, "RHY1": -0.0062355, "RHY2": 0.0044985,
    "RVY1": 0.013748, "RVY2": 0.012074, "RVY3": 0.47896, "RVY4": -97.0538, "RVY5": -1.7992, "RVY6": -27.5155,
    # [ROLLING_COEFFICIENTS]
    "QSY1": 0.01, "QSY2": 0.0, "QSY3": 0.0004, "QSY4": 4e-05, "QSY5": 0.0, "QSY6": 0.0, "QSY7": 0.85,
    "QSY8": -0.4,
    # [ALIGNING_COEFFICIENTS]
    "QBZ1": 12.5909, "QBZ2": -0.90176, "QBZ3": -0.60231, "QBZ4": -1.2812, "QBZ5": 3.1497, "QBZ9": 176.0292,
    "QBZ10": 17.3439, "QCZ1": 1.1676, "QDZ1": 0.084112, "QDZ2": 0.0024576, "QDZ3": -1.0046, "QDZ4": 9.1761,
    "QDZ6": 0.0020533, "QDZ7": 0.0020396, "QDZ8": -0.34545, "QDZ9": 0.52144, "QDZ10": 1.0329, "QDZ11": -4.3212,
    "QEZ1": -3.4668, "QEZ2": -1.6919, "QEZ3": 1.4023, "QEZ4": 0.37768, "QEZ5": -8.9305, "QHZ1": 0.0023613,
    "QHZ2": 0.0019525, "QHZ3": 0.28223, "QHZ4": -0.22141, "PPZ1": 0.94372, "PPZ2": 0.5053,
    "SSZ1": 0.0, "SSZ2": 0.0, "SSZ3": 0.0, "SSZ4": 0.0,
}

#: the default programme (SI): loads as fractions of FNOMIN, pressures [Pa], cambers and slip angles [deg]
PROGRAMME = {
    "load_fractions": (0.4, 0.7, 1.0, 1.3, 1.6),
    "pressures": (220e3, 260e3, 300e3),
    "cambers_deg": (0.0, 2.0, 4.0),
    "slip_angles_deg": (0.0, -3.0, -6.0),
    "kappa_max": 0.2,
    "alpha_max_deg": 12.0,
    "speed": 11.1,  # m/s (40 km/h)
}


#: coefficient groups of an MF 6.1 set that carry one physical effect each (Pacejka 2012, Sec. 4.3.2): zeroing a
#: group removes the effect from every channel (camber and pressure: checked by benchmarks/diagnose_channels.py)
COEFFICIENT_GROUPS: dict[str, tuple[str, ...]] = {
    "camber": ("PDY3", "PKY3", "PKY5", "PKY6", "PKY7", "PVY3", "PVY4", "PEY5", "PHY3", "QHZ3", "QHZ4", "QBZ4",
               "QBZ5", "QDZ3", "QDZ4", "QEZ5", "QDZ8", "QDZ9", "QDZ10", "QDZ11", "PDX3"),
    "pressure": ("PPX1", "PPX2", "PPX3", "PPX4", "PPY1", "PPY2", "PPY3", "PPY4", "PPY5", "PPZ1", "PPZ2"),
    "offsets": ("QHZ1", "QHZ2", "QDZ6", "QDZ7", "PHY1", "PHY2", "PVY1", "PVY2", "PHX1", "PHX2"),
    "rolling": ("PVX1", "PVX2"),
    "asymmetry": ("QEZ4", "PEX4", "PEY3"),
}


def contract_mf61() -> dict[str, float]:
    """:func:`published_mf61` with its combined-slip shifts removed (RHX1 = RHY1 = RHY2 = 0).

    As published, the set's combined-slip weight G_yk reaches 1.028 (and G_xa 1.002) inside its own
    data range, near kappa = 0 at every slip angle: combined slip adds lateral force there, which the
    physical-validity contract of every tyre tyrefit writes forbids (:mod:`tyrefit.tyres.contract`).  A
    fit under the contract cannot come closer than that to the published curves; this set keeps the
    contract (G <= 1 everywhere), so a fit can recover it to the noise.
    """
    return dict(published_mf61(), RHX1=0.0, RHY1=0.0, RHY2=0.0)


def published_mf61() -> dict[str, float]:
    """A complete MF 6.1 parameter set: :data:`PUBLISHED_MF61` over :func:`tyrefit.models.mf61.neutral`."""
    p = mf61.neutral()
    p.update(PUBLISHED_MF61)
    return p


def _eval(p, fz, kappa, alpha, gamma, pressure, speed):
    return mf61.forces(p, fz, slip_ratio=kappa, slip_angle=alpha, camber=gamma, pressure=pressure, speed=speed)


def make_sweeps(p: dict | None = None, *, seed: int = SEED, noise: float = 0.01, loads=None, pressures=None,
                cambers_deg=None, slip_angles_deg=None, n_points: int = 41, combined: bool = True,
                pure: bool = True, speeds=None, kappa_max: float | None = None) -> pd.DataFrame:
    """Set-point sweeps of the tyre ``p`` (default :func:`published_mf61`) with relative noise.

    Parameters
    ----------
    p : dict, optional
        MF 6.1 coefficients.
    noise : float
        noise sigma as a fraction of each sweep's peak |channel| (all of fx, fy, mz, mx, my).
    loads : sequence of float, optional
        [N]; default :data:`PROGRAMME` fractions of FNOMIN.
    pressures : sequence of float, optional
        [Pa].
    cambers_deg, slip_angles_deg : sequence of float, optional
        [deg]; slip angles of the slip-ratio sweeps (0 is pure longitudinal).
    n_points : int
        points per sweep.
    speeds : sequence of float, optional
        forward speeds [m/s] (default the one :data:`PROGRAMME` speed); every sweep is repeated at each
        speed (the outermost loop, so the default gives the same runs and noise as a single speed).  The
        forces depend on speed through the slip speed in the friction law (LMUV, Pacejka 4.E7) and My.
    kappa_max : float, optional
        the slip-ratio sweeps' end, +-kappa_max (default :data:`PROGRAMME`'s).

    Returns
    -------
    DataFrame
        ``run fz slip_angle slip_ratio camber pressure speed fx fy mz mx my`` (SI,
        ISO-W) and the noise-free ``true_<channel>`` columns.
    """
    p = published_mf61() if p is None else p
    rng = np.random.default_rng(seed)
    P = PROGRAMME
    loads = [f * p["FNOMIN"] for f in P["load_fractions"]] if loads is None else list(loads)
    pressures = P["pressures"] if pressures is None else pressures
    cambers = P["cambers_deg"] if cambers_deg is None else cambers_deg
    alphas = P["slip_angles_deg"] if slip_angles_deg is None else slip_angles_deg
    km = P["kappa_max"] if kappa_max is None else float(kappa_max)
    kap = np.linspace(-km, km, n_points)
    alp = np.linspace(-P["alpha_max_deg"], P["alpha_max_deg"], n_points) * _DEG
    speeds = [P["speed"]] if speeds is None else list(speeds)
    frames = []
    run = 0
    for v in speeds:
        for pr in pressures:
            for g in cambers:
                for fz in loads:
                    sweeps = []
                    if pure:
                        sweeps.append((kap * 0.0, alp))  # slip-angle sweep at kappa = 0
                    for a in alphas:
                        if a == 0 and not pure:
                            continue
                        if a != 0 and not combined:
                            continue
                        sweeps.append((kap, np.full_like(kap, a * _DEG)))
                    for k, a in sweeps:
                        n = len(k)
                        f = _eval(p, np.full(n, fz), k, a, np.full(n, g * _DEG), np.full(n, pr), np.full(n, v))
                        d = {"run": run, "fz": fz, "slip_angle": a, "slip_ratio": k, "camber": g * _DEG,
                             "pressure": pr, "speed": v}
                        for c in ("fx", "fy", "mz", "mx", "my"):
                            y = np.asarray(f[c], float)
                            d[f"true_{c}"] = y
                            d[c] = y + rng.normal(0.0, noise * max(float(np.max(np.abs(y))), 1e-9), n)
                        frames.append(pd.DataFrame(d))
                        run += 1
    return pd.concat(frames, ignore_index=True)


def _ramp(n, a, b):
    return a + (b - a) * np.linspace(0.0, 1.0, n, endpoint=False)


def make_record(kind: str = "drivebrake", p: dict | None = None, *, seed: int = SEED, rate: float = 20.0,
                loads=None, pressures=None, cambers_deg=None, slip_angles_deg=None, sweep_seconds: float = 8.0,
                noise: bool = True) -> pd.DataFrame:
    """One continuous TTC-style record (SI, ISO-W): ``kind`` 'drivebrake' or 'cornering'.

    Columns ``time speed wheel_rpm slip_angle camber loaded_radius pressure fx fy fz mx mz
    slip_ratio temperature`` (the channels :func:`tyrefit.synthetic.ttc.format_ttc` writes).
    """
    if kind not in ("drivebrake", "cornering"):
        raise ValueError("kind must be 'drivebrake' or 'cornering'")
    p = published_mf61() if p is None else p
    rng = np.random.default_rng(seed + (0 if kind == "drivebrake" else 1))
    P = PROGRAMME
    loads = [f * p["FNOMIN"] for f in P["load_fractions"]] if loads is None else list(loads)
    pressures = P["pressures"] if pressures is None else pressures
    cambers = P["cambers_deg"] if cambers_deg is None else cambers_deg
    alphas = P["slip_angles_deg"] if slip_angles_deg is None else slip_angles_deg
    segs: dict[str, list] = {k: [] for k in ("fz", "ia", "p", "sa", "sl", "v")}

    def seg(n, fz0, fz1, ia0, ia1, pr, sa0, sa1, sl=None, sa=None, v=P["speed"]):
        segs["fz"].append(_ramp(n, fz0, fz1))
        segs["ia"].append(_ramp(n, ia0, ia1))
        segs["p"].append(np.full(n, pr))
        segs["sa"].append(_ramp(n, sa0, sa1) if sa is None else sa)
        segs["sl"].append(np.zeros(n) if sl is None else sl)
        segs["v"].append(np.full(n, v))

    n_sw = int(sweep_seconds * rate)
    tri = np.concatenate([np.linspace(0, 1, n_sw // 4, endpoint=False), np.linspace(1, -1, n_sw // 2, endpoint=False),
                          np.linspace(-1, 0, n_sw - n_sw // 4 - n_sw // 2)])
    # warm-up at the first pressure and nominal load: sine slip cycles (the segmentation drops them)
    pr0, fzw = pressures[0], loads[len(loads) // 2]
    seg(int(2 * rate), 0, fzw, 0, 0, pr0, 0, 0)
    t = np.arange(int(12 * rate)) / rate
    if kind == "drivebrake":
        seg(len(t), fzw, fzw, 0, 0, pr0, 0, 0, sl=0.08 * np.sin(2 * np.pi * t / 4))
    else:
        seg(len(t), fzw, fzw, 0, 0, pr0, 0, 0, sa=4 * _DEG * np.sin(2 * np.pi * t / 4))
    fz_now, ia_now, sa_now = fzw, 0.0, 0.0
    for pr in pressures:
        for g in cambers:
            for a in (alphas if kind == "drivebrake" else (None,)):
                for fz in loads:
                    a_rad = 0.0 if a is None else a * _DEG
                    seg(int(2.0 * rate), fz_now, fz, ia_now, g * _DEG, pr, sa_now, a_rad)
                    seg(int(1.0 * rate), fz, fz, g * _DEG, g * _DEG, pr, a_rad, a_rad)
                    if kind == "drivebrake":
                        seg(n_sw, fz, fz, g * _DEG, g * _DEG, pr, a_rad, a_rad, sl=P["kappa_max"] * tri)
                    else:
                        seg(n_sw, fz, fz, g * _DEG, g * _DEG, pr, 0, 0, sa=P["alpha_max_deg"] * _DEG * tri)
                    seg(int(1.0 * rate), fz, fz, g * _DEG, g * _DEG, pr, a_rad, a_rad)
                    fz_now, ia_now, sa_now = fz, g * _DEG, a_rad
        # unload between pressures (re-inflation)
        seg(int(2 * rate), fz_now, 0, ia_now, 0, pr, sa_now, 0)
        seg(int(4 * rate), 0, 0, 0, 0, pr, 0, 0)
        fz_now, ia_now, sa_now = 0.0, 0.0, 0.0
    cat = {k: np.concatenate(v) for k, v in segs.items()}
    n = len(cat["fz"])
    time_s = np.arange(n) / rate
    # the tyre's force follows its slip with a relaxation lag (first order, tau = 0.03 s: about 0.3 m at
    # 40 km/h) while the rig records the kinematic slip: hysteresis between the up and down branches
    lag = math.exp(-1.0 / (0.03 * rate))
    sa_eff, sl_eff = np.empty(n), np.empty(n)
    sa_eff[0], sl_eff[0] = cat["sa"][0], cat["sl"][0]
    for i in range(1, n):
        sa_eff[i] = lag * sa_eff[i - 1] + (1 - lag) * cat["sa"][i]
        sl_eff[i] = lag * sl_eff[i - 1] + (1 - lag) * cat["sl"][i]
    loaded = cat["fz"] > 1.0
    slip_mag = np.abs(cat["sl"]) / P["kappa_max"] + np.abs(cat["sa"]) / (P["alpha_max_deg"] * _DEG)
    fz_true = cat["fz"] * (1 + 0.02 * np.clip(slip_mag, 0, 1) + 0.003 * np.sin(2 * np.pi * time_s / 90.0))
    temp = 25 + 35 * (1 - np.exp(-time_s / 300.0))
    pr_true = cat["p"] + 3e3 * (temp - 25) / 35
    f = _eval(p, np.clip(fz_true, 1.0, None), sl_eff, sa_eff, cat["ia"], pr_true, cat["v"])
    f = {k: np.where(loaded, np.asarray(v, float), 0.0) for k, v in f.items()}
    ia_true = cat["ia"] + 0.015 * _DEG * f["fy"] / 1000.0  # camber compliance
    if ia_true is not cat["ia"]:  # forces at the compliant camber (one more evaluation)
        f = _eval(p, np.clip(fz_true, 1.0, None), sl_eff, sa_eff, ia_true, pr_true, cat["v"])
        f = {k: np.where(loaded, np.asarray(v, float), 0.0) for k, v in f.items()}
    s = 1.0 if noise else 0.0
    rn = lambda sd: rng.normal(0.0, 1.0, n) * sd * s  # noqa: E731
    df = pd.DataFrame({
        "time": time_s,
        "speed": cat["v"] + rn(0.04),
        "slip_angle": cat["sa"] + rn(0.03 * _DEG),
        "camber": ia_true + rn(0.03 * _DEG),
        "loaded_radius": p["UNLOADED_RADIUS"] - np.clip(fz_true, 0, None) / p.get("VERTICAL_STIFFNESS", 3e5),
        "pressure": pr_true + rn(300.0),
        "fx": f["fx"] * (1 + rn(0.01)) + rn(10.0),
        "fy": f["fy"] * (1 + rn(0.01)) + rn(10.0),
        "fz": fz_true + rn(15.0),
        "mx": f["mx"] * (1 + rn(0.01)) + rn(0.5),
        "mz": f["mz"] * (1 + rn(0.01)) + rn(0.5),
        "slip_ratio": cat["sl"] + rn(0.002),
        "temperature": temp,
    })
    re = df["loaded_radius"] + 0.01
    df["wheel_rpm"] = df["speed"] / (2 * np.pi * re) * 60 * (1 + df["slip_ratio"])
    return df


def format_record(df: pd.DataFrame, kind: str, seed: int = SEED) -> str:
    """TTC ``.dat`` text (SAE signs) of a record from :func:`make_record`."""
    text = format_ttc(df, seed=seed)
    info = (f"SYNTHETIC FSAE TTC-style {kind} run (not a measurement): generated by tyrefit.synthetic.ttc_drivebrake "
            f"from the published MF 6.1 set of MFeval's MagicFormula61_Parameters.tir, seed {seed}; SAE axis system, "
            f"{len(df)} samples")
    return info + text[text.index("\n"):]


README = """# data/ttc_mf61 — synthetic TTC-style drive/brake and cornering records of a published MF 6.1 tyre

**Synthetic.** Made by `tyrefit.synthetic.ttc_drivebrake.generate` (seed {seed}); the tyre is
MFeval's published example set `MagicFormula61_Parameters.tir` (FITTYP 61), evaluated by
`tyrefit.models.mf61`; programme, lag, drift and noise in that module's docstring. No file here is a
measurement and none comes from the FSAE Tire Test Consortium.

| file | what |
|---|---|
| `drivebrake.dat` | slip-ratio sweeps 0 -> +0.2 -> -0.2 -> 0 at slip angles 0, -3, -6 deg, 2 loads, 1 pressure, 2 cambers; SAE signs |
| `cornering.dat` | slip-angle sweeps 0 -> +12 -> -12 -> 0 deg at the same conditions; SAE signs |

Fit both into one tyre: `tyrefit fit data/ttc_mf61/cornering.dat data/ttc_mf61/drivebrake.dat --convention sae --model mf61 --out tyre.tir`
"""


def generate(out_dir: Path) -> list[Path]:
    """Write a small drive/brake and cornering pair (TTC layout, SAE signs) and a README to ``out_dir``."""
    out_dir = Path(out_dir)
    p = published_mf61()
    kw = dict(loads=[0.6 * p["FNOMIN"], 1.2 * p["FNOMIN"]], pressures=[260e3], cambers_deg=[0.0, 3.0])
    files = []
    for kind, name in (("drivebrake", "drivebrake.dat"), ("cornering", "cornering.dat")):
        df = make_record(kind, p, **kw)
        files.append(write_text(out_dir / name, format_record(df, kind), force=True))
    files.append(write_text(out_dir / "README.md", README.format(seed=SEED), force=True))
    return files
