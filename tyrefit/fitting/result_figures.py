"""Figures of a PAC89 fit: the model over the data, one panel per condition level, and the residuals.

Used by :class:`tyrefit.fitting.result.FitResult` (``plot``, ``plot_residuals``, ``facets``,
``facet_figures``) and by its HTML report (:mod:`tyrefit.fitting.result_report`); as
:mod:`tyrefit.fitting.mf_figures` does for the Magic Formula fit, every function takes the fit result
first.  Panels are the condition levels of :func:`tyrefit.io.facets.facet_sweeps` (pressure, speed and
camber; slip angle too for slip-ratio sweeps); loads are colours on one scale per figure.  Figures for
a report are built through matplotlib's object API (:class:`matplotlib.figure.Figure`), so a report
run never touches the user's pyplot state; only :func:`plot_fit` with ``ax=None`` makes a pyplot figure.

:func:`unfitted_figures` draws the sweeps a fit left out (data only, no model line).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..io.facets import describe_constant, facet_sweeps, format_load, pages

__all__ = ["part_facets", "draw_panel", "plot_fit", "plot_residuals", "facet_figures", "residual_figure",
           "unfitted_figures", "describe_constant_text"]

_RAD_TO_DEG = 180.0 / math.pi
#: per part: (column, symbol, unit, slip column, slip axis label, slip scale to display units)
_LABEL = {"lateral": ("fy", "Fy", "N", "slip_angle", "slip angle [deg]", _RAD_TO_DEG),
          "longitudinal": ("fx", "Fx", "N", "slip_ratio", "slip ratio [%]", 100.0),
          "aligning": ("mz", "Mz", "N·m", "slip_angle", "slip angle [deg]", _RAD_TO_DEG)}


def describe_constant_text(info: dict) -> str:
    """The conditions common to every panel, in words (:func:`tyrefit.io.facets.describe_constant`)."""
    return describe_constant(info)


def part_facets(result, part: str | None = None):
    """Panels of ``part``: one per combination of condition levels in its data (see :mod:`tyrefit.io.facets`).

    Returns ``(facets, info)`` of :func:`tyrefit.io.facets.facet_sweeps`.
    """
    part = part or result.parts[0]
    ch = ("pressure", "speed", "slip_angle", "camber") if part == "longitudinal" else \
        ("pressure", "speed", "camber")
    return facet_sweeps(result._parts[part].data.df, ch)


def draw_panel(result, ax, part: str, facet, fz_range=None, legend: bool = True):
    """Draw one panel on ``ax``: each sweep of ``facet`` as dots (data) and a line (the model at the sweep's mean
    load and camber), coloured by load over ``fz_range`` (default: the facet's loads); returns the Axes."""
    import matplotlib as mpl

    col, sym, unit, slip, xlabel, xs = _LABEL[part]
    pf = result._parts[part]
    df = pf.data.df
    cmap = mpl.colormaps["viridis"]
    lo, hi = fz_range or (min(facet.loads), max(facet.loads))
    for run, fzm in zip(facet.runs, facet.loads):
        g = df[df["run"] == run]
        c = cmap(0.85 * (fzm - lo) / (hi - lo)) if hi > lo else cmap(0.3)
        ax.plot(g[slip] * xs, g[col], ".", ms=3, color=c, alpha=0.5)
        xg = np.linspace(g[slip].min(), g[slip].max(), 200)
        cm = float(g["camber"].mean()) if "camber" in g else 0.0
        yg = pf.data.part.model(pf.coefficients, np.full_like(xg, fzm), xg, cm)
        ax.plot(xg * xs, yg, "-", color=c, lw=1.4, label=format_load(fzm), gid=f"model run {run}")
    ax.set_title(facet.title, fontsize=9)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(f"{sym} [{unit}]")
    ax.grid(alpha=0.3)
    if legend and 0 < len(facet.runs) <= 12:
        ax.legend(fontsize=7, title="Fz", title_fontsize=7)
    return ax


def plot_fit(result, ax=None, part: str | None = None, camber: float | None = None, pressure: float | None = None):
    """Fit (lines) over data (dots), loads as lines; returns the Axes.

    ``ax`` None: a pyplot figure with one panel per condition level (an array of Axes when several);
    an Axes: the panel of one condition level, chosen by ``camber`` and ``pressure``.

    Parameters
    ----------
    part : {'lateral', 'longitudinal', 'aligning'}, optional
        default: the first fitted part.
    camber : float, optional
        the panel at the camber level nearest this [rad]; default: nearest zero.
    pressure : float, optional
        the panel at the pressure level nearest this [Pa]; default: the first level.
    """
    part = part or result.parts[0]
    facets, info = part_facets(result, part)
    if ax is None:  # a pyplot figure (notebooks and plt.show() display it), one panel per condition level
        import matplotlib.pyplot as plt

        n = len(facets)
        cols = min(3, n)
        rows = -(-n // cols)
        fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.3 * rows), squeeze=False, sharex=True,
                                 sharey=True, layout="constrained")
        flat = axes.ravel()
        for a, f in zip(flat, sorted(facets, key=lambda f: f.row)):
            draw_panel(result, a, part, f)
            a.set_title(f.title, fontsize=9)
        for a in flat[n:]:
            a.set_visible(False)
        const = describe_constant_text(info)
        if const:
            fig.suptitle(const, fontsize=9)
        return axes if n > 1 else flat[0]
    want = {"camber": 0.0 if camber is None else camber}
    if pressure is not None:
        want["pressure"] = pressure

    def dist(f):
        return tuple(abs(f.conditions[c] - v) if c in f.conditions else 0.0 for c, v in want.items())

    best = min(facets, key=lambda f: (dist(f)[::-1], f.row))
    draw_panel(result, ax, part, best)
    const = describe_constant_text(info)
    if const:
        ax.set_title(best.title + (", " if best.title != "all sweeps" else ": ") + const
                     if best.title != "all sweeps" else const, fontsize=9)
    return ax


def plot_residuals(result, ax=None, part: str | None = None):
    """Residuals (model - data) vs slip, coloured by load; returns the Axes."""
    part = part or result.parts[0]
    if ax is None:
        from matplotlib.figure import Figure

        ax = Figure(figsize=(6.4, 4.0)).subplots()
    col, sym, unit, slip, xlabel, xs = _LABEL[part]
    pf = result._parts[part]
    d = pf.data
    res = d.part.model(pf.coefficients, d.fz, d.slip, d.camber) - d.y
    sc = ax.scatter(d.slip * xs, res, c=d.fz / 1e3, s=4, cmap="viridis", alpha=0.6)
    ax.axhline(0, color="k", lw=0.8)
    nf = result.stats[part]["noise_floor"]
    if np.isfinite(nf):
        ax.axhspan(-nf, nf, color="0.85", zorder=0, label=f"± noise floor {nf:.3g} {unit}")
        ax.legend(fontsize=7)
    ax.figure.colorbar(sc, ax=ax, label="Fz [kN]")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(f"{sym} model − data [{unit}]")
    ax.set_title(f"{result.model_label} {part} {sym}: residuals of all {result.stats[part]['sweeps']} sweeps, "
                 f"RMSE {result.stats[part]['rmse']:.3g} {unit}", fontsize=9)
    ax.grid(alpha=0.3)
    return ax


def facet_figures(result, part: str, max_rows: int = 4) -> list:
    """One figure per page of panels showing every sweep of ``part`` (see :func:`part_facets`).

    Each figure's title names the model, what it carries and the
    conditions common to every panel; each panel's title gives its
    condition levels in display units.  Returns a list of
    :class:`matplotlib.figure.Figure`.
    """
    from matplotlib.figure import Figure


    facets, info = part_facets(result, part)
    lo, hi = result.stats[part]["fz_range"]
    figs = []
    all_pages = pages(facets, max_rows=max_rows)
    ncols = max(f.col for f in facets) + 1
    for k, page in enumerate(all_pages):
        rows = sorted({f.row for f in page})
        fig = Figure(figsize=(4.2 * ncols, 3.4 * len(rows) + 0.7))
        axes = fig.subplots(len(rows), ncols, squeeze=False, sharex=True, sharey=True)
        used = set()
        for f in page:
            i = rows.index(f.row)
            draw_panel(result, axes[i][f.col], part, f, fz_range=(lo, hi))
            used.add((i, f.col))
        for i in range(len(rows)):
            for j in range(ncols):
                if (i, j) not in used:
                    axes[i][j].set_visible(False)
        const = describe_constant_text(info)
        title = result.figure_title(part) + (f"\nall sweeps at {const}" if const else "")
        if len(all_pages) > 1:
            title += f" (page {k + 1} of {len(all_pages)})"
        fig.suptitle(title, fontsize=10)
        fig.tight_layout()
        figs.append(fig)
    return figs


def residual_figure(result, part: str):
    """:func:`plot_residuals` of ``part`` on a Figure of its own (the object API; the report's figure)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 3.6))
    plot_residuals(result, fig.subplots(), part=part)
    fig.tight_layout()
    return fig


def unfitted_figures(df: pd.DataFrame, runs, max_rows: int = 4) -> list:
    """Data-only panels of sweeps a fit left out (combined slip for PAC89, say): one per condition level.

    ``df``: the data read (canonical SI columns with ``run``); ``runs``: the sweeps to draw.  Slip-ratio
    sweeps draw Fx against slip ratio, slip-angle sweeps Fy against slip angle; panels come from
    :func:`tyrefit.io.facets.facet_sweeps` (pressure, speed, slip angle, camber) and carry their
    conditions in the title.  Returns a list of Figures (empty when there is nothing to draw).
    """
    import matplotlib as mpl
    from matplotlib.figure import Figure


    sub = df[df["run"].isin(list(runs))]
    if sub.empty:
        return []
    ratio = "slip_ratio" in sub and "fx" in sub and sub.groupby("run")["slip_ratio"].agg(np.ptp).median() > 0.01
    x, y, xl, yl, xs = (("slip_ratio", "fx", "slip ratio [%]", "Fx [N]", 100.0) if ratio else
                        ("slip_angle", "fy", "slip angle [deg]", "Fy [N]", _RAD_TO_DEG))
    if x not in sub or y not in sub:
        return []
    ch = ("pressure", "speed", "slip_angle", "camber") if ratio else ("pressure", "speed", "camber")
    facets, info = facet_sweeps(sub, ch)
    lo, hi = float(sub["fz"].min()), float(sub["fz"].max())
    cmap = mpl.colormaps["viridis"]
    ncols = max(f.col for f in facets) + 1
    figs = []
    for page in pages(facets, max_rows=max_rows):
        rows = sorted({f.row for f in page})
        fig = Figure(figsize=(4.2 * ncols, 3.4 * len(rows) + 0.7))
        axes = fig.subplots(len(rows), ncols, squeeze=False, sharex=True, sharey=True)
        used = set()
        for f in page:
            ax = axes[rows.index(f.row)][f.col]
            used.add((rows.index(f.row), f.col))
            for run, fzm in zip(f.runs, f.loads):
                g = sub[sub["run"] == run]
                c = cmap(0.85 * (fzm - lo) / (hi - lo)) if hi > lo else cmap(0.3)
                ax.plot(g[x] * xs, g[y], ".", ms=3, color=c, label=format_load(fzm), gid=f"data run {run}")
            ax.set_title(f.title, fontsize=9)
            ax.set_xlabel(xl)
            ax.set_ylabel(yl)
            ax.grid(alpha=0.3)
            if len(f.runs) <= 12:
                ax.legend(fontsize=7, title="Fz", title_fontsize=7, markerscale=3)
        for i in range(len(rows)):
            for j in range(ncols):
                if (i, j) not in used:
                    axes[i][j].set_visible(False)
        const = describe_constant(info)
        fig.suptitle(f"{len(set(sub['run']))} sweeps NOT FITTED (data only, no model line)"
                     + (f"; all at {const}" if const else ""), fontsize=10)
        fig.tight_layout()
        figs.append(fig)
    return figs

