"""Reading ``.tir`` files: a hostile file of long runs of spaces against an ordinary one of the same size.

The parser must be linear in the file size whatever the lines hold (issue 15:
a 150 KB file of space-padded comment rulers took 69 s with the old
regular-expression parser).  Baseline: an ordinary PAC89 file (the Adams
example repeated as comment lines) of the same number of bytes; the ratio
stays near 1 for a linear parser and grows with the size for a quadratic one.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from tyrefit.io.tir import read_property_file

from . import best_of, measurement

EXAMPLE = Path(__file__).resolve().parents[1] / "tests" / "data" / "ref_adams_pac89_example.tir"


def _files(d: Path, size: int) -> tuple[Path, Path]:
    head = EXAMPLE.read_text()
    n_lines = 5
    pad = max((size - len(head)) // n_lines, 10)
    hostile = d / "hostile.tir"
    hostile.write_text(head + "".join("$---- " + " " * pad + "1\n" for _ in range(n_lines)))
    ordinary = d / "ordinary.tir"
    line = "! an ordinary comment line of a tyre property file, about eighty characters long\n"
    ordinary.write_text(head + line * max((hostile.stat().st_size - len(head)) // len(line), 1))
    return hostile, ordinary


def run() -> dict:
    out = []
    with tempfile.TemporaryDirectory() as tmp:
        for size in (150_000, 1_500_000):
            hostile, ordinary = _files(Path(tmp), size)
            t_base, _ = best_of(lambda: read_property_file(ordinary), repeat=3)
            t_ours, _ = best_of(lambda: read_property_file(hostile), repeat=3)
            out.append(measurement(f"read_property_file, {hostile.stat().st_size // 1000} KB of space-padded rulers",
                                   t_ours, "an ordinary .tir of the same size", t_base,
                                   bytes=hostile.stat().st_size))
    return {"measurements": out}
