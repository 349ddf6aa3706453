"""The command line's check of a command's outputs, before it does any work (the flags' side of
:mod:`tyrefit.io.outputs`, which writes them)."""

from __future__ import annotations

from pathlib import Path

from ..errors import OutputError
from ..io.outputs import check_output, check_report_dir, real_path

__all__ = ["check_outputs"]


def check_outputs(args, files=("out", "json"), reports=("report",)) -> None:
    """Check a command's output flags before it does any work.

    ``files`` name ``args`` attributes holding output files, ``reports``
    attributes holding report folders; attributes that are missing or None
    are skipped.  Honours ``args.force``.  Two outputs naming the same file
    are refused.
    """
    force = bool(getattr(args, "force", False))
    seen: dict[Path, str] = {}
    for name in files:
        v = getattr(args, name, None)
        if v:
            r = real_path(v)
            if r in seen:
                raise OutputError(f"--{name} {v}: the same file as --{seen[r]}; give each output its own name")
            seen[r] = name
            check_output(v, force)
    for name in reports:
        v = getattr(args, name, None)
        if v:
            check_report_dir(v, force)
