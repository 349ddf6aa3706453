"""The MF fit report shows every condition (issue 23, item 6): tyrefit.fitting.mf_figures.

A FitResultMF of a 3-pressure x 3-camber set of pure and combined sweeps (the generating tyre as the
"fitted" one, so no fit is run): one panel per condition level for every channel view, a residual map
per channel, the error per condition cell as a heat map, the friction ellipse only inside the measured
slip range, figures through pyplot when no Axes are given, and a report that leaves no pyplot figure.
"""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import QuadMesh  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from tyrefit.fitting import mf_figures as M  # noqa: E402
from tyrefit.fitting.mf import prepare_mf_data  # noqa: E402
from tyrefit.fitting.mf_result import FitResultMF  # noqa: E402
from tyrefit.io.report import Report  # noqa: E402
from tyrefit.synthetic import ttc_drivebrake as gen  # noqa: E402

PRESSURES = (220e3, 260e3, 300e3)
CAMBERS = (0.0, 2.0, 4.0)
ALPHAS = (0.0, -3.0, -6.0)


def _result(pressures, cambers):
    p = gen.published_mf61()
    f = p["FNOMIN"]
    df = gen.make_sweeps(p, loads=[0.5 * f, f], pressures=list(pressures), cambers_deg=list(cambers),
                         slip_angles_deg=list(ALPHAS), n_points=31, seed=3)
    # the pressure creeps up to 3 kPa within a level (tread temperature): still one level, one panel
    creep = (df["run"].to_numpy() % 4) * 1e3
    df["pressure"] = df["pressure"] + creep
    data = prepare_mf_data(df)
    return FitResultMF.build(p, {}, data, model="mf61", version="6.1", cost="l2", notes=[], tyre_info={},
                             seconds=0.0)


@pytest.fixture(scope="module")
def result():
    return _result(PRESSURES, CAMBERS)


def _n_panels(kind):
    return len(PRESSURES) * len(CAMBERS) * (len([a for a in ALPHAS if a]) if kind == "combined" else 1)


def test_one_panel_per_condition_level_for_every_channel(result):
    views = M.views(result)
    assert {(k, c) for k, c, _ in views} >= {("longitudinal", "fx"), ("lateral", "fy"), ("lateral", "mz"),
                                              ("lateral", "mx"), ("combined", "fx"), ("combined", "fy")}
    for kind, ch, _ in views:
        fig = Figure()
        axes = M.plot_curves(result, kind, ch, ax=fig)
        titles = [a.get_title() for a in axes]
        assert len(axes) == _n_panels(kind), (kind, ch, titles)
        assert len(set(titles)) == len(titles)                       # every condition once
        assert {a for a in fig.axes if a.get_visible()} == set(axes)
        for t in titles:
            assert "kPa" in t and "γ" in t and ("α" in t) == (kind == "combined"), t
        labels = [t.split(" kPa")[0].split(" ")[-1] for t in titles]   # the pressure level of each panel
        assert sorted(float(x) for x in set(labels)) == pytest.approx([221.5, 261.5, 301.5], abs=1.0)
        assert all(labels.count(x) == _n_panels(kind) // 3 for x in labels)
        # model lines in every panel, one per load; the legend names the loads; titles legible
        for a in axes:
            assert sum(len(ln.get_xdata()) > 2 and ln.get_linestyle() == "-" for ln in a.get_lines()) == 2
            assert a.title.get_fontsize() >= 9
        assert [t.get_text() for t in fig.legends[0].get_texts()] == ["Fz 3.38 kN", "Fz 6.75 kN"]
        xl = axes[0].get_xlim()
        assert all(a.get_xlim() == xl for a in axes)                  # shared axes


def test_residual_map_per_channel(result):
    for kind, ch, _ in M.views(result):
        fig = Figure()
        axes = M.plot_residual_map(result, kind, ch, ax=fig)
        assert len(axes) == _n_panels(kind)
        meshes = [c for a in axes for c in a.collections if isinstance(c, QuadMesh)]
        assert len(meshes) == len(axes)
        norm = meshes[0].norm
        assert norm.vmin == pytest.approx(-norm.vmax) and meshes[0].get_cmap().name == "RdBu_r"
        cbar = [a for a in fig.axes if a not in set(axes)]
        assert len(cbar) == 1 and f"[{M._UNIT[ch]}]" in cbar[0].get_ylabel()
        # residual = model - data: the map's mean equals the data's mean residual within the binned range
        d = result.data.df
        d = d[d["kind"] == kind]
        assert np.isfinite(meshes[0].get_array()).any()
        assert np.nanmax(np.abs(np.ma.filled(meshes[0].get_array(), np.nan))) <= \
            np.nanmax(np.abs(d[f"model_{ch}"] - d[ch])) + 1e-9


def test_cells_are_a_heat_map_of_clustered_conditions(result):
    c = result.cells
    assert sorted(c["pressure [kPa]"].unique()) == pytest.approx([221.5, 261.5, 301.5], abs=1.0)
    assert sorted(c["camber [deg]"].unique()) == pytest.approx(list(CAMBERS), abs=0.05)
    ax = M.plot_cells(result, ax=Figure())
    # no lines join unrelated cells: the only lines are the vertical separators between channel groups
    assert all(np.ptp(ln.get_xdata()) == 0 for ln in ax.get_lines())
    M_, rows, loads, groups, _ = M._cells_matrix(result)
    assert M_.shape == (9, len(loads)) and len(rows) == 9
    assert [g[0] for g in groups][:4] == ["Fx pure", "Fy pure", "Mz pure", "Mx pure"]
    assert np.isfinite(M_).all()


def test_friction_ellipse_model_inside_the_measured_slip_range(result):
    d = result.data.df
    sw = M.sweep_levels(d)
    dd = d[d["kind"] != "lateral"].join(sw[["load", "p", "v", "g", "a"]], on="run")
    curves = M.ellipse_curves(result)
    assert len(curves) == 9 * 2 * 3                                   # conditions x loads x slip angles
    for r in curves:
        g = dd[(dd["p"] == r["key"][0]) & (dd["v"] == r["key"][1]) & (dd["g"] == r["key"][2])
               & (dd["load"] == r["load"])]
        assert len(g)
        lo, hi = g["slip_ratio"].min(), g["slip_ratio"].max()
        assert lo - 1e-12 <= r["kappa"].min() and r["kappa"].max() <= hi + 1e-12
        a = r["alpha_pts"]
        assert g["slip_angle"].min() - 0.5 * math.pi / 180 <= a.min() and \
            a.max() <= g["slip_angle"].max() + 0.5 * math.pi / 180
        same = g[np.abs(g["slip_angle"] - a[0]) < 0.5 * math.pi / 180]
        assert len(same) and same["slip_ratio"].min() - 1e-12 <= r["kappa"].min() \
            and r["kappa"].max() <= same["slip_ratio"].max() + 1e-12
    axes = M.plot_friction_ellipse(result, ax=Figure())
    assert len(axes) == 9
    fmax = float(np.hypot(d["fx"], d["fy"]).max())
    for a in axes:
        for ln in a.get_lines():
            if ln.get_linestyle() == "--":                           # the data's largest |F|/Fz x Fz
                r = np.hypot(ln.get_xdata(), ln.get_ydata())
                assert r.max() <= 1.02 * fmax
        assert any("|F|/Fz" in t.get_text() for t in a.texts)
    # no Kamm circle of the fitted friction: a tyre with PDX1 x 4 draws the same circles
    big = FitResultMF(**{**result.__dict__, "params": dict(result.params, PDX1=4 * result.params["PDX1"])})
    circ = lambda ax: [ln.get_xdata().max() for ln in ax.get_lines() if ln.get_linestyle() == "--"]  # noqa: E731
    assert circ(M.plot_friction_ellipse(big, ax=Figure())[0]) == pytest.approx(circ(axes[0]))


def test_pyplot_figures_and_single_axes(result):
    before = set(plt.get_fignums())
    try:
        axes = result.plot_curves("lateral", "fy")
        assert plt.fignum_exists(axes[0].figure.number)                # a pyplot figure: plt.show() shows it
        assert len(axes) == 9
        ax = plt.figure().subplots()
        out = result.plot_curves("lateral", "fy", ax=ax)
        assert out is ax and "kPa" in ax.get_title() and len(ax.get_lines()) >= 2
        assert result.plot_friction_ellipse(ax=plt.figure().subplots()).get_title()
        assert result.plot_cells().figure.number in plt.get_fignums()
    finally:
        for n in set(plt.get_fignums()) - before:
            plt.close(n)


def test_report_every_condition_then_the_table_collapsed():
    result = _result(PRESSURES[1:2], CAMBERS[:2])                     # a small report: 2 panels a channel
    before = set(plt.get_fignums())
    r = Report("MF")
    result.report_blocks(r)
    html = r.html()
    n_views = len(M.views(result))
    assert html.count("<img ") == 2 * n_views + 2                     # curves, residual maps, cells, ellipse
    assert set(plt.get_fignums()) == before                           # nothing left open
    i_table = html.index("<details><summary>Error per condition cell")
    assert i_table > html.rindex("<img ")                             # the table after the figures, collapsed
    assert html.count("<tr>", i_table, html.index("</details>", i_table)) <= 61
