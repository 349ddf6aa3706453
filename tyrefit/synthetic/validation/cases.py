"""Rig layouts, noise models and generated cases of the diagnose validation.

**Synthetic.**  A case is one data set: a :class:`~.truth.TruthTyre` (the null
tyre or the null tyre plus one effect) sampled on a rig *layout* with one
*noise model*, seeded.  The same (layout, noise, effect, seed) always gives
the same data, bit for bit.

Layouts (passenger tyre, rated load 6000 N, 220 kPa unless varied)
------------------------------------------------------------------
``load5``      5 loads 2.0-8.0 kN, one sweep -12 -> +12 deg each (the DTTR test of Komana et al.: five loads,
               one sweep each)
``load6``      6 loads 2.0-8.0 kN, one sweep each (a supplier's dynamic-rig sheet) - the layout of
               the diagnosis targets
``load7``      7 loads 2.0-8.0 kN, one sweep each
``onesided6``  6 loads, one sweep 0 -> +12 deg each (a one-sided rig programme: no shift is testable)
``grid8``      4 loads x cambers 0, +4 deg
``grid24``     4 loads x cambers -4, 0, +4 deg x pressures 200, 250 kPa
``grid60``     5 loads x cambers -4, -2, +2, +4 deg x pressures 190, 220, 250 kPa

Slip is sampled every 0.5 deg (49 points over -12..+12 deg; a flat-track rig
sweeping at 1-2 deg/s and logging at a few Hz after filtering); the measured
load jitters 0.5 % (1 sigma) about its set point.

Noise models (``sigma`` = the total standard deviation per point)
-----------------------------------------------------------------
``iid``      independent Gaussian noise;
``offsets``  a random offset per sweep (0.5 sigma, rig drift / zeroing between sweeps) plus
             independent noise (sqrt(0.75) sigma);
``ar1``      Gaussian AR(1) noise along each sweep with correlation 0.8 between neighbouring points
             (0.5 deg apart), stationary sd sigma;
``ar1_09``   the same at correlation 0.9 (not in the default plan).

sigma = 40 N: 1 % of the peak force at 4 kN, 0.5-2 % over the load range
(flat-track lateral-force channels after filtering; the previous session's
bundled passenger tyre has 26 N).  The TRUE sigma is stored with each case so
held-out errors can be compared with it.
"""

from __future__ import annotations

import zlib
from dataclasses import dataclass

import numpy as np
import pandas as pd

from .truth import EFFECT_FAMILY, P0, RATED_LOAD, TruthTyre

__all__ = ["LAYOUTS", "NOISE_MODELS", "SIGMA", "Layout", "Case", "make_case", "noise", "layout_frame",
           "applicable"]

_DEG = np.pi / 180.0

NOISE_MODELS = ("iid", "offsets", "ar1")
#: further noise models a run may ask for (not in the default plan): AR(1) at 0.9
EXTRA_NOISE_MODELS = ("ar1_09",)
#: total noise standard deviation per point [N]
SIGMA = 40.0
#: AR(1) correlation between neighbouring points
AR_RHO = 0.8
#: sd of the per-sweep offset as a share of sigma (``offsets`` noise)
OFFSET_SHARE = 0.5


@dataclass(frozen=True)
class Layout:
    """A rig test programme: one slip sweep per load x camber x pressure."""

    name: str
    loads: tuple[float, ...]
    cambers_deg: tuple[float, ...] = (0.0,)
    pressures: tuple[float, ...] = (P0,)
    slip_min_deg: float = -12.0
    slip_max_deg: float = 12.0
    step_deg: float = 0.5
    description: str = ""

    @property
    def n_sweeps(self) -> int:
        return len(self.loads) * len(self.cambers_deg) * len(self.pressures)

    @property
    def two_sided(self) -> bool:
        return self.slip_min_deg < 0 < self.slip_max_deg


_L6 = (2000.0, 3200.0, 4400.0, 5600.0, 6800.0, 8000.0)
LAYOUTS: dict[str, Layout] = {
    "load5": Layout("load5", (2000.0, 3500.0, 5000.0, 6500.0, 8000.0),
                    description="5 loads, one -12..12 deg sweep each (the DTTR test of Komana et al.)"),
    "load6": Layout("load6", _L6, description="6 loads, one -12..12 deg sweep each (supplier's rig sheet)"),
    "load7": Layout("load7", tuple(1000.0 * np.arange(2, 9)), description="7 loads, one -12..12 deg sweep each"),
    "onesided6": Layout("onesided6", _L6, slip_min_deg=0.0, description="6 loads, one 0..12 deg sweep each"),
    "grid8": Layout("grid8", (2000.0, 4000.0, 6000.0, 8000.0), (0.0, 4.0),
                    description="4 loads x 2 cambers"),
    "grid24": Layout("grid24", (2000.0, 4000.0, 6000.0, 8000.0), (-4.0, 0.0, 4.0), (200e3, 250e3),
                     description="4 loads x 3 cambers x 2 pressures"),
    "grid60": Layout("grid60", (2000.0, 3500.0, 5000.0, 6500.0, 8000.0), (-4.0, -2.0, 2.0, 4.0),
                     (190e3, 220e3, 250e3), description="5 loads x 4 cambers x 3 pressures"),
}


def applicable(layout: Layout, effect: str | None) -> bool:
    """Whether the layout varies what ``effect`` changes (a camber effect needs cambers, ...).

    Effects a layout *can* carry but not identify (shifts on one-sided sweeps)
    stay applicable: the diagnosis must then say so rather than find them.
    """
    if effect is None:
        return True
    if effect in ("camber", "camber_shift"):
        return len(layout.cambers_deg) >= 2
    if effect == "pressure":
        return len(layout.pressures) >= 2
    if effect == "overload":
        return max(layout.loads) > RATED_LOAD
    return True


def layout_frame(layout: Layout, rng: np.random.Generator | None = None) -> pd.DataFrame:
    """Set points (and measured loads, jittered 0.5 % when ``rng`` is given) of a layout.

    Columns ``run``, ``fz`` [N], ``slip_angle`` [rad], ``camber`` [rad],
    ``pressure`` [Pa]; one sweep per load x camber x pressure, in rig order.
    """
    n = int(round((layout.slip_max_deg - layout.slip_min_deg) / layout.step_deg)) + 1
    slips = np.linspace(layout.slip_min_deg, layout.slip_max_deg, n) * _DEG
    parts = []
    run = 0
    for p in layout.pressures:
        for c in layout.cambers_deg:
            for fz in layout.loads:
                parts.append(pd.DataFrame({"run": run, "fz": fz, "slip_angle": slips, "camber": c * _DEG,
                                           "pressure": p}))
                run += 1
    d = pd.concat(parts, ignore_index=True)
    if rng is not None:
        d["fz"] = d["fz"] * (1.0 + 0.005 * rng.standard_normal(len(d)))
    return d


def noise(kind: str, sweep: np.ndarray, sigma: float, rng: np.random.Generator) -> np.ndarray:
    """Noise of model ``kind`` (see the module docstring) for points in sweeps ``sweep`` (0..G-1, contiguous)."""
    sweep = np.asarray(sweep)
    n = len(sweep)
    if kind == "iid":
        return rng.normal(0.0, sigma, n)
    if kind == "offsets":
        g = int(sweep.max()) + 1
        w = np.sqrt(1.0 - OFFSET_SHARE**2)
        return rng.normal(0.0, OFFSET_SHARE * sigma, g)[sweep] + rng.normal(0.0, w * sigma, n)
    if kind in ("ar1", "ar1_09"):
        rho = AR_RHO if kind == "ar1" else 0.9
        e = rng.normal(0.0, sigma * np.sqrt(1.0 - rho**2), n)
        start = np.r_[True, sweep[1:] != sweep[:-1]]
        out = np.empty(n)
        for i in range(n):
            out[i] = rng.normal(0.0, sigma) if start[i] else rho * out[i - 1] + e[i]
        return out
    raise ValueError(f"unknown noise model {kind!r}; known: {', '.join(NOISE_MODELS + EXTRA_NOISE_MODELS)}")


@dataclass
class Case:
    """One generated data set with its truth."""

    layout: str
    noise: str
    effect: str | None
    seed: int
    sigma: float
    tyre: TruthTyre
    data: pd.DataFrame
    truth_fy: np.ndarray

    @property
    def family(self) -> str | None:
        """The diagnose family the effect must be reported as (None for a null)."""
        return EFFECT_FAMILY[self.effect] if self.effect else None

    @property
    def rated_load(self) -> float:
        return self.tyre.rated_load

    @property
    def key(self) -> str:
        return f"{self.layout}/{self.noise}/{self.effect or 'null'}/{self.seed}"


def _seed(layout: str, kind: str, effect: str | None, seed: int, repeat: int = 0) -> np.random.SeedSequence:
    words = [zlib.crc32(s.encode()) for s in (layout, kind, effect or "null")]
    return np.random.SeedSequence([*words, int(seed)] + ([int(repeat)] if repeat else []))


def make_case(layout: str | Layout, noise_model: str = "iid", effect: str | None = None, seed: int = 0,
              sigma: float = SIGMA, repeat: int = 0) -> Case:
    """Generate one case: the truth tyre (null, or null + ``effect``) on ``layout`` with noise.

    Deterministic in (layout, noise model, effect, seed).  ``effect=None`` is a null case.
    ``repeat`` = k > 0 gives the k-th independent rerun of the same test: the same tyre and set points,
    new load jitter and new noise (held-out data for the fitted model; ``repeat=0`` is the case itself).
    """
    lay = LAYOUTS[layout] if isinstance(layout, str) else layout
    if noise_model not in NOISE_MODELS + EXTRA_NOISE_MODELS:
        raise ValueError(f"unknown noise model {noise_model!r}; known: {', '.join(NOISE_MODELS)}")
    rng = np.random.default_rng(_seed(lay.name, noise_model, effect, seed, repeat))
    tyre = TruthTyre.with_effects((effect,) if effect else ())
    d = layout_frame(lay, rng)
    fy = tyre.lateral_force(d["fz"].to_numpy(), d["slip_angle"].to_numpy(), d["camber"].to_numpy(),
                            d["pressure"].to_numpy())
    d["fy"] = fy + noise(noise_model, d["run"].to_numpy(), sigma, rng)
    return Case(lay.name, noise_model, effect, int(seed), float(sigma), tyre, d, fy)
