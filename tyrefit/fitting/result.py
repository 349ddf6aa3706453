"""The result of a PAC89 fit: the tyre, its coefficients with uncertainties, and how well it fits.

:class:`FitResult` is returned by :func:`tyrefit.fitting.fit_pac89`.  Like
lmfit's ``ModelResult`` it carries its own text and HTML reports and a
``plot(ax=None)`` of the fit over the data.

Statistics (per part: lateral Fy, longitudinal Fx, aligning Mz)
---------------------------------------------------------------
* residual = model - data at each measured point, in N (N*m for Mz);
* per sweep: RMSE and bias (mean residual) in N and in % of the sweep's
  peak |F| measured;
* R^2 = 1 - SS_res / SS_tot over all points of the part;
* noise floor: see :func:`tyrefit.fitting.engine.noise_floor` (neighbouring
  points along each sweep after removing a local linear trend);
* the fitted cost in mu (``objective``): sum over sweeps of the mean squared
  (l2) or mean absolute (l1, Komana et al. Eq. 5) mu residual, and the plain
  Eq. 5 sum sum|mu_model - mu_data| over all points.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from .. import __version__
from ..tyres.pac89 import Pac89Tyre

__all__ = ["FitResult"]

_RAD_TO_DEG = 180.0 / math.pi
_LABEL = {"lateral": ("fy", "Fy", "N", "slip_angle", "slip angle [deg]", _RAD_TO_DEG),
          "longitudinal": ("fx", "Fx", "N", "slip_ratio", "slip ratio [%]", 100.0),
          "aligning": ("mz", "Mz", "N·m", "slip_angle", "slip angle [deg]", _RAD_TO_DEG)}
_DESIGN = ("unloaded_radius", "width", "fnomin", "lateral_stiffness", "vertical_stiffness", "rolling_resistance",
           "name", "tyreside", "vertical_curve")


@dataclass
class FitResult:
    """A fitted PAC89 tyre and the statistics of the fit.

    Attributes
    ----------
    tyre : Pac89Tyre
        coefficients, fitted ranges (``fz``, ``slip_angle``, ``camber``,
        ``slip_ratio``), design data, and a header recording the source data
        and fit statistics.
    params : lmfit.Parameters
        every coefficient of the fitted parts: value, ``vary``, bounds (where
        a coefficient is bounded directly), ``stderr`` and ``correl``.
    coefficients : pandas.DataFrame
        name, part, value, stderr, rel_stderr [%], varied, initial, status.
    correlations : dict of str -> DataFrame
        correlation matrix of the varied coefficients per part.
    sweeps : pandas.DataFrame
        one row per sweep: part, run, n, fz [N], camber [deg], pressure [Pa],
        peak [N], rmse, bias [N] and rmse_pct, bias_pct [% of peak], noise [N].
    stats : dict of str -> dict
        per part: n, sweeps, rmse, r2, noise_floor, objective, eq5_cost,
        nfev, seconds, load range.
    not_identifiable : dict of str -> str
        coefficient -> why the data cannot determine it (held at its neutral value).
    estimates : dict of str -> DataFrame
        the Eq. 2-4 per-sweep estimates.
    initial : dict
        starting coefficients from the estimates.
    notes : list of str
    cost : str
        'l1' or 'l2'.
    """

    tyre: Pac89Tyre
    params: object
    coefficients: pd.DataFrame
    correlations: dict
    sweeps: pd.DataFrame
    stats: dict
    not_identifiable: dict
    estimates: dict
    initial: dict
    notes: list
    cost: str
    source: str = ""
    seconds: float = 0.0
    constraints: list = field(default_factory=list)
    _parts: dict = field(default_factory=dict, repr=False)

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_parts(cls, fits: dict, *, info: dict, cost: str, notes: list, tyre_info=None, fixed=None,
                   initial=None, seconds: float = 0.0) -> "FitResult":
        import lmfit

        coeffs: dict[str, float] = {}
        for pf in fits.values():
            coeffs.update(pf.coefficients)
        rows, sweep_rows, stats, not_id, correl, est, init = [], [], {}, {}, {}, {}, {}
        params = lmfit.Parameters()
        constraints = []
        for name, pf in fits.items():
            d = pf.data
            col, sym, unit, slip, _, _ = _LABEL[name]
            model = pf.data.part.model(pf.coefficients, d.fz, d.slip, d.camber)
            res = model - d.y
            ss_res = float(np.sum(res**2))
            ss_tot = float(np.sum((d.y - d.y.mean()) ** 2))
            mu_res = (model - d.y) / d.fz
            stats[name] = {
                "n": int(d.n), "sweeps": int(len(set(d.run.tolist()))), "rmse": math.sqrt(ss_res / d.n),
                "r2": 1.0 - ss_res / ss_tot if ss_tot > 0 else float("nan"), "noise_floor": pf.noise_floor,
                "objective": pf.objective, "eq5_cost": float(np.sum(np.abs(mu_res))),
                "mean_abs_mu": float(np.mean(np.abs(mu_res))), "nfev": pf.nfev, "seconds": pf.seconds,
                "fz_range": d.fz_range, "unit": unit, "varied": len(pf.varied), "facts": pf.facts,
            }
            df = d.df.assign(_res=res)
            for run, g in df.groupby("run", sort=True):
                peak = float(np.max(np.abs(g[col])))
                r = g["_res"].to_numpy()
                row = {"part": name, "run": int(run), "n": len(g), "fz": float(g["fz"].mean()),
                       "camber": float(g["camber"].mean()) * _RAD_TO_DEG}
                if "pressure" in g:
                    row["pressure"] = float(g["pressure"].mean())
                rmse, bias = float(np.sqrt(np.mean(r**2))), float(np.mean(r))
                row.update({"peak": peak, "rmse": rmse, "bias": bias,
                            "rmse_pct": 100 * rmse / peak if peak > 0 else float("nan"),
                            "bias_pct": 100 * bias / peak if peak > 0 else float("nan"),
                            "noise": float(pf.noise_per_run.get(run, float("nan")))})
                sweep_rows.append(row)
            for k, why in pf.not_identifiable.items():
                not_id[k] = why
            correl[name] = pf.correl
            est[name] = pf.estimates
            init.update(pf.initial)
            constraints += [f"{name}: {c}" for c in pf.constraints]
            for k in pf.data.part.names:
                v = pf.coefficients[k]
                varied = k in pf.varied
                se = pf.stderr.get(k, float("nan")) if varied else float("nan")
                if varied:
                    status = "fitted"
                elif k in (fixed or {}):
                    status = "fixed"
                elif k in pf.not_identifiable:
                    status = "not identifiable: " + pf.not_identifiable[k]
                else:
                    status = "held"
                rows.append({"name": k, "part": name, "value": v, "stderr": se,
                             "rel_stderr": 100 * se / abs(v) if varied and v != 0 else float("nan"),
                             "varied": varied, "initial": pf.initial.get(k, float("nan")), "status": status})
                lo, hi = pf.bounds.get(k, (-np.inf, np.inf))
                params.add(k, value=v, vary=varied, min=lo if lo < v else -np.inf, max=hi if hi > v else np.inf)
                params[k].stderr = se if varied else None
            if isinstance(pf.correl, pd.DataFrame) and not pf.correl.empty:
                cm, ci = pf.correl.to_numpy(), list(pf.correl.index)
                for a, k in enumerate(ci):
                    params[k].correl = {j: float(cm[a, b]) for b, j in enumerate(ci) if j != k}
        tyre = _make_tyre(coeffs, fits, info, cost, stats, not_id, tyre_info)
        return cls(tyre=tyre, params=params, coefficients=pd.DataFrame(rows), correlations=correl,
                   sweeps=pd.DataFrame(sweep_rows), stats=stats, not_identifiable=not_id, estimates=est,
                   initial=init, notes=list(dict.fromkeys(notes)), cost=cost, source=info.get("source", ""),
                   seconds=seconds, constraints=constraints, _parts=fits)

    # ------------------------------------------------------------------ convenience
    @property
    def parts(self) -> list[str]:
        """Fitted parts: 'lateral', 'longitudinal', 'aligning'."""
        return list(self._parts)

    @property
    def rmse(self) -> float:
        """Lateral-force RMSE [N] (longitudinal if no lateral part)."""
        return self.stats[self.parts[0]]["rmse"]

    @property
    def noise_floor(self) -> float:
        """Noise-floor estimate [N] of the first part (lateral if fitted)."""
        return self.stats[self.parts[0]]["noise_floor"]

    @property
    def values(self) -> dict[str, float]:
        """All coefficients a0..c17 of the tyre (PAC89 units)."""
        return dict(self.tyre.coefficients)

    @property
    def data(self) -> pd.DataFrame:
        """The points fitted, with ``part`` and model/residual columns."""
        frames = []
        for name, pf in self._parts.items():
            d = pf.data
            model = d.part.model(pf.coefficients, d.fz, d.slip, d.camber)
            frames.append(d.df.assign(part=name, model=model, residual=model - d.y))
        return pd.concat(frames, ignore_index=True)

    def predict(self, df: pd.DataFrame) -> pd.DataFrame:
        """Model values at the conditions of ``df`` (canonical SI columns).

        Returns a DataFrame with ``fy_model`` (needs ``slip_angle``), ``mz_model``
        (when Mz was fitted) and ``fx_model`` (needs ``slip_ratio``) [N, N*m].
        """
        t = self.tyre
        fz = df["fz"].to_numpy(float)
        cam = df["camber"].to_numpy(float) if "camber" in df else 0.0
        out = pd.DataFrame(index=df.index)
        if "slip_angle" in df and "lateral" in self._parts:
            out["fy_model"] = t.fy(fz, df["slip_angle"].to_numpy(float), cam)
        if "slip_angle" in df and "aligning" in self._parts:
            out["mz_model"] = t.mz(fz, df["slip_angle"].to_numpy(float), cam)
        if "slip_ratio" in df and "longitudinal" in self._parts:
            out["fx_model"] = t.fx(fz, df["slip_ratio"].to_numpy(float))
        return out

    # ------------------------------------------------------------------ reports
    def summary(self) -> str:
        """Plain-text report: statistics, coefficients, not-identifiable terms, notes."""
        L = [f"PAC89 fit ({'Komana et al. Eq. 5, sum |mu error|' if self.cost == 'l1' else 'least squares on mu'})"
             f" of {self.source or 'data'} in {self.seconds:.2f} s"]
        for name, s in self.stats.items():
            lo, hi = s["fz_range"]
            L.append(f"  {name:<12} {s['n']} points, {s['sweeps']} sweeps, Fz {lo:.0f}-{hi:.0f} N: "
                     f"RMSE {s['rmse']:.4g} {s['unit']}, R² {s['r2']:.5f}, noise floor {s['noise_floor']:.3g} "
                     f"{s['unit']}, {s['varied']} coefficients fitted")
        L.append("")
        L.append(f"  {'name':<5} {'value':>14} {'stderr':>11} {'rel %':>8}  status")
        for r in self.coefficients.itertuples():
            se = f"{r.stderr:11.3g}" if r.varied else " " * 11
            rel = f"{r.rel_stderr:8.2f}" if r.varied and np.isfinite(r.rel_stderr) else " " * 8
            L.append(f"  {r.name:<5} {r.value:14.6g} {se} {rel}  {r.status}")
        worst = self.sweeps.sort_values("rmse_pct", ascending=False).head(5)
        L.append("")
        L.append("  worst sweeps (RMSE % of peak): " + ", ".join(
            f"{r.part[:3]} run {r.run} Fz {r.fz:.0f} N: {r.rmse_pct:.2f} %" for r in worst.itertuples()))
        if self.constraints:
            L.append("  constraints: " + "; ".join(self.constraints))
        for n in self.notes:
            L.append(f"  note: {n}")
        return "\n".join(L)

    def __str__(self) -> str:  # pragma: no cover - convenience
        return self.summary()

    def _stats_rows(self) -> list[dict]:
        rows = []
        for name, s in self.stats.items():
            lo, hi = s["fz_range"]
            rows.append({"part": name, "points": s["n"], "sweeps": s["sweeps"], "Fz range [N]": f"{lo:.0f}–{hi:.0f}",
                         "RMSE": f"{s['rmse']:.4g} {s['unit']}", "R²": s["r2"],
                         "noise floor": f"{s['noise_floor']:.3g} {s['unit']}",
                         "Eq. 5 cost Σ|Δμ|": s["eq5_cost"], "fitted coefficients": s["varied"],
                         "evaluations": s["nfev"], "time [s]": s["seconds"]})
        return rows

    def _coef_rows(self) -> pd.DataFrame:
        t = self.coefficients.copy()
        return t[["name", "value", "stderr", "rel_stderr", "initial", "status"]].rename(
            columns={"rel_stderr": "stderr [%]", "initial": "Eq. 2–4 start"})

    def to_html(self) -> str:
        """HTML fragment: statistics, coefficient table, not-identifiable list, notes."""
        from ..io.report import Report

        r = Report("PAC89 fit")
        self._report_blocks(r, figures=False)
        return "\n".join(r.blocks)

    def _repr_html_(self) -> str:
        return self.to_html()

    def _report_blocks(self, r, figures: bool = True) -> None:
        r.p(f"Source: {self.source or 'data frame'}; cost: "
            f"{'sum of absolute μ errors (Komana et al. Eq. 5)' if self.cost == 'l1' else 'least squares on μ'}, "
            "each sweep weighted 1/n.", "note")
        r.h2("Statistics")
        r.table(self._stats_rows())
        if figures:
            for part in self.parts:
                r.figure(self._facet_figure(part), f"{part}: PAC89 fit (lines) over the data (dots), per load")
                r.figure(self._residual_figure(part), f"{part}: residuals (model − data) vs slip, per load")
        r.h2("Coefficients")
        r.table(self._coef_rows(), digits=6)
        if self.not_identifiable:
            r.h3("Not identifiable from these data (held at neutral values)")
            r.bullets([f"{k}: {v}" for k, v in self.not_identifiable.items()])
        if self.constraints:
            r.h3("Constraints")
            r.bullets(self.constraints)
        for part, c in self.correlations.items():
            if isinstance(c, pd.DataFrame) and not c.empty:
                strong = [(a, b, c.loc[a, b]) for i, a in enumerate(c.index) for b in c.columns[i + 1:]
                          if abs(c.loc[a, b]) > 0.95]
                if strong:
                    r.p(f"{part}: strongly correlated pairs: " + ", ".join(f"{a}–{b} {v:+.3f}" for a, b, v in strong))
        r.h2("Sweeps")
        cols = [c for c in ("part", "run", "n", "fz", "camber", "pressure", "peak", "rmse", "rmse_pct", "bias",
                            "bias_pct", "noise") if c in self.sweeps]
        r.table(self.sweeps[cols], digits=4)
        if self.notes:
            r.h3("Notes")
            r.bullets(self.notes)

    def report(self, directory: str | os.PathLike, force: bool = False, title: str | None = None) -> Path:
        """Write ``directory/index.html`` (figures embedded) and ``sweeps.csv``; returns the HTML path."""
        from ..io.outputs import check_output, write_text
        from ..io.report import Report

        d = Path(directory)
        check_output(d / "index.html", force)
        r = Report(title or f"PAC89 fit — {Path(self.source).name if self.source else 'data'}")
        self._report_blocks(r, figures=True)
        d.mkdir(parents=True, exist_ok=True)
        write_text(d / "sweeps.csv", self.sweeps.to_csv(index=False), force=True)
        return r.save(d, force=force)

    # ------------------------------------------------------------------ plots
    def plot(self, ax=None, part: str | None = None, camber: float | None = None, pressure: float | None = None):
        """Fit (lines) over data (dots) for each load, on one Axes; returns the Axes.

        Parameters
        ----------
        part : {'lateral', 'longitudinal', 'aligning'}, optional
            default: the first fitted part.
        camber : float, optional
            show only sweeps at this camber [rad] (nearest level); default: the
            level nearest to zero.
        pressure : float, optional
            show only sweeps at this pressure [Pa] (nearest level).
        """
        import matplotlib.pyplot as plt

        part = part or self.parts[0]
        if ax is None:
            _, ax = plt.subplots(figsize=(6.4, 4.4))
        col, sym, unit, slip, xlabel, xs = _LABEL[part]
        pf = self._parts[part]
        df = pf.data.df
        sel = np.ones(len(df), bool)
        cams = df["camber"].to_numpy()
        target = 0.0 if camber is None else camber
        levels = np.unique(np.round(cams, 4))
        near = levels[np.argmin(np.abs(levels - target))] if len(levels) else 0.0
        sel &= np.abs(np.round(cams, 4) - near) < math.radians(0.2)
        if pressure is not None and "pressure" in df:
            pl = np.unique(np.round(df["pressure"].to_numpy(), -2))
            pn = pl[np.argmin(np.abs(pl - pressure))]
            sel &= np.abs(df["pressure"].to_numpy() - pn) < 0.05e5
        sub = df[sel]
        cmap = plt.get_cmap("viridis")
        runs = sub.groupby("run")["fz"].mean().sort_values()
        fz_all = runs.to_numpy()
        lo, hi = (fz_all.min(), fz_all.max()) if len(fz_all) else (0, 1)
        for run, fzm in runs.items():
            g = sub[sub["run"] == run]
            c = cmap(0.85 * (fzm - lo) / (hi - lo)) if hi > lo else cmap(0.3)
            ax.plot(g[slip] * xs, g[col], ".", ms=3, color=c, alpha=0.5)
            xg = np.linspace(g[slip].min(), g[slip].max(), 200)
            cm = float(g["camber"].mean())
            yg = pf.data.part.model(pf.coefficients, np.full_like(xg, fzm), xg, cm)
            ax.plot(xg * xs, yg, "-", color=c, lw=1.4, label=f"{fzm / 1e3:.2f} kN")
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"{sym} [{unit}]")
        ax.set_title(f"{part}: camber {math.degrees(near):.1f}°" if part != "longitudinal" else part)
        ax.grid(alpha=0.3)
        if len(runs) <= 12:
            ax.legend(fontsize=7, title="Fz", title_fontsize=7)
        return ax

    def plot_residuals(self, ax=None, part: str | None = None):
        """Residuals (model - data) vs slip, coloured by load; returns the Axes."""
        import matplotlib.pyplot as plt

        part = part or self.parts[0]
        if ax is None:
            _, ax = plt.subplots(figsize=(6.4, 4.0))
        col, sym, unit, slip, xlabel, xs = _LABEL[part]
        pf = self._parts[part]
        d = pf.data
        res = d.part.model(pf.coefficients, d.fz, d.slip, d.camber) - d.y
        sc = ax.scatter(d.slip * xs, res, c=d.fz / 1e3, s=4, cmap="viridis", alpha=0.6)
        ax.axhline(0, color="k", lw=0.8)
        nf = self.stats[part]["noise_floor"]
        if np.isfinite(nf):
            ax.axhspan(-nf, nf, color="0.85", zorder=0, label=f"± noise floor {nf:.3g} {unit}")
            ax.legend(fontsize=7)
        ax.figure.colorbar(sc, ax=ax, label="Fz [kN]")
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"{sym} model − data [{unit}]")
        ax.grid(alpha=0.3)
        return ax

    def _facet_figure(self, part: str):
        import matplotlib.pyplot as plt

        df = self._parts[part].data.df
        cams = np.unique(np.round(np.degrees(df["camber"].to_numpy()) * 4) / 4) if part != "longitudinal" else [0.0]
        pres = np.unique(np.round(df["pressure"].to_numpy(), -3)) if "pressure" in df and df["pressure"].notna().all() \
            else [None]
        cams = list(cams)[:6]
        pres = list(pres)[:4]
        fig, axes = plt.subplots(len(pres), len(cams), figsize=(4.2 * len(cams), 3.4 * len(pres)), squeeze=False)
        for i, p in enumerate(pres):
            for j, c in enumerate(cams):
                ax = self.plot(axes[i][j], part=part, camber=math.radians(c), pressure=p)
                if p is not None:
                    ax.set_title(ax.get_title() + f", {p / 1e5:.2f} bar")
        fig.tight_layout()
        return fig

    def _residual_figure(self, part: str):
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(7, 3.6))
        self.plot_residuals(ax, part=part)
        fig.tight_layout()
        return fig


def _make_tyre(coeffs, fits, info, cost, stats, not_id, tyre_info) -> Pac89Tyre:
    design = {}
    extra_header = []
    if tyre_info is not None:
        if isinstance(tyre_info, Pac89Tyre):
            design = {k: getattr(tyre_info, k) for k in _DESIGN}
        else:
            design = {k: v for k, v in dict(tyre_info).items() if k in _DESIGN}
            extra_header = list(dict(tyre_info).get("header", []))
    design = {k: v for k, v in design.items() if v is not None}
    ranges = {}
    fz_lo = min(s["fz_range"][0] for s in stats.values())
    fz_hi = max(s["fz_range"][1] for s in stats.values())
    ranges["fz"] = (fz_lo, fz_hi)
    if "lateral" in fits or "aligning" in fits:
        d = (fits.get("lateral") or fits.get("aligning")).data
        ranges["slip_angle"] = (float(d.slip.min()), float(d.slip.max()))
        ranges["camber"] = (float(d.camber.min()), float(d.camber.max()))
    if "longitudinal" in fits:
        d = fits["longitudinal"].data
        ranges["slip_ratio"] = (float(d.slip.min()), float(d.slip.max()))
    src = info.get("source") or "a data frame"
    header = [f"PAC89 tyre fitted by tyrefit {__version__} (tyrefit.fitting.fit_pac89, cost "
              f"{'l1: Komana et al. Eq. 5' if cost == 'l1' else 'l2: least squares'} on mu = F/Fz)",
              f"source data: {src}" + (f" ({info['kind']})" if info.get("kind") else "")]
    for name, s in stats.items():
        lo, hi = s["fz_range"]
        header.append(f"{name}: {s['n']} points in {s['sweeps']} sweeps, Fz {lo:.0f}-{hi:.0f} N; "
                      f"RMSE {s['rmse']:.4g} {s['unit']}, R2 {s['r2']:.5f}, noise floor {s['noise_floor']:.3g} "
                      f"{s['unit']}")
    if not_id:
        header.append("not identifiable from the data (held at neutral values): " + ", ".join(sorted(
            not_id, key=lambda k: (k[0], int(k[1:])))))
    header += extra_header
    return Pac89Tyre(coefficients=Pac89Tyre.coefficients_from(coeffs), ranges=ranges, header=header,
                     **{k: v for k, v in design.items()})
