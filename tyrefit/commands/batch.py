"""``tyrefit batch fit DIR_OR_GLOB --out DIR [--scheduler ADDRESS] [--workers N]``.

Fits every data file with :func:`tyrefit.workflows.batch.batch_fit` and prints one
summary line on stdout.  A bad file does not stop the batch: it is listed on
stderr (one line each) and in ``DIR/summary.csv`` / ``DIR/index.html``.

Exit codes: 0 every tyre fitted or up to date; 2 bad arguments, no data
files, or one or more files that could not be fitted (the others are fitted
and the summary is written); 1 a tyre hit an internal error (a tyrefit bug;
the traceback is in ``DIR/status/<name>.json``).
"""

from __future__ import annotations

import argparse
import sys
import warnings

from ..workflows.batch import SchedulerWarning, batch_fit, scheduler_address, scheduler_from_file

#: failures listed on stderr before "... and N more"
_MAX_LISTED = 20


def run(args: argparse.Namespace) -> int:
    """Run ``tyrefit batch <command>``; return the exit code."""
    if args.batch_command != "fit":  # pragma: no cover - argparse allows only 'fit'
        raise SystemExit(2)
    if getattr(args, "scheduler_file", None):
        scheduler = scheduler_from_file(args.scheduler_file)
    else:
        scheduler = args.scheduler if scheduler_address(args.scheduler) is not None else None  # '' runs locally
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", SchedulerWarning)
        try:
            res = batch_fit(args.source, args.out, workers=args.workers, scheduler=scheduler, force=args.force,
                            progress=True, cost=getattr(args, "cost", "l2"),
                            convention=getattr(args, "convention", "iso"),
                            model=getattr(args, "model", "pac89") or "pac89",
                            manifest=getattr(args, "manifest", None),
                            allow_mirrored=bool(getattr(args, "allow_mirrored", False)))
        finally:
            for w in caught:
                if issubclass(w.category, SchedulerWarning):
                    print(f"tyrefit batch: warning: {w.message}", file=sys.stderr)
                else:
                    warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    print(f"{len(res.records)} data files: {res.n_ok} fitted, {res.n_skipped} up to date, {res.n_failed} failed "
          f"in {res.elapsed:.1f} s ({res.backend}); summary {res.summary_csv}, report {res.report}")
    failed = res.failed
    for r in failed[:_MAX_LISTED]:
        print(f"tyrefit batch: {r['name']}: {r['status']}: {r.get('error', '')}", file=sys.stderr)
    if len(failed) > _MAX_LISTED:
        print(f"tyrefit batch: ... and {len(failed) - _MAX_LISTED} more (see {res.summary_csv})", file=sys.stderr)
    if any(r["status"] == "error" for r in failed):
        return 1
    return 2 if failed else 0
