"""Batch fitting of a tyre database: local processes or a Dask cluster.

:func:`batch_fit` fits a tyre (PAC89, or MF 6.1/5.2) to every data file it is given (CSV with
unit headers, TYDEX ``.tdx``, FSAE TTC ``.dat``) and writes, in the output
folder,

* ``<name>.tir`` per tyre (``<name>`` is the file stem, or its path below the
  common root when two files share a stem);
* ``status/<name>.json`` per tyre, written by the worker as soon as the tyre
  is done: ``status`` (``ok``, ``failed``, ``error``, ``skipped``), the
  one-line error, fit quality and timings;
* ``summary.csv`` and ``index.html``, a table of every tyre's fit quality.

Execution
---------
The unit of work is one file *path*: each worker reads its file, fits, and
writes the ``.tir`` and the status record itself, so nothing bigger than a
path and a small dict of numbers crosses a process boundary.

* ``scheduler=None`` (default): a :class:`concurrent.futures.ProcessPoolExecutor`
  of ``workers`` processes (default: the CPUs this process may use).  It is
  in the standard library, so Dask stays an optional dependency
  (``pip install tyrefit[dask]``), and it adds no task-graph overhead to tasks
  that last a fraction of a second.  Workers start warm: the reading and
  fitting modules (NumPy, pandas, SciPy, lmfit) are imported once, then the
  workers are forked (Linux, single-threaded caller) or started from a fork
  server that preloaded them (see :func:`_pool_context`).  ``workers=1``
  runs in this process.
* ``scheduler='tcp://host:8786'`` (or a ``distributed.Client``): the same
  task function is mapped over the paths on that Dask cluster; imports are
  warmed once per worker with ``Client.run``.  Workers must see the same
  file system as the caller (the usual shared-storage set-up).

Resuming
--------
Beside each ``.tir`` the batch writes a fingerprint, ``<name>.fit.json``: the
SHA-256 of the source file's contents, the fit options (cost, sign
convention, ...), the tyrefit version and the SHA-256 of the ``.tir`` it
wrote.  A tyre is *up to date* (skipped, its previous status record reused)
only when all of them still match; file times are not used, so a source
replaced by another tyre's data (even with an older time stamp), changed
options (``--cost l1``) or a new tyrefit refit it.  A ``.tir`` the batch did
not write (no fingerprint and no status record), or one edited since the
batch wrote it, is never replaced without ``force`` (that tyre is reported as
failed).  ``summary.csv`` and ``index.html`` belong to the batch folder and
are rewritten (atomically) on every run.

Each tyre is committed as it finishes (its ``.tir``, then its fingerprint),
so an interrupted batch keeps the tyres it finished; this is the one place
where tyrefit does not stage a run's outputs until the whole run succeeded
(:mod:`tyrefit.io.outputs`).

A bad file never stops the batch: it is reported with status ``failed`` and
the one-line :class:`~tyrefit.errors.TyrefitError` message.  Any other
exception is a bug in tyrefit; the tyre gets status ``error`` with the
exception and the traceback in its status record, and the batch goes on.
"""

from __future__ import annotations

import glob
import hashlib
import json
import math
import os
import re
import sys
import time
import traceback
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import DataError, OutputExistsError, TyrefitError, option, render
from ..io.outputs import write_text
from .._version import __version__
from ..io.report import Report
from ..models import pac89
from ..nomenclature import UnitError, dimension_of, parse_header, to_si
from ..tyres.size import size_and_rated_load
from .fit import fit

__all__ = ["BatchResult", "batch_fit", "find_data_files", "fit_file", "fit_quality", "read_manifest", "SUMMARY_COLUMNS",
           "DATA_SUFFIXES"]

#: data-file suffixes a folder is searched for (case-insensitive)
DATA_SUFFIXES = (".csv", ".tdx", ".dat")
#: columns of ``summary.csv`` in order
SUMMARY_COLUMNS = ("name", "status", "points", "sweeps", "rmse", "r2", "peak_mu", "fz_min", "fz_max",
                   "time_s", "error", "source", "tir")
#: modules every worker needs; imported once per worker (fork-server preload / Client.run)
_WARM_MODULES = ("tyrefit.workflows.batch", "tyrefit.workflows.fit", "tyrefit.io.readers", "tyrefit.fitting",
                 "tyrefit.io.tir", "lmfit")
_STATUS_DIR = "status"


# --------------------------------------------------------------------------- discovery

def find_data_files(source: str | os.PathLike | Iterable[str | os.PathLike],
                    exclude: str | os.PathLike | None = None) -> list[Path]:
    """The data files named by a folder, a glob pattern, a file, or a list of those.

    A folder is searched recursively for :data:`DATA_SUFFIXES`; a glob pattern
    (``*``, ``?``, ``[``; ``**`` recursive) keeps every matching file; files
    under ``exclude`` (the output folder) are left out.  The result is sorted
    and free of duplicates.

    Raises
    ------
    DataError
        nothing found, or a named file / folder does not exist.
    """
    items = [source] if isinstance(source, (str, os.PathLike)) else list(source)
    ex = Path(exclude).resolve() if exclude is not None else None
    found: dict[Path, None] = {}
    for item in items:
        s = str(item)
        p = Path(s)
        if p.is_dir():
            cands = sorted(q for q in p.rglob("*") if q.is_file() and q.suffix.lower() in DATA_SUFFIXES)
        elif p.is_file():
            cands = [p]
        elif glob.has_magic(s):
            cands = sorted(Path(q) for q in glob.glob(s, recursive=True) if Path(q).is_file())
        else:
            raise DataError(f"{s}: no such file or folder; give a folder of data files (CSV, .tdx, .dat), "
                            "a glob pattern such as 'db/*.csv', or a data file")
        for q in cands:
            r = q.resolve()
            if ex is not None and (r == ex or ex in r.parents):
                continue
            found.setdefault(r, None)
    if not found:
        raise DataError(f"{', '.join(str(i) for i in items)}: no data files found (looked for "
                        + ", ".join(f"*{s}" for s in DATA_SUFFIXES) + ")")
    return sorted(found)


_UNSAFE = re.compile(r"[^A-Za-z0-9._+-]+")


def _tyre_names(paths: Sequence[Path]) -> list[str]:
    """File-system-safe, unique tyre names: the stem, or the path below the common root."""
    stems = [_UNSAFE.sub("_", p.stem) or "tyre" for p in paths]
    dup = {s for s in stems if stems.count(s) > 1}
    if not dup:
        return stems
    root = Path(os.path.commonpath([str(p.parent) for p in paths]))
    names = []
    for p, s in zip(paths, stems):
        if s in dup:
            rel = p.relative_to(root).with_suffix("")
            s = _UNSAFE.sub("_", "__".join(rel.parts)) + ("_" + p.suffix.lstrip(".").lower() if p.suffix else "")
        names.append(s)
    seen: dict[str, int] = {}
    out = []
    for s in names:  # still equal (same stem and suffix case only): number them
        k = seen.get(s, 0)
        seen[s] = k + 1
        out.append(s if k == 0 else f"{s}_{k}")
    return out


# --------------------------------------------------------------------------- one tyre (runs in a worker)

def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or exc.__class__.__name__


def fit_quality(tyre, ds) -> dict[str, Any]:
    """Fit quality of ``tyre`` on data set ``ds``: rmse [N], r2, peak_mu, points, sweeps, load range.

    Slip-angle data are compared in lateral force, slip-ratio data in
    longitudinal force, static-rig data in friction coefficient Fy/Fz (whose
    rmse is then dimensionless).  ``peak_mu`` is the model's peak friction
    coefficient D/Fz (Fy, or Fx for slip-ratio data) at the median load of the data.
    """
    df = ds.df
    fz = df["fz"].to_numpy(float) if "fz" in df else None
    out: dict[str, Any] = {"points": int(len(df)), "sweeps": int(ds.n_runs)}
    y = yhat = None
    if ds.kind == "slip_angle":
        cam = df["camber"].to_numpy(float) if "camber" in df else 0.0
        y, yhat = df["fy"].to_numpy(float), tyre.fy(fz, df["slip_angle"].to_numpy(float), cam)
    elif ds.kind == "slip_ratio":
        y, yhat = df["fx"].to_numpy(float), tyre.fx(fz, df["slip_ratio"].to_numpy(float))
    if y is not None:
        res = y - yhat
        ss_tot = float(np.sum((y - y.mean()) ** 2))
        out["rmse"] = float(np.sqrt(np.mean(res**2)))
        out["r2"] = float(1.0 - np.sum(res**2) / ss_tot) if ss_tot > 0 else math.nan
    if fz is not None and fz.size:
        fzm = float(np.median(fz))
        out["fz_min"], out["fz_max"] = float(fz.min()), float(fz.max())
        if ds.kind == "slip_ratio":
            f = pac89.longitudinal_factors(tyre.coefficients, fzm * 1e-3)
        else:
            f = pac89.lateral_factors(tyre.coefficients, fzm * 1e-3, 0.0)
        out["peak_mu"] = float(abs(f.D) / fzm)
    return out


def _fit_quality_from_result(result, tyre, ds) -> dict[str, Any]:
    q = fit_quality(tyre, ds)
    if "rmse" not in q:  # static-rig data: the fitter knows what it fitted
        for key in ("rmse", "r2"):
            v = getattr(result, key, None)
            if isinstance(v, (int, float)):
                q[key] = float(v)
    return q


def _sha256(path: str | os.PathLike) -> str | None:
    h = hashlib.sha256()
    try:
        with open(path, "rb") as fh:
            for block in iter(lambda: fh.read(1 << 20), b""):
                h.update(block)
    except OSError:
        return None
    return h.hexdigest()


def fingerprint(source: str | os.PathLike, options: dict[str, Any]) -> dict[str, Any]:
    """What a batch ``.tir`` was fitted from: source contents (SHA-256), fit options, tyrefit version."""
    return {"source": str(source), "source_sha256": _sha256(source),
            "options": {k: options[k] for k in sorted(options)}, "tyrefit": __version__}


def _sidecar(tir: str | os.PathLike) -> Path:
    p = Path(tir)
    return p.with_name(p.stem + ".fit.json")


def _read_json(path: Path) -> dict | None:
    try:
        rec = json.loads(path.read_text(encoding="utf-8"))
        return rec if isinstance(rec, dict) else None
    except (OSError, ValueError):
        return None


def fit_file(source: str, tir: str, *, name: str | None = None, cost: str = "l2", convention: str = "iso",
             status_path: str | None = None, fingerprint: dict | None = None, model: str = "pac89",
             size: str | None = None, rated_load: float | None = None,
             allow_mirrored: bool = False) -> dict[str, Any]:
    """Read one data file, fit it (:func:`tyrefit.workflows.fit.fit`, the code of ``tyrefit fit``), write the
    ``.tir`` (replacing it) and the status record.

    ``size`` and ``rated_load`` complete the tyre's design data as ``fit --size --rated-load`` does (a
    manifest gives them per file, :func:`read_manifest`).  This is the task every worker runs; it never
    raises for a bad file.

    Returns
    -------
    dict
        the status record (see :data:`SUMMARY_COLUMNS`).
    """
    t0 = time.perf_counter()
    rec: dict[str, Any] = {"name": name or Path(source).stem, "status": "failed", "source": str(source),
                           "tir": str(tir), "error": ""}
    try:
        result = fit(source, model=model, cost=cost, convention=convention, size=size, rated_load=rated_load,
                     allow_mirrored=allow_mirrored)
        if model != "pac89":  # Magic Formula: the written file is checked against the tyre contract
            result.write_tir(tir, force=True)
            rec.update(_mf_quality(result))
        else:
            result.tyre.to_tir(tir, force=True)  # the caller decided that this .tir may be (re)written
            rec.update(_fit_quality_from_result(result, result.tyre, result.extras["dataset"]))
        if fingerprint is not None:  # what this .tir was fitted from: decides 'up to date' next time
            write_text(_sidecar(tir), json.dumps({**fingerprint, "tir_sha256": _sha256(tir)}, indent=1) + "\n",
                       force=True)
        rec["status"] = "ok"
    except TyrefitError as exc:
        rec["error"] = _one_line(exc)
    except Exception as exc:  # a bug: record it with its traceback, keep the batch going
        rec["status"] = "error"
        rec["error"] = f"internal error {exc.__class__.__name__}: {_one_line(exc)}"
        rec["traceback"] = traceback.format_exc()
    rec["time_s"] = time.perf_counter() - t0
    rec["finished"] = time.time()
    if status_path:
        try:
            write_text(status_path, json.dumps(_jsonable(rec), indent=1) + "\n", force=True)
        except OSError as exc:  # the record still reaches the caller
            rec["error"] = (rec["error"] + "; " if rec["error"] else "") + f"status record not written: {exc}"
    return rec


def _mf_quality(result) -> dict[str, Any]:
    """Summary fields of a Magic Formula fit to one record (Fy for slip-angle data, else Fx, as for PAC89)."""
    ds = result.datasets[0]
    s = result.stats.get("fy" if ds.kind == "slip_angle" else "fx") or next(iter(result.stats.values()))
    fz = ds.df["fz"].to_numpy(float)
    mu = result.params.get("PDY1" if ds.kind == "slip_angle" else "PDX1", math.nan)
    return {"points": int(len(ds.df)), "sweeps": int(ds.n_runs), "rmse": s["rmse"], "r2": s["r2"],
            "peak_mu": float(abs(mu)), "fz_min": float(fz.min()), "fz_max": float(fz.max())}


def _fit_task(task: tuple) -> dict[str, Any]:
    source, tir, name, cost, convention, status_path, fp, model, design = task
    return fit_file(source, tir, name=name, cost=cost, convention=convention, status_path=status_path,
                    fingerprint=fp, model=model, **design)


def _jsonable(rec: dict) -> dict:
    out = {}
    for k, v in rec.items():
        if isinstance(v, float) and not math.isfinite(v):
            v = None
        elif isinstance(v, np.generic):
            v = v.item()
        out[k] = v
    return out


def _warm_imports() -> None:
    """Import what a worker needs once (pool initializer / ``Client.run``)."""
    import importlib

    for m in _WARM_MODULES:
        try:
            importlib.import_module(m)
        except ImportError:  # reported per tyre when the task runs
            pass


# --------------------------------------------------------------------------- result

@dataclass
class BatchResult:
    """What :func:`batch_fit` did.

    Attributes
    ----------
    out_dir : Path
    records : list of dict
        one status record per tyre, sorted by name (:data:`SUMMARY_COLUMNS`).
    elapsed : float
        wall time of the whole batch [s].
    backend : str
        ``'serial'``, ``'processes(N)'`` or ``'dask(<address>)'``.
    summary_csv, report : Path or None
        the summary table and HTML report written.
    """

    out_dir: Path
    records: list[dict[str, Any]] = field(default_factory=list)
    elapsed: float = 0.0
    backend: str = ""
    summary_csv: Path | None = None
    report: Path | None = None

    def count(self, status: str) -> int:
        return sum(1 for r in self.records if r.get("status") == status)

    @property
    def n_ok(self) -> int:
        return self.count("ok")

    @property
    def n_skipped(self) -> int:
        return self.count("skipped")

    @property
    def n_failed(self) -> int:
        """Tyres that failed (bad input) or hit an internal error."""
        return self.count("failed") + self.count("error")

    @property
    def failed(self) -> list[dict[str, Any]]:
        return [r for r in self.records if r.get("status") in ("failed", "error")]

    def table(self):
        """The summary as a pandas DataFrame (one row per tyre)."""
        import pandas as pd

        return pd.DataFrame([{c: r.get(c) for c in SUMMARY_COLUMNS} for r in self.records],
                            columns=list(SUMMARY_COLUMNS))

    def __repr__(self) -> str:
        return (f"BatchResult({len(self.records)} tyres: {self.n_ok} ok, {self.n_skipped} skipped, "
                f"{self.n_failed} failed; {self.elapsed:.1f} s on {self.backend})")


# --------------------------------------------------------------------------- manifest

def read_manifest(path: str | os.PathLike, files: Sequence[Path]) -> dict[Path, dict[str, Any]]:
    """Per-file design data for a batch: ``{data file: {"size": ..., "rated_load": ...}}``.

    The manifest is a CSV with a ``file`` column (a path relative to the manifest's folder, or a file
    name found once among the batch's data files) and either or both of ``size`` (``385/65R22.5``,
    ``16x7.5-10``) and ``rated_load`` with its unit in the header (``rated_load [N]``, ``[kN]``,
    ``[lbf]``, ``[kg]``).  These are what ``tyrefit fit --size --rated-load`` takes for one file, so a
    batch tyre gets the same dimensions, FNOMIN and estimates as one fitted alone.  Data files without
    a row are fitted without design data; a row that names no data file of the batch is an error.
    """
    import csv


    mpath = Path(path)
    try:
        text = mpath.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise DataError(f"manifest {mpath}: cannot be read ({exc.__class__.__name__}: {exc})") from None
    rows = list(csv.reader(text.splitlines()))
    rows = [r for r in rows if any(c.strip() for c in r)]
    if not rows:
        raise DataError(f"manifest {mpath}: empty; it needs a header 'file,size,rated_load [N]' and a row per tyre")
    cols = {}
    for k, h in enumerate(rows[0]):
        name, unit = parse_header(h)
        if name in cols:
            raise DataError(f"manifest {mpath}: column {name!r} appears twice")
        cols[name] = (k, unit)
    if "file" not in cols or not ({"size", "rated_load"} & set(cols)):
        raise DataError(f"manifest {mpath}: header {','.join(rows[0])!r} needs 'file' and 'size' and/or "
                        "'rated_load [N]'")
    unknown = sorted(set(cols) - {"file", "size", "rated_load"})
    if unknown:
        raise DataError(f"manifest {mpath}: unknown column(s) {', '.join(unknown)}; accepted: file, size, "
                        "rated_load [N]")
    unit = cols.get("rated_load", (0, None))[1]
    if "rated_load" in cols:
        if unit is None:
            raise DataError(f"manifest {mpath}: 'rated_load' needs its unit in the header, e.g. 'rated_load [N]'")
        try:
            scale = float(to_si(1.0, unit))
            ok = dimension_of(unit) in ("force", "mass")
        except UnitError as exc:
            raise DataError(f"manifest {mpath}: rated_load [{unit}]: {exc}") from None
        if not ok:
            raise DataError(f"manifest {mpath}: rated_load [{unit}] is not a force; accepted: [N], [kN], [lbf], "
                            "[kg] (a load in kg is taken as kg x g)")
    by_name: dict[str, list[Path]] = {}
    for f in files:
        by_name.setdefault(Path(f).name, []).append(Path(f).resolve())
    out: dict[Path, dict[str, Any]] = {}
    for line, row in enumerate(rows[1:], start=2):
        def cell(c):
            k = cols[c][0] if c in cols else None
            return row[k].strip() if k is not None and k < len(row) else ""

        where = f"manifest {mpath}, line {line}"
        ref = cell("file")
        if not ref:
            raise DataError(f"{where}: no file named")
        cand = (mpath.parent / ref).resolve()
        if cand not in {Path(f).resolve() for f in files}:
            hits = by_name.get(Path(ref).name, [])
            if len(hits) != 1:
                raise DataError(f"{where}: {ref!r} is " + ("none of the batch's data files" if not hits else
                                f"{len(hits)} of the batch's data files; give its path relative to the manifest"))
            cand = hits[0]
        if cand in out:
            raise DataError(f"{where}: {ref!r} has a row already")
        design: dict[str, Any] = {}
        if cell("size"):
            design["size"] = cell("size")
        if cell("rated_load"):
            try:
                v = float(cell("rated_load")) * scale
            except ValueError:
                raise DataError(f"{where}: rated_load {cell('rated_load')!r} is not a number") from None
            design["rated_load"] = v
        try:
            size_and_rated_load(design.get("size"), design.get("rated_load"))
        except DataError as exc:
            raise DataError(f"{where}: {exc}") from None
        out[cand] = design
    return out


# --------------------------------------------------------------------------- orchestration

def _plan(paths: Sequence[Path], out: Path, force: bool, options: dict[str, Any] | None = None,
          design: dict[Path, dict[str, Any]] | None = None) -> tuple[list[tuple], list[dict]]:
    """Tasks to run and records of tyres not to run (up to date, or refused).

    Each task carries the fingerprint (:func:`fingerprint`) the worker records beside the ``.tir``; a
    file's design data (``design``, from the manifest) are part of its options.
    """
    options, design = dict(options or {}), dict(design or {})
    tasks, done = [], []
    sdir = out / _STATUS_DIR
    for path, name in zip(paths, _tyre_names(paths)):
        tir, status = out / f"{name}.tir", sdir / f"{name}.json"
        own = design.get(Path(path).resolve(), {})
        fp = fingerprint(path, {**options, **own})
        if tir.exists() and not force:
            prev = _read_json(status)
            side = _read_json(_sidecar(tir))
            ours = side is not None and side.get("tir_sha256") == _sha256(tir)
            if ours and all(side.get(k) == fp[k] for k in ("source_sha256", "options", "tyrefit")):
                rec = {c: prev.get(c) for c in SUMMARY_COLUMNS if c in prev} if prev else {}
                rec.update(name=name, status="skipped", source=str(path), tir=str(tir), time_s=0.0,
                           error="" if prev else "up to date; no status record, fit quality unknown")
                done.append(rec)
                continue
            if side is not None and not ours:
                err = OutputExistsError(f"{tir}: changed since 'tyrefit batch fit' wrote it (its SHA-256 differs "
                                        f"from {_sidecar(tir).name}); pass {option('force', flag=True)} to replace it")
                done.append({"name": name, "status": "failed", "source": str(path), "tir": str(tir),
                             "error": _one_line(err), "time_s": 0.0})
                continue
            if side is None and not prev:  # not written by this batch: never replace without force
                err = OutputExistsError(f"{tir}: exists and was not written by 'tyrefit batch fit' (no "
                                        f"{_sidecar(tir).name}); pass {option('force', flag=True)} to replace it")
                done.append({"name": name, "status": "failed", "source": str(path), "tir": str(tir),
                             "error": _one_line(err), "time_s": 0.0})
                continue
            # ours but stale (source, options or version changed), or written before fingerprints: refit
        tasks.append((str(path), str(tir), name, None, None, str(status), fp, own))
    return tasks, done


def _progress(total: int, enabled: bool, desc: str):
    from tqdm.auto import tqdm

    return tqdm(total=total, disable=not enabled or total == 0, file=sys.stderr, unit="tyre", desc=desc,
                dynamic_ncols=True, leave=True)


def _default_workers() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def _run_serial(tasks, progress: bool):
    _warm_imports()
    out = []
    with _progress(len(tasks), progress, "batch fit") as bar:
        for t in tasks:
            out.append(_fit_task(t))
            bar.update(1)
    return out


def _pool_context():
    """``fork`` from a single-threaded process on Linux, else ``forkserver`` (POSIX) or ``spawn``.

    ``fork`` starts workers at once with everything this process imported
    (the worker modules are imported here first).  It is used only while
    this process runs a single Python thread, where forking is safe; with
    threads (a Dask client, a GUI, a notebook kernel) the ``forkserver``
    (worker modules preloaded once) is used instead.  Like ``spawn``, it
    re-imports the calling script in each worker, so scripts that call
    :func:`batch_fit` from there need the ``if __name__ == "__main__":`` guard.
    """
    import multiprocessing as mp
    import threading

    methods = mp.get_all_start_methods()
    if sys.platform.startswith("linux") and "fork" in methods and threading.active_count() == 1:
        _warm_imports()
        return mp.get_context("fork")
    if sys.platform != "win32" and "forkserver" in methods:
        ctx = mp.get_context("forkserver")
        ctx.set_forkserver_preload(list(_WARM_MODULES))
        return ctx
    return mp.get_context("spawn")


def _run_processes(tasks, workers: int, progress: bool):
    from concurrent.futures import ProcessPoolExecutor, as_completed
    from concurrent.futures.process import BrokenProcessPool

    out = []
    ex = ProcessPoolExecutor(max_workers=workers, mp_context=_pool_context(), initializer=_warm_imports)
    try:
        # submit (which starts the workers) before the progress bar starts its monitor thread
        futs = {ex.submit(_fit_task, t): t for t in tasks}
        with _progress(len(tasks), progress, "batch fit") as bar:
            for fut in as_completed(futs):
                try:
                    rec = fut.result()
                except BrokenProcessPool as exc:  # a worker died (out of memory, killed)
                    rec = _lost(futs[fut], exc)
                out.append(rec)
                bar.update(1)
    except BaseException:  # Ctrl-C: drop the queue, do not wait for it (finished tyres keep their records)
        ex.shutdown(wait=False, cancel_futures=True)
        raise
    ex.shutdown(wait=True)
    return out


def _lost(task: tuple, exc: BaseException) -> dict[str, Any]:
    source, tir, name = task[:3]
    return {"name": name, "status": "error", "source": source, "tir": tir, "time_s": math.nan,
            "error": f"worker lost: {exc.__class__.__name__}: {_one_line(exc)}"}


#: seconds to wait for a scheduler to answer (a TCP connect, then Dask's handshake)
CONNECT_TIMEOUT_S = 5.0
class SchedulerWarning(UserWarning):
    """A ``--scheduler`` that is neither on this machine nor reached over TLS."""


#: address schemes a batch can use: a scheduler reached over the network, plain or TLS
_SCHEMES = ("tcp", "tls")


def scheduler_address(scheduler) -> tuple[str, str, int] | None:
    """Check a ``--scheduler`` address before anything connects; ``None`` (or ``''``) means run locally.

    Returns ``(scheme, host, port)`` for ``tcp://host:port``, ``tls://host:port`` or ``host:port``
    (tcp; the port defaults to Dask's 8786).  Any other scheme (``ucx://``, ``inproc://``,
    ``file://``, ...), a bracket left open, a port that is not a number from 1 to 65535 is a
    one-line :class:`DataError`.
    """
    if scheduler is None:
        return None
    text = str(scheduler).strip()
    if not text:
        return None
    accepted = "give it as tcp://host:8786 or tls://host:8786"
    scheme, sep, rest = text.partition("://")
    if not sep:
        scheme, rest = "tcp", text
    scheme = scheme.lower()
    if scheme not in _SCHEMES:
        why = {"inproc": "in-process addresses reach only a scheduler inside the same Python process",
               "ucx": "the UCX transport is not supported by tyrefit batch",
               "ws": "websocket transports are not supported by tyrefit batch",
               "wss": "websocket transports are not supported by tyrefit batch"}.get(scheme, "unknown scheme")
        raise DataError(f"{option('scheduler', repr(text))} (Dask scheduler address): {why}; {accepted}")
    if "/" in rest or not rest:
        raise DataError(f"{option('scheduler', repr(text))} (Dask scheduler address): not a host:port address; {accepted}")
    if rest.startswith("["):
        host, close, tail = rest[1:].partition("]")
        if not close or not host:
            raise DataError(f"{option('scheduler', repr(text))} (Dask scheduler address): an IPv6 address needs its closing bracket, e.g. tcp://[::1]:8786")
        if tail and not tail.startswith(":"):
            raise DataError(f"{option('scheduler', repr(text))} (Dask scheduler address): not a host:port address; {accepted}")
        port_text = tail[1:] if tail else ""
    else:
        host, _, port_text = rest.rpartition(":") if ":" in rest else (rest, "", "")
        if ":" in host:
            raise DataError(f"{option('scheduler', repr(text))} (Dask scheduler address): write an IPv6 address in brackets, e.g. tcp://[::1]:8786")
    if not host:
        raise DataError(f"{option('scheduler', repr(text))} (Dask scheduler address): no host; {accepted}")
    if port_text == "":
        port = 8786
    elif not port_text.isdigit() or not 1 <= int(port_text) <= 65535:
        raise DataError(f"{option('scheduler', repr(text))} (Dask scheduler address): port {port_text!r} is not a number from 1 to 65535; {accepted}")
    else:
        port = int(port_text)
    return scheme, host, port


def scheduler_from_file(path: str | os.PathLike) -> str:
    """The scheduler address in a Dask scheduler file (``dask scheduler --scheduler-file FILE`` writes it).

    Dask writes ``{"type": "Scheduler", "address": "tls://10.0.0.5:8786", ...}``; the address is then
    checked like a ``--scheduler`` address (:func:`scheduler_address`).  TLS still takes its
    certificates from Dask's security configuration.
    """
    p = Path(path)
    try:
        info = json.loads(p.read_text(encoding="utf-8"))
    except OSError as exc:
        raise DataError(f"{option('scheduler_file', p)}: cannot be read ({exc.strerror or exc.__class__.__name__})") from None
    except ValueError:
        raise DataError(f"{option('scheduler_file', p)}: not a Dask scheduler file (not JSON)") from None
    address = info.get("address") if isinstance(info, dict) else None
    if not isinstance(address, str) or not address.strip():
        raise DataError(f"{option('scheduler_file', p)}: no 'address' in it; Dask's scheduler writes one with "
                        "'dask scheduler --scheduler-file FILE'")
    scheduler_address(address)
    return address.strip()


def is_loopback(host: str) -> bool:
    """Is ``host`` this machine (``localhost``, 127.0.0.0/8, ``::1``)?  Names are not resolved."""
    import ipaddress

    if host.lower() in ("localhost", "localhost.localdomain", "ip6-localhost"):
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def scheduler_warning(address: tuple[str, str, int]) -> str | None:
    """The warning for a scheduler that is neither on this machine nor reached over TLS, else ``None``."""
    scheme, host, port = address
    if scheme == "tls" or is_loopback(host):
        return None
    return render(f"{option('scheduler', f'{scheme}://{host}:{port}')} is not on this machine and not TLS: the fits "
                  "are sent there as pickled Python and the answers unpickled here, so whoever controls that address "
                  "or the network between runs code in tyrefit; use tls:// with Dask's security options (README, "
                  "batch)")


def _dask_client(scheduler):
    try:
        from distributed import Client
    except ImportError:
        raise DataError(f"{option('scheduler')} needs Dask's distributed scheduler; install it with "
                        "'pip install tyrefit[dask]' (or dask[distributed])") from None
    if isinstance(scheduler, Client):
        return scheduler, False
    import socket
    import warnings

    from distributed.security import Security

    scheme, host, port = scheduler_address(scheduler)
    address = f"{scheme}://{f'[{host}]' if ':' in host else host}:{port}"
    security = Security()  # Dask's configuration: distributed.comm.tls.* (files or DASK_* variables)
    if scheme == "tls" and security.get_connection_args("client").get("ssl_context") is None:
        raise DataError(f"{option('scheduler', address)}: TLS needs Dask's security options (a CA file and this "
                        "client's certificate and key: distributed.comm.tls.ca-file, .client.cert, .client.key "
                        "in Dask's configuration or DASK_DISTRIBUTED__COMM__TLS__* variables); see the README")
    warning = scheduler_warning((scheme, host, port))
    if warning:
        warnings.warn(SchedulerWarning(warning), stacklevel=3)
    try:  # a plain TCP connect first: a refused or silent address is one line in seconds
        socket.create_connection((host, port), timeout=CONNECT_TIMEOUT_S).close()
    except OSError as exc:
        raise DataError(f"cannot connect to the Dask scheduler {address} ({_one_line(exc) or 'timed out'})") from None

    class _Client(Client):
        def __del__(self):  # a client that failed to start: no 20 s close, no 'Exception ignored' traceback
            try:
                if getattr(self, "status", "closed") not in ("closed", "closing", "newly-created"):
                    self.close(timeout=1)
            except Exception:  # noqa: BLE001
                pass

    import threading

    box: dict = {}

    def start():  # in a thread: Dask's handshake has no deadline of its own (a silent peer holds it)
        try:
            box["client"] = _Client(address, timeout=f"{CONNECT_TIMEOUT_S:g}s", set_as_default=False,
                                    security=security)
        except BaseException as exc:  # noqa: BLE001 - TLS handshake, not a Dask scheduler, timeout, ...
            box["error"] = exc

    th = threading.Thread(target=start, name="tyrefit-dask-connect", daemon=True)
    th.start()
    th.join(CONNECT_TIMEOUT_S + 2)
    if "client" in box:
        return box["client"], True
    exc = box.get("error")
    why = f"{exc.__class__.__name__}: {_one_line(exc)}" if exc is not None else \
        f"no Dask answer within {CONNECT_TIMEOUT_S + 2:g} s; is it a Dask scheduler?"
    raise DataError(f"cannot connect to the Dask scheduler {address} ({why})")


def _run_dask(tasks, client, progress: bool):
    from distributed import as_completed

    try:
        client.run(_warm_imports)
    except Exception:  # noqa: BLE001 - warming is an optimisation only
        pass
    futs = client.map(_fit_task, tasks, pure=False, key=[f"tyrefit-fit-{t[2]}-{os.urandom(4).hex()}"
                                                          for t in tasks])
    index = {f.key: t for f, t in zip(futs, tasks)}
    out = []
    try:
        with _progress(len(tasks), progress, "batch fit") as bar:
            for fut in as_completed(futs, loop=client.loop):
                try:
                    rec = fut.result()
                except Exception as exc:  # noqa: BLE001 - KilledWorker, lost connection, ...
                    rec = _lost(index[fut.key], exc)
                out.append(rec)
                bar.update(1)
                fut.release()
    except BaseException:
        client.cancel(futs)
        raise
    return out


def batch_fit(paths, out_dir: str | os.PathLike, *, workers: int | None = None, scheduler=None,
              force: bool = False, progress: bool = True, cost: str = "l2", convention: str = "iso",
              summary: bool = True, model: str = "pac89", manifest: str | os.PathLike | None = None,
              allow_mirrored: bool = False) -> BatchResult:
    """Fit a PAC89 tyre to every data file; write ``.tir`` files, status records and a summary.

    Parameters
    ----------
    paths : path, glob pattern or iterable of them
        a folder (searched recursively for CSV, ``.tdx``, ``.dat``), a glob
        pattern, a data file, or a list of those.
    out_dir : path
        output folder (created).  Files under it are never taken as input.
    workers : int, optional
        local worker processes; default the CPUs available; 1 runs in this
        process.  Ignored with ``scheduler``.
    scheduler : str or distributed.Client, optional
        Dask scheduler address (``tcp://host:8786``, ``tls://host:8786`` with Dask's TLS security
        options configured) or a connected client; ``None`` or ``''`` runs locally.  An address
        neither on this machine nor TLS gives a :class:`SchedulerWarning` (pickled work goes there).
    force : bool
        refit tyres whose ``.tir`` is up to date, and replace ``.tir`` files
        the batch did not write.
    progress : bool
        show a progress bar on stderr.
    cost : {'l2', 'l1'}
        fit cost (``tyrefit.fitting.fit_pac89``).
    model : {'pac89', 'mf61', 'mf52'}
        tyre family fitted and written (Magic Formula: :func:`tyrefit.fitting.mf.fit_mf`, FITTYP 61 files).
    convention : {'iso', 'sae'}
        sign convention of the data files.
    summary : bool
        write ``summary.csv`` and ``index.html``.
    manifest : path, optional
        a CSV of per-file ``size`` and ``rated_load [N]`` (:func:`read_manifest`): each tyre gets the
        design data ``tyrefit fit --size --rated-load`` would give it.
    allow_mirrored : bool
        fit records whose camber thrust, trail or Fx has the sign of a mirrored tyre (refused otherwise,
        :func:`tyrefit.io.plausibility.check_mirrored`).

    Returns
    -------
    BatchResult

    Raises
    ------
    DataError
        no data files, bad options, or an unreachable scheduler.
    """
    if model not in ("pac89", "mf52", "mf61"):
        raise DataError(f"unknown model {model!r}; accepted: 'pac89', 'mf52', 'mf61'")
    if cost not in ("l1", "l2", "soft_l1", "huber"):
        raise DataError(f"unknown fit cost {cost!r}; accepted: 'l1', 'l2', 'soft_l1', 'huber'")
    if convention not in ("iso", "sae"):
        raise DataError(f"unknown sign convention {convention!r}; accepted: 'iso', 'sae'")
    if workers is not None and int(workers) < 1:
        raise DataError(f"{option('workers', workers)}: need at least 1 worker process")
    if scheduler is not None and isinstance(scheduler, str):
        scheduler_address(scheduler)  # a bad address is refused before any folder is made
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise DataError(f"{out}: exists and is not a folder; {option('out_dir', cli='out')} needs a folder for the .tir files")
    files = find_data_files(paths, exclude=out)
    design = read_manifest(manifest, files) if manifest is not None else {}
    if allow_mirrored:
        design = {f: {**design.get(Path(f).resolve(), {}), "allow_mirrored": True} for f in files}
    if summary and not force and not (out / _STATUS_DIR).is_dir():  # a folder the batch never wrote
        for n in ("summary.csv", "index.html"):
            if (out / n).exists():
                raise OutputExistsError(f"{out / n}: exists and was not written by 'tyrefit batch fit' (no "
                                        f"{_STATUS_DIR}/ folder); pass {option('force', flag=True)} to replace it, "
                                        f"or choose another {option('out_dir', cli='out')}")
    t0 = time.perf_counter()
    client, own_client = (None, False)
    if scheduler is not None and (not isinstance(scheduler, str) or scheduler_address(scheduler) is not None):
        client, own_client = _dask_client(scheduler)  # before any folder is made: a bad address leaves nothing
    try:
        out.mkdir(parents=True, exist_ok=True)
        (out / _STATUS_DIR).mkdir(exist_ok=True)
        # every option that changes the fitted tyre: a change refits (the fingerprint beside each .tir)
        options = {"cost": cost, "convention": convention, **({"model": model} if model != "pac89" else {})}
        tasks, records = _plan(files, out, force, options, design)
    except BaseException:
        if own_client:
            client.close()
        raise
    tasks = [(s, t, n, cost, convention, st, fp, model, own) for (s, t, n, _, _, st, fp, own) in tasks]

    if client is not None:
        backend = f"dask({getattr(client, 'scheduler', None) and client.scheduler.address})"
    else:
        n = min(int(workers) if workers else _default_workers(), max(len(tasks), 1))
        backend = "serial" if n <= 1 else f"processes({n})"
    try:
        if not tasks:
            pass
        elif client is not None:
            records += _run_dask(tasks, client, progress)
        elif backend == "serial":
            records += _run_serial(tasks, progress)
        else:
            records += _run_processes(tasks, n, progress)
    finally:
        if own_client:
            client.close()
    records.sort(key=lambda r: r["name"])
    res = BatchResult(out_dir=out, records=records, elapsed=time.perf_counter() - t0, backend=backend)
    if summary:
        res.summary_csv, res.report = write_summary(res)
    return res


# --------------------------------------------------------------------------- summary

def _csv_cell(v) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return "" if not math.isfinite(v) else repr(v)
    s = str(v)
    if any(ch in s for ch in ',"\n\r'):
        s = '"' + s.replace('"', '""').replace("\n", " ").replace("\r", " ") + '"'
    return s


def summary_csv_text(records: Sequence[dict]) -> str:
    """The summary table as CSV text, units in the headers."""
    units = {"rmse": "rmse [N]", "fz_min": "fz_min [N]", "fz_max": "fz_max [N]", "time_s": "time [s]",
             "peak_mu": "peak_mu [-]", "r2": "r2 [-]"}
    lines = [",".join(units.get(c, c) for c in SUMMARY_COLUMNS)]
    for r in records:
        lines.append(",".join(_csv_cell(r.get(c)) for c in SUMMARY_COLUMNS))
    return "\n".join(lines) + "\n"


def write_summary(res: BatchResult) -> tuple[Path, Path]:
    """Write ``summary.csv`` and ``index.html`` into the batch folder (replacing them)."""
    csv_path = write_text(res.out_dir / "summary.csv", summary_csv_text(res.records), force=True)
    rep = Report("tyrefit batch fit", f"{len(res.records)} data files; {res.n_ok} fitted, {res.n_skipped} "
                 f"skipped (up to date), {res.n_failed} failed; {res.elapsed:.1f} s on {res.backend}.")
    ok = [r for r in res.records if r.get("status") in ("ok", "skipped") and r.get("rmse") is not None]
    if ok:
        rep.h2("Fit quality")
        _quality_figure(rep, ok)
    if res.failed:
        rep.h2("Failed")
        rep.table([{"name": r["name"], "status": r["status"], "error": r.get("error", "")} for r in res.failed])
    rep.h2("Every tyre")
    rep.p("rmse in N (lateral force for slip-angle data, longitudinal for slip-ratio data), R² of the same, "
          "peak μ = D/Fz at the median load of the data. The table is also in summary.csv; per-tyre records "
          "are in status/.", cls="note")
    cols = ["name", "status", "points", "rmse", "r2", "peak_mu", "time_s", "error"]
    rep.table([{c: r.get(c, "") if r.get(c) is not None else "" for c in cols} for r in res.records], columns=cols)
    html_path = rep.save(res.out_dir, "index.html", force=True)
    return csv_path, html_path


def _quality_figure(rep, ok: list[dict]) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 3.2))
    axes = fig.subplots(1, 3)
    for ax, key, label in zip(axes, ("rmse", "r2", "peak_mu"), ("rmse [N]", "R² [-]", "peak μ [-]")):
        v = np.array([r.get(key) for r in ok if r.get(key) is not None], float)
        v = v[np.isfinite(v)]
        if v.size:
            ax.hist(v, bins=min(30, max(5, v.size // 5)), color="#4a6fa5")
        ax.set_xlabel(label)
        ax.set_ylabel("tyres")
    fig.tight_layout()
    rep.figure(fig, f"Distribution over the {len(ok)} fitted tyres.")
