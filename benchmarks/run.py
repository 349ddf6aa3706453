"""Run every benchmark module and write ``results.json`` and ``README.md``.

``python -m benchmarks.run --out reports/bench [--only io batch] [--full]``

Discovers ``benchmarks/bench_*.py``, calls each module's ``run() -> dict`` in
turn (one at a time: the benchmarks themselves decide on parallelism), and
records a module that raises as failed with its error instead of stopping.
The markdown table shows each measurement, its baseline measured in the same
run, and their ratio (< 1: faster than the baseline).  The output folder
belongs to the harness and is rewritten on every run.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import importlib
import json
import math
import os
import platform
import subprocess
import sys
import time
import traceback
from pathlib import Path
from typing import Any

from . import FULL_ENV

HERE = Path(__file__).resolve().parent


def discover() -> list[str]:
    """Names of the bench modules (``bench_io`` ...), sorted."""
    return sorted(p.stem for p in HERE.glob("bench_*.py"))


def _normalise(result: Any) -> tuple[list[dict], dict]:
    """Accept ``{"measurements": [...], "info": {...}}`` or a mapping name -> row."""
    if not isinstance(result, dict):
        raise TypeError(f"run() returned {type(result).__name__}; expected a dict")
    if "measurements" in result:
        rows = list(result["measurements"])
        info = {k: v for k, v in result.items() if k != "measurements"}
    else:
        rows, info = [], {}
        for k, v in result.items():
            if isinstance(v, dict) and "seconds" in v:
                rows.append({"name": k, **v})
            else:
                info[k] = v
    for r in rows:
        s, b = r.get("seconds"), r.get("baseline_seconds")
        if "ratio" not in r and isinstance(s, (int, float)) and isinstance(b, (int, float)) and b > 0:
            r["ratio"] = s / b
    return rows, info


def run_module(name: str) -> dict[str, Any]:
    """Import and run one bench module; never raises."""
    t0 = time.perf_counter()
    entry: dict[str, Any] = {"module": name, "status": "ok"}
    try:
        mod = importlib.import_module(f"benchmarks.{name}")
        rows, info = _normalise(mod.run())
        entry["measurements"], entry["info"] = rows, info
    except Exception as exc:  # noqa: BLE001 - a failing benchmark is recorded, not fatal
        entry.update(status="failed", error=f"{exc.__class__.__name__}: {' '.join(str(exc).split())[:300]}",
                     traceback=traceback.format_exc(), measurements=[])
    entry["wall_seconds"] = time.perf_counter() - t0
    return entry


def _machine() -> dict[str, Any]:
    try:
        load = os.getloadavg()
    except OSError:  # pragma: no cover
        load = None
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=HERE.parent, capture_output=True,
                                text=True, timeout=5).stdout.strip() or None
    except (OSError, subprocess.SubprocessError):
        commit = None
    try:
        cpus = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover
        cpus = os.cpu_count()
    return {"date": _dt.datetime.now().isoformat(timespec="seconds"), "python": platform.python_version(),
            "platform": platform.platform(), "cpus": cpus, "load_average_at_start": load, "commit": commit,
            "full": bool(os.environ.get(FULL_ENV))}


def _num(v: Any, fmt: str) -> str:
    if isinstance(v, (int, float)) and math.isfinite(v):
        return format(v, fmt)
    return "–"


def markdown(doc: dict) -> str:
    """The results as a markdown page (one table for every module)."""
    m = doc["machine"]
    out = ["# tyrefit benchmarks", "",
           f"{m['date']}, commit {m['commit']}, Python {m['python']}, {m['cpus']} CPUs, load average at start "
           f"{', '.join(f'{x:.2f}' for x in m['load_average_at_start']) if m['load_average_at_start'] else '?'}"
           f"{', full variants' if m['full'] else ''}.", "",
           "Each measurement is timed against a baseline measured **in the same run**; ratio = time / baseline "
           "(< 1: faster than the baseline). Absolute times depend on the load of the machine; compare ratios.", "",
           "| module | measurement | time [s] | baseline | baseline [s] | ratio |",
           "|---|---|---:|---|---:|---:|"]
    notes, failed = [], []
    for e in doc["modules"]:
        if e["status"] != "ok":
            failed.append(f"- `{e['module']}` failed: {e['error']}")
            continue
        for r in e["measurements"]:
            out.append(f"| {e['module']} | {r.get('name', '?')} | {_num(r.get('seconds'), '.3g')} | "
                       f"{r.get('baseline', '')} | {_num(r.get('baseline_seconds'), '.3g')} | "
                       f"{_num(r.get('ratio'), '.3f')} |")
            extra = {k: v for k, v in r.items() if k not in ("name", "seconds", "baseline", "baseline_seconds",
                                                                "ratio")}
            if extra:
                notes.append(f"- {e['module']} / {r.get('name')}: "
                             + ", ".join(f"{k} = {_fmt_extra(v)}" for k, v in extra.items()))
    if notes:
        out += ["", "## Notes", ""] + notes
    if failed:
        out += ["", "## Failed modules", ""] + failed
    out += ["", f"Total wall time {doc['wall_seconds']:.0f} s.", ""]
    return "\n".join(out)


def _fmt_extra(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.run", description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="reports/bench", help="output folder (default reports/bench)")
    ap.add_argument("--only", nargs="*", metavar="NAME", help="run only these modules (bench_io or io)")
    ap.add_argument("--full", action="store_true", help=f"long variants too (sets {FULL_ENV}=1)")
    args = ap.parse_args(argv)
    if args.full:
        os.environ[FULL_ENV] = "1"
    names = discover()
    if args.only:
        want = {n if n.startswith("bench_") else f"bench_{n}" for n in args.only}
        unknown = want - set(names)
        if unknown:
            ap.error(f"unknown benchmark module(s) {', '.join(sorted(unknown))}; found {', '.join(names)}")
        names = [n for n in names if n in want]
    t0 = time.perf_counter()
    doc = {"machine": _machine(), "modules": []}
    for name in names:
        print(f"benchmarks: {name} ...", file=sys.stderr, flush=True)
        entry = run_module(name)
        doc["modules"].append(entry)
        status = "ok" if entry["status"] == "ok" else f"FAILED ({entry['error']})"
        print(f"benchmarks: {name} {status} in {entry['wall_seconds']:.1f} s", file=sys.stderr, flush=True)
    doc["wall_seconds"] = time.perf_counter() - t0
    from tyrefit.io.outputs import write_text

    out = Path(args.out)
    write_text(out / "results.json", json.dumps(_finite(doc), indent=1, default=_json_default, allow_nan=False)
               + "\n", force=True)
    write_text(out / "README.md", markdown(doc), force=True)
    print(f"benchmarks: wrote {out / 'results.json'} and {out / 'README.md'}", file=sys.stderr)
    return 0 if all(e["status"] == "ok" for e in doc["modules"]) else 1


def _finite(o: Any) -> Any:
    """NaN and infinities -> None, so that results.json is strict JSON."""
    if isinstance(o, float):
        return o if math.isfinite(o) else None
    if isinstance(o, dict):
        return {k: _finite(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_finite(v) for v in o]
    return o


def _json_default(o: Any):
    try:
        import numpy as np

        if isinstance(o, np.generic):
            return o.item()
        if isinstance(o, np.ndarray):
            return o.tolist()
    except ImportError:  # pragma: no cover
        pass
    if isinstance(o, Path):
        return str(o)
    return repr(o)


if __name__ == "__main__":
    sys.exit(main())
