"""``tyrefit rig calibrate --static S --dynamic D --patch P --out RIG.json [--report DIR]``.

Fits the factor f of Komana et al. Eq. 1 (lateral displacement to slip angle)
on a tyre tested on both the static and the dynamic rig
(:func:`tyrefit.rig.calibrate`) and writes it as RIG.json, with the range of
Delta y / L, loads and pressures it is valid for.  ``tyrefit fit STTR.csv
--patch P --rig RIG.json`` then uses it for other tyres.
"""

from __future__ import annotations

import warnings
from pathlib import Path

from ..errors import DataError
from .outputs import check_outputs
from ..io.readers import read_data
from ..io.report import Report
from ..nomenclature import G0
from ..rig import calibrate, prepare_static_fit

__all__ = ["run", "calibration_report"]


def calibration_report(cal, static_ds, dynamic_ds, patch_ds, title: str = "Eq. 1 rig calibration"):
    """A :class:`tyrefit.io.report.Report` of a calibration: f, the static data mapped onto the dynamic curves."""
    import matplotlib
    from matplotlib.figure import Figure
    import numpy as np

    r = Report(title, cal.summary())
    r.h2("What the calibration means")
    r.p("Komana et al. Eq. 1: alpha = f(u) atan(u), u = Delta y / L (L: contact-patch length at the measured load). "
        "Calibrated form tan(alpha) = u / (n (1 + b u)): a rolling tyre at slip angle alpha carries its carcass "
        "deflected sideways by y with tan(alpha) = y / sigma, sigma = C_alpha / C_y the relaxation length, so n is "
        "the relaxation length in contact-patch lengths (f(0) = 1/n) and b lets it grow with the displacement. "
        "Monotone and bounded for every n > 0, b >= 0; n = 1, b = 0 is the uncalibrated f = 1.")
    r.table([{"n": cal.n, "n stderr": cal.n_stderr, "b": cal.b, "b stderr": cal.b_stderr, "f(0)": 1 / cal.n,
              "valid u up to": cal.u_range[1], "loads [kg]": f"{cal.fz_range[0] / G0:.0f}-{cal.fz_range[1] / G0:.0f}",
              "slip angles [deg]": f"{np.degrees(cal.slip_angle_range[0]):.1f}-"
                                   f"{np.degrees(cal.slip_angle_range[1]):.1f}",
              "rms mu residual": cal.rmse_mu, "samples": cal.points}])
    if cal.per_load:
        r.p("n fitted alone at each load (b = 0): if f depended on more than u = Delta y / L these would drift "
            "with load.")
        r.table([{"load [kg]": d["load_N"] / G0, "n alone": d["n_alone"], "u max": d["u_max"],
                  "samples": d["points"]} for d in cal.per_load])
    fig = Figure(figsize=(6.5, 4.2))
    ax = fig.subplots()
    cal.plot(ax)
    r.figure(fig, "Eq. 1: slip angle against Delta y / L, uncalibrated and calibrated; shaded: calibrated range.")
    samples = getattr(cal, "_samples", None)
    dyn = getattr(cal, "_dynamic", None)
    if samples is not None and dyn is not None:
        fig = Figure(figsize=(7, 4.6))
        ax = fig.subplots()
        colors = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            unc = prepare_static_fit(static_ds, patch_ds).converted
        for j, (run, g) in enumerate(samples.groupby("run")):
            c = colors[j % len(colors)]
            ax.plot(np.degrees(g["slip_angle"]), g["mu_static"], ".", ms=2.5, color=c)
            fz = float(g["fz"].mean())
            aa = np.radians(np.linspace(0, np.degrees(dyn.max_slip), 200))
            ax.plot(np.degrees(aa), dyn.mu(aa, np.full(aa.shape, fz)), "-", color=c, lw=1.5,
                    label=f"{fz / G0:.0f} kg")
            u = unc[(unc["run"] == run) & (unc["part"] == "rising")]
            ax.plot(np.degrees(u["slip_angle"]), u["mu"], ".", ms=1.5, color=c, alpha=0.25)
        ax.set_xlabel("slip angle [deg]")
        ax.set_ylabel("friction coefficient [-]")
        ax.set_xlim(0, np.degrees(dyn.max_slip) * 1.5)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, title="load")
        r.figure(fig, "Static samples (rising part) mapped with the calibrated Eq. 1 (dots) onto the dynamic rig's "
                      "curves (lines: Magic Formula per sweep); faint dots: the same samples with f = 1.")
    r.h2("Sources")
    r.bullets([f"{k}: {v}" for k, v in cal.source.items()])
    r.json_block(cal.to_dict(), "RIG.json")
    return r


def run(args) -> int:
    """Entry point of ``tyrefit rig``."""
    if args.rig_command != "calibrate":  # pragma: no cover - argparse restricts the choices
        raise DataError(f"unknown rig command {args.rig_command!r}; accepted: calibrate")

    out = Path(args.out)
    check_outputs(args)
    static = read_data(args.static, kind="static")
    dynamic = read_data(args.dynamic)
    if dynamic.kind != "slip_angle":
        raise DataError(f"{args.dynamic}: is a {dynamic.kind} test; --dynamic needs slip-angle sweeps "
                        "('slip_angle', 'fy', 'fz')")
    patch = read_data(args.patch, kind="patch")
    cal = calibrate(static, dynamic, patch)
    cal.to_json(out, force=args.force)
    print(cal.summary())
    print(f"wrote {out}")
    if args.report:
        r = calibration_report(cal, static, dynamic, patch)
        r.save(args.report, force=args.force)
        print(f"wrote {Path(args.report) / 'index.html'}")
    return 0
