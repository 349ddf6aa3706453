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
each model is also scored against the data.  Both models are evaluated at
each sweep's own conditions: its measured load (per bin), its camber, its
pressure and its speed (for families with those inputs; PAC89 has no
pressure or speed input, which the notes say), never at zero camber for a
cambered sweep.  Peaks are searched only within the slip range the sweep
tested (without data: the tyres' fitted slip-angle range where they carry
one, else 0-30 deg); a model whose curve still rises at the end of that
range has its peak "not reached within +/-X deg" (``peak_mu`` and
``slip_at_peak_deg`` NaN, ``null`` in JSON, ``peak_reached`` false).

Any tyre family is compared through the tyre interface: an object with
``forces(fz, slip_angle=, slip_ratio=, camber=, pressure=, speed=) -> dict``
(:mod:`tyrefit.tyres`) or, for older containers, ``fy(fz, slip_angle, camber)``.  The data curve of a sweep is
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


def lateral_force(tyre, fz, slip_angle, camber=0.0, pressure=None, speed=None) -> np.ndarray:
    """Fy [N] (ISO-W) of any tyre family at load [N], slip angle [rad], camber [rad], pressure [Pa], speed [m/s].

    Uses the tyre interface ``forces(...)`` when the tyre has it, else ``fy(fz, slip_angle, camber)``
    (pressure and speed are then not inputs of the model).
    """
    fz = np.asarray(fz, float)
    forces = getattr(tyre, "forces", None)
    if callable(forces):
        kw = {"slip_angle": slip_angle, "camber": camber}
        if pressure is not None:
            kw["pressure"] = pressure
        if speed is not None:
            kw["speed"] = speed
        return np.asarray(forces(fz, **kw)["fy"], float)
    return np.asarray(tyre.fy(fz, slip_angle, camber), float)


def takes(tyre, channel: str) -> bool:
    """Whether a tyre model has ``channel`` ('pressure', 'speed') as an input."""
    fn = getattr(tyre, "inputs", None)
    if fn is not None:
        return channel in (fn() if callable(fn) else fn)
    return callable(getattr(tyre, "forces", None)) and getattr(tyre, "family", "PAC89") != "PAC89"


def _mu(tyre, fz, slip_angle, camber=0.0, pressure=None, speed=None):
    """-Fy/Fz of a tyre model (positive for positive ISO-W slip angles)."""
    fz = np.asarray(fz, float)
    return -lateral_force(tyre, fz, slip_angle, camber, pressure, speed) / fz


def model_metrics(tyre, fz: float, slip_range_deg=SLIP_RANGE_DEG, *, camber: float = 0.0, pressure=None,
                  speed=None, max_slip_deg: float | None = None) -> dict:
    """Cornering stiffness [N/rad], peak mu, slip at peak [deg] of a tyre model at load ``fz`` [N].

    The cornering stiffness is the central difference of -Fy at +/-1e-4 rad
    (at ``camber`` [rad], so a camber shift does not enter it).  The peak is
    searched over 0..``max_slip_deg`` (default 30 deg); a maximum at the end
    of that range is not a peak: ``peak_reached`` is False and ``peak_mu``,
    ``slip_at_peak_deg`` are NaN (``max_mu`` keeps the largest value seen).
    """
    h = 1e-4
    ev = dict(camber=camber, pressure=pressure, speed=speed)
    cs = float((-lateral_force(tyre, fz, h, **ev) + lateral_force(tyre, fz, -h, **ev)) / (2 * h))
    top = _PEAK_SEARCH_DEG if max_slip_deg is None else float(max_slip_deg)
    a = np.radians(np.arange(0.0, top + 1e-9, 0.01))
    mu = _mu(tyre, np.full(a.shape, fz), a, **ev)
    i = int(np.argmax(mu))
    reached = i < len(a) - 1 - int(round(0.05 / 0.01))  # at least 0.05 deg inside the range
    lo, hi = slip_range_deg
    w = (a >= math.radians(lo) - 1e-12) & (a <= math.radians(min(hi, top)) + 1e-12)
    nan = float("nan")
    return {"cornering_stiffness": cs, "peak_mu": float(mu[i]) if reached else nan,
            "slip_at_peak_deg": float(np.degrees(a[i])) if reached else nan, "peak_reached": bool(reached),
            "max_mu": float(mu[i]), "search_deg": top, "peak_mu_in_range": float(mu[w].max()) if w.any() else nan}


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
    cols = {"slip_angle": a[keep], "fz": fz[keep], "mu": mu[keep], "bin": b}
    if "camber" in df:
        cols["camber"] = df["camber"].to_numpy(float)[keep]
    g = pd.DataFrame(cols).groupby("bin")
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
    camber: float = 0.0
    pressure: float | None = None
    speed: float | None = None
    search_deg: float = _PEAK_SEARCH_DEG
    peak_reached: tuple[bool, bool] = (True, True)
    max_mu: tuple[float, float] = (float("nan"), float("nan"))

    @property
    def conditions(self) -> str:
        """The sweep's conditions in display units: ``'Fz 1.11 kN, camber 2.0°, pressure 83 kPa'``."""
        from ..io.facets import format_condition, format_load

        t = [f"Fz {format_load(self.fz)}", format_condition("camber", self.camber)]
        if self.pressure is not None and np.isfinite(self.pressure):
            t.append(format_condition("pressure", self.pressure))
        if self.speed is not None and np.isfinite(self.speed):
            t.append(format_condition("speed", self.speed))
        return ", ".join(t)

    def peak_text(self, k: int) -> str:
        """Peak of tyre ``k`` (0: a, 1: b) in words: ``'1.72 at 6.3°'`` or ``'not reached within ±9.8°'``."""
        if self.peak_reached[k]:
            return f"{self.peak_mu[k]:.3f} at {self.slip_at_peak_deg[k]:.1f}°"
        return f"not reached within ±{self.search_deg:.1f}°"

    @property
    def agreement_pct(self) -> float:
        """100 (1 - mean |dmu| / mu_peak) between a and b [%]."""
        return 100.0 * (1.0 - self.mean_abs_dmu_over_peak)

    def to_dict(self) -> dict:
        d = {"fz": self.fz, "cornering_stiffness": list(self.cornering_stiffness), "peak_mu": list(self.peak_mu),
             "slip_at_peak_deg": list(self.slip_at_peak_deg),
             "mean_abs_dmu_over_peak": self.mean_abs_dmu_over_peak,
             "agreement_pct": self.agreement_pct, "peak_reached": list(self.peak_reached),
             "max_mu_in_search": list(self.max_mu), "peak_search_deg": self.search_deg,
             "camber_deg": math.degrees(self.camber)}
        if self.pressure is not None:
            d["pressure_kpa"] = self.pressure / 1e3
        if self.speed is not None:
            d["speed_kmh"] = self.speed * 3.6
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
            if self._data is not None:
                sub = self._data[self._data["run"].isin([lc.run for lc in self.loads])]
                n = np.array([lc.data["points"] for lc in self.loads], float)
                r = np.array([lc.data["rmse_N"] for lc in self.loads], float)
                out["rmse_N"] = [float(np.sqrt(np.sum(n * r[:, k] ** 2) / n.sum())) for k in (0, 1)]
                from ..fitting.result import noise_floor_of

                out["noise_floor_N"] = noise_floor_of(sub["slip_angle"].to_numpy(float), sub["fy"].to_numpy(float),
                                                      sub["run"].to_numpy(), sub["fz"].to_numpy(float))[0]
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
                    "agreement_pct": "100 (1 - mean_abs_dmu_over_peak)",
                    "rmse_N": "root mean square of Fy_model - Fy_data over every point of the sweep (summary: of "
                              "all sweeps), each model at the point's load and camber - as fit and diagnose",
                    "noise_floor_N": "within-sweep noise floor, the one definition of fit and diagnose "
                                     "(tyrefit.diagnose.stats.noise_floor)"},
                "summary": self.summary(), "notes": list(self.notes)}

    def table(self) -> pd.DataFrame:
        a, b = self.names
        rows = []
        for lc in self.loads:
            r = {"Fz [kN]": lc.fz * 1e-3, "load [kg]": lc.fz / G0, "camber [deg]": math.degrees(lc.camber)}
            if lc.pressure is not None:
                r["pressure [kPa]"] = lc.pressure / 1e3
            r.update({
                 f"C_alpha {a} [kN/deg]": lc.cornering_stiffness[0] * 1e-3 * math.pi / 180,
                 f"C_alpha {b} [kN/deg]": lc.cornering_stiffness[1] * 1e-3 * math.pi / 180,
                 f"peak mu {a}": lc.peak_text(0), f"peak mu {b}": lc.peak_text(1),
                 "mean |dmu|/mu_peak [%]": 100 * lc.mean_abs_dmu_over_peak, "agreement [%]": lc.agreement_pct})
            if lc.data is not None:
                r.update({"C_alpha data [kN/deg]": lc.data["cornering_stiffness"] * 1e-3 * math.pi / 180,
                          "peak mu data": lc.data["peak_mu"],
                          f"{a} vs data [%]": 100 * lc.data["mean_abs_dmu_over_peak_vs_data"][0],
                          f"{b} vs data [%]": 100 * lc.data["mean_abs_dmu_over_peak_vs_data"][1]})
            rows.append(r)
        return pd.DataFrame(rows)

    # -- figures ------------------------------------------------------------------------------
    def plot_overlay(self, axes=None):
        """mu against slip angle: both models (and the data), each at the sweep's own conditions.

        With data, one panel per condition level of the data (pressure,
        speed, camber; :func:`tyrefit.io.facets.facet_sweeps`), titled with
        it, one colour per load; without data one panel per load.  Returns
        the Axes array.
        """
        import matplotlib as mpl
        from matplotlib.figure import Figure

        from ..io.facets import facet_sweeps, format_load

        ta, tb = self._tyres
        a_name, b_name = self.names
        lo, hi = self.slip_range_deg
        by_run = {lc.run: lc for lc in self.loads}
        if self._data is not None and all(lc.run is not None for lc in self.loads):
            facets, _ = facet_sweeps(self._data[self._data["run"].isin(by_run)], ("pressure", "speed", "camber"))
            groups = [(f.title, [by_run[r] for r in f.runs]) for f in facets]
        else:
            groups = [(lc.conditions, [lc]) for lc in self.loads]
        n = len(groups)
        if axes is None:
            cols = min(n, 3)
            rows = math.ceil(n / cols)
            axes = Figure(figsize=(4.6 * cols, 3.6 * rows + 0.6)).subplots(rows, cols, squeeze=False)
        axes = np.ravel(axes)
        fzs = [lc.fz for lc in self.loads]
        flo, fhi = min(fzs), max(fzs)
        cmap = mpl.colormaps["viridis"]
        for ax, (title, lcs) in zip(axes, groups):
            for lc in lcs:
                col = cmap(0.85 * (lc.fz - flo) / (fhi - flo)) if fhi > flo and len(lcs) > 1 else "k"
                top = hi if lc.search_deg is None else min(hi, lc.search_deg)
                ev = {"camber": lc.camber, "pressure": lc.pressure, "speed": lc.speed}
                if self._data is not None and lc.run is not None:
                    g = self._data[self._data["run"] == lc.run]
                    c = binned_curve(g, self.slip_range_deg)
                    ax.plot(np.degrees(c["slip_angle"]), c["mu"], "o", color=col, ms=3, mfc="none")
                    top = max(top, float(np.degrees(np.abs(c["slip_angle"]).max())))
                    aa = np.radians(np.linspace(-top, top, 241))
                else:
                    aa = np.radians(np.linspace(lo, top, 241))
                fz = np.full(aa.shape, lc.fz)
                ax.plot(np.degrees(aa), _mu(ta, fz, aa, **ev), "-", color=col, lw=1.5, label=format_load(lc.fz),
                        gid=f"a run {lc.run}")
                ax.plot(np.degrees(aa), _mu(tb, fz, aa, **ev), "--", color=col, lw=1.5, gid=f"b run {lc.run}")
            if self._data is not None:
                d = np.array([lc.data["mean_abs_dmu_over_peak_vs_data"] for lc in lcs if lc.data is not None])
                if d.size:
                    title += f"\nvs data (worst load): {100 * d[:, 0].max():.1f} % / {100 * d[:, 1].max():.1f} %"
            ax.set_title(title, fontsize=9)
            ax.set_xlabel("slip angle [deg]")
            ax.set_ylabel("-Fy/Fz [-]")
            ax.grid(alpha=0.3)
            if len(lcs) > 1:
                ax.legend(fontsize=7, title="Fz", title_fontsize=7)
        for ax in axes[n:]:
            ax.set_visible(False)
        fig = axes[0].figure
        fa, fb = (getattr(t, "family", "") or type(t).__name__ for t in (ta, tb))
        a_name, b_name = f"{a_name} [{fa}]", f"{b_name} [{fb}]"
        fig.suptitle(f"{a_name} (solid) and {b_name} (dashed), each evaluated at every sweep's own load, camber"
                     + (", pressure and speed" if self._data is not None else "") + "; circles: data (0.5° bins)"
                     if self._data is not None else f"{a_name} (solid) and {b_name} (dashed) at camber 0°", fontsize=10)
        fig.tight_layout()
        return axes

    def plot_load_laws(self, axes=None):
        """Cornering stiffness and peak mu against load for a, b at camber 0 (and the data's sweeps)."""

        if axes is None:
            from matplotlib.figure import Figure

            axes = Figure(figsize=(11, 3.8)).subplots(1, 2)
        ta, tb = self._tyres
        fz = np.array([lc.fz for lc in self.loads])
        grid = np.linspace(0.5 * fz.min(), 1.1 * fz.max(), 60)
        for k, (t, name, st) in enumerate(((ta, self.names[0], "C0-"), (tb, self.names[1], "C3--"))):
            reach = _default_reach(ta, tb) if self.data_source is None else max(lc.search_deg for lc in self.loads)
            m = [model_metrics(t, f, max_slip_deg=reach) for f in grid]
            axes[0].plot(grid * 1e-3, [x["cornering_stiffness"] * 1e-3 * math.pi / 180 for x in m], st, label=name)
            axes[1].plot(grid * 1e-3, [x["peak_mu"] for x in m], st, label=name + " (camber 0°)")
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
                f"and {s['min_agreement_with_data_pct'][1]:.1f} %."
                + (f" Lateral RMSE over every point, each model at the point's load and camber: "
                   f"{s['rmse_N'][0]:.4g} N for {a}, {s['rmse_N'][1]:.4g} N for {b}; within-sweep noise floor "
                   f"{s['noise_floor_N']:.4g} N (the definitions of fit and diagnose)." if "rmse_N" in s else ""))
        r.table(self.table(), digits=4)
        fig_axes = self.plot_overlay()
        r.figure(fig_axes[0].figure, f"Friction coefficient against slip angle: {a} (solid), {b} (dashed), each "
                 "at the sweep's own load and camber" + (", pressure and speed; data as 0.5° bin means (circles); one "
                                                         "panel per condition level" if self.data_source else "") + ".")
        axes = self.plot_load_laws()
        r.figure(axes[0].figure, "Cornering stiffness and peak friction coefficient against load (models at camber "
                                 "0°, peaks within the tested slip range; data: each sweep at its own camber).")
        for n in self.notes:
            r.p(n, cls="note")


def _default_loads(ta, tb) -> tuple[np.ndarray, str]:
    """Five loads where both tyres are meant to be used.

    A tyre's load range is its declared ``[VERTICAL_FORCE_RANGE]``, else
    0.2-2 x FNOMIN (vendor files often leave FZMIN/FZMAX empty: comparing an
    FSAE tyre over the other file's 0-18 kN range gave Fz = 0 and 6 x its
    nominal load).  A declared FZMIN of 0 (MFeval's example) starts at 5 % of
    the top load instead: no friction coefficient exists at Fz = 0.
    """
    rs, declared = [], []
    for t in (ta, tb):
        r = (getattr(t, "ranges", None) or {}).get("fz")
        if r:
            rs.append(tuple(map(float, r)))
            declared.append(True)
        elif getattr(t, "fnomin", None):
            rs.append((0.2 * float(t.fnomin), 2.0 * float(t.fnomin)))
            declared.append(False)
    what = ("the tyres' fitted load ranges" if all(declared) else
            "the tyres' load ranges (declared, else 0.2-2 x FNOMIN)")

    def spread(lo, hi):
        return np.linspace(lo if lo > 0 else 0.05 * hi, hi, 5)

    if len(rs) == 2:
        lo, hi = max(rs[0][0], rs[1][0]), min(rs[0][1], rs[1][1])
        if hi > lo:
            return spread(lo, hi), f"5 loads over the overlap of {what}"
        lo, hi = min(rs[0][0], rs[1][0]), max(rs[0][1], rs[1][1])
        return spread(lo, hi), f"5 loads over the union of {what} (they do not overlap)"
    if len(rs) == 1:
        return spread(*rs[0]), ("5 loads over the fitted load range of the one tyre that has one" if declared[0]
                                else "0.2-2 x FNOMIN of the one tyre that gives it")
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
        load_list = []
        for r, g in runs:
            cond = {c: (float(g[c].mean()) if c in g and g[c].notna().any() else None)
                    for c in ("camber", "pressure", "speed")}
            reach = float(np.degrees(np.max(np.abs(g["slip_angle"].to_numpy(float)))))
            load_list.append((float(g["fz"].mean()), r, g, cond, reach))
        for c in ("pressure", "speed"):
            vals = [x[3][c] for x in load_list if x[3][c] is not None]
            if vals and np.ptp(vals) > {"pressure": 5e3, "speed": 2 / 3.6}[c]:
                for t, nm in ((tyre_a, names[0]), (tyre_b, names[1])):
                    if not takes(t, c):
                        notes.append(f"the data hold several {c} levels; {nm} has no {c} input, so it gives one "
                                     f"curve for all of them")
    else:
        if loads is None:
            grid, how = _default_loads(tyre_a, tyre_b)
            notes.append(f"loads: {how}")
        else:
            grid = np.atleast_1d(np.asarray(loads, float))
            if np.any(grid <= 0):
                raise DataError("loads must be positive [N]")
        reach = _default_reach(tyre_a, tyre_b)
        if reach is not None:
            notes.append(f"peaks searched within the tyres' fitted slip-angle range, 0-{reach:.1f} deg")
        load_list = [(float(f), None, None, {"camber": 0.0, "pressure": None, "speed": None}, reach) for f in grid]
    out = []
    for fz, run, g, cond, reach in load_list:
        ev = {"camber": cond["camber"] or 0.0, "pressure": cond["pressure"], "speed": cond["speed"]}
        ma = model_metrics(tyre_a, fz, slip_range_deg, max_slip_deg=reach, **ev)
        mb = model_metrics(tyre_b, fz, slip_range_deg, max_slip_deg=reach, **ev)
        top = hi if reach is None else min(hi, reach)
        aa = np.radians(np.arange(lo, top + 1e-9, 0.05))
        mua, mub = _mu(tyre_a, np.full(aa.shape, fz), aa, **ev), _mu(tyre_b, np.full(aa.shape, fz), aa, **ev)
        score = float(np.mean(np.abs(mua - mub)) / np.max(mua)) if aa.size else float("nan")
        ddict = None
        if g is not None:
            dm = data_metrics(g, slip_range_deg)
            curve = binned_curve(g, slip_range_deg)
            pk = float(np.abs(curve["mu"]).max())
            cam = curve["camber"].to_numpy() if "camber" in curve else 0.0
            vs, rmse = [], []
            pcam = g["camber"].to_numpy(float) if "camber" in g else 0.0
            for t in (tyre_a, tyre_b):
                mm = _mu(t, curve["fz"].to_numpy(), curve["slip_angle"].to_numpy(), cam, ev["pressure"], ev["speed"])
                vs.append(float(np.mean(np.abs(mm - curve["mu"].to_numpy())) / pk))
                # RMSE as fit and diagnose define it: every point, at its own load and camber [N]
                fy = lateral_force(t, g["fz"].to_numpy(float), g["slip_angle"].to_numpy(float), pcam,
                                   ev["pressure"], ev["speed"])
                rmse.append(float(np.sqrt(np.mean((fy - g["fy"].to_numpy(float)) ** 2))))
            ddict = {"cornering_stiffness": dm["cornering_stiffness"], "peak_mu": dm["peak_mu"],
                     "slip_at_peak_deg": dm["slip_at_peak_deg"], "peak_at_range_edge": dm["at_edge"],
                     "mean_abs_dmu_over_peak_vs_data": vs, "agreement_with_data_pct": [100 * (1 - v) for v in vs],
                     "bins": int(len(curve)), "points": int(len(g)), "rmse_N": rmse,
                     "noise_floor_N": _sweep_floor(g)}
        out.append(LoadComparison(fz=fz, cornering_stiffness=(ma["cornering_stiffness"], mb["cornering_stiffness"]),
                                  peak_mu=(ma["peak_mu"], mb["peak_mu"]),
                                  slip_at_peak_deg=(ma["slip_at_peak_deg"], mb["slip_at_peak_deg"]),
                                  mean_abs_dmu_over_peak=score, data=ddict, run=run, camber=ev["camber"],
                                  pressure=ev["pressure"], speed=ev["speed"], search_deg=ma["search_deg"],
                                  peak_reached=(ma["peak_reached"], mb["peak_reached"]),
                                  max_mu=(ma["max_mu"], mb["max_mu"])))
    for k, nm in enumerate(names):
        miss = [lc for lc in out if not lc.peak_reached[k]]
        if miss:
            notes.append(f"{nm}: the peak is not reached within the tested slip range at {len(miss)} of {len(out)} "
                         f"loads (e.g. {miss[0].conditions}: still rising at {miss[0].search_deg:.1f} deg); "
                         "peak_mu and slip_at_peak_deg are left empty there")
    return Comparison(out, names, tuple(slip_range_deg), source, notes, (tyre_a, tyre_b), df)


def _sweep_floor(g: pd.DataFrame) -> float:
    """The within-sweep noise floor [N] of one sweep (the definition of fit and diagnose)."""
    from ..fitting.result import noise_floor_of

    f, _ = noise_floor_of(g["slip_angle"].to_numpy(float), g["fy"].to_numpy(float), np.zeros(len(g), int),
                          g["fz"].to_numpy(float))
    return float(f)


def _default_reach(ta, tb) -> float | None:
    """Largest slip angle [deg] both tyres were fitted to (None when neither says)."""
    r = []
    for t in (ta, tb):
        rng = (getattr(t, "ranges", None) or {}).get("slip_angle")
        if rng:
            r.append(max(abs(rng[0]), abs(rng[1])))
    return float(np.degrees(min(r))) if r else None
