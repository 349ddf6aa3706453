"""Diagnose the bundled passenger tyre, then fit the effects it found.

The whole loop of issue 5 on ``data/passenger``: ``tyrefit diagnose`` finds
where the base PAC89 model fails and which physical effects are missing, and
``tyrefit fit --effects`` adds the accepted ones that PAC89 can hold and
writes the ``.tir`` with its before/after report.  Then the commonest rig layout,
truck tyre A's five one-sided dynamic-rig sweeps (``truck_a/``), whose advice
section says what such data cannot carry and which test would decide it.  No
logic of its own.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from tyrefit.cli import run_checked
from tyrefit.io.datasets import data_path

RATED_LOAD_N = 6031.0  # load index 91 (data/passenger/README.md)
TRUCK_RATED_LOAD_N = 41680.0  # 4250 kg, the rated load of tyre A (tyrefit.synthetic.truck, seed 003)


def _run(argv: list[str]) -> None:
    run_checked(argv + ["--force"])


def main(out_dir: str | Path = "reports/diagnose_passenger") -> dict:
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    data = str(data_path("passenger", "passenger_205_55R16.csv"))
    _run(["diagnose", data, "--rated-load", str(RATED_LOAD_N), "--json", str(out / "diagnose.json"),
          "--report", str(out)])
    diag = json.loads((out / "diagnose.json").read_text())
    accepted = diag["accepted"]
    if accepted:
        _run(["fit", data, "--effects", ",".join(accepted), "--rated-load", str(RATED_LOAD_N),
              "--out", str(out / "passenger.tir"), "--report", str(out / "fit_with_effects")])
    steps = diag["steps"]
    # the commonest rig layout: truck tyre A's dynamic-rig test, five loads, one 0..12 deg sweep each
    truck = out / "truck_a"
    _run(["diagnose", str(data_path("truck", "tyre_a_dynamic.csv")), "--rated-load", str(TRUCK_RATED_LOAD_N),
          "--json", str(truck / "diagnose.json"), "--report", str(truck)])
    tdiag = json.loads((truck / "diagnose.json").read_text())

    def advice(d):
        return "; ".join(f"{a['family']} {a['status']} -> {a['test'].split(':')[0]}" for a in d["advice"]
                         if a["status"] != "not detected")

    # the ladder's next rung: effects PAC89 cannot carry (pressure) go into an MF 6.1 tyre
    mf_rmse = _mf61_export(data, accepted, out) if accepted else None
    mf_text = (f"; exported MF 6.1 tyre RMSE {mf_rmse:.0f} N (diagnose's final {steps[-1]['rmse']:.0f} N)"
               if mf_rmse is not None else "")
    return {"headline": f"accepted {', '.join(accepted) or 'nothing'}; RMSE {steps[0]['rmse']:.0f} -> "
                        f"{steps[-1]['rmse']:.0f} N (held-out {steps[-1]['rmse_heldout']:.0f} N, "
                        f"noise floor {diag['noise_floor']:.0f} N){mf_text}; advice: {advice(diag) or 'none'}. "
                        f"Truck A (5 one-sided sweeps, truck_a/index.html): accepted "
                        f"{', '.join(tdiag['accepted']) or 'nothing'}; advice: {advice(tdiag) or 'none'}",
            "accepted": accepted, "advice": diag["advice"], "truck_a_accepted": tdiag["accepted"],
            "truck_a_advice": tdiag["advice"], "mf61_rmse": mf_rmse, "diagnose_rmse": steps[-1]["rmse"]}


def _mf61_export(data: str, accepted: list[str], out: Path) -> float:
    """``fit --effects ... --model mf61``: the accepted effects in an MF 6.1 tyre; its Fy RMSE [N] (.tir header)."""
    from tyrefit.io.tir import read_tyre

    tir = out / "passenger_mf61.tir"
    _run(["fit", data, "--model", "mf61", "--effects", ",".join(accepted), "--rated-load", str(RATED_LOAD_N),
          "--out", str(tir), "--report", str(out / "fit_mf61")])
    for line in read_tyre(tir).header:
        if line.strip().startswith("RMSE FY "):
            return float(line.split()[2])
    raise RuntimeError(f"{tir}: no 'RMSE FY' line in the header")


if __name__ == "__main__":
    print(main(sys.argv[1] if len(sys.argv) > 1 else "reports/diagnose_passenger"))
