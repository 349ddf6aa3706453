"""``tyrefit slip DATA [--json OUT.json] [--report DIR]``: longitudinal slip characteristics (Ghasemi et al. 2021).

Reads slip-ratio data (:func:`tyrefit.io.readers.read_data`), fits
``mu = mu_p (1 - exp(-k s))`` per load level, and reports the characteristic
curvature, slip and friction (Ghasemi et al., Eq. 15-17), the mobility
indices (Eq. 24-27) and, when the file has ``torque`` and ``rolling_radius``
columns, the rolling radius against torque and the longitudinal elasticity
factor (Eq. 19-20).

JSON (DESIGN): ``{"mu_peak", "k", "characteristic_curvature",
"characteristic_slip", "characteristic_mu"}`` for one load, or
``{"loads": [{"fz", "mu_peak", ...}, ...]}`` for several; extra keys: standard
errors, ``rmse_mu``, ``n_points`` and ``rolling_radius``.
"""

from __future__ import annotations

import json
import math

import numpy as np

from ..errors import DataError
from ..io.outputs import write_text
from .outputs import check_outputs
from ..io.readers import read_data
from ..io.report import Report
from ..models import slip as sl
from ..fitting.slip import SlipAnalysis, analyse_slip

__all__ = ["run", "slip_report"]


def _jsonable(x):
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, (float, np.floating)):
        v = float(x)
        return v if math.isfinite(v) else None
    if isinstance(x, np.integer):
        return int(x)
    return x


def _summary(a: SlipAnalysis) -> str:
    lines = [f"slip characteristics (Ghasemi et al. 2021), nu_c = {a.nu_c:g}"]
    for f in a.fits:
        lab = f"Fz {f.fz / 1e3:6.2f} kN" if f.fz is not None else "all"
        lines.append(f"  {lab}: mu_p = {f.mu_peak:.4f} +/- {f.mu_peak_stderr:.4f}, k = {f.k:.3f} +/- {f.k_stderr:.3f}, "
                     f"s_c = {f.characteristic_slip:.4f}, mu_c = {f.characteristic_mu:.4f}, "
                     f"rmse(mu) = {f.rmse:.4f} ({f.n} points)")
    if a.radius is not None:
        r = a.radius
        lines.append(f"  rolling radius: r0 = {r.r0 * 1e3:.2f} mm, lambda_w(0) = {r.lambda_0:.4g} m/(N m), "
                     f"rmse = {r.rmse * 1e3:.3f} mm ({r.n} points)")
    return "\n".join(lines)


def slip_report(a: SlipAnalysis, title: str = "Slip characteristics (Ghasemi et al. 2021)"):
    """An HTML :class:`tyrefit.io.report.Report` of a slip analysis."""
    from matplotlib.figure import Figure

    r = Report(title, subtitle=f"data: {a.source}" if a.source else None)
    r.p("Longitudinal friction against slip, fitted with mu = mu_p (1 - exp(-k s)) (Ghasemi et al., Eq. 8). "
        f"The characteristic slip s_c is where the curvature d2mu/ds2 = -k^2 mu_p exp(-k s) (Eq. 15) reaches "
        f"nu_c = {a.nu_c:g}: s_c = ln(k^2 mu_p / -nu_c) / k (Eq. 16), mu_c = mu_p + nu_c / k^2 (Eq. 17). "
        "Beyond s_c the curve is quasi-linear: more slip buys little traction and the wheel is about to lose "
        "mobility, so s_c is the slip limit of a traction controller.")
    if a.fits:
        rows = [{"Fz [kN]": (f.fz or float("nan")) / 1e3, "mu_p": f.mu_peak, "+/-": f.mu_peak_stderr, "k": f.k,
                 "+/- ": f.k_stderr, "s_c": f.characteristic_slip, "mu_c": f.characteristic_mu,
                 "rmse(mu)": f.rmse, "points": f.n} for f in a.fits]
        r.h2("Friction-slip law per load").table(rows)
        fig = Figure(figsize=(7, 4.5))
        ax = fig.subplots()
        a.plot_friction(ax)
        r.figure(fig, "Friction coefficient against slip: data, fitted Eq. 8, characteristic points (circles).")
        fig = Figure(figsize=(7, 4.5))
        ax = fig.subplots()
        a.plot_curvature(ax)
        r.figure(fig, "Curvature of the fitted laws (Eq. 15); dotted lines mark s_c where it meets nu_c "
                 "(Ghasemi et al., Fig. 5).")
        fig = Figure(figsize=(11, 4))
        axs = fig.subplots(1, 2)
        a.plot_mobility(axs[0], modified=False)
        a.plot_mobility(axs[1], modified=True)
        r.figure(fig, "Wheel mobility-agility index mu (1 - mu/mu_p) (Eq. 26, left) and its modified form "
                 "mu (1 - mu/mu_c) up to s_c (Eq. 27, right): Ghasemi et al., Fig. 7-8.")
        best = []
        for f in a.fits:
            s = np.linspace(0, f.characteristic_slip, 400)
            w = sl.modified_mobility_agility_index(s, f.mu_peak, f.k, a.nu_c)
            i = int(np.argmax(w))
            best.append({"Fz [kN]": (f.fz or float("nan")) / 1e3, "slip at max modified WMAI": s[i],
                         "max modified WMAI": w[i], "mu there": f.predict(s[i])})
        r.table(best, caption="Where the modified mobility-agility index peaks")
    if a.radius is not None:
        rad = a.radius
        r.h2("Rolling radius against wheel torque (Eq. 18-20)")
        r.table([{k: v for k, v in rad.as_dict().items() if not isinstance(v, list)}])
        fig = Figure(figsize=(11, 4))
        axs = fig.subplots(1, 2)
        rad.plot(axs[0])
        lw = rad.lambda_w
        axs[1].plot(rad.torque, lw * 1e6, ".")
        axs[1].set_xlabel("wheel torque T [N m]")
        axs[1].set_ylabel("elasticity factor lambda_w [mm/(kN m)]")
        r.figure(fig, "Left: rolling radius vs torque with the quadratic fit (Eq. 19, Ghasemi et al., Fig. 6). "
                 "Right: the longitudinal elasticity factor (r0 - r)/T at each point (Eq. 20).")
    r.json_block(_jsonable(a.as_dict()))
    return r


def run(args) -> int:
    """Entry point of ``tyrefit slip``."""
    check_outputs(args)
    ds = read_data(args.data, convention=getattr(args, "convention", "iso"))
    if ds.kind != "slip_ratio" and not {"torque", "rolling_radius"} <= set(ds.df.columns):
        raise DataError(f"{args.data}: is a {ds.kind} test; 'tyrefit slip' needs slip-ratio data "
                        "(slip_ratio, fx, fz) or torque and rolling_radius columns")
    a = analyse_slip(ds.df, source=str(args.data))
    print(_summary(a))
    if getattr(args, "json", None):
        write_text(args.json, json.dumps(_jsonable(a.as_dict()), indent=2) + "\n", force=args.force)
        print(f"wrote {args.json}")
    if getattr(args, "report", None):
        path = slip_report(a).save(args.report, force=args.force)
        print(f"wrote {path}")
    return 0
