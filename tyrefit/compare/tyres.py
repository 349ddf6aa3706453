"""Compare two tyre models, and each with measured data, load by load.

For each load the comparison gives, for tyre *a* and tyre *b*:

* the cornering stiffness [N/rad]: the slope dFy/d(alpha) at zero slip angle
  (for PAC89, BCD);
* the peak friction coefficient -Fy/Fz for positive slip angles (searched to
  30 deg) and the slip angle at the peak [deg];
* ``mean_abs_dmu_over_peak``: the mean of |mu_a - mu_b| over slip angles
  0-12 deg (0.05 deg steps), divided by the peak of mu_a within 0-12 deg
  (*a* is the reference).

With data (slip-angle sweeps, ISO-W), the loads are the data's sweeps and
each model is also scored against the data.  The data curve of a sweep is
its points averaged in 0.5 deg bins of slip angle (0-12 deg, either sign),
which keeps measurement noise out of the score; each model is evaluated at
each bin's mean slip angle and mean measured load, and
``mean_abs_dmu_over_peak_vs_data`` is the mean |mu_model - mu_data| over the
bins divided by the data's peak |mu| in 0-12 deg.

The "agreement" 100 (1 - mean |dmu| / mu_peak) [%] turns the seed's "the
STTR tyre model captures the tyre's nonlinear behaviour within 90 % of the
DTTR tyre measurements" (Komana et al., Sec. 7) into a number per load.

JSON (``Comparison.to_json``, the ``tyrefit compare --json`` contract)::

    {"loads": [{"fz": N, "cornering_stiffness": [a, b], "peak_mu": [a, b],
                "slip_at_peak_deg": [a, b], "mean_abs_dmu_over_peak": x, ...}, ...], ...}
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import DataError
from ..nomenclature import G0

__all__ = ["LoadComparison", "Comparison", "compare_tyres", "model_metrics", "data_metrics", "binned_curve",
           "SLIP_RANGE_DEG"]

#: slip-angle window of the mean |dmu| score [deg] (the DTTR sweeps 0-12 deg, seed 003)
SLIP_RANGE_DEG = (0.0, 12.0)
#: bin width of the data curve [deg]
BIN_DEG = 0.5
_PEAK_SEARCH_DEG = 30.0


def _mu(tyre, fz, slip_angle):
    """-Fy/Fz of a tyre model (positive for positive ISO-W slip angles)."""
    fz = np.asarray(fz, float)
    return -np.asarray(tyre.fy(fz, slip_angle), float) / fz


def model_metrics(tyre, fz: float, slip_range_deg=SLIP_RANGE_DEG) -> dict:
    """Cornering stiffness [N/rad], peak mu, slip at peak [deg] of a tyre model at load ``fz`` [N].

    The cornering stiffness is the central difference of -Fy at +/-1e-4 rad.
    """
    h = 1e-4
    cs = float((-tyre.fy(fz, h) + tyre.fy(fz, -h)) / (2 * h))
    a = np.radians(np.arange(0.0, _PEAK_SEARCH_DEG + 1e-9, 0.01))
    mu = _mu(tyre, np.full(a.shape, fz), a)
    i = int(np.argmax(mu))
    lo, hi = slip_range_deg
    w = (a >= math.radians(lo) - 1e-12) & (a <= math.radians(hi) + 1e-12)
    return {"cornering_stiffness": cs, "peak_mu": float(mu[i]), "slip_at_peak_deg": float(np.degrees(a[i])),
            "peak_mu_in_range": float(mu[w].max())}


def binned_curve(df: pd.DataFrame, slip_range_deg=SLIP_RANGE_DEG, bin_deg: float = BIN_DEG) -> pd.DataFrame:
    """A sweep's data curve: means of slip_angle [rad], fz [N] and mu = -fy/fz in slip bins.

    Bins of ``bin_deg`` over |slip angle| within ``slip_range_deg``, either sign.
    """
    a = df["slip_angle"].to_numpy(float)
    fz = df["fz"].to_numpy(float)
    mu = -df["fy"].to_numpy(float) / fz
    ad = np.degrees(a)
    lo, hi = slip_range_deg
    keep = (np.abs(ad) >= lo) & (np.abs(ad) <= hi + 1e-9)
    b = np.floor(ad[keep] / bin_deg)
    g = pd.DataFrame({"slip_angle": a[keep], "fz": fz[keep], "mu": mu[keep], "bin": b}).groupby("bin")
    out = g.mean()
    out["n"] = g.size()
    return out.reset_index(drop=True)


def data_metrics(df: pd.DataFrame, slip_range_deg=SLIP_RANGE_DEG) -> dict:
    """Cornering stiffness [N/rad], peak mu and slip at peak [deg] of one measured sweep.

    The cornering stiffness is the linear term of -Fy = c0 + c1 alpha + c3 alpha^3
    fitted over |alpha| <= 3 deg (the tangent at zero, comparable with BCD);
    peak mu and its slip angle come from the binned curve.
    """
    a = df["slip_angle"].to_numpy(float)
    fy = -df["fy"].to_numpy(float)
    m = np.abs(a) <= math.radians(3.0)
    if m.sum() >= 5 and np.ptp(a[m]) > math.radians(0.5):
        A = np.column_stack([np.ones(m.sum()), a[m], a[m] ** 3])
        cs = float(np.linalg.lstsq(A, fy[m], rcond=None)[0][1])
    else:
        cs = float("nan")
    curve = binned_curve(df, slip_range_deg)
    if curve.empty:
        return {"cornering_stiffness": cs, "peak_mu": float("nan"), "slip_at_peak_deg": float("nan"),
                "at_edge": False}
    mu = np.abs(curve["mu"].to_numpy())
    i = int(np.argmax(mu))
    at_edge = bool(abs(np.degrees(curve["slip_angle"].iloc[i])) >= slip_range_deg[1] - 2 * BIN_DEG)
    return {"cornering_stiffness": cs, "peak_mu": float(mu[i]),
            "slip_at_peak_deg": float(abs(np.degrees(curve["slip_angle"].iloc[i]))), "at_edge": at_edge}


@dataclass
class LoadComparison:
    """Both models (and the data) at one load; see the module docstring for each number."""

    fz: float
    cornering_stiffness: tuple[float, float]
    peak_mu: tuple[float, float]
    slip_at_peak_deg: tuple[float, float]
    mean_abs_dmu_over_peak: float
    data: dict | None = None
    run: int | None = None

    @property
    def agreement_pct(self) -> float:
        """100 (1 - mean |dmu| / mu_peak) between a and b [%]."""
        return 100.0 * (1.0 - self.mean_abs_dmu_over_peak)

    def to_dict(self) -> dict:
        d = {"fz": self.fz, "cornering_stiffness": list(self.cornering_stiffness), "peak_mu": list(self.peak_mu),
             "slip_at_peak_deg": list(self.slip_at_peak_deg),
             "mean_abs_dmu_over_peak": self.mean_abs_dmu_over_peak,
             "agreement_pct": self.agreement_pct}
        if self.run is not None:
            d["run"] = self.run
        if self.data is not None:
            d["data"] = dict(self.data)
        return d


@dataclass
class Comparison:
    """Load-by-load comparison of tyres a and b (and data)."""

    loads: list[LoadComparison]
    names: tuple[str, str]
    slip_range_deg: tuple[float, float] = SLIP_RANGE_DEG
    data_source: str | None = None
    notes: list[str] = field(default_factory=list)
    _tyres: tuple = field(default=(), repr=False)
    _data: pd.DataFrame | None = field(default=None, repr=False)

    # -- numbers ----------------------------------------------------------------------------
    def vs_data(self) -> np.ndarray | None:
        """(n_loads, 2) mean |dmu| / mu_peak of a and b against the data (None without data)."""
        if self.data_source is None:
            return None
        return np.array([lc.data["mean_abs_dmu_over_peak_vs_data"] for lc in self.loads])

    def summary(self) -> dict:
        d = self.vs_data()
        out = {"worst_mean_abs_dmu_over_peak": max(lc.mean_abs_dmu_over_peak for lc in self.loads),
               "min_agreement_pct": min(lc.agreement_pct for lc in self.loads)}
        if d is not None:
            out["worst_vs_data"] = [float(d[:, 0].max()), float(d[:, 1].max())]
            out["min_agreement_with_data_pct"] = [float(100 * (1 - d[:, 0].max())), float(100 * (1 - d[:, 1].max()))]
        return out

    def to_json(self) -> dict:
        """The ``tyrefit compare --json`` document (DESIGN contract keys plus details)."""
        return {"loads": [lc.to_dict() for lc in self.loads], "tyres": list(self.names),
                "slip_range_deg": list(self.slip_range_deg), "data": self.data_source,
                "definitions": {
                    "cornering_stiffness": "dFy/dalpha at zero slip angle [N/rad] (models); linear term of a cubic "
                                           "fit over |alpha| <= 3 deg (data)",
                    "peak_mu": "max of -Fy/Fz over positive slip angles (models: to 30 deg; data: binned curve "
                               "within the slip range)",
                    "mean_abs_dmu_over_peak": "mean |mu_a - mu_b| over the slip range / peak mu_a in the range",
                    "mean_abs_dmu_over_peak_vs_data": "mean |mu_model - mu_data| over 0.5 deg bins / peak |mu| "
                                                      "of the data in the range, for [a, b]",
                    "agreement_pct": "100 (1 - mean_abs_dmu_over_peak)"},
                "summary": self.summary(), "notes": list(self.notes)}

    def table(self) -> pd.DataFrame:
        a, b = self.names
        rows = []
        for lc in self.loads:
            r = {"Fz [kN]": lc.fz * 1e-3, "load [kg]": lc.fz / G0,
                 f"C_alpha {a} [kN/deg]": lc.cornering_stiffness[0] * 1e-3 * math.pi / 180,
                 f"C_alpha {b} [kN/deg]": lc.cornering_stiffness[1] * 1e-3 * math.pi / 180,
                 f"peak mu {a}": lc.peak_mu[0], f"peak mu {b}": lc.peak_mu[1],
                 f"slip at peak {a} [deg]": lc.slip_at_peak_deg[0], f"slip at peak {b} [deg]": lc.slip_at_peak_deg[1],
                 "mean |dmu|/mu_peak [%]": 100 * lc.mean_abs_dmu_over_peak, "agreement [%]": lc.agreement_pct}
            if lc.data is not None:
                r.update({"C_alpha data [kN/deg]": lc.data["cornering_stiffness"] * 1e-3 * math.pi / 180,
                          "peak mu data": lc.data["peak_mu"],
                          f"{a} vs data [%]": 100 * lc.data["mean_abs_dmu_over_peak_vs_data"][0],
                          f"{b} vs data [%]": 100 * lc.data["mean_abs_dmu_over_peak_vs_data"][1]})
            rows.append(r)
        return pd.DataFrame(rows)

    # -- figures ------------------------------------------------------------------------------
    def plot_overlay(self, axes=None):
        """mu against slip angle per load: both models (and the data)."""
        import matplotlib.pyplot as plt

        n = len(self.loads)
        if axes is None:
            cols = min(n, 3)
            rows = math.ceil(n / cols)
            _, axes = plt.subplots(rows, cols, figsize=(4.3 * cols, 3.4 * rows), squeeze=False)
        axes = np.ravel(axes)
        ta, tb = self._tyres
        a_name, b_name = self.names
        lo, hi = self.slip_range_deg
        aa = np.radians(np.linspace(lo, hi, 241))
        for ax, lc in zip(axes, self.loads):
            if self._data is not None and lc.run is not None:
                g = self._data[self._data["run"] == lc.run]
                ax.plot(np.degrees(g["slip_angle"]), -g["fy"] / g["fz"], ".", color="0.7", ms=2, label="data")
                c = binned_curve(g, self.slip_range_deg)
                ax.plot(np.degrees(c["slip_angle"]), c["mu"], "ko", ms=3, label="data, 0.5° bins")
            ax.plot(np.degrees(aa), _mu(ta, np.full(aa.shape, lc.fz), aa), "C0-", lw=1.8, label=a_name)
            ax.plot(np.degrees(aa), _mu(tb, np.full(aa.shape, lc.fz), aa), "C3--", lw=1.8, label=b_name)
            title = f"{lc.fz * 1e-3:.1f} kN ({lc.fz / G0:.0f} kg)"
            if lc.data is not None:
                d = lc.data["mean_abs_dmu_over_peak_vs_data"]
                title += f"\nvs data: {100 * d[0]:.1f} % / {100 * d[1]:.1f} %"
            ax.set_title(title, fontsize=9)
            ax.set_xlabel("slip angle [deg]")
            ax.set_ylabel("-Fy/Fz [-]")
            ax.grid(alpha=0.3)
        for ax in axes[n:]:
            ax.set_visible(False)
        axes[0].legend(fontsize=7)
        axes[0].figure.tight_layout()
        return axes

    def plot_load_laws(self, axes=None):
        """Cornering stiffness and peak mu against load for a, b (and data)."""
        import matplotlib.pyplot as plt

        if axes is None:
            _, axes = plt.subplots(1, 2, figsize=(11, 3.8))
        ta, tb = self._tyres
        fz = np.array([lc.fz for lc in self.loads])
        grid = np.linspace(0.5 * fz.min(), 1.1 * fz.max(), 60)
        for k, (t, name, st) in enumerate(((ta, self.names[0], "C0-"), (tb, self.names[1], "C3--"))):
            m = [model_metrics(t, f) for f in grid]
            axes[0].plot(grid * 1e-3, [x["cornering_stiffness"] * 1e-3 * math.pi / 180 for x in m], st, label=name)
            axes[1].plot(grid * 1e-3, [x["peak_mu"] for x in m], st, label=name)
        if self.data_source is not None:
            axes[0].plot(fz * 1e-3, [lc.data["cornering_stiffness"] * 1e-3 * math.pi / 180 for lc in self.loads],
                         "ko", label="data")
            axes[1].plot(fz * 1e-3, [lc.data["peak_mu"] for lc in self.loads], "ko", label="data (in range)")
        axes[0].set_ylabel("cornering stiffness [kN/deg]")
        axes[1].set_ylabel("peak friction coefficient [-]")
        for ax in axes:
            ax.set_xlabel("Fz [kN]")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
        return axes

    def report_section(self, report, title: str | None = None) -> None:
        """Append the comparison (table, agreement, overlays) to a :class:`tyrefit.io.report.Report`."""
        import matplotlib.pyplot as plt

        a, b = self.names
        r = report
        r.h2(title or f"{a} vs {b}")
        s = self.summary()
        lo, hi = self.slip_range_deg
        r.p(f"Mean |Δμ| / μ_peak over {lo:g}-{hi:g} deg between the models: worst load "
            f"{100 * s['worst_mean_abs_dmu_over_peak']:.2f} % — {b} agrees with {a} within "
            f"{s['min_agreement_pct']:.1f} % at every load (the seed's 'within 90 %', as a number).")
        if self.data_source is not None:
            r.p(f"Against the data ({self.data_source}): worst load {100 * s['worst_vs_data'][0]:.2f} % for {a}, "
                f"{100 * s['worst_vs_data'][1]:.2f} % for {b}: agreement {s['min_agreement_with_data_pct'][0]:.1f} % "
                f"and {s['min_agreement_with_data_pct'][1]:.1f} %.")
        r.table(self.table(), digits=4)
        fig_axes = self.plot_overlay()
        r.figure(fig_axes[0].figure, f"Friction coefficient against slip angle per load: {a} (solid), {b} (dashed)"
                 + (", data (grey) and its 0.5° bin means (black)" if self.data_source else "") + ".")
        axes = self.plot_load_laws()
        r.figure(axes[0].figure, "Cornering stiffness and peak friction coefficient against load.")
        plt.close("all")
        for n in self.notes:
            r.p(n, cls="note")


def _default_loads(ta, tb) -> tuple[np.ndarray, str]:
    rs = [t.ranges.get("fz") for t in (ta, tb) if getattr(t, "ranges", None) and t.ranges.get("fz")]
    if len(rs) == 2:
        lo, hi = max(rs[0][0], rs[1][0]), min(rs[0][1], rs[1][1])
        if hi > lo:
            return np.linspace(lo, hi, 5), "5 loads over the overlap of the tyres' fitted load ranges"
        lo, hi = min(rs[0][0], rs[1][0]), max(rs[0][1], rs[1][1])
        return np.linspace(lo, hi, 5), "5 loads over the union of the tyres' fitted load ranges (they do not overlap)"
    if len(rs) == 1:
        return np.linspace(rs[0][0], rs[0][1], 5), "5 loads over the fitted load range of the one tyre that has one"
    fn = [t.fnomin for t in (ta, tb) if getattr(t, "fnomin", None)]
    if fn:
        f = float(np.mean(fn))
        return f * np.array([0.25, 0.5, 0.75, 1.0, 1.25]), "0.25-1.25 x FNOMIN"
    return np.array([2e3, 4e3, 6e3, 8e3, 10e3]), "2-10 kN (the tyre files give neither load ranges nor FNOMIN)"


def compare_tyres(tyre_a, tyre_b, data=None, *, loads=None, names: tuple[str, str] | None = None,
                  slip_range_deg=SLIP_RANGE_DEG) -> Comparison:
    """Compare two tyre models load by load, and each against slip-angle data.

    Parameters
    ----------
    tyre_a, tyre_b : Pac89Tyre (or anything with ``fy(fz, slip_angle)``)
        *a* is the reference of ``mean_abs_dmu_over_peak``.
    data : Dataset or DataFrame, optional
        slip-angle sweeps (canonical SI columns ``run``, ``fz``, ``fy``,
        ``slip_angle``; ISO-W).  Its sweeps set the loads.
    loads : array_like, optional
        loads [N] when there are no data; default from the tyres' fitted load
        ranges (or FNOMIN).
    names : (str, str), optional
    slip_range_deg : (float, float)

    Returns
    -------
    Comparison
    """
    names = tuple(names) if names else (getattr(tyre_a, "name", "a") or "a", getattr(tyre_b, "name", "b") or "b")
    if names[0] == names[1]:
        names = (names[0] + " (a)", names[1] + " (b)")
    lo, hi = slip_range_deg
    if not (0 <= lo < hi <= 90):
        raise DataError(f"slip range {lo}-{hi} deg: accepted 0 <= low < high <= 90 deg")
    notes = []
    df = None
    source = None
    if data is not None:
        df = getattr(data, "df", data)
        source = getattr(data, "source", None) or "data"
        kind = getattr(data, "kind", "slip_angle")
        if kind != "slip_angle":
            raise DataError(f"{source}: is a {kind} test; compare needs slip-angle sweeps ('slip_angle', 'fy', 'fz')")
        for c in ("slip_angle", "fy", "fz"):
            if c not in df:
                raise DataError(f"{source}: no '{c}' column; compare needs slip-angle sweeps")
        if "run" not in df:
            df = df.assign(run=0)
        runs = [(int(r), g) for r, g in df.groupby("run", sort=True)]
        runs = [(r, g) for r, g in runs if len(binned_curve(g, slip_range_deg)) >= 3]
        if not runs:
            raise DataError(f"{source}: no sweep has data across {lo:g}-{hi:g} deg of slip angle")
        if "camber" in df and np.ptp(df["camber"]) > math.radians(0.25):
            notes.append("the data hold several camber angles; models are evaluated at zero camber")
        load_list = [(float(g["fz"].mean()), r, g) for r, g in runs]
    else:
        if loads is None:
            grid, how = _default_loads(tyre_a, tyre_b)
            notes.append(f"loads: {how}")
        else:
            grid = np.atleast_1d(np.asarray(loads, float))
            if np.any(grid <= 0):
                raise DataError("loads must be positive [N]")
        load_list = [(float(f), None, None) for f in grid]
    out = []
    aa = np.radians(np.arange(lo, hi + 1e-9, 0.05))
    for fz, run, g in load_list:
        ma, mb = model_metrics(tyre_a, fz, slip_range_deg), model_metrics(tyre_b, fz, slip_range_deg)
        mua, mub = _mu(tyre_a, np.full(aa.shape, fz), aa), _mu(tyre_b, np.full(aa.shape, fz), aa)
        score = float(np.mean(np.abs(mua - mub)) / ma["peak_mu_in_range"])
        ddict = None
        if g is not None:
            dm = data_metrics(g, slip_range_deg)
            curve = binned_curve(g, slip_range_deg)
            pk = float(np.abs(curve["mu"]).max())
            vs = []
            for t in (tyre_a, tyre_b):
                mm = _mu(t, curve["fz"].to_numpy(), curve["slip_angle"].to_numpy())
                vs.append(float(np.mean(np.abs(mm - curve["mu"].to_numpy())) / pk))
            ddict = {"cornering_stiffness": dm["cornering_stiffness"], "peak_mu": dm["peak_mu"],
                     "slip_at_peak_deg": dm["slip_at_peak_deg"], "peak_at_range_edge": dm["at_edge"],
                     "mean_abs_dmu_over_peak_vs_data": vs, "agreement_with_data_pct": [100 * (1 - v) for v in vs],
                     "bins": int(len(curve)), "points": int(len(g))}
        out.append(LoadComparison(fz=fz, cornering_stiffness=(ma["cornering_stiffness"], mb["cornering_stiffness"]),
                                  peak_mu=(ma["peak_mu"], mb["peak_mu"]),
                                  slip_at_peak_deg=(ma["slip_at_peak_deg"], mb["slip_at_peak_deg"]),
                                  mean_abs_dmu_over_peak=score, data=ddict, run=run))
    return Comparison(out, names, tuple(slip_range_deg), source, notes, (tyre_a, tyre_b), df)
