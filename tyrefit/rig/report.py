"""The report of the static-rig pipeline: its figures and its section of an HTML report.

Used by :class:`tyrefit.rig.pipeline.StaticFitInput` (``plot_converted``, ``report_section``); each
function takes the pipeline's result first.  The section shows every step of Komana, Els and Becker's
static-rig route to a rolling-tyre model: the contact patch against load and pressure (their Fig. 2),
the vertical stiffness with its loading/unloading hysteresis (Fig. 3), the static lateral pushes with the
measured load falling (Fig. 5), Eq. 1 (lateral displacement to slip angle) with the rig calibration, and
the converted data that feed the PAC89 fit.  Figures are built through matplotlib's object API, so a
report run never touches the user's pyplot state.
"""

from __future__ import annotations

import numpy as np

from ..nomenclature import G0
from .static import __doc__ as static_doc

__all__ = ["plot_converted", "report_section"]


def plot_converted(inp, ax=None, model=None):
    """Friction coefficient against converted slip angle per load; samples not used in grey.

    ``inp``: the :class:`~tyrefit.rig.pipeline.StaticFitInput`; ``ax``: the Axes to draw on (None: a new
    :class:`matplotlib.figure.Figure`); returns the Axes.

    ``model`` (a :class:`Pac89Tyre` or a list of ``(label, tyre)``) is drawn at each run's mean load.
    """
    import matplotlib
    from matplotlib.figure import Figure

    if ax is None:
        ax = Figure(figsize=(7, 4.6)).subplots()
    colors = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
    used = "rising" if inp.part == "peak" else None
    models = [] if model is None else (model if isinstance(model, list) else [("model", model)])
    styles = ["-", "--", ":", "-."]
    for j, (run, g) in enumerate(inp.converted.groupby("run", sort=True)):
        c = colors[j % len(colors)]
        a = np.degrees(np.abs(g["slip_angle"]))
        inuse = g["part"] == used if used else np.ones(len(g), bool)
        ax.plot(a[inuse], g["mu"][inuse], ".", ms=2.5, color=c)
        ax.plot(a[~inuse], g["mu"][~inuse], ".", ms=2.5, color="0.75")
        ax.plot([], [], "o", color=c, label=f"{g['load'].mean() / G0 if 'load' in g else g['fz'].mean() / G0:.0f} kg")
        fz = float(g["fz"].mean())
        aa = np.linspace(0, max(a.max(), 1.0), 200)
        for k, (lab, tyre) in enumerate(models):
            mu = -tyre.fy(fz, np.radians(aa)) / fz
            ax.plot(aa, mu, styles[k % 4], color=c, lw=1.3, label=lab if j == 0 else None)
    ax.set_xlabel("slip angle from Eq. 1 [deg]")
    ax.set_ylabel("friction coefficient Fy/Fz [-]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    return ax


def report_section(inp, report, model=None) -> None:
    """Append the static-rig pipeline to a :class:`tyrefit.io.report.Report`.

    Contact patch (Komana et al. Fig. 2), vertical stiffness (Fig. 3), the
    static pushes (Fig. 5), Eq. 1 and the converted data, the part used and every
    note and range warning.  ``model``: optional fitted tyre(s) to overlay.
    """
    from matplotlib.figure import Figure

    r = report
    r.h2("Static tyre test rig (STTR) pipeline")
    r.p("Komana, Els and Becker: contact patch -> vertical stiffness -> static lateral push -> "
        "Eq. 1 (lateral displacement to slip angle with the patch length L) -> PAC89 fit on mu = Fy/Fz.")
    for w in inp.warnings:
        r.p("Range warning: " + w, cls="warn")
    r.h3("Contact patch")
    r.table(inp.patch.table(), digits=4)
    if inp.patch.laws:
        r.p(f"Pressure law across {len(inp.patch.fits)} pressures (reference {inp.patch.p_ref / 1e5:.2f} bar): "
            "power law theta_ref (p/p_ref)^m for gradients, breakpoints and widths; linear for intercepts.")
        r.table(inp.patch.laws_table(), digits=4)
    fig = Figure(figsize=(13, 3.8))
    axes = fig.subplots(1, 3)
    inp.patch.plot(getattr(inp, "_patch_df", None), axes=axes)
    r.figure(fig, "Contact-patch length, width and area against load per pressure (cf. Komana et al., Fig. 2); "
                  "dotted lines: fitted shoulder (breakpoint) loads.")
    if inp.vertical is not None:
        r.h3("Vertical stiffness")
        r.table(inp.vertical.table(inp.patch), digits=4)
        r.p(f"VERTICAL_STIFFNESS = {inp.vertical_stiffness * 1e-3:.1f} N/mm at {inp.fnomin / G0:.0f} kg "
            "(mean of the loading and unloading tangents: the elastic middle of the hysteresis loop); "
            f"the Chrono JSON gets the loop's middle as a {len(inp.vertical_curve or [])}-point curve.")
        fig = Figure(figsize=(6.5, 4.5))
        ax = fig.subplots()
        inp.vertical.plot(getattr(inp, "_vertical_df", None), ax=ax)
        r.figure(fig, "Vertical force against deflection, loading (solid) and unloading (dashed) (cf. Fig. 3).")
    r.h3("Static lateral push")
    r.table(inp.static.table(), digits=4)
    r.p(f"LATERAL_STIFFNESS = {inp.lateral_stiffness * 1e-3:.1f} N/mm at {inp.fnomin / G0:.0f} kg "
        "(tangent at zero displacement of Fy = a + k dy + c dy^3 fitted up to half the static peak force, "
        "interpolated in load).  C from Eq. 2 uses the sliding level as the asymptote y_a.")
    fig = Figure(figsize=(12, 4.2))
    axes = fig.subplots(1, 2)
    inp.static.plot(axes[0], "mu")
    inp.static.plot(axes[1], "fz")
    r.figure(fig, "Left: mu = Fy/Fz with the measured load against lateral displacement; triangles: static "
                  "peaks, dashed: sliding levels (cf. Fig. 5).  Right: the measured load falls during the push.")
    r.h3("Eq. 1: displacement to slip angle")
    r.p(inp.rig.summary() + ".  L is the contact-patch length at each sample's measured load and the test "
        "pressure.  n is the relaxation length in patch lengths: a rolling tyre at slip angle alpha carries "
        "its carcass deflected sideways by y with tan(alpha) = y / sigma, sigma = C_alpha / C_y.")
    fig = Figure(figsize=(6.5, 4.2))
    ax = fig.subplots()
    inp.rig.plot(ax, u_max=max(1.2 * float(np.nanmax(np.abs(inp.converted["u"]))), 0.1))
    r.figure(fig, "Eq. 1: slip angle against u = Delta y / L, uncalibrated (f = 1) and with the rig calibration.")
    r.h3(f"Part of the static curve used: '{inp.part}'")
    doc = static_doc.split("Which part of the curve feeds the rolling-tyre fit")[1].split("Either way")[0]
    r.raw("<pre style='white-space:pre-wrap'>" + doc.strip("\n -") + "</pre>")
    n_r = int((inp.converted["part"] == "rising").sum())
    r.p(f"{len(inp.data.df) if hasattr(inp.data, 'df') else len(inp.data)} samples feed the fit "
        f"({n_r} rising, {len(inp.converted) - n_r} sliding in the whole push).")
    fig = Figure(figsize=(7, 4.6))
    ax = fig.subplots()
    plot_converted(inp, ax, model)
    r.figure(fig, "Converted static data: mu against the slip angle of Eq. 1 per load; grey samples are not "
                  "used with this part" + ("; lines: fitted model(s)" if model is not None else "") + ".")
    if inp.notes:
        r.h3("Notes")
        r.bullets(inp.notes)

