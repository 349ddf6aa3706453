"""Does diagnose name the physics that is there, and only that?  Rates on the validation truths (issue 24).

Usage (from the repository root; about 1 s per case on one core)::

    nice python -m benchmarks.diagnose_names [--seeds-null 4] [--seeds-effect 3] [--jobs 2]
                                             [--out /tmp/diagnose_names] [--json rates.json]

Cases come from :mod:`tyrefit.synthetic.validation` (SYNTHETIC truth tyres written independently of
the effect catalogue, seven rig layouts), here with four noise models: iid, sweep offsets, AR(1) at
rho 0.8 and at rho 0.9.  Printed:

* per layout x noise x truth: the families diagnose named (share of sets);
* false names: ``offsets`` on truths without a shift (nulls, asymmetric curvature, camber-driven shift,
  ...), on two-sided layouts; ``overload`` on truths without a knee; ``camber`` / ``pressure`` on truths
  without them;
* present-and-testable named: camber (camber, camber_shift truths on camber layouts), pressure (pressure
  layouts), load friction (power and tanh laws, >= 3 loads), shifts (offsets, two-sided layouts),
  asymmetry (asymmetric curvature, two-sided layouts);
* "nothing left" verdicts (``noise``) whose held-out RMSE is above 1.5 x the true sigma.
"""

from __future__ import annotations

import argparse
import json
from collections import defaultdict
from pathlib import Path

from tyrefit.synthetic.validation.cases import LAYOUTS
from tyrefit.synthetic.validation.runner import _family, plan_cases, run, wilson

NOISES = ("iid", "offsets", "ar1", "ar1_09")

#: truth -> the families it carries (what may be named without a false name)
CARRIES = {None: set(), "load_friction_power": {"load_friction"}, "load_friction_tanh": {"load_friction"},
           "curvature": {"curvature_load"}, "overload": {"overload", "load_friction"}, "offsets": {"offsets"},
           "camber": {"camber"}, "pressure": {"pressure"}, "asym_curvature": {"asymmetry"},
           "camber_shift": {"camber"}}


def _named(row) -> set:
    return {_family(a) for a in row.get("accepted", [])}


def _share(rows, pred):
    k = sum(1 for r in rows if pred(r))
    n = len(rows)
    lo, hi = wilson(k, n)
    return {"k": k, "n": n, "share": k / n if n else float("nan"), "ci95": [lo, hi]}


def metrics(rows: list[dict]) -> dict:
    ok = [r for r in rows if "error" not in r]
    two_sided = {k for k, v in LAYOUTS.items() if v.two_sided}
    out = {"errors": len(rows) - len(ok)}
    out["false_offsets"] = _share([r for r in ok if r["effect"] != "offsets" and r["layout"] in two_sided],
                                  lambda r: "offsets" in _named(r))
    out["false_overload"] = _share([r for r in ok if r["effect"] != "overload"], lambda r: "overload" in _named(r))
    out["false_camber"] = _share([r for r in ok if r["effect"] not in ("camber", "camber_shift")],
                                 lambda r: "camber" in _named(r))
    out["false_pressure"] = _share([r for r in ok if r["effect"] != "pressure"], lambda r: "pressure" in _named(r))
    out["false_asymmetry"] = _share([r for r in ok if r["effect"] != "asym_curvature"],
                                    lambda r: "asymmetry" in _named(r))
    cam = {k for k, v in LAYOUTS.items() if len(v.cambers_deg) >= 2}
    prs = {k for k, v in LAYOUTS.items() if len(v.pressures) >= 2}
    loads3 = {k for k, v in LAYOUTS.items() if len(set(v.loads)) >= 3}
    out["found_camber"] = _share([r for r in ok if r["effect"] in ("camber", "camber_shift") and r["layout"] in cam],
                                 lambda r: "camber" in _named(r))
    out["found_pressure"] = _share([r for r in ok if r["effect"] == "pressure" and r["layout"] in prs],
                                   lambda r: "pressure" in _named(r))
    out["found_load_friction"] = _share([r for r in ok if r["effect"] in ("load_friction_power", "load_friction_tanh")
                                         and r["layout"] in loads3], lambda r: "load_friction" in _named(r))
    out["found_shifts"] = _share([r for r in ok if r["effect"] == "offsets" and r["layout"] in two_sided],
                                 lambda r: "offsets" in _named(r))
    out["found_asymmetry"] = _share([r for r in ok if r["effect"] == "asym_curvature" and r["layout"] in two_sided],
                                    lambda r: "asymmetry" in _named(r))
    noise_v = [r for r in ok if r.get("verdict") == "noise"]
    out["nothing_left_above_1p5_sigma"] = _share(noise_v, lambda r: r["rmse_heldout"] > 1.5 * r["sigma"])
    out["verdicts"] = {v: sum(1 for r in ok if r.get("verdict") == v) for v in ("noise", "structure", "undecided")}
    return out


def table(rows: list[dict]) -> list[dict]:
    """Per layout x noise x truth: n and the share of sets naming each family."""
    groups = defaultdict(list)
    for r in rows:
        if "error" not in r:
            groups[(r["layout"], r["noise"], r["effect"] or "null")].append(r)
    out = []
    for (lay, noise, eff), rs in sorted(groups.items()):
        fams = defaultdict(int)
        for r in rs:
            for f in _named(r):
                fams[f] += 1
        out.append({"layout": lay, "noise": noise, "truth": eff, "n": len(rs),
                    "named": {f: round(k / len(rs), 2) for f, k in sorted(fams.items())}})
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.diagnose_names")
    ap.add_argument("--seeds-null", type=int, default=4)
    ap.add_argument("--seeds-effect", type=int, default=3)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--layout", action="append")
    ap.add_argument("--out", default="/tmp/diagnose_names")
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    cases = plan_cases(layouts=a.layout, noises=list(NOISES), n_null=a.seeds_null, n_effect=a.seeds_effect)
    rows = run(cases, out=Path(a.out), jobs=a.jobs, verbose=False)
    m, t = metrics(rows), table(rows)
    for g in t:
        print(f"{g['layout']:<10} {g['noise']:<8} {g['truth']:<20} n={g['n']:<3} "
              + ", ".join(f"{k} {v:.2f}" for k, v in g["named"].items()))
    print()
    for k, v in m.items():
        if isinstance(v, dict) and "share" in v:
            print(f"{k:<30} {v['k']:>4}/{v['n']:<4} = {100 * v['share']:5.1f} %  (95 % CI {100 * v['ci95'][0]:.1f}-"
                  f"{100 * v['ci95'][1]:.1f} %)")
        else:
            print(f"{k:<30} {v}")
    if a.json:
        Path(a.json).write_text(json.dumps({"metrics": m, "table": t}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
