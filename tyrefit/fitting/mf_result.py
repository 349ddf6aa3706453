"""The result of a Magic Formula fit: the parameter set, what was fitted, and how well.

:class:`FitResultMF` is returned by :func:`tyrefit.fitting.mf.fit_mf`.  It
holds the complete MF parameter set (neutral where not fitted), the stage
results, the per-channel statistics over every measured point (the model is
evaluated at each point's measured load, slips, camber, pressure and speed),
the error per condition cell, and writes the ``FITTYP = 61`` file
(:func:`tyrefit.io.mf_tir.write_mf_tir`) and a self-contained HTML report
(:class:`tyrefit.io.report.Report`).

Statistics
----------
* RMSE per channel [N or N*m] over every point where the channel is measured;
  R^2 = 1 - SS_res/SS_tot;
* noise floor per channel: the one definition of ``fit`` (PAC89), ``diagnose``
  and ``compare`` (:func:`tyrefit.fitting.noise.noise_floor` with the fit's
  parameters, :func:`tyrefit.fitting.result.noise_floor_of`: a smooth spline
  through each sweep, pooled), slip-angle and slip-ratio sweeps pooled by points;
* condition cells: sweeps grouped by kind, load level, pressure, camber and
  slip angle (combined); RMSE per cell in % of the cell's peak |F|.

Figures (matplotlib object API, ``ax=None`` -> a new Figure, the Axes returned)
------------------------------------------------------------------------------
``plot_curves`` (Fx vs kappa, Fy vs alpha, Mz vs alpha, Fy vs kappa at each
alpha, model over data at each load), ``plot_cells`` (error per cell),
``plot_friction_ellipse`` (Fx against Fy of the combined sweeps, model and
data, with the Kamm circle mu Fz of the fitted friction).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from .._version import __version__
from ..models import mf61
from . import mf_figures
from .mf_figures import condition_cells, nominal_slice
from .mf_stages import STAGES
from .result import FLOOR_RATIO_WARN, noise_floor_of
from .result_base import TyreFitResult
from ..errors import FitError
from ..io.mf_tir import format_mf_tir, write_mf_tir
from ..io.outputs import write_text
from ..io.report import Report
from ..tyres.contract import violations
from ..tyres.mf import MFTyre

__all__ = ["FitResultMF"]

_DEG = math.pi / 180.0
_UNIT = {"fx": "N", "fy": "N", "mz": "N·m", "mx": "N·m", "my": "N·m"}
_SLIP = {"longitudinal": "slip_ratio", "lateral": "slip_angle", "combined": "slip_ratio"}


def _noise_floor(df: pd.DataFrame, channel: str) -> float:
    """The noise floor of ``fit``, ``diagnose`` and ``compare`` of one channel over sweeps of several kinds.

    One definition for every model, so a PAC89 and an MF fit of one file report the same floor:
    :func:`tyrefit.fitting.noise.noise_floor` with the fit's parameters
    (:func:`tyrefit.fitting.result.noise_floor_of`: 1.5 deg knots along slip angle, 0.03 along slip
    ratio), on each kind of sweep (slip-angle sweeps; slip-ratio sweeps, pure or combined) apart,
    since the kinds need different knot spacings; the kinds' floors are pooled by points.
    """
    tot, npts = 0.0, 0
    for kind, g in df.groupby("kind", sort=True):
        slip = _SLIP[kind]
        y = g[channel].to_numpy(float)
        x = g[slip].to_numpy(float)
        ok = np.isfinite(x) & np.isfinite(y)
        if ok.sum() < 10:
            continue
        part = "longitudinal" if slip == "slip_ratio" else ("aligning" if channel == "mz" else "lateral")
        floor, _ = noise_floor_of(x[ok], y[ok], g["run"].to_numpy()[ok], g["fz"].to_numpy(float)[ok], part)
        if np.isfinite(floor):
            tot += ok.sum() * floor**2
            npts += int(ok.sum())
    return float(np.sqrt(tot / npts)) if npts else float("nan")


def _by_record(df: pd.DataFrame, channel: str) -> dict[str, dict]:
    """RMSE, noise floor (:func:`_noise_floor`) and points of ``channel`` per record (``source``)."""
    out = {}
    for src, g in df.groupby("source", sort=False):
        m, y = g[f"model_{channel}"].to_numpy(float), g[channel].to_numpy(float)
        ok = np.isfinite(m) & np.isfinite(y)
        if ok.sum() < 10:
            continue
        out[os.path.basename(str(src))] = {"rmse": float(np.sqrt(np.mean((m[ok] - y[ok]) ** 2))),
                                           "noise_floor": _noise_floor(g[ok], channel), "n": int(ok.sum())}
    return out


@dataclass
class FitResultMF(TyreFitResult):
    """A fitted Magic Formula tyre and the statistics of the fit (the MF 5.2 / 6.1 :class:`TyreFitResult`).

    Attributes
    ----------
    params : dict
        the complete parameter set (.tir keys, upper case, SI).
    model : str
        ``'mf61'`` or ``'mf52'``.
    stages : dict of str -> StageFit
        per stage: varied and held coefficients (with reasons), start values,
        objective, evaluations, seconds, constraint checks.
    data : MFData
        the prepared points with ``model_<channel>`` columns added.
    stats : dict of channel -> dict
        ``rmse``, ``r2``, ``noise_floor``, ``n``, ``unit``, ``peak``.
    cells : DataFrame
        RMSE per condition cell and channel.
    not_identifiable : dict
        coefficient -> reason it was held.
    fitted : list of str
    notes : list of str
    warnings : list of str
        fit-quality warnings, as PAC89's (:func:`tyrefit.fitting.result._fit_warnings`): a fitted
        coefficient at a bound in the final set, a fitted channel's RMSE above FLOOR_RATIO_WARN x its
        noise floor; written into the .tir header as ``WARNING:`` lines, printed by ``fit``.
    """

    params: dict
    model: str
    version: str
    cost: str
    stages: dict
    data: object
    stats: dict
    cells: pd.DataFrame
    not_identifiable: dict
    fitted: list
    notes: list = field(default_factory=list)
    tyre_info: dict = field(default_factory=dict)
    seconds: float = 0.0
    effects: list = field(default_factory=list)
    warnings: list = field(default_factory=list)

    # ------------------------------------------------------------------ building
    @classmethod
    def build(cls, p, fits, data, *, model, version, cost, notes, tyre_info, seconds, effects=None, warnings=()):
        mf = mf61
        df = data.df
        kw = {"version": version} if version != "6.1" else {}
        pr = df["pressure"].to_numpy(float)
        sp = df["speed"].to_numpy(float)
        # pure-slip sweeps are evaluated as pure slip, as they are fitted: a cornering sweep at kappa = 0 (the
        # rig's slip-ratio noise, +-0.002 on TTC records, times K_x would otherwise be the "model" Fx), a
        # drive/brake sweep at alpha = 0
        kind = df["kind"].to_numpy()
        kap = np.where(kind == "lateral", 0.0, df["slip_ratio"].to_numpy(float))
        alp = np.where(kind == "longitudinal", 0.0, df["slip_angle"].to_numpy(float))
        out = mf.forces(p, df["fz"].to_numpy(float), slip_ratio=kap, slip_angle=alp, camber=df["camber"].to_numpy(float),
                        pressure=np.where(np.isfinite(pr), pr, p.get("NOMPRES")) if np.isfinite(pr).any() else None,
                        speed=np.where(np.isfinite(sp), sp, p.get("LONGVL")) if np.isfinite(sp).any() else None, **kw)
        stats = {}
        for c in ("fx", "fy", "mz", "mx", "my"):
            m = np.asarray(out.get(c, np.full(len(df), np.nan)), float)
            df[f"model_{c}"] = m
            y = df[c].to_numpy(float)
            ok = np.isfinite(y) & np.isfinite(m)
            if ok.sum() < 10:
                continue
            # only channels the fit was asked to carry: a channel with no fitted stage is reported, not hidden
            res = m[ok] - y[ok]
            sst = float(np.sum((y[ok] - y[ok].mean()) ** 2))
            stats[c] = {"rmse": float(np.sqrt(np.mean(res**2))), "r2": 1.0 - float(np.sum(res**2)) / sst if sst > 0
                        else float("nan"), "noise_floor": data.floors[c] if c in getattr(data, "floors", {})
                        else _noise_floor(df[np.isfinite(df[c])], c), "n": int(ok.sum()),
                        "unit": _UNIT[c], "peak": float(np.max(np.abs(y[ok]))),
                        "fitted": any(f.channel == c and f.varied for f in fits.values())}
            if df["source"].nunique() > 1:  # each record judged against its own noise (rigs differ per channel)
                # Fx on the sweeps it is fitted to (a cornering sweep's Fx is not the Fx model's: kappa = 0)
                on = np.isfinite(df[c]) & ((df["kind"] != "lateral") if c == "fx" else True)
                stats[c]["by_record"] = _by_record(df[on], c)
        held: dict[str, str] = {}
        fitted: list[str] = []
        for f in fits.values():
            fitted += [k for k in f.varied if k not in fitted]
            for k, why in f.held.items():
                held.setdefault(k, why)
        # a coefficient two stages share (LMUV: Fx0 and Fy0) is fitted when one of them fitted it
        held = {k: why for k, why in held.items() if k not in fitted}
        cells = _cells(df)
        warns = list(warnings)
        for c, s in stats.items():
            for src, rs in (s.get("by_record") or {"": s}).items():
                nf = rs["noise_floor"]
                if s["fitted"] and np.isfinite(nf) and nf > 0 and rs["rmse"] > FLOOR_RATIO_WARN * nf:
                    on = f" on {src}" if src else ""
                    warns.append(f"{c.upper()}{on}: RMSE {rs['rmse']:.4g} {s['unit']} is {rs['rmse'] / nf:.1f} x "
                                 f"the noise floor {nf:.3g} {s['unit']}{' of that record' if src else ''}: the model "
                                 "does not reach the noise (structure left in the residuals; see the error per "
                                 "condition cell)")
        return cls(params=dict(p), model=model, version=version, cost=cost, stages=fits, data=data, stats=stats,
                   cells=cells, not_identifiable=held, fitted=fitted, notes=list(dict.fromkeys(notes)),
                   tyre_info=dict(tyre_info), seconds=float(seconds), effects=list(effects or []), warnings=warns)

    # ------------------------------------------------------------------ numbers
    @property
    def rmse(self) -> float:
        """Lateral-force RMSE [N] (the diagnose figure); Fx when no Fy is measured."""
        s = self.stats.get("fy") or self.stats.get("fx")
        return float(s["rmse"]) if s else float("nan")

    def ranges(self) -> dict[str, tuple[float, float]]:
        """Fitted operating ranges (SI): fz, slip_ratio, slip_angle, camber, pressure (:meth:`MFData.envelope`)."""
        return self.data.envelope()

    def header(self) -> list[str]:
        lines = [f"tyrefit {__version__}: Magic Formula {self.version} fit ({self.cost} cost on mu, staged "
                 f"{' -> '.join(self.stages)})"]
        for s in self.data.sources:
            lines.append(f"data: {os.path.basename(str(s))}")
        for c, s in self.stats.items():
            u = s['unit'].replace('·', '*')
            lines.append(f"RMSE {c.upper()} {s['rmse']:.4g} {u} (R2 {s['r2']:.4f}, noise "
                         f"floor {s['noise_floor']:.3g}){'' if s['fitted'] else ' - not fitted'}")
            for src, rs in (s.get("by_record") or {}).items():
                lines.append(f"  {c.upper()} on {src}: RMSE {rs['rmse']:.4g} {u}, noise floor {rs['noise_floor']:.3g} "
                             f"{u} ({rs['n']} points)")
        for k, why in self.not_identifiable.items():  # the holds a reader should know of, with their reason
            if why.startswith(("not identified", "held at 0", "no sweep reaches")) or " not fitted: " in why:
                lines.append(f"HELD {k} = {self.params.get(k, float('nan')):.6g}: {why}")
        if self.effects:
            lines.append("Fy0 effects: " + ", ".join(self.effects))
        lines += self._speed_lines()
        lines += [f"WARNING: {w}" for w in self.warnings]
        lines += [str(x) for x in (self.tyre_info or {}).get("header", ())]  # design data: origin of each value
        return lines

    def _speed_lines(self) -> list[str]:
        """Header lines on LMUV (friction decay with slip speed) when the fit set it."""
        if "LMUV" not in self.fitted:
            return []
        stages = [n for n, f in self.stages.items() if "LMUV" in f.varied]
        speeds = sorted({round(v, 2) for n in stages if n in ("Fx0", "Fy0")
                         for v in self.stages[n].facts.get("levels", {}).get("speed", [])})
        sp = ", ".join(f"{v:g}" for v in speeds)
        return [f"LMUV = {self.params['LMUV']:.4g} fitted (friction decay with slip speed, Pacejka 4.E7: "
                f"mu / (1 + LMUV Vs/LONGVL), LONGVL = {self.params.get('LONGVL', float('nan')):g} m/s) from "
                f"{len(speeds)} speeds ({sp} m/s), stages {', '.join(stages)}",
                "LMUV note: MFeval 4.0 sets LMUV = 0 whatever the file says; there the friction is the one at "
                "zero slip speed"]

    def contract(self) -> list:
        """Rules of the physical-validity contract (:mod:`tyrefit.tyres.contract`) the tyre breaks.

        Checked over the envelope the file declares (:meth:`ranges`), for the channels the fit carries,
        with the peak-friction ceiling of the Fx0/Fy0 stages (1.15 x the data's peak |F|/Fz). Empty when
        the tyre keeps it.
        """
        chans = [c for c in ("fx", "fy", "mz") if self.stats.get(c, {}).get("fitted")]
        ceiling = {ax: self.stages[st].facts.get("mu_ceiling") for ax, st in (("x", "Fx0"), ("y", "Fy0"))
                   if st in self.stages and self.stages[st].varied}
        return violations(self.params, self.ranges(), version=self.version, mu_ceiling=ceiling, channels=chans)

    def write_tir(self, path, *, force: bool = False) -> Path:
        """Write the ``FITTYP = 61`` property file (every coefficient; neutral where not fitted).

        Raises :class:`~tyrefit.errors.FitError` and writes nothing when the tyre breaks the physical-validity
        contract (:meth:`contract`) or would be refused by tyrefit's own reader (:meth:`MFTyre.check`).
        """
        self.require_valid()

        not_fitted = [s.name.lower() for s in STAGES if s.name != "Mz*"
                      and (s.name not in self.stages or not self.stages[s.name].varied)]
        held = sorted(k for k in self.not_identifiable if k not in self.fitted
                      and any(k in self.stages[s].held for s in self.stages if self.stages[s].varied))
        if held:
            not_fitted.append("held at neutral values (not identifiable from these data): " + ", ".join(held))
        if self.version != "5.2":
            write_mf_tir(self.params, path, ranges=self.ranges(), header=tuple(self.header()),
                         not_fitted=tuple(not_fitted), force=force)
            return Path(path)
        # MF 5.2: the same layout, declared FITTYP = 6 (MF 5.2), with the 5.2-only PHY3; the 6.1-only keys
        # stay at their neutral values (held in the fit) so a 6.1 reader of the file gets the same tyre
        import re


        head = list(self.header()) + ["MF 5.2 coefficients (FITTYP = 6); the MF 6.1-only keys are neutral"]
        text = format_mf_tir(self.params, ranges=self.ranges(), header=head, not_fitted=tuple(not_fitted))
        text, n = re.subn(r"(?m)^(FITTYP\s*=\s*)61\b", lambda m: m.group(1) + "6", text)
        if n != 1:  # pragma: no cover - the writer's layout changed
            raise RuntimeError("MF 5.2 file: FITTYP line not found in the MF 6.1 layout")
        text = re.sub(r"(?m)^(PHY2\s*=.*)$", lambda m: m.group(1) + f"\nPHY3                     = "
                      f"{self.params.get('PHY3', 0.0):.10g}", text, count=1)
        write_text(path, text, force=force)
        return Path(path)

    # ------------------------------------------------------------------ the Python API (tyrefit.fit)
    @property
    def tyre(self):
        """The fitted tyre (:class:`tyrefit.tyres.mf.MFTyre`): ``forces``, ``to_tir`` (the file ``fit`` writes)."""
        t = MFTyre(params=dict(self.params), family="MF52" if self.version == "5.2" else "MF61",
                   version=self.version, ranges=self.ranges(), fnomin=self.params.get("FNOMIN"),
                   unloaded_radius=self.params.get("UNLOADED_RADIUS"), nominal_pressure=self.params.get("NOMPRES"),
                   name=str((self.tyre_info or {}).get("name") or "MF tyre"), header=list(self.header()))
        t._result = self  # to_tir writes through write_tir: the contract check, header and not-fitted lines
        return t

    def plot(self, ax=None):
        """Model over data, one panel per condition level, Fy against slip angle (Fx where no Fy was fitted).

        ``ax``: an Axes (the nominal condition), an array of Axes, a Figure, or None (a pyplot figure).
        Returns the Axes.  :func:`tyrefit.fitting.mf_figures.plot_curves` draws every channel and kind.
        """
        kind = "lateral" if "fy" in self.stats else "longitudinal"
        return self.plot_curves(kind, None, ax=ax)

    def to_frame(self) -> pd.DataFrame:
        """Every point with its sweep, conditions, measured channels and the model (``model_<channel>``)."""
        return self.data.df.copy()

    def to_html(self) -> str:
        """HTML fragment: statistics per channel and record, stages, coefficients, holds, notes (no figures)."""
        r = Report(f"Magic Formula {self.version} fit")
        r.h2("Fit quality per channel")
        r.table([{"channel": c.upper(), "RMSE": s["rmse"], "unit": s["unit"], "R²": s["r2"],
                  "noise floor": s["noise_floor"], "fitted": s["fitted"]} for c, s in self.stats.items()])
        if self.not_identifiable:
            r.h3("Held")
            r.table([{"name": k, "value": self.params.get(k, float("nan")), "reason": v}
                     for k, v in self.not_identifiable.items()])
        if self.warnings:
            r.bullets(self.warnings)
        return "\n".join(r.blocks)

    def _repr_html_(self) -> str:
        return self.to_html()

    def report(self, directory, force: bool = False, title: str | None = None) -> Path:
        """Write the self-contained HTML report (the one ``fit --report`` writes) and ``fit.json`` to ``directory``."""
        import json


        r = Report(title or f"Magic Formula {self.version} fit — {', '.join(map(os.path.basename, self.data.sources))}")
        self.report_blocks(r)
        d = Path(directory)
        out = r.save(d, force=force)
        write_text(d / "fit.json", json.dumps(self.to_dict(), indent=1, default=float), force=True)
        return out

    def to_dict(self) -> dict:
        """The fit as JSON-able data: model, per-channel statistics (and per record), the coefficients fitted
        and held (with the reason), the contract's verdict, warnings and notes."""
        return {"model": self.model, "version": self.version, "cost": self.cost, "seconds": self.seconds,
                "stats": self.stats, "fitted": {k: self.params[k] for k in self.fitted},
                "not_identified": {k: {"value": self.params.get(k), "reason": why}
                                   for k, why in self.not_identifiable.items()},
                "ranges": self.ranges(), "contract": [str(v) for v in self.contract()],
                "warnings": list(self.warnings), "notes": list(self.notes)}

    def lmfit_params(self):
        """The Magic Formula coefficients (P*, Q*, R*, S* and the L* scaling factors; not the design data) as
        :class:`lmfit.Parameters`: the fitted ones with ``vary=True`` and their standard errors from the stage
        that fitted them last, the others held (``vary=False``)."""
        import re

        import lmfit

        se = {}
        for st in self.stages.values():
            se.update({k: v for k, v in (st.stderr or {}).items() if k in st.varied})
        out = lmfit.Parameters()
        for k, v in self.params.items():
            coefficient = re.fullmatch(r"[PQRS][A-Z]{1,3}\d+|L(?!ONGVL)[A-Z]+", k)
            if not coefficient or not isinstance(v, (int, float)) or isinstance(v, bool):
                continue
            out.add(k, value=float(v), vary=k in self.fitted)
            if k in se and se[k] is not None and math.isfinite(se[k]):
                out[k].stderr = float(se[k])
        return out

    def require_valid(self) -> None:
        """Raise :class:`~tyrefit.errors.FitError` if the tyre breaks the contract or its reader's check."""
        problems = [str(v) for v in self.contract()]
        tyre = MFTyre(params=dict(self.params), family="MF52" if self.version == "5.2" else "MF61",
                      version=self.version, ranges=self.ranges(), fnomin=self.params.get("FNOMIN"),
                      unloaded_radius=self.params.get("UNLOADED_RADIUS"),
                      nominal_pressure=self.params.get("NOMPRES"))
        problems += tyre.check()
        if problems:
            more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
            raise FitError(f"the fitted tyre is not physical over the range it would declare, not written: "
                           f"{problems[0]}{more}")

    def summary(self) -> str:
        lines = [f"Magic Formula {self.version} fit, {len(self.fitted)} coefficients fitted in {self.seconds:.1f} s"]
        for name, f in self.stages.items():
            lines.append(f"  {name}: {len(f.varied)} varied, {f.n_points} points in {f.n_sweeps} sweeps, "
                         f"{f.nfev} evaluations, {f.seconds:.2f} s")
        for c, s in self.stats.items():
            lines.append(f"  {c}: RMSE {s['rmse']:.4g} {s['unit']} (R² {s['r2']:.4f}, noise floor "
                         f"{s['noise_floor']:.3g} {s['unit']})")
        return "\n".join(lines)

    # ------------------------------------------------------------------ figures
    def plot_curves(self, kind: str = "lateral", channel: str | None = None, ax=None, **kw):
        """Model (lines) over data (dots) along the sweep's slip, one panel per condition level, loads as colours.

        ``kind``: 'longitudinal' (Fx vs kappa), 'lateral' (Fy, Mz or Mx vs alpha, ``channel``), 'combined'
        (Fx, Fy or Mz vs kappa, a panel per slip angle too).  ``ax``: None (a new pyplot figure), a Figure,
        an array of Axes or one Axes (the nominal condition); returns the Axes
        (:func:`tyrefit.fitting.mf_figures.plot_curves`; residual maps:
        :func:`~tyrefit.fitting.mf_figures.plot_residual_map`).
        """
        return mf_figures.plot_curves(self, kind, channel, ax, **kw)

    def plot_cells(self, ax=None):
        """RMSE per condition cell in % of the channel's peak at that load: a heat map of condition x load,
        grouped by channel (:func:`tyrefit.fitting.mf_figures.plot_cells`); returns the Axes."""
        return mf_figures.plot_cells(self, ax)

    def plot_friction_ellipse(self, ax=None, **kw):
        """Fx against Fy of the drive/brake sweeps per condition level: the model only over the measured slip
        ranges, the data's largest |F|/Fz instead of a Kamm circle
        (:func:`tyrefit.fitting.mf_figures.plot_friction_ellipse`); returns the Axes."""
        return mf_figures.plot_friction_ellipse(self, ax, **kw)

    # ------------------------------------------------------------------ report
    def report_blocks(self, r) -> None:
        r.h2("Fit quality per channel")
        rows = []
        for c, s in self.stats.items():
            rows.append({"channel": c.upper(), "record": "all", "RMSE": s["rmse"], "unit": s["unit"], "R²": s["r2"],
                         "noise floor": s["noise_floor"], "RMSE/noise": s["rmse"] / s["noise_floor"]
                         if s["noise_floor"] > 0 else float("nan"), "points": s["n"], "fitted": s["fitted"]})
            for src, rs in (s.get("by_record") or {}).items():  # each record against its own noise
                rows.append({"channel": c.upper(), "record": src, "RMSE": rs["rmse"], "unit": s["unit"],
                             "R²": float("nan"), "noise floor": rs["noise_floor"],
                             "RMSE/noise": rs["rmse"] / rs["noise_floor"] if rs["noise_floor"] > 0 else float("nan"),
                             "points": rs["n"], "fitted": s["fitted"]})
        r.table(rows)
        r.h2("Stages")
        r.table([{"stage": n, "channel": f.channel.upper(), "points": f.n_points, "sweeps": f.n_sweeps,
                  "varied": ", ".join(f.varied), "evaluations": f.nfev, "seconds": f.seconds}
                 for n, f in self.stages.items()])

        mf_figures.report_figures(self, r)  # every condition; the cell table after the figures, collapsed
        r.h2("Coefficients")
        rows = []
        for n, f in self.stages.items():
            for k in f.varied:
                rows.append({"stage": n, "name": k, "value": self.params[k], "stderr": f.stderr.get(k, float("nan")),
                             "initial": f.initial.get(k, float("nan"))})
        r.table(rows)
        if self.not_identifiable:
            r.h3("Held (not identifiable from these data)")
            r.table([{"name": k, "value": self.params.get(k, float("nan")), "reason": v}
                     for k, v in self.not_identifiable.items()])
        cons = [c for f in self.stages.values() for c in f.constraints]
        if cons:
            r.h3("Physical constraints over the fitted range (grid of load, pressure, camber, slip sign)")
            r.table(cons)
        if self.warnings:
            r.h3("Warnings")
            r.bullets(self.warnings)
        if self.notes:
            r.h3("Notes")
            r.bullets(self.notes)


def _nominal_slice(d: pd.DataFrame, p) -> pd.DataFrame:
    """Sweeps at the pressure level nearest NOMPRES and the camber level nearest 0 (``mf_figures.nominal_slice``)."""
    return nominal_slice(d, p)


def _cells(df: pd.DataFrame) -> pd.DataFrame:
    """RMSE per condition cell (kind, load, pressure, camber, speed, slip-angle level) and channel
    (:func:`tyrefit.fitting.mf_figures.condition_cells`: levels clustered, so a pressure that creeps with tread
    temperature stays one cell)."""
    return condition_cells(df)
