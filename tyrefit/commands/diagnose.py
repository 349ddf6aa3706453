"""``tyrefit diagnose DATA [DATA ...] --json OUT.json [--report DIR]``: find the effects a PAC89 model misses.

Reads lateral-force slip sweeps (CSV with unit headers, TYDEX, FSAE TTC), and
optionally more records of the same tyre (a drive/brake record beside the
cornering one), runs :func:`tyrefit.workflows.diagnose.diagnose_records` (the
function ``tf.diagnose`` calls: Fy from the PAC89 start model plus ``--start``
effects, Mz and Fx on their own catalogues, or with ``--base mf61`` the Magic
Formula tyre of ``fit --model mf61``) and writes the JSON of the DESIGN contract (``start``, ``accepted``,
``noise_floor``, ``steps``, ``candidates``, ``channels``) and, with
``--report DIR``, ``DIR/index.html`` with the whole loop.
"""

from __future__ import annotations

import math
from pathlib import Path

from ..effects import parse_effects
from ..errors import OutputExistsError, ValueRangeError
from ..io.outputs import check_output
from ..io.readers import read_data
from ..workflows.diagnose import diagnose_records
from ..workflows.fit import fit_pac89_record

__all__ = ["run"]


def run(args) -> int:
    """Run ``tyrefit diagnose``; return the exit code."""

    force = bool(getattr(args, "force", False))
    json_path = check_output(args.json, force)
    report_dir = getattr(args, "report", None)
    if report_dir:
        p = Path(report_dir)
        if p.exists() and (not p.is_dir() or any(p.iterdir())) and not force:
            raise OutputExistsError(f"{p}: report folder exists and is not empty; pass --force to replace it")
    start = parse_effects(getattr(args, "start", None))
    rated = getattr(args, "rated_load", None)
    if rated is not None and not (math.isfinite(rated) and rated > 0):
        raise ValueRangeError(f"--rated-load {rated}: the rated load must be a positive force in N (e.g. 6031)")
    paths = list(args.data) if isinstance(args.data, (list, tuple)) else [args.data]
    convention = getattr(args, "convention", "iso") or "iso"
    records = [read_data(p, convention=convention) for p in paths]
    base = getattr(args, "base", "pac89") or "pac89"
    result, lead = diagnose_records(records, start=start, rated_load=rated, seed=int(getattr(args, "seed", 0) or 0),
                                    base=base, patch=getattr(args, "patch", None), rig=getattr(args, "rig", None),
                                    vertical=getattr(args, "vertical", None),
                                    static_part=getattr(args, "static_part", "peak") or "peak")
    if report_dir:
        if base == "pac89":
            _run_export(result, lead, args)
        result.report(report_dir, force=force)
    result.to_json(json_path, force=force)
    print(result.summary())
    print(f"wrote {json_path}" + (f" and {Path(report_dir) / 'index.html'}" if report_dir else ""))
    return 0


def _run_export(dg, ds, args) -> None:
    """Run the fit of the export command the report suggests, so the report states what that command gives.

    ``dg.export['fit_rmse']`` [N]: lateral RMSE of ``tyrefit fit DATA --effects <PAC89 export effects>``
    (:func:`tyrefit.workflows.fit.fit_pac89_record`, the same code the command runs).
    """
    result = fit_pac89_record(ds, name=str(ds.source), cost="l2", effects=list(dg.export.get("effects", [])),
                              rated_load=getattr(args, "rated_load", None))
    dg.export["fit_rmse"] = float(result.rmse)
