"""``tyrefit demo``: run the main jobs on the bundled data and link every report.

Each step is a script in ``pipelines/`` exposing ``main(out_dir) -> dict``;
the demo runs them in order, each into its own sub-folder, and writes an
``index.html`` that links every report with the step's headline numbers.  A
step that fails is shown as failed (with its one-line error) and makes the
demo exit non-zero; the other steps still run.
"""

from __future__ import annotations

import contextlib
import importlib.util
import io
import json
import time
import traceback
from pathlib import Path

from ..io.datasets import data_dir
from ..errors import DataError
from ..io.outputs import staged_dir
from ..io.report import Report

#: (folder, pipeline script, what it shows)
STEPS = [
    ("fit", "fit_truck.py", "PAC89 fit of the bundled truck tyre's dynamic-rig data, .tir and Chrono JSON"),
    ("sttr_vs_dttr", "sttr_vs_dttr.py",
     "Static-rig tyre from two days of static tests, calibrated on a second tyre, against its dynamic data"),
    ("diagnose", "diagnose_passenger.py",
     "Diagnosis of the bundled passenger tyre: where the model fails, which effect is missing"),
    ("emission_control", "emission_control.py",
     "Fitted soft and hard tyres in the wear-aware torque-allocation scenarios of Pham et al. 2025"),
    ("physics", "physics.py", "Camber brush model, EKF road-adhesion estimation, slip characteristics"),
]


def _load(script: Path):
    spec = importlib.util.spec_from_file_location(f"tyrefit_pipeline_{script.stem}", script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run_demo(out: Path, force: bool = False, steps=STEPS, pipelines: Path | None = None) -> tuple[list[dict], Path]:
    """Run every demo step into ``out``; return the step records and the index path."""
    pipelines = Path(pipelines) if pipelines is not None else data_dir().parent / "pipelines"
    if not pipelines.is_dir():
        raise DataError(f"{pipelines}: the demo's pipelines folder is missing (the package ships it beside its data); "
                        "reinstall tyrefit")
    records = []
    with staged_dir(out, force=force) as tmp:
        for folder, script, what in steps:
            t0 = time.perf_counter()
            rec = {"step": folder, "what": what, "status": "ok", "headline": "", "link": f"{folder}/index.html"}
            log = io.StringIO()
            try:
                with contextlib.redirect_stdout(log):
                    result = _load(pipelines / script).main(tmp / folder) or {}
                rec["headline"] = str(result.get("headline", ""))
                rec["numbers"] = {k: v for k, v in result.items() if k != "headline"}
            except Exception as exc:  # a failing step is reported, the others still run
                rec["status"] = "failed"
                rec["headline"] = " ".join(f"{exc.__class__.__name__}: {exc}".split())[:300]
                rec["traceback"] = traceback.format_exc()
            rec["seconds"] = round(time.perf_counter() - t0, 1)
            (tmp / folder).mkdir(parents=True, exist_ok=True)  # what the step printed, with its final paths
            (tmp / folder / "log.txt").write_text(log.getvalue().replace(str(tmp), str(out)))
            print(f"[demo] {folder:<18} {rec['status']:<7} {rec['seconds']:>6.1f} s  {rec['headline'][:90]}")
            records.append(rec)
        r = Report("tyrefit demo", "Every result below was produced just now from the bundled data in data/. "
                   "All bundled data are synthetic, made by the seeded generators in tyrefit/synthetic "
                   "(see data/README.md); none of it is a measurement.")
        r.h2("Steps")
        rows = []
        for rec in records:
            link = f'<a href="{rec["link"]}">{rec["step"]}</a>' if rec["status"] == "ok" else rec["step"]
            cls = "ok" if rec["status"] == "ok" else "bad"
            rows.append(f"<tr><td>{link}</td><td>{rec['what']}</td><td class='{cls}'>{rec['status']}</td>"
                        f"<td>{rec['headline']}</td><td>{rec['seconds']}</td>"
                        f"<td><a href=\"{rec['step']}/log.txt\">log</a></td></tr>")
        r.raw("<table><tr><th>report</th><th>what it shows</th><th>status</th><th>headline</th><th>s</th>"
              "<th>output</th></tr>"
              + "".join(rows) + "</table>")
        r.save(tmp)
        (tmp / "demo.json").write_text(json.dumps(
            [{k: v for k, v in rec.items() if k != "traceback"} for rec in records], indent=2, default=str))
        _final_paths(tmp, out)
    return records, out / "index.html"


def _final_paths(tmp: Path, out: Path) -> None:
    """Point the JSON and HTML the steps wrote at the final folder, not the staging one they ran in.

    The steps write into the staging folder (committed as a whole at the end), so a path one step
    recorded (``sim --json``'s tyre ``file``, a report's link) names a folder that is gone afterwards.
    """
    old = str(tmp)
    for f in sorted(tmp.rglob("*")):
        if f.suffix.lower() in (".json", ".html") and f.is_file():
            text = f.read_text(encoding="utf-8", errors="surrogateescape")
            if old in text:
                f.write_text(text.replace(old, str(out)), encoding="utf-8", errors="surrogateescape")


def run(args) -> int:
    records, index = run_demo(Path(args.out), force=args.force)
    print(f"[demo] wrote {index}")
    failed = [r for r in records if r["status"] != "ok"]
    for r in failed:
        if args.debug:
            print(r["traceback"])
    return 1 if failed else 0
