"""Where the bundled example data live.

The example sets in ``data/`` are **synthetic**: each is made by a seeded
generator in :mod:`tyrefit.synthetic` whose physics and parameters are
documented there and in ``data/README.md``.  No set in ``data/`` is a
measurement.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import DataError

__all__ = ["data_dir", "data_path"]


def data_dir() -> Path:
    """The folder of bundled data: ``tyrefit/data`` (package data in a wheel; in a source checkout a link to
    ``<repo>/data``), else ``<repo>/data``."""
    pkg = Path(__file__).resolve().parents[1]  # tyrefit/
    for cand in (pkg / "data", pkg.parent / "data"):
        if cand.is_dir():
            return cand
    raise DataError("bundled data folder not found; run tyrefit from a source checkout "
                    "(pip install -e .) or regenerate with 'python -m tyrefit.synthetic'")


def data_path(*parts: str) -> Path:
    """Path of a bundled file, e.g. ``data_path('truck', 'tyre_a_dynamic.csv')``."""
    p = data_dir().joinpath(*parts)
    if not p.exists():
        raise DataError(f"bundled file {'/'.join(parts)} not found in {data_dir()}; "
                        "regenerate with 'python -m tyrefit.synthetic'")
    return p
