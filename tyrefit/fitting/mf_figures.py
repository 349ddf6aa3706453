"""Figures of a Magic Formula fit that show every condition the data hold.

Used by :class:`tyrefit.fitting.mf_result.FitResultMF` (``plot_curves``,
``plot_cells``, ``plot_friction_ellipse``, ``report_blocks``).  Every function
takes the fit result and an optional ``ax``:

* ``None``: a new figure made with :func:`matplotlib.pyplot.subplots`, so a
  notebook or ``plt.show()`` displays it;
* a :class:`matplotlib.figure.Figure`: the panels are laid out inside it (the
  report builds its figures this way, through the object API, so a report run
  never touches the user's pyplot state or backend);
* an array of Axes (one per panel, at least :func:`panels` many) or, for the
  multi-panel figures, a single Axes: the panel of the nominal condition.

The Axes are returned (an array for the multi-panel figures).

Condition levels
----------------
A sweep's condition is its pressure, camber and speed level (and, for a
combined-slip sweep, its slip-angle level); levels are clusters of the sweeps'
means (gap clustering of :func:`tyrefit.io.levels.group_levels` within
max(atol, rtol x the largest value): pressure within 5 kPa or 2 %, camber
within 0.5 deg, speed within 1 m/s or 5 %, slip angle within 0.5 deg), so a pressure that creeps up 3 kPa with tread temperature stays one
level.  Loads are clustered over every sweep of the fit and keep one colour in
every figure.

Figures
-------
:func:`plot_curves`
    one panel per condition level for one channel view (:data:`VIEWS`), loads
    as coloured lines (the model, evaluated along the slip range the data cover
    at the level's mean load, camber, pressure and speed) over dots (the data,
    at most ``max_dots`` a sweep); shared axes.
:func:`plot_residual_map`
    the residual model - data (the model at every measured point, as the fit
    statistics) averaged in bins of slip x load level, one panel per
    condition level, diverging colour map centred on 0 with one colour bar.
:func:`plot_cells`
    RMSE per condition cell in % of the channel's peak at that load: a heat map
    of condition (rows) against load (columns), the columns grouped by channel
    view and slip angle; no lines join cells.
:func:`plot_friction_ellipse`
    Fx against Fy of the drive/brake sweeps (pure and combined) per condition,
    loads as colours: the model only over the slip ratios and slip angles the
    data covered at that load and condition (:func:`ellipse_curves`), and a
    circle of the data's largest |F|/Fz (99.5th percentile) x Fz instead of a
    Kamm circle of the fitted (possibly extrapolated) friction.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..io.levels import group_levels
from ..models import mf61

__all__ = ["VIEWS", "sweep_levels", "condition_cells", "nominal_slice", "views", "panels", "plot_curves",
           "plot_residual_map", "plot_cells", "ellipse_curves", "plot_friction_ellipse", "report_figures"]

_DEG = math.pi / 180.0
_UNIT = {"fx": "N", "fy": "N", "mz": "N·m", "mx": "N·m", "my": "N·m"}
_SLIP = {"longitudinal": "slip_ratio", "lateral": "slip_angle", "combined": "slip_ratio"}
_SLIP_SCALE = {"slip_ratio": 100.0, "slip_angle": 1.0 / _DEG}
_SLIP_LABEL = {"slip_ratio": "slip ratio [%]", "slip_angle": "slip angle [deg]"}

#: font sizes [pt] at the figure's own size; figures are at most FIG_WIDTH wide, which the report shows at
#: about 1:1 (1150 px page width, 110 dpi), so panel titles stay >= 9 pt on the page
TITLE_PT, LABEL_PT, TICK_PT, SUPTITLE_PT = 10.5, 10.0, 9.0, 11.5
FIG_WIDTH = 10.4

#: (kind, channel, title) of each channel view: one figure of panels and one residual map each
VIEWS = (("longitudinal", "fx", "Fx vs slip ratio, pure (α = 0)"),
         ("lateral", "fy", "Fy vs slip angle, pure (κ = 0)"),
         ("lateral", "mz", "Mz vs slip angle, pure (κ = 0)"),
         ("lateral", "mx", "Mx vs slip angle, pure (κ = 0)"),
         ("longitudinal", "my", "My vs slip ratio, pure (α = 0)"),
         ("combined", "fx", "Fx vs slip ratio at each slip angle (combined)"),
         ("combined", "fy", "Fy vs slip ratio at each slip angle (combined)"),
         ("combined", "mz", "Mz vs slip ratio at each slip angle (combined)"))
_SHORT = {("longitudinal", "fx"): "Fx pure", ("lateral", "fy"): "Fy pure", ("lateral", "mz"): "Mz pure",
          ("lateral", "mx"): "Mx pure", ("longitudinal", "my"): "My pure", ("combined", "fx"): "Fx comb.",
          ("combined", "fy"): "Fy comb.",
          ("combined", "mz"): "Mz comb."}

_COND = ("p", "v", "g", "a")  # pressure, speed, camber, slip angle (combined only)


# ---------------------------------------------------------------------------------------- levels
def sweep_levels(df: pd.DataFrame) -> pd.DataFrame:
    """One row per sweep (``run``): kind, mean conditions and their levels.

    Columns ``kind fz pressure camber speed alpha n`` (means; ``alpha`` the
    median slip angle), ``load`` (load level over every sweep) and ``fz_cell``
    (its mean load), and per condition ``p v g a`` the level index (-1 where
    not given) and ``p_cell v_cell g_cell a_cell`` the level's mean value (SI;
    ``a_cell`` is 0 for pure-slip sweeps).
    """
    sw = df.groupby("run", sort=True).agg(kind=("kind", "first"), fz=("fz", "mean"), pressure=("pressure", "mean"),
                                          camber=("camber", "mean"), speed=("speed", "mean"),
                                          alpha=("slip_angle", "median"), n=("fz", "size"))
    sw["load"] = group_levels(sw["fz"], 100.0, 0.04)[1]
    sw["fz_cell"] = sw.groupby("load")["fz"].transform("mean")
    for key, col, ab, rel in (("p", "pressure", 5e3, 0.02), ("v", "speed", 1.0, 0.05),
                              ("g", "camber", 0.5 * _DEG, 0.0)):
        sw[key] = group_levels(sw[col], ab, rel)[1]
        sw[f"{key}_cell"] = sw[col].groupby(sw[key]).transform("mean").where(sw[key] >= 0)
    comb = (sw["kind"] == "combined").to_numpy()
    a = np.full(len(sw), -1, int)
    a[comb] = group_levels(sw["alpha"].to_numpy(float)[comb], 0.5 * _DEG)[1]
    sw["a"] = a
    sw["a_cell"] = sw["alpha"].groupby(sw["a"]).transform("mean").where(sw["a"] >= 0, 0.0)
    return sw


def condition_cells(df: pd.DataFrame) -> pd.DataFrame:
    """RMSE per condition cell (kind, load, pressure, camber, speed, slip angle) and channel.

    Columns ``channel kind fz [N] pressure [kPa] camber [deg] speed [m/s] slip angle [deg] n rmse bias
    rmse_pct_peak rmse_pct_load_peak``: the levels' mean values (rounded), RMSE and bias of model - data,
    RMSE in % of the cell's peak |channel| and of the channel's peak at that load (every kind).
    """
    sw = sweep_levels(df)
    cell = pd.DataFrame({"fz_c": np.round(sw["fz_cell"], -1), "p_c": np.round(sw["p_cell"] / 1e3).fillna(-1),
                         "g_c": np.round(sw["g_cell"] / _DEG, 1).fillna(0.0),
                         "v_c": np.round(sw["v_cell"], 1).fillna(-1),
                         "a_c": np.round(sw["a_cell"] / _DEG, 1)}, index=sw.index)
    key = ["kind", "fz_c", "p_c", "g_c", "v_c", "a_c"]
    d = df.join(cell, on="run")
    rows = []
    for c in ("fx", "fy", "mz", "mx", "my"):
        if f"model_{c}" not in d or c not in d:
            continue
        e = d[np.isfinite(d[c]) & np.isfinite(d[f"model_{c}"])]
        if e.empty:
            continue
        load_peak = e[c].abs().groupby(e["fz_c"]).max()
        res_all = e[f"model_{c}"] - e[c]
        for k, g in e.groupby(key, sort=True):
            res = res_all.loc[g.index]
            rmse = float(np.sqrt(np.mean(res**2)))
            pk = float(np.max(np.abs(g[c]))) or 1.0
            rows.append({"channel": c, "kind": k[0], "fz [N]": k[1], "pressure [kPa]": k[2] if k[2] >= 0 else None,
                         "camber [deg]": k[3], "speed [m/s]": k[4] if k[4] >= 0 else None, "slip angle [deg]": k[5],
                         "n": len(g), "rmse": rmse, "bias": float(res.mean()), "rmse_pct_peak": 100.0 * rmse / pk,
                         "rmse_pct_load_peak": 100.0 * rmse / (float(load_peak[k[1]]) or 1.0)})
    return pd.DataFrame(rows)


def nominal_slice(d: pd.DataFrame, p) -> pd.DataFrame:
    """The sweeps of ``d`` at the pressure level nearest NOMPRES and the camber level nearest 0."""
    if d.empty:
        return d
    sw = sweep_levels(d)
    keep = _nominal(sw, p)
    return d[d["run"].isin(sw.index[keep])]


def _nominal(sw: pd.DataFrame, p) -> np.ndarray:
    """Mask of the sweeps at the nominal condition: pressure, then camber (|.| smallest), then speed."""
    keep = np.ones(len(sw), bool)
    for cell, target in (("p_cell", p.get("NOMPRES", np.nan)), ("g_cell", 0.0), ("v_cell", p.get("LONGVL", np.nan))):
        x = sw[cell].to_numpy(float)
        if not np.isfinite(x[keep]).any():
            continue
        t = target if np.isfinite(target) else np.nanmedian(x[keep])
        dist = np.abs(x - t)
        keep &= np.isfinite(dist) & (dist <= np.nanmin(np.where(keep, dist, np.nan)) + 1e-9)
    return keep


# ---------------------------------------------------------------------------------------- panels
def _samples(result, kinds, channel: str | None) -> tuple[pd.DataFrame, pd.DataFrame]:
    """(samples of ``kinds`` with ``channel`` and its model finite, joined to their sweep levels; sweep table)."""
    df = result.data.df
    sw = sweep_levels(df)
    d = df[df["kind"].isin(kinds)]
    if channel is not None:
        if channel not in d or f"model_{channel}" not in d:
            return d.iloc[:0], sw
        d = d[np.isfinite(d[channel].to_numpy(float)) & np.isfinite(d[f"model_{channel}"].to_numpy(float))]
    cols = ["load", "fz_cell", *_COND, *(f"{k}_cell" for k in _COND)]
    return d.join(sw[cols], on="run"), sw


def views(result) -> list[tuple[str, str, str]]:
    """The channel views (:data:`VIEWS`) with at least 10 measured points and a model of the channel."""
    df = result.data.df
    stats = getattr(result, "stats", {}) or {}
    out = []
    for kind, ch, title in VIEWS:
        if ch not in stats or ch not in df or f"model_{ch}" not in df:
            continue
        k = (df["kind"] == kind).to_numpy()
        ok = np.isfinite(df[ch].to_numpy(float)[k]) & np.isfinite(df[f"model_{ch}"].to_numpy(float)[k])
        if ok.sum() >= 10:
            out.append((kind, ch, title))
    return out


def _panel_table(d: pd.DataFrame, dims=("p", "v", "g", "a")) -> pd.DataFrame:
    """One row per condition level present in ``d`` (index 0..n-1), sorted by pressure, speed, slip angle, camber."""
    keys = list(dims)
    t = d.groupby(keys, sort=False)[[f"{k}_cell" for k in keys]].first().reset_index()
    order = [f"{k}_cell" for k in ("p", "v", "a", "g") if k in keys]
    if "a" in keys:  # slip angles from the smallest |alpha| up
        t = t.assign(_abs_a=t["a_cell"].abs())
        order = ["_abs_a" if o == "a_cell" else o for o in order]
    t = t.sort_values(order, kind="stable", na_position="first").reset_index(drop=True)
    return t.drop(columns="_abs_a", errors="ignore")


def _label(row, show) -> str:
    parts = []
    if "a" in show and np.isfinite(row.get("a_cell", np.nan)):
        parts.append(f"α {round(row['a_cell'] / _DEG, 1):g}°")
    if "p" in show and np.isfinite(row.get("p_cell", np.nan)):
        parts.append(f"{row['p_cell'] / 1e3:.0f} kPa")
    if "g" in show and np.isfinite(row.get("g_cell", np.nan)):
        parts.append(f"γ {round(row['g_cell'] / _DEG, 1):g}°")
    if "v" in show and np.isfinite(row.get("v_cell", np.nan)):
        parts.append(f"{row['v_cell']:.1f} m/s")
    return " · ".join(parts) or "all sweeps"


def _varying(t: pd.DataFrame, dims) -> tuple[list[str], str]:
    """(dims with more than one level among the panels, text of the constant ones)."""
    show = [k for k in dims if t[k].nunique() > 1]
    const = [k for k in dims if k not in show and k != "a"]
    return show, _label(t.iloc[0], const) if len(t) and const else ""


def panels(result, kind: str, channel: str | None = None) -> pd.DataFrame:
    """The condition levels of ``kind`` (one panel each): level indices, mean values and ``title``."""
    kinds = ("longitudinal", "combined") if kind == "ellipse" else (kind,)
    d, _ = _samples(result, kinds, channel)
    dims = ("p", "v", "g") if kind == "ellipse" else (("p", "v", "g", "a") if kind == "combined" else ("p", "v", "g"))
    if d.empty:
        return pd.DataFrame(columns=[*dims, "title"])
    return _titled(d, dims)[0]


def _titled(d: pd.DataFrame, dims) -> tuple[pd.DataFrame, str]:
    """The panels of ``d`` (:func:`_panel_table`) titled by the conditions that vary; the constant ones' text."""
    t = _panel_table(d, dims)
    show, const = _varying(t, dims)
    t["title"] = [_label(r, show) for _, r in t.iterrows()]
    return t, const


def _single_axes(ax) -> bool:
    """One Axes given (draw the nominal condition on it), not a Figure, an array of Axes or None."""
    return ax is not None and not _is_figure(ax) and not isinstance(ax, (np.ndarray, list, tuple))


def _grid(t: pd.DataFrame, dims, max_cols: int = 4) -> tuple[int, int, list[tuple[int, int]]]:
    """(rows, cols, (row, col) of each panel): camber levels (else pressure levels) as columns when 2..6."""
    n = len(t)
    col_dim = next((k for k in ("g", "p", "a") if k in dims and 2 <= t[k].nunique() <= 6), None)
    if col_dim is None or n <= 1:
        nc = min(max_cols, max(1, n))
        return math.ceil(n / nc), nc, [(i // nc, i % nc) for i in range(n)]
    cols = sorted(t[col_dim].unique(), key=lambda k: t.loc[t[col_dim] == k, f"{col_dim}_cell"].iloc[0])
    rest = [k for k in dims if k != col_dim]
    rkeys = list(dict.fromkeys(tuple(r) for r in t[rest].itertuples(index=False))) if rest else [()]
    pos = [(rkeys.index(tuple(r[k] for k in rest)), cols.index(r[col_dim])) for _, r in t.iterrows()]
    return len(rkeys), len(cols), pos


def _new_figure(ax, figsize, layout=None):
    """A figure of ``figsize`` [in]: ``ax`` None -> a new pyplot figure (shown by notebooks and ``plt.show()``),
    a Figure -> that figure, resized."""
    if ax is None:
        import matplotlib.pyplot as plt

        return plt.figure(figsize=figsize, layout=layout)
    ax.set_size_inches(*figsize)
    ax.set_layout_engine(layout if layout else "none")
    return ax


def _is_figure(ax) -> bool:
    from matplotlib.figure import FigureBase

    return isinstance(ax, FigureBase)


def _axes_grid(ax, t, dims, *, panel_w=3.0, panel_h=2.4, square=False, cbar=False, title="", legend=True):
    """(figure, one Axes per row of the panel table, geometry) for ``ax`` None or a Figure; given Axes as they are.

    A fixed layout in inches (no layout engine: a report of a hundred panels renders in seconds): margins for
    the figure title, the load legend, the shared axis labels and a colour bar; shared axes, tick labels on the
    outer panels and on the lowest panel of each column.
    """
    if ax is not None and not _is_figure(ax):
        arr = np.atleast_1d(np.asarray(ax, dtype=object)).ravel()
        return arr[0].figure, arr, None
    nr, nc, pos = _grid(t, dims)
    L, R, B, ws, hs = 1.0, 1.25 if cbar else 0.25, 0.62, 0.32, 0.45
    W = min(FIG_WIDTH, L + R + nc * panel_w + (nc - 1) * ws)
    import textwrap

    # figure title lines, the load legend, the panel titles of the first row
    T = 0.15 + 0.24 * max(1, len(textwrap.wrap(title, int(W * 10.5)))) + (0.34 if legend else 0.0) + 0.3
    pw = (W - L - R - (nc - 1) * ws) / nc
    ph = pw if square else min(panel_h, 0.8 * pw)
    H = T + B + nr * ph + (nr - 1) * hs
    fig = _new_figure(ax, (W, H))
    # no shared axes (matplotlib's sibling search makes a figure of n shared panels O(n^2) to draw):
    # common limits and outer tick labels are set by _unify once the panels are drawn
    grid = fig.subplots(nr, nc, squeeze=False,
                        gridspec_kw=dict(left=L / W, right=1 - R / W, bottom=B / H, top=1 - T / H,
                                         wspace=ws / pw, hspace=hs / ph))
    out = np.empty(len(t), dtype=object)
    used = np.zeros((nr, nc), bool)
    for i, (r, c) in enumerate(pos):
        out[i] = grid[r, c]
        used[r, c] = True
    for r in range(nr):
        for c in range(nc):
            if not used[r, c]:
                grid[r, c].set_visible(False)
    geom = {"W": W, "H": H, "L": L, "R": R, "B": B, "T": T, "grid": grid, "used": used}
    return fig, out, geom


def _unify(axes, geom=None, *, x=True, y=True, nbins: int = 5) -> None:
    """One x and one y range over ``axes``; with a grid (``geom``), tick labels on the left column and on the
    lowest panel of each column only."""
    from matplotlib.ticker import MaxNLocator

    axes = [a for a in axes if a.get_visible()]
    if not axes:
        return
    for flag, get, set_ in ((x, "get_xlim", "set_xlim"), (y, "get_ylim", "set_ylim")):
        if flag:
            lims = np.array([getattr(a, get)() for a in axes])
            for a in axes:
                getattr(a, set_)(lims[:, 0].min(), lims[:, 1].max())
    for a in axes:
        if x:
            a.xaxis.set_major_locator(MaxNLocator(nbins))
        if y:
            a.yaxis.set_major_locator(MaxNLocator(nbins))
    if geom is None:
        return
    grid, used = geom["grid"], geom["used"]
    nr, nc = used.shape
    for r in range(nr):
        for c in range(nc):
            if used[r, c]:
                low = r + 1 >= nr or not used[r + 1:, c].any()
                first = not used[r, :c].any()
                grid[r, c].tick_params(labelbottom=low, labelleft=first)


def _finish(fig, geom, title: str, xlabel: str, ylabel: str, handles=None, mappable=None, cbar_label=None):
    """Figure title, shared axis labels, load legend and colour bar, placed in the margins of ``geom``."""
    import textwrap

    W, H = geom["W"], geom["H"]
    fig.suptitle(textwrap.fill(title, int(W * 10.5)), fontsize=SUPTITLE_PT, y=1 - 0.12 / H, va="top")
    fig.supxlabel(xlabel, fontsize=LABEL_PT, y=0.1 / H, va="bottom")
    fig.supylabel(ylabel, fontsize=LABEL_PT, x=0.08 / W, ha="left")
    if handles:
        items = sorted(handles.items())
        fig.legend([h[0] for _, h in items], [h[1] for _, h in items], loc="lower center",
                   bbox_to_anchor=(0.5, 1 - (geom["T"] - 0.3) / H), ncols=min(6, len(items)), fontsize=TICK_PT,
                   frameon=False, handlelength=2.2, markerscale=3)
    if mappable is not None:
        cax = fig.add_axes(((W - geom["R"] + 0.3) / W, geom["B"] / H, 0.16 / W, (H - geom["T"] - geom["B"]) / H))
        cb = fig.colorbar(mappable, cax=cax, extend="both")
        cb.set_label(cbar_label, fontsize=LABEL_PT)
        cb.ax.tick_params(labelsize=TICK_PT)


def _load_colours(levels: np.ndarray):
    import matplotlib

    cmap = matplotlib.colormaps["viridis"]
    lv = sorted(set(int(x) for x in levels))
    return {k: cmap(0.8 * i / max(1, len(lv) - 1)) for i, k in enumerate(lv)}  # no light yellow on white


def _thin(d: pd.DataFrame, max_dots: int) -> pd.DataFrame:
    """At most ``max_dots`` samples per sweep (every k-th, in record order)."""
    if d.empty:
        return d
    size = d.groupby("run")["run"].transform("size").to_numpy()
    step = np.maximum(1, np.ceil(size / max_dots)).astype(int)
    pos = d.groupby("run").cumcount().to_numpy()
    return d[pos % step == 0]


def _model(result, rows: list[dict], n: int = 80) -> list[dict]:
    """Evaluate the fitted model along each row's slip range (``slip`` 'slip_ratio'/'slip_angle', ``lo hi``,
    ``fz camber pressure speed alpha``; pure-slip rows at the other slip 0), in one call."""
    if not rows:
        return rows
    p = result.params
    x = np.concatenate([np.linspace(r["lo"], r["hi"], n) for r in rows])
    rep = lambda k: np.repeat([float(r[k]) for r in rows], n)  # noqa: E731
    lat = np.repeat([r["slip"] == "slip_angle" for r in rows], n)
    kap = np.where(lat, 0.0, x)
    alp = np.where(lat, x, rep("alpha"))
    pr, sp = rep("pressure"), rep("speed")
    kw = {"version": result.version} if getattr(result, "version", "6.1") != "6.1" else {}
    out = mf61.forces(p, rep("fz"), slip_ratio=kap, slip_angle=alp, camber=rep("camber"),
                      pressure=np.where(np.isfinite(pr), pr, p.get("NOMPRES")) if np.isfinite(pr).any() else None,
                      speed=np.where(np.isfinite(sp), sp, p.get("LONGVL")) if np.isfinite(sp).any() else None, **kw)
    for i, r in enumerate(rows):
        s = slice(i * n, (i + 1) * n)
        r["x"] = x[s]
        r["kappa"], r["alpha_pts"] = kap[s], alp[s]
        for c in ("fx", "fy", "mz", "mx", "my"):
            r[c] = np.asarray(out.get(c, np.full(len(x), np.nan)), float)[s]
    return rows


def _style(ax, title: str | None = None):
    ax.tick_params(labelsize=TICK_PT)
    ax.grid(True, alpha=0.3)
    if title:
        ax.set_title(title, fontsize=TITLE_PT, pad=3, y=1.0)  # y given: no automatic (slow) title placement


def _fz_text(fz: float) -> str:
    return f"Fz {fz / 1e3:.2f} kN" if fz < 1e4 else f"Fz {fz / 1e3:.1f} kN"


def _pick_nominal(result, t: pd.DataFrame, panel) -> int:
    if panel is not None:
        return int(panel)
    keep = _nominal(t, result.params)
    cand = np.flatnonzero(keep)
    if not len(cand):
        return 0
    if "a_cell" in t:  # combined: the largest slip angle (most combined)
        return int(cand[np.argmax(np.abs(t["a_cell"].to_numpy(float)[cand]))])
    return int(cand[0])


# ---------------------------------------------------------------------------------------- curves
def plot_curves(result, kind: str = "lateral", channel: str | None = None, ax=None, *, max_dots: int = 120,
                panel: int | None = None):
    """Model (lines) over data (dots) of ``channel`` in ``kind`` sweeps: one panel per condition level.

    ``kind``: 'longitudinal' (Fx vs slip ratio), 'lateral' (Fy, Mz or Mx vs slip angle), 'combined' (Fx, Fy
    or Mz vs slip ratio, one panel per slip-angle level too).  Loads are colours.  ``ax``: None (a new pyplot
    figure), a Figure to fill, an array of Axes (one per panel of :func:`panels`) or one Axes (the panel
    ``panel``, default the nominal condition).  Returns the array of Axes, one per panel (titles name the
    condition), or the one Axes given.
    """
    channel = channel or {"longitudinal": "fx", "lateral": "fy", "combined": "fy"}[kind]
    d, sw = _samples(result, (kind,), channel)
    dims = ("p", "v", "g", "a") if kind == "combined" else ("p", "v", "g")
    if d.empty:
        if ax is None or _is_figure(ax):
            fig = _new_figure(ax, (5.0, 3.0))
            ax = fig.subplots()
        a0 = np.atleast_1d(np.asarray(ax, dtype=object)).ravel()[0]
        a0.text(0.5, 0.5, f"no {kind} sweeps with {channel.upper()}", ha="center", transform=a0.transAxes)
        return ax
    t, const = _titled(d, dims)
    single = _single_axes(ax)
    if single:
        idx = [_pick_nominal(result, t, panel)]
        axes = np.array([ax], dtype=object)
    else:
        title = next((v[2] for v in VIEWS if v[:2] == (kind, channel)), f"{channel.upper()} ({kind})")
        title = f"{title}: model (lines) over data (dots)" + (f"; all at {const}" if const else "")
        fig, axes, geom = _axes_grid(ax, t, dims, title=title)
        if len(axes) < len(t):
            raise ValueError(f"{len(t)} panels of {kind} {channel}, {len(axes)} Axes given")
        idx = list(range(len(t)))
    slip = _SLIP[kind]
    xs = _SLIP_SCALE[slip]
    colours = _load_colours(sw["load"].to_numpy())
    dots = _thin(d, max_dots)
    # model rows: one per (panel, load level), over the slip range its data cover
    key = list(dims)
    rows = []
    for k, g in d.groupby([*key, "load"], sort=False):
        s = g[slip].to_numpy(float)
        m = sw.loc[g["run"].unique()]
        rows.append({"key": k[:-1], "load": k[-1], "slip": slip, "lo": float(np.min(s)), "hi": float(np.max(s)),
                     "fz": m["fz"].mean(), "camber": m["camber"].mean(), "pressure": m["pressure"].mean(),
                     "speed": m["speed"].mean(), "alpha": m["alpha"].mean() if kind == "combined" else 0.0})
    rows = _model(result, rows)
    handles = {}
    for a, i in zip(axes, idx):
        cond = tuple(t.loc[i, key])
        mask = np.all([dots[k].to_numpy() == v for k, v in zip(key, cond)], axis=0)
        g = dots[mask]
        for lv, h in g.groupby("load"):
            a.plot(h[slip] * xs, h[channel], ".", ms=3, alpha=0.45, color=colours[lv], rasterized=True)
        for r in rows:
            if tuple(r["key"]) == cond:
                (ln,) = a.plot(r["x"] * xs, r[channel], "-", lw=1.4, color=colours[r["load"]])
                handles.setdefault(r["load"], (ln, _fz_text(sw.loc[sw["load"] == r["load"], "fz_cell"].iloc[0])))
        _style(a, t.loc[i, "title"] if not single else _label(t.loc[i], dims))
        a.axhline(0.0, color="0.6", lw=0.6, zorder=0)
    unit = _UNIT[channel]
    if single:
        a = axes[0]
        a.set_xlabel(_SLIP_LABEL[slip], fontsize=LABEL_PT)
        a.set_ylabel(f"{channel.upper()} [{unit}]", fontsize=LABEL_PT)
        a.legend([h[0] for _, h in sorted(handles.items())], [h[1] for _, h in sorted(handles.items())],
                 fontsize=TICK_PT - 1)
        return a
    _unify(axes, geom)
    if geom is not None:
        _finish(fig, geom, title, _SLIP_LABEL[slip], f"{channel.upper()} [{unit}]", handles)
    return axes


# ---------------------------------------------------------------------------------------- residual maps
def plot_residual_map(result, kind: str = "lateral", channel: str | None = None, ax=None, *, nbins: int = 24,
                      min_count: int = 2):
    """Mean residual (model - data) in bins of slip x load level, one panel per condition level.

    Diverging colour map centred on 0, symmetric about the 98th percentile of |bin mean| over all panels, one
    colour bar in the channel's unit; grey: no data.  ``ax`` as :func:`plot_curves`.  Returns the Axes (one per
    panel).
    """
    from matplotlib.colors import Normalize

    channel = channel or {"longitudinal": "fx", "lateral": "fy", "combined": "fy"}[kind]
    d, sw = _samples(result, (kind,), channel)
    dims = ("p", "v", "g", "a") if kind == "combined" else ("p", "v", "g")
    if d.empty:
        return plot_curves(result, kind, channel, ax)
    t, const = _titled(d, dims)
    single = _single_axes(ax)
    if single:
        idx, axes, fig = [_pick_nominal(result, t, None)], np.array([ax], dtype=object), ax.figure
    else:
        title = next((v[2] for v in VIEWS if v[:2] == (kind, channel)), f"{channel.upper()} ({kind})")
        title = (f"{title}: residual map (red: model above the data, blue: below; grey: no data)"
                 + (f"; all at {const}" if const else ""))
        fig, axes, geom = _axes_grid(ax, t, dims, panel_h=1.9, cbar=True, title=title, legend=False)
        idx = list(range(len(t)))
    slip = _SLIP[kind]
    xs = _SLIP_SCALE[slip]
    x = d[slip].to_numpy(float) * xs
    lo, hi = np.nanpercentile(x, [0.2, 99.8])
    edges = np.linspace(lo, hi, nbins + 1)
    loads = sorted(set(d["load"]))
    fz_of = {lv: float(sw.loc[sw["load"] == lv, "fz_cell"].iloc[0]) for lv in loads}
    row = np.searchsorted(loads, d["load"].to_numpy())
    col = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, nbins - 1)
    res = (d[f"model_{channel}"] - d[channel]).to_numpy(float)
    inside = (x >= lo) & (x <= hi)
    key = list(dims)
    maps = []
    for i in idx:
        m = inside & np.all([d[k].to_numpy() == v for k, v in zip(key, t.loc[i, key])], axis=0)
        flat = row[m] * nbins + col[m]
        cnt = np.bincount(flat, minlength=len(loads) * nbins)
        tot = np.bincount(flat, weights=res[m], minlength=len(loads) * nbins)
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = np.where(cnt >= min_count, tot / cnt, np.nan)
        maps.append(np.ma.masked_invalid(mean.reshape(len(loads), nbins)))
    vals = np.concatenate([np.abs(m.compressed()) for m in maps]) if maps else np.zeros(0)
    lim = float(np.percentile(vals, 98)) if vals.size else 1.0
    norm = Normalize(-(lim or 1.0), lim or 1.0)
    mesh = None
    yedges = np.arange(len(loads) + 1) - 0.5
    for a, i, mp in zip(axes, idx, maps):
        a.set_facecolor("0.88")
        mesh = a.pcolormesh(edges, yedges, mp, cmap="RdBu_r", norm=norm, rasterized=True)
        a.set_yticks(range(len(loads)), [f"{fz_of[lv] / 1e3:.1f}" for lv in loads])
        a.set_xlim(lo, hi)
        _style(a, t.loc[i, "title"])
        a.grid(False)
    unit = _UNIT[channel]
    label = f"mean residual, model − data [{unit}]"
    vis = [a for a in axes if a.get_visible()]
    if single:
        axes[0].set_xlabel(_SLIP_LABEL[slip], fontsize=LABEL_PT)
        axes[0].set_ylabel("Fz [kN]", fontsize=LABEL_PT)
        fig.colorbar(mesh, ax=axes[0], label=label, extend="both")
        return axes[0]
    _unify(axes, geom, y=False)
    if geom is not None:
        _finish(fig, geom, title, _SLIP_LABEL[slip], "load level Fz [kN]", mappable=mesh, cbar_label=label)
    else:
        fig.colorbar(mesh, ax=list(vis), label=label, extend="both")
    return axes


# ---------------------------------------------------------------------------------------- cells
def _cells_matrix(result):
    """(matrix [conditions x columns] of RMSE % of the load's peak, row labels, column loads, groups)."""
    c = getattr(result, "cells", None)
    if c is None or c.empty:
        c = condition_cells(result.data.df)
    if c.empty:
        return None
    vs = [(k, ch) for k, ch, _ in views(result)]
    c = c[[(k, ch) in vs for k, ch in zip(c["kind"], c["channel"])]]
    if c.empty:
        return None
    cond_cols = [k for k in ("pressure [kPa]", "camber [deg]", "speed [m/s]") if k in c]
    cond = c[cond_cols].astype(float).fillna(-1.0)
    conds = sorted(set(map(tuple, cond.to_numpy())))
    vary = [j for j in range(len(cond_cols)) if len({r[j] for r in conds}) > 1] or [0]
    unit = {"pressure [kPa]": " kPa", "camber [deg]": "°", "speed [m/s]": " m/s"}
    pre = {"pressure [kPa]": "", "camber [deg]": "γ ", "speed [m/s]": ""}

    def lab(r):
        return " · ".join(f"{pre[cond_cols[j]]}{r[j]:g}{unit[cond_cols[j]]}" for j in vary if r[j] != -1.0) or "all"

    groups, columns = [], []
    for k, ch in vs:
        g = c[(c["kind"] == k) & (c["channel"] == ch)]
        for a in sorted(set(g["slip angle [deg]"]), key=lambda v: (abs(v), v)):
            loads = sorted(set(g.loc[g["slip angle [deg]"] == a, "fz [N]"]))
            name = _SHORT[(k, ch)] + (f"\nα {a:g}°" if k == "combined" else "")
            groups.append((name, len(columns), len(loads)))
            columns += [(k, ch, a, fz) for fz in loads]
    M = np.full((len(conds), len(columns)), np.nan)
    ci = {col: j for j, col in enumerate(columns)}
    ri = {r: i for i, r in enumerate(conds)}
    kinds, chans = c["kind"].to_numpy(), c["channel"].to_numpy()
    alphas, fzs, vals = c["slip angle [deg]"].to_numpy(), c["fz [N]"].to_numpy(), c["rmse_pct_load_peak"].to_numpy()
    for i, cr in enumerate(map(tuple, cond.to_numpy())):
        j = ci.get((kinds[i], chans[i], alphas[i], fzs[i]))
        if j is not None:
            M[ri[cr], j] = vals[i]
    return M, [lab(r) for r in conds], [col[3] for col in columns], groups, [cond_cols[j] for j in vary]


def plot_cells(result, ax=None):
    """RMSE per condition cell in % of the channel's peak at that load: conditions (rows) x loads (columns),
    the columns grouped by channel view (and slip angle for combined slip).  Returns the Axes."""
    mat = _cells_matrix(result)
    if ax is None or _is_figure(ax):
        nrow = len(mat[1]) if mat else 1
        ncol = len(mat[2]) if mat else 1
        fig = _new_figure(ax, (min(FIG_WIDTH, 2.2 + 0.42 * ncol + 1.2), 1.9 + 0.34 * nrow), layout="constrained")
        ax = fig.subplots()
    if mat is None:
        ax.text(0.5, 0.5, "no condition cells", ha="center", transform=ax.transAxes)
        return ax
    M, rlabels, loads, groups, _ = mat
    fin = M[np.isfinite(M)]
    vmax = max(float(np.percentile(fin, 98)), 1e-9) if fin.size else 1.0
    ax.set_facecolor("0.93")
    im = ax.imshow(np.ma.masked_invalid(M), cmap="YlOrRd", vmin=0.0, vmax=vmax, aspect="auto",
                   interpolation="nearest")
    ax.set_yticks(range(len(rlabels)), rlabels, fontsize=TICK_PT)
    ax.set_xticks(range(len(loads)), [f"{fz / 1e3:.1f}" for fz in loads], fontsize=TICK_PT - 0.5,
                  rotation=90 if len(loads) > 30 else 0)
    ax.set_xlabel("load level Fz [kN], grouped by channel (and slip angle)", fontsize=LABEL_PT)
    if M.size <= 900 and M.shape[1] <= 40:
        for (i, j), v in np.ndenumerate(M):
            if np.isfinite(v):
                ax.text(j, i, f"{v:.1f}" if v < 99.5 else f"{v:.0f}", ha="center", va="center",
                        fontsize=TICK_PT - 1 if M.shape[1] > 24 else TICK_PT,
                        color="white" if v > 0.6 * vmax else "black")
    for name, j0, n in groups:
        if j0 > 0:
            ax.axvline(j0 - 0.5, color="k", lw=1.6)
        ax.text(j0 + (n - 1) / 2, -0.6, name, ha="center", va="bottom", fontsize=TICK_PT,
                transform=ax.transData, clip_on=False)
    ax.set_xlim(-0.5, len(loads) - 0.5)
    ax.set_ylim(len(rlabels) - 0.5, -0.5)
    cb = ax.figure.colorbar(im, ax=ax, extend="max", pad=0.01)
    cb.set_label("RMSE [% of the channel's peak at that load]", fontsize=LABEL_PT)
    cb.ax.tick_params(labelsize=TICK_PT)
    return ax


# ---------------------------------------------------------------------------------------- friction ellipse
def ellipse_curves(result, n: int = 60) -> list[dict]:
    """The model's Fx, Fy along each drive/brake sweep group's measured slip range.

    One entry per (condition level, load level, slip-angle level) of the longitudinal and combined sweeps with
    Fx and Fy measured: ``key`` (p, v, g), ``load``, ``fz``, ``alpha`` (the level's mean slip angle; 0 for pure
    slip), ``lo hi`` (the slip ratios the data cover there), ``a_lo a_hi`` (their slip angles) and the arrays
    ``kappa alpha_pts fx fy``.  The model is never drawn outside ``lo..hi`` or at a slip angle the data did not
    hold at that load.
    """
    d, sw = _samples(result, ("longitudinal", "combined"), None)
    if d.empty:
        return []
    d = d[np.isfinite(d["fx"].to_numpy(float)) & np.isfinite(d["fy"].to_numpy(float))]
    rows = []
    for k, g in d.groupby(["p", "v", "g", "load", "a"], sort=False):
        s = g["slip_ratio"].to_numpy(float)
        m = sw.loc[g["run"].unique()]
        pure = k[4] < 0
        rows.append({"key": k[:3], "load": k[3], "slip": "slip_ratio", "lo": float(np.min(s)),
                     "hi": float(np.max(s)), "fz": m["fz"].mean(), "camber": m["camber"].mean(),
                     "pressure": m["pressure"].mean(), "speed": m["speed"].mean(),
                     "alpha": 0.0 if pure else m["alpha"].mean(),
                     "a_lo": 0.0 if pure else float(g["slip_angle"].min()),
                     "a_hi": 0.0 if pure else float(g["slip_angle"].max())})
    return _model(result, rows, n)


def plot_friction_ellipse(result, ax=None, *, max_dots: int = 150, panel: int | None = None):
    """Fx against Fy of the drive/brake sweeps (pure and combined), one panel per condition level.

    Dots: data, coloured by load; lines: the model along each measured sweep group's slip-ratio range at its
    slip angle (:func:`ellipse_curves`); dashed circle: the data's largest |F|/Fz (99.5th percentile) at that
    load and condition times Fz -- never a friction circle of the fitted (possibly extrapolated) mu.  ``ax`` as
    :func:`plot_curves`.  Returns the Axes.
    """
    d, sw = _samples(result, ("longitudinal", "combined"), None)
    dims = ("p", "v", "g")
    if not d.empty:
        d = d[np.isfinite(d["fx"].to_numpy(float)) & np.isfinite(d["fy"].to_numpy(float))]
    if d.empty:
        if ax is None or _is_figure(ax):
            ax = _new_figure(ax, (5.0, 3.0)).subplots()
        a0 = np.atleast_1d(np.asarray(ax, dtype=object)).ravel()[0]
        a0.text(0.5, 0.5, "no sweeps with both Fx and Fy", ha="center", transform=a0.transAxes)
        return ax
    t, const = _titled(d, dims)
    single = _single_axes(ax)
    if single:
        idx, axes, fig = [_pick_nominal(result, t, panel)], np.array([ax], dtype=object), ax.figure
    else:
        title = ("Friction ellipse: data (dots); model only over the measured slip ranges (lines); dashed: the "
                 "data's largest |F|/Fz × Fz" + (f"; all at {const}" if const else ""))
        fig, axes, geom = _axes_grid(ax, t, dims, panel_w=3.2, square=True, title=title)
        idx = list(range(len(t)))
    colours = _load_colours(sw["load"].to_numpy())
    curves = ellipse_curves(result)
    dots = _thin(d, max_dots)
    mu_all = np.hypot(d["fx"], d["fy"]) / d["fz"].clip(lower=1.0)
    tt = np.linspace(0.0, 2 * np.pi, 181)
    lim = 0.0
    handles = {}
    for a, i in zip(axes, idx):
        cond = tuple(t.loc[i, list(dims)])
        m = np.all([d[k].to_numpy() == v for k, v in zip(dims, cond)], axis=0)
        md = np.all([dots[k].to_numpy() == v for k, v in zip(dims, cond)], axis=0)
        texts = []
        for lv, h in dots[md].groupby("load"):
            a.plot(h["fx"], h["fy"], ".", ms=2.5, alpha=0.4, color=colours[lv], rasterized=True)
        for lv in sorted(set(d.loc[m, "load"])):
            sel = m & (d["load"] == lv).to_numpy()
            mu = float(np.percentile(mu_all[sel], 99.5))
            fz = float(d.loc[sel, "fz"].mean())
            a.plot(mu * fz * np.cos(tt), mu * fz * np.sin(tt), "--", lw=0.9, color=colours[lv], alpha=0.8)
            lim = max(lim, mu * fz)
            texts.append((lv, mu))
        for r in curves:
            if tuple(r["key"]) == cond:
                (ln,) = a.plot(r["fx"], r["fy"], "-", lw=1.6, color=colours[r["load"]])
                handles.setdefault(r["load"], (ln, _fz_text(sw.loc[sw["load"] == r["load"], "fz_cell"].iloc[0])))
        for j, (lv, mu) in enumerate(texts):
            a.text(0.02, 0.98 - 0.085 * j, f"|F|/Fz ≤ {mu:.2f}", transform=a.transAxes, ha="left", va="top",
                   fontsize=TICK_PT - 0.5, color=colours[lv], bbox=dict(fc="white", ec="none", alpha=0.75, pad=0.8))
        a.axhline(0, color="0.6", lw=0.5, zorder=0)
        a.axvline(0, color="0.6", lw=0.5, zorder=0)
        _style(a, t.loc[i, "title"] if not single else _label(t.loc[i], dims))
    lim *= 1.08
    for a in axes:
        a.set_xlim(-lim, lim)
        a.set_ylim(-lim, lim)
        a.set_aspect("equal", adjustable="box")
    if single:
        axes[0].set_xlabel("Fx [N]", fontsize=LABEL_PT)
        axes[0].set_ylabel("Fy [N]", fontsize=LABEL_PT)
        return axes[0]
    _unify(axes, geom, nbins=4)
    if geom is not None:
        _finish(fig, geom, title, "Fx [N]", "Fy [N]", handles)
    return axes


# ---------------------------------------------------------------------------------------- report
def report_figures(result, r, *, max_table_rows: int = 60) -> None:
    """The figure sections of the MF report, then the condition table (collapsed, the worst cells first).

    Figures are made through the object API (:class:`matplotlib.figure.Figure`), embedded and dropped, so a
    report run neither touches pyplot nor keeps figures alive.
    """
    from matplotlib.figure import Figure

    vs = views(result)
    if vs:
        r.h2("Model over data at every condition")
        r.p("One figure per channel, one panel per condition level (pressure × camber × speed; slip angle too "
            "for combined slip), shared axes; loads are colours: lines are the model along the slip range the "
            "data cover at that load, dots the data.")
        for kind, ch, title in vs:
            fig = Figure()
            plot_curves(result, kind, ch, ax=fig)
            r.figure(fig, f"{title}: model (lines) over data (dots), one panel per condition level")
        r.h2("Residual maps (model − data) in slip × load")
        for kind, ch, title in vs:
            fig = Figure()
            plot_residual_map(result, kind, ch, ax=fig)
            r.figure(fig, f"{title}: mean residual per slip bin and load level, per condition level")
    r.h2("Error per condition cell")
    fig = Figure()
    plot_cells(result, ax=fig)
    r.figure(fig, "RMSE per condition cell in % of the channel's peak at that load (rows: conditions; columns: "
                  "loads, grouped by channel and slip angle; grey: not measured)")
    d = result.data.df
    if ((d["kind"] != "lateral") & np.isfinite(d["fx"]) & np.isfinite(d["fy"])).sum() >= 10:
        r.h2("Friction ellipse within the measured range")
        fig = Figure()
        plot_friction_ellipse(result, ax=fig)
        r.figure(fig, "Fx against Fy of the drive/brake sweeps per condition level: the model only over the slip "
                      "ratios and slip angles measured at each load; dashed: the data's largest |F|/Fz × Fz "
                      "(no Kamm circle of the fitted friction, which the data may not reach)")
    cells = result.cells
    if cells is not None and not cells.empty:
        worst = cells.sort_values("rmse_pct_load_peak", ascending=False).head(max_table_rows)
        more = len(cells) - len(worst)
        r.raw(f"<details><summary>Error per condition cell: table of {len(cells)} cells"
              + (f" (the {len(worst)} worst shown; all in cells.csv)" if more > 0 else "") + "</summary>")
        r.table(worst)
        r.raw("</details>")
