"""Physics of seeds 001 and 002 on the bundled data.

Runs ``tyrefit slip`` on the bundled slip-ratio sweeps (seed 002's slip
characteristics) and ``tyrefit sim adhesion`` on the wet and dry roads with
cambered wheels (seed 001's EKF with the improved and the original brush
model), then links the reports.  No logic of its own.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from tyrefit.cli import run_checked
from tyrefit.datasets import data_path
from tyrefit.report import Report

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
    r = Report("Physics of seeds 001 and 002",
               "Slip characteristics of the bundled slip-ratio sweeps (seed 002) and extended-Kalman-filter "
               "road-adhesion estimation with the camber brush model (seed 001). Bundled data are synthetic.")
    r.h2("Slip characteristics (seed 002)")
    r.raw('<p><a href="slip/index.html">slip report</a></p>')
    r.table(slip.get("loads", [slip]), columns=["fz", "mu_peak", "k", "characteristic_slip", "characteristic_mu"])
    r.h2("Road-adhesion estimation (seed 001)")
    r.raw("<table><tr>" + "".join(f"<th>{k}</th>" for k in rows[0]) + "</tr>"
          + "".join("<tr>" + "".join(f"<td>{v}</td>" for v in row.values()) + "</tr>" for row in rows)
          + "</table>")
    r.save(out)
    return {"headline": f"EKF worst wheel error {max(errors):.1f} % over {len(rows)} road/camber cases; "
                        f"slip characteristics at {len(slip.get('loads', [slip]))} loads",
            "adhesion_worst_error_pct": max(errors)}


if __name__ == "__main__":
    print(main(sys.argv[1] if len(sys.argv) > 1 else "reports/physics"))
