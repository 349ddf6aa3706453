"""Slow tier: the mutation run (benchmarks/mutation.py) - issue 15's named mutants must all be killed.

Runs each named mutant against its test files in a scratch copy of the repository,
plus a small seeded sample of operator/constant mutants of ``tyrefit/models/pac89.py``,
and prints the score.  The full before/after comparison is
``nice python -m benchmarks.mutation --sample 42 --seed 15 --named`` (minutes).
"""

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_named_mutants_are_killed_and_the_sample_is_scored(capsys):
    sys.path.insert(0, str(ROOT))
    from benchmarks.mutation import run

    res = run(ROOT, sample=3, seed=15, named=True, files=["tyrefit/models/pac89.py"], log=lambda *_: None)
    named = [r for r in res["rows"] if r["site"] < 0]
    assert len(named) == 5
    survivors = [r["what"] for r in named if not r["outcome"].startswith("killed")]
    assert survivors == [], survivors
    with capsys.disabled():
        print(f"\nmutation score {res['score']:.3f} ({res['killed']}/{res['mutants']}); "
              f"surviving: {[r['file'] + ':' + str(r['line']) + ' ' + r['what'] for r in res['rows'] if r['outcome'] == 'survived']}")
    assert res["sampled_mutants"] == 3
