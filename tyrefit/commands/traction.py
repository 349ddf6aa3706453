"""``tyrefit traction BRAKING.csv [--json OUT.json] [--report DIR]``: treadwear-traction law (Pham et al. 2025).

Reads a table of tyres with their UTQG treadwear grade and a braking test
(``treadwear [-]``, ``stopping_distance [m|ft]``, ``initial_speed
[km/h|mph|m/s]``, optionally ``name``), turns each stopping distance into a
peak friction coefficient with Eq. 41 of Pham et al. (HPwizard's K = 6.58e-5
s^2/m^2 and f_r = 0.013), fits mu = a TW^-b (Eq. 42) and compares it with
HPwizard's a = 2.25, b = 0.15.  With the fitted b it gives the emission ratio
k = (mu_h / mu_s)^(1/b) (Eq. 43) of the bundled hard/soft pair of ``tyrefit
sim``.

JSON keys: ``a``, ``b``, ``a_stderr``, ``b_stderr``, ``r2``, ``rmse``,
``n_tyres``, ``hpwizard`` {a, b}, ``K``, ``f_r``, ``tyres`` (name,
treadwear, stopping_distance_m, initial_speed_mps, mu, mu_fit),
``examples`` (mu at treadwear 300 and 600 and the wear saving),
``bundled_pair`` {mu_soft, mu_hard, mu_ratio, k, ideal_reduction_pct}.
"""

from __future__ import annotations

import json

import numpy as np

from ..io.outputs import write_text
from .outputs import check_outputs
from ..io.readers import read_data
from ..io.report import Report
from ..sim.traction import traction_from_data
from ..sim.tyres import AxleTyre, default_tyres
from ..sim.vehicle import DEFAULT_VEHICLE

__all__ = ["run", "traction_report", "traction_dict"]


def _bundled_pair(b: float) -> dict | None:
    """k for the default tyres of ``tyrefit sim`` at the default vehicle's front axle load."""
    try:
        front, rear = default_tyres()
    except Exception:  # noqa: BLE001 - no bundled tyres: leave the pair out
        return None
    fz = DEFAULT_VEHICLE.axle_load_front / 2.0
    mh, ms = AxleTyre(front, fz).mu_peak, AxleTyre(rear, fz).mu_peak
    k = (mh / ms) ** (1.0 / b)
    return {"front_tyre": front.name, "rear_tyre": rear.name, "tyre_load_N": fz, "mu_soft": ms, "mu_hard": mh,
            "mu_ratio": mh / ms, "k": k, "ideal_reduction_pct": 100.0 * (1 - k) / (1 + k)}


def traction_dict(table) -> dict:
    """The ``--json`` document."""
    fit = table.fit
    ex = []
    for tw in (300.0, 600.0):
        ex.append({"treadwear": tw, "mu": float(fit.predict(tw))})
    d = {**fit.to_dict(), "K": table.K, "f_r": table.f_r, "source": table.source, "tyres": table.rows(),
         "examples": {"points": ex, "traction_loss_pct": 100 * (1 - ex[1]["mu"] / ex[0]["mu"]),
                      "wear_saving_pct": 100 * (1 - ex[0]["treadwear"] / ex[1]["treadwear"])}}
    pair = _bundled_pair(fit.b)
    if pair is not None:
        d["bundled_pair"] = pair
    return d


def traction_report(table, d: dict):
    """HTML report: the tyres, the fit against HPwizard's law, k against the friction ratio."""
    from matplotlib.figure import Figure

    fit = table.fit
    r = Report("Treadwear against traction (Pham et al. 2025, Eq. 41-43)",
               subtitle=f"data: {table.source}" if table.source else None)
    r.p("Each tyre's stopping distance d from speed v0 gives its peak friction by Eq. 41, "
        f"mu = K v0^2 / (exp(2 g K d) - 1) - f_r with K = {table.K:g} s^2/m^2 and f_r = {table.f_r:g} "
        "(HPwizard's typical values). The power law mu = a TW^-b (Eq. 42) is fitted by least squares on mu. "
        "Wear is proportional to 1/TW, so a hard tyre of friction mu_h emits k = TW_s/TW_h = (mu_h/mu_s)^(1/b) "
        "of what the soft one does (Eq. 43).")
    r.h2("Fit")
    r.table([{"": "this fit", "a": fit.a, "+/- a": fit.a_stderr, "b": fit.b, "+/- b": fit.b_stderr,
              "R2": fit.r2, "rmse(mu)": fit.rmse},
             {"": "HPwizard", "a": 2.25, "+/- a": float("nan"), "b": 0.15, "+/- b": float("nan"),
              "R2": float("nan"), "rmse(mu)": float("nan")}])
    fig = Figure(figsize=(7, 4.5))
    ax = fig.subplots()
    fit.plot(ax)
    r.figure(fig, "Peak friction from the stopping distances against UTQG treadwear, with the fitted law and "
                  "HPwizard's (Pham et al., Fig. 4).")
    ex = d["examples"]
    r.p(f"By the fitted law a tyre of treadwear {ex['points'][0]['treadwear']:g} has mu = "
        f"{ex['points'][0]['mu']:.3f} and one of {ex['points'][1]['treadwear']:g} has mu = "
        f"{ex['points'][1]['mu']:.3f}: {ex['traction_loss_pct']:.1f} % less traction for "
        f"{ex['wear_saving_pct']:.0f} % less wear.")
    pair = d.get("bundled_pair")
    fig = Figure(figsize=(6, 4))
    ax = fig.subplots()
    ratio = np.linspace(0.6, 1.0, 200)
    ax.plot(ratio, ratio ** (1 / fit.b), label=f"this fit, b = {fit.b:.3f}")
    ax.plot(ratio, ratio ** (1 / 0.15), "--", label="HPwizard, b = 0.15")
    if pair:
        ax.plot([pair["mu_ratio"]], [pair["k"]], "ko", label="bundled hard/soft pair")
    ax.set_xlabel("peak friction ratio mu_h / mu_s [-]")
    ax.set_ylabel("emission ratio k [-]")
    ax.legend(fontsize=8)
    r.figure(fig, "Emission ratio k of a hard tyre against its friction ratio to the soft one (Eq. 43).")
    if pair:
        r.h2("The bundled tyres of tyrefit sim")
        r.table([{"front (hard)": pair["front_tyre"], "rear (soft)": pair["rear_tyre"],
                  "mu hard": pair["mu_hard"], "mu soft": pair["mu_soft"], "ratio": pair["mu_ratio"],
                  "k": pair["k"], "ideal reduction %": pair["ideal_reduction_pct"]}])
    r.h2("Tyres")
    r.table(d["tyres"])
    r.json_block(d)
    return r


def run(args) -> int:
    """Entry point of ``tyrefit traction``."""
    check_outputs(args)
    ds = read_data(args.data, kind="braking")
    table = traction_from_data(ds)
    d = traction_dict(table)
    fit = table.fit
    print(f"treadwear-traction law (Pham et al. 2025, Eq. 42) from {len(table.names)} tyres: "
          f"mu = {fit.a:.4f} TW^-{fit.b:.4f} (+/- {fit.a_stderr:.4f}, {fit.b_stderr:.4f}), R2 = {fit.r2:.3f}; "
          "HPwizard: 2.25 TW^-0.15")
    if "bundled_pair" in d:
        p = d["bundled_pair"]
        print(f"bundled pair: mu_h/mu_s = {p['mu_ratio']:.4f} -> k = {p['k']:.4f} (Eq. 43), ideal reduction "
              f"{p['ideal_reduction_pct']:.1f} %")
    if getattr(args, "json", None):
        write_text(args.json, json.dumps(d, indent=2, default=float) + "\n", force=args.force)
        print(f"wrote {args.json}")
    if getattr(args, "report", None):
        path = traction_report(table, d).save(args.report, force=args.force)
        print(f"wrote {path}")
    return 0
