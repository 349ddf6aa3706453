"""Vertical stiffness from load-unload tests: two gradients and hysteresis.

Komana, Els and Becker (Sec. 4.1, Fig. 3): the vertical force of a
truck tyre grows piecewise-linearly with the deflection, with a second,
steeper gradient once the contact patch reaches the shoulders and the
sidewalls start to carry load; loading is stiffer than unloading
(hysteresis: the tyre stores and dissipates energy).  Each branch is fitted
with the two-gradient law of :mod:`tyrefit.rig.patch`; the loop energy
(the area enclosed by the load-unload cycle) is the energy lost per cycle.

For the tyre files:

* ``VERTICAL_STIFFNESS`` (``.tir``) is the mean of the loading and unloading
  tangent stiffnesses at the rated load: a simulated rolling tyre has one
  spring and no hysteresis, and the middle of the loop is its elastic part;
* the Chrono JSON ``Vertical Curve Data`` table is the middle of the loop,
  F_mid(delta) = (F_load(delta) + F_unload(delta)) / 2, from (0, 0).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import ColumnError, DataError
from ..nomenclature import G0
from .patch import TwoGradientFit, fit_two_gradient

__all__ = ["VerticalFit", "VerticalModel", "fit_vertical", "loop_energy"]


def loop_energy(deflection, force) -> float:
    """Energy enclosed by a load-unload cycle [J] (shoelace area of the recorded loop).

    Parameters
    ----------
    deflection : array_like
        vertical deflection [m] in recorded order (loading then unloading).
    force : array_like
        vertical force [N].
    """
    x = np.asarray(deflection, float)
    y = np.asarray(force, float)
    return float(0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y)))


@dataclass
class VerticalFit:
    """Load and unload branches at one pressure.

    Attributes
    ----------
    pressure : float
        [Pa] (NaN if unknown).
    loading, unloading : TwoGradientFit or None
        force [N] against deflection [m]; ``breakpoint`` is a deflection [m].
    loop_energy : float
        energy dissipated per cycle [J] (NaN without an unloading branch).
    loading_work : float
        work done while loading [J].
    max_force : float
        [N].
    """

    pressure: float
    loading: TwoGradientFit
    unloading: TwoGradientFit | None
    loop_energy: float
    loading_work: float
    max_force: float

    @property
    def breakpoint_force(self) -> float:
        """Load [N] at the loading branch's breakpoint (compare with the patch's shoulder load)."""
        return float(self.loading(self.loading.breakpoint))

    def _tangent(self, fit: TwoGradientFit, fz) -> np.ndarray:
        fb = float(fit(fit.breakpoint))
        return np.where(np.asarray(fz, float) <= fb, fit.k1, fit.k2)

    def stiffness(self, fz) -> np.ndarray:
        """Tangent vertical stiffness [N/m] at load ``fz`` [N]: mean of the loading and unloading tangents."""
        k = self._tangent(self.loading, fz)
        if self.unloading is not None:
            k = 0.5 * (k + self._tangent(self.unloading, fz))
        return k

    def mid_force(self, deflection) -> np.ndarray:
        """Middle of the loop: (F_load + F_unload) / 2 [N] at ``deflection`` [m], >= 0."""
        d = np.asarray(deflection, float)
        f = np.maximum(self.loading(d), 0.0)
        if self.unloading is not None:
            f = 0.5 * (f + np.maximum(self.unloading(d), 0.0))
        return f

    def curve(self, max_force: float | None = None, n: int = 11) -> list[tuple[float, float]]:
        """(deflection [m], force [N]) table of the loop's middle, from (0, 0) to ``max_force``."""
        fmax = self.max_force if max_force is None else max_force
        d = np.linspace(0.0, 1.2 * self._deflection_at(fmax), 400)
        f = np.maximum.accumulate(self.mid_force(d) - self.mid_force(0.0))
        dmax = float(np.interp(fmax, f, d))
        dd = np.linspace(0.0, dmax, n)
        ff = np.interp(dd, d, f)
        return [(float(a), float(b)) for a, b in zip(dd, ff)]

    def _deflection_at(self, fz) -> float:
        lf = self.loading
        fb = float(lf(lf.breakpoint))
        if fz <= fb:
            return float((fz - lf.y0) / lf.k1)
        return float(lf.breakpoint + (fz - fb) / lf.k2)


@dataclass
class VerticalModel:
    """Vertical-stiffness fits per pressure.

    Attributes
    ----------
    fits : list of VerticalFit
        by increasing pressure.
    source : str
    """

    fits: list[VerticalFit]
    source: str = ""
    notes: list[str] = field(default_factory=list)

    def at(self, pressure=None) -> VerticalFit:
        """The fit at the tested pressure closest to ``pressure`` [Pa] (the only one if one)."""
        if pressure is None or len(self.fits) == 1 or not np.isfinite(pressure):
            return self.fits[len(self.fits) // 2]
        ps = np.array([f.pressure for f in self.fits])
        return self.fits[int(np.nanargmin(np.abs(ps - pressure)))]

    def vertical_stiffness(self, fz, pressure=None) -> float:
        """VERTICAL_STIFFNESS [N/m] at load ``fz`` [N] (mean of loading and unloading tangents)."""
        return float(self.at(pressure).stiffness(fz))

    def curve(self, pressure=None, max_force=None, n: int = 11) -> list[tuple[float, float]]:
        """Chrono ``Vertical Curve Data`` table at ``pressure``: list of (deflection [m], force [N])."""
        return self.at(pressure).curve(max_force, n)

    def table(self, patch=None) -> pd.DataFrame:
        """One row per pressure: gradients, breakpoints, loop energy (and the patch's shoulder load)."""
        rows = []
        for f in self.fits:
            r = {"pressure [bar]": f.pressure / 1e5,
                 "loading k1 [N/mm]": f.loading.k1 * 1e-3, "loading k2 [N/mm]": f.loading.k2 * 1e-3,
                 "loading breakpoint [mm]": f.loading.breakpoint * 1e3,
                 "breakpoint load [kg]": f.breakpoint_force / G0}
            if patch is not None and patch.has("length"):
                sl = patch.shoulder_load(f.pressure if np.isfinite(f.pressure) else None)
                r["patch shoulder load [kg]"] = sl / G0
                r["difference [%]"] = 100.0 * (f.breakpoint_force - sl) / sl
            if f.unloading is not None:
                r.update({"unloading k1 [N/mm]": f.unloading.k1 * 1e-3,
                          "unloading k2 [N/mm]": f.unloading.k2 * 1e-3,
                          "loop energy [J]": f.loop_energy,
                          "loss [% of loading work]": 100.0 * f.loop_energy / f.loading_work})
            rows.append(r)
        return pd.DataFrame(rows)

    def plot(self, data: pd.DataFrame | None = None, ax=None):
        """Force against deflection, loading and unloading, per pressure (Komana et al., Fig. 3)."""
        import matplotlib
        from matplotlib.figure import Figure

        if ax is None:
            ax = Figure(figsize=(6.5, 4.5)).subplots()
        colors = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
        for j, f in enumerate(self.fits):
            c = colors[j % len(colors)]
            if data is not None:
                d = data[np.isclose(data["pressure"], f.pressure, rtol=0.01)] if "pressure" in data and \
                    np.isfinite(f.pressure) else data
                ax.plot(1e3 * d["vertical_displacement"], d["fz"] * 1e-3, ".", color=c, ms=2, alpha=0.5)
            dmax = f._deflection_at(f.max_force)
            dd = np.linspace(0, dmax, 200)
            lab = f"{f.pressure / 1e5:.1f} bar" if np.isfinite(f.pressure) else "fit"
            ax.plot(1e3 * dd, 1e-3 * np.maximum(f.loading(dd), 0), color=c, lw=1.5, label=f"{lab} loading")
            if f.unloading is not None:
                du = np.linspace(0, dmax * 1.06, 200)
                fu = f.unloading(du)
                keep = (fu >= 0) & (fu <= f.max_force)
                ax.plot(1e3 * du[keep], 1e-3 * fu[keep], color=c, lw=1.2, ls="--", label=f"{lab} unloading")
            ax.axvline(1e3 * f.loading.breakpoint, color=c, ls=":", lw=0.8)
        ax.set_xlabel("vertical deflection [mm]")
        ax.set_ylabel("vertical force [kN]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        return ax


def fit_vertical(vertical) -> VerticalModel:
    """Fit two-gradient loading and unloading curves per pressure.

    Parameters
    ----------
    vertical : Dataset or DataFrame
        canonical columns ``vertical_displacement`` [m], ``fz`` [N] (or
        ``load``), optionally ``phase`` (+1 loading, -1 unloading; all
        loading if absent), ``pressure`` [Pa], ``run``.

    Returns
    -------
    VerticalModel
    """
    df = getattr(vertical, "df", vertical)
    src = getattr(vertical, "source", "") or "vertical-stiffness data"
    if "vertical_displacement" not in df:
        raise ColumnError(f"{src}: vertical-stiffness data need 'vertical_displacement [mm]'")
    fc = "fz" if "fz" in df else ("load" if "load" in df else None)
    if fc is None:
        raise ColumnError(f"{src}: vertical-stiffness data need a force column, 'fz [N]' or 'load [kg]'")
    if "pressure" in df:
        groups = list(df.groupby(df["pressure"].round(-3), sort=True))
    else:
        groups = [(float("nan"), df)]
    fits = []
    notes = []
    for p, g in groups:
        where = f"{src} at {p / 1e5:.2f} bar" if p == p else src
        phase = g["phase"].to_numpy() if "phase" in g else np.ones(len(g))
        d = g["vertical_displacement"].to_numpy(float)
        F = g[fc].to_numpy(float)
        up = phase > 0
        if up.sum() < 5:
            raise DataError(f"{where}: fewer than 5 loading points ({int(up.sum())}); cannot fit the loading curve")
        # the first-contact toe (F ~ 0) carries no stiffness information
        use = up & (F > 0.02 * F.max())
        loading = fit_two_gradient(d[use], F[use], min_side=3, what=f"{where}, loading")
        unloading = None
        energy = float("nan")
        down = (phase < 0) & (F > 0.02 * F.max())
        if down.sum() >= 7:
            unloading = fit_two_gradient(d[down], F[down], min_side=3, what=f"{where}, unloading")
            energy = loop_energy(d, F)
        else:
            notes.append(f"{where}: no unloading branch; no hysteresis reported")
        order = np.argsort(d[up])
        work = float(np.trapezoid(F[up][order], d[up][order])) if hasattr(np, "trapezoid") else \
            float(np.trapz(F[up][order], d[up][order]))
        pressure = float(g["pressure"].mean()) if "pressure" in g else float("nan")
        fits.append(VerticalFit(pressure, loading, unloading, energy, work, float(F.max())))
    return VerticalModel(fits, src, notes)
