"""STTR vs DTTR on the bundled truck tyres (seed 003's promise, end to end).

Calibrates Eq. 1 on truck tyre A (tested on both rigs), fits tyre B from its
static-rig tests only (calibrated and uncalibrated, parts 'peak' and
'sliding'), and compares every model with tyre B's dynamic-rig data.  All the
work is :func:`tyrefit.workflows.sttr_vs_dttr.sttr_vs_dttr`; this script reads the bundled
files and writes

    <out>/index.html           the report
    <out>/RIG.json             the calibration (as 'tyrefit rig calibrate' writes it)
    <out>/tyre_b_*.tir, .json  the fitted tyres (PAC89 .tir and Chrono JSON)
    <out>/compare_*.json       'tyrefit compare --json' documents, DTTR fit vs each STTR model
    <out>/summary.json         the numbers per load

Run: ``python pipelines/sttr_vs_dttr.py [--out reports/sttr_vs_dttr] [--force]``.
The bundled data are synthetic (tyrefit.synthetic.truck).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from tyrefit.io.datasets import data_path
from tyrefit.nomenclature import G0
from tyrefit.io.outputs import staged_dir, write_text
from tyrefit.io.readers import read_data
from tyrefit.workflows.sttr_vs_dttr import sttr_vs_dttr
from tyrefit.tyres.size import parse_size, with_design


#: the tyres' rated load (load index on the sidewall, seed 003: 4250 kg), FNOMIN of the .tir
RATED_LOAD_KG = 4250.0
#: the bundled truck tyres' size (data/truck/README.md): radius and width for the Chrono JSON, which also needs
#: mass, inertia and damping (estimated from the size as ``tyrefit fit --size`` does, said in the header)
SIZE = "385/65R22.5"


def main(out_dir="reports/sttr_vs_dttr", force: bool = False) -> dict:
    """Run the study into ``out_dir``; return the headline numbers."""
    def read(name, kind=None):
        return read_data(data_path("truck", name), kind=kind) if kind else read_data(data_path("truck", name))

    study = sttr_vs_dttr(read("tyre_a_static.csv", "static"), read("tyre_a_dynamic.csv"),
                         read("tyre_a_patch.csv", "patch"),
                         read("tyre_b_static.csv", "static"), read("tyre_b_patch.csv", "patch"),
                         read("tyre_b_dynamic.csv"), target_vertical=read("tyre_b_vertical.csv", "vertical"),
                         cost="l1", rated_load=RATED_LOAD_KG * G0)
    summary = study.summary()
    with staged_dir(out_dir, force=force) as tmp:
        study.calibration.to_json(tmp / "RIG.json")
        for key, fit in list(study.fits.items()):
            fit = study.fits[key] = fit.with_tyre(with_design(fit.tyre, parse_size(SIZE), RATED_LOAD_KG * G0)[0])
            fit.tyre.to_tir(tmp / f"tyre_b_{key}.tir")
            fit.tyre.to_chrono_json(tmp / f"tyre_b_{key}.json")
        for key, cmp in study.comparisons.items():
            write_text(tmp / f"compare_{key}.json", json.dumps(cmp.to_json(), indent=2, default=float) + "\n")
        write_text(tmp / "summary.json", json.dumps(summary, indent=2, default=float) + "\n")
        write_text(tmp / "per_load.csv", study.table.to_csv(index=False))
        study.report().save(tmp)
    return summary


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="reports/sttr_vs_dttr")
    ap.add_argument("--force", action="store_true", help="replace an existing report folder")
    a = ap.parse_args()
    s = main(Path(a.out), force=a.force)
    print(s["headline"])
    for row in s["per_load"]:
        print("  " + ", ".join(f"{k} {v:.2f}" if isinstance(v, float) else f"{k} {v}" for k, v in row.items()))
    sys.exit(0)
