"""Regenerate every bundled synthetic data set: ``python -m tyrefit.synthetic --out data``."""

from __future__ import annotations

import argparse
import importlib
import sys
from pathlib import Path

from . import GENERATORS


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m tyrefit.synthetic", description=__doc__)
    ap.add_argument("--out", default="data", help="data folder (default: data)")
    ap.add_argument("--only", nargs="*", choices=sorted(GENERATORS), help="regenerate only these sets")
    args = ap.parse_args(argv)
    out = Path(args.out)
    for folder, module in GENERATORS.items():
        if args.only and folder not in args.only:
            continue
        files = importlib.import_module(module).generate(out / folder)
        for f in files:
            print(f)
    return 0


if __name__ == "__main__":
    sys.exit(main())
