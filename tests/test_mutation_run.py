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
    from benchmarks.mutation import NAMED, run

    res = run(ROOT, sample=3, seed=15, named=True, files=["tyrefit/models/pac89.py"], log=lambda *_: None)
    named = [r for r in res["rows"] if r["site"] < 0]
    assert len(named) == len(NAMED)
    survivors = [r["what"] for r in named if not r["outcome"].startswith("killed")]
    assert survivors == [], survivors
    with capsys.disabled():
        print(f"\nmutation score {res['score']:.3f} ({res['killed']}/{res['mutants']}); "
              f"surviving: {[r['file'] + ':' + str(r['line']) + ' ' + r['what'] for r in res['rows'] if r['outcome'] == 'survived']}")
    assert res["sampled_mutants"] == 3


def test_a_named_mutant_that_no_longer_matches_the_code_stops_the_run(monkeypatch):
    # quick: the check runs before any test does (issue 25: the 1/n mutant had silently left the score)
    sys.path.insert(0, str(ROOT))
    import benchmarks.mutation as bm

    assert len(bm.named_mutants(ROOT)) == len(bm.NAMED)   # every named mutant matches today's code
    stale = ("a line that is not there", "tyrefit/rig/patch.py", "no such text", "x", ["tests/test_rig_patch.py"])
    monkeypatch.setattr(bm, "NAMED", [*bm.NAMED, stale])
    with pytest.raises(bm.StaleMutant, match="a line that is not there"):
        bm.named_mutants(ROOT)
    with pytest.raises(bm.StaleMutant):
        bm.run(ROOT, sample=0, seed=15, named=True, log=lambda *_: None)
    assert [m.what for m in bm.named_mutants(ROOT, only=["pressure law"])] == ["linear pressure law's sign flipped"]


def test_the_targets_cover_issue_25s_modules_with_existing_quick_test_files():
    # issue 25 must-show: benchmarks/mutation.py covers every module the issue names
    sys.path.insert(0, str(ROOT))
    from benchmarks.mutation import TARGETS

    issue25 = ["tyrefit/fitting/core.py", "tyrefit/fitting/mf.py", "tyrefit/sim/allocator.py", "tyrefit/io/pac89_tir.py",
               "tyrefit/rig/patch.py", "tyrefit/models/mf61.py", "tyrefit/diagnose/engine.py",
               "tyrefit/diagnose/stats.py", "tyrefit/io/ttc.py", "tyrefit/io/outputs.py", "tyrefit/rig/conversion.py",
               "tyrefit/fitting/initial.py"]
    assert set(issue25) <= set(TARGETS)
    for module, tests in TARGETS.items():
        assert (ROOT / module).is_file(), module
        assert tests and all((ROOT / t).is_file() for t in tests), (module, tests)


def test_a_rerun_rebuilds_the_survivors_and_stops_when_their_file_changed():
    sys.path.insert(0, str(ROOT))
    import benchmarks.mutation as bm

    m = bm.mutants_of(ROOT, "tyrefit/io/ttc.py", 2, 15)[0]
    row = {"file": m.file, "site": m.site, "what": m.what, "line": m.line, "outcome": "survived"}
    again = bm.rerun_mutants(ROOT, [row, {**row, "outcome": "killed"}])
    assert [(x.site, x.what, x.line, x.source) for x in again] == [(m.site, m.what, m.line, m.source)]
    assert m.changed and m.changed in m.source
    with pytest.raises(bm.StaleMutant, match="changed since that run"):
        bm.rerun_mutants(ROOT, [{**row, "line": m.line + 1}])


def test_known_survivors_name_a_target_a_kind_and_a_reason():
    sys.path.insert(0, str(ROOT))
    import benchmarks.mutation as bm

    for f, fragment, kind, why in bm.KNOWN_SURVIVORS:
        assert f in bm.TARGETS and fragment and why and kind in ("equivalent", "tie", "harmless")
    m = bm.Mutant("tyrefit/io/outputs.py", 0, "constant 8 changed", 83, changed="_RANDOM = 16")
    assert bm.known_survivor(m)[0] == "harmless"
    assert bm.known_survivor(bm.Mutant("tyrefit/io/outputs.py", 0, "x", 1, changed="_RANDOM = 9")) == ()


def test_the_adjusted_score_leaves_out_only_the_survivors_shown_equivalent():
    sys.path.insert(0, str(ROOT))
    from benchmarks.mutation import score

    rows = [{"site": 1, "outcome": "killed"}, {"site": 2, "outcome": "killed (timeout)"},
            {"site": 3, "outcome": "survived", "known": "equivalent"},
            {"site": 4, "outcome": "survived", "known": "harmless"},
            {"site": -1, "outcome": "killed"}, {"site": 5, "outcome": "no tests"}]
    s = score(rows)
    assert (s["killed"], s["mutants"], s["sampled_killed"], s["sampled_mutants"], s["equivalent"]) == (3, 5, 2, 4, 1)
    assert s["adjusted_score"] == pytest.approx(2 / 3)
