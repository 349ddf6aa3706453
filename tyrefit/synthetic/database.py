"""A **synthetic** tyre database: N tyres with known PAC89 lateral coefficients.

Nothing written here is a measurement.  The generator exists so that batch
fitting (``tyrefit batch fit``), its tests and the benchmarks can check every
fitted ``.tir`` against the curves that made the data.  It writes to a folder
you name (a temporary one in tests and benchmarks); no bulk copy is bundled
in ``data/``.

Physics
-------
Each tyre is a passenger-car-sized PAC89 tyre (Bakker, Nyborg & Pacejka 1989;
evaluated by :func:`tyrefit.models.pac89.lateral_force`, Chrono's ChPac89Tire)
whose pure-side-slip lateral force is measured at ``loads`` vertical loads,
camber 0, in one slip-angle sweep per load.  The coefficients are drawn
(seeded, per tyre) so that the derived quantities have a realistic spread:

=====================  ======================================  ====================
quantity               drawn as                                PAC89 coefficients
=====================  ======================================  ====================
nominal load           Fnom ~ U(3.5, 6.5) kN                   (FNOMIN)
shape factor           C ~ U(1.30, 1.70)                       a0 = C
friction at 0 load     mu0 ~ U(0.95, 1.25)                     a2 = 1000 mu0
load sensitivity       mu falls by s ~ U(5, 15) % per Fnom     a1 = -s a2 / Fnom
cornering stiffness    BCD(Fnom)/Fnom ~ U(0.20, 0.40) 1/deg    a3 = BCD(Fnom)/sin(2 atan(Fnom/a4))
stiffness peak load    a4 ~ Fnom x U(1.5, 2.5) kN              a4
curvature              E = a6 Fz + a7, a6 ~ U(-0.05, 0),       a6, a7 (E <= 0.6 < 1)
                       a7 ~ U(-0.5, 0.6)
ply steer / conicity   Sh = a9 Fz + a10, Sv = a12 Fz + a13:    a9, a10, a12, a13
(``shifts=True``)      a9 ~ N(0, 0.01) deg/kN, a10 ~ N(0, 0.05)
                       deg, a12 ~ N(0, 4) N/kN, a13 ~ N(0, 15) N
camber terms           not excited (camber 0): a5 = a8 = a11 = 0
=====================  ======================================  ====================

Data: ``loads`` set points at Fnom x (0.5 ... 1.4), each a sweep of
``points // loads`` slip angles uniformly from -12 to +12 deg (ISO-W).  The
measured load scatters about its set point with sigma = 0.3 % Fnom (the curve
is evaluated at the measured load, as a rig measures it), and the lateral
force carries Gaussian noise of sigma = ``noise`` x the peak |Fy| at that load
(default 0.5 %).

Files: ``tyre_0000.csv`` ... with unit headers ``run, fz [N], slip_angle [deg],
camber [deg], fy [N]``, each starting with a ``# synthetic:`` line, and
``truth.json`` holding every tyre's coefficients, FNOMIN, set loads and slip
grid.  :func:`curve_error` compares a fitted tyre with its truth over that
noiseless grid, relative to the peak force.

Seeding: tyre ``i`` of database seed ``s`` uses ``numpy.random.default_rng([s, i])``,
so a tyre does not change when N changes.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..io.outputs import write_text
from ..models import pac89

__all__ = ["Database", "draw_coefficients", "tyre_data", "generate_database", "load_truth",
           "truth_grid", "curve_error", "generate"]

#: slip-angle sweep limits [deg]
SLIP_LIMIT_DEG = 12.0
#: load set points as fractions of the nominal load (the first ``loads`` of an even spread)
LOAD_SPAN = (0.5, 1.4)


@dataclass
class Database:
    """A generated database: the data files and, per file name, its truth."""

    root: Path
    paths: list[Path]
    truth: dict[str, dict] = field(default_factory=dict)
    seed: int = 0


def draw_coefficients(rng: np.random.Generator, shifts: bool = True) -> tuple[dict[str, float], float]:
    """Draw one tyre's PAC89 lateral coefficients (PAC89 units) and its nominal load [N].

    See the module docstring for the distributions.
    """
    fnom = rng.uniform(3.5, 6.5)  # kN
    C = rng.uniform(1.30, 1.70)
    mu0 = rng.uniform(0.95, 1.25)
    s = rng.uniform(0.05, 0.15)
    cc = rng.uniform(0.20, 0.40)  # BCD(Fnom) / Fnom  [1/deg]
    a4 = fnom * rng.uniform(1.5, 2.5)
    a2 = 1000.0 * mu0
    a1 = -s * a2 / fnom
    a3 = cc * fnom * 1000.0 / math.sin(2.0 * math.atan(fnom / a4))
    a6 = rng.uniform(-0.05, 0.0)
    a7 = rng.uniform(-0.5, 0.6)
    c = {k: 0.0 for k in pac89.LATERAL}
    c.update(a0=C, a1=a1, a2=a2, a3=a3, a4=a4, a6=a6, a7=a7)
    if shifts:
        c.update(a9=rng.normal(0.0, 0.01), a10=rng.normal(0.0, 0.05),
                 a12=rng.normal(0.0, 4.0), a13=rng.normal(0.0, 15.0))
    return {k: float(v) for k, v in c.items()}, float(fnom * 1e3)


def _set_loads(fnom: float, loads: int) -> np.ndarray:
    return fnom * np.linspace(LOAD_SPAN[0], LOAD_SPAN[1], loads)


def tyre_data(coeffs: dict[str, float], fnom: float, rng: np.random.Generator, *, points: int = 200,
              loads: int = 4, noise: float = 0.005) -> dict[str, np.ndarray]:
    """Noisy sweeps of one tyre, SI/ISO-W: run, fz [N], slip_angle [rad], camber [rad], fy [N]."""
    per = max(points // loads, 3)
    set_fz = _set_loads(fnom, loads)
    alpha = np.radians(np.linspace(-SLIP_LIMIT_DEG, SLIP_LIMIT_DEG, per))
    run = np.repeat(np.arange(1, loads + 1), per)
    fz = np.repeat(set_fz, per) + rng.normal(0.0, 0.003 * fnom, run.size)
    sa = np.tile(alpha, loads)
    fy = pac89.lateral_force(coeffs, fz, sa, 0.0)
    peak = np.repeat([np.max(np.abs(pac89.lateral_force(coeffs, f, alpha, 0.0))) for f in set_fz], per)
    fy = fy + rng.normal(0.0, 1.0, run.size) * noise * peak
    return {"run": run, "fz": fz, "slip_angle": sa, "camber": np.zeros_like(sa), "fy": fy}


def _csv_text(d: dict[str, np.ndarray], seed: int, index: int) -> str:
    lines = [f"# synthetic: generated by tyrefit.synthetic.database, seed {seed}, tyre {index}",
             "run,fz [N],slip_angle [deg],camber [deg],fy [N]"]
    deg = np.degrees
    for r, fz, sa, cb, fy in zip(d["run"], d["fz"], deg(d["slip_angle"]), deg(d["camber"]), d["fy"]):
        lines.append(f"{r:d},{fz:.3f},{sa:.5f},{cb:.4f},{fy:.3f}")
    return "\n".join(lines) + "\n"


def generate_database(out_dir: str | os.PathLike, n: int = 200, *, seed: int = 0, points: int = 200,
                      loads: int = 4, noise: float = 0.005, shifts: bool = True,
                      force: bool = False) -> Database:
    """Write ``n`` synthetic tyres (``tyre_0000.csv`` ...) and ``truth.json`` to ``out_dir``.

    Parameters
    ----------
    out_dir : path
        folder to write (created); existing files are replaced only with ``force``.
    n : int
        number of tyres.
    seed : int
        database seed; tyre ``i`` uses ``default_rng([seed, i])``.
    points : int
        points per tyre (split evenly over ``loads`` sweeps).
    loads : int
        load set points per tyre.
    noise : float
        lateral-force noise sigma as a fraction of the peak |Fy| at each load [-].
    shifts : bool
        draw ply-steer / conicity shifts (a9, a10, a12, a13); else they are 0.

    Returns
    -------
    Database
    """
    root = Path(out_dir)
    root.mkdir(parents=True, exist_ok=True)
    truth: dict[str, dict] = {}
    paths: list[Path] = []
    for i in range(n):
        rng = np.random.default_rng([seed, i])
        coeffs, fnom = draw_coefficients(rng, shifts=shifts)
        d = tyre_data(coeffs, fnom, rng, points=points, loads=loads, noise=noise)
        name = f"tyre_{i:04d}"
        p = write_text(root / f"{name}.csv", _csv_text(d, seed, i), force=force)
        paths.append(p)
        per = max(points // loads, 3)
        truth[name] = {"coefficients": coeffs, "fnomin": fnom,
                       "loads": _set_loads(fnom, loads).tolist(),
                       "slip_angle_deg": np.linspace(-SLIP_LIMIT_DEG, SLIP_LIMIT_DEG, per).tolist(),
                       "noise": noise}
    doc = {"generator": "tyrefit.synthetic.database", "synthetic": True, "seed": seed, "n": n,
           "points": points, "loads": loads, "noise": noise, "shifts": shifts, "tyres": truth}
    write_text(root / "truth.json", json.dumps(doc, indent=1) + "\n", force=force)
    return Database(root=root, paths=paths, truth=truth, seed=seed)


def load_truth(out_dir: str | os.PathLike) -> dict[str, dict]:
    """The per-tyre truth written by :func:`generate_database` (name -> entry)."""
    return json.loads((Path(out_dir) / "truth.json").read_text(encoding="utf-8"))["tyres"]


def truth_grid(entry: dict) -> tuple[np.ndarray, np.ndarray]:
    """The noiseless (fz [N], slip_angle [rad]) grid of one truth entry, broadcast 2-D."""
    fz = np.asarray(entry["loads"], float)[:, None]
    sa = np.radians(np.asarray(entry["slip_angle_deg"], float))[None, :]
    return np.broadcast_arrays(fz, sa)


def curve_error(tyre, entry: dict) -> float:
    """Max |Fy_fit - Fy_true| over the truth grid, relative to the peak |Fy_true| [-].

    ``tyre`` is anything with ``.fy(fz, slip_angle, camber)`` (a
    :class:`~tyrefit.tyres.pac89.Pac89Tyre`) or a coefficient mapping.
    """
    fz, sa = truth_grid(entry)
    true = pac89.lateral_force(entry["coefficients"], fz, sa, 0.0)
    if hasattr(tyre, "fy"):
        fit = tyre.fy(fz, sa, 0.0)
    else:
        fit = pac89.lateral_force(tyre, fz, sa, 0.0)
    return float(np.max(np.abs(fit - true)) / np.max(np.abs(true)))


def generate(out_dir: Path, n: int = 10, seed: int = 0) -> list[Path]:
    """Write a small database of ``n`` tyres to ``out_dir``; return the written paths.

    Not part of the bundled ``data/`` (see the module docstring): call it with
    a temporary folder, or ``python -c "from tyrefit.synthetic.database import
    generate; generate(Path('db'), n=200)"`` for a larger one.
    """
    db = generate_database(out_dir, n, seed=seed, force=True)
    return db.paths + [Path(out_dir) / "truth.json"]
