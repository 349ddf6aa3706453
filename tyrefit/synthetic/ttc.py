"""**Synthetic** FSAE-TTC-style flat-track record and a small TYDEX file.

Nothing written here is a measurement.  The generator imitates the layout
and the test programme of an FSAE Tire Test Consortium cornering run (a
10-inch FSAE slick on a flat-track machine) so that the TTC reader and its
segmentation can be tested on a realistic continuous record.

Test programme (one continuous record, sampled at ``rate`` = 20 Hz)
------------------------------------------------------------------
1. standstill, unloaded (4 s); spin-up to 40 km/h (4 s); load applied;
2. warm-up at 890 N (200 lb): three +/-4 deg sine cycles (12 s);
3. for pressure 12 psi then 10 psi (82.7, 68.9 kPa), camber 0, 2, 4 deg, and
   loads 1112, 667, 222, 1557 N (250, 150, 50, 350 lb): a 2.5 s ramp of load
   and camber with the slip angle at 0, 1 s dwell, one slip-angle sweep
   0 -> +12 -> -12 -> 0 deg at 3 deg/s (16 s), 1 s dwell;
   between the pressure blocks the tyre is unloaded, stopped and re-inflated;
4. at 10 psi and 0 deg camber the speed is raised to 72 km/h and the four
   loads are swept again;
5. unload and stop.

That is 28 slip sweeps (24 + 4) at 4 loads x 3 cambers x 2 pressures (+ the
72 km/h block), plus a warm-up the segmentation should drop.

Tyre physics (ISO-W inside, written in the SAE axis system of TTC data)
-----------------------------------------------------------------------
Lateral force: PAC89 (:func:`tyrefit.models.pac89.lateral_force`) with
:data:`FSAE_PAC89`: friction mu = a1 Fz + a2 (Fz in kN) about 2.85 at 222 N
falling to 2.5 at 1557 N, cornering stiffness a3 sin(2 atan(Fz/a4)) about
420 N/deg at 1112 N, camber thrust a11 = 25 N/(kN deg).  Pressure scales the
peak by 1 - 0.25 (p/p0 - 1) and the cornering stiffness by 1 + 0.3 (p/p0 - 1)
(p0 = 82.7 kPa); speed lowers the peak by 0.06 % per km/h above 40 km/h.
Aligning moment: pneumatic trail t = 0.02 m (Fz/1 kN)^0.3 cos(pi/2 min(|alpha|/9 deg, 1)),
Mz = -t Fy.  Rolling resistance Fx = -0.015 Fz minus a slip drag; overturning
moment Mx = 0.02 m * Fy.  Loaded radius 260 mm - Fz / 110 kN/m.

Measurement imperfections: the load control lets Fz rise by 3 % at 12 deg;
noise (1 sigma) 0.02 deg on SA and IA, 12 N on Fz, 15 N + 1 % on Fy, 8 N on
Fx, 0.5 N m on Mz, 0.2 kPa on P, 0.15 km/h on V; camber compliance
0.03 deg per kN of Fy; pressure grows by up to 1.5 kPa as the tyre warms
(surface temperature 25 -> 55 degC).

Signs in the file: SAE (z down, y right): FZ negative, and a positive SA
gives a negative FY (SA = -alpha_ISO, FY = -Fy_ISO, MZ = -Mz_ISO, FZ = -Fz).
Read it with ``read_data(path, convention='sae')``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from ..io.outputs import write_text
from ..models import pac89

__all__ = ["generate", "make_record", "format_ttc", "make_tydex", "FSAE_PAC89", "PROGRAMME", "SEED"]

SEED = 20240611

#: PAC89 lateral coefficients of the synthetic FSAE slick (PAC89 units: kN, deg, N)
FSAE_PAC89 = {"a0": 1.45, "a1": -250.0, "a2": 2900.0, "a3": 470.0, "a4": 1.7, "a5": 0.008,
              "a6": -0.15, "a7": -0.4, "a8": 0.02, "a9": 0.0, "a10": 0.05, "a11": 25.0, "a12": 4.0, "a13": 5.0}

_LB = 4.4482216152605
_PSI = 6894.757293168361

#: the test programme (set points)
PROGRAMME = {
    "loads_N": [250 * _LB, 150 * _LB, 50 * _LB, 350 * _LB],
    "cambers_deg": [0.0, 2.0, 4.0],
    "pressures_kPa": [12 * _PSI / 1e3, 10 * _PSI / 1e3],
    "speeds_kmh": [40.0, 72.0],
    "warmup_load_N": 200 * _LB,
    "sweep_amplitude_deg": 12.0,
    "sweep_rate_deg_s": 3.0,
}


def _segment(dur, rate, fz0, fz1, ia0, ia1, p0, p1, v0, v1, sa=None):
    n = max(1, int(round(dur * rate)))
    s = np.linspace(0.0, 1.0, n, endpoint=False)
    t = s * dur
    return {"fz": fz0 + (fz1 - fz0) * s, "ia": ia0 + (ia1 - ia0) * s, "p": p0 + (p1 - p0) * s,
            "v": v0 + (v1 - v0) * s, "sa": sa(t) if sa is not None else np.zeros(n)}


def _triangle(amp: float, rate_deg_s: float):
    T = 4 * amp / rate_deg_s  # 0 -> +A -> -A -> 0

    def f(t):
        ph = (t / T) % 1.0
        return amp * np.where(ph < 0.25, 4 * ph, np.where(ph < 0.75, 2 - 4 * ph, 4 * ph - 4))

    return f, T


def make_record(seed: int = SEED, rate: float = 20.0, programme: dict | None = None) -> tuple[pd.DataFrame, list[dict]]:
    """The continuous record in SI and ISO-W, and the list of the sweeps it holds.

    ``programme`` updates :data:`PROGRAMME` (other loads, cambers, pressures or
    sweep amplitude; with one entry in ``speeds_kmh`` there is no speed block).

    Returns
    -------
    (DataFrame, list of dict)
        columns ``time speed slip_angle camber pressure fx fy fz mx mz slip_ratio
        loaded_radius wheel_rpm temperature`` [SI; temperature in degC]; each
        sweep dict gives its set points ``fz`` [N], ``camber_deg``,
        ``pressure_kpa``, ``speed_kmh``.
    """
    rng = np.random.default_rng(seed)
    P = {**PROGRAMME, **(programme or {})}
    amp = P["sweep_amplitude_deg"]
    tri, T = _triangle(amp, P["sweep_rate_deg_s"])
    segs, truth = [], []
    p_a, v_a = P["pressures_kPa"][0], P["speeds_kmh"][0]
    wl = P["warmup_load_N"]
    segs.append(_segment(4, rate, 0, 0, 0, 0, p_a, p_a, 0, 0))
    segs.append(_segment(4, rate, 0, 0, 0, 0, p_a, p_a, 0, v_a))
    segs.append(_segment(2, rate, 0, wl, 0, 0, p_a, p_a, v_a, v_a))
    segs.append(_segment(12, rate, wl, wl, 0, 0, p_a, p_a, v_a, v_a, sa=lambda t: 4 * np.sin(2 * np.pi * t / 4)))
    fz_now, ia_now, p_now, v_now = wl, 0.0, p_a, v_a

    def sweep(load, ia, p, v):
        nonlocal fz_now, ia_now
        segs.append(_segment(2.5, rate, fz_now, load, ia_now, ia, p, p, v, v))
        segs.append(_segment(1, rate, load, load, ia, ia, p, p, v, v))
        segs.append(_segment(T, rate, load, load, ia, ia, p, p, v, v, sa=tri))
        segs.append(_segment(1, rate, load, load, ia, ia, p, p, v, v))
        truth.append({"fz": load, "camber_deg": ia, "pressure_kpa": p, "speed_kmh": v})
        fz_now, ia_now = load, ia

    for k, p in enumerate(P["pressures_kPa"]):
        if k:  # unload, stop, re-inflate, spin up, load
            segs.append(_segment(2, rate, fz_now, 0, ia_now, 0, p_now, p_now, v_now, v_now))
            segs.append(_segment(3, rate, 0, 0, 0, 0, p_now, p_now, v_now, 0))
            segs.append(_segment(10, rate, 0, 0, 0, 0, p_now, p, 0, 0))
            segs.append(_segment(3, rate, 0, 0, 0, 0, p, p, 0, v_a))
            segs.append(_segment(2, rate, 0, P["loads_N"][0], 0, 0, p, p, v_a, v_a))
            fz_now, ia_now, p_now = P["loads_N"][0], 0.0, p
        for ia in P["cambers_deg"]:
            for load in P["loads_N"]:
                sweep(load, ia, p, v_now)
    # speed step at the last pressure, camber back to 0
    for v_b in P["speeds_kmh"][1:]:
        segs.append(_segment(2.5, rate, fz_now, P["loads_N"][0], ia_now, 0, p_now, p_now, v_now, v_now))
        segs.append(_segment(4, rate, P["loads_N"][0], P["loads_N"][0], 0, 0, p_now, p_now, v_now, v_b))
        fz_now, ia_now, v_now = P["loads_N"][0], 0.0, v_b
        for load in P["loads_N"]:
            sweep(load, 0.0, p_now, v_now)
    segs.append(_segment(2, rate, fz_now, 0, 0, 0, p_now, p_now, v_now, v_now))
    segs.append(_segment(3, rate, 0, 0, 0, 0, p_now, p_now, v_now, 0))

    cat = {k: np.concatenate([s[k] for s in segs]) for k in segs[0]}
    n = len(cat["fz"])
    t = np.arange(n) / rate
    alpha_deg = cat["sa"] + rng.normal(0, 0.02, n)
    # load control: a small rise with slip, noise; unloaded samples read noise around zero
    fz = cat["fz"] * (1 + 0.03 * (cat["sa"] / amp) ** 2) + rng.normal(0, 12.0, n) + 4 * np.sin(2 * np.pi * t / 7)
    temp = 25 + 30 * (1 - np.exp(-t / 200.0)) + rng.normal(0, 0.3, n)
    p_kpa = cat["p"] + 1.5 * (temp - 25) / 30 + rng.normal(0, 0.2, n)
    v = cat["v"] + rng.normal(0, 0.15, n) * (cat["v"] > 0)
    # tyre model on the true (set) slip; pressure and speed scale peak and stiffness
    coef = dict(FSAE_PAC89)
    rel_p = cat["p"] / PROGRAMME["pressures_kPa"][0] - 1
    k_d = (1 - 0.25 * rel_p) * (1 - 0.0006 * np.clip(cat["v"] - 40, 0, None))
    k_k = 1 + 0.3 * rel_p
    fzk = np.clip(cat["fz"] * (1 + 0.03 * (cat["sa"] / amp) ** 2), 1.0, None)
    gamma = np.deg2rad(cat["ia"])
    alpha = np.deg2rad(cat["sa"])
    # scaled coefficients per sample: D scales a1, a2; BCD scales a3
    fy_base = np.empty(n)
    for kd, kk in set(zip(np.round(k_d, 6), np.round(k_k, 6))):
        sel = (np.round(k_d, 6) == kd) & (np.round(k_k, 6) == kk)
        c = dict(coef, a1=coef["a1"] * kd, a2=coef["a2"] * kd, a3=coef["a3"] * kk)
        fy_base[sel] = pac89.lateral_force(c, fzk[sel], alpha[sel], gamma[sel])
    loaded = cat["fz"] > 1.0
    fy = np.where(loaded, fy_base * (1 + rng.normal(0, 0.01, n)), 0.0) + rng.normal(0, 15.0, n)
    trail = 0.02 * (np.clip(cat["fz"], 0, None) / 1000) ** 0.3 * np.cos(
        np.pi / 2 * np.minimum(np.abs(cat["sa"]) / 9.0, 1.0))
    mz = -trail * fy + rng.normal(0, 0.5, n)
    fx = -0.015 * np.clip(cat["fz"], 0, None) - np.abs(fy) * np.abs(np.sin(alpha)) * 0.3 + rng.normal(0, 8.0, n)
    mx = 0.02 * fy + rng.normal(0, 0.3, n)
    ia = cat["ia"] + rng.normal(0, 0.02, n) + 0.03 * fy / 1000
    rl = 0.260 - np.clip(fz, 0, None) / 110e3
    re = rl + 0.004
    rpm = (v / 3.6) / (2 * np.pi * re) * 60
    sl = rng.normal(0, 0.002, n) - 0.003 * loaded
    df = pd.DataFrame({
        "time": t, "speed": v / 3.6, "wheel_rpm": rpm, "slip_angle": np.deg2rad(alpha_deg),
        "camber": np.deg2rad(ia), "loaded_radius": rl, "pressure": p_kpa * 1e3, "fx": fx, "fy": fy,
        "fz": fz, "mx": mx, "mz": mz, "slip_ratio": sl, "temperature": temp,
    })
    return df, truth


#: TTC channels: (name, glossary column, {unit system: (unit, factor from SI)})
_CHANNELS = [
    ("ET", "time", {"metric": ("s", 1.0), "usc": ("s", 1.0)}, "{:.3f}"),
    ("V", "speed", {"metric": ("kph", 3.6), "usc": ("mph", 1 / 0.44704)}, "{:.2f}"),
    ("N", "wheel_rpm", {"metric": ("rpm", 1.0), "usc": ("rpm", 1.0)}, "{:.1f}"),
    ("SA", "slip_angle", {"metric": ("deg", 180 / math.pi), "usc": ("deg", 180 / math.pi)}, "{:.3f}"),
    ("IA", "camber", {"metric": ("deg", 180 / math.pi), "usc": ("deg", 180 / math.pi)}, "{:.3f}"),
    ("RL", "loaded_radius", {"metric": ("cm", 100.0), "usc": ("in", 1 / 0.0254)}, "{:.2f}"),
    ("P", "pressure", {"metric": ("kPa", 1e-3), "usc": ("psi", 1 / _PSI)}, "{:.2f}"),
    ("FX", "fx", {"metric": ("N", 1.0), "usc": ("lb", 1 / _LB)}, "{:.1f}"),
    ("FY", "fy", {"metric": ("N", 1.0), "usc": ("lb", 1 / _LB)}, "{:.1f}"),
    ("FZ", "fz", {"metric": ("N", 1.0), "usc": ("lb", 1 / _LB)}, "{:.1f}"),
    ("MX", "mx", {"metric": ("N-m", 1.0), "usc": ("ft-lb", 1 / 1.3558179483314004)}, "{:.2f}"),
    ("MZ", "mz", {"metric": ("N-m", 1.0), "usc": ("ft-lb", 1 / 1.3558179483314004)}, "{:.2f}"),
    ("SL", "slip_ratio", {"metric": ("none", 1.0), "usc": ("none", 1.0)}, "{:.4f}"),
    ("TSTC", "temperature", {"metric": ("degC", 1.0), "usc": ("degC", 1.0)}, "{:.1f}"),
]
#: columns that change sign from ISO-W to SAE
_SAE = {"slip_angle", "fy", "fz", "mz"}


def format_ttc(df: pd.DataFrame, units: str = "metric", seed: int = SEED) -> str:
    """Write the record as TTC ``.dat`` text (SAE signs): info line, names, units, tab-separated rows."""
    cols, names, unit_line = [], [], []
    for name, col, u, fmt in _CHANNELS:
        unit, f = u[units]
        x = df[col].to_numpy() * f
        if col in _SAE:
            x = -x
        cols.append((x, fmt))
        names.append(name)
        unit_line.append(unit)
    info = (f"SYNTHETIC FSAE TTC-style cornering run (not a measurement): generated by tyrefit.synthetic.ttc, "
            f"seed {seed}; 10-inch FSAE slick, SAE axis system, {len(df)} samples")
    lines = [info, "\t".join(names), "\t".join(unit_line)]
    body = np.column_stack([np.char.mod(fmt.replace("{:", "%").replace("}", ""), x) for x, fmt in cols])
    lines.extend("\t".join(r) for r in body)
    return "\n".join(lines) + "\n"


def make_tydex(seed: int = SEED) -> str:
    """A small TYDEX file: three slip-angle sweeps (-10..10 deg) at 700, 1100, 1500 N, ISO-W.

    ``FYW`` is written in kN with conversion factor 0.001 (raw values in N), to
    exercise the channel conversion; pressure, camber and speed are constants.
    """
    rng = np.random.default_rng(seed + 1)
    loads = [700.0, 1100.0, 1500.0]
    alpha_deg = np.linspace(-10, 10, 41)
    rows = []
    t = 0.0
    for fz in loads:
        a = alpha_deg + rng.normal(0, 0.02, alpha_deg.size)
        fzm = fz + rng.normal(0, 8.0, a.size)
        fy = pac89.lateral_force(FSAE_PAC89, fzm, np.deg2rad(a)) + rng.normal(0, 12.0, a.size)
        mz = -0.02 * fy * np.cos(np.pi / 2 * np.minimum(np.abs(a) / 9, 1)) + rng.normal(0, 0.4, a.size)
        for k in range(a.size):
            rows.append((t, a[k], fzm[k], fy[k], mz[k]))
            t += 0.1
    head = [
        "**HEADER",
        f"{'RELEASE':<10}{'Release of TYDEX-Format':<30}1.3",
        f"{'MEASID':<10}{'Measurement id':<30}SYNTH-TTC-TDX-01",
        f"{'SUPPLIER':<10}{'Data supplier':<30}tyrefit.synthetic.ttc (synthetic)",
        f"{'DATE':<10}{'Date':<30}01-01-2024",
        "**COMMENTS",
        f"SYNTHETIC data, not a measurement: generated by tyrefit.synthetic.ttc, seed {seed}.",
        "Three slip-angle sweeps of the synthetic FSAE slick at 700, 1100, 1500 N; ISO-W (TYDEX W-axis) signs.",
        "**CONSTANTS",
        f"{'INFLPRES':<10}{'Inflation pressure':<30}{'kPa':<10}{82.7:<10}",
        f"{'INCLANGL':<10}{'Inclination angle':<30}{'deg':<10}{0.0:<10}",
        f"{'LONGVEL':<10}{'Longitudinal velocity':<30}{'km/h':<10}{40.0:<10}",
        f"{'FNOMIN':<10}{'Nominal wheel load':<30}{'N':<10}{1100.0:<10}",
        "**MEASURCHANNELS",
        "! name    description                   unit      factor    offset m. offset p.",
        f"{'RUNTIME':<10}{'Running time':<30}{'s':<10}{'1':<10}{'0':<10}{'0':<10}",
        f"{'SLIPANGL':<10}{'Slip angle':<30}{'deg':<10}{'1':<10}{'0':<10}{'0':<10}",
        f"{'FZW':<10}{'Vertical force':<30}{'N':<10}{'1':<10}{'0':<10}{'0':<10}",
        f"{'FYW':<10}{'Lateral force':<30}{'kN':<10}{'0.001':<10}{'0':<10}{'0':<10}",
        f"{'MZW':<10}{'Self aligning moment':<30}{'Nm':<10}{'1':<10}{'0':<10}{'0':<10}",
        "**MEASURDATA",
    ]
    body = ["".join(f"{v:10.3f}" for v in r) for r in rows]
    return "\n".join(head + body + ["**END"]) + "\n"


README = """# data/ttc — synthetic FSAE TTC-style record and TYDEX file

**Synthetic.** Made by `tyrefit.synthetic.ttc.generate` (seed {seed}; physics,
test programme and noise in that module's docstring). No file here is a
measurement and none comes from the FSAE Tire Test Consortium; only the file
layout and the kind of test programme imitate theirs.

| file | what |
|---|---|
| `fsae_cornering.dat` | one continuous flat-track cornering record, TTC `.dat` layout (info line, names line, units line, tab separated), SAE signs (FZ negative), {n} samples at 20 Hz: warm-up, then 28 slip-angle sweeps 0 -> +12 -> -12 -> 0 deg at 4 loads (222, 667, 1112, 1557 N), 3 cambers (0, 2, 4 deg), 2 pressures (12, 10 psi) and 2 speeds (40, 72 km/h), with transitions, lift-offs and dwell between them. Read with `--convention sae`. |
| `fsae_sweeps.tdx` | TYDEX 1.3 file: three slip-angle sweeps (-10..10 deg) at 700, 1100, 1500 N, ISO-W; `FYW` in kN with conversion factor 0.001; pressure, camber and speed as constants. |

`tyrefit inspect data/ttc/fsae_cornering.dat --convention sae` shows the sweeps
and conditions the segmentation finds.  Regenerate with
`python -m tyrefit.synthetic --out data --only ttc`.
"""


def generate(out_dir: Path) -> list[Path]:
    """Write ``fsae_cornering.dat`` (TTC-style, SAE signs), ``fsae_sweeps.tdx`` and ``README.md`` to ``out_dir``."""
    out_dir = Path(out_dir)
    df, _ = make_record()
    a = write_text(out_dir / "fsae_cornering.dat", format_ttc(df), force=True)
    b = write_text(out_dir / "fsae_sweeps.tdx", make_tydex(), force=True)
    c = write_text(out_dir / "README.md", README.format(seed=SEED, n=len(df)), force=True)
    return [a, b, c]
