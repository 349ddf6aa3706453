"""Where the model fails: residual tables and plots of a :class:`Diagnosis`.

Every plot function takes ``ax=None`` (or ``fig=None`` for multi-panel views),
labels axes in display units (kN, deg, kPa) and returns what it drew on.
"""

from __future__ import annotations

import matplotlib
import numpy as np
from matplotlib.figure import Figure
import pandas as pd

from ..effects.signatures import SignatureView, sweep_characteristics
from ..io.facets import _decimals, format_condition

__all__ = ["even_odd", "plot_waterfall", "plot_residual_maps", "plot_even_odd", "plot_fit",
           "plot_cell_rmse", "signature_view", "facets"]

_DEG = np.pi / 180.0


def even_odd(slip_angle, resid, sweep, n_bins: int = 12) -> pd.DataFrame:
    """Even and odd parts of the residual along each sweep.

    The residual of each sweep is averaged in bins of |slip angle| on each
    side; even = (r(+a) + r(-a))/2, odd = (r(+a) - r(-a))/2.  An even
    residual points at shifts (offsets, camber thrust: Fy is odd in slip, a
    shift adds an even part); an odd residual at stiffness, friction or shape
    errors.

    Returns
    -------
    DataFrame
        One row per sweep: ``sweep``, ``even_rms``, ``odd_rms`` [N].
    """
    a = np.asarray(slip_angle, dtype=float)
    r = np.asarray(resid, dtype=float)
    sw = np.asarray(sweep)
    rows = []
    for g in np.unique(sw):
        m = sw == g
        ag, rg = a[m], r[m]
        reach = min(-ag.min(), ag.max())
        if reach <= 0:
            rows.append({"sweep": int(g), "even_rms": np.nan, "odd_rms": np.nan})
            continue
        edges = np.linspace(0, reach, n_bins + 1)
        ev, od = [], []
        for lo, hi in zip(edges[:-1], edges[1:]):
            p = (ag > lo) & (ag <= hi)
            q = (ag < -lo) & (ag >= -hi)
            if p.any() and q.any():
                mp, mq = rg[p].mean(), rg[q].mean()
                ev.append(0.5 * (mp + mq))
                od.append(0.5 * (mp - mq))
        rows.append({"sweep": int(g), "even_rms": float(np.sqrt(np.mean(np.square(ev)))) if ev else np.nan,
                     "odd_rms": float(np.sqrt(np.mean(np.square(od)))) if od else np.nan})
    return pd.DataFrame(rows)


def plot_waterfall(diagnosis, ax=None):
    """RMSE and held-out RMSE [N] from the start model to the final one, against the noise floor."""
    if ax is None:
        ax = Figure(figsize=(6.5, 3.6)).subplots()
    steps = diagnosis.steps
    labels = ["start\n" + ("+".join(diagnosis.start) or "base PAC89")] + [f"+\n{s.added}" for s in steps[1:]]
    x = np.arange(len(steps))
    ax.bar(x - 0.18, [s.rmse for s in steps], 0.36, label="RMSE (all sweeps)", color="#4c78a8")
    ax.bar(x + 0.18, [s.rmse_heldout for s in steps], 0.36, label="RMSE (held-out sweeps)", color="#f58518")
    ax.axhline(diagnosis.noise_floor, color="k", ls="--", lw=1, label=f"noise floor {diagnosis.noise_floor:.1f} N")
    for i, s in enumerate(steps):
        ax.annotate(f"{s.rmse_heldout:.0f}", (i + 0.18, s.rmse_heldout), ha="center", va="bottom", fontsize=7)
    ax.set_xticks(x, labels, fontsize=8)
    ax.set_ylabel("lateral force RMSE [N]")
    ax.set_title("Error from the start model to the final model", fontsize=10)
    ax.legend(fontsize=7)
    return ax


def facets(data, max_facets: int | None = None) -> list[tuple[int, int | None]]:
    """(camber level, pressure level) pairs to show: every pair present in the data, pressure-major.

    No level is dropped (a report that hides a pressure hides where the model fails); ``max_facets`` is
    kept for callers and ignored.
    """
    cam = np.asarray(data.level_index["camber"])
    if "pressure" in data.levels:
        pr = np.asarray(data.level_index["pressure"])
        return [(int(c), int(p)) for p, c in sorted(set(zip(pr.tolist(), cam.tolist())))]
    return [(int(c), None) for c in sorted(set(cam.tolist()))]


def _facet_mask(data, c, p):
    m = data.level_index["camber"] == c
    if p is not None:
        m &= data.level_index["pressure"] == p
    return m


def _facet_title(data, c, p):
    t = format_condition("camber", float(data.levels["camber"][c]), _decimals("camber", data.levels["camber"]))
    if p is not None:
        t += ", " + format_condition("pressure", float(data.levels["pressure"][p]),
                                     _decimals("pressure", data.levels["pressure"]))
    return t


def plot_residual_maps(diagnosis, steps=(0, -1), fig=None, n_slip_bins: int = 24, *,
                       slip_label: str = "slip angle [deg]", slip_factor: float = 1.0 / _DEG, unit: str = "N"):
    """Residual maps over slip and load, faceted by camber and pressure.

    One row per step (start model, final model), one column per facet; the
    colour is the mean residual (model - data) [``unit``] in each slip bin and load
    level, on one symmetric colour scale shared by every panel.  The slip axis
    shows ``d.inputs.slip_angle`` times ``slip_factor`` (a channel diagnosis
    passes its slip ratio in percent, :mod:`tyrefit.diagnose.channels`).
    """
    d = diagnosis.data
    fc = facets(d)
    sts = [diagnosis.steps[i] for i in steps]
    ext = np.max(np.abs(d.inputs.slip_angle))
    edges = np.linspace(-ext, ext, n_slip_bins + 1)
    nl = len(d.levels["fz"])
    grids = []
    for st in sts:
        row = []
        for c, p in fc:
            m = _facet_mask(d, c, p)
            img = np.full((nl, n_slip_bins), np.nan)
            b = np.clip(np.digitize(d.inputs.slip_angle[m], edges) - 1, 0, n_slip_bins - 1)
            lv = d.level_index["fz"][m]
            r = st.fit.resid[m]
            sums = np.zeros((nl, n_slip_bins))
            cnt = np.zeros((nl, n_slip_bins))
            np.add.at(sums, (lv, b), r)
            np.add.at(cnt, (lv, b), 1)
            ok = cnt > 0
            img[ok] = sums[ok] / cnt[ok]
            row.append(img)
        grids.append(row)
    allv = np.concatenate([g.ravel() for row in grids for g in row])
    vmax = float(np.nanpercentile(np.abs(allv), 98)) if np.isfinite(allv).any() else 1.0
    vmax = max(vmax, 1e-9)
    # one block per model (start, final), each a grid a report shows at its width: a column per camber level,
    # a row per pressure level (combinations the record lacks left empty); titles on the edges, not per panel
    cams = sorted({c for c, _ in fc})
    prs = sorted({p for _, p in fc}, key=lambda v: -1 if v is None else v)
    wrap = max(1, min(len(cams), 5))
    ncol = wrap
    rows_per_p = -(-len(cams) // wrap)
    nrow_b = rows_per_p * len(prs)
    if fig is None:
        fig = Figure(figsize=(min(2.5 * ncol + 2.2, 13.0), (2.1 * nrow_b + 0.8) * len(sts)), layout="constrained")
    blocks = fig.subfigures(len(sts), 1, squeeze=False)[:, 0] if len(sts) > 1 else [fig]
    im = None
    for i, st in enumerate(sts):
        name = "start model" if st is diagnosis.steps[0] else ("final model" if st is diagnosis.steps[-1]
                                                               else f"+ {st.added}")
        sub = blocks[i]
        axes = sub.subplots(nrow_b, ncol, squeeze=False, sharex=True, sharey=True)
        used = np.zeros(axes.shape, bool)
        for j, (c, p) in enumerate(fc):
            k = cams.index(c)
            r, col = prs.index(p) * rows_per_p + k // wrap, k % wrap
            ax = axes[r, col]
            used[r, col] = True
            im = ax.imshow(grids[i][j], aspect="auto", origin="lower", cmap="RdBu_r", vmin=-vmax, vmax=vmax,
                           extent=(edges[0] * slip_factor, edges[-1] * slip_factor, -0.5, nl - 0.5),
                           interpolation="nearest")
            ax.set_yticks(range(nl), [f"{v / 1e3:.1f}" for v in d.levels["fz"]], fontsize=9)
            ax.tick_params(axis="x", labelsize=9)
            if r % rows_per_p == 0 or rows_per_p > 1:
                ax.set_title(format_condition("camber", float(d.levels["camber"][c]),
                                              _decimals("camber", d.levels["camber"])), fontsize=10)
            if col == 0:
                lab = "Fz [kN]"
                if p is not None:
                    lab = format_condition("pressure", float(d.levels["pressure"][p]),
                                           _decimals("pressure", d.levels["pressure"])) + "\n" + lab
                ax.set_ylabel(lab, fontsize=10)
        for ax in axes[~used]:
            ax.set_visible(False)
        for ax in axes[-1]:
            ax.set_xlabel(slip_label, fontsize=10)
        sub.suptitle(name, fontsize=12, fontweight="bold")
        cb = sub.colorbar(im, ax=axes, shrink=0.8)  # the same scale in every block
        cb.set_label(f"mean residual model - data [{unit}]", fontsize=10)
    return fig


def plot_even_odd(diagnosis, steps=(0, -1), ax=None):
    """RMS of the even and odd residual parts of every sweep, start vs final model."""
    if ax is None:
        ax = Figure(figsize=(7, 3.4)).subplots()
    d = diagnosis.data
    x = d.inputs
    order = np.argsort(d.sweep_cells(), kind="stable")
    for k, (i, style) in enumerate(zip(steps, ("o", "s"))):
        st = diagnosis.steps[i]
        eo = even_odd(x.slip_angle, st.fit.resid, d.sweep).set_index("sweep").reindex(range(d.n_sweeps))
        name = "start" if k == 0 else "final"
        ax.plot(np.arange(d.n_sweeps), eo["even_rms"].to_numpy()[order], style, ms=3.5, mfc="none" if k == 0 else None,
                color="#e45756", label=f"even part, {name}")
        ax.plot(np.arange(d.n_sweeps), eo["odd_rms"].to_numpy()[order], style, ms=3.5, mfc="none" if k == 0 else None,
                color="#4c78a8", label=f"odd part, {name}")
    ax.axhline(diagnosis.noise_floor, color="k", ls="--", lw=0.8, label="noise floor")
    ax.set_yscale("log")
    ax.set_xlabel("sweep (ordered by condition cell)")
    ax.set_ylabel("RMS of residual part [N]")
    ax.set_title("Even (shift-like) and odd (stiffness/friction-like) residual parts per sweep", fontsize=9)
    ax.legend(fontsize=6.5, ncol=2)
    return ax


def plot_fit(diagnosis, facet: tuple[int, int | None], steps=(0, -1), ax=None):
    """Measured Fy against slip angle for one camber/pressure facet, with the start and final models."""
    if ax is None:
        ax = Figure(figsize=(4.2, 3.2)).subplots()
    d = diagnosis.data
    c, p = facet
    m = _facet_mask(d, c, p)
    cmap = matplotlib.colormaps["viridis"]
    nl = len(d.levels["fz"])
    for k in range(nl):
        mk = m & (d.level_index["fz"] == k)
        if not mk.any():
            continue
        col = cmap(k / max(nl - 1, 1))
        a = d.inputs.slip_angle[mk]
        o = np.argsort(a)
        ax.plot(a[o] / _DEG, d.fy[mk][o], ".", ms=2, color=col, alpha=0.5)
        for i, ls in zip(steps, (":", "-")):
            st = diagnosis.steps[i]
            yhat = st.fit.resid[mk] + d.fy[mk]
            ax.plot(a[o] / _DEG, yhat[o], ls, color=col, lw=1.1,
                    label=(f"{d.levels['fz'][k] / 1e3:.1f} kN" if ls == "-" else None))
    ax.set_xlabel("slip angle [deg]")
    ax.set_ylabel("Fy [N] (ISO-W)")
    ax.set_title(_facet_title(d, c, p) + "  (dotted: start, solid: final)", fontsize=8)
    ax.legend(fontsize=6)
    return ax


def plot_cell_rmse(diagnosis, steps=(0, -1), ax=None):
    """RMSE per condition cell [N], start vs final model, with the noise floor."""
    if ax is None:
        ax = Figure(figsize=(7, 3.2)).subplots()
    for i, (k, col) in enumerate(zip(steps, ("#bbbbbb", "#4c78a8"))):
        t = diagnosis.cell_table(k)
        ax.bar(np.arange(len(t)) + (i - 0.5) * 0.4, t["rmse_N"], 0.4, color=col,
               label="start" if i == 0 else "final")
    ax.axhline(diagnosis.noise_floor, color="k", ls="--", lw=0.8, label="noise floor")
    ax.set_xlabel("condition cell (load fastest, then camber, pressure)")
    ax.set_ylabel("RMSE [N]")
    ax.set_yscale("log")
    ax.legend(fontsize=7)
    return ax


def signature_view(diagnosis, effect_id: str) -> SignatureView:
    """Characteristics of the data and of the models just before and after ``effect_id`` was added."""
    d = diagnosis.data
    x = d.inputs
    k = next(i for i, s in enumerate(diagnosis.steps) if s.added == effect_id)
    before, after = diagnosis.steps[k - 1], diagnosis.steps[k]

    def ch(fy):
        return sweep_characteristics(d.sweep, x.fz, x.slip_angle, fy, x.camber, x.pressure, x.speed)

    return SignatureView(data=ch(d.fy), before=ch(before.fit.resid + d.fy), after=ch(after.fit.resid + d.fy),
                         rated_load=x.rated_load, before_label=f"without {effect_id}",
                         after_label=f"with {effect_id}")
