"""tyrefit benchmarks: ``make bench`` = ``python -m benchmarks.run --out reports/bench``.

Every ``benchmarks/bench_*.py`` module exposes ``run() -> dict``; the harness
(:mod:`benchmarks.run`) calls each one, records failures, and writes
``results.json`` and a markdown table.  A module's dict holds a list of
measurements, each timed against a **baseline measured in the same run** (the
machine is shared, so only ratios are comparable between runs)::

    {"measurements": [measurement("read CSV, 300k rows", 1.9, "pandas.read_csv", 0.7), ...],
     "info": {...anything JSON-able...}}

Helpers for bench modules: :func:`best_of` (best wall time of a few repeats),
:func:`measurement` (one row), :func:`full` (whether the long variants were
asked for, ``TYREFIT_BENCH_FULL=1`` or ``run.py --full``).
"""

from __future__ import annotations

import gc
import os
import time
from collections.abc import Callable
from typing import Any

__all__ = ["best_of", "measurement", "full", "FULL_ENV"]

#: set to 1 to run the long variants (e.g. 1000-tyre batch fits)
FULL_ENV = "TYREFIT_BENCH_FULL"


def full() -> bool:
    """True when the long benchmark variants are asked for."""
    return os.environ.get(FULL_ENV, "").strip() not in ("", "0", "false", "no")


def best_of(fn: Callable[[], Any], repeat: int = 3, setup: Callable[[], Any] | None = None) -> tuple[float, Any]:
    """Best wall time [s] of ``repeat`` calls of ``fn`` (``setup`` runs untimed before each), and the last result.

    The minimum is the least disturbed estimate on a shared machine.
    """
    best, out = float("inf"), None
    for _ in range(max(1, repeat)):
        if setup is not None:
            setup()
        gc.collect()
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def measurement(name: str, seconds: float, baseline: str, baseline_seconds: float, **extra: Any) -> dict:
    """One benchmark row: a measurement, its same-run baseline, and ``ratio = seconds / baseline_seconds``.

    ``ratio < 1`` means faster than the baseline.  ``extra`` (e.g. ``n``,
    ``points``, ``note``) is kept in results.json and shown in the markdown notes.
    """
    ratio = seconds / baseline_seconds if baseline_seconds and baseline_seconds > 0 else float("nan")
    return {"name": name, "seconds": float(seconds), "baseline": baseline,
            "baseline_seconds": float(baseline_seconds), "ratio": ratio, **extra}
