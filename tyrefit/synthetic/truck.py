"""Synthetic static- and dynamic-rig data of two 385/65R22.5 truck tyres.

**Everything this module writes is synthetic.**  No file in ``data/truck/`` is
a measurement: each is computed from the documented "truth" below, with seeded
noise, to stand in for the static tyre test rig (STTR) and dynamic tyre test
rig (DTTR) programme of Komana, Els and Becker on a Goodyear
Regional RHT 385/65R22.5 at 7.4 bar.  Two tyres are made, *A* and *B*, of the
same size but with different grip, stiffness and contact patch, so that a
static-to-rolling calibration found on A can be tried on B.

Files (``generate(out_dir)``), each starting with a ``# synthetic:`` line
--------------------------------------------------------------------------
``tyre_{a,b}_patch.csv``
    contact patch ``load [kg]``, ``pressure [bar]``, ``length [mm]``,
    ``width [mm]``, ``area [cm2]`` at 500-10000 kg (the 12 loads of Komana et al.) and
    5.9, 7.4, 9.0 bar.
``tyre_{a,b}_vertical.csv``
    vertical stiffness: ``run``, ``pressure [bar]``, ``phase`` (+1 load,
    -1 unload), ``vertical_displacement [mm]``, ``fz [N]``, a load-hold-unload
    cycle to 10000 kg at each pressure.
``tyre_{a,b}_static.csv``
    STTR lateral push at 7.4 bar and 500, 1100, 2200, 3200, 4400, 6000 kg:
    ``run``, ``load [kg]``, ``pressure [bar]``, ``lateral_displacement [mm]``,
    ``fy [N]``, ``fz [N]`` (``fy`` has the sign of the displacement, ``fz`` is
    the measured load, which falls during the push).
``tyre_{a,b}_dynamic.csv``
    DTTR free-rolling slip-angle sweeps 0 -> 12 deg at 7.4 bar, 40 km/h and
    1100, 2200, 3200, 4400, 6000 kg: ``run``, ``load [kg]``, ``pressure
    [bar]``, ``speed [km/h]``, ``slip_angle [deg]``, ``fy [N]``, ``fz [N]``.
    ISO-W signs: a positive slip angle gives a negative ``fy``.  Only positive
    slip angles are swept, as the DTTR of Komana et al. does (0-12 deg).
``truth.json``
    the parameters below, so tests and reports can compare fits with them.

The truth
---------
*Contact patch* (Komana et al., Sec. 4.1, Fig. 2).  At the reference pressure
p_ref = 7.4 bar, length and area are two-gradient piecewise-linear in the load
F with a break at the shoulder load F_b (the load at which the patch reaches
the tyre shoulders, 4800 kg for A)::

    L(F) = L0 + k1 F                         F <= F_b
    L(F) = L0 + k1 F_b + k2 (F - F_b)        F >  F_b      (k2 ~ 1.8 k1: only the length grows now)
    A(F) = A0 + a1 F ... a2 (F - F_b)                      (a2 ~ 1.2 a1: the patch squares off)
    W(F) = W_sh (1 - exp(-F / F_w)),   F_w = F_b / ln 100  (99 % of the shoulder width at F_b)

*Pressure law*: a stiffer (higher-pressure) tyre needs more load for the same
patch, so every dimension is a function of the effective load
F (p_ref / p)^beta, beta = 0.75: the shoulder load scales as (p / p_ref)^beta and
the gradients as (p_ref / p)^beta.  Noise: 2 mm on length and width, 1.5 % on
area.

*Vertical stiffness* (Fig. 3).  Loading is two-gradient piecewise-linear in
the deflection, k_v1 below and k_v2 above the shoulder load F_b(p) (the
sidewalls join in); both scale with pressure as (0.3 + 0.7 p / p_ref).  At the
top the load is held and the tyre creeps by 4.5 % of the deflection; unloading
follows gradients 0.97 k_v1, 0.97 k_v2 from there, so the unloading curve lies
below the loading one (hysteresis) and ends at a small residual deflection.
Noise: 150 N and 0.15 mm.

*Rolling tyre (DTTR truth)*, "PAC89-like" in PAC89 units (Fz in kN, alpha in
deg): mu = Fy/Fz = (D/Fz) sin(C atan(B a - E (B a - atan B a))) with
C = a0, BCD = a3 sin(2 atan(Fz/a4)) [N/deg], E = a6 Fz + a7 and a peak friction
coefficient mu0 (0.76 for A, 0.80 for B) below the rated load F_r = 4250 kg that
falls above it (Sec. 4.2: the overloaded patch lifts at its centre)::

    mu_peak(F) = mu0 (1 - k_o softplus_s(F - F_r) / F_r),  s = 300 kg

-- not exactly representable in PAC89, whose D/Fz is linear in Fz.
Cornering stiffness at the rated load is about 7.9 kN/deg (A) and 7.5 kN/deg
(B): 0.18-0.19 /deg, a truck-tyre cornering coefficient.  DTTR noise: the
load wanders by 3 % (AR(1), the air-suspension and road), the friction by 1 %
(road patches), 0.05 deg on the slip-angle encoder, 0.8 % of the peak force
plus 60 N on Fy, 100 N on the Fz load cell.

*Static lateral test (STTR truth).*  The link between a static lateral
displacement and a rolling slip angle is the tyre's lateral deflection: in
steady free rolling at slip angle alpha the carcass under the contact patch is
deflected sideways by y with tan(alpha) = y / sigma, where sigma = C_alpha/C_y
is the relaxation length (Pacejka, *Tyre and Vehicle Dynamics*, Ch. 5/7).
The truth assumes (i) the static tyre pushed by Delta y carries the same
carcass deflection and hence the same friction coefficient as the rolling
tyre at tan(alpha) = Delta y / sigma, up to the static peak, and (ii) the
relaxation length is a fixed multiple of the patch half-length a = L/2:
sigma = 4.5 a = n L with n = 2.25, the same for both tyres (about 0.44 m at
the rated load, a truck-tyre relaxation length).  Then, in the
notation of Komana et al. Eq. 1, alpha = f(Delta y / L) atan(Delta y / L) with
f(u) = atan(u / n) / atan(u), which is 1/n = 0.44 for small u and tends to 1:
the uncalibrated conversion f = 1 overstates the slip angle about 2.25-fold.
The lateral stiffness follows as C_y = C_alpha / sigma.

During the push the vertical plate is held, and the rim-to-patch distance
grows as the patch moves sideways (Sec. 4.2): the deflection falls by
sqrt(l^2 + y^2) - l, with an effective lever l = 1.0 m (about twice the
loaded radius, since the rim also rolls a little), and the measured Fz falls
by the vertical stiffness times that.  At the static peak (the maximum of mu) the
patch breaks loose; the friction then decays over 4 mm of further travel to
the sliding level mu_peak sin(pi C / 2) -- the Magic-Formula asymptote that
Eq. 2 of Komana et al. reads off the sliding plateau -- while the carcass springs
back in proportion to the force.  Noise: 0.1 mm, 50 N + 0.5 % on Fy, 60 N on
Fz, and 1 % stick-slip scatter while sliding.

All numbers are plausible for the size, not taken from any tyre's data.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..io.outputs import write_text
from ..models.pac89 import magic_formula
from ..nomenclature import G0

__all__ = [
    "TruckTyreTruth",
    "TYRE_A",
    "TYRE_B",
    "PATCH_LOADS_KG",
    "PRESSURES_BAR",
    "STATIC_LOADS_KG",
    "DYNAMIC_LOADS_KG",
    "patch_truth",
    "vertical_loading",
    "relaxation_length",
    "true_f",
    "mu_rolling",
    "static_truth",
    "patch_table",
    "vertical_table",
    "static_table",
    "dynamic_table",
    "generate",
]

#: contact-patch and vertical-test loads of Komana et al., Sec. 4 [kg]
PATCH_LOADS_KG = (500, 1000, 2100, 3200, 3835, 4300, 5235, 6500, 7000, 8000, 9000, 10000)
#: inflation pressures of Komana et al. [bar]
PRESSURES_BAR = (5.9, 7.4, 9.0)
#: STTR lateral-test loads of Komana et al., Sec. 4.2 [kg]
STATIC_LOADS_KG = (500, 1100, 2200, 3200, 4400, 6000)
#: DTTR loads (a subset; the trailer axle cannot be unloaded to 500 kg) [kg]
DYNAMIC_LOADS_KG = (1100, 2200, 3200, 4400, 6000)
#: pressure of the lateral tests [bar]
TEST_PRESSURE_BAR = 7.4
_KG = G0  # N per kg of load


@dataclass(frozen=True)
class TruckTyreTruth:
    """The true parameters of one synthetic truck tyre (see the module docstring).

    Loads in kg, lengths in m, stiffnesses in N/m, PAC89-like coefficients in
    PAC89 units (kN, deg).
    """

    name: str
    seed: int
    # contact patch at p_ref
    p_ref_bar: float
    shoulder_load_kg: float     # F_b, breakpoint of length, area, vertical stiffness
    length0: float              # L0 [m]
    length_k1: float            # [m/kg]
    length_k2: float            # [m/kg]
    area0: float                # [m2]
    area_k1: float              # [m2/kg]
    area_k2: float              # [m2/kg]
    shoulder_width: float       # W_sh [m]
    pressure_exponent: float    # beta
    # vertical
    kv1: float                  # [N/m] below the shoulder load, at p_ref
    kv2: float                  # [N/m] above
    unload_ratio: float         # unloading gradients / loading gradients
    creep: float                # creep at the top as a fraction of the deflection
    unloaded_radius: float      # [m]
    lever: float                # [m] effective rim-to-patch lever of the static push
    # rolling (DTTR) truth
    a0: float                   # C
    mu0: float                  # peak friction below the rated load
    overload_slope: float       # k_o
    rated_load_kg: float
    a3: float                   # [N/deg]
    a4: float                   # [kN]
    a6: float                   # [1/kN]
    a7: float                   # [-]
    # static-to-rolling link
    n_relax: float              # sigma / L
    slide_decay: float          # [m] travel over which the static peak decays to sliding

    @property
    def width_load_kg(self) -> float:
        """F_w: the exponential width law reaches 99 % of W_sh at the shoulder load."""
        return self.shoulder_load_kg / np.log(100.0)


TYRE_A = TruckTyreTruth(
    name="A", seed=385_651, p_ref_bar=7.4, shoulder_load_kg=4800.0,
    length0=0.085, length_k1=0.026e-3, length_k2=0.046e-3,
    area0=29e-4, area_k1=0.107e-4, area_k2=0.129e-4, shoulder_width=0.285, pressure_exponent=0.75,
    kv1=0.95e6, kv2=1.25e6, unload_ratio=0.97, creep=0.045, unloaded_radius=0.536, lever=1.0,
    a0=1.45, mu0=0.76, overload_slope=0.35, rated_load_kg=4250.0, a3=8400.0, a4=60.0, a6=-0.012, a7=-0.2,
    n_relax=2.25, slide_decay=4e-3,
)

TYRE_B = TruckTyreTruth(
    name="B", seed=385_652, p_ref_bar=7.4, shoulder_load_kg=5100.0,
    length0=0.090, length_k1=0.024e-3, length_k2=0.043e-3,
    area0=32e-4, area_k1=0.1046e-4, area_k2=0.124e-4, shoulder_width=0.292, pressure_exponent=0.75,
    kv1=1.05e6, kv2=1.35e6, unload_ratio=0.97, creep=0.045, unloaded_radius=0.536, lever=1.0,
    a0=1.38, mu0=0.80, overload_slope=0.30, rated_load_kg=4250.0, a3=7800.0, a4=55.0, a6=-0.012, a7=-0.2,
    n_relax=2.25, slide_decay=4e-3,
)


# ----------------------------------------------------------------------------- truth (noise-free)
def _effective_load_kg(t: TruckTyreTruth, fz, pressure_bar):
    """F (p_ref / p)^beta in kg: the pressure law of every patch dimension."""
    return np.asarray(fz, float) / _KG * (t.p_ref_bar / np.asarray(pressure_bar, float)) ** t.pressure_exponent


def _two_gradient(x, y0, k1, k2, xb):
    """y0 + k1 x below xb, continuing with k2 above (Komana et al., Sec. 4.1)."""
    x = np.asarray(x, float)
    return y0 + k1 * np.minimum(x, xb) + k2 * np.maximum(x - xb, 0.0)


def patch_truth(t: TruckTyreTruth, fz, pressure_bar=TEST_PRESSURE_BAR):
    """True contact-patch length [m], width [m] and area [m2] at load ``fz`` [N]."""
    fe = _effective_load_kg(t, fz, pressure_bar)
    length = _two_gradient(fe, t.length0, t.length_k1, t.length_k2, t.shoulder_load_kg)
    area = _two_gradient(fe, t.area0, t.area_k1, t.area_k2, t.shoulder_load_kg)
    width = t.shoulder_width * (1.0 - np.exp(-fe / t.width_load_kg))
    return length, width, area


def shoulder_load(t: TruckTyreTruth, pressure_bar) -> float:
    """True shoulder (breakpoint) load [N] at ``pressure_bar``."""
    return t.shoulder_load_kg * _KG * (pressure_bar / t.p_ref_bar) ** t.pressure_exponent


def _kv(t: TruckTyreTruth, pressure_bar):
    s = 0.3 + 0.7 * pressure_bar / t.p_ref_bar
    return t.kv1 * s, t.kv2 * s


def vertical_loading(t: TruckTyreTruth, deflection, pressure_bar=TEST_PRESSURE_BAR):
    """True loading-branch vertical force [N] at ``deflection`` [m]."""
    k1, k2 = _kv(t, pressure_bar)
    db = shoulder_load(t, pressure_bar) / k1
    return _two_gradient(deflection, 0.0, k1, k2, db)


def _vertical_deflection(t: TruckTyreTruth, fz, pressure_bar=TEST_PRESSURE_BAR):
    """Inverse of :func:`vertical_loading`: loading-branch deflection [m] at ``fz`` [N]."""
    k1, k2 = _kv(t, pressure_bar)
    fb = shoulder_load(t, pressure_bar)
    fz = np.asarray(fz, float)
    return np.minimum(fz, fb) / k1 + np.maximum(fz - fb, 0.0) / k2


def relaxation_length(t: TruckTyreTruth, fz, pressure_bar=TEST_PRESSURE_BAR):
    """True relaxation length sigma = n L [m] at ``fz`` [N]."""
    return t.n_relax * patch_truth(t, fz, pressure_bar)[0]


def true_f(t: TruckTyreTruth, u):
    """The true Eq. 1 factor f(u) = atan(u/n)/atan(u), u = Delta y / L (f(0) = 1/n)."""
    u = np.asarray(u, float)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(np.abs(u) < 1e-12, 1.0 / t.n_relax, np.arctan(u / t.n_relax) / np.arctan(u))


def mu_peak(t: TruckTyreTruth, fz):
    """True peak friction coefficient at ``fz`` [N]: mu0, falling above the rated load."""
    fr = t.rated_load_kg * _KG
    s = 300.0 * _KG
    over = s * np.logaddexp(0.0, (np.asarray(fz, float) - fr) / s)
    return t.mu0 * (1.0 - t.overload_slope * over / fr)


def mu_rolling(t: TruckTyreTruth, fz, slip_angle):
    """True free-rolling friction coefficient -Fy/Fz (positive for a positive ISO-W slip angle).

    ``fz`` [N], ``slip_angle`` [rad]; a PAC89-shaped curve (see module docstring).
    """
    fz = np.asarray(fz, float)
    fzk = fz * 1e-3
    alpha = np.degrees(np.asarray(slip_angle, float))
    mu_d = mu_peak(t, fz)
    bcd = t.a3 * np.sin(2.0 * np.arctan(fzk / t.a4))
    b = bcd / (t.a0 * mu_d * fz)
    e = t.a6 * fzk + t.a7
    return magic_formula(alpha, b, t.a0, mu_d, e)


def true_cornering_stiffness(t: TruckTyreTruth, fz):
    """True cornering stiffness [N/rad] at ``fz`` [N]."""
    return t.a3 * np.sin(2.0 * np.arctan(np.asarray(fz, float) * 1e-3 / t.a4)) * 180.0 / np.pi


def static_truth(t: TruckTyreTruth, load_kg: float, dy):
    """Noise-free static push at set load ``load_kg``: (fy [N], fz [N], peak index) at plate travel ``dy`` [m].

    Rising branch: mu = mu_rolling(Fz, atan(dy / (n L(Fz)))) at the falling Fz;
    after the static peak the friction decays to mu_peak sin(pi C / 2).
    """
    dy = np.asarray(dy, float)
    fz0 = load_kg * _KG
    p = TEST_PRESSURE_BAR
    lever = t.lever
    k1, k2 = _kv(t, p)
    kv = k1 if fz0 <= shoulder_load(t, p) else k2

    def fz_at(y):
        return fz0 - kv * (np.sqrt(lever**2 + y**2) - lever)

    fz_r = fz_at(dy)
    alpha = np.arctan(dy / relaxation_length(t, fz_r, p))
    mu_r = mu_rolling(t, fz_r, alpha)
    # the static peak: the first maximum of the lateral force along the push
    # ("static saturation lateral force", Sec. 4.2); with Fz falling it comes
    # at or a little before the maximum of mu
    falling = np.flatnonzero(np.diff(mu_r * fz_r) < 0)
    i_pk = int(falling[0]) if falling.size else len(dy) - 1
    mu_pk, dy_pk = mu_r[i_pk], dy[i_pk]
    mu_sl = mu_pk * np.sin(np.pi * t.a0 / 2.0)
    after = dy > dy_pk
    mu = mu_r.copy()
    mu[after] = mu_sl + (mu_pk - mu_sl) * np.exp(-(dy[after] - dy_pk) / t.slide_decay)
    yc = np.where(after, dy_pk * mu / mu_pk, dy)      # carcass springs back while sliding
    fz = fz_at(yc)
    return mu * fz, fz, i_pk


# ----------------------------------------------------------------------------- noisy tables (file units)
def _ar1(rng, n, rho, sd):
    """AR(1) noise with stationary standard deviation ``sd``."""
    e = rng.normal(0.0, sd * np.sqrt(1 - rho**2), n)
    x = np.empty(n)
    x[0] = rng.normal(0.0, sd)
    for i in range(1, n):
        x[i] = rho * x[i - 1] + e[i]
    return x


def patch_table(t: TruckTyreTruth, rng: np.random.Generator, loads_kg=PATCH_LOADS_KG,
                pressures_bar=PRESSURES_BAR) -> pd.DataFrame:
    """Contact-patch table with noise (columns in file units)."""
    rows = []
    for p in pressures_bar:
        for kg in loads_kg:
            length, width, area = patch_truth(t, kg * _KG, p)
            rows.append({
                "load [kg]": float(kg), "pressure [bar]": p,
                "length [mm]": round(1e3 * length + rng.normal(0, 2.0), 1),
                "width [mm]": round(1e3 * width + rng.normal(0, 2.0), 1),
                "area [cm2]": round(1e4 * area * (1 + rng.normal(0, 0.015)), 1),
            })
    return pd.DataFrame(rows)


def vertical_table(t: TruckTyreTruth, rng: np.random.Generator, max_load_kg: float = 10000.0,
                   pressures_bar=PRESSURES_BAR, n: int = 60) -> pd.DataFrame:
    """Load-hold-unload cycles, one run per pressure (columns in file units)."""
    rows = []
    for run, p in enumerate(pressures_bar, start=1):
        k1, k2 = _kv(t, p)
        fmax = max_load_kg * _KG
        dmax = float(_vertical_deflection(t, fmax, p))
        d_load = np.linspace(0.0, dmax, n)
        f_load = vertical_loading(t, d_load, p)
        # hold: creep at constant load, then unload with softer gradients through the top point
        dtop = dmax * (1 + t.creep)
        fb = shoulder_load(t, p)
        r = t.unload_ratio
        f_un = np.linspace(fmax, 0.0, n)
        d_un = dtop - (fmax - np.maximum(f_un, fb)) / (r * k2) - np.maximum(fb - f_un, 0.0) / (r * k1)
        for ph, d, f in ((1, d_load, f_load), (-1, d_un, f_un)):
            dn = d + rng.normal(0, 0.15e-3, d.size)
            fn = np.maximum(f + rng.normal(0, 150.0, f.size), 0.0)
            for di, fi in zip(dn, fn):
                rows.append({"run": run, "pressure [bar]": p, "phase": ph,
                             "vertical_displacement [mm]": round(1e3 * di, 2), "fz [N]": round(fi, 0)})
    return pd.DataFrame(rows)


def static_table(t: TruckTyreTruth, rng: np.random.Generator, loads_kg=STATIC_LOADS_KG,
                 step: float = 0.6e-3) -> pd.DataFrame:
    """STTR lateral pushes at 7.4 bar, one run per load (columns in file units)."""
    rows = []
    for run, kg in enumerate(loads_kg, start=1):
        probe = np.arange(0.0, 0.4, 0.5e-3)
        _, _, i_pk = static_truth(t, kg, probe)
        dy_end = probe[i_pk] * 1.25 + 0.030          # push on well into the sliding plateau
        dy = np.arange(0.0, dy_end, step)
        fy, fz, i_pk = static_truth(t, kg, dy)
        sliding = np.arange(dy.size) > i_pk
        fy = fy * (1 + np.where(sliding, 0.01, 0.0) * rng.normal(0, 1, dy.size))
        fy = fy + rng.normal(0, 50.0, dy.size) + 0.005 * fy * rng.normal(0, 1, dy.size)
        fz = fz + rng.normal(0, 60.0, dy.size)
        dyn = dy + rng.normal(0, 0.1e-3, dy.size)
        for a, b, c in zip(dyn, fy, fz):
            rows.append({"run": run, "load [kg]": float(kg), "pressure [bar]": TEST_PRESSURE_BAR,
                         "lateral_displacement [mm]": round(1e3 * a, 2), "fy [N]": round(b, 0),
                         "fz [N]": round(c, 0)})
    return pd.DataFrame(rows)


def dynamic_table(t: TruckTyreTruth, rng: np.random.Generator, loads_kg=DYNAMIC_LOADS_KG,
                  max_slip_deg: float = 12.0, step_deg: float = 0.05) -> pd.DataFrame:
    """DTTR slip-angle sweeps 0 -> 12 deg at 7.4 bar, 40 km/h (columns in file units, ISO-W)."""
    rows = []
    for run, kg in enumerate(loads_kg, start=1):
        alpha = np.radians(np.arange(0.0, max_slip_deg + 1e-9, step_deg))
        n = alpha.size
        fz_true = kg * _KG * (1 + _ar1(rng, n, 0.95, 0.03))
        mu = mu_rolling(t, fz_true, alpha) * (1 + _ar1(rng, n, 0.9, 0.01))
        fy = -mu * fz_true
        d = mu_peak(t, kg * _KG) * kg * _KG
        fy = fy + rng.normal(0, 0.008 * d + 60.0, n)
        fz_meas = fz_true + rng.normal(0, 100.0, n)
        a_meas = np.degrees(alpha) + rng.normal(0, 0.05, n)
        for a, b, c in zip(a_meas, fy, fz_meas):
            rows.append({"run": run, "load [kg]": float(kg), "pressure [bar]": TEST_PRESSURE_BAR,
                         "speed [km/h]": 40.0, "slip_angle [deg]": round(a, 3), "fy [N]": round(b, 0),
                         "fz [N]": round(c, 0)})
    return pd.DataFrame(rows)


# ----------------------------------------------------------------------------- files
def _csv(df: pd.DataFrame, what: str, seed: int) -> str:
    head = (f"# synthetic: generated by tyrefit.synthetic.truck, seed {seed}\n"
            f"# {what}\n")
    return head + df.to_csv(index=False, lineterminator="\n")


def truth_dict(t: TruckTyreTruth) -> dict:
    """The truth of one tyre, plus derived values at the test pressure, for ``truth.json``."""
    d = asdict(t)
    fr = t.rated_load_kg * _KG
    d["derived"] = {
        "shoulder_load_N_by_pressure_bar": {str(p): shoulder_load(t, p) for p in PRESSURES_BAR},
        "patch_length_at_rated_load_m": float(patch_truth(t, fr)[0]),
        "relaxation_length_at_rated_load_m": float(relaxation_length(t, fr)),
        "cornering_stiffness_at_rated_load_N_per_rad": float(true_cornering_stiffness(t, fr)),
        "lateral_stiffness_at_rated_load_N_per_m": float(true_cornering_stiffness(t, fr) / relaxation_length(t, fr)),
        "vertical_stiffness_loading_at_rated_load_N_per_m": float(_kv(t, TEST_PRESSURE_BAR)[0]),
        "true_f_at_u_0": 1.0 / t.n_relax,
    }
    return d


_README = """# data/truck — synthetic truck-tyre rig data

**Synthetic.** Made by `tyrefit.synthetic.truck.generate` (seeded; physics and
parameters in that module's docstring and in `truth.json`). No file here is a
measurement. Two 385/65R22.5 tyres, A and B, with different grip, stiffness and
contact patch, stand in for the static (STTR) and dynamic (DTTR) rig programme of
Komana, Els and Becker, *Cost efficient tyre testing, modelling and validation for
PBS assessments*.

| file | test |
|---|---|
| `tyre_?_patch.csv` | contact patch length, width, area vs load (500-10000 kg) at 5.9 / 7.4 / 9.0 bar |
| `tyre_?_vertical.csv` | vertical stiffness load-hold-unload cycles at 5.9 / 7.4 / 9.0 bar |
| `tyre_?_static.csv` | STTR lateral push at 7.4 bar, 500-6000 kg (fy with the displacement's sign, measured falling fz) |
| `tyre_?_dynamic.csv` | DTTR slip-angle sweeps 0-12 deg at 7.4 bar, 1100-6000 kg, ISO-W signs (positive slip -> negative fy) |
| `truth.json` | the true parameters |

Regenerate with `python -m tyrefit.synthetic --out data --only truck`.
"""


def generate(out_dir: Path) -> list[Path]:
    """Write the synthetic truck data to ``out_dir`` and return the files written.

    Existing files are replaced (the generator is deterministic: same seed, same bytes).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files: list[Path] = []
    for t in (TYRE_A, TYRE_B):
        rng = np.random.default_rng(t.seed)
        stem = f"tyre_{t.name.lower()}"
        tables = [
            ("patch", patch_table(t, rng), "contact patch vs load and pressure"),
            ("vertical", vertical_table(t, rng), "vertical stiffness: load-hold-unload cycle per pressure"),
            ("static", static_table(t, rng), "static tyre test rig (STTR) lateral push at 7.4 bar"),
            ("dynamic", dynamic_table(t, rng),
             "dynamic tyre test rig (DTTR) free-rolling slip-angle sweeps at 7.4 bar, 40 km/h, ISO-W signs"),
        ]
        for kind, df, what in tables:
            path = out / f"{stem}_{kind}.csv"
            write_text(path, _csv(df, f"truck tyre {t.name} (385/65R22.5): {what}", t.seed), force=True)
            files.append(path)
    truth = {"synthetic": "generated by tyrefit.synthetic.truck", "tyres": {t.name: truth_dict(t)
                                                                             for t in (TYRE_A, TYRE_B)}}
    files.append(write_text(out / "truth.json", json.dumps(truth, indent=2) + "\n", force=True))
    files.append(write_text(out / "README.md", _README, force=True))
    return files
