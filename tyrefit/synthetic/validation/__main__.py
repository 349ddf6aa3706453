"""``python -m tyrefit.synthetic.validation``: the diagnose rates table (cached, resumable)."""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from .cases import LAYOUTS, NOISE_MODELS, SIGMA
from .runner import (MUTATIONS, PLAN, base_fit, check_targets, fingerprint, git_commit, invariant_checks, markdown,
                     oracle, plan_cases, rates, run, summary_markdown, targets_markdown)
from .truth import EFFECT_FAMILY, EFFECTS


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m tyrefit.synthetic.validation",
                                 description="diagnose validation on truths outside the effect catalogue: "
                                             "rates by layout x noise model x family (JSON + markdown)")
    ap.add_argument("--out", default="reports/diag_validation", help="output and cache folder")
    ap.add_argument("--layout", action="append", choices=list(LAYOUTS), help="layout(s) (default: all)")
    ap.add_argument("--noise", action="append", choices=list(NOISE_MODELS), help="noise model(s) (default: all)")
    ap.add_argument("--family", action="append",
                    help="effect name(s) or diagnose family(ies), 'null' for null cases (default: all); known: "
                         + ", ".join(["null", *EFFECTS, *sorted(set(EFFECT_FAMILY.values()))]))
    ap.add_argument("--n-null", type=int, help="null seeds per layout x noise (default per layout: "
                    + ", ".join(f"{k} {v[0]}" for k, v in PLAN.items()) + ")")
    ap.add_argument("--n-effect", type=int, help="seeds per effect x layout x noise (default per layout: "
                    + ", ".join(f"{k} {v[1]}" for k, v in PLAN.items()) + ")")
    ap.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    ap.add_argument("--mutation", help="run a deliberately broken engine (one job): "
                    + "; ".join(f"{k}: {v}" for k, v in MUTATIONS.items()) + "; join with '+'")
    ap.add_argument("--base-fit", action="store_true", help="also measure how well the start model fits each truth")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    known = {"null", *EFFECTS, *EFFECT_FAMILY.values()}
    bad = [f for f in args.family or [] if f not in known]
    if bad:
        print(f"error: unknown family {bad[0]!r}; known: {', '.join(sorted(known))}", file=sys.stderr)
        return 2
    cases = plan_cases(args.layout, args.noise, args.family, args.n_null, args.n_effect)
    out = Path(args.out)
    t0 = time.perf_counter()
    for m in (args.mutation or "").split("+"):
        if m and m not in MUTATIONS and not m.startswith("noguard-"):
            print(f"error: unknown mutation {m!r}; known: {', '.join(MUTATIONS)}", file=sys.stderr)
            return 2
    rows = run(cases, out=out, jobs=args.jobs, verbose=not args.quiet, mutation=args.mutation)
    res = rates(rows)
    meta = {"commit": git_commit(), "code fingerprint": fingerprint(), "true noise sigma [N]": SIGMA,
            "cases": len(rows), "mutation": args.mutation or "none", "seconds (this call)": round(time.perf_counter() - t0, 1),
            "command": "python -m tyrefit.synthetic.validation " + " ".join(sys.argv[1:] if argv is None else argv)}
    if args.base_fit:
        meta["start-model fit to noise-free truth, RMSE / sigma"] = {
            lay: {k: round(v, 3) for k, v in d.items()} for lay, d in base_fit(args.layout).items()}
    checks = [c for lay in dict.fromkeys(r["layout"] for r in rows)
              for c in (check_targets(rows, lay) if lay.startswith("load")
                        else invariant_checks([r for r in rows if r["layout"] == lay], lay))]
    if args.base_fit:
        meta["best single catalogue effects on the noise-free truth, RMSE / sigma"] = {
            lay: {eff or "null": {k: round(v, 2) for k, v in list(oracle(lay, eff).items())[:4]}
                  for eff in dict.fromkeys(r["effect"] for r in rows if r["layout"] == lay)}
            for lay in dict.fromkeys(r["layout"] for r in rows)}
    res["meta"] = meta
    res["targets"] = checks
    res["rows"] = rows
    out.mkdir(parents=True, exist_ok=True)
    (out / "rates.json").write_text(json.dumps(res, indent=1, default=str))
    md = markdown(res, {k: v for k, v in meta.items() if not isinstance(v, dict)})
    head, sep, table = md.partition("| layout | noise |")
    md = head + "## Summary\n\n" + summary_markdown(res) + "\n## By layout, noise model and truth\n\n" + sep + table
    if checks:
        md += "\nDiagnosis targets (one sweep per load) and the invariants of every layout:\n\n" + targets_markdown(checks)
    if args.base_fit:
        md += "\nStart-model fit to the noise-free truth, RMSE / sigma:\n\n"
        for lay, d in meta["start-model fit to noise-free truth, RMSE / sigma"].items():
            md += f"- {lay}: " + ", ".join(f"{k} {v:.2f}" for k, v in d.items()) + "\n"
        md += "\nBest single catalogue effects fitted to the noise-free truth (oracle), RMSE / sigma:\n\n"
        for lay, d in meta["best single catalogue effects on the noise-free truth, RMSE / sigma"].items():
            for eff, o in d.items():
                md += f"- {lay} {eff}: " + ", ".join(f"{k} {v:.2f}" for k, v in o.items()) + "\n"
    (out / "rates.md").write_text(md)
    print(md)
    print(f"wrote {out / 'rates.json'} and {out / 'rates.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
