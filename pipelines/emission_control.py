"""Fitted tyres in seed 000's tyre-emission control scenarios (issue 6).

The chain, each step a ``tyrefit`` command on the bundled synthetic data in
``data/sim``:

1. ``tyrefit fit`` the hard and the soft tyre (slip-angle and slip-ratio
   sweeps) into ``.tir`` files;
2. ``tyrefit traction`` the UTQG/braking table: mu = a TW^-b (Eq. 42) and the
   hard tyre's emission ratio k (Eq. 43);
3. ``tyrefit sim braking|straight|curved --front hard.tir --rear soft.tir``
   with the tyres fitted in step 1.

Writes every report under ``out_dir`` and an ``index.html`` linking them with
the headline numbers.  No logic of its own.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from tyrefit.cli import run_checked
from tyrefit.io.datasets import data_path
from tyrefit.io.report import Report


def _run(argv: list[str]) -> None:
    run_checked(argv + ["--force"])


def main(out_dir: str | Path = "reports/emission_control") -> dict:
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    tyres = {}
    for role, which in (("front", "hard"), ("rear", "soft")):
        tyres[role] = out / "tyres" / f"{which}_{role}.tir"
        _run(["fit", str(data_path("sim", f"{which}_tyre.csv")), "--out", str(tyres[role]),
              "--report", str(out / f"fit_{which}")])
    _run(["traction", str(data_path("sim", "braking_utqg.csv")), "--json", str(out / "traction.json"),
          "--report", str(out / "traction")])
    results = {}
    for scenario in ("braking", "straight", "curved"):
        _run(["sim", scenario, "--front", str(tyres["front"]), "--rear", str(tyres["rear"]),
              "--json", str(out / f"{scenario}.json"), "--report", str(out / scenario)])
        results[scenario] = json.loads((out / f"{scenario}.json").read_text())
    traction = json.loads((out / "traction.json").read_text())

    brake = results["braking"]["details"]
    stop_err = max(abs(d["stopping_distance_m"] / d["paper_stopping_distance_m"] - 1) * 100 for d in brake)
    rows = results["braking"]["rows"]
    ratios = [rows[i + 1]["stopping_distance_m"] / rows[i]["stopping_distance_m"] for i in range(0, len(rows), 2)]
    paths = results["straight"]["rows"] + results["curved"]["rows"]
    red = [r["reduction_pct"] for r in paths]
    numbers = {
        "traction_a": traction["a"], "traction_b": traction["b"], "k": results["braking"]["setup"]["k"],
        "max_stopping_distance_error_pct": stop_err, "stopping_distance_ratio": [min(ratios), max(ratios)],
        "reduction_pct": [min(red), max(red)],
        "max_path_difference_m": max(r["max_path_difference_m"] for r in paths),
        "max_speed_difference_pct": max(r["max_speed_difference_pct"] for r in paths),
    }
    headline = (f"Table 3 within {stop_err:.1f} % (low-wear/base {min(ratios):.3f}-{max(ratios):.3f}); emission "
                f"-{min(red):.0f} to -{max(red):.0f} % with k = {numbers['k']:.3f}; path within "
                f"{numbers['max_path_difference_m'] * 1e3:.2f} mm, speed within "
                f"{numbers['max_speed_difference_pct']:.3f} %")

    r = Report("Tyre-emission control with fitted tyres (seed 000)",
               "Hard (front) and soft (rear) tyres fitted by 'tyrefit fit' from synthetic rig data, the "
               "treadwear-traction law from a synthetic UTQG/braking table, and the three scenarios of the paper.")
    r.p(headline, cls="note")
    r.table([{"step": "fit hard tyre", "report": "fit_hard/index.html"},
             {"step": "fit soft tyre", "report": "fit_soft/index.html"},
             {"step": "treadwear-traction law", "report": "traction/index.html"},
             {"step": "emergency braking", "report": "braking/index.html"},
             {"step": "straight path", "report": "straight/index.html"},
             {"step": "curved path", "report": "curved/index.html"}])
    for name in ("fit_hard", "fit_soft", "traction", "braking", "straight", "curved"):
        r.link(f"{name}/index.html", name)
    r.json_block(numbers, "numbers")
    r.save(out)
    return {"headline": headline, **numbers}


if __name__ == "__main__":
    print(main(sys.argv[1] if len(sys.argv) > 1 else "reports/emission_control"))
