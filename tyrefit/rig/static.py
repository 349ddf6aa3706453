"""Static tyre test rig (STTR) lateral tests: stiffness, friction, peak and sliding.

On the STTR (Komana, Els and Becker, Sec. 4.2, Fig. 5) the loaded,
non-rolling tyre is pushed sideways by a plate.  The lateral force first
grows at a constant rate (stage one: the lateral stiffness), then more slowly
(stage two: adhesion saturates, the outer sidewall starts to lift), up to the
*static peak*, where the patch breaks loose; the force then falls to a
*sliding* level and stays there.  The vertical load falls during the push
because the rim-to-patch distance grows, so the friction coefficient is
taken sample by sample with the measured load, mu = Fy / Fz.

Which part of the curve feeds the rolling-tyre fit
---------------------------------------------------
``'peak'`` (default)
    the curve from zero up to the static peak.  This is the part where the
    static tyre, like a rolling one, holds its patch and the force follows
    the carcass deflection, so Eq. 1 can map displacement to slip angle; the
    peak is where the static and rolling tyres both reach the friction limit.
``'sliding'``
    the whole push, including the sliding plateau after the static peak,
    converted with the same Eq. 1.  A sliding static tyre has no rolling
    counterpart at the converted slip angle: the plateau is the fully sliding
    level (the Magic-Formula asymptote y_a that Eq. 2 uses), which a rolling
    tyre approaches only at far larger slip angles.  Feeding it to the fit
    pulls the fitted curve down just after the peak; the report of
    ``pipelines/sttr_vs_dttr.py`` shows by how much against dynamic data.

Either way the sliding level is measured per load and reported, with the
shape factor C it implies through Eq. 2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import ColumnError, DataError
from ..nomenclature import G0

__all__ = ["PARTS", "StaticRun", "StaticAnalysis", "analyse_static", "shape_factor_from_sliding"]

#: the parts of a static curve that can feed the rolling-tyre fit
PARTS = ("peak", "sliding")


def shape_factor_from_sliding(y_a, d):
    """Shape factor C from the sliding (asymptotic) level and the peak (Komana et al., Eq. 2).

    C = 1 + (1 - (2/pi) asin(y_a / D)), the root with C >= 1 (a curve that
    falls after its peak).  ``y_a`` and ``d`` may be forces or friction
    coefficients; NaN where y_a/D is outside (0, 1].
    """
    r = np.asarray(y_a, float) / np.asarray(d, float)
    with np.errstate(invalid="ignore"):
        c = 1.0 + (1.0 - 2.0 / np.pi * np.arcsin(r))   # Komana et al., Eq. 2
    return np.where((r > 0) & (r <= 1), c, np.nan)


@dataclass
class StaticRun:
    """Results of one static push (one load).

    All values SI: loads [N], displacements [m], stiffness [N/m].
    """

    run: int
    load: float                 # set load (or the load at zero displacement)
    pressure: float
    lateral_stiffness: float    # tangent at zero displacement, stage one
    peak_index: int             # position (in the run's sample order) of the static peak
    peak_displacement: float
    peak_force: float
    peak_fz: float              # measured load at the static peak
    peak_mu: float              # mu at the static peak (measured Fz)
    max_mu: float               # highest mu before sliding
    sliding_mu: float           # median mu on the sliding plateau (NaN if none)
    fz_drop: float              # relative fall of Fz from start to peak [-]
    sign: float                 # +1 pushed to positive displacements, -1 negative
    notes: list[str] = field(default_factory=list)

    @property
    def shape_factor(self) -> float:
        """C from Eq. 2 with y_a = sliding level and D = static peak."""
        return float(shape_factor_from_sliding(self.sliding_mu, self.max_mu))


def _smooth(x: np.ndarray, w: int) -> np.ndarray:
    if x.size < 3:
        return x
    return pd.Series(x).rolling(w, center=True, min_periods=1).median().to_numpy()


@dataclass
class StaticAnalysis:
    """Per-load analysis of a static lateral test.

    Attributes
    ----------
    runs : list of StaticRun
    df : DataFrame
        the samples (canonical SI columns) plus ``mu`` (= fy/fz with the
        displacement's sign made positive), ``position`` (sample order in the
        run) and ``part`` ('rising' or 'sliding').
    source : str
    """

    runs: list[StaticRun]
    df: pd.DataFrame
    source: str = ""

    def table(self) -> pd.DataFrame:
        """One row per load, in display units."""
        return pd.DataFrame([{
            "run": r.run, "load [kg]": r.load / G0, "pressure [bar]": r.pressure / 1e5,
            "lateral stiffness [N/mm]": r.lateral_stiffness * 1e-3,
            "static peak mu": r.peak_mu, "max mu": r.max_mu,
            "displacement at peak [mm]": r.peak_displacement * 1e3, "peak force [kN]": r.peak_force * 1e-3,
            "sliding mu": r.sliding_mu, "sliding / peak": r.sliding_mu / r.max_mu,
            "C from Eq. 2": r.shape_factor, "Fz drop to peak [%]": 100 * r.fz_drop,
        } for r in self.runs])

    def lateral_stiffness(self, fz: float) -> float:
        """LATERAL_STIFFNESS [N/m] at load ``fz`` [N], interpolated linearly between the tested loads."""
        loads = np.array([r.load for r in self.runs])
        k = np.array([r.lateral_stiffness for r in self.runs])
        o = np.argsort(loads)
        return float(np.interp(fz, loads[o], k[o]))

    def select(self, part: str = "peak") -> pd.DataFrame:
        """The samples that feed the rolling-tyre fit (see the module docstring)."""
        if part not in PARTS:
            raise DataError(f"unknown static part {part!r}; accepted: " + ", ".join(repr(p) for p in PARTS))
        if part == "sliding":
            return self.df
        return self.df[self.df["part"] == "rising"]

    def plot(self, ax=None, what: str = "mu"):
        """Static curves against lateral displacement, with the static peak and sliding level marked.

        ``what`` is ``'mu'`` (friction coefficient with the measured Fz), ``'fy'`` [kN] or ``'fz'`` [kN].
        """
        import matplotlib
        from matplotlib.figure import Figure

        if ax is None:
            ax = Figure(figsize=(6.5, 4.5)).subplots()
        colors = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
        for j, r in enumerate(self.runs):
            c = colors[j % len(colors)]
            g = self.df[self.df["run"] == r.run]
            dy = 1e3 * r.sign * g["lateral_displacement"]
            y = {"mu": g["mu"], "fy": 1e-3 * r.sign * g["fy"], "fz": 1e-3 * g["fz"]}[what]
            ax.plot(dy, y, ".", ms=2, color=c, alpha=0.6)
            ax.plot([], [], "-", color=c, label=f"{r.load / G0:.0f} kg")
            if what == "mu":
                ax.plot(1e3 * r.peak_displacement, r.peak_mu, "v", color=c, ms=7, mec="k")
                if np.isfinite(r.sliding_mu):
                    ax.hlines(r.sliding_mu, 1e3 * r.peak_displacement, dy.max(), color=c, ls="--", lw=1)
            elif what == "fy":
                ax.plot(1e3 * r.peak_displacement, 1e-3 * r.peak_force, "v", color=c, ms=7, mec="k")
        ax.set_xlabel("lateral displacement [mm]")
        ax.set_ylabel({"mu": "friction coefficient Fy/Fz [-]", "fy": "lateral force [kN]",
                       "fz": "vertical load (measured) [kN]"}[what])
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, title="load")
        return ax


def _tangent_stiffness(dy: np.ndarray, fy: np.ndarray, peak: float) -> float:
    """Tangent at zero of Fy = a + k dy + c dy^3 fitted where Fy <= 50 % of the peak (stage one)."""
    m = (fy <= 0.5 * peak) & (dy >= 0)
    if m.sum() < 5:
        m = np.arange(dy.size) < max(5, dy.size // 4)
    A = np.column_stack([np.ones(m.sum()), dy[m], dy[m] ** 3])
    coef, *_ = np.linalg.lstsq(A, fy[m], rcond=None)
    return float(coef[1])


def analyse_static(static) -> StaticAnalysis:
    """Analyse a static lateral test load by load.

    Parameters
    ----------
    static : Dataset or DataFrame
        canonical columns ``run``, ``lateral_displacement`` [m], ``fy`` [N]
        (same sign as the displacement), ``fz`` [N] (measured), optionally
        ``load`` [N] (set point) and ``pressure`` [Pa].  Samples in recorded
        order.

    Returns
    -------
    StaticAnalysis

    Notes
    -----
    Per run: the sign of the push is that of the median displacement; the
    static peak is the maximum of the lateral force (5-sample running median),
    "the static saturation lateral force"; the sliding level is the median
    friction coefficient over the second half of the travel after the peak
    (at least 5 mm of post-peak travel are needed, else NaN); the lateral
    stiffness is the tangent at zero of Fy = a + k dy + c dy^3 fitted up to
    half the peak force.
    """
    df = getattr(static, "df", static)
    src = getattr(static, "source", "") or "static data"
    for c in ("lateral_displacement", "fy", "fz"):
        if c not in df:
            raise ColumnError(f"{src}: static-rig data need '{c}'; found {', '.join(map(str, df.columns))}")
    df = df.copy()
    if "run" not in df:
        df["run"] = 0
    runs: list[StaticRun] = []
    parts = []
    for run, g in df.groupby("run", sort=True):
        idx = g.index
        dy = g["lateral_displacement"].to_numpy(float)
        fy = g["fy"].to_numpy(float)
        fz = g["fz"].to_numpy(float)
        if dy.size < 10:
            raise DataError(f"{src}: run {run} has {dy.size} samples; a static push needs at least 10")
        if np.any(fz <= 0):
            raise DataError(f"{src}: run {run}: measured fz <= 0 during the push; mu = Fy/Fz needs a positive load")
        sign = 1.0 if np.median(dy) >= 0 else -1.0
        dy_s, fy_s = sign * dy, sign * fy
        mu = fy_s / fz
        w = 5 if dy.size >= 25 else 3
        fy_sm = _smooth(fy_s, w)
        mu_sm = _smooth(mu, w)
        i_pk = int(np.argmax(fy_sm))
        notes = []
        span = np.ptp(dy_s)
        if span < 2e-3:
            raise DataError(f"{src}: run {run} spans {span * 1e3:.2f} mm of lateral displacement; at least 2 mm needed")
        post = dy_s[i_pk:]
        travel = float(post.max() - dy_s[i_pk]) if post.size else 0.0
        if travel >= 5e-3:
            plateau = np.arange(dy.size) >= i_pk
            plateau &= dy_s >= dy_s[i_pk] + 0.5 * travel
            sliding = float(np.median(mu[plateau]))
        else:
            sliding = float("nan")
            notes.append(f"run {run}: less than 5 mm of travel after the static peak; no sliding level")
        if i_pk >= dy.size - 2:
            notes.append(f"run {run}: the force still rises at the end of the push; the static peak was not reached")
        load = float(g["load"].mean()) if "load" in g else float(np.median(fz[: max(3, dy.size // 50)]))
        fz0 = float(np.median(fz[: max(3, dy.size // 50)]))
        pressure = float(g["pressure"].mean()) if "pressure" in g else float("nan")
        k = _tangent_stiffness(dy_s, fy_s, float(fy_sm[i_pk]))
        runs.append(StaticRun(
            run=int(run), load=load, pressure=pressure, lateral_stiffness=k, peak_index=i_pk,
            peak_displacement=float(dy_s[i_pk]), peak_force=float(fy_sm[i_pk]),
            peak_fz=float(np.median(fz[max(i_pk - 2, 0): i_pk + 3])), peak_mu=float(mu_sm[i_pk]),
            max_mu=float(np.max(mu_sm[: i_pk + 1])), sliding_mu=sliding,
            fz_drop=float(1.0 - np.median(fz[max(i_pk - 2, 0): i_pk + 3]) / fz0), sign=sign, notes=notes))
        pos = np.arange(dy.size)
        parts.append(pd.DataFrame({"mu": mu, "position": pos,
                                   "part": np.where(pos <= i_pk, "rising", "sliding")}, index=idx))
    extra = pd.concat(parts)
    out = df.join(extra)
    runs.sort(key=lambda r: r.load)
    if not math.isfinite(sum(r.lateral_stiffness for r in runs)):  # pragma: no cover - guarded above
        raise DataError(f"{src}: lateral stiffness could not be computed")
    return StaticAnalysis(runs, out, src)
