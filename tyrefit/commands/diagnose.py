"""``tyrefit diagnose DATA [DATA ...] --json OUT.json [--report DIR]``: find the effects a PAC89 model misses.

Reads lateral-force slip sweeps (CSV with unit headers, TYDEX, FSAE TTC), and
optionally more records of the same tyre (a drive/brake record beside the
cornering one), runs :func:`tyrefit.diagnose.diagnose` from the start model
(base PAC89 plus ``--start`` effects) on Fy and
:func:`tyrefit.diagnose.diagnose_channels` on Mz and Fx where the records carry
them, and writes the JSON of the DESIGN contract (``start``, ``accepted``,
``noise_floor``, ``steps``, ``candidates``, ``channels``) and, with
``--report DIR``, ``DIR/index.html`` with the whole loop.
"""

from __future__ import annotations

import math
from pathlib import Path

from ..diagnose import combine_records, diagnose, diagnose_channels
from ..effects import parse_effects
from ..errors import DataError, OutputExistsError, ValueRangeError
from ..io.outputs import check_output
from ..io.readers import read_data
from ..workflows.fit import fit_pac89_record, static_input
from ..workflows.ladder import diagnose_mf

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
    notes: list[str] = []
    ds = records[0] if len(records) == 1 else None
    base = getattr(args, "base", "pac89") or "pac89"
    if base != "pac89" and any(r.kind not in ("slip_angle", "slip_ratio") for r in records):
        raise DataError(f"--base {base} diagnoses dynamic-rig slip sweeps (the Magic Formula tyre `tyrefit fit --model "
                        f"{base}` writes); static-rig pushes are diagnosed with the PAC89 base and --patch")
    if ds is not None and ds.kind == "static":
        # static-rig pushes: the same Eq. 1 conversion as `tyrefit fit` (tyrefit.rig.prepare_static_fit)
        sfi = static_input(ds, patch=getattr(args, "patch", None), rig=getattr(args, "rig", None),
                           vertical=getattr(args, "vertical", None),
                           static_part=getattr(args, "static_part", "peak") or "peak", rated_load=rated, notes=notes)
        ds = sfi.data
        notes[:0] = [f"static-rig pushes converted to slip angles with Komana et al. Eq. 1 "
                     f"({'calibrated' if sfi.rig.calibrated else 'uncalibrated, f = 1'}; part '{sfi.part}')"]
        notes += list(sfi.notes)
    elif getattr(args, "patch", None) or getattr(args, "rig", None):
        kinds = ", ".join(sorted({r.kind for r in records}))
        raise DataError(f"{' '.join(paths)}: --patch and --rig convert static-rig pushes (one record); "
                        f"these hold {kinds!s} data")
    else:
        lateral = [r for r in records if r.kind == "slip_angle" and "fy" in r.df.columns]
        if not lateral:
            kinds = ", ".join(sorted({repr(r.kind) for r in records}))
            hint = ("; give the tyre's cornering record too (`tyrefit diagnose CORNERING DRIVEBRAKE`) to diagnose "
                    "Fx beside Fy and Mz, or fit drive/brake records with `tyrefit fit FILE --model mf61`"
                    if any(r.kind == "slip_ratio" for r in records) else "")
            raise DataError(f"{' '.join(paths)}: diagnose needs lateral-force slip-angle sweeps (fy against "
                            f"slip_angle) or static-rig pushes with --patch; found {kinds} data" + hint)
        ds = combine_records(records)
        lead = lateral[0]
    if base != "pac89":
        return _run_ladder(records if len(records) > 1 else [ds], base, args, rated, json_path, report_dir, force,
                           start)
    dg = diagnose(ds, start=start, rated_load=rated, seed=int(getattr(args, "seed", 0) or 0))
    dg.channels, dg.channels_absent = diagnose_channels(ds, rated_load=rated, seed=int(getattr(args, "seed", 0) or 0))
    dg.data.notes[:0] = notes
    if report_dir:
        _run_export(dg, lead if len(records) > 1 else ds, args)
        dg.report(report_dir, force=force)
    dg.to_json(json_path, force=force)
    print(dg.summary())
    print(f"wrote {json_path}" + (f" and {Path(report_dir) / 'index.html'}" if report_dir else ""))
    return 0


def _run_ladder(records, base, args, rated, json_path, report_dir, force, start) -> int:
    """``--base mf61|mf52``: what the Magic Formula tyre of ``fit --model`` still misses (:mod:`tyrefit.workflows.ladder`)."""
    if start:
        raise DataError("--start names PAC89 effects; with --base mf61 the start is the Magic Formula tyre of "
                        "`tyrefit fit --model mf61`")
    lg = diagnose_mf(records, model=base, rated_load=rated, seed=int(getattr(args, "seed", 0) or 0))
    if report_dir:
        lg.report(report_dir, force=force)
    lg.to_json(json_path, force=force)
    print(lg.summary())
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
