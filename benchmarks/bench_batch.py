"""Batch fitting: ``tyrefit batch fit`` on a synthetic database vs a serial loop.

The database comes from :mod:`tyrefit.synthetic.database` (synthetic tyres
with known PAC89 coefficients, ~200 points each) in a temporary folder.

* measurement: the command line ``tyrefit batch fit DB --out OUT`` run as a
  subprocess (interpreter start, imports, worker pool, progress bar off stderr
  noise aside, summary CSV/HTML included) on the default local worker processes;
* baseline: a plain serial loop in this (already warm) process over the same
  files: ``read_data`` -> ``fit_pac89`` -> ``to_tir``.

Every ``.tir`` written by the batch is read back and compared with the
generating curves over the generated load / slip grid (max error relative to
the peak force).  200 tyres always; with ``TYREFIT_BENCH_FULL=1`` also 1000
tyres, and 200 tyres through a Dask ``LocalCluster`` (2 worker processes).
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from . import full, measurement

#: database sizes (the second only with TYREFIT_BENCH_FULL=1)
SIZES = (200, 1000)


def serial_loop(paths, out: Path) -> float:
    """The baseline: fit every file one after the other in this process; return the wall time [s]."""
    from tyrefit.fitting import fit_pac89
    from tyrefit.io.readers import read_data

    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    for p in paths:
        res = fit_pac89(read_data(p))
        res.tyre.to_tir(out / f"{Path(p).stem}.tir", force=True)
    return time.perf_counter() - t0


def cli_batch(db: Path, out: Path, *extra: str) -> float:
    """Run ``tyrefit batch fit`` as a subprocess; return the wall time [s]."""
    cmd = [sys.executable, "-m", "tyrefit.cli", "batch", "fit", str(db), "--out", str(out), *extra]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited {proc.returncode}: {proc.stderr.strip()[-500:]}")
    return dt


def max_curve_error(db, out: Path) -> tuple[float, int]:
    """Largest .tir-vs-truth error over the database [-] and the number of tyres checked."""
    from tyrefit.io.tir import read_tir
    from tyrefit.synthetic.database import curve_error

    errs = [curve_error(read_tir(out / f"{name}.tir"), entry) for name, entry in db.truth.items()]
    return max(errs), len(errs)


def _warm() -> None:
    """Import and run one fit so the serial baseline does not pay the first-call costs."""
    from tyrefit.synthetic.database import generate_database

    with tempfile.TemporaryDirectory() as tmp:
        db = generate_database(Path(tmp) / "db", 1, seed=99)
        serial_loop(db.paths, Path(tmp) / "out")


def run() -> dict:
    from tyrefit.synthetic.database import generate_database

    sizes = SIZES if full() else SIZES[:1]
    rows, info = [], {"cpus": len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()}
    _warm()
    for n in sizes:
        with tempfile.TemporaryDirectory(prefix=f"tyrefit-bench-batch-{n}-") as tmp:
            tmp = Path(tmp)
            db = generate_database(tmp / "db", n, seed=0)
            t_serial = serial_loop(db.paths, tmp / "serial")
            t_batch = cli_batch(tmp / "db", tmp / "out")
            err, checked = max_curve_error(db, tmp / "out")
            rows.append(measurement(f"tyrefit batch fit, {n} tyres x ~200 points (local processes)", t_batch,
                                    "serial loop in one process", t_serial, tyres=n,
                                    tyres_per_s=n / t_batch, max_tir_error_pct=100 * err, checked=checked))
            if n == 200 and full():
                rows.append(_dask_row(db, tmp, t_serial))
    return {"measurements": rows, "info": info}


def _dask_row(db, tmp: Path, t_serial: float) -> dict:
    from distributed import Client, LocalCluster

    from tyrefit.workflows.batch import batch_fit

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        t0 = time.perf_counter()
        batch_fit(db.paths, tmp / "dask", scheduler=client, progress=False)
        t = time.perf_counter() - t0
    err, checked = max_curve_error(db, tmp / "dask")
    return measurement(f"batch_fit on a Dask LocalCluster (2 processes), {len(db.paths)} tyres", t,
                       "serial loop in one process", t_serial, max_tir_error_pct=100 * err, checked=checked,
                       coefficients_differing_from_local=_differences(db, tmp / "out", tmp / "dask"),
                       note="cluster start-up not timed")


def _differences(db, a: Path, b: Path) -> int:
    """How many coefficients differ (bit for bit) between two batch outputs of the same database."""
    from tyrefit.io.tir import read_tir

    n = 0
    for name in db.truth:
        ca, cb = read_tir(a / f"{name}.tir").coefficients, read_tir(b / f"{name}.tir").coefficients
        n += sum(ca[k] != cb[k] for k in ca)
    return n
