"""Does diagnose name the Mz and Fx physics that is there, and only that?  Rates by layout x noise x family.

Usage (from the repository root; about 1 s per case on one core)::

    nice python -m benchmarks.diagnose_channels [--seeds 2] [--jobs 2] [--json rates.json]

Truth tyres (SYNTHETIC data, nothing here is a measurement): MFeval's published Magic Formula 6.1
set (:func:`tyrefit.synthetic.ttc_drivebrake.published_mf61`, a 255/55-size car tyre) evaluated by
:mod:`tyrefit.models.mf61`.  From it, a *plain* tyre has every camber, pressure, shift and asymmetry
coefficient zeroed (:data:`GROUPS`); each truth turns one group back on (``published`` turns all on).
Each group's coefficients are checked to be the whole of it: the plain tyre's Mz and Fx do not change
with camber or pressure (:func:`_check_plain`).

The Fx catalogue extends PAC89's longitudinal curve, a form the truth does not share.  The Mz catalogue
is MF 5.2/6.1's own trail form (:func:`tyrefit.effects.channels.trail_moment`), so on Mz these rates
measure the selection (which terms the data support), not the form; tests/test_trail_model.py adds a
truth of another form (Pacejka's brush model).  Mz is diagnosed as a trail times the measured side force,
so a group counts as present on Mz by the size of its own trail and residual-torque coefficients
(:func:`own_coefficients`); what it does to Fy reaches Mz through the measured Fy.

Layouts (set-point sweeps of :func:`~tyrefit.synthetic.ttc_drivebrake.make_sweeps`, 41 points,
slip angle -12..12 deg for Mz, slip ratio -0.2..0.2 at zero slip angle for Fx): :data:`LAYOUTS`.
Noise: independent, or AR(1) along the sweep at rho 0.8 and 0.9, 1 % of the sweep's peak |channel|
(marginal sd), on the channel and, for Mz, on the side force it reads.

Printed: per channel and family, the share of sets where the family was named when present and
testable, and when absent (invented), by layout x noise; and "nothing missing" verdicts whose held-out
RMSE is above 1.5 x the true noise sd.
"""

from __future__ import annotations

import argparse
import json
import os
from collections import defaultdict
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pandas as pd

from tyrefit.synthetic.ttc_drivebrake import COEFFICIENT_GROUPS

#: coefficient groups of the MF 6.1 tyre that carry each family (Pacejka 2012, Sec. 4.3.2)
GROUPS = COEFFICIENT_GROUPS
#: the catalogue family that names each group, per channel (None: the channel has no such family)
FAMILY = {"mz": {"camber": "mz_camber", "pressure": "mz_pressure", "offsets": "mz_offsets", "rolling": None,
                 "asymmetry": "mz_asymmetry"},
          "fx": {"camber": "fx_camber", "pressure": "fx_pressure", "offsets": "fx_offsets", "rolling": "fx_rolling",
                 "asymmetry": "fx_asymmetry"}}
TRUTHS = ("plain", "camber", "pressure", "offsets", "rolling", "asymmetry", "published")
#: name -> (loads as fractions of FNOMIN, cambers [deg], pressures [kPa])
LAYOUTS = {
    "3loads": ((0.5, 1.0, 1.5), (0.0,), (260,)),
    "2loads_2cambers": ((0.6, 1.2), (0.0, 3.0), (260,)),
    "3loads_3cambers": ((0.5, 1.0, 1.5), (0.0, 2.0, 4.0), (260,)),
    "3loads_3pressures": ((0.5, 1.0, 1.5), (0.0,), (220, 260, 300)),
    "4loads_2cambers_2pressures": ((0.4, 0.8, 1.2, 1.6), (0.0, 3.0), (230, 290)),
}
NOISES = {"iid": 0.0, "ar1_08": 0.8, "ar1_09": 0.9}
SIGMA = 0.01
#: a group counts as present when its RMS effect on the channel at the case's points is >= this x sigma
MIN_SIZE = 1.0


def truth(name: str) -> dict:
    """The MF 6.1 coefficients of truth ``name`` (see the module docstring)."""
    from tyrefit.synthetic.ttc_drivebrake import published_mf61

    p = published_mf61()
    if name == "published":
        return p
    for g, keys in GROUPS.items():
        if g != name:
            for k in keys:
                p[k] = 0.0
    return p


def _ar1(rng, n: int, rho: float) -> np.ndarray:
    e = rng.normal(size=n)
    out = np.empty(n)
    out[0] = e[0]
    for i in range(1, n):
        out[i] = rho * out[i - 1] + np.sqrt(1.0 - rho * rho) * e[i]
    return out


def make_case(channel: str, truth_name: str, layout: str, noise: str, seed: int) -> pd.DataFrame:
    from tyrefit.synthetic.ttc_drivebrake import make_sweeps

    p = truth(truth_name)
    loads, cambers, pressures = LAYOUTS[layout]
    df = make_sweeps(p, seed=seed, noise=0.0, loads=[f * p["FNOMIN"] for f in loads], cambers_deg=cambers,
                     pressures=[v * 1e3 for v in pressures], slip_angles_deg=(0.0,), n_points=41, combined=False,
                     pure=True)
    rng = np.random.default_rng(seed + 7919 * (1 + list(NOISES).index(noise)))
    rho = NOISES[noise]
    # the channel and the side force (which the Mz model reads) each with its own noise of the same kind
    for y in (channel, "fy"):
        for run, g in df.groupby("run"):
            t = g[f"true_{y}"].to_numpy(float)
            sd = SIGMA * max(float(np.max(np.abs(t))), 1e-9)
            df.loc[g.index, y] = t + sd * _ar1(rng, len(g), rho)
    swept = df.groupby("run")["slip_ratio"].transform(np.ptp) > 0.05
    # cornering sweeps (slip angle swept at zero slip ratio) for Mz, drive/brake sweeps at zero slip angle for Fx
    df = df[~swept] if channel == "mz" else df[swept]
    return df.reset_index(drop=True)


def run_case(args) -> dict:
    channel, truth_name, layout, noise, seed = args
    from tyrefit.diagnose.channels import channel_data, diagnose_channel

    df = make_case(channel, truth_name, layout, noise, seed)
    sd_true = float(np.sqrt(np.mean([(SIGMA * np.max(np.abs(g[f"true_{channel}"]))) ** 2
                                     for _, g in df.groupby("run")])))
    cols = ["run", "fz", "slip_angle", "slip_ratio", "camber", "pressure", channel] + (["fy"] if channel == "mz" else [])
    cd = channel_data(df[cols], channel)
    row = {"channel": channel, "truth": truth_name, "layout": layout, "noise": noise, "seed": seed}
    if isinstance(cd, str):
        return {**row, "error": cd}
    dg = diagnose_channel(cd, seed=seed)
    fams = {c["effect"]: c for c in dg.candidates}
    # how large each group is in this channel at these points: RMS of truth minus the truth without it, / sigma
    sizes = {}
    if truth_name != "plain":
        from tyrefit.models import mf61

        groups = list(GROUPS) if truth_name == "published" else [truth_name]
        p = truth(truth_name)
        x = (df["fz"].to_numpy(float), df["slip_ratio"].to_numpy(float), df["slip_angle"].to_numpy(float),
             df["camber"].to_numpy(float))
        base = mf61.forces(p, *x, pressure=df["pressure"].to_numpy(float))[channel]
        for g in groups:
            q = dict(p, **{k: 0.0 for k in own_coefficients(channel, g)})
            d = base - mf61.forces(q, *x, pressure=df["pressure"].to_numpy(float))[channel]
            sizes[g] = float(np.sqrt(np.mean(d * d)) / sd_true)
    row.update(accepted=list(dg.accepted), sizes=sizes, named={fams[e]["family"] for e in dg.accepted},
               testable={c["family"] for c in dg.candidates if c["status"] != "not testable"},
               rmse_heldout=dg.steps[-1].rmse_heldout, sd_true=sd_true,
               structure_found=bool(dg.unexplained["structure_found"]), ratio=dg.unexplained["ratio_to_floor"],
               verdict=dg.unexplained["verdict"],
               seconds=dg.seconds)
    row["named"] = sorted(row["named"])
    row["testable"] = sorted(row["testable"])
    return row


def own_coefficients(channel: str, group: str) -> tuple[str, ...]:
    """The coefficients of ``group`` that act on ``channel``'s own model.

    Mz is diagnosed as a trail times the measured side force plus a residual torque, so what a group does
    to Fy reaches Mz through the measured Fy and is Fy's to name; Mz's own coefficients are the trail and
    residual-torque ones (QBZ, QCZ, QDZ, QEZ, QHZ, PPZ; Pacejka 2012, Eq. 4.E31-4.E47).  Fx: the whole group.
    """
    keys = GROUPS[group]
    if channel == "mz":
        return tuple(k for k in keys if k[0] == "Q" and k[2] == "Z" or k.startswith("PPZ"))
    return tuple(keys)


def _check_plain() -> None:
    """The plain tyre's Mz and Fx must not depend on camber or pressure (the groups are complete)."""
    from tyrefit.models import mf61

    p = truth("plain")
    n = 41
    a = np.radians(np.linspace(-12, 12, n))
    k = np.linspace(-0.2, 0.2, n)
    ref = None
    for g, pr in ((0.0, 260e3), (np.radians(4.0), 260e3), (0.0, 300e3)):
        f1 = mf61.forces(p, np.full(n, 6000.0), np.zeros(n), a, np.full(n, g), pressure=np.full(n, pr))
        f2 = mf61.forces(p, np.full(n, 6000.0), k, np.zeros(n), np.full(n, g), pressure=np.full(n, pr))
        cur = np.r_[f1["mz"], f2["fx"]]
        if ref is not None and not np.allclose(cur, ref, rtol=1e-9, atol=1e-9):
            raise AssertionError("the plain truth still depends on camber or pressure")
        ref = cur


def plan(seeds: int, channels=("mz", "fx")) -> list[tuple]:
    out = []
    for ch in channels:
        for t in TRUTHS:
            if t == "rolling" and ch == "mz":
                continue
            for lay in LAYOUTS:
                for nz in NOISES:
                    for s in range(seeds):
                        out.append((ch, t, lay, nz, 1000 + s))
    return out


def rates(rows: list[dict]) -> dict:
    ok = [r for r in rows if "error" not in r]
    out = {"errors": len(rows) - len(ok), "cases": len(rows)}
    table = defaultdict(lambda: {"present_named": [0, 0], "absent_named": [0, 0]})
    for r in ok:
        for group, fam in FAMILY[r["channel"]].items():
            if fam is None or fam not in r["testable"]:
                continue
            present = r["truth"] in (group, "published")
            if present and r["sizes"].get(group, 0.0) < MIN_SIZE:
                continue  # present but smaller than the noise: counted apart
            key = (r["channel"], fam, r["layout"], r["noise"])
            cell = table[key]["present_named" if present else "absent_named"]
            cell[0] += fam in r["named"]
            cell[1] += 1
    out["by_cell"] = {" | ".join(k): v for k, v in sorted(table.items())}
    tot = defaultdict(lambda: {"present_named": [0, 0], "absent_named": [0, 0]})
    for (ch, fam, _, _), v in table.items():
        for kk in ("present_named", "absent_named"):
            tot[fam][kk][0] += v[kk][0]
            tot[fam][kk][1] += v[kk][1]
    out["by_family"] = dict(tot)
    nothing = [r for r in ok if r["verdict"] == "nothing"]
    out["nothing_missing_above_1p5_sigma"] = [sum(r["rmse_heldout"] > 1.5 * r["sd_true"] for r in nothing),
                                              len(nothing)]
    out["verdicts"] = {v: sum(r["verdict"] == v for r in ok) for v in ("nothing", "undecided", "structure")}
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--json", default="")
    ap.add_argument("--channels", default="mz,fx", help="comma-separated: mz, fx")
    args = ap.parse_args(argv)
    _check_plain()
    cases = plan(args.seeds, tuple(c.strip() for c in args.channels.split(",") if c.strip()))
    if args.jobs > 1:
        with ProcessPoolExecutor(args.jobs) as ex:
            rows = list(ex.map(run_case, cases, chunksize=4))
    else:
        rows = [run_case(c) for c in cases]
    res = rates(rows)
    print(f"{res['cases']} cases, {res['errors']} without channel data")
    print(f"{'family':<16} {'present: named':>16} {'absent: named':>15}")
    for fam, v in sorted(res["by_family"].items()):
        a, b = v["present_named"], v["absent_named"]
        print(f"{fam:<16} {a[0]:>7}/{a[1]:<4} {100 * a[0] / max(a[1], 1):5.1f} %  {b[0]:>5}/{b[1]:<4} "
              f"{100 * b[0] / max(b[1], 1):5.1f} %")
    k, n = res["nothing_missing_above_1p5_sigma"]
    print(f"'nothing missing' with held-out RMSE > 1.5 sigma: {k}/{n}; verdicts {res['verdicts']}")
    print("by channel | family | layout | noise: present named, absent named")
    for key, v in res["by_cell"].items():
        print(f"  {key:<62} {v['present_named'][0]}/{v['present_named'][1]}  {v['absent_named'][0]}/{v['absent_named'][1]}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"rates": res, "rows": rows}, f, indent=1, default=str)
    return 0


if __name__ == "__main__":
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    raise SystemExit(main())
