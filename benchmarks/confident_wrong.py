"""Confident wrong answers of the PAC89 fitter (issue 15): each damaged case's tyre error / the clean fit's.

Run: ``nice python -m benchmarks.confident_wrong [--cost l2] [--cases a,b]``.
Prints one line per case: outcome (fitted / error message), the tyre's error
against the generating tyre (:func:`tyrefit.synthetic.robust_cases.tyre_error`,
% of peak), the ratio to the clean fit's error, R², RMSE / noise floor, the
warnings and the fit time.  A ratio near 1 means the damage did not matter.
"""

from __future__ import annotations

import argparse
import time

from tyrefit.errors import TyrefitError
from tyrefit.fitting import fit_pac89
from tyrefit.synthetic.robust_cases import CASES, make_case, tyre_error


def run(cases, cost="l2"):
    rows = []
    base = None
    for name in ["clean", *cases]:
        df = make_case(name)
        t0 = time.perf_counter()
        try:
            r = fit_pac89(df, cost=cost)
        except TyrefitError as e:
            rows.append({"case": name, "outcome": f"error: {e}", "seconds": time.perf_counter() - t0})
            continue
        err = tyre_error(r.values)
        if base is None:
            base = err
        s = r.stats["lateral"]
        rows.append({"case": name, "outcome": "fitted", "error_pct": err, "ratio": err / base, "r2": s["r2"],
                     "rmse_over_floor": s["rmse"] / s["noise_floor"], "a0": r.values["a0"], "a3": r.values["a3"],
                     "warnings": list(getattr(r, "warnings", [])), "seconds": time.perf_counter() - t0})
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--cost", default="l2")
    ap.add_argument("--cases", default=",".join(CASES))
    a = ap.parse_args(argv)
    for row in run([c for c in a.cases.split(",") if c], a.cost):
        if row["outcome"] != "fitted":
            print(f"{row['case']:<15} {row['outcome'][:150]}  ({row['seconds']:.1f} s)")
            continue
        print(f"{row['case']:<15} error {row['error_pct']:8.3f} % of peak  ratio {row['ratio']:9.2f}  "
              f"R2 {row['r2']:.4f}  RMSE/floor {row['rmse_over_floor']:7.2f}  C {row['a0']:.3g} a3 {row['a3']:.3g}  "
              f"{row['seconds']:.1f} s  warnings: {len(row['warnings'])} {[w[:80] for w in row['warnings']]}")


if __name__ == "__main__":
    main()
