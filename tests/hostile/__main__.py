"""``python -m tests.hostile [--fast] [-j N] [-k PATTERN] [--out FILE]``: run the corpus, print the table."""

from __future__ import annotations

import argparse
import json
import sys
import time
from concurrent.futures import ThreadPoolExecutor

from . import all_cases, run_case, summary, table


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m tests.hostile")
    ap.add_argument("--fast", action="store_true", help="only the fast subset of the default test tier")
    ap.add_argument("-j", "--jobs", type=int, default=1, help="cases run at once (default 1)")
    ap.add_argument("-k", default="", help="only cases whose name contains this text")
    ap.add_argument("--out", help="also write the table (markdown) and the counts (JSON) here")
    args = ap.parse_args(argv)
    cases = [c for c in all_cases() if (c.fast or not args.fast) and args.k.lower() in c.name.lower()]
    t0 = time.perf_counter()
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as ex:
        outcomes = list(ex.map(run_case, cases))
    text = table(outcomes)
    counts = summary(outcomes)
    counts["seconds"] = round(time.perf_counter() - t0, 1)
    print(text)
    print()
    print(json.dumps(counts))
    if args.out:
        with open(args.out, "w", encoding="utf-8") as fh:
            fh.write(text + "\n\n" + json.dumps(counts) + "\n")
    bad = counts["cases"] - counts["pass"]
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
