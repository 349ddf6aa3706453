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

The "agreement" 100 (1 - mean |dmu| / mu_peak) [%] turns the claim "the
STTR tyre model captures the tyre's nonlinear behaviour within 90 % of the
DTTR tyre measurements" (Komana et al., Sec. 7) into a number per load.

Every channel both tyres carry (:func:`compare_channels`): Fx (slip stiffness,
driving and braking peak mu_x and slip ratio at each), Fy (the numbers above),
Mz (peak, its slip angle, aligning stiffness, pneumatic trail at zero slip), Mx
(range over the slip range, value and slope at zero), each with a
model-against-model score (:data:`CHANNEL_DEFINITIONS`).  A channel one tyre
does not carry (PAC89 has no Mx; a part the file does not compute, declares not
fitted, or gives as zeros) is named with the reason.  Slip-ratio sweeps are
accepted as data too: they set the loads and score Fx; slip-angle sweeps score
Fy, Mz and Mx where they carry them.

JSON (``Comparison.to_json``, the ``tyrefit compare --json`` contract)::

    {"loads": [{"fz": N, "cornering_stiffness": [a, b], "peak_mu": [a, b],
                "slip_at_peak_deg": [a, b], "mean_abs_dmu_over_peak": x, ...}, ...],
     "channels": {"fx": {"loads": [{"fz", "slip_stiffness", "peak_mu", "slip_at_peak", ...}]},
                  "fy": {...}, "mz": {...}, "mx": {...}},
     "channels_skipped": {"mx": "why"}, ...}
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import DataError
from ..nomenclature import G0
from ..fitting.result import noise_floor_of
from ..io.facets import facet_sweeps, format_condition, format_load

__all__ = ["LoadComparison", "Comparison", "compare_tyres", "model_metrics", "data_metrics", "binned_curve",
           "SLIP_RANGE_DEG", "CHANNELS", "compare_channels", "channel_value", "fx_metrics", "mz_metrics",
           "mx_metrics", "channel_vs_data"]

#: slip-angle window of the mean |dmu| score [deg] (the DTTR of Komana et al. sweeps 0-12 deg)
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
    #: the sweep's mean slip angle [rad] (slip-ratio sweeps: the Fx channel is evaluated there)
    slip_angle: float = 0.0
    #: the sweep's points (with data)
    sweep: pd.DataFrame | None = field(default=None, repr=False, compare=False)

    @property
    def conditions(self) -> str:
        """The sweep's conditions in display units: ``'Fz 1.11 kN, camber 2.0°, pressure 83 kPa'``."""
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
    #: channel -> per-load dicts for every channel both tyres carry (:func:`compare_channels`)
    channels: dict = field(default_factory=dict)
    #: channel -> why it was not compared
    channels_skipped: dict = field(default_factory=dict)
    #: 'slip_angle' or 'slip_ratio' sweeps (None without data)
    data_kind: str | None = None

    # -- numbers ----------------------------------------------------------------------------
    def vs_data(self) -> np.ndarray | None:
        """(n_loads, 2) mean |dmu| / mu_peak of a and b against the data (None without slip-angle data)."""
        if self.data_source is None or any(lc.data is None for lc in self.loads):
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
                                     "(tyrefit.fitting.noise.noise_floor)"},
                "summary": self.summary(), "notes": list(self.notes),
                "channels": {ch: {"quantity": CHANNEL_WORDS[ch], "loads": rows,
                                  "definitions": CHANNEL_DEFINITIONS[ch]} for ch, rows in self.channels.items()},
                "channels_skipped": dict(self.channels_skipped),
                "channel_data_definitions": CHANNEL_DEFINITIONS["data"], "data_kind": self.data_kind}

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


        ta, tb = self._tyres
        a_name, b_name = self.names
        lo, hi = self.slip_range_deg
        by_run = {lc.run: lc for lc in self.loads}
        lat_data = self._data is not None and self.data_kind == "slip_angle"
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
                if lat_data and lc.run is not None:
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
            worst = [lc.data["mean_abs_dmu_over_peak_vs_data"] for lc in lcs if lc.data is not None] if lat_data else []
            _finish_panel(ax, title, worst, "slip angle [deg]", "-Fy/Fz [-]", legend=len(lcs) > 1)
        for ax in axes[n:]:
            ax.set_visible(False)
        fig = axes[0].figure
        fa, fb = (getattr(t, "family", "") or type(t).__name__ for t in (ta, tb))
        a_name, b_name = f"{a_name} [{fa}]", f"{b_name} [{fb}]"
        fig.suptitle(f"{a_name} (solid) and {b_name} (dashed), each evaluated at every sweep's own load, camber"
                     + (", pressure and speed" if self._data is not None else "")
                     + ("; circles: data (0.5° bins)" if lat_data else "")
                     if self._data is not None else f"{a_name} (solid) and {b_name} (dashed) at camber 0°",
                     fontsize=10)
        fig.tight_layout()
        return axes

    def _groups(self):
        """Panels: (title, [LoadComparison]) per condition level of the data, else one per load."""
        by_run = {lc.run: lc for lc in self.loads}
        if self._data is not None and all(lc.run is not None for lc in self.loads):
            chans = ("pressure", "speed", "slip_angle", "camber") if self.data_kind == "slip_ratio" else \
                ("pressure", "speed", "camber")
            facets, _ = facet_sweeps(self._data[self._data["run"].isin(by_run)], chans)
            return [(f.title, [by_run[r] for r in f.runs]) for f in facets]
        return [(lc.conditions, [lc]) for lc in self.loads]

    def plot_channel(self, ch: str, axes=None):  # noqa: C901 - one loop over panels and loads
        """One channel ('fx', 'mz', 'mx'; 'fy' is :meth:`plot_overlay`) against its slip variable.

        Both tyres at every compared load and condition (a solid, b dashed), and
        the data's bin means (circles) where the data carry the channel; one
        panel per condition level, loads as colours.  Returns the Axes array.
        """
        import matplotlib as mpl
        from matplotlib.figure import Figure


        if ch == "fy":
            return self.plot_overlay(axes)
        if ch not in self.channels:
            raise ValueError(f"channel {ch!r} was not compared ({self.channels_skipped.get(ch, 'unknown channel')})")
        ta, tb = self._tyres
        rows = {id(lc): row for lc, row in zip(self.loads, self.channels[ch])}
        groups = self._groups()
        n = len(groups)
        if axes is None:
            cols = min(n, 3)
            axes = Figure(figsize=(4.6 * cols, 3.6 * math.ceil(n / cols) + 0.6)).subplots(
                math.ceil(n / cols), cols, squeeze=False)
        axes = np.ravel(axes)
        fzs = [lc.fz for lc in self.loads]
        flo, fhi = min(fzs), max(fzs)
        cmap = mpl.colormaps["viridis"]
        lo, hi = self.slip_range_deg
        has_data = False
        for ax, (title, lcs) in zip(axes, groups):
            for lc in lcs:
                col = cmap(0.85 * (lc.fz - flo) / (fhi - flo)) if fhi > flo and len(lcs) > 1 else "k"
                ev = {"camber": lc.camber, "pressure": lc.pressure, "speed": lc.speed}
                g = lc.sweep
                if ch == "fx":
                    kr = rows[id(lc)]["kappa_range"]
                    x0, x1 = max(kr[0], -SLIP_RATIO_RANGE), min(kr[1], SLIP_RATIO_RANGE)
                    if g is not None and self.data_kind == "slip_ratio" and "fx" in g:
                        c = binned_channel(g, "slip_ratio", "fx", SLIP_RATIO_RANGE, RATIO_BIN)
                        ax.plot(c["slip_ratio"], c["fx"] / c["fz"], "o", color=col, ms=3, mfc="none")
                        has_data = True
                    xs = np.linspace(x0, x1, 241)
                    kw = {"slip_ratio": xs, "slip_angle": lc.slip_angle}
                    scale, xplot = 1.0 / lc.fz, xs
                else:
                    top = hi if lc.search_deg is None else min(hi, lc.search_deg)
                    if g is not None and self.data_kind == "slip_angle" and ch in g and g[ch].notna().sum() >= 3:
                        c = binned_channel(g, "slip_angle", ch, math.radians(hi), math.radians(BIN_DEG))
                        ax.plot(np.degrees(c["slip_angle"]), c[ch], "o", color=col, ms=3, mfc="none")
                        has_data = True
                    xs = np.radians(np.linspace(-top, top, 241))
                    kw = {"slip_angle": xs}
                    scale, xplot = 1.0, np.degrees(xs)
                fz = np.full(xs.shape, lc.fz)
                ax.plot(xplot, scale * channel_value(ta, ch, fz, **kw, **ev), "-", color=col, lw=1.5,
                        label=format_load(lc.fz), gid=f"{ch} a run {lc.run}")
                ax.plot(xplot, scale * channel_value(tb, ch, fz, **kw, **ev), "--", color=col, lw=1.5,
                        gid=f"{ch} b run {lc.run}")
            if len(lcs) == 1 and "Fz" not in title:
                title += f", Fz {format_load(lcs[0].fz)}"
            worst = [rows[id(lc)]["data"]["mean_abs_diff_over_peak_vs_data"] for lc in lcs if "data" in rows[id(lc)]]
            _finish_panel(ax, title, worst, "slip ratio [-]" if ch == "fx" else "slip angle [deg]",
                          {"fx": "Fx/Fz [-]", "mz": "Mz [N·m]", "mx": "Mx [N·m]"}[ch], legend=len(lcs) > 1)
        for ax in axes[n:]:
            ax.set_visible(False)
        fig = axes[0].figure
        fa, fb = (getattr(t, "family", "") or type(t).__name__ for t in (ta, tb))
        fig.suptitle(f"{CHANNEL_WORDS[ch]}\n{self.names[0]} [{fa}] (solid), {self.names[1]} [{fb}] (dashed)"
                     + ("; circles: data bin means" if has_data else ""), fontsize=10)
        fig.tight_layout()
        return axes

    def channel_table(self, ch: str) -> pd.DataFrame:
        """The per-load numbers of one compared channel, a and b side by side."""
        a, b = self.names
        out = []
        for row in self.channels.get(ch, []):
            r = {}
            for k, v in row.items():
                if k == "data" and isinstance(v, dict):
                    for j, nm in enumerate((a, b)):
                        r[f"{nm} vs data [%]"] = 100 * v["mean_abs_diff_over_peak_vs_data" if ch != "fy"
                                                        else "mean_abs_dmu_over_peak_vs_data"][j]
                        r[f"{nm} RMSE vs data [{v['unit']}]"] = v["rmse"][j]
                elif k in ("kappa_range", "run") or k.startswith("peak_reached"):
                    continue
                elif k == "mx_range":
                    for j, nm in enumerate((a, b)):
                        r[f"Mx range {nm} [N·m]"] = f"{v[j][0]:.4g} .. {v[j][1]:.4g}"
                elif isinstance(v, list) and len(v) == 2:
                    r[f"{k} {a}"], r[f"{k} {b}"] = v
                elif k.startswith("mean_abs"):
                    r[f"{k} [%]"] = 100 * v
                else:
                    r[k] = v
            out.append(r)
        return pd.DataFrame(out)

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
        if self.vs_data() is not None:
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
            f"{s['min_agreement_pct']:.1f} % at every load (Komana et al.'s 'within 90 %', as a number).")
        if "worst_vs_data" in s:
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
        for ch in CHANNELS:
            if ch == "fy" or ch not in self.channels:
                continue
            r.h3(f"{CHANNEL_WORDS[ch]}")
            r.table(self.channel_table(ch), digits=4)
            ax = self.plot_channel(ch)
            r.figure(ax[0].figure, f"{CHANNEL_WORDS[ch]}: {a} (solid), {b} (dashed) at each compared load and "
                                   "condition" + ("; data as bin means (circles)" if self.data_source else "") + ".")
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
        ``slip_angle``; ISO-W; ``mz``, ``mx`` scored where present) or, as a
        Dataset of kind ``slip_ratio``, slip-ratio sweeps (``slip_ratio``,
        ``fx``, ``fz``; scored on Fx).  Its sweeps set the loads.
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
    data_kind = None
    if data is not None:
        df = getattr(data, "df", data)
        source = getattr(data, "source", None) or "data"
        kind = getattr(data, "kind", "slip_angle")
        if kind not in ("slip_angle", "slip_ratio"):
            raise DataError(f"{source}: is a {kind} test; compare needs slip-angle sweeps ('slip_angle', 'fy', 'fz') "
                            "or slip-ratio sweeps ('slip_ratio', 'fx', 'fz')")
        need = ("slip_angle", "fy", "fz") if kind == "slip_angle" else ("slip_ratio", "fx", "fz")
        for c in need:
            if c not in df:
                raise DataError(f"{source}: no '{c}' column; compare needs {kind.replace('_', '-')} sweeps")
        if "run" not in df:
            df = df.assign(run=0)
        runs = [(int(r), g) for r, g in df.groupby("run", sort=True)]
        if kind == "slip_angle":
            runs = [(r, g) for r, g in runs if len(binned_curve(g, slip_range_deg)) >= 3]
            if not runs:
                raise DataError(f"{source}: no sweep has data across {lo:g}-{hi:g} deg of slip angle")
        else:
            runs = [(r, g) for r, g in runs
                    if len(binned_channel(g, "slip_ratio", "fx", SLIP_RATIO_RANGE, RATIO_BIN)) >= 3]
            if not runs:
                raise DataError(f"{source}: no sweep has data across +/-{SLIP_RATIO_RANGE:g} of slip ratio")
            lat_reach = _default_reach(tyre_a, tyre_b)
            notes.append("slip-ratio sweeps: the data score the Fx channel (each model at every point's own slip "
                         "ratio, slip angle and camber); Fy, Mz and Mx are compared model against model at the "
                         "sweeps' loads and conditions")
        data_kind = kind
        load_list = []
        for r, g in runs:
            cond = {c: (float(g[c].mean()) if c in g and g[c].notna().any() else None)
                    for c in ("camber", "pressure", "speed")}
            if kind == "slip_angle":
                reach = float(np.degrees(np.max(np.abs(g["slip_angle"].to_numpy(float)))))
            else:
                reach = lat_reach
                sa = float(g["slip_angle"].mean()) if "slip_angle" in g and g["slip_angle"].notna().any() else 0.0
                cond["slip_angle"] = sa if abs(sa) > math.radians(0.25) else 0.0
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
        if g is not None and data_kind == "slip_angle":
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
                                  max_mu=(ma["max_mu"], mb["max_mu"]), slip_angle=cond.get("slip_angle", 0.0),
                                  sweep=g))
    for k, nm in enumerate(names):
        miss = [lc for lc in out if not lc.peak_reached[k]]
        if miss:
            notes.append(f"{nm}: the peak is not reached within the tested slip range at {len(miss)} of {len(out)} "
                         f"loads (e.g. {miss[0].conditions}: still rising at {miss[0].search_deg:.1f} deg); "
                         "peak_mu and slip_at_peak_deg are left empty there")
    channels, skipped = compare_channels(tyre_a, tyre_b, out, names, slip_range_deg, data_kind)
    for ch, why in skipped.items():
        notes.append(f"{CHANNEL_WORDS[ch]} not compared: {why}")
    return Comparison(out, names, tuple(slip_range_deg), source, notes, (tyre_a, tyre_b), df, channels=channels,
                      channels_skipped=skipped, data_kind=data_kind)


def _sweep_floor(g: pd.DataFrame) -> float:
    """The within-sweep noise floor [N] of one sweep (the definition of fit and diagnose)."""
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


# ================================================================================ every channel
#: the channels compared, in order
CHANNELS = ("fx", "fy", "mz", "mx")
#: what each channel is, in words
CHANNEL_WORDS = {"fx": "longitudinal force Fx", "fy": "lateral force Fy", "mz": "aligning moment Mz",
                 "mx": "overturning moment Mx"}
_HAS = {"fx": "has_longitudinal", "fy": "has_lateral", "mz": "has_aligning", "mx": "has_overturning"}
_PAC89_BLOCK = {"fx": "longitudinal block b0..b10", "fy": "lateral block a0..a13", "mz": "aligning block c0..c17"}
#: slip-ratio window of the Fx score and plots, either sign [-]
SLIP_RATIO_RANGE = 0.3
#: bin width of a slip-ratio sweep's data curve [-]
RATIO_BIN = 0.01
_KAPPA_STEP = 0.0005
#: channel definitions (``channels`` in the JSON)
CHANNEL_DEFINITIONS = {
    "fx": {"slip_stiffness": "dFx/dkappa at zero slip ratio [N per unit slip ratio], at the load's slip angle",
           "peak_mu": "max of Fx/Fz over driving slip ratios (0..the tested or fitted slip ratio, else 1)",
           "slip_at_peak": "slip ratio [-] at peak_mu",
           "peak_mu_braking": "max of -Fx/Fz over braking slip ratios", "slip_at_peak_braking": "slip ratio [-]",
           "mean_abs_dmu_over_peak": "mean |Fx_a/Fz - Fx_b/Fz| over kappa in +/-0.3 (within the searched range) / "
                                     "peak |Fx_a/Fz| there"},
    "fy": {"cornering_stiffness": "as in loads[] (these are the top-level loads[] numbers)",
           "peak_mu": "as in loads[]", "slip_at_peak_deg": "as in loads[]", "mean_abs_dmu_over_peak": "as in loads[]"},
    "mz": {"aligning_stiffness": "dMz/dalpha at zero slip angle [N*m/rad]",
           "pneumatic_trail_at_zero": "-(dMz/dalpha)/(dFy/dalpha) at zero slip angle [m] (includes the residual "
                                      "torque's slope)",
           "peak_mz": "max of Mz (ISO-W: aligning is positive for positive slip angles) over 0..the searched slip "
                      "angle [N*m]", "slip_at_peak_deg": "slip angle at peak_mz [deg]",
           "mean_abs_diff_over_peak": "mean |Mz_a - Mz_b| over the slip range / max |Mz_a| there"},
    "mx": {"mx_range": "[min, max] of Mx over +/- the searched slip angle [N*m], per tyre",
           "mx_at_zero_slip": "Mx at zero slip angle [N*m]", "overturning_stiffness": "dMx/dalpha at zero [N*m/rad]",
           "mean_abs_diff_over_range": "mean |Mx_a - Mx_b| over +/- the slip range / (max - min) of Mx_a there"},
    "data": {"rmse": "root mean square of model - data over every point of the sweep, each model at the point's "
                     "own load, slip angle, slip ratio (slip-ratio sweeps) and camber [N or N*m]",
             "mean_abs_diff_over_peak_vs_data": "mean |model - data| over bins of the sweep variable (0.5 deg, "
                                                "0.01 slip ratio) / the data's peak |value| (Fx: of Fx/Fz; Mx: the "
                                                "data's max - min) in the window, for [a, b]"},
}


def channel_value(tyre, ch: str, fz, slip_angle=0.0, slip_ratio=0.0, camber=0.0, pressure=None,
                  speed=None) -> np.ndarray:
    """Channel ``ch`` ('fx', 'fy', 'mz', 'mx') of any tyre family [N or N*m], ISO-W; NaN where it has none."""
    fz = np.asarray(fz, float)
    shape = np.broadcast_shapes(np.shape(fz), np.shape(slip_angle), np.shape(slip_ratio), np.shape(camber))
    forces = getattr(tyre, "forces", None)
    with np.errstate(all="ignore"):
        if callable(forces):
            kw = {"slip_angle": slip_angle, "slip_ratio": slip_ratio, "camber": camber}
            if pressure is not None:
                kw["pressure"] = pressure
            if speed is not None:
                kw["speed"] = speed
            v = forces(fz, **kw).get(ch)
        else:  # older containers: fy(fz, alpha, camber), fx(fz, kappa), mz(fz, alpha, camber)
            fn = getattr(tyre, ch, None)
            v = None if not callable(fn) else (fn(fz, slip_ratio) if ch == "fx" else
                                               fn(fz, slip_angle, camber) if ch in ("fy", "mz") else None)
    if v is None:
        return np.full(shape, np.nan)
    return np.array(np.broadcast_to(np.asarray(v, float), shape))


def absent_reason(tyre, ch: str, name: str = "") -> str | None:
    """Why ``tyre`` does not carry channel ``ch`` from its own description (None: it says it does)."""
    fam = getattr(tyre, "family", "") or type(tyre).__name__
    who = f"{name} ({fam})" if name else fam
    word = CHANNEL_WORDS[ch]
    flag = getattr(tyre, _HAS[ch], None)
    if flag is None:
        outs = getattr(tyre, "outputs", None)
        if ch == "mx" and fam == "PAC89":
            return f"{who}: PAC89 has no overturning moment"
        if outs is not None and ch not in outs:
            return f"{who}: the model gives no {word}"
        return None
    if flag:
        return None
    if fam == "PAC89":
        return f"{who}: its {_PAC89_BLOCK[ch]} is zero or neutral, so it gives no {word}"
    computed = getattr(tyre, "_computed", None)
    nf = getattr(tyre, "not_fitted", None) or ()
    if ch in nf:
        return f"{who}: {word} is declared not fitted in the file (TYREFIT_NOT_FITTED)"
    if computed is not None and ch not in computed:
        return f"{who}: USE_MODE {getattr(tyre, 'use_mode', None)} does not compute {word}"
    if ch == "mx" and not getattr(tyre, "has_lateral", True):
        return f"{who}: no lateral part, so no {word}"
    return f"{who}: its {word} coefficients are all zero or absent"


def _probe(tyre, ch, loads) -> str | None:
    """'nan' or 'zero' when the channel gives nothing at the compared loads and conditions, else None."""
    vals = []
    for fz, ev in loads:
        if ch == "fx":
            x = {"slip_ratio": np.linspace(-0.2, 0.2, 21), "slip_angle": ev.get("slip_angle", 0.0) or 0.0}
        else:
            x = {"slip_angle": np.radians(np.linspace(-10, 10, 21))}
        vals.append(channel_value(tyre, ch, np.full(21, fz), camber=ev["camber"], pressure=ev["pressure"],
                                  speed=ev["speed"], **x))
    v = np.concatenate(vals)
    if not np.isfinite(v).any():
        return "nan"
    if np.nanmax(np.abs(v)) < 1e-9:
        return "zero"
    return None


def _peak(x, y, inside: int):
    """Index of the max of y and whether it lies at least ``inside`` steps inside the searched range."""
    if not x.size or not np.isfinite(y).any():
        return 0, False
    i = int(np.nanargmax(y))
    return i, bool(0 < i < len(x) - 1 - inside)  # a maximum at either end of the range is not a peak


def fx_metrics(tyre, fz, *, camber=0.0, pressure=None, speed=None, slip_angle=0.0,
               kappa_range=(-1.0, 1.0)) -> dict:
    """Slip stiffness [N/-], driving and braking peak mu_x and their slip ratios of a tyre at load ``fz``.

    Peaks are searched over ``kappa_range`` (driving 0..high, braking low..0);
    a maximum at the end of the range is not a peak (NaN, ``peak_reached`` False).
    """
    ev = dict(camber=camber, pressure=pressure, speed=speed, slip_angle=slip_angle)
    h = 1e-4
    ks = float((channel_value(tyre, "fx", fz, slip_ratio=h, **ev) - channel_value(tyre, "fx", fz, slip_ratio=-h, **ev))
               / (2 * h))
    nan = float("nan")
    out = {"slip_stiffness": ks, "kappa_range": [float(kappa_range[0]), float(kappa_range[1])]}
    for side, sgn, lim in (("", 1.0, kappa_range[1]), ("_braking", -1.0, kappa_range[0])):
        k = sgn * np.arange(0.0, abs(lim) + 1e-12, _KAPPA_STEP) if sgn * lim > 0 else np.zeros(0)
        mu = sgn * channel_value(tyre, "fx", np.full(k.shape, fz), slip_ratio=k, **ev) / fz
        i, ok = _peak(k, mu, int(round(0.005 / _KAPPA_STEP)))
        out[f"peak_mu{side}"] = float(mu[i]) if ok else nan
        out[f"slip_at_peak{side}"] = float(k[i]) if ok else nan
        out[f"peak_reached{side}"] = ok
    return out


def mz_metrics(tyre, fz, *, camber=0.0, pressure=None, speed=None, max_slip_deg=_PEAK_SEARCH_DEG) -> dict:
    """Aligning stiffness, pneumatic trail near zero slip, peak Mz and its slip angle of a tyre at ``fz``."""
    ev = dict(camber=camber, pressure=pressure, speed=speed)
    h = 1e-4
    dmz = float((channel_value(tyre, "mz", fz, h, **ev) - channel_value(tyre, "mz", fz, -h, **ev)) / (2 * h))
    dfy = float((channel_value(tyre, "fy", fz, h, **ev) - channel_value(tyre, "fy", fz, -h, **ev)) / (2 * h))
    a = np.radians(np.arange(0.0, max_slip_deg + 1e-9, 0.01))
    mz = channel_value(tyre, "mz", np.full(a.shape, fz), a, **ev)
    i, ok = _peak(a, mz, 5)
    nan = float("nan")
    return {"aligning_stiffness": dmz, "pneumatic_trail_at_zero": -dmz / dfy if dfy and np.isfinite(dfy) else nan,
            "peak_mz": float(mz[i]) if ok else nan, "slip_at_peak_deg": float(np.degrees(a[i])) if ok else nan,
            "peak_reached": ok, "max_mz": float(np.nanmax(mz)) if np.isfinite(mz).any() else nan}


def mx_metrics(tyre, fz, *, camber=0.0, pressure=None, speed=None, max_slip_deg=_PEAK_SEARCH_DEG) -> dict:
    """Overturning moment range over +/- the slip range, at zero slip and its slope, of a tyre at ``fz``."""
    ev = dict(camber=camber, pressure=pressure, speed=speed)
    h = 1e-4
    a = np.radians(np.arange(-max_slip_deg, max_slip_deg + 1e-9, 0.05))
    mx = channel_value(tyre, "mx", np.full(a.shape, fz), a, **ev)
    return {"mx_range": [float(np.nanmin(mx)), float(np.nanmax(mx))],
            "mx_at_zero_slip": float(channel_value(tyre, "mx", fz, 0.0, **ev)),
            "overturning_stiffness": float((channel_value(tyre, "mx", fz, h, **ev)
                                            - channel_value(tyre, "mx", fz, -h, **ev)) / (2 * h))}


def _score(ch, ya, yb, fz) -> float:
    """Model-against-model score of one channel on a grid (see CHANNEL_DEFINITIONS)."""
    if not ya.size:
        return float("nan")
    if ch == "mx":
        norm = float(np.ptp(ya))
    else:
        norm = float(np.max(np.abs(ya)))
    if ch == "fx":
        ya, yb, norm = ya / fz, yb / fz, norm / fz
    return float(np.mean(np.abs(ya - yb)) / norm) if norm > 0 else float("nan")


def binned_channel(g: pd.DataFrame, x: str, ch: str, window, width) -> pd.DataFrame:
    """Means of x, fz, camber, slip_angle and ``ch`` in bins of ``width`` of the sweep variable ``x`` within
    |x| <= ``window`` (either sign)."""
    keep = g[ch].notna().to_numpy() & (np.abs(g[x].to_numpy(float)) <= window + 1e-12)
    cols = {x: g[x].to_numpy(float)[keep], "fz": g["fz"].to_numpy(float)[keep], ch: g[ch].to_numpy(float)[keep]}
    for c in ("camber", "slip_angle"):
        if c in g and c not in cols:
            cols[c] = g[c].to_numpy(float)[keep]
    df = pd.DataFrame(cols)
    df["bin"] = np.floor(df[x] / width)
    grp = df.groupby("bin")
    out = grp.mean()
    out["n"] = grp.size()
    return out.reset_index(drop=True)


def _point_inputs(d: pd.DataFrame, x: str) -> dict:
    """Model inputs at each row of ``d``: its slip variable, slip angle (slip-ratio sweeps) and camber."""
    kw = {"camber": d["camber"].to_numpy(float) if "camber" in d else 0.0}
    if x == "slip_ratio":
        kw["slip_ratio"] = d["slip_ratio"].to_numpy(float)
        kw["slip_angle"] = d["slip_angle"].to_numpy(float) if "slip_angle" in d else 0.0
    else:
        kw["slip_angle"] = d["slip_angle"].to_numpy(float)
    return kw


def channel_vs_data(tyres, g: pd.DataFrame, x: str, ch: str, ev: dict, window, width) -> dict | None:
    """Both models against one sweep's ``ch`` column (None when the sweep does not carry it)."""
    if ch not in g or g[ch].notna().sum() < 3:
        return None
    c = binned_channel(g, x, ch, window, width)
    if len(c) < 3:
        return None
    pts = g[g[ch].notna()]
    y = c[ch].to_numpy(float)
    fzb = c["fz"].to_numpy(float)
    if ch in ("fx", "fy"):
        y = y / fzb
    norm = float(np.ptp(y)) if ch == "mx" else float(np.max(np.abs(y)))
    vs, rmse = [], []
    for t in tyres:
        m = channel_value(t, ch, fzb, pressure=ev["pressure"], speed=ev["speed"], **_point_inputs(c, x))
        if ch in ("fx", "fy"):
            m = m / fzb
        vs.append(float(np.mean(np.abs(m - y)) / norm) if norm > 0 else float("nan"))
        mp = channel_value(t, ch, pts["fz"].to_numpy(float), pressure=ev["pressure"], speed=ev["speed"],
                           **_point_inputs(pts, x))
        rmse.append(float(np.sqrt(np.mean((mp - pts[ch].to_numpy(float)) ** 2))))
    out = {"rmse": rmse, "unit": "N" if ch in ("fx", "fy") else "N*m", "mean_abs_diff_over_peak_vs_data": vs,
           "agreement_with_data_pct": [100 * (1 - v) for v in vs], "bins": int(len(c)), "points": int(len(pts))}
    xs = c[x].to_numpy(float)
    if ch == "fx":
        for side, sel, sgn in (("", xs > 0, 1.0), ("_braking", xs < 0, -1.0)):
            if sel.any():
                i = int(np.argmax(sgn * y[sel]))
                out[f"peak_mu{side}"] = float(sgn * y[sel][i])
                out[f"slip_at_peak{side}"] = float(xs[sel][i])
    elif ch == "mz":
        i = int(np.argmax(np.abs(y)))
        out["peak_abs_mz"] = float(abs(y[i]))
        out["slip_at_peak_deg"] = float(abs(np.degrees(xs[i])))
    elif ch == "mx":
        out["mx_range"] = [float(y.min()), float(y.max())]
    return out


def _fx_range(tyres, g=None) -> tuple[float, float]:
    """Slip-ratio search range: the sweep's (with data), else the tyres' fitted ones, else +/-1."""
    if g is not None and "slip_ratio" in g:
        k = g["slip_ratio"].to_numpy(float)
        return float(min(k.min(), 0.0)), float(max(k.max(), 0.0))
    lo, hi = -1.0, 1.0
    for t in tyres:
        r = (getattr(t, "ranges", None) or {}).get("slip_ratio")
        if r:
            lo, hi = max(lo, float(r[0])), min(hi, float(r[1]))
    return min(lo, 0.0), max(hi, 0.0)


def compare_channels(tyre_a, tyre_b, loads: list, names, slip_range_deg=SLIP_RANGE_DEG, data_kind=None):
    """Every channel both tyres carry at the compared loads.

    ``loads`` is the list of ``LoadComparison`` of :func:`compare_tyres` (each with its sweep in
    ``lc.sweep`` when there are data, and ``lc.slip_angle`` for slip-ratio sweeps).  Returns ``(channels, skipped)``: channel -> list of
    per-load dicts, and channel -> the reason it was not compared.
    """
    tyres = (tyre_a, tyre_b)
    lo, hi = slip_range_deg
    conds = [(lc.fz, {"camber": lc.camber, "pressure": lc.pressure, "speed": lc.speed,
                      "slip_angle": lc.slip_angle}) for lc in loads]
    channels, skipped = {}, {}
    for ch in CHANNELS:
        why = []
        for t, nm in zip(tyres, names):
            r = absent_reason(t, ch, nm)
            if r is None:
                p = _probe(t, ch, conds)
                if p == "nan":
                    r = f"{nm}: gives no {CHANNEL_WORDS[ch]} (not a number at every compared load)"
                elif p == "zero":
                    r = f"{nm}: {CHANNEL_WORDS[ch]} is zero at every compared load and slip (its coefficients " \
                        "are zero)"
            if r:
                why.append(r)
        if why:
            skipped[ch] = "; ".join(why)
            continue
        rows = []
        for lc in loads:
            ev = {"camber": lc.camber, "pressure": lc.pressure, "speed": lc.speed}
            base = {"fz": lc.fz, "camber_deg": math.degrees(lc.camber)}
            if lc.pressure is not None:
                base["pressure_kpa"] = lc.pressure / 1e3
            if lc.speed is not None:
                base["speed_kmh"] = lc.speed * 3.6
            if lc.run is not None:
                base["run"] = lc.run
            g = lc.sweep
            reach = lc.search_deg
            top = hi if reach is None else min(hi, reach)
            if ch == "fy":
                d = lc.to_dict()
                row = {**base, **{k: d[k] for k in ("cornering_stiffness", "peak_mu", "slip_at_peak_deg",
                                                    "mean_abs_dmu_over_peak", "peak_reached")}}
                if lc.data is not None:
                    row["data"] = {"rmse": lc.data["rmse_N"], "unit": "N",
                                   "mean_abs_dmu_over_peak_vs_data": lc.data["mean_abs_dmu_over_peak_vs_data"],
                                   "peak_mu": lc.data["peak_mu"], "points": lc.data["points"]}
            elif ch == "fx":
                sa = lc.slip_angle or 0.0
                kr = _fx_range(tyres, g if data_kind == "slip_ratio" else None)
                m = [fx_metrics(t, lc.fz, slip_angle=sa, kappa_range=kr, **ev) for t in tyres]
                k = np.arange(max(kr[0], -SLIP_RATIO_RANGE), min(kr[1], SLIP_RATIO_RANGE) + 1e-12, 0.002)
                ya, yb = (channel_value(t, "fx", np.full(k.shape, lc.fz), sa, k, **ev) for t in tyres)
                row = {**base, "slip_angle_deg": math.degrees(sa)} if sa else dict(base)
                row.update({key: [m[0][key], m[1][key]] for key in
                            ("slip_stiffness", "peak_mu", "slip_at_peak", "peak_mu_braking", "slip_at_peak_braking",
                             "peak_reached", "peak_reached_braking")})
                row["kappa_range"] = m[0]["kappa_range"]
                row["mean_abs_dmu_over_peak"] = _score("fx", ya, yb, lc.fz)
                if g is not None and data_kind == "slip_ratio":
                    row["data"] = channel_vs_data(tyres, g, "slip_ratio", "fx", ev, SLIP_RATIO_RANGE, RATIO_BIN)
            elif ch == "mz":
                m = [mz_metrics(t, lc.fz, max_slip_deg=reach if reach is not None else _PEAK_SEARCH_DEG, **ev)
                     for t in tyres]
                aa = np.radians(np.arange(lo, top + 1e-9, 0.05))
                ya, yb = (channel_value(t, "mz", np.full(aa.shape, lc.fz), aa, **ev) for t in tyres)
                row = {**base, **{key: [m[0][key], m[1][key]] for key in
                                  ("peak_mz", "slip_at_peak_deg", "pneumatic_trail_at_zero", "aligning_stiffness",
                                   "peak_reached")}}
                row["mean_abs_diff_over_peak"] = _score("mz", ya, yb, lc.fz)
            else:
                m = [mx_metrics(t, lc.fz, max_slip_deg=top, **ev) for t in tyres]
                aa = np.radians(np.arange(-top, top + 1e-9, 0.05))
                ya, yb = (channel_value(t, "mx", np.full(aa.shape, lc.fz), aa, **ev) for t in tyres)
                row = {**base, **{key: [m[0][key], m[1][key]] for key in
                                  ("mx_range", "mx_at_zero_slip", "overturning_stiffness")}}
                row["mean_abs_diff_over_range"] = _score("mx", ya, yb, lc.fz)
            if ch in ("mz", "mx") and g is not None and data_kind == "slip_angle":
                row["data"] = channel_vs_data(tyres, g, "slip_angle", ch, ev, math.radians(hi), math.radians(BIN_DEG))
            if "data" in row and row["data"] is None:
                del row["data"]
            rows.append(row)
        channels[ch] = rows
    return channels, skipped


def _finish_panel(ax, title: str, worst, xlabel: str, ylabel: str, legend: bool) -> None:
    """Title (with the panel's worst score against the data, tyre a / tyre b), labels, grid, the load legend."""
    if len(worst):
        d = np.asarray(worst, float)
        title += f"\nvs data (worst load): {100 * d[:, 0].max():.1f} % / {100 * d[:, 1].max():.1f} %"
    ax.set_title(title, fontsize=9)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    if legend:
        ax.legend(fontsize=7, title="Fz", title_fontsize=7)
