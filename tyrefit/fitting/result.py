"""The result of a PAC89 fit: the tyre, its coefficients with uncertainties, and how well it fits.

:class:`FitResult` is returned by :func:`tyrefit.fitting.fit_pac89`.  Like
lmfit's ``ModelResult`` it carries its own text and HTML reports and a
``plot(ax=None)`` of the fit over the data.

This module holds the class, its statistics and warnings, and the
:class:`~tyrefit.tyres.pac89.Pac89Tyre` it builds (coefficients, fitted
ranges, design data and the ``.tir`` header).  The figures are
:mod:`tyrefit.fitting.result_figures` and the HTML report
:mod:`tyrefit.fitting.result_report`; the methods that draw or report
delegate to them, and ``unfitted_figures``, ``describe_constant_text`` and
``NOISE_FLOOR_DEFINITION`` stay importable from here.

Statistics (per part: lateral Fy, longitudinal Fx, aligning Mz)
---------------------------------------------------------------
* residual = model - data at each measured point, in N (N*m for Mz);
* per sweep: RMSE and bias (mean residual) in N and in % of the sweep's
  peak |F| measured;
* R^2 = 1 - SS_res / SS_tot over all points of the part;
* noise floor (``noise_floor``): the *within-sweep noise floor* of
  :func:`tyrefit.fitting.noise.noise_floor` -- the pooled RMSE of a smooth
  curve (cubic spline, knots every 1.5 deg of slip angle or 0.03 of slip
  ratio, with a load-jitter term) through each sweep on its own.  ``fit``,
  ``diagnose`` and ``compare`` report this one definition under this name.
  The engine's neighbour-difference estimate
  (:func:`tyrefit.fitting.engine.point_scatter`, which also counts the
  hysteresis between up and down branches) is kept as ``point_scatter``;
* fit-quality warnings (:attr:`FitResult.warnings`): a fitted coefficient at
  one of its bounds (its standard error then means nothing), an RMSE above
  1.5 x the noise floor (the model misses structure; 1.5 is the diagnose end
  check's threshold), and condition levels the model cannot carry (PAC89 has
  no pressure or speed input) merged into one tyre;
* the fitted cost in mu (``objective``): sum over sweeps of the mean squared
  (l2) or mean absolute (l1, Komana et al. Eq. 5) mu residual, and the plain
  Eq. 5 sum sum|mu_model - mu_data| over all points.
"""

from __future__ import annotations

import copy
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from .._version import __version__
from ..tyres.pac89 import Pac89Tyre
from .noise import MAX_POINTS_PER_SWEEP, noise_floor as _nf
from .core import Parameters
from . import result_figures, result_report
from .result_base import TyreFitResult
from .result_figures import _LABEL, _RAD_TO_DEG, describe_constant_text, unfitted_figures  # noqa: F401 (re-exported)
from .result_report import _COST_TEXT, NOISE_FLOOR_DEFINITION
from ..io.facets import channel_levels, format_levels, sweep_conditions

__all__ = ["FitResult", "noise_floor_of", "NOISE_FLOOR_DEFINITION"]

#: RMSE / noise floor above which a fit is flagged (the diagnose end check's threshold)
FLOOR_RATIO_WARN = 1.5
#: knot spacing of the within-sweep noise floor per part [deg of slip angle; slip ratio]
_FLOOR_SPACING = {"lateral": 1.5, "aligning": 1.5, "longitudinal": 0.03 * _RAD_TO_DEG}
_PART_COEFS = {"lateral": "a0-a13", "longitudinal": "b0-b10", "aligning": "c0-c17"}
_PART_NEEDS = {"lateral": "slip-angle sweeps with fy", "longitudinal": "slip-ratio sweeps with fx",
               "aligning": "slip-angle sweeps with mz"}
_DESIGN = ("unloaded_radius", "width", "fnomin", "lateral_stiffness", "vertical_stiffness", "rolling_resistance",
           "name", "tyreside", "vertical_curve")


@dataclass
class FitResult(TyreFitResult):
    """A fitted PAC89 tyre and the statistics of the fit (the PAC89 :class:`TyreFitResult`).

    Attributes
    ----------
    tyre : Pac89Tyre
        coefficients, fitted ranges (``fz``, ``slip_angle``, ``camber``,
        ``slip_ratio``), design data, and a header recording the source data
        and fit statistics.
    params : tyrefit.fitting.core.Parameters
        every coefficient of the fitted parts: value, ``vary``, bounds (where
        a coefficient is bounded directly) and ``stderr``, in lmfit's names;
        :meth:`lmfit_params` gives them as :class:`lmfit.Parameters` with ``correl``.
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
        'l2', 'l1', 'soft_l1' or 'huber'.
    warnings : list of str
        what must not be missed: samples left out as lift-off or spikes, an RMSE
        far above the noise floor, degenerate sweeps (one line each; also in
        the ``.tir`` header and the Chrono JSON's ``warnings``).
    screening : dict of str -> dict
        per part, what :func:`tyrefit.fitting.engine.screen_sweeps` left out
        (counts ``low_load``, ``load_spikes``, ``force_spikes``; ``runs``; ``index``).
    at_bound : dict of str -> list of str
        per part, the fitted parameters that ended at a bound (constraint active).
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
    warnings: list = field(default_factory=list)
    merged: dict = field(default_factory=dict)
    model_label: str = "PAC89"
    screening: dict = field(default_factory=dict)
    at_bound: dict = field(default_factory=dict)
    _parts: dict = field(default_factory=dict, repr=False)

    # ------------------------------------------------------------------ construction
    def with_tyre(self, tyre: Pac89Tyre) -> "FitResult":
        """This result with another tyre (the same fit's tyre with design data added, renamed, ...).

        A shallow copy: the statistics are shared, the notes and warnings lists are the copy's own,
        and neither result's tyre is changed.
        """
        out = copy.copy(self)
        out.tyre, out.notes, out.warnings = tyre, list(self.notes), list(self.warnings)
        return out

    @classmethod
    def from_parts(cls, fits: dict, *, info: dict, cost: str, notes: list, tyre_info=None, fixed=None,
                   initial=None, seconds: float = 0.0, bounds=None) -> "FitResult":
        coeffs: dict[str, float] = {}
        for pf in fits.values():
            coeffs.update(pf.coefficients)
        rows, sweep_rows, stats, not_id, correl, est, init = [], [], {}, {}, {}, {}, {}
        params = Parameters()  # tyrefit's container; lmfit's on request (lmfit_params), so the CLI never imports it
        constraints = []
        for name, pf in fits.items():
            d = pf.data
            col, sym, unit, slip, _, _ = _LABEL[name]
            model = pf.data.part.model(pf.coefficients, d.fz, d.slip, d.camber)
            res = model - d.y
            ss_res = float(np.sum(res**2))
            ss_tot = float(np.sum((d.y - d.y.mean()) ** 2))
            mu_res = (model - d.y) / d.fz
            floor, floor_runs = within_sweep_noise(d, name)
            stats[name] = {
                "n": int(d.n), "sweeps": int(len(set(d.run.tolist()))), "rmse": math.sqrt(ss_res / d.n),
                "r2": 1.0 - ss_res / ss_tot if ss_tot > 0 else float("nan"), "noise_floor": floor,
                "point_scatter": pf.point_scatter,
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
                for c in ("pressure", "speed"):
                    if c in g and g[c].notna().any():
                        row[c] = float(g[c].mean())
                if name == "longitudinal" and "slip_angle" in g:
                    row["slip_angle"] = float(g["slip_angle"].mean()) * _RAD_TO_DEG
                rmse, bias = float(np.sqrt(np.mean(r**2))), float(np.mean(r))
                row.update({"peak": peak, "rmse": rmse, "bias": bias,
                            "rmse_pct": 100 * rmse / peak if peak > 0 else float("nan"),
                            "bias_pct": 100 * bias / peak if peak > 0 else float("nan"),
                            "noise": float(floor_runs.get(run, float("nan")))})
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
                lo, hi = pf.bounds.get(k, (-np.inf, np.inf))
                at = _at_bound(v, lo, hi) if varied else None
                if at:
                    status = f"at its {at} bound {lo if at == 'lower' else hi:.4g}: not a free fit (stderr meaningless)"
                elif varied:
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
                if k in (bounds or {}):  # bounds the caller gave: shown as given (intersected), even when reached
                    lo, hi = (lo, hi) if varied else bounds[k]
                    if not varied and not lo <= v <= hi:
                        notes.append(f"{name}: {k} = {v:g} is held (not fitted), outside the bounds given [{lo:g}, "
                                     f"{hi:g}]")
                        lo, hi = -np.inf, np.inf
                    params.add(k, value=v, vary=varied, min=lo, max=hi)
                else:
                    params.add(k, value=v, vary=varied, min=lo if lo < v else -np.inf, max=hi if hi > v else np.inf)
                params[k].stderr = se if varied else None
        coef_df = pd.DataFrame(rows)
        merged = _merged_levels(fits)
        # the engine's warnings (samples left out, degenerate sweeps) first, then the fit-quality ones
        warns = list(dict.fromkeys([w for pf in fits.values() for w in getattr(pf, "warnings", [])]
                                   + _fit_warnings(coef_df, stats, merged)))
        tyre = _make_tyre(coeffs, fits, info, cost, stats, not_id, tyre_info, warns)
        return cls(tyre=tyre, params=params, coefficients=coef_df, correlations=correl,
                   sweeps=pd.DataFrame(sweep_rows), stats=stats, not_identifiable=not_id, estimates=est,
                   initial=init, notes=list(dict.fromkeys(notes)), cost=cost, source=info.get("source", ""),
                   seconds=seconds, constraints=constraints, warnings=warns, merged=merged,
                   screening={k: dict(pf.data.screening) for k, pf in fits.items()},
                   at_bound={k: list(getattr(pf, "at_bound", [])) for k, pf in fits.items()}, _parts=fits)

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

    def to_frame(self) -> pd.DataFrame:
        """Every fitted point with its part, conditions, the measurement ``y``, ``model`` and ``residual``."""
        return self.data

    def contract(self) -> list:
        """What the tyre breaks of PAC89's physical checks over its declared ranges (:meth:`Pac89Tyre.check`:
        C > 0, D > 0, BCD > 0, E <= 1, bounded friction, finite forces); empty when it keeps them."""
        return list(self.tyre.check())

    def write_tir(self, path, *, force: bool = False) -> Path:
        """Write the Adams PAC89 ``.tir`` (the file ``tyrefit fit`` writes) after :meth:`require_valid`."""
        self.require_valid()
        return self.tyre.to_tir(path, force=force)

    def lmfit_params(self):
        """The coefficients of the fitted parts as :class:`lmfit.Parameters` (value, bounds, vary, stderr, and the
        correlations of the varied ones, as lmfit's ``correl``)."""
        out = self.params.to_lmfit()
        for cm in self.correlations.values():
            if isinstance(cm, pd.DataFrame) and not cm.empty:
                names = list(cm.index)
                for a, k in enumerate(names):
                    out[k].correl = {j: float(cm.iat[a, b]) for b, j in enumerate(names) if j != k}
        return out

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

    # ------------------------------------------------------------------ what the model is
    def model_lines(self) -> list[str]:
        """What the fitted model holds, in words: parts fitted or not, camber terms, conditions merged."""
        L = [f"model: {self.model_label} (Pacejka '89: Bakker, Nyborg, Pacejka 1989), evaluated with Fz, slip and "
             "camber only"]
        fitted = set(self.coefficients.loc[self.coefficients["varied"], "name"])
        for part in ("lateral", "longitudinal", "aligning"):
            sym = _LABEL[part][1]
            if part not in self._parts:
                L.append(f"{part} {sym} ({_PART_COEFS[part]}): NOT FITTED - the data hold no {_PART_NEEDS[part]}; "
                         "the file carries placeholder values for it, not a model of this tyre")
                continue
            names = [k for k in self._parts[part].data.part.names if k in fitted]
            cam = [k for k in _CAMBER_TERMS[part] if k in fitted]
            txt = f"{part} {sym} ({_PART_COEFS[part]}): {len(names)} fitted ({', '.join(names)})"
            if _CAMBER_TERMS[part]:
                txt += ("; camber terms " + ", ".join(cam) + " fitted" if cam else
                        "; camber terms not in the model (held at 0)")
            L.append(txt)
        for c, lv in self.merged.items():
            L.append(_merged_text(c, lv))
        return L

    def figure_title(self, part: str) -> str:
        """One-line title of a figure of ``part``: model, what it carries, how the lines are evaluated."""
        sym = _LABEL[part][1]
        fitted = set(self.coefficients.loc[self.coefficients["varied"], "name"])
        cam = [k for k in _CAMBER_TERMS[part] if k in fitted]
        carried = "camber terms " + ", ".join(cam) if cam else ("no camber terms" if _CAMBER_TERMS[part] else
                                                                 "no camber input")
        t = f"{self.model_label} {part} {sym} ({carried}); lines: model at each sweep's mean Fz" + \
            (" and camber" if cam else "")
        notin = [c for c in self.merged]
        if notin:
            t += "; " + " and ".join(notin) + " not in the model (one curve for every level)"
        return t

    # ------------------------------------------------------------------ reports
    def summary(self) -> str:
        """Plain-text report: statistics, coefficients, not-identifiable terms, warnings, notes."""
        L = [f"PAC89 fit ({_COST_TEXT.get(self.cost, self.cost)}) of {self.source or 'data'} in {self.seconds:.2f} s"]
        for name, s in self.stats.items():
            lo, hi = s["fz_range"]
            L.append(f"  {name:<12} {s['n']} points, {s['sweeps']} sweeps, Fz {lo:.0f}-{hi:.0f} N: "
                     f"RMSE {s['rmse']:.4g} {s['unit']}, R² {s['r2']:.5f}, noise floor {s['noise_floor']:.3g} "
                     f"{s['unit']}, {s['varied']} coefficients fitted")
        L += ["  " + m for m in self.model_lines()[1:]]
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
        for w in self.warnings:
            L.append(f"  WARNING: {w}")
        for n in self.notes:
            L.append(f"  note: {n}")
        return "\n".join(L)

    def __str__(self) -> str:  # pragma: no cover - convenience
        return self.summary()

    def to_dict(self) -> dict:
        """Statistics, warnings and model description as plain JSON-able values."""
        stats = {p: {k: (list(v) if isinstance(v, tuple) else v) for k, v in s.items() if k != "facts"}
                 for p, s in self.stats.items()}
        return {"source": self.source, "model": self.model_label, "parts": self.parts, "stats": stats,
                "noise_floor_definition": NOISE_FLOOR_DEFINITION, "warnings": list(self.warnings),
                "merged": {c: [float(x) for x in lv] for c, lv in self.merged.items()},
                "model_description": self.model_lines(), "notes": list(self.notes),
                "coefficients": {r.name: r.value for r in self.coefficients.itertuples()}}

    def _stats_rows(self) -> list[dict]:
        return result_report.stats_rows(self)

    def _coef_rows(self) -> pd.DataFrame:
        return result_report.coef_rows(self)

    def sweeps_table(self) -> pd.DataFrame:
        """The per-sweep table in display units with unit headers (kN, deg, kPa, km/h)
        (:func:`tyrefit.fitting.result_report.sweeps_table`)."""
        return result_report.sweeps_table(self)

    def to_html(self) -> str:
        """HTML fragment: statistics, coefficient table, not-identifiable list, notes
        (:func:`tyrefit.fitting.result_report.to_html`)."""
        return result_report.to_html(self)

    def _repr_html_(self) -> str:
        return self.to_html()

    def _report_blocks(self, r, figures: bool = True) -> None:
        """Append the fit to the :class:`~tyrefit.io.report.Report` ``r``
        (:func:`tyrefit.fitting.result_report.report_blocks`)."""
        result_report.report_blocks(self, r, figures=figures)

    def report(self, directory: str | os.PathLike, force: bool = False, title: str | None = None) -> Path:
        """Write ``directory/index.html`` (figures embedded) and ``sweeps.csv``; returns the HTML path
        (:func:`tyrefit.fitting.result_report.write_report`)."""
        return result_report.write_report(self, directory, force=force, title=title)

    # ------------------------------------------------------------------ plots
    def facets(self, part: str | None = None):
        """Panels of ``part``: one per combination of condition levels in its data (see :mod:`tyrefit.io.facets`).

        Returns ``(facets, info)`` of :func:`tyrefit.io.facets.facet_sweeps`.
        """
        return result_figures.part_facets(self, part)

    def _draw_panel(self, ax, part: str, facet, fz_range=None, legend: bool = True):
        return result_figures.draw_panel(self, ax, part, facet, fz_range=fz_range, legend=legend)

    def plot(self, ax=None, part: str | None = None, camber: float | None = None, pressure: float | None = None):
        """Fit (lines) over data (dots), loads as lines; returns the Axes.

        ``ax`` None: a pyplot figure with one panel per condition level (an array of Axes when several);
        an Axes: the panel of one condition level, chosen by ``camber`` and ``pressure``
        (:func:`tyrefit.fitting.result_figures.plot_fit`).

        Parameters
        ----------
        part : {'lateral', 'longitudinal', 'aligning'}, optional
            default: the first fitted part.
        camber : float, optional
            the panel at the camber level nearest this [rad]; default: nearest zero.
        pressure : float, optional
            the panel at the pressure level nearest this [Pa]; default: the first level.
        """
        return result_figures.plot_fit(self, ax, part=part, camber=camber, pressure=pressure)

    def plot_residuals(self, ax=None, part: str | None = None):
        """Residuals (model - data) vs slip, coloured by load; returns the Axes
        (:func:`tyrefit.fitting.result_figures.plot_residuals`)."""
        return result_figures.plot_residuals(self, ax, part=part)

    def facet_figures(self, part: str, max_rows: int = 4) -> list:
        """One figure per page of panels showing every sweep of ``part`` (see :meth:`facets`).

        Each figure's title names the model, what it carries and the
        conditions common to every panel; each panel's title gives its
        condition levels in display units.  Returns a list of
        :class:`matplotlib.figure.Figure` (:func:`tyrefit.fitting.result_figures.facet_figures`).
        """
        return result_figures.facet_figures(self, part, max_rows=max_rows)

    def _facet_figure(self, part: str):
        """The first page of :meth:`facet_figures` (kept for callers of the old name)."""
        return self.facet_figures(part)[0]

    def _residual_figure(self, part: str):
        return result_figures.residual_figure(self, part)


#: PAC89 coefficients that carry camber, per part
_CAMBER_TERMS = {"lateral": ("a5", "a8", "a11"), "longitudinal": (),
                 "aligning": ("c6", "c10", "c11", "c14", "c15")}
#: condition channels PAC89 has no input for
_NOT_IN_PAC89 = ("pressure", "speed")


def within_sweep_noise(d, part: str) -> tuple[float, pd.Series]:
    """Within-sweep noise floor [N or N*m] of one part's data and its per-sweep values.

    :func:`tyrefit.fitting.noise.noise_floor` on the part's sweeps (slip,
    force or moment, measured load), so ``fit`` and ``diagnose`` report the
    same number for the same sweeps.
    """
    return noise_floor_of(d.slip, d.y, d.run, d.fz, part)


def noise_floor_of(slip, y, run, fz, part: str = "lateral") -> tuple[float, pd.Series]:
    """The fit's parametrisation of :func:`tyrefit.fitting.noise.noise_floor` [N or N*m].

    The one within-sweep noise floor of ``fit``, ``diagnose`` and ``compare`` with the fit's
    parameters: the knot spacing of ``part``, each sweep thinned to at most
    :data:`~tyrefit.fitting.noise.MAX_POINTS_PER_SWEEP` points as diagnose thins it
    (:func:`tyrefit.diagnose.data.prepare`), any sweep labels, and per-sweep values by label.

    Parameters
    ----------
    slip : array_like
        slip angle [rad] (``lateral``, ``aligning``) or slip ratio [-] (``longitudinal``).
    y : array_like
        force [N] or moment [N*m].
    run : array_like
        sweep id of each point.
    fz : array_like
        measured load [N].
    part : str
        sets the spline's knot spacing (1.5 deg of slip angle, 0.03 slip ratio).

    Returns
    -------
    (float, Series)
        pooled floor and per-sweep values (index: run).
    """
    uniq, idx = np.unique(np.asarray(run), return_inverse=True)
    floor, per = _nf(slip, y, idx, spacing_deg=_FLOOR_SPACING[part], fz=np.asarray(fz, float),
                     max_points_per_sweep=MAX_POINTS_PER_SWEEP)
    return float(floor), pd.Series(per, index=uniq, dtype=float)


def _at_bound(v: float, lo: float, hi: float) -> str | None:
    """'lower' / 'upper' when ``v`` sits on a finite bound (relative 1e-6), else None."""
    for side, b in (("lower", lo), ("upper", hi)):
        if np.isfinite(b) and abs(v - b) <= 1e-6 * max(1.0, abs(b)):
            return side
    return None


def _merged_levels(fits: dict) -> dict:
    """Channels PAC89 cannot carry (pressure, speed) with more than one level in the fitted data -> levels [SI]."""
    frames = []
    for pf in fits.values():
        sc = sweep_conditions(pf.data.df, _NOT_IN_PAC89)
        frames.append(sc)
    out = {}
    for c in _NOT_IN_PAC89:
        arrs = [f[c].to_numpy(float) for f in frames if c in f]
        vals = np.concatenate(arrs) if arrs else np.array([])
        vals = vals[np.isfinite(vals)]
        if vals.size:
            lv, _ = channel_levels(vals, c)
            if len(lv) > 1:
                out[c] = lv
    return out


def _merged_text(channel: str, levels) -> str:
    return (f"{channel}: not in the model (PAC89 has no {channel} input): {len(levels)} levels "
            f"({format_levels(channel, levels)}) "
            f"merged into one tyre; `tyrefit fit --by {channel}` writes one tyre per level")


def _fit_warnings(coefs: pd.DataFrame, stats: dict, merged: dict) -> list[str]:
    """Coefficients at a bound, RMSE above FLOOR_RATIO_WARN x the noise floor, merged condition levels."""
    out = []
    for r in coefs.itertuples():
        if r.status.startswith("at its"):
            out.append(f"{r.part}: {r.name} = {r.value:.4g} is {r.status.split(':')[0][3:]}; the fit is "
                       "constrained there, its standard error means nothing and the shape it sets may be wrong")
    for part, s in stats.items():
        nf = s["noise_floor"]
        if np.isfinite(nf) and nf > 0 and s["rmse"] > FLOOR_RATIO_WARN * nf:
            out.append(f"{part}: RMSE {s['rmse']:.4g} {s['unit']} is {s['rmse'] / nf:.1f} x the within-sweep noise "
                       f"floor {nf:.4g} {s['unit']}: the model does not reach the noise (structure left in the "
                       "residuals; see the panels)")
    for c, lv in merged.items():
        out.append(_merged_text(c, lv))
    return out


def _make_tyre(coeffs, fits, info, cost, stats, not_id, tyre_info, warns=()) -> Pac89Tyre:
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
    if os.path.isfile(src):  # the same file named the same way, however the command or the batch was given it
        src = os.path.abspath(src)
    header = [f"PAC89 tyre fitted by tyrefit {__version__} (tyrefit.fitting.fit_pac89, cost "
              f"{ {'l1': 'l1: Komana et al. Eq. 5', 'l2': 'l2: least squares'}.get(cost, cost)} on mu = F/Fz)",
              f"source data: {src}" + (f" ({info['kind']})" if info.get("kind") else "")]
    for name, s in stats.items():
        lo, hi = s["fz_range"]
        header.append(f"{name}: {s['n']} points in {s['sweeps']} sweeps, Fz {lo:.0f}-{hi:.0f} N; "
                      f"RMSE {s['rmse']:.4g} {s['unit']}, R2 {s['r2']:.5f}, noise floor {s['noise_floor']:.3g} "
                      f"{s['unit']}")
    for part in ("lateral", "longitudinal", "aligning"):
        if part not in fits:
            header.append(f"{part} ({_PART_COEFS[part]}): NOT FITTED - the data hold no {_PART_NEEDS[part]}; "
                          "its coefficients are placeholders, not a model of this tyre")
    if not_id:
        header.append("not identifiable from the data (held at neutral values): " + ", ".join(sorted(
            not_id, key=lambda k: (k[0], int(k[1:])))))
    header += [f"WARNING: {w}" for w in warns]
    header += extra_header
    return Pac89Tyre(coefficients=Pac89Tyre.coefficients_from(coeffs), ranges=ranges, header=header,
                     **{k: v for k, v in design.items()})
