"""**Synthetic** FSAE-TTC-style record pair of one racing tyre, made hard on purpose.

Nothing written here is a measurement, and nothing comes from the FSAE Tire
Test Consortium: real TTC records cannot be shipped.  The generator imitates
the *layout* and the *difficulties* of a TTC pair of a 16x7.5-10 FSAE slick -
a cornering record and a drive/brake record of the same tyre - so that a
Magic Formula fit can be judged against the RMSE and friction targets set
for real TTC records (``benchmarks/ttc_field_judge.py``).

:func:`make_pair` gives ``(cornering, drivebrake)`` DataFrames (SI, ISO-W; the
recorded channels plus set-point and noise-free columns, see
:func:`make_record`); :func:`write_pair` writes them as TTC ``.dat`` text in
SAE signs (read with ``--convention sae``), the info line of each saying it is
synthetic.  Everything is seeded: the same ``seed`` and ``scale`` give the
same bytes.

The truth tyre
--------------
A Magic Formula 6.1 core, *plus* physics the MF 6.1 form does not carry, so
that the fitting data are not drawn from the fitted model's own form.

MF 6.1 core (:func:`truth_params`): the published MF 6.1 set of
:mod:`tyrefit.synthetic.ttc_drivebrake` (MFeval's example
``MagicFormula61_Parameters.tir``) rescaled to an FSAE-sized tyre:
FNOMIN 1100 N, UNLOADED_RADIUS 0.2085 m, VERTICAL_STIFFNESS 180 N/mm,
NOMPRES = INFLPRES 82.7 kPa (12 psi), LONGVL 11.11 m/s (40 km/h); friction
PDX1 2.25, PDX2 -0.12, PDY1 2.30, PDY2 -0.10; cornering stiffness PKY1 -48,
PKY2 2.2, PKY4 2.0 (about 40 kN/rad at 1112 N, Fy peak near 9-10 deg);
slip stiffness PKX1 48, PKX2 -20, PKX3 -0.4 (Kx/Fz about 88 at 222 N falling
to about 34 at 1557 N, so the pure-Fx peak (drive, brake) moves from kappa
~0.08, -0.09 at the lightest load to ~0.12, -0.14 at 1112 N and ~0.17, -0.20
at 1557 N: :func:`fx_peak_slip`); pneumatic trail QDZ1 0.11; Mx from
QSX1 0, QSX2 0.6, QSX3 0.03 (the published passenger-car QSX4..QSX11 set
to 0).  Shape, camber, pressure and
combined-slip terms stay as published.

Added physics (none of it in the MF 6.1 form):

* **load-dependent friction curvature**: the friction of both directions is
  multiplied by (Fz / FNOMIN)^-0.08, on top of the linear-in-dfz PDX2/PDY2
  (peak |F|/Fz about 2.7 at 222 N, 2.3 at 1112 N, 2.2 at 1557 N, at the
  optimum temperature);
* **thermal grip**: the tread temperature T of the record (channel TSTC)
  follows a first-order carcass warm-up (tau 200 s, towards 58 degC while
  loaded and rolling, 30 degC while stopped for re-inflation) plus flash
  heating by the slip power |Fy V sin(alpha)| + |Fx V kappa| (0.0015 K/W,
  tau 10 s); the friction of both directions is multiplied by
  1 - 6e-5 (T - 65 degC)^2 (about 0.93 on a cold tyre at 30 degC).  The grip
  therefore drifts slowly along the record and differs between the two
  records at the same set point;
* **relaxation lag**: the forces follow the slip through a first-order lag of
  0.03 s (about 0.33 m at 40 km/h) while the rig records the kinematic slip:
  hysteresis between the up and down branches of each sweep;
* **overturning moment from the contact-patch shift**: Mx gains
  Fz Fy / k_lat with k_lat = 80 kN/m (Fz/FNOMIN)^0.3 (not a product of the
  MF 6.1 Mx terms);
* **load control and compliance**: the load rises 2 % with |slip| and
  drifts 0.3 % slowly; camber compliance 0.03 deg per kN of Fy; the pressure
  rises with tread temperature (up to about +3 kPa).

:func:`truth` evaluates the steady-state noise-free truth (MF core times the
friction factors, plus the Mx term) at any points; the records also carry
the noise-free value of every sample (``true_fx``, ``true_fy``, ``true_mz``,
``true_mx``: lag, temperature, compliance and load rise included, no noise).

The records
-----------
Both records run at 40 km/h.  The set-point loads are TTC's 50, 100, 150,
200, 250 and 350 lb (222, 445, 667, 890, 1112, 1557 N; the last above
FNOMIN).

Cornering (``kind='cornering'``): warm-up (+/-4 deg sine cycles at 890 N),
then for each pressure 82.7, 68.9, 55.2 kPa (12, 10, 8 psi; re-inflated,
unloaded and stopped between them), camber 0, 2, 4 deg and each load a 2 s
ramp, a 1 s dwell, a slip-angle sweep 0 -> +12 -> -12 -> 0 deg and a 0.5 s
dwell.  Noise (1 sigma): 0.03 deg on SA, IA; 0.002 on SL; 15 N on FZ; 1 % +
10 N on FX, FY; 1 % + 1.5 N m on MZ; 1 % + 2 N m on MX; 0.3 kPa on P;
0.04 m/s on V; 0.2 mm on RL; 0.5 degC on TSTC.

Drive/brake (``kind='drivebrake'``): warm-up (+/-0.03 slip-ratio sine
cycles), then for each pressure (82.7 and 55.2 kPa; ``'small'``: 82.7 only), camber
(0, 2, 4 deg; ``'small'``: 0, 2), slip angle 0, -3, -6 deg and load (222,
667, 1112, 1557 N; ``'small'``: 222, 1112, 1557) a slip-ratio sweep
0 -> +0.10 -> -0.10 -> 0.  Only a few slip angles, and the slip-ratio range
stops short of the Fx peak at the higher loads (the truth's peak is at
kappa ~0.12-0.20 at 1112 and 1557 N); only the lightest load's sweeps pass
their peak.  The rig's Mz is much noisier here (1 % + 18 N m), Mx 1 % + 4 N m;
the other noise as in cornering.

Loaded radius (RL): the cornering record gives RL = UNLOADED_RADIUS - Fz / Cz
(0.199-0.208 m); the drive/brake record's RL is offset by +2 cm
(0.219-0.228 m), as real TTC records of the two machines disagree.

Scale: ``'full'`` samples at 100 Hz (8 s cornering sweeps, 5.8 s slip-ratio
sweeps): 66,100 cornering + 69,960 drive/brake = 136,060 samples, as a TTC
pair.  ``'small'`` keeps every 10th sample of the same 100 Hz physics (10 Hz;
the relaxation lag's hysteresis is still in the samples), with fewer loads in
cornering (222, 667, 1112, 1557 N) and the drive/brake reductions above:
4,540 + 1,838 = 6,378 samples, for tests.

Extra columns of the DataFrames (not written to the ``.dat``):
``set_pressure`` [Pa] (the regulator's set pressure of the block, on every
row), ``sp_fz`` [N], ``sp_pressure`` [Pa], ``sp_camber``, ``sp_slip_angle``
[rad] (the set points of a sweep, NaN in warm-up and transitions),
``sweep`` (sweep number, -1 outside sweeps), ``true_fx true_fy true_mz
true_mx`` (noise-free channels, ISO-W) and ``true_temperature`` [degC].
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from ..io.outputs import write_text
from ..models import mf61
from .ttc import format_ttc
from .ttc_drivebrake import published_mf61

__all__ = ["SEED", "SCALES", "TRUTH", "truth_params", "friction_factor", "truth", "make_record", "format_record",
           "make_pair", "write_pair", "fx_peak_slip"]

SEED = 20260123
_DEG = math.pi / 180.0
_LB = 4.4482216152605
_PSI = 6894.757293168361

#: changes to the published MF 6.1 set (:func:`tyrefit.synthetic.ttc_drivebrake.published_mf61`)
TRUTH: dict[str, float] = {
    "FNOMIN": 1100.0, "UNLOADED_RADIUS": 0.2085, "VERTICAL_STIFFNESS": 180e3, "NOMPRES": 12 * _PSI,
    "INFLPRES": 12 * _PSI, "LONGVL": 40 / 3.6, "WIDTH": 0.19, "ASPECT_RATIO": 0.45, "RIM_RADIUS": 0.127,
    "RIM_WIDTH": 0.178,
    "PDX1": 2.25, "PDX2": -0.12, "PDY1": 2.30, "PDY2": -0.10,
    "PKY1": -48.0, "PKY2": 2.2, "PKY4": 2.0,
    "PKX1": 48.0, "PKX2": -20.0, "PKX3": -0.4,
    "QDZ1": 0.11,
    "QSX1": 0.0, "QSX2": 0.6, "QSX3": 0.03, "QSX4": 0.0, "QSX5": 0.0, "QSX6": 0.0, "QSX7": 0.0, "QSX8": 0.0,
    "QSX9": 0.0, "QSX10": 0.0, "QSX11": 0.0, "PPMX1": 0.0,
}
#: non-MF physics constants (module docstring)
FRICTION_LOAD_EXPONENT = -0.08
T_OPT, THERMAL_COEF = 65.0, 6e-5
K_LAT0, K_LAT_EXP = 80e3, 0.3
RELAXATION_S = 0.03
RL_OFFSET_DRIVEBRAKE = 0.02

_LOADS = tuple(x * _LB for x in (50, 100, 150, 200, 250, 350))
#: programme per scale
SCALES = {
    "full": {"rate": 100.0, "decimate": 1, "corner_sweep_s": 8.0, "db_sweep_s": 5.8,
             "corner_loads": _LOADS, "corner_pressures": (12 * _PSI, 10 * _PSI, 8 * _PSI),
             "corner_cambers": (0.0, 2.0, 4.0),
             "db_loads": (_LOADS[0], _LOADS[2], _LOADS[4], _LOADS[5]), "db_pressures": (12 * _PSI, 8 * _PSI),
             "db_cambers": (0.0, 2.0, 4.0), "db_slip_angles": (0.0, -3.0, -6.0), "kappa_max": 0.10,
             "alpha_max_deg": 12.0},
    "small": {"rate": 10.0, "decimate": 10, "corner_sweep_s": 8.0, "db_sweep_s": 5.6,
              "corner_loads": (_LOADS[0], _LOADS[2], _LOADS[4], _LOADS[5]),
              "corner_pressures": (12 * _PSI, 10 * _PSI, 8 * _PSI), "corner_cambers": (0.0, 2.0, 4.0),
              "db_loads": (_LOADS[0], _LOADS[4], _LOADS[5]), "db_pressures": (12 * _PSI,),
              "db_cambers": (0.0, 2.0), "db_slip_angles": (0.0, -3.0, -6.0), "kappa_max": 0.10,
              "alpha_max_deg": 12.0},
}
SPEED = 40 / 3.6


def truth_params() -> dict[str, float]:
    """The MF 6.1 core of the truth tyre: the published set with :data:`TRUTH` applied."""
    p = published_mf61()
    p.update(TRUTH)
    return p


def friction_factor(fz, temperature=T_OPT):
    """The non-MF friction multiplier: (Fz/FNOMIN)^-0.08 * (1 - 6e-5 (T - 65 degC)^2)."""
    fz = np.clip(np.asarray(fz, float), 1.0, None)
    t = np.asarray(temperature, float)
    return (fz / TRUTH["FNOMIN"]) ** FRICTION_LOAD_EXPONENT * (1.0 - THERMAL_COEF * (t - T_OPT) ** 2)


def truth(fz, slip_ratio=0.0, slip_angle=0.0, camber=0.0, pressure=None, speed=SPEED, temperature=T_OPT) -> dict:
    """Steady-state noise-free forces of the truth tyre (SI, ISO-W), broadcast over the inputs.

    ``temperature`` [degC] is the tread temperature (the grip optimum by default).  Returns ``fx``,
    ``fy`` [N], ``mz``, ``mx`` [N m].  No relaxation lag (steady state) and no rig effects.
    """
    p = truth_params()
    lam = friction_factor(fz, temperature)
    q = dict(p, LMUX=lam, LMUY=lam)
    f = mf61.forces(q, fz, slip_ratio=slip_ratio, slip_angle=slip_angle, camber=camber,
                    pressure=p["NOMPRES"] if pressure is None else pressure, speed=speed)
    fzc = np.clip(np.asarray(fz, float), 1.0, None)
    k_lat = K_LAT0 * (fzc / p["FNOMIN"]) ** K_LAT_EXP
    mx = f["mx"] + fzc * f["fy"] / k_lat
    return {"fx": f["fx"], "fy": f["fy"], "mz": f["mz"], "mx": mx}


def fx_peak_slip(fz, camber=0.0, pressure=None, temperature=T_OPT) -> tuple[float, float]:
    """Slip ratios of the truth's pure-Fx peaks (drive, brake) at one load (steady state)."""
    k = np.linspace(-0.4, 0.4, 8001)
    fx = truth(fz, slip_ratio=k, camber=camber, pressure=pressure, temperature=temperature)["fx"]
    return float(k[np.argmax(fx)]), float(k[np.argmin(fx)])


def _ramp(n, a, b):
    return a + (b - a) * np.linspace(0.0, 1.0, n, endpoint=False)


def _lowpass(x, rate, tau):
    """First-order lag y' = (x - y)/tau, y(0) = x(0) (exact discretisation)."""
    from scipy.signal import lfilter

    a = math.exp(-1.0 / (tau * rate))
    x = np.asarray(x, float)
    y, _ = lfilter([1.0 - a], [1.0, -a], x, zi=[a * x[0]])
    return y


def make_record(kind: str, seed: int = SEED, scale: str = "full") -> pd.DataFrame:
    """One continuous record (SI, ISO-W) of ``kind`` 'cornering' or 'drivebrake' (module docstring).

    Columns ``time speed wheel_rpm slip_angle camber loaded_radius pressure fx fy fz mx mz slip_ratio
    temperature`` (what :func:`tyrefit.synthetic.ttc.format_ttc` writes), then ``set_pressure sp_fz
    sp_pressure sp_camber sp_slip_angle sweep true_fx true_fy true_mz true_mx true_temperature``.
    """
    if kind not in ("cornering", "drivebrake"):
        raise ValueError("kind must be 'cornering' or 'drivebrake'")
    if scale not in SCALES:
        raise ValueError(f"scale must be one of {', '.join(SCALES)}")
    S = SCALES[scale]
    rate = S["rate"] * S["decimate"]  # the physics runs at 100 Hz; 'small' keeps every 10th sample
    p = truth_params()
    rng = np.random.default_rng([int(seed), 0 if kind == "cornering" else 1, 0 if scale == "full" else 1])
    corner = kind == "cornering"
    loads = S["corner_loads"] if corner else S["db_loads"]
    pressures = S["corner_pressures"] if corner else S["db_pressures"]
    cambers = S["corner_cambers"] if corner else S["db_cambers"]
    alphas = (None,) if corner else S["db_slip_angles"]
    keys = ("fz", "ia", "p", "sa", "sl", "v", "spfz", "spp", "spia", "spsa", "sweep")
    segs: dict[str, list] = {k: [] for k in keys}

    def seg(dur, fz0, fz1, ia0, ia1, pr, sa0, sa1, v0=SPEED, v1=SPEED, sl=None, sa=None, sp=None, sweep=-1):
        n = len(sl) if sl is not None else len(sa) if sa is not None else max(1, int(round(dur * rate)))
        segs["fz"].append(_ramp(n, fz0, fz1))
        segs["ia"].append(_ramp(n, ia0, ia1))
        segs["p"].append(np.full(n, pr))
        segs["sa"].append(_ramp(n, sa0, sa1) if sa is None else sa)
        segs["sl"].append(np.zeros(n) if sl is None else sl)
        segs["v"].append(_ramp(n, v0, v1))
        for k, x in zip(("spfz", "spp", "spia", "spsa"), sp if sp is not None else (np.nan,) * 4):
            segs[k].append(np.full(n, x))
        segs["sweep"].append(np.full(n, sweep))

    def tri(seconds):
        n = int(round(seconds * rate))
        return np.concatenate([np.linspace(0, 1, n // 4, endpoint=False),
                               np.linspace(1, -1, n // 2, endpoint=False),
                               np.linspace(-1, 0, n - n // 4 - n // 2)])

    # spin-up unloaded, load, warm-up cycles at 890 N (the segmentation drops them)
    pr0, fzw = pressures[0], _LOADS[3]
    seg(2, 0, 0, 0, 0, pr0, 0, 0, v0=0.0)
    seg(2, 0, fzw, 0, 0, pr0, 0, 0)
    t = np.arange(int(12 * rate)) / rate
    if corner:
        seg(0, fzw, fzw, 0, 0, pr0, 0, 0, sa=4 * _DEG * np.sin(2 * np.pi * t / 4))
    else:
        seg(0, fzw, fzw, 0, 0, pr0, 0, 0, sl=0.03 * np.sin(2 * np.pi * t / 4))
    fz_now, ia_now, sa_now = fzw, 0.0, 0.0
    n_sweep = 0
    tri_c, tri_d = tri(S["corner_sweep_s"]), tri(S["db_sweep_s"])
    for k, pr in enumerate(pressures):
        if k:  # unload, stop, re-inflate, spin up, load
            seg(2, fz_now, 0, ia_now, 0, pressures[k - 1], sa_now, 0)
            seg(6, 0, 0, 0, 0, pr, 0, 0, v0=0.0, v1=0.0)
            seg(2, 0, 0, 0, 0, pr, 0, 0, v0=0.0)
            fz_now, ia_now, sa_now = 0.0, 0.0, 0.0
        for g in cambers:
            for a in alphas:
                a_rad = 0.0 if a is None else a * _DEG
                for fz in loads:
                    sp = (fz, pr, g * _DEG, a_rad)
                    seg(2.0, fz_now, fz, ia_now, g * _DEG, pr, sa_now, a_rad)
                    seg(1.0, fz, fz, g * _DEG, g * _DEG, pr, a_rad, a_rad, sp=sp)
                    if corner:
                        seg(0, fz, fz, g * _DEG, g * _DEG, pr, 0, 0, sa=S["alpha_max_deg"] * _DEG * tri_c, sp=sp,
                            sweep=n_sweep)
                    else:
                        seg(0, fz, fz, g * _DEG, g * _DEG, pr, a_rad, a_rad, sl=S["kappa_max"] * tri_d, sp=sp,
                            sweep=n_sweep)
                    seg(0.5, fz, fz, g * _DEG, g * _DEG, pr, a_rad, a_rad, sp=sp)
                    n_sweep += 1
                    fz_now, ia_now, sa_now = fz, g * _DEG, a_rad
    seg(2, fz_now, 0, ia_now, 0, pressures[-1], sa_now, 0)
    seg(2, 0, 0, 0, 0, pressures[-1], 0, 0, v1=0.0)
    cat = {k: np.concatenate(v) for k, v in segs.items()}
    n = len(cat["fz"])
    time_s = np.arange(n) / rate
    loaded = cat["fz"] > 1.0
    # relaxation lag of the forces behind the kinematic slip
    sa_eff = _lowpass(cat["sa"], rate, RELAXATION_S)
    sl_eff = _lowpass(cat["sl"], rate, RELAXATION_S)
    slip_mag = np.abs(cat["sl"]) / S["kappa_max"] + np.abs(cat["sa"]) / (S["alpha_max_deg"] * _DEG)
    fz_true = cat["fz"] * (1 + 0.02 * np.clip(slip_mag, 0, 1) + 0.003 * np.sin(2 * np.pi * time_s / 90.0))
    fzc = np.clip(fz_true, 1.0, None)
    v = cat["v"]
    # tread temperature: carcass warm-up (rolling loaded) + flash heating by the slip power of a first pass
    rolling = loaded & (v > 1.0)
    f0 = truth(fzc, slip_ratio=sl_eff, slip_angle=sa_eff, camber=cat["ia"], pressure=cat["p"], speed=v,
               temperature=50.0)
    power = np.where(loaded, np.abs(f0["fy"] * v * np.sin(sa_eff)) + np.abs(f0["fx"] * v * sl_eff), 0.0)
    temp = (_lowpass(np.where(rolling, 58.0, 30.0), rate, 200.0)
            + 0.0015 * _lowpass(power, rate, 10.0))
    temp = temp - temp[0] + 30.0
    pr_true = cat["p"] + 3e3 * np.clip((temp - 30.0) / 30.0, 0, None)
    f = truth(fzc, slip_ratio=sl_eff, slip_angle=sa_eff, camber=cat["ia"], pressure=pr_true, speed=v,
              temperature=temp)
    ia_true = cat["ia"] + 0.03 * _DEG * np.where(loaded, f["fy"], 0.0) / 1000.0   # camber compliance
    f = truth(fzc, slip_ratio=sl_eff, slip_angle=sa_eff, camber=ia_true, pressure=pr_true, speed=v,
              temperature=temp)
    f = {k: np.where(loaded, np.asarray(x, float), 0.0) for k, x in f.items()}
    rn = lambda sd: rng.normal(0.0, 1.0, n) * sd  # noqa: E731
    mz_sd, mx_sd = (1.5, 2.0) if corner else (18.0, 4.0)
    rl = p["UNLOADED_RADIUS"] - np.clip(fz_true, 0, None) / p["VERTICAL_STIFFNESS"]
    if not corner:
        rl = rl + RL_OFFSET_DRIVEBRAKE
    df = pd.DataFrame({
        "time": time_s,
        "speed": v + rn(0.04) * (v > 0),
        "slip_angle": cat["sa"] + rn(0.03 * _DEG),
        "camber": ia_true + rn(0.03 * _DEG),
        "loaded_radius": rl + rn(2e-4),
        "pressure": pr_true + rn(300.0),
        "fx": f["fx"] * (1 + rn(0.01)) + rn(10.0),
        "fy": f["fy"] * (1 + rn(0.01)) + rn(10.0),
        "fz": fz_true + rn(15.0),
        "mx": f["mx"] * (1 + rn(0.01)) + rn(mx_sd),
        "mz": f["mz"] * (1 + rn(0.01)) + rn(mz_sd),
        "slip_ratio": cat["sl"] + rn(0.002),
        "temperature": temp + rn(0.5),
    })
    re = p["UNLOADED_RADIUS"] - np.clip(fz_true, 0, None) / p["VERTICAL_STIFFNESS"] / 3.0
    df["wheel_rpm"] = df["speed"] / (2 * np.pi * re) * 60 * (1 + df["slip_ratio"])
    df["set_pressure"] = cat["p"]
    df["sp_fz"], df["sp_pressure"] = cat["spfz"], cat["spp"]
    df["sp_camber"], df["sp_slip_angle"] = cat["spia"], cat["spsa"]
    df["sweep"] = cat["sweep"].astype(int)
    for k in ("fx", "fy", "mz", "mx"):
        df[f"true_{k}"] = f[k]
    df["true_temperature"] = temp
    if S["decimate"] > 1:
        df = df.iloc[::S["decimate"]].reset_index(drop=True)
    return df


def format_record(df: pd.DataFrame, kind: str, seed: int = SEED, scale: str = "full") -> str:
    """TTC ``.dat`` text (SAE signs, metric units) of a record from :func:`make_record`."""
    text = format_ttc(df, seed=seed)
    info = (f"SYNTHETIC FSAE TTC-style {kind} run of a 16x7.5-10 slick (not a measurement, not TTC data): generated "
            f"by tyrefit.synthetic.ttc_field (MF 6.1 core + thermal grip, load-curved friction, relaxation lag), "
            f"seed {seed}, scale {scale}; SAE axis system, {len(df)} samples")
    return info + text[text.index("\n"):]


def make_pair(seed: int = SEED, scale: str = "full") -> tuple[pd.DataFrame, pd.DataFrame]:
    """``(cornering, drivebrake)`` records (SI, ISO-W DataFrames; module docstring)."""
    return make_record("cornering", seed, scale), make_record("drivebrake", seed, scale)


def write_pair(out_dir, seed: int = SEED, scale: str = "full") -> tuple[Path, Path]:
    """Write ``cornering.dat`` and ``drivebrake.dat`` (TTC text, SAE signs) to ``out_dir``; their paths."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    c, d = make_pair(seed, scale)
    a = write_text(out_dir / "cornering.dat", format_record(c, "cornering", seed, scale), force=True)
    b = write_text(out_dir / "drivebrake.dat", format_record(d, "drivebrake", seed, scale), force=True)
    return Path(a), Path(b)
