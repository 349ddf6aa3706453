"""Fit the bundled truck tyre A's dynamic-rig sweeps to PAC89 and export it.

Runs ``tyrefit fit`` with the seed's Eq. 5 cost (sum of absolute errors on mu)
and the vertical-stiffness test, writing the ``.tir``, Chrono JSON and the fit
report into ``out_dir``.  No logic of its own: it only calls the library.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

from tyrefit.cli import run_checked
from tyrefit.io.datasets import data_path
from tyrefit.io.tir import read_tir


def main(out_dir: str | Path = "reports/fit_truck") -> dict:
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    tir = out / "tyre_a.tir"
    run_checked(["fit", str(data_path("truck", "tyre_a_dynamic.csv")),
                    "--vertical", str(data_path("truck", "tyre_a_vertical.csv")),
                    "--size", "385/65R22.5", "--rated-load", str(4250 * 9.80665),
                    "--cost", "l1", "--out", str(tir), "--json", str(out / "tyre_a_chrono.json"),
                    "--report", str(out), "--force"])
    tyre = read_tir(tir)
    fz = 4250 * 9.80665
    return {"headline": f"tyre_a.tir written; cornering stiffness at the rated load "
                        f"{math.radians(tyre.cornering_stiffness(fz)) / 1e3:.2f} kN/deg",
            "tir": str(tir)}


if __name__ == "__main__":
    print(main(sys.argv[1] if len(sys.argv) > 1 else "reports/fit_truck"))
