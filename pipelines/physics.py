"""Physics of seeds 001 and 002 on the bundled data.

Runs ``tyrefit slip`` on the bundled slip-ratio sweeps (seed 002's slip
characteristics), ``tyrefit sim adhesion`` on the wet and dry roads with
cambered wheels (seed 001's EKF with the improved and the original brush
model) and :func:`tyrefit.compare.brush.compare_brush_pac89` (the camber brush
model against PAC89: where the Magic Formula cannot follow), then links the
reports.  No logic of its own.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from tyrefit.compare.brush import compare_brush_pac89
from tyrefit.cli import run_checked
from tyrefit.io.datasets import data_path
from tyrefit.io.outputs import write_text
from tyrefit.io.report import Report

#: (road mu, camber on the left wheels [deg]) shown in the demo
ADHESION_CASES = [(0.8, 0.0), (0.3, 6.0)]


def _run(argv: list[str]) -> None:
    run_checked(argv + ["--force"])


def main(out_dir: str | Path = "reports/physics") -> dict:
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    _run(["slip", str(data_path("slip", "slip_ratio.csv")), "--json", str(out / "slip.json"),
          "--report", str(out / "slip")])
    slip = json.loads((out / "slip.json").read_text())
    rows, errors = [], []
    for mu, camber in ADHESION_CASES:
        name = f"adhesion_mu{mu:g}_camber{camber:g}"
        _run(["sim", "adhesion", "--road-mu", str(mu), "--camber", str(camber),
              "--json", str(out / f"{name}.json"), "--report", str(out / name)])
        res = json.loads((out / f"{name}.json").read_text())
        worst = max(abs(e) for e in res["relative_error_pct"])
        errors.append(worst)
        rows.append({"road mu": mu, "camber left/right [deg]": f"{camber:+g}/{-camber:+g}",
                     "estimates fl fr rl rr": " ".join(f"{e:.3f}" for e in res["estimates"]),
                     "worst error [%]": round(worst, 2), "converged [s]": res["converged_s"],
                     "report": f'<a href="{name}/index.html">{name}</a>'})
    # the camber brush model against PAC89 (seed 001), a sub-report of its own
    cmp = compare_brush_pac89()
    sub = Report("Camber brush model vs PAC89 (seed 001)",
                 "Generated from tyrefit.models.brush with its default (illustrative 205/55R16) parameters; "
                 "no measurement is involved.")
    cmp.report_section(sub)
    sub.save(out / "brush_pac89")
    write_text(out / "brush_pac89.json", json.dumps(cmp.to_dict(), indent=2, default=float) + "\n", force=True)
    r = Report("Physics of seeds 001 and 002",
               "Slip characteristics of the bundled slip-ratio sweeps (seed 002), extended-Kalman-filter "
               "road-adhesion estimation with the camber brush model (seed 001) and the camber brush model "
               "against PAC89 (seed 001). Bundled data are synthetic.")
    r.h2("Slip characteristics (seed 002)")
    r.raw('<p><a href="slip/index.html">slip report</a></p>')
    r.table(slip.get("loads", [slip]), columns=["fz", "mu_peak", "k", "characteristic_slip", "characteristic_mu"])
    r.h2("Road-adhesion estimation (seed 001)")
    r.raw("<table><tr>" + "".join(f"<th>{k}</th>" for k in rows[0]) + "</tr>"
          + "".join("<tr>" + "".join(f"<td>{v}</td>" for v in row.values()) + "</tr>" for row in rows)
          + "</table>")
    r.h2("Camber brush model vs PAC89 (seed 001)")
    r.raw('<p><a href="brush_pac89/index.html">camber brush model vs PAC89 report</a></p>')
    r.p(f"PAC89 fitted to the improved camber brush model: RMSE {cmp.improved.rmse:.0f} N "
        f"({cmp.improved.rmse_pct:.1f} % of the largest peak); to the original brush model: RMSE "
        f"{cmp.original.rmse:.0f} N ({cmp.original.rmse_pct:.1f} %).")
    r.bullets(cmp.findings())
    r.save(out)
    return {"headline": f"EKF worst wheel error {max(errors):.1f} % over {len(rows)} road/camber cases; "
                        f"slip characteristics at {len(slip.get('loads', [slip]))} loads; PAC89 follows the "
                        f"camber brush model to {cmp.improved.rmse_pct:.1f} % of peak",
            "adhesion_worst_error_pct": max(errors), "brush_pac89_rmse_pct": cmp.improved.rmse_pct}


if __name__ == "__main__":
    print(main(sys.argv[1] if len(sys.argv) > 1 else "reports/physics"))
